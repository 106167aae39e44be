"""One verdict per motion: coordinates that disagree are reconciled by the joint evidence."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import (
    MotionVerdict,
    SectionStructure,
    VerdictRule,
    classify_motion,
    lyapunov_rosenstein,
    systems,
)
from chaoskit.verdict import RuleOutcome
from chaoskit.verdict._motion_combine import combine_motion

OMEGA = 1.2
DRIVE = 2 * np.pi / OMEGA


@pytest.fixture(scope="module")
def duffing_with_phase() -> tuple[np.ndarray, float]:
    """Chaotic forced Duffing position beside its forcing cos(ωt) (periodic by construction)."""
    t, s = systems.duffing(4000, gamma=0.5, samples_per_period=40)
    return np.column_stack([s[:, 0], np.cos(OMEGA * t)]), float(t[1] - t[0])


def test_duffing_position_beside_its_forcing_phase_is_chaotic(duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    mv = classify_motion(data, dt=dt, drive_period=DRIVE, rng=0)
    assert isinstance(mv, MotionVerdict)
    assert mv.label == "chaotic"
    assert mv.confidence >= 0.5
    assert mv.drive_variables == ("x2",)  # found: one strobe point to round-off
    assert mv.voting == ("x1",)
    assert mv.variables["x2"].label == "periodic"  # the per-variable verdict is kept
    assert any("following the drive" in r and "x2" in r for r in mv.reasons)


def test_forcing_phase_without_the_drive_period_is_outweighed_by_the_joint_evidence(
    duffing_with_phase,
) -> None:
    data, dt = duffing_with_phase
    mv = classify_motion(data, dt=dt, rng=0)  # an autonomous reading: nothing set aside
    assert mv.drive_variables == ()
    assert {v.label for v in mv.variables.values()} == {"chaotic", "periodic"}
    assert mv.label == "chaotic"
    assert mv.structure is not None and mv.structure.kind == "scattered"
    assert mv.exponent_positive is True
    assert mv.votes["variable x2"] == "opposes"
    assert mv.confidence < 1.0  # the periodic coordinate's vote is counted against


def test_drive_variables_may_be_named(duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    ds = chaoskit.load_trajectory(data, dt=dt, variables=["x", "forcing"])
    mv = classify_motion(ds, drive_variables=["forcing"], rng=0)
    assert mv.drive_variables == ("forcing",) and mv.label == "chaotic"
    with pytest.raises(ValueError, match="drive_variables"):
        classify_motion(ds, drive_variables=["nope"], rng=0)


def test_rossler_seen_through_a_nearly_periodic_coordinate_is_never_confidently_regular() -> None:
    s = systems.rossler(4000, dt=0.1)
    phase = np.cos(np.arctan2(s[:, 1], s[:, 0]))  # the phase of a phase-coherent flow
    mv = classify_motion(np.column_stack([s[:, 0], phase]), dt=0.1, rng=0)
    assert mv.label in ("chaotic", "undetermined")
    if mv.label == "undetermined":
        assert mv.needs and math.isnan(mv.confidence)


def test_periodic_two_variable_orbit_has_the_right_period() -> None:
    t, s = systems.duffing(4000, gamma=0.28, samples_per_period=40)  # period 2 (drive periods)
    mv = classify_motion(s, dt=float(t[1] - t[0]), drive_period=DRIVE, rng=0)
    assert (mv.label, mv.period) == ("periodic", 2)
    assert mv.structure is not None and mv.structure.n_clusters == 2
    assert mv.confidence >= 0.75


def test_a_pandas_time_index_sets_the_sampling_interval() -> None:
    """A DataFrame indexed by time stamps 10 ms apart is a flow sampled at 0.01 s, decided
    as the same array with ``dt=0.01``; a ``dt`` that contradicts the index is refused."""
    pd = pytest.importorskip("pandas")
    t, s = systems.duffing(4000, gamma=0.28, samples_per_period=40)
    dt = float(t[1] - t[0])
    index = pd.timedelta_range(0, periods=s.shape[0], freq=pd.Timedelta(seconds=dt))
    frame = pd.DataFrame(s, columns=["x1", "x2"], index=index)
    by_index = classify_motion(frame, drive_period=DRIVE, rng=0)
    by_dt = classify_motion(s, dt=dt, drive_period=DRIVE, rng=0)
    assert by_index.kind == by_dt.kind != "map"
    assert by_index.dt == pytest.approx(dt, rel=1e-7)  # time stamps resolve 1 ns
    assert (by_index.label, by_index.period) == (by_dt.label, by_dt.period)
    with pytest.raises(ValueError, match="dt"):
        classify_motion(frame, dt=2 * dt, drive_period=DRIVE, rng=0)


def test_two_frequency_torus_is_quasi_periodic() -> None:
    t = np.arange(4000) * 0.05
    w2 = np.pi * (np.sqrt(5) - 1)
    data = np.column_stack(
        [np.sin(2 * np.pi * t) + 0.6 * np.sin(w2 * t), np.cos(2 * np.pi * t) + 0.6 * np.cos(w2 * t)]
    )
    mv = classify_motion(data, dt=0.05, rng=0)
    assert mv.label == "quasi-periodic"
    assert mv.structure is not None and mv.structure.kind == "closed-curve"


def test_map_with_both_coordinates() -> None:
    mv = classify_motion(systems.henon(2000), rng=0)  # an array without dt: a map
    assert mv.kind == "map" and mv.label == "chaotic"
    assert mv.exponent is not None
    assert mv.exponent.mle == pytest.approx(0.419, rel=0.15)  # Hénon λ₁ = 0.419 / iteration


# ---------------------------------------------------------------- the rule on its own


def _verdict(label: str, period: int | None = None) -> SimpleNamespace:
    return SimpleNamespace(label=label, period=period, needs=(), lines=None, surrogates=None)


def _structure(kind: str, n_clusters: int = 0, n_points: int = 100) -> SectionStructure:
    nan = float("nan")
    return SectionStructure(
        kind=kind, n_clusters=n_clusters, labels=np.zeros(n_points, dtype=np.int64),
        cluster_radius=nan, cyclic_fraction=nan, curve_closure=nan, curve_coverage=nan,
        curve_thickness=nan, n_points=n_points, scale=1.0,
    )  # fmt: skip


def _fields(outcome: RuleOutcome) -> tuple:
    """The outcome's label, period, confidence, reason, votes and needs, in that order."""
    assert isinstance(outcome, RuleOutcome)
    o = outcome
    return o.label, o.period, o.confidence, o.reason, o.votes, o.needs


