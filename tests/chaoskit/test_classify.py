"""The verdict on systems whose answer is known, and the combination rule itself."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import chaoskit
from chaoskit import SectionStructure, Verdict, VerdictRule, classify, systems
from chaoskit.verdict import RuleEvidence, RuleOutcome, combine
from tests.chaoskit.test_sections import duffing_dataset
from tests.chaoskit.test_surrogates import ar1


def _combine(**kwargs) -> RuleOutcome:
    """The rule on evidence given as keywords (``rule`` among them)."""
    rule = kwargs.pop("rule")
    return combine(RuleEvidence(**kwargs), rule)


def _fields(outcome: RuleOutcome) -> tuple:
    """The outcome's label, period, confidence, reason, votes and needs, in that order."""
    o = outcome
    return o.label, o.period, o.confidence, o.reason, o.votes, o.needs


DRIVE = 2 * np.pi / 1.2  # forced Duffing drive period, s


def noisy_sine(n: int = 3000, dt: float = 0.05, noise: float = 0.05, seed: int = 0) -> np.ndarray:
    """sin(2π·0.2 t) plus white noise of ``noise`` times the amplitude (5 % by default)."""
    t = np.arange(n) * dt
    return np.sin(2 * np.pi * 0.2 * t) + noise * np.random.default_rng(seed).standard_normal(n)


def duffing_x(gamma: float, n_periods: int) -> xr.Dataset:
    return duffing_dataset(gamma, n_periods, spp=50)[["x"]]


# (name, data factory, classify keywords, expected label, expected period)
CASES = [
    ("logistic r=3.2", lambda: systems.logistic(800, r=3.2), {}, "periodic", 2),
    ("logistic r=3.5", lambda: systems.logistic(800, r=3.5), {}, "periodic", 4),
    ("logistic r=3.9", lambda: systems.logistic(1000, r=3.9), {}, "chaotic", None),
    ("henon", lambda: systems.henon(1000)[:, 0], {}, "chaotic", None),
    ("lorenz", lambda: systems.lorenz(10_000, dt=0.01)[:, 0], {"dt": 0.01}, "chaotic", None),
    ("rossler", lambda: systems.rossler(3000, dt=0.1)[:, 0], {"dt": 0.1}, "chaotic", None),
    ("duffing periodic window", lambda: duffing_x(0.37, 80), {"drive_period": DRIVE},
     "periodic", 5),
    ("duffing gamma=0.28", lambda: duffing_x(0.28, 80), {"drive_period": DRIVE}, "periodic", 2),
    ("duffing gamma=0.5", lambda: duffing_x(0.5, 120), {"drive_period": DRIVE}, "chaotic", None),
    ("torus", lambda: systems.torus(3000, dt=0.05), {"dt": 0.05}, "quasi-periodic", None),
    ("sine + 5% noise", lambda: noisy_sine(), {"dt": 0.05}, "periodic", 1),
    ("constant", lambda: np.full(500, 2.5), {}, "equilibrium", None),
    ("white noise", lambda: np.random.default_rng(1).standard_normal(1000), {}, "noise-like",
     None),
    ("red noise", lambda: ar1(2000, 0.9, 3), {"dt": 1.0}, "noise-like", None),
]  # fmt: skip


@pytest.mark.parametrize(
    ("make", "kwargs", "label", "period"),
    [pytest.param(*case[1:], id=case[0]) for case in CASES],
)
def test_verdict_on_known_systems(make, kwargs: dict, label: str, period: int | None) -> None:
    verdict = classify(make(), rng=1, **kwargs)
    assert verdict.label == label, verdict.reason
    assert verdict.period == period
    assert 0.5 <= verdict.confidence <= 1.0
    assert verdict.reason
    if label == "equilibrium":
        return
    # the evidence travels with the verdict
    assert verdict.lag >= 1 and verdict.embedding_dim >= 1
    assert verdict.structure is not None and verdict.section is not None
    assert verdict.zero_one is not None and verdict.surrogates is not None
    # a forced series also votes with its noisy-periodic-orbit test
    assert set(verdict.votes) == {
        "lines", "section", "rosenstein", "wolf", "zero_one", "surrogates"
    } | ({"cycles"} if "drive_period" in kwargs else set())  # fmt: skip
    assert (verdict.surrogates_cycle is not None) == ("drive_period" in kwargs)
    assert verdict.needs == ()
    if label == "chaotic":
        assert verdict.rosenstein_positive and verdict.wolf_positive
        assert verdict.surrogates.rejected and verdict.structure.kind == "scattered"
        assert verdict.lines.kind == "broadband"
        assert verdict.confidence == 1.0 or verdict.votes["zero_one"] == "neutral"


