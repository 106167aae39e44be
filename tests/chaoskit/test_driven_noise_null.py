"""A driven periodic orbit seen through coloured measurement noise is periodic, not noise.

The null of a driven series is "a periodic orbit plus measurement noise", and measurement
noise may be coloured (AR(1)) as well as white: the verdict must not call such a series
noise-like, while chaos (whose departure from the mean cycle depends on the phase and
carries over from cycle to cycle) must still beat that null.
"""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import classify, cycle_spread, systems

PERIOD = 2.0  # s, drive period of the synthetic orbit
PER_PERIOD = 100  # samples per drive period
N_CYCLES = 100
DUFFING_DRIVE = 2 * np.pi / 1.2  # systems.duffing's default omega = 1.2


def ar1(n: int, phi: float, seed: int) -> np.ndarray:
    """Unit-variance AR(1) noise with coefficient ``phi``."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n) * np.sqrt(1.0 - phi**2)
    out = np.empty(n)
    out[0] = rng.standard_normal()
    for i in range(1, n):
        out[i] = phi * out[i - 1] + e[i]
    return out


def orbit() -> tuple[np.ndarray, np.ndarray]:
    """A periodic orbit with harmonics (a journal-like waveform) and its time axis."""
    t = np.arange(N_CYCLES * PER_PERIOD) * (PERIOD / PER_PERIOD)
    w = 2 * np.pi / PERIOD
    x = np.sin(w * t) + 0.4 * np.sin(2 * w * t + 0.3) + 0.15 * np.cos(3 * w * t)
    return t, x


@pytest.mark.parametrize("level", [0.05, 0.10])
def test_a_periodic_orbit_with_coloured_noise_is_periodic(level: float) -> None:
    t, x = orbit()
    y = x + level * np.std(x) * ar1(x.size, 0.9, seed=3)
    v = classify(y, dt=float(t[1] - t[0]), drive_period=PERIOD, rng=0)
    assert v.label == "periodic", v.reason
    assert v.period == 1
    assert "a periodic orbit plus coloured noise" in v.reason
    # white noise reads the AR(1) wander as sqrt(0.9) of the noise level; the departure is
    # the same at every phase, so nothing is left beyond noise
    assert cycle_spread(y, PERIOD, dt=float(t[1] - t[0]), noise="white") > 0.5 * level
    assert v.cycle_spread <= 0.05


def test_the_white_noise_reading_is_kept_on_request() -> None:
    t, x = orbit()
    y = x + 0.1 * np.std(x) * ar1(x.size, 0.9, seed=4)
    dt = float(t[1] - t[0])
    white = cycle_spread(y, PERIOD, dt=dt, noise="white")
    # sqrt(phi) * level = 0.095, less the bias corrections
    assert white == pytest.approx(0.095, abs=0.015)
    assert cycle_spread(y, PERIOD, dt=dt) <= 0.02


@pytest.mark.parametrize("level", [0.05, 0.10])
@pytest.mark.parametrize("nudge", [0.0, 1e-12])
def test_driven_chaos_with_coloured_noise_is_not_periodic(level: float, nudge: float) -> None:
    t, s = systems.duffing(6000, samples_per_period=60, initial=(1.0 + nudge, 0.0))
    x = s[:, 0]
    y = x + level * np.std(x) * ar1(x.size, 0.9, seed=5)
    dt = float(t[1] - t[0])
    v = classify(y, dt=dt, drive_period=DUFFING_DRIVE, rng=0)
    assert v.label != "periodic", v.reason
    assert v.label != "noise-like", v.reason
    assert cycle_spread(y, DUFFING_DRIVE, dt=dt) > 0.3


def test_coloured_noise_without_a_drive_is_noise_like() -> None:
    y = ar1(8000, 0.9, seed=6)
    v = classify(y, dt=0.01, rng=0)
    assert v.label == "noise-like", v.reason


def test_coloured_noise_with_a_drive_is_not_a_periodic_orbit() -> None:
    # a drive period given, but no orbit: the mean cycle carries nothing
    y = ar1(10_000, 0.9, seed=7)
    v = classify(y, dt=PERIOD / PER_PERIOD, drive_period=PERIOD, rng=0)
    assert v.label != "periodic", v.reason
    assert cycle_spread(y, PERIOD, dt=PERIOD / PER_PERIOD) > 0.5


def test_cycle_spread_names_the_accepted_noise_kinds() -> None:
    t, x = orbit()
    with pytest.raises(ValueError, match='noise must be "stationary" or "white"; got \'pink\''):
        cycle_spread(x, PERIOD, dt=float(t[1] - t[0]), noise="pink")