def _combine(voters, structure, positive, say, n_cycles=100.0):
    return _fields(
        combine_motion(
            voters,
            structure=structure,
            positive=positive,
            say=say,
            n_cycles=n_cycles,
            cycle_unit="drive periods",
            rule=VerdictRule(),
        )
    )


def test_unresolved_disagreement_is_undetermined_with_needs() -> None:
    voters = {"x": _verdict("periodic", 1), "y": _verdict("chaotic")}
    label, period, confidence, reason, votes, needs = _combine(
        voters, _structure("scattered"), False, None
    )
    assert label == "undetermined" and period is None and math.isnan(confidence)
    assert votes == {}
    assert any("clearly positive exponent" in n for n in needs)
    assert "the variables disagree (x: periodic, y: chaotic)" in reason


def test_reason_says_whether_variables_disagree_or_do_not_decide() -> None:
    """Undetermined variables do not disagree: the reason says what happened."""
    none = {"x": _verdict("undetermined"), "y": _verdict("undetermined")}
    reason = _combine(none, _structure("clusters", 1), None, None)[3]
    assert "no variable decides on its own (x: undetermined, y: undetermined)" in reason
    assert "disagree" not in reason
    some = {"x": _verdict("periodic", 1), "y": _verdict("undetermined")}
    reason = _combine(some, _structure("scattered"), False, None)[3]
    assert "not every variable decides (x: periodic, y: undetermined)" in reason


def test_clusters_with_a_chaotic_variable_and_too_few_periods_asks_for_more() -> None:
    voters = {"x": _verdict("periodic", 2), "y": _verdict("chaotic")}
    label, *_, needs = _combine(voters, _structure("too-few-points", n_points=8), True, None, 8)
    assert label == "undetermined"
    assert any("≥ 20 drive periods; the series has 8" in n for n in needs)
    assert any("joint section has 8" in n for n in needs)