@pytest.mark.parametrize("seed", range(3))
def test_noise_is_never_chaotic(seed: int) -> None:
    for x, dt in ((np.random.default_rng(seed).standard_normal(800), None),
                  (ar1(1500, 0.95, seed), 0.01)):  # fmt: skip
        assert classify(x, dt=dt, rng=seed).label == "noise-like"


def test_same_seed_same_verdict() -> None:
    x = systems.henon(600)[:, 0]
    a, b = classify(x, rng=4), classify(x, rng=4)
    np.testing.assert_array_equal(a.surrogates.surrogate_statistics,
                                  b.surrogates.surrogate_statistics)  # fmt: skip
    np.testing.assert_equal(a.summary(), b.summary())


def test_dataset_and_dataarray_input() -> None:
    ds = chaoskit.load_trajectory(systems.henon(800), dt=1.0, variables=["x", "y"])
    with pytest.raises(ValueError, match="several variables"):
        classify(ds)
    v = classify(ds, variable="x", rng=0)
    assert v.label == "chaotic" and v.variable == "x" and v.kind == "flow"
    step = xr.Dataset({"x": ("step", systems.logistic(800, r=3.5))},
                      coords={"step": np.arange(800)})  # fmt: skip
    v = classify(step["x"], rng=0)
    assert (v.label, v.period, v.kind, v.dt) == ("periodic", 4, "map", 1.0)


def test_stroboscopic_by_drive_angle() -> None:
    ds = duffing_dataset(0.28, 80, spp=50)
    ds["drive_angle"] = ("time", 1.2 * ds["time"].values, {"units": "rad", "long_name": "phase"})
    v = classify(ds, variable="x", phase_variable="drive_angle", rng=0)
    assert (v.label, v.period, v.kind) == ("periodic", 2, "forced")
    assert v.characteristic_time == pytest.approx(DRIVE, rel=1e-9)


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="too short"):
        classify(systems.logistic(100, r=3.9))
    with pytest.raises(ValueError, match="continuous-time"):
        classify(systems.logistic(500), drive_period=1.0)
    with pytest.raises(ValueError, match="not both"):
        ds = duffing_dataset(0.28, 10, spp=50)
        ds["a"] = ("time", ds["time"].values, {"units": "rad", "long_name": "a"})
        classify(ds, variable="x", drive_period=DRIVE, phase_variable="a")
    with pytest.raises(ValueError, match="NaN"):
        classify(np.r_[np.nan, systems.logistic(500)])


# ----------------------------------------------------------------- the rule alone


def _structure(kind: str, n_clusters: int = 0) -> SectionStructure:
    nan = float("nan")
    return SectionStructure(
        kind=kind, n_clusters=n_clusters, labels=np.zeros(50, dtype=np.int64),
        cluster_radius=nan, cyclic_fraction=nan, curve_closure=nan, curve_coverage=nan,
        curve_thickness=nan, n_points=50, scale=1.0,
    )  # fmt: skip


RULE = VerdictRule()


def test_rule_noise_beats_positive_exponents() -> None:
    label, *_ = _fields(_combine(structure=_structure("scattered"), rosenstein_positive=True,
                        wolf_positive=True, zero_one_k=1.0, surrogates_rejected=False,
                        rule=RULE))  # fmt: skip
    assert label == "noise-like"


def test_rule_chaos_needs_every_piece() -> None:
    # K between the thresholds: the 0–1 test cannot stand in for an exponent (tested in
    # test_verdict_evidence.py)
    full = {"structure": _structure("scattered"), "rosenstein_positive": True,
            "wolf_positive": True, "zero_one_k": 0.5, "surrogates_rejected": True}  # fmt: skip
    assert _combine(**full, rule=RULE).label == "chaotic"
    assert _combine(**full, rule=RULE).confidence == 1.0
    for key, value in (("rosenstein_positive", False), ("wolf_positive", None),
                       ("surrogates_rejected", None)):  # fmt: skip
        label, _, confidence, reason, _, needs = _fields(
            _combine(**{**full, key: value}, rule=RULE)
        )
        assert label == "undetermined" and np.isnan(confidence) and needs
        assert reason.startswith("the evidence cannot decide: needs")
    # a regular-looking section counts unless the spectrum speaks against it: broadband
    # over enough cycles, or lines that are not one period's harmonics
    near = {**full, "lines": "unresolved"}
    label, period, _, _, _, needs = _fields(
        _combine(**{**near, "structure": _structure("clusters", 3)}, rule=RULE)
    )
    assert (label, period) == ("undetermined", None)
    assert any("3 tight clusters but the spectrum is not the harmonics" in n for n in needs)
    short = {**full, "lines": "broadband", "n_cycles": 8.0}
    clusters = _combine(**{**short, "structure": _structure("clusters", 3)}, rule=RULE)
    assert (clusters.label, clusters.period) == ("periodic", 3)
    torus = {**full, "lines": "quasi-periodic", "structure": _structure("clusters", 1)}
    assert _combine(**torus, rule=RULE).label == "quasi-periodic"
    assert _combine(**{**near, "structure": _structure("closed-curve")}, rule=RULE).label == (
        "undetermined"
    )


