"""A noise-like verdict on a driven series must beat "a periodic orbit plus coloured noise".

For a driven series the departure from the phase-locked mean cycle is read as measurement
noise when the mean cycle carries most of the variance and the departure is consistent
with a linear Gaussian process (its IAAFT surrogate test does not reject): the series is
then periodic, with the noise's level and colour stated. Where that departure is more
predictable than linear noise, it is the surrogate evidence chaos needs (the test of the
whole series misses it when the mean cycle dilutes it).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from chaoskit import SectionStructure, VerdictRule, classify, systems
from chaoskit.verdict import RuleEvidence, RuleOutcome, combine
from chaoskit.verdict._cycles import OrbitResidual


def _combine(**kwargs) -> RuleOutcome:
    """The rule on evidence given as keywords (``rule`` among them)."""
    rule = kwargs.pop("rule")
    return combine(RuleEvidence(**kwargs), rule)


def _fields(outcome: RuleOutcome) -> tuple:
    """The outcome's label, period, confidence, reason, votes and needs, in that order."""
    o = outcome
    return o.label, o.period, o.confidence, o.reason, o.votes, o.needs


RULE = VerdictRule()
PER_PERIOD = 100


def ar1(n: int, seed: int, phi: float = 0.9) -> np.ndarray:
    """Unit-variance AR(1) noise."""
    e = np.random.default_rng(seed).standard_normal(n)
    out = np.empty(n)
    out[0] = e[0]
    for i in range(1, n):
        out[i] = phi * out[i - 1] + np.sqrt(1.0 - phi * phi) * e[i]
    return out


def harmonic_orbit(n_cycles: int = 100) -> np.ndarray:
    """A period-1 orbit with harmonics, one drive period of 1 s at 100 samples."""
    w = 2 * np.pi
    t = np.arange(n_cycles * PER_PERIOD) / PER_PERIOD
    return (
        np.sin(w * t)
        + 0.5 * np.sin(2 * w * t + 1.0)
        + 0.3 * np.sin(3 * w * t + 0.5)
        + 0.2 * np.sin(5 * w * t)
    )


def test_a_harmonic_orbit_with_ar1_noise_is_periodic() -> None:
    """AR(1) noise (phi = 0.9) at 10 % of the standard deviation: the cycle-shuffled test
    rejects (the noise carries over a cycle boundary by its own short memory) and so does
    the IAAFT test of the whole series, yet the departure from the mean cycle is linear
    noise. Before the rule read that departure, this series was undetermined."""
    x = harmonic_orbit()
    x = x + 0.10 * x.std() * ar1(x.size, seed=0)
    v = classify(x, dt=1.0 / PER_PERIOD, drive_period=1.0, rng=0)
    assert (v.label, v.period) == ("periodic", 1)
    assert v.confidence == 1.0
    assert "periodic orbit plus coloured measurement noise" in v.reason
    assert "lag-one autocorrelation 0." in v.reason


def test_driven_chaos_with_the_same_noise_is_not_periodic() -> None:
    """The forced Duffing oscillator in its chaotic regime with the same noise: its mean
    cycle carries a few per cent of the variance, so the departure is not noise."""
    _, xv = systems.duffing(6000)
    x = xv[:, 0] + 0.10 * xv[:, 0].std() * ar1(6000, seed=3)
    v = classify(x, dt=2 * np.pi / 1.2 / PER_PERIOD, drive_period=2 * np.pi / 1.2, rng=0)
    assert v.label != "periodic"


@pytest.mark.parametrize("drive_period", [None, 1.0])
def test_ar1_noise_is_still_noise_like(drive_period: float | None) -> None:
    """Pure AR(1) noise, with or without a (meaningless) drive period: no mean cycle
    carries its variance."""
    x = ar1(6000, seed=5)
    v = classify(x, dt=1.0 / PER_PERIOD, drive_period=drive_period, rng=0)
    assert v.label == "noise-like"


def _structure(kind: str) -> SectionStructure:
    return SectionStructure(
        kind=kind, n_clusters=1 if kind == "clusters" else 0, labels=np.zeros(50, int),
        cluster_radius=0.01, cyclic_fraction=1.0, curve_closure=np.nan,
        curve_coverage=np.nan, curve_thickness=np.nan, n_points=50, scale=1.0,
    )  # fmt: skip


def _residual(fraction: float, rejected: bool, level: float = 0.1) -> OrbitResidual:
    test = SimpleNamespace(rejected=rejected)
    return OrbitResidual(fraction=fraction, level=level, lag_one=0.9, cycles=1, test=test)  # type: ignore[arg-type]


NOISE_LIKE = {
    "structure": _structure("scattered"), "rosenstein_positive": True, "wolf_positive": True,
    "zero_one_k": 0.5, "surrogates_rejected": False, "rule": RULE, "lines": "broadband",
    "n_cycles": 100.0, "cycles_rejected": False, "driven": True, "noise": 0.1,
}  # fmt: skip


def test_noise_like_must_beat_a_periodic_orbit_plus_coloured_noise() -> None:
    # without the residual, or a mean cycle carrying little: noise-like, as before
    assert _combine(**NOISE_LIKE, cycle_spread=0.08).label == "noise-like"
    small = _residual(0.2, rejected=False)
    assert _combine(**NOISE_LIKE, cycle_spread=0.08, orbit_residual=small).label == "noise-like"
    # a dominant mean cycle and a linear departure: periodic; a phase-dependent spread
    # beyond the tolerance counts against it
    label, period, confidence, reason, votes, needs = _fields(
        _combine(**NOISE_LIKE, cycle_spread=0.08, orbit_residual=_residual(0.99, rejected=False))
    )
    assert (label, period, needs) == ("periodic", 1, ())
    assert votes["residual"] == "supports" and votes["cycles"] == "opposes"
    assert confidence == 0.5
    assert "carries 99 % of the variance" in reason
    assert "correlation time 9.5 samples" in reason
    # within the tolerance the orbit needs no noise-like candidate at all
    label, _, confidence, *_ = _fields(
        _combine(
            **{**NOISE_LIKE, "surrogates_rejected": True, "cycles_rejected": True},
            cycle_spread=0.02,
            orbit_residual=_residual(0.99, rejected=False),
        )
    )
    assert (label, confidence) == ("periodic", 1.0)


def test_a_departure_too_large_for_noise_is_not_read_as_noise() -> None:
    label, *_, needs = _fields(
        _combine(**NOISE_LIKE, cycle_spread=0.6, orbit_residual=_residual(0.64, False, level=0.6))
    )
    assert label == "undetermined"
    assert needs[0].startswith("a departure from the mean cycle over the drive that is more")
    assert "0.6 of the standard deviation" in needs[0]


def test_a_nonlinear_departure_is_the_surrogate_evidence_of_driven_chaos() -> None:
    args = {**NOISE_LIKE, "zero_one_k": 1.0, "cycle_spread": 0.59}
    label, _, confidence, reason, votes, _ = _fields(
        _combine(**args, orbit_residual=_residual(0.65, rejected=True, level=0.6))
    )
    assert label == "chaotic"
    assert votes["surrogates"] == "opposes" and votes["residual"] == "supports"
    assert confidence == pytest.approx(7 / 8, abs=1e-12)
    assert "the departure from the mean cycle over the drive (which carries 65 % of" in reason
    # the same departure without a dominant mean cycle is no such evidence
    label = _combine(**args, orbit_residual=_residual(0.3, rejected=True, level=0.8)).label
    assert label == "noise-like"
