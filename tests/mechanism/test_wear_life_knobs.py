"""The cost knobs of ``mechanism.wear_life``: their defaults, the exponent's stopping rule
and the run shared by a checkpoint's analysis and its first increment.

Their accuracy against the cost is in ``docs/accuracy-vs-cost.md`` ("Wear path").
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mechanism
from mechanism.studies import _wear_life as life_module
from mechanism.studies import _wear_life_analysis as analysis_module
from mechanism.studies import _wear_prediction as prediction_module
from tests.mechanism.scenes import rigid_paper


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        # worn states may warn about step limits; what matters is asserted
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        return fn(*args, **kwargs)


def test_the_cost_knobs_default_to_the_measured_settings():
    """The defaults whose accuracy docs/accuracy-vs-cost.md shows: a first exponent run of 6
    revolutions, one run per checkpoint state, 125 verdict samples per revolution, every
    increment started from the scene's initial state."""
    settings = mechanism.WearLifeSettings()
    assert settings.lyapunov_first_revolutions == 6.0
    assert settings.share_state_run is True
    assert settings.verdict_samples_per_revolution == 125
    assert settings.increment_settle_revolutions is None


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"lyapunov_first_revolutions": 2.0},
            "lyapunov_first_revolutions must be None or a number of revolutions > "
            "lyapunov_discard (2); got 2.0.",
        ),
        (
            {"lyapunov_first_revolutions": "six"},
            "lyapunov_first_revolutions must be None or a number of revolutions > "
            "lyapunov_discard (2); got 'six'.",
        ),
        (
            {"verdict_samples_per_revolution": 10},
            "verdict_samples_per_revolution must be in [20, 100000]; got 10.",
        ),
        ({"share_state_run": 1}, "share_state_run must be True or False; got 1."),
    ],
)
def test_the_cost_knobs_are_validated_in_one_line(kwargs, message):
    with pytest.raises(ValueError) as info:
        mechanism.WearLifeSettings(**kwargs)
    assert str(info.value) == message


def _estimate(lo: float, hi: float, revolutions: float) -> mechanism.SceneLyapunov:
    return mechanism.SceneLyapunov(
        exponent=0.5 * (lo + hi), ci=(lo, hi), ci_method="batch means", drive_period=0.4,
        time=np.arange(1.0, revolutions - 1.0), running_exponent=np.zeros(0),
        segment_exponent=np.zeros(0), batches=4, settings={"revolutions": revolutions},
    )  # fmt: skip


@pytest.mark.parametrize(
    ("lo", "hi", "decided"),
    [
        (34.0, 59.3, True),  # a worn chaotic state: beyond zero by 2.7 half-widths
        (-4.09, -4.02, True),  # an unworn periodic state
        (12.0, 36.0, False),  # above zero, but by one half-width exactly: not beyond it
        (1.0, 20.0, False),  # above zero by less than its half-width
        (-5.0, 13.0, False),  # contains zero
        (float("nan"), float("nan"), False),
    ],
)
def test_the_exponent_is_decided_beyond_zero_by_its_half_width(lo, hi, decided):
    assert _estimate(lo, hi, 6.0).sign_decided is decided


def _how(first):
    return analysis_module.CheckpointAnalysis(
        discard=2.0, revolutions=25, exponent=True, lyapunov_revolutions=10.0,
        lyapunov_discard=2.0, lyapunov_first=first, continuous_fraction=0.01,
        verdict_samples=250, simulate_kwargs={},
    )  # fmt: skip


@pytest.mark.parametrize(
    ("first", "decide_after"),
    [
        (6.0, 6.0),  # one run, ended after 6 revolutions when their sign is decided
        (10.0, None),  # no shorter first look: the full run
        (None, None),
    ],
)
def test_the_checkpoint_exponent_is_one_run_that_may_end_early(monkeypatch, first, decide_after):
    calls = []

    def fake(scene, **span):
        calls.append(span)
        return _estimate(20.0, 40.0, span["revolutions"])

    monkeypatch.setattr(analysis_module, "lyapunov_exponent", fake)
    analysis_module.checkpoint_exponent(rigid_paper(), _how(first))
    expected = {"revolutions": 10.0, "discard": 2.0}
    if decide_after is not None:
        expected["decide_after"] = decide_after
    assert calls == [expected]


@pytest.mark.slow
def test_a_shared_state_run_gives_the_path_of_two_runs():
    """One run per checkpoint state (its first revolutions wear, all of them are analysed)
    against a run each. The unworn state's analysis is the same run either way, so its
    numbers are equal exactly; the increment reads the first revolutions of a longer run,
    which differ from a run of their own only in its last, shortened step, so the depth
    after 500 cycles at 150 rpm agrees to rounding (measured: 16 of 1440 regions differ,
    by at most 2.3e-11 m; asserted 1e-9 m, a nanometre)."""
    settings = {"settle_revolutions": 1.0, "analysis_revolutions": 4}
    runs = {}
    for share in (True, False):
        runs[share] = _quiet(
            mechanism.wear_life, rigid_paper({"drive.speed_rpm": 150.0}), cycles=500,
            checkpoints=[500], averaged_revolutions=2, exponent=False,
            settings=mechanism.WearLifeSettings(share_state_run=share, **settings),
        ).to_dataset()  # fmt: skip
    shared, separate = runs[True], runs[False]
    assert shared.attrs["share_state_run"] == 1 and separate.attrs["share_state_run"] == 0
    np.testing.assert_allclose(
        shared["wear_depth"].values, separate["wear_depth"].values, rtol=0.0, atol=1e-9
    )
    for name in ("peak_contact_force", "mean_contact_force", "continuous_contact_fraction"):
        np.testing.assert_array_equal(
            shared[name].isel(checkpoint=0).values, separate[name].isel(checkpoint=0).values
        )