def test_rule_confidence_counts_disagreement() -> None:
    label, period, confidence, _, votes, _ = _fields(_combine(
        structure=_structure("clusters", 2), rosenstein_positive=False, wolf_positive=True,
        zero_one_k=0.5, surrogates_rejected=True, rule=RULE, lines=None,
    ))  # fmt: skip
    assert (label, period) == ("periodic", 2)
    assert votes == {"lines": "missing", "section": "supports", "rosenstein": "supports",
                     "wolf": "opposes", "zero_one": "neutral",
                     "surrogates": "neutral"}  # fmt: skip
    assert confidence == pytest.approx(2 / 3)
    label, _, confidence, _, _, _ = _fields(_combine(
        structure=_structure("closed-curve"), rosenstein_positive=False, wolf_positive=False,
        zero_one_k=0.05, surrogates_rejected=True, rule=RULE, lines="quasi-periodic",
    ))  # fmt: skip
    assert label == "quasi-periodic" and confidence == 1.0


@pytest.mark.parametrize(
    ("field", "value"),
    [("min_growth", 0.0), ("alpha", 1.0), ("min_effect", 1.0), ("max_period", 0),
     ("zero_one_regular", 0.9)],
)  # fmt: skip
def test_rule_validation(field: str, value: float) -> None:
    with pytest.raises(ValueError):
        VerdictRule(**{field: value})


def test_verdict_is_frozen_and_tabulates() -> None:
    v = classify(systems.logistic(600, r=3.2), rng=0)
    assert isinstance(v, Verdict)
    with pytest.raises(dataclasses.FrozenInstanceError):
        v.label = "chaotic"  # type: ignore[misc]
    row = v.summary()
    assert row["label"] == "periodic" and row["period"] == 2.0
    assert np.isnan(row["mle_rosenstein"])  # Rosenstein refuses an exactly periodic series
    assert "rosenstein" in v.errors and v.votes["rosenstein"] == "missing"
    ds = v.to_dataset()
    assert ds.sizes["variable"] == 1 and str(ds["label"].values[0]) == "periodic"


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(10))
def test_verdicts_are_stable_across_seeds_and_lengths(seed: int) -> None:
    g = np.random.default_rng(100 + seed)
    assert classify(g.standard_normal(1000), rng=seed).label == "noise-like"
    assert classify(ar1(2000, 0.9, seed), dt=1.0, rng=seed).label == "noise-like"
    assert classify(noisy_sine(seed=seed), dt=0.05, rng=seed).label == "periodic"
    assert classify(systems.torus(2000 + 500 * seed), dt=0.05, rng=seed).label == ("quasi-periodic")
    x = systems.logistic(600 + 100 * seed, r=3.9, x0=0.1 + 0.05 * seed)
    assert classify(x, rng=seed).label == "chaotic"


def _words(text: str) -> str:
    return " ".join(text.split())


def test_docs_state_the_same_rule_as_the_docstring() -> None:
    from tests.conftest import verdict_docs_block

    doc = classify.__doc__ or ""
    rule = doc[doc.index("**Rule.**") + len("**Rule.**") : doc.index("Parameters")]
    block = verdict_docs_block("rule")
    assert _words(rule).rstrip("-") == _words(block)


def test_rule_noise_needs_the_low_dimensional_test_to_fail_too() -> None:
    noise = {"structure": _structure("scattered"), "rosenstein_positive": False,
             "wolf_positive": False, "zero_one_k": 1.0, "surrogates_rejected": False,
             "lines": "broadband", "n_cycles": 100.0}  # fmt: skip
    assert _combine(**noise, rule=RULE).label == "noise-like"
    assert _combine(**noise, low_dim_rejected=False, rule=RULE).label == "noise-like"
    label, _, confidence, _, _, needs = _fields(_combine(**noise, low_dim_rejected=True, rule=RULE))
    assert label == "undetermined" and np.isnan(confidence)
    assert any("3 delay coordinates" in n for n in needs)
    # it never makes chaos: that still needs the first test to reject
    chaos = {**noise, "rosenstein_positive": True, "wolf_positive": True}
    assert _combine(**chaos, low_dim_rejected=True, rule=RULE).label == "undetermined"


