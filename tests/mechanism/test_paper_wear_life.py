"""The paper study's wear-life answer: cycles to chaos per wear path, and the paper's
transition claims judged on them.

The claim comparison is tested on synthetic wear paths (objects with the attributes of
``mechanism.WearLife`` that the comparison reads); the report's first lines on a tiny run
of the whole study (rigid rods, two analysed states per path) are in the slow test.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

import mechanism
from mechanism.studies import StudySettings
from mechanism.studies.paper import _claims as claims
from mechanism.studies.paper._published import TRANSITION_CLAIMS, WEAR_PATHS
from mechanism.studies.paper._wear_paths import wear_life_opening, wear_life_tables

CLEARANCE_CLAIM, SPEED_CLAIM = TRANSITION_CLAIMS
CHECKPOINTS = (0.0, 5000.0, 10000.0, 20000.0)


def _life(
    motions: list[str],
    *,
    depths_um: list[float] | None = None,
    lam: list[tuple[float, float, float]] | None = None,
    status: str = "complete",
    reason: str = "3 checkpoints up to 20000 cycles",
    cycles: float = 20000.0,
) -> SimpleNamespace:
    """A wear path with the attributes of mechanism.WearLife that the comparison reads;
    cycles to chaos as wear_life finds it (first checkpoint with λ₁'s interval above zero
    and a chaotic verdict)."""
    n = len(motions)
    checkpoints = np.array(CHECKPOINTS[:n])
    depths = np.array(depths_um if depths_um is not None else [10.0 * i for i in range(n)])
    lam = lam or [(50.0, 30.0, 70.0) if m == "chaotic" else (1.0, -5.0, 7.0) for m in motions]
    exponents = tuple(SimpleNamespace(exponent=v, ci=(lo, hi)) for v, lo, hi in lam)
    chaos = next(
        (
            float(c)
            for c, m, (_, lo, _) in zip(checkpoints, motions, lam, strict=True)
            if m == "chaotic" and lo > 0
        ),
        None,
    )
    depth = np.zeros((n, 1, 2))
    depth[:, 0, 0] = depths * 1e-6
    return SimpleNamespace(
        checkpoints=checkpoints,
        cycles=cycles,
        status=status,
        reason=reason,
        cycles_to_chaos=chaos,
        verdicts=tuple(SimpleNamespace(label=m, confidence=0.8) for m in motions),
        exponents=exponents,
        dataset=xr.Dataset(
            {"max_wear_depth": (("checkpoint", "joint", "surface"), depth)},
            coords={"checkpoint": checkpoints},
        ),
    )


REGULAR = ["periodic"] * 4
TURNS_AT_5000 = ["periodic", "chaotic", "chaotic", "chaotic"]
TURNS_AT_10000 = ["periodic", "periodic", "chaotic", "chaotic"]
CHAOTIC_UNWORN = ["chaotic"] * 4


def _speed_paths(slow, mid, fast) -> dict[tuple[float, float], claims.PathOutcome]:
    return {
        key: claims.path_outcome(*key, life)
        for key, life in zip(SPEED_CLAIM.paths, (slow, mid, fast), strict=True)
    }


def _clearance_paths(small, mid, large) -> dict[tuple[float, float], claims.PathOutcome]:
    return {
        key: claims.path_outcome(*key, life)
        for key, life in zip(CLEARANCE_CLAIM.paths, (small, mid, large), strict=True)
    }


def test_a_path_regular_throughout_is_not_chaotic_within_its_cycles():
    outcome = claims.path_outcome(30.0, 2e-4, _life(REGULAR))
    assert outcome.answer == "not within 20,000 cycles"
    assert math.isinf(outcome.onset) and outcome.regular_throughout
    assert outcome.confidence == 0.8 and outcome.exponent == (1.0, -5.0, 7.0)  # last checkpoint
    chaotic = claims.path_outcome(150.0, 2e-4, _life(TURNS_AT_5000))
    assert chaotic.answer == "chaotic after 5,000 cycles" and chaotic.onset == 5000.0
    assert chaotic.exponent == (50.0, 30.0, 70.0)  # the deciding checkpoint's
    assert claims.path_outcome(150.0, 5e-4, _life(CHAOTIC_UNWORN)).answer == "chaotic unworn"
    # a positive exponent without a chaotic verdict is not chaos
    positive = _life(["periodic", "undetermined"], lam=[(1.0, -5.0, 7.0), (40.0, 20.0, 60.0)])
    assert claims.path_outcome(90.0, 2e-4, positive).answer == "not within 5,000 cycles"


def test_speed_claim_agrees_when_the_slow_path_stays_regular_and_a_fast_one_turns():
    outcomes = _speed_paths(
        _life(REGULAR, depths_um=[0, 2, 4, 8]),
        _life(TURNS_AT_10000, depths_um=[0, 10, 20, 40]),
        _life(TURNS_AT_5000, depths_um=[0, 20, 40, 80]),
    )
    (verdict,) = claims.judge_claims([SPEED_CLAIM], outcomes)
    assert verdict.agreement == "agree"
    assert verdict.why == (
        "30 rpm, 0.2 mm regular through 20,000 cycles, 90 rpm, 0.2 mm chaotic after 10,000 "
        "cycles, 150 rpm, 0.2 mm chaotic after 5,000 cycles; largest wear depth after "
        "20,000 cycles 8 µm at 30 rpm, 40 µm at 90 rpm, 80 µm at 150 rpm"
    )
    assert verdict.line.startswith(
        "paper: “rotational speeds below 90 rpm effectively suppressing wear severity and "
        "stabilizing motion” — agree: 30 rpm, 0.2 mm regular through 20,000 cycles"
    )


def test_speed_claim_disagrees_with_a_chaotic_slow_path_or_more_wear_there():
    chaotic_slow = _speed_paths(_life(TURNS_AT_10000), _life(REGULAR), _life(TURNS_AT_5000))
    (verdict,) = claims.judge_claims([SPEED_CLAIM], chaotic_slow)
    assert verdict.agreement == "disagree"
    assert verdict.why.startswith("30 rpm, 0.2 mm chaotic after 10,000 cycles")
    more_wear = _speed_paths(
        _life(REGULAR, depths_um=[0, 30, 60, 90]),
        _life(REGULAR, depths_um=[0, 10, 20, 40]),
        _life(TURNS_AT_5000, depths_um=[0, 20, 40, 80]),
    )
    (verdict,) = claims.judge_claims([SPEED_CLAIM], more_wear)
    assert verdict.agreement == "disagree"
    assert verdict.why.startswith("30 rpm wears no less than 90 rpm: largest wear depth after")


def test_speed_claim_cannot_tell_without_contrast_or_a_decided_slow_motion():
    slow = [0, 1, 2, 3]  # µm: the slow path wears less
    everything_regular = _speed_paths(
        _life(REGULAR, depths_um=slow), _life(REGULAR), _life(REGULAR)
    )
    (verdict,) = claims.judge_claims([SPEED_CLAIM], everything_regular)
    assert verdict.agreement == "cannot tell"
    assert verdict.why.startswith("no speed turns chaotic within its path")
    undecided = _speed_paths(
        _life(["periodic", "undetermined", "periodic", "periodic"], depths_um=slow),
        _life(REGULAR),
        _life(TURNS_AT_5000),
    )
    (verdict,) = claims.judge_claims([SPEED_CLAIM], undecided)
    assert verdict.agreement == "cannot tell"
    assert verdict.why == (
        "30 rpm, 0.2 mm is not chaotic through 20,000 cycles but not judged regular at "
        "every checkpoint (periodic → undetermined → periodic → periodic)"
    )


def test_a_failed_path_cannot_tell_and_says_why():
    reason = (
        "the path ended after 10000 cycles: the penetration of the state after 12500 "
        "cycles exceeds the radial clearance"
    )
    ended = _life(REGULAR[:3], depths_um=[0, 1, 2], status="failed", reason=reason)
    outcome = claims.path_outcome(30.0, 2e-4, ended)
    assert outcome.onset is None and outcome.answer == f"cannot tell: {reason}"
    (verdict,) = claims.judge_claims(
        [SPEED_CLAIM], _speed_paths(ended, _life(REGULAR), _life(TURNS_AT_5000))
    )
    assert verdict.agreement == "cannot tell"
    assert verdict.why == f"30 rpm, 0.2 mm: {reason}"
    # a run that raised: no checkpoint at all
    crashed = claims.path_outcome(150.0, 5e-4, mechanism.SimulationError("diverged at t = 1 s"))
    assert crashed.answer.startswith("cannot tell: the path's run failed: SimulationError: ")
    (verdict,) = claims.judge_claims(
        [CLEARANCE_CLAIM],
        {
            **_clearance_paths(_life(REGULAR), _life(TURNS_AT_5000), _life(TURNS_AT_5000)),
            (150.0, 5e-4): crashed,
        },
    )
    assert verdict.agreement == "cannot tell"
    assert verdict.why.startswith("150 rpm, 0.5 mm: the path's run failed: SimulationError")
    # a path that turned chaotic before it ended still answers
    late_end = _life(TURNS_AT_5000[:3], status="failed", reason=reason)
    assert claims.path_outcome(150.0, 2e-4, late_end).answer == "chaotic after 5,000 cycles"


def test_clearance_claim_compares_the_onsets_in_clearance_order():
    agree = _clearance_paths(_life(REGULAR), _life(TURNS_AT_10000), _life(TURNS_AT_5000))
    (verdict,) = claims.judge_claims([CLEARANCE_CLAIM], agree)
    assert verdict.agreement == "agree"
    assert verdict.why == (
        "150 rpm, 0.1 mm regular through 20,000 cycles, 150 rpm, 0.2 mm chaotic after "
        "10,000 cycles, 150 rpm, 0.5 mm chaotic after 5,000 cycles"
    )
    reversed_ = _clearance_paths(_life(TURNS_AT_5000), _life(TURNS_AT_10000), _life(REGULAR))
    (verdict,) = claims.judge_claims([CLEARANCE_CLAIM], reversed_)
    assert verdict.agreement == "disagree"
    assert verdict.why.startswith("the larger clearance 0.2 mm turns chaotic later than 0.1 mm")
    unworn = _clearance_paths(*(_life(CHAOTIC_UNWORN) for _ in range(3)))
    (verdict,) = claims.judge_claims([CLEARANCE_CLAIM], unworn)
    assert verdict.agreement == "cannot tell"
    assert verdict.why.startswith("every clearance is chaotic already unworn")
    # larger clearances chaotic sooner, but unworn: wear drives no transition
    unworn_only = _clearance_paths(_life(REGULAR), _life(CHAOTIC_UNWORN), _life(CHAOTIC_UNWORN))
    (verdict,) = claims.judge_claims([CLEARANCE_CLAIM], unworn_only)
    assert verdict.agreement == "cannot tell"
    assert verdict.why.startswith(
        "the larger clearances are chaotic sooner, but already unworn: no clearance turns "
        "chaotic by wear (150 rpm, 0.1 mm regular through 20,000 cycles, 150 rpm, 0.2 mm "
        "chaotic unworn"
    )
    (verdict,) = claims.judge_claims([CLEARANCE_CLAIM], {})
    assert verdict.agreement == "cannot tell" and verdict.why.startswith("not run: the wear path")


def test_opening_sentence_and_tables_carry_every_claim_and_path():
    lives = {
        (30.0, 2e-4): _life(REGULAR, depths_um=[0, 2, 4, 8]),
        (90.0, 2e-4): _life(TURNS_AT_10000, depths_um=[0, 10, 20, 40]),
        (150.0, 2e-4): _life(TURNS_AT_5000, depths_um=[0, 20, 40, 80]),
        (150.0, 1e-4): _life(REGULAR),
        (150.0, 5e-4): _life(CHAOTIC_UNWORN),
    }
    outcomes = {key: claims.path_outcome(*key, life) for key, life in lives.items()}
    verdicts = claims.judge_claims(TRANSITION_CLAIMS, outcomes)
    assert [v.agreement for v in verdicts] == ["agree", "agree"]
    settings = StudySettings.quick()
    text = wear_life_opening(outcomes, verdicts, settings)
    assert text.startswith(
        "Wear life against the paper's claims on the transition to chaos. Paper: “enlarged "
        "clearances accelerate the transition from periodic to chaotic motion due to "
        "intensified wear” — agree: "
    )
    assert "30 rpm, 0.2 mm: not within 20,000 cycles (confidence 0.80)" in text
    claim_table, path_table = wear_life_tables(outcomes, verdicts, settings)
    assert list(claim_table.data["agreement"]) == ["agree", "agree"]
    assert list(path_table.data.index) == [claims.path_label(*p) for p in WEAR_PATHS]
    assert path_table.data.at["150 rpm, 0.5 mm", "answer"] == "chaotic unworn"
    assert path_table.data.at["150 rpm, 0.2 mm", "depth"] == pytest.approx(80.0, rel=1e-12)


def test_wear_path_settings_are_checked_in_one_line():
    with pytest.raises(ValueError) as err:
        StudySettings(wear_path_cycles=10_000.0, wear_path_checkpoints=(5_000.0, 20_000.0))
    assert str(err.value) == (
        "StudySettings.wear_path_checkpoints must be strictly increasing cycle counts in "
        "(0, wear_path_cycles] = (0, 10000]; got (5000.0, 20000.0)."
    )
    with pytest.raises(ValueError, match=r"wear_path_analysis_revolutions must be an integer"):
        StudySettings(wear_path_analysis_revolutions=3)


# --------------------------------------------------------------------------- the whole study

#: the tiny study of test_paper_study.py with two states per wear path
TINY = {
    "revolutions": 1.5,
    "discard_revolutions": 0.5,
    "samples_per_revolution": 400,
    "flexible_rods": False,
    "wear_updates": 1,
    "wear_cycles_per_update": 1.0e4,
    "wear_settle_revolutions": 0.25,
    "elements": (4,),
    "convergence_revolutions": 0.02,
    "max_samples": 500,
    "chaos_revolutions": 2.0,
    "chaos_samples_per_revolution": 400,
    "exponent_revolutions": 1.0,
    "rigid_rod_exponent": False,
    "orbit_speeds": (150.0,),
    "orbit_revolutions": 2.0,
    "orbit_discard_revolutions": 1.0,
    "orbit_flexible_rods": False,
    "wear_path_cycles": 2000.0,
    "wear_path_checkpoints": (2000.0,),
    "wear_path_averaged_revolutions": 1,
    "wear_path_analysis_revolutions": 4,
    "wear_path_lyapunov_revolutions": 1.0,
    "wear_path_lyapunov_discard": 0.5,
    "wear_path_flexible_rods": False,
}


@pytest.mark.slow
def test_report_opens_with_the_wear_life_answer(tmp_path):
    """The Markdown report's first paragraph is the wear-life answer: each claim with
    agree / disagree / cannot tell, then each path's cycles to chaos."""
    with warnings.catch_warnings():
        warnings.simplefilter("always", mechanism.SimulationWarning)
        study = mechanism.run_paper_study(
            tmp_path / "out", client="serial", settings=TINY, command="test"
        )
    md = study.report_markdown.read_text(encoding="utf-8")
    headings = re.findall(r"^## (.+)$", md, flags=re.M)
    assert headings[0] == "Summary"
    first = md.split("\n## Summary\n", 1)[1].strip().split("\n\n")[0]
    assert first.startswith("Wear life against the paper's claims on the transition to chaos.")
    for claim in TRANSITION_CLAIMS:
        found = re.search(
            re.escape(f"“{claim.quote}” — ") + r"(agree|disagree|cannot tell): ", first
        )
        assert found, claim.key
    for rpm, clearance in WEAR_PATHS:
        label = claims.path_label(rpm, clearance)
        assert re.search(
            re.escape(label) + r": (chaotic unworn|chaotic after [\d,]+ cycles|not within "
            r"2,000 cycles|cannot tell: .+)",
            first,
        ), label
    summary = md.split("\n## ", 2)[1]
    assert (
        summary.index("**Table 1.** The wear life against the paper's claims")
        < summary.index("**Table 2.** Cycles to chaos of each wear path")
        < summary.index("The answer: the motion of the journal centre")
    )
    assert dataclasses.replace(StudySettings.paper(), **TINY) == study.settings
