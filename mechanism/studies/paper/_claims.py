"""The wear-life answer: what each wear path says, and the paper's transition claims
judged on them (agree, disagree or cannot tell, with one line of why).

The inputs are :class:`mechanism.WearLife` results (or anything with the same attributes:
``checkpoints``, ``cycles``, ``status``, ``reason``, ``cycles_to_chaos``, ``verdicts``,
``exponents`` and the ``dataset`` variable ``max_wear_depth``), or the exception that ended
a path's task.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._published import TransitionClaim

#: Verdict labels of a regular (not chaotic) motion.
REGULAR = ("periodic", "quasi-periodic", "equilibrium")
AGREE, DISAGREE, CANNOT_TELL = "agree", "disagree", "cannot tell"


def cycles_text(n: float) -> str:
    """A cycle count as the report prints it: ``20,000``."""
    return f"{n:,.0f}"


def path_label(rpm: float, clearance: float) -> str:
    """``"150 rpm, 0.2 mm"``."""
    return f"{rpm:g} rpm, {clearance * 1e3:g} mm"


@dataclass(frozen=True)
class PathOutcome:
    """What one wear path says about the transition to chaos.

    ``onset`` is the cycles to chaos (0: chaotic unworn), ``math.inf`` when a complete path
    did not turn chaotic, and None when the path cannot tell (``problem`` says why: it
    ended early, before any chaotic checkpoint, or its run failed). ``confidence`` and
    ``exponent`` (λ₁, low, high in 1/s) are those of the checkpoint that decided: the
    chaotic one, else the last one. ``motions`` and ``depths`` (largest wear depth, m) run
    over the finished checkpoints ``checkpoints``.
    """

    rpm: float
    clearance: float
    cycles: float
    checkpoints: tuple[float, ...]
    onset: float | None
    confidence: float
    exponent: tuple[float, float, float]
    motions: tuple[str, ...]
    depths: tuple[float, ...]
    problem: str = ""

    @property
    def label(self) -> str:
        """``"150 rpm, 0.2 mm"``."""
        return path_label(self.rpm, self.clearance)

    @property
    def reached(self) -> float:
        """Cycles of the last finished checkpoint (0 when none finished)."""
        return self.checkpoints[-1] if self.checkpoints else 0.0

    @property
    def regular_throughout(self) -> bool:
        """True when every finished checkpoint was judged regular."""
        return bool(self.motions) and all(m in REGULAR for m in self.motions)

    @property
    def answer(self) -> str:
        """``"chaotic after 5,000 cycles"``, ``"chaotic unworn"``, ``"not within 20,000
        cycles"`` or ``"cannot tell: <why>"``."""
        if self.onset is None:
            return f"{CANNOT_TELL}: {self.problem}"
        if math.isinf(self.onset):
            return f"not within {cycles_text(self.reached)} cycles"
        if self.onset == 0.0:
            return "chaotic unworn"
        return f"chaotic after {cycles_text(self.onset)} cycles"

    def depth_at(self, cycles: float) -> float:
        """Largest wear depth (m) at the checkpoint ``cycles`` (NaN when not reached)."""
        for n, d in zip(self.checkpoints, self.depths, strict=True):
            if n == cycles:
                return d
        return math.nan


def path_outcome(rpm: float, clearance: float, life: Any) -> PathOutcome:
    """The outcome of one wear path from its :class:`mechanism.WearLife`, or from the
    exception its run raised (then it cannot tell, and says why)."""
    if isinstance(life, BaseException):
        return PathOutcome(
            rpm=float(rpm), clearance=float(clearance), cycles=math.nan, checkpoints=(),
            onset=None, confidence=math.nan, exponent=(math.nan,) * 3, motions=(), depths=(),
            problem=f"the path's run failed: {type(life).__name__}: {life}",
        )  # fmt: skip
    checkpoints = tuple(float(n) for n in np.asarray(life.checkpoints, dtype=np.float64))
    motions = tuple(str(v.label) for v in life.verdicts)
    depth = np.asarray(life.dataset["max_wear_depth"].values, dtype=np.float64)
    depths = tuple(float(d) for d in depth.reshape(len(checkpoints), -1).max(axis=1, initial=0.0))
    chaos = life.cycles_to_chaos
    problem = ""
    if chaos is not None:
        onset: float | None = float(chaos)
        at = checkpoints.index(onset)
    elif life.status != "complete" or not checkpoints:
        onset, at = None, len(checkpoints) - 1
        problem = str(life.reason) or "the path ended before its last checkpoint"
    else:
        onset, at = math.inf, len(checkpoints) - 1
    confidence, exponent = math.nan, (math.nan,) * 3
    if at >= 0:
        confidence = float(life.verdicts[at].confidence)
        lam = life.exponents[at]
        if lam is not None:
            exponent = (float(lam.exponent), float(lam.ci[0]), float(lam.ci[1]))
    return PathOutcome(
        rpm=float(rpm), clearance=float(clearance), cycles=float(life.cycles),
        checkpoints=checkpoints, onset=onset, confidence=confidence, exponent=exponent,
        motions=motions, depths=depths, problem=problem,
    )  # fmt: skip