def test_equations_decide_between_a_scattered_section_and_a_flat_exponent() -> None:
    voters = {"x": _verdict("periodic", 1), "y": _verdict("chaotic")}
    label, _, confidence, *_ = _combine(voters, _structure("scattered"), False, "chaotic")
    assert label == "chaotic"
    assert 0.5 <= confidence < 1.0  # exponent and x oppose; section, equations and y support


def test_equations_against_agreeing_variables_without_a_deciding_section() -> None:
    voters = {"x": _verdict("periodic", 1), "y": _verdict("periodic", 1)}
    label, *_, needs = _combine(voters, _structure("too-few-points", n_points=10), False, "chaotic")
    assert label == "undetermined"
    assert any("the equations say chaotic" in n and "finer sampling" in n for n in needs)
    # a joint section of tight clusters decides against the equations; the vote is counted
    label, period, confidence, reason, votes, _ = _combine(
        voters, _structure("clusters", n_clusters=1), False, "chaotic"
    )
    assert (label, period) == ("periodic", 1)
    assert votes["equations"] == "opposes" and confidence < 1.0
    assert "decides against the equations" in reason


def test_without_a_joint_section_a_repeating_variable_stands_only_unopposed() -> None:
    repeats = SimpleNamespace(
        label="periodic", period=1, needs=(), surrogates=None,
        lines=SimpleNamespace(kind="periodic", base_frequencies=np.array([1.0])),
    )  # fmt: skip
    voters = {"x": repeats, "y": _verdict("undetermined")}
    label, period, *_ = _combine(voters, None, False, None)
    assert (label, period) == ("periodic", 1)
    assert _combine(voters, None, True, None)[0] == "undetermined"  # the exponent says no
    assert _combine(voters, _structure("scattered"), False, None)[0] == "undetermined"
    chaotic = {"x": _verdict("chaotic"), "y": _verdict("undetermined")}
    assert _combine(chaotic, None, True, None)[0] == "chaotic"
    assert _combine(chaotic, None, False, None)[0] == "undetermined"
    assert _combine(chaotic, None, True, "regular")[0] == "undetermined"


def test_agreeing_variables_against_the_joint_section() -> None:
    voters = {"x": _verdict("chaotic"), "y": _verdict("chaotic")}
    label, *_, needs = _combine(voters, _structure("clusters", n_clusters=3), True, None)
    assert label == "undetermined"
    assert any("joint section of all variables is clusters" in n for n in needs)


# ---------------------------------------------------------------- the equations' exponent