def test_white_noise_fails_the_low_dimensional_test_as_well() -> None:
    v = classify(np.random.default_rng(5).standard_normal(2000), rng=5)
    assert v.label == "noise-like"
    assert v.embedding_dim > 3 and v.surrogates_low_dim is not None
    assert not v.surrogates_low_dim.rejected and v.surrogates_low_dim.embedding_dim == 3


def test_a_sampled_noise_fails_the_one_step_test_as_well() -> None:
    # AR(1) sampled as a flow: the first test predicts one delay ahead, the one-step test
    # one (thinned) sample ahead in three coordinates; linear noise is no more predictable
    # than its surrogates at either horizon
    v = classify(ar1(2000, 0.9, seed=3), dt=0.01, rng=3)
    assert v.label == "noise-like", v.reason
    one = v.surrogates_one_step
    assert v.surrogates is not None and v.surrogates.horizon > 1 and one is not None
    assert (one.horizon, one.embedding_dim, one.theiler_window) == (1, 3, 3 * one.lag)
    assert not one.rejected


@pytest.mark.slow
def test_a_chaotic_flow_predictable_only_one_sample_ahead_is_not_called_noise() -> None:
    # dysts' OscillatingFlow (a periodically forced flow), 200 periods at 100 samples each:
    # a locally constant predictor one delay ahead in ten coordinates with a period-long
    # Theiler window is no better than on the surrogates, so the verdict used to say
    # "noise-like" with confidence 1; in three coordinates it beats every surrogate by
    # about 30 %
    pytest.importorskip("dysts")
    from benchmarks import corpus_flows

    x = corpus_flows.dysts_flow("OscillatingFlow", 20000, pts_per_period=100, cache_dir=None).x
    v = classify(x, dt=1.0, rng=1)
    assert v.surrogates is not None and not v.surrogates.rejected
    assert v.label == "undetermined", v.reason
    assert v.surrogates_one_step is not None and v.surrogates_one_step.rejected
    assert v.surrogates_one_step.effect > 0.2
    assert any("one sample ahead" in n for n in v.needs)


def test_a_pandas_time_index_sets_dt() -> None:
    """A Series indexed by time stamps is a flow sampled at their interval, not a map."""
    x = noisy_sine(3000, dt=0.01)
    expected = classify(x, dt=0.01, rng=0)
    stamps = pd.date_range("2020", periods=3000, freq="10ms")
    for index in (stamps, pd.Index(np.arange(3000) * 0.01)):
        v = classify(pd.Series(x, index=index), rng=0)
        assert (v.kind, v.label, v.period) == ("flow", expected.label, expected.period)
        assert v.dt == pytest.approx(0.01, rel=1e-12)
        assert v.reason == expected.reason
    with pytest.raises(ValueError, match=r"^dt=0\.02 contradicts the time index of the Series"):
        classify(pd.Series(x, index=stamps), dt=0.02)
    jitter = stamps.to_numpy().copy()
    jitter[1000:] += np.timedelta64(3, "ms")
    with pytest.raises(ValueError, match=r"^the time index of the Series is not uniform"):
        classify(pd.Series(x, index=pd.DatetimeIndex(jitter)))


# ----------------------------------------------------------------- the noisy-periodic null


def _clusters(k: int, radius: float) -> SectionStructure:
    return dataclasses.replace(_structure("clusters", k), cluster_radius=radius)


# what a period-1 orbit plus noise shows the other estimators: a broadband spectrum over
# many drive periods, two clearly positive exponents, K near 1, IAAFT rejected
NOISY_ORBIT = {"rosenstein_positive": True, "wolf_positive": True, "zero_one_k": 0.95,
               "surrogates_rejected": True, "lines": "broadband", "n_cycles": 120.0,
               "driven": True, "noise": 0.1}  # fmt: skip