@dataclass(frozen=True)
class ClaimVerdict:
    """One claim of the paper beside the wear paths: ``agreement`` is ``"agree"``,
    ``"disagree"`` or ``"cannot tell"``; ``why`` one line naming the paths' evidence."""

    claim: TransitionClaim
    agreement: str
    why: str

    @property
    def line(self) -> str:
        """``paper: <quote> — <agreement>: <why>``."""
        return f"paper: “{self.claim.quote}” — {self.agreement}: {self.why}"


def _brief(outcome: PathOutcome) -> str:
    """``"0.5 mm chaotic after 5,000"``-style evidence of one path, its label first."""
    if outcome.onset is not None and math.isinf(outcome.onset):
        kind = "regular" if outcome.regular_throughout else "not chaotic"
        return f"{outcome.label} {kind} through {cycles_text(outcome.reached)} cycles"
    return f"{outcome.label} {outcome.answer}"


def _unknown(outcomes: Sequence[PathOutcome]) -> str:
    """The paths that cannot tell, with their reasons ("" when every path can)."""
    return "; ".join(f"{o.label}: {o.problem}" for o in outcomes if o.onset is None)


def judge_clearance(claim: TransitionClaim, outcomes: Sequence[PathOutcome]) -> ClaimVerdict:
    """Larger clearances turn chaotic sooner through wear: the onsets (cycles to chaos, ∞
    when not within the path) must not grow with the clearance, must differ, and at least
    one path must turn chaotic by wear (after some cycles, not unworn). A larger clearance
    turning chaotic later disagrees; a path that cannot tell leaves the rest undecided."""
    paths = sorted(outcomes, key=lambda o: o.clearance)
    known = [o for o in paths if o.onset is not None]
    evidence = ", ".join(_brief(o) for o in known)
    later = [(a, b) for i, a in enumerate(known) for b in known[i + 1 :] if b.onset > a.onset]  # type: ignore[operator]
    if later:
        a, b = later[0]
        return ClaimVerdict(
            claim,
            DISAGREE,
            f"the larger clearance {b.clearance * 1e3:g} mm turns chaotic later than "
            f"{a.clearance * 1e3:g} mm ({evidence})",
        )
    unknown = _unknown(paths)
    if unknown:
        return ClaimVerdict(claim, CANNOT_TELL, unknown)
    onsets = {float(o.onset) for o in known}  # type: ignore[arg-type]
    by_wear = [o for o in known if 0.0 < o.onset < math.inf]  # type: ignore[operator]
    if not by_wear:
        if onsets == {math.inf}:
            why = f"no clearance turns chaotic within its path ({evidence})"
        elif onsets == {0.0}:
            why = f"every clearance is chaotic already unworn: no transition to time ({evidence})"
        else:
            why = (
                "the larger clearances are chaotic sooner, but already unworn: no clearance "
                f"turns chaotic by wear ({evidence})"
            )
        return ClaimVerdict(claim, CANNOT_TELL, why)
    if len(onsets) == 1:
        return ClaimVerdict(
            claim,
            CANNOT_TELL,
            f"every clearance turns chaotic by the same checkpoint ({evidence}); finer "
            "checkpoints would separate them",
        )
    return ClaimVerdict(claim, AGREE, evidence)