def test_exponent_from_the_equations_is_reported_beside_the_data(duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    eq = SimpleNamespace(exponent=0.1, interval=(0.08, 0.12))  # 'interval' is accepted too
    mv = classify_motion(data, dt=dt, drive_period=DRIVE, exponent=eq, rng=0)
    assert mv.equations_say == "chaotic" and mv.votes["equations"] == "supports"
    assert any(r.startswith("the equations say chaotic") for r in mv.reasons)
    assert any(r.startswith("the data say") for r in mv.reasons)
    regular = SimpleNamespace(exponent=0.001, ci=(-0.01, 0.012))
    mv = classify_motion(data, dt=dt, drive_period=DRIVE, exponent=regular, rng=0)
    assert mv.equations_say == "regular"
    assert any("the equations and the data disagree" in r for r in mv.reasons)
    assert mv.label == "chaotic"  # the scattered joint section with a positive exponent decides
    assert mv.votes["equations"] == "opposes" and mv.confidence < 1.0


@pytest.mark.parametrize(
    "bad", [object(), SimpleNamespace(exponent=1.0), SimpleNamespace(exponent=1.0, ci=(2.0, 1.0))]
)
def test_exponent_without_an_interval_is_refused(bad, duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    with pytest.raises(ValueError, match="exponent"):
        classify_motion(data[:400], dt=dt, exponent=bad)


def test_exponent_with_an_undefined_interval_is_no_evidence(duffing_with_phase) -> None:
    # A short run of the equations gives a value but no interval (too few blocks).
    data, dt = duffing_with_phase
    eq = SimpleNamespace(exponent=101.2, ci=(float("nan"), float("nan")))
    mv = classify_motion(data, dt=dt, drive_period=DRIVE, exponent=eq, rng=0)
    assert mv.equations_say is None and mv.votes["equations"] == "missing"
    assert any("not used as evidence" in r for r in mv.reasons)
    assert mv.label == "chaotic"


# ---------------------------------------------------------------- output and input


def test_to_dataset_holds_the_motion_and_the_variables(duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    mv = classify_motion(data, dt=dt, drive_period=DRIVE, rng=0)
    ds = mv.to_dataset()
    assert str(ds["motion_label"].item()) == "chaotic"
    assert list(ds["variable"].values) == ["x1", "x2"]
    assert ds["motion_mle"].attrs["units"] == "s-1"
    for name, var in ds.data_vars.items():
        assert "long_name" in var.attrs, name
        if var.dtype.kind == "f":
            assert "units" in var.attrs, name
    assert "x2" in ds.attrs["motion_reasons"]


def test_dataset_with_a_multi_dimensional_variable_is_expanded_by_label() -> None:
    s = systems.lorenz(2500, dt=0.03)
    ds = xr.Dataset(
        {"q": (("time", "axis"), s[:, :2])},
        coords={"time": np.arange(2500) * 0.03, "axis": ["x", "y"]},
    )
    mv = classify_motion(ds, rng=0)
    assert list(mv.variables) == ["q[axis=x]", "q[axis=y]"]
    assert mv.label == "chaotic"


def test_bad_input_is_refused() -> None:
    with pytest.raises(ValueError, match="array"):
        classify_motion(np.zeros(10))


# ---------------------------------------------------------------- state vectors for Rosenstein


def test_rosenstein_on_state_vectors_matches_the_lorenz_exponent() -> None:
    s = systems.lorenz(5000, dt=0.02)
    res = lyapunov_rosenstein(s, dt=0.02)
    assert res.embedding_dim == 3
    assert res.mle == pytest.approx(0.906, rel=0.15)  # Lorenz λ₁ = 0.906 (Sprott 2003)
    scaled = lyapunov_rosenstein(s * np.array([1e3, 1.0, 1e-3]), dt=0.02, lag=res.lag)
    assert scaled.mle == pytest.approx(res.mle, rel=1e-9)  # columns are standardised
    with pytest.raises(ValueError, match="embedding_dim"):
        lyapunov_rosenstein(s, dt=0.02, embedding_dim=2)


def test_docs_state_the_same_motion_rule_as_the_docstring() -> None:
    from tests.conftest import verdict_docs_block

    doc = classify_motion.__doc__ or ""
    rule = doc[doc.index("**Rule.**") + len("**Rule.**") : doc.index("**Confidence**")]
    block = verdict_docs_block("motion rule")
    assert " ".join(rule.split()) == " ".join(block.split())


def test_a_variable_that_is_all_zeros_or_fails_is_set_aside(duffing_with_phase) -> None:
    data, dt = duffing_with_phase
    zeros = np.column_stack([data[:, 0], np.zeros(len(data))])  # e.g. a joint never touched
    mv = classify_motion(zeros, dt=dt, drive_period=DRIVE, rng=0)
    assert "x2" not in mv.voting and mv.label == "chaotic"
    assert any("x2" in r and "set aside" in r for r in mv.reasons)


# ---------------------------------------------------------------- a periodic orbit of the equations


def _orbit(period: int = 1, multiplier: complex = 0.4 + 0.3j, approach: float = 1e-6):
    return chaoskit.PeriodicOrbitEvidence(
        period, np.array([multiplier, 0.1]), np.array([1.0]), 1e-11, approach, 1e-4
    )


def _with_orbit(voters, structure, orbit, say=None, positive=True):
    return _fields(combine_motion(
        voters, structure=structure, positive=positive, say=say, n_cycles=100.0,
        cycle_unit="drive periods", rule=VerdictRule(), orbit=orbit,
    ))  # fmt: skip


def test_a_stable_attracting_orbit_says_periodic_like_the_equations_exponent() -> None:
    voters = {"x": _verdict("chaotic"), "y": _verdict("undetermined")}
    label, period, confidence, reason, votes, needs = _with_orbit(
        voters, _structure("too-few-points", n_points=10), _orbit(2)
    )
    assert (label, period, needs) == ("periodic", 2, ())
    assert reason.startswith("the equations say regular: periodic with period 2 (a converged")
    assert votes["orbit"] == "supports" and votes["variable x"] == "opposes"
    assert confidence == pytest.approx(1 / 3, abs=1e-12)  # orbit for; x and the exponent against
    label, period, *_ = _with_orbit(voters, _structure("clusters", 2), _orbit(2))
    assert (label, period) == ("periodic", 2)


@pytest.mark.parametrize(
    ("structure", "say", "why"),
    [
        (_structure("scattered"), None, "but the joint section of the data is scattered"),
        (_structure("closed-curve"), None, "but the joint section of the data is closed-curve"),
        (_structure("clusters", 3), None, "but the joint section is 3 tight clusters, not 1"),
        (_structure("clusters", 1), "chaotic", "but the equations' exponent says chaotic"),
    ],
)
def test_an_orbit_against_the_data_is_undetermined_and_says_why(structure, say, why) -> None:
    voters = {"x": _verdict("periodic", 1), "y": _verdict("periodic", 1)}
    label, period, confidence, reason, _, needs = _with_orbit(voters, structure, _orbit(), say)
    assert label == "undetermined" and period is None and math.isnan(confidence)
    assert why in reason
    assert needs[0].startswith("a longer series after the transient or a tighter integration")


@pytest.mark.parametrize(
    ("orbit", "problem"),
    [
        (_orbit(multiplier=-1.2), "it is unstable (largest multiplier |μ| = 1.2 ≥ 1)"),
        (_orbit(approach=0.01), "the motion does not approach it (distance 0.01 > tolerance"),
    ],
)
def test_an_unstable_or_unapproached_orbit_is_no_evidence(orbit, problem) -> None:
    t, s = systems.duffing(3000, gamma=0.2, samples_per_period=40)  # period-1 window
    data = s + 0.01 * s.std(axis=0) * np.random.default_rng(5).standard_normal(s.shape)
    mv = classify_motion(data, dt=float(t[1] - t[0]), drive_period=DRIVE, orbit=orbit, rng=0)
    assert mv.label == "periodic" and mv.period == 1  # the data decide alone
    assert mv.votes["orbit"] == "neutral" and not mv.orbit_says_periodic
    assert any(r.startswith("the equations' periodic orbit (period 1) is not evidence: " + problem)
               for r in mv.reasons)  # fmt: skip
    summary = mv.summary()
    assert summary["motion_orbit_period"] == 1.0 and summary["motion_orbit_evidence"] == 0.0
    ds = mv.to_dataset()
    assert ds["motion_orbit_multiplier"].attrs["units"] == "1"
    assert float(ds["motion_orbit_multiplier"]) == pytest.approx(abs(orbit.multipliers).max())


def test_a_stable_orbit_is_recorded_in_the_motion_verdict() -> None:
    t, s = systems.duffing(3000, gamma=0.2, samples_per_period=40)
    data = s + 0.01 * s.std(axis=0) * np.random.default_rng(5).standard_normal(s.shape)
    mv = classify_motion(data, dt=float(t[1] - t[0]), drive_period=DRIVE, orbit=_orbit(), rng=0)
    assert (mv.label, mv.period, mv.orbit_says_periodic) == ("periodic", 1, True)
    assert mv.votes["orbit"] == "supports"
    assert mv.reason.startswith("the equations say regular: periodic with period 1")
    assert mv.summary()["motion_orbit_evidence"] == 1.0


def test_orbit_must_be_periodic_orbit_evidence() -> None:
    with pytest.raises(
        ValueError, match=r"orbit must be a chaoskit\.PeriodicOrbitEvidence or None"
    ):
        classify_motion(np.zeros((300, 2)), dt=0.1, orbit={"period": 1})
