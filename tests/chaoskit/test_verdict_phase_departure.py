"""A tight section is evidence of a stable orbit only when the departure is noise-like.

For a driven series the rule calls a tight stroboscopic cluster "a periodic orbit plus
noise" when what varies from cycle to cycle beyond noise is within the cluster tolerance.
A departure from the mean cycle that is spiky (not smooth over a sample, so the lag-one
reading discounts it as white noise) but confined to some phases of the cycle is not
stationary measurement noise: a stable orbit jolted afresh every cycle and chaos that
lives in the timing of impacts both look like that. Its phase-dependent part then votes
against the periodic label (``votes["phase"]``), so the label is never confident.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from chaoskit import SectionStructure, VerdictRule, classify
from chaoskit.verdict import RuleEvidence, combine

RULE = VerdictRule()
PER_PERIOD = 100
CYCLES = 100


def _cluster() -> SectionStructure:
    return SectionStructure(
        kind="clusters", n_clusters=1, labels=np.zeros(100, int), cluster_radius=0.01,
        cyclic_fraction=1.0, curve_closure=np.nan, curve_coverage=np.nan,
        curve_thickness=np.nan, n_points=100, scale=1.0,
    )  # fmt: skip


def _noisy_orbit_evidence(phase_spread: float) -> RuleEvidence:
    """A driven series: one tight cluster, a broadband spectrum, the cycle test does not
    reject and the lag-one reading of the departure is 0."""
    return RuleEvidence(
        structure=_cluster(), rosenstein_positive=True, wolf_positive=True, zero_one_k=0.7,
        surrogates_rejected=True, lines="broadband", n_cycles=100.0,
        cycle_unit="drive periods", cycles_rejected=False, driven=True, noise=0.09,
        cycle_spread=0.0, phase_spread=phase_spread,
    )  # fmt: skip


def test_phase_dependent_departure_votes_against_periodic():
    out = combine(_noisy_orbit_evidence(0.084), RULE)
    assert out.label == "periodic"
    assert out.votes["phase"] == "opposes"
    assert out.votes["cycles"] == "supports"
    assert out.confidence == pytest.approx(2 / 3, abs=1e-12)
    assert "depends on the phase of the cycle (0.084 of the standard deviation" in out.reason


def test_stationary_departure_keeps_a_confident_orbit():
    for phased in (0.0, RULE.cluster_tol, float("nan")):
        out = combine(_noisy_orbit_evidence(phased), RULE)
        assert (out.label, out.confidence) == ("periodic", 1.0)
        assert "phase" not in out.votes


def test_phase_vote_only_for_driven_periodic_labels():
    # a chaotic verdict with a phase-dependent departure keeps its votes
    ev = RuleEvidence(
        structure=None, rosenstein_positive=True, wolf_positive=True, zero_one_k=0.95,
        surrogates_rejected=True, lines="broadband", n_cycles=100.0, cycles_rejected=True,
        driven=True, cycle_spread=0.2, phase_spread=0.2,
    )  # fmt: skip
    out = combine(ev, RULE)
    assert out.label == "chaotic"
    assert "phase" not in out.votes


def _orbit() -> np.ndarray:
    """A journal that sweeps across its clearance once per drive period."""
    phase = (np.arange(PER_PERIOD * CYCLES) % PER_PERIOD) / PER_PERIOD
    return np.tanh(8.0 * np.sin(2.0 * np.pi * phase))


def _with_impacts(u0: float) -> np.ndarray:
    """The orbit plus a ringing impact whose instant in each cycle follows the logistic
    map (chaotic): a departure confined to the impact's phases and not smooth over a
    sample, about 0.09 of the standard deviation."""
    x = _orbit()
    u = u0
    for c in range(CYCLES):
        u = 4.0 * u * (1.0 - u)
        k = np.arange(c * PER_PERIOD, c * PER_PERIOD + 25)
        s = k - (c * PER_PERIOD + 5.0 + 6.0 * u)
        x[k] += 1.25 * np.where(s > 0, np.exp(-s / 2.5) * np.sin(2.6 * s), 0.0)
    return x


def _rig(x: np.ndarray, level: float, seed: int) -> xr.Dataset:
    """``x`` plus AR(1) noise (phi = 0.9) of ``level`` of its spread, with the crank
    angle as the phase variable (T = 1 s at 100 samples per period)."""
    e = np.random.default_rng(seed).standard_normal(x.size)
    noise = np.empty_like(e)
    noise[0] = e[0]
    for i in range(1, e.size):
        noise[i] = 0.9 * noise[i - 1] + np.sqrt(1.0 - 0.81) * e[i]
    t = np.arange(x.size) / PER_PERIOD
    return xr.Dataset(
        {"x": ("time", x + level * x.std() * noise), "crank": ("time", 2.0 * np.pi * t)},
        coords={"time": t},
    )


@pytest.mark.parametrize("level", [0.05, 0.10])
def test_periodic_orbit_plus_coloured_noise_is_confidently_periodic(level):
    v = classify(_rig(_orbit(), level, seed=3), variable="x", phase_variable="crank", rng=0)
    assert v.label == "periodic"
    assert v.period == 1
    assert v.confidence == 1.0
    assert v.phase_spread <= RULE.cluster_tol
    assert "phase" not in v.votes


@pytest.mark.slow
@pytest.mark.parametrize("u0", [0.3123, 0.3123 * (1.0 + 1e-12)])
def test_chaotic_impacts_are_not_confidently_periodic(u0):
    # the logistic map loses the 1e-12 perturbation within the series: only what holds
    # for either trajectory is asserted
    v = classify(_rig(_with_impacts(u0), 0.01, seed=4), variable="x",
                 phase_variable="crank", rng=0)  # fmt: skip
    assert v.phase_spread == pytest.approx(0.09, abs=0.02)
    assert v.label != "periodic" or v.confidence < 0.9
    if v.label == "periodic":
        assert v.votes["phase"] == "opposes"