def judge_speed(claim: TransitionClaim, outcomes: Sequence[PathOutcome]) -> ClaimVerdict:
    """Speeds below the threshold wear less and stay regular: every slow path regular
    throughout while a faster one turns chaotic, and less wear at the slow speed than at
    each faster one after the same cycles. A chaotic slow path, or more wear at it,
    disagrees; a slow path that cannot tell, or no faster path turning chaotic, leaves it
    undecided."""
    threshold = float(claim.threshold if claim.threshold is not None else math.inf)
    paths = sorted(outcomes, key=lambda o: o.rpm)
    slow = [o for o in paths if o.rpm < threshold]
    fast = [o for o in paths if o.rpm >= threshold]
    if not slow or not fast:
        return ClaimVerdict(claim, CANNOT_TELL, f"no wear path on both sides of {threshold:g} rpm")
    evidence = ", ".join(_brief(o) for o in paths if o.onset is not None)
    chaotic_slow = [o for o in slow if o.onset is not None and math.isfinite(o.onset)]
    if chaotic_slow:
        return ClaimVerdict(claim, DISAGREE, evidence)
    wear, wear_why = _wear_part(slow, fast)
    if wear == DISAGREE:
        return ClaimVerdict(claim, DISAGREE, wear_why)
    if _unknown(slow):
        return ClaimVerdict(claim, CANNOT_TELL, _unknown(slow))
    undecided = [o for o in slow if not o.regular_throughout]
    if undecided:
        o = undecided[0]
        return ClaimVerdict(
            claim,
            CANNOT_TELL,
            f"{o.label} is not chaotic through {cycles_text(o.reached)} cycles but not judged "
            f"regular at every checkpoint ({' → '.join(o.motions)})",
        )
    if not any(o.onset is not None and math.isfinite(o.onset) for o in fast):
        why = _unknown(fast) or (
            f"no speed turns chaotic within its path, so speed makes no difference here "
            f"({evidence})"
        )
        return ClaimVerdict(claim, CANNOT_TELL, why)
    if wear != AGREE:
        return ClaimVerdict(claim, CANNOT_TELL, f"{evidence}; {wear_why}")
    return ClaimVerdict(claim, AGREE, f"{evidence}; {wear_why}")


def _wear_part(slow: Sequence[PathOutcome], fast: Sequence[PathOutcome]) -> tuple[str, str]:
    """Is the slow speeds' wear depth below every faster one's at their last common worn
    checkpoint? (agreement, one clause). Paths without checkpoints are left out."""
    ran = [o for o in fast if o.checkpoints]
    if not ran or not all(o.checkpoints for o in slow):
        return CANNOT_TELL, "no wear depths to compare"
    common = set.intersection(*(set(o.checkpoints) for o in (*slow, *ran))) - {0.0}
    if not common:
        return CANNOT_TELL, "the paths share no worn checkpoint to compare wear at"
    at = max(common)
    depths = ", ".join(f"{o.depth_at(at) * 1e6:.3g} µm at {o.rpm:g} rpm" for o in (*slow, *ran))
    clause = f"largest wear depth after {cycles_text(at)} cycles {depths}"
    more = [(s, f) for s in slow for f in ran if not s.depth_at(at) < f.depth_at(at)]
    if more:
        s, f = more[0]
        return DISAGREE, f"{s.rpm:g} rpm wears no less than {f.rpm:g} rpm: {clause}"
    return AGREE, clause


def judge_claims(
    claims: Sequence[TransitionClaim], outcomes: Mapping[tuple[float, float], PathOutcome]
) -> list[ClaimVerdict]:
    """Each claim judged on its wear paths (``outcomes`` by (rpm, clearance)); a claim
    whose paths were not run cannot tell."""
    verdicts = []
    for claim in claims:
        paths = [outcomes[p] for p in claim.paths if p in outcomes]
        missing = [path_label(*p) for p in claim.paths if p not in outcomes]
        if missing:
            verdicts.append(
                ClaimVerdict(claim, CANNOT_TELL, "not run: the wear path " + ", ".join(missing))
            )
        elif claim.key == "clearance":
            verdicts.append(judge_clearance(claim, paths))
        else:
            verdicts.append(judge_speed(claim, paths))
    return verdicts
