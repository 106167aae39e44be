"""Determinism of a forced series shown in a few delay coordinates, confirmed.

When the IAAFT surrogate test in the full embedding dimension does not reject but the one
in three delay coordinates (or one sample ahead) does, that test is repeated at half the
level with twice as many surrogates. For a forced series whose mean cycle carries most of
its variance (not noise) a confirmed rejection is the determinism a chaotic label needs;
everything else chaos needs (two clearly positive exponents, a spectrum that is not lines,
regular motion ruled out, a departure beyond a noisy periodic orbit) is unchanged.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from chaoskit import SectionStructure, VerdictRule, surrogate_test, systems
from chaoskit.verdict import RuleEvidence, combine
from chaoskit.verdict._cycles import OrbitResidual
from chaoskit.verdict._evidence import confirm_low_dim

RULE = VerdictRule()


def _structure(kind: str) -> SectionStructure:
    return SectionStructure(
        kind=kind, n_clusters=1 if kind == "clusters" else 0, labels=np.zeros(50, int),
        cluster_radius=0.01, cyclic_fraction=1.0, curve_closure=np.nan,
        curve_coverage=np.nan, curve_thickness=np.nan, n_points=50, scale=1.0,
    )  # fmt: skip


def _residual(fraction: float) -> OrbitResidual:
    test = SimpleNamespace(rejected=False)  # the departure's own IAAFT test: no rejection
    return OrbitResidual(fraction=fraction, level=0.6, lag_one=0.1, cycles=1, test=test)  # type: ignore[arg-type]


#: The 150 rpm housing of the machine corpus at 10 % white noise: everything chaos needs
#: but the IAAFT test in the embedding dimension.
HOUSING = {
    "structure": _structure("scattered"), "rosenstein_positive": True, "wolf_positive": True,
    "zero_one_k": 0.99, "surrogates_rejected": False, "low_dim_rejected": True,
    "lines": "broadband", "n_cycles": 100.0, "cycles_rejected": False, "driven": True,
    "noise": 0.1, "cycle_spread": 0.59, "phase_spread": 0.59,
    "orbit_residual": _residual(0.64),
}  # fmt: skip


def test_a_confirmed_low_dim_rejection_is_determinism_for_a_forced_series() -> None:
    out = combine(RuleEvidence(**HOUSING, low_dim_confirmed=True), RULE)
    assert out.label == "chaotic"
    assert out.votes["low_dim"] == "supports"
    assert out.votes["surrogates"] == "opposes"  # the first test still counts
    assert out.confidence == pytest.approx(7 / 9, abs=1e-12)
    assert "in 3 delay coordinates, at 0.05 and again at 0.025" in out.reason
    assert "carries 64 % of the variance" in out.reason


@pytest.mark.parametrize("confirmed", [None, False])
def test_an_unconfirmed_rejection_decides_nothing(confirmed: bool | None) -> None:
    """Before this evidence existed, every such series was undetermined."""
    out = combine(RuleEvidence(**HOUSING, low_dim_confirmed=confirmed), RULE)
    assert out.label == "undetermined"
    assert out.needs[0].startswith("a longer or more finely sampled series: the data are more")


def test_confirmation_needs_a_dominant_mean_cycle() -> None:
    """Without a mean cycle carrying at least half the variance the series may be noise:
    the confirmed test is not read (noise fools the exponents and the 0–1 test)."""
    ev = {**HOUSING, "orbit_residual": _residual(0.3)}
    assert combine(RuleEvidence(**ev, low_dim_confirmed=True), RULE).label == "undetermined"
    ev = {**HOUSING, "orbit_residual": None, "driven": False}
    assert combine(RuleEvidence(**ev, low_dim_confirmed=True), RULE).label == "undetermined"


def test_confirmation_does_not_replace_the_exponents_or_the_orbit_null() -> None:
    one = {**HOUSING, "wolf_positive": False, "zero_one_k": 0.5}
    assert combine(RuleEvidence(**one, low_dim_confirmed=True), RULE).label == "undetermined"
    orbit = {**HOUSING, "cycle_spread": 0.02, "structure": _structure("clusters")}
    assert combine(RuleEvidence(**orbit, low_dim_confirmed=True), RULE).label == "periodic"


def _low_dim(x: np.ndarray, seed: int):
    return surrogate_test(x, embedding_dim=3, lag=1, horizon=1, theiler_window=3, rng=seed)


def test_a_chaotic_map_with_10_percent_noise_is_confirmed() -> None:
    """Hénon's x with white noise of 10 % of its standard deviation: both the test at 0.05
    (19 surrogates) and its repetition at 0.025 (39) reject."""
    x = systems.henon(2000)[:, 0]
    x = x + 0.10 * x.std() * np.random.default_rng(3).standard_normal(x.size)
    first = _low_dim(x, seed=1)
    assert first.rejected
    errors: dict[str, str] = {}
    res = confirm_low_dim(
        x, lag=1, tests=(first, None), n_surrogates=19, max_samples=4096, rule=RULE,
        gen=np.random.default_rng(2), errors=errors,
    )  # fmt: skip
    assert res is not None and errors == {}
    assert (res.n_surrogates, res.alpha) == (39, 0.025)
    assert res.rejected and res.p_value == pytest.approx(0.025, abs=1e-12)
    assert res.effect > 0.3


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_noisy_periodic_orbit_gives_no_evidence(seed: int) -> None:
    """A sine of 50 samples per period with 10 % white noise: nothing is more predictable
    than its surrogates in three coordinates, so there is nothing to confirm; and a
    confirmation of a given rejection on it does not reject."""
    t = np.arange(5000)
    x = np.sin(2 * np.pi * t / 50) + 0.1 * np.random.default_rng(seed).standard_normal(t.size)
    first = _low_dim(x[::4], seed=seed)
    assert not first.rejected
    errors: dict[str, str] = {}
    kwargs = {"lag": 4, "n_surrogates": 19, "max_samples": 4096, "rule": RULE, "errors": errors}
    assert confirm_low_dim(x, tests=(first, None), gen=np.random.default_rng(0), **kwargs) is None
    forced = SimpleNamespace(rejected=True, embedding_dim=3, lag=1, horizon=1, theiler_window=3)
    res = confirm_low_dim(x, tests=(None, forced), gen=np.random.default_rng(seed), **kwargs)  # type: ignore[arg-type]
    assert res is not None and not res.rejected