def test_the_path_records_its_runs_lean_and_its_phases_cpu(monkeypatch):
    """Every run of a path records what the wear and the analysis read (``WearRecord``:
    no ideal companion), and the path's attrs say where its CPU time went."""
    seen = []

    def failing(scene, revolutions, **kwargs):
        seen.append(kwargs["record"])
        raise mechanism.SimulationError("stopped by the test", time=0.0)

    monkeypatch.setattr(prediction_module, "simulate_turns", failing)
    life = mechanism.wear_life(rigid_paper(), cycles=500, checkpoints=[500])
    assert life.status == "failed"
    assert len(seen) == 1 and isinstance(seen[0], mechanism.WearRecord)
    attrs = life.to_dataset().attrs
    phases = [attrs[f"phase_cpu_{k}"] for k in ("runs", "wear", "exponent", "verdict")]
    assert all(p >= 0.0 for p in phases)
    assert sum(phases) <= attrs["phase_cpu_total"] + 1e-9


@pytest.mark.slow
def test_the_lean_record_gives_the_path_of_the_full_record():
    """The path recorded lean against the same path recorded in full: the same
    integrations sampled on the same grid, so the wear and the analysis agree bit for bit
    (150 rpm, 500 cycles, no exponent)."""
    settings = mechanism.WearLifeSettings(settle_revolutions=1.0, analysis_revolutions=4)
    runs = {}
    for lean in (True, False):
        with pytest.MonkeyPatch.context() as patch:
            if not lean:
                patch.setattr(life_module, "WearRecord", mechanism.FullRecord)
            runs[lean] = _quiet(
                mechanism.wear_life, rigid_paper({"drive.speed_rpm": 150.0}), cycles=500,
                checkpoints=[500], averaged_revolutions=2, exponent=False, settings=settings,
            ).to_dataset()  # fmt: skip
    compared = ("wear_depth", "strobe_x", "peak_contact_force", "mean_contact_force",
                "impact_fraction", "continuous_contact_fraction", "motion_confidence")  # fmt: skip
    for name in compared:
        np.testing.assert_array_equal(runs[True][name].values, runs[False][name].values)


def test_the_increment_settle_is_validated_in_one_line():
    assert mechanism.WearLifeSettings().increment_settle_revolutions is None
    with pytest.raises(ValueError) as info:
        mechanism.WearLifeSettings(increment_settle_revolutions=0.5)
    assert str(info.value) == "increment_settle_revolutions must be an integer; got 0.5."


@pytest.mark.slow
def test_warm_started_increments_start_where_the_previous_run_ended(monkeypatch):
    """With ``increment_settle_revolutions`` the runs between checkpoints start from the
    last state of the run before (which ended after whole drive periods) and settle that
    many revolutions; the checkpoint states start from the scene's initial state with the
    full settle. The path still only deepens (150 rpm, 500 cycles in increments of at most
    0.005 c₀, so that several increments run between the two states)."""
    calls = []
    real = prediction_module.simulate_turns

    def spy(scene, revolutions, **kwargs):
        traj = real(scene, revolutions, **kwargs)
        calls.append((revolutions, kwargs.get("start"), traj.attrs["final_q"]))
        return traj

    monkeypatch.setattr(prediction_module, "simulate_turns", spy)
    settings = mechanism.WearLifeSettings(
        settle_revolutions=1.0, analysis_revolutions=4, increment_settle_revolutions=0
    )
    life = _quiet(
        mechanism.wear_life, rigid_paper({"drive.speed_rpm": 150.0}), cycles=500,
        checkpoints=[500], averaged_revolutions=2, exponent=False, max_depth_increment=0.005,
        settings=settings,
    )  # fmt: skip
    assert life.status == "complete", life.reason
    # the unworn state, then increments of 0 + 2 revolutions each from the run before,
    # then the state after 500 cycles from the initial state again (1 + 4 revolutions)
    assert calls[0][0] == 5.0 and calls[0][1] is None
    assert calls[-1][0] == 5.0 and calls[-1][1] is None
    warm = calls[1:-1]
    assert len(warm) >= 2 and all(c[0] == 2.0 for c in warm)
    for before, (_, start, _) in zip(calls, warm, strict=False):
        np.testing.assert_array_equal(start[0], before[2])
    ds = life.to_dataset()
    assert ds.attrs["increment_settle_revolutions"] == 0
    assert (np.diff(ds["wear_depth"].values, axis=0) >= 0.0).all()
    assert ds["max_wear_depth"].sel(joint="C", surface="bearing").values[-1] > 0.0
