"""A periodic motion plus measurement noise is periodic; a chaotic one stays chaotic.

The rigid paper scene at 30 rpm settles on a period-1 orbit (a stroboscopic cluster of a few
micrometres); at 150 rpm it is chaotic. Noise added to the journal coordinates must not turn
the first into chaos (the noisy-periodic-orbit null of the verdict), nor the second into a
regular motion.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import chaoskit
import mechanism

REVOLUTIONS = 140
DROPPED = 20
JOURNAL = ["eccentricity_x", "eccentricity_y"]


def _journal(rpm: float) -> xr.Dataset:
    """The journal centre and the crank angle, 120 drive periods after 20, at T/200."""
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    period = 60.0 / rpm
    traj = mechanism.simulate(scene, revolutions=REVOLUTIONS, output_step=period / 200)
    series = traj.sel(time=slice(DROPPED * period - 1e-9, None))
    return series[[*JOURNAL, "crank_angle"]].isel(joint=0, drop=True)


@pytest.fixture(scope="module")
def slow_journal() -> xr.Dataset:
    return _journal(30.0)


@pytest.fixture(scope="module")
def fast_journal() -> xr.Dataset:
    return _journal(150.0)


def _noisy(ds: xr.Dataset, level: float) -> xr.Dataset:
    """``ds`` with white Gaussian noise of ``level`` times each journal coordinate's spread."""
    out = ds.copy()
    rng = np.random.default_rng(7)
    for name in JOURNAL:
        x = out[name]
        out[name] = x + level * float(x.std()) * rng.standard_normal(x.size)
    return out


@pytest.mark.slow
@pytest.mark.parametrize("level", [0.0, 0.01, 0.05, 0.10])
def test_the_30_rpm_orbit_with_noise_is_periodic(slow_journal, level) -> None:
    """The orbit's departure from its mean cycle is white (measured: 0 of the spread at
    every level), so the stroboscopic cluster decides: periodic with period 1, its noise
    stated. Before the noisy-periodic null the clean run was called chaotic (0.83)."""
    data = _noisy(slow_journal, level)
    v = chaoskit.classify(data, variable="eccentricity_x", phase_variable="crank_angle", rng=0)
    assert (v.label, v.period) == ("periodic", 1)
    assert v.cycle_spread <= v.rule.cluster_tol
    assert "a periodic orbit plus noise (measurement noise about" in v.reason
    mv = chaoskit.classify_motion(data, variables=JOURNAL, phase_variable="crank_angle", rng=0)
    assert (mv.label, mv.period) == ("periodic", 1)


@pytest.mark.slow
@pytest.mark.parametrize("level", [0.0, 0.05])
def test_the_150_rpm_motion_stays_chaotic(fast_journal, level) -> None:
    """Its departure from the mean cycle is not white: measured 0.15 of the spread of the
    journal's x, three times the cluster tolerance, at 0 to 20 % noise."""
    data = _noisy(fast_journal, level)
    v = chaoskit.classify(data, variable="eccentricity_x", phase_variable="crank_angle", rng=0)
    assert v.label == "chaotic"
    assert v.cycle_spread > 2 * v.rule.cluster_tol
    mv = chaoskit.classify_motion(data, variables=JOURNAL, phase_variable="crank_angle", rng=0)
    assert mv.label == "chaotic"