def test_rule_a_driven_orbit_plus_white_noise_is_periodic_with_its_noise_stated() -> None:
    label, period, confidence, reason, votes, needs = _fields(_combine(
        structure=_clusters(1, 0.24), cycles_rejected=False, cycle_spread=0.0, rule=RULE,
        **NOISY_ORBIT,
    ))  # fmt: skip
    assert (label, period, confidence, needs) == ("periodic", 1, 1.0, ())
    assert "a periodic orbit plus noise (measurement noise about 0.1 of the standard" in reason
    assert votes["cycles"] == "supports" and votes["section"] == "supports"
    # the estimators that noise fools are no evidence here
    assert {votes[k] for k in ("rosenstein", "wolf", "zero_one", "lines")} == {"neutral"}
    # before this rule the same evidence was called chaotic: without a drive it still is
    undriven = {**NOISY_ORBIT, "driven": False}
    assert _combine(structure=_clusters(1, 0.24), rule=RULE, **undriven).label == "chaotic"


def test_rule_cycle_to_cycle_determinism_within_the_cluster_tolerance_is_periodic() -> None:
    # the cycle test rejects, but what varies beyond white noise is within cluster_tol
    label, period, _, reason, votes, _ = _fields(_combine(
        structure=_clusters(2, 0.02), cycles_rejected=True, cycle_spread=0.02, rule=RULE,
        **NOISY_ORBIT,
    ))  # fmt: skip
    assert (label, period) == ("periodic", 2)
    assert "the cycle-shuffled surrogate test rejects, within that tolerance" in reason
    assert votes["cycles"] == "neutral"


def test_rule_a_driven_chaotic_label_needs_the_noisy_orbit_null_rejected() -> None:
    chaos = {**NOISY_ORBIT, "structure": _structure("scattered")}
    label, _, _, reason, votes, _ = _fields(
        _combine(cycles_rejected=True, cycle_spread=0.01, rule=RULE, **chaos)
    )
    assert label == "chaotic" and votes["cycles"] == "supports"
    assert "than their cycle-shuffled ones" in reason
    # a departure from the mean cycle that is not white and exceeds cluster_tol also rejects
    label, _, _, reason, votes, _ = _fields(
        _combine(cycles_rejected=False, cycle_spread=0.15, rule=RULE, **chaos)
    )
    assert label == "chaotic" and votes["cycles"] == "supports"  # the spread rejects the null
    assert "departure from the mean cycle is not white noise (0.15 of" in reason
    label, _, confidence, _, _, needs = _fields(
        _combine(cycles_rejected=None, cycle_spread=0.01, rule=RULE, **chaos)
    )
    assert label == "undetermined" and np.isnan(confidence)
    assert needs[0].startswith("evidence beyond a noisy periodic orbit")
    # the cycle test ran and does not reject, the spread is within cluster_tol: a section
    # scattered by coloured noise about a periodic orbit
    label, period, _, reason, _, _ = _fields(
        _combine(cycles_rejected=False, cycle_spread=0.01, rule=RULE, **chaos)
    )
    assert (label, period) == ("periodic", 1)
    assert "a periodic orbit plus coloured noise" in reason


def test_rule_a_wandering_beyond_the_tolerance_is_not_a_noisy_orbit() -> None:
    # tight clusters (noise allowance) but a correlated spread above cluster_tol: chaos if
    # the rest says so, never a noisy periodic orbit
    label, *_ = _fields(_combine(
        structure=_clusters(1, 0.17), cycles_rejected=False, cycle_spread=0.15, rule=RULE,
        **NOISY_ORBIT,
    ))  # fmt: skip
    assert label == "chaotic"
    weak = {**NOISY_ORBIT, "wolf_positive": False, "zero_one_k": 0.5}
    label, *_ = _fields(_combine(
        structure=_clusters(1, 0.17), cycles_rejected=False, cycle_spread=0.15, rule=RULE,
        **weak,
    ))  # fmt: skip
    assert label == "undetermined"


@pytest.mark.parametrize("noise", [0.0, 0.05])
def test_noisy_periodic_duffing_is_periodic_and_chaotic_duffing_stays_chaotic(noise) -> None:
    rng = np.random.default_rng(11)
    orbit = duffing_x(0.28, 150)  # period-2 window
    orbit["x"] = orbit["x"] + noise * float(orbit["x"].std()) * rng.standard_normal(
        orbit.sizes["time"]
    )
    v = classify(orbit, drive_period=DRIVE, rng=0)
    assert (v.label, v.period) == ("periodic", 2)
    assert v.surrogates_cycle is not None and not v.surrogates_cycle.rejected
    chaos = duffing_x(0.5, 150)
    v = classify(chaos, drive_period=DRIVE, rng=0)
    assert v.label == "chaotic" and v.surrogates_cycle.rejected
    assert v.cycle_spread > 0.5  # measured 0.96
