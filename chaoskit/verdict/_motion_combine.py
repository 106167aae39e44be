"""The rule of the motion verdict: :func:`combine_motion` weighs the variables and the joint
evidence."""

from __future__ import annotations

import math
from collections.abc import Mapping

from ._combine import RuleOutcome
from ._motion_arbiters import Arbiter
from ._motion_evidence import count_bases
from ._orbit import PeriodicOrbitEvidence
from ._result import Verdict
from ._rule import Label, VerdictRule, Vote
from ._section_structure import SectionStructure


def _section_vote(label: str, structure: SectionStructure | None, n_bases: int) -> Vote:
    if structure is None:
        return "missing"
    if structure.kind == "too-few-points":
        return "neutral"
    if label == "quasi-periodic" and n_bases >= 3 and structure.kind == "scattered":
        return "neutral"  # a three-torus's section fills a surface
    wanted = {"periodic": "clusters", "quasi-periodic": "closed-curve"}.get(label, "scattered")
    return "supports" if structure.kind == wanted else "opposes"


def _exponent_vote(label: str, positive: bool | None) -> Vote:
    if positive is None:
        return "missing"
    if label == "noise-like":
        return "neutral"
    return "supports" if positive == (label == "chaotic") else "opposes"


def _equations_vote(label: str, say: Arbiter | None) -> Vote:
    if say is None:
        return "missing"
    if label == "noise-like":
        return "opposes"  # the equations are deterministic
    return "supports" if (say == "chaotic") == (label == "chaotic") else "opposes"


def _decides(
    label: str,
    *,
    structure: SectionStructure | None,
    positive: bool | None,
    say: Arbiter | None,
    voters: Mapping[str, Verdict],
) -> bool:
    """Whether the joint evidence alone establishes ``label`` (given one variable says it,
    or — for chaos — the data are more predictable than their surrogates)."""
    kind = "none" if structure is None else structure.kind
    labels = {v.label for v in voters.values()}
    # without a usable joint section, a variable's own decisive evidence stands when every
    # other variable is undetermined and the exponents do not contradict it
    no_section = kind in ("none", "too-few-points")
    if label == "periodic":
        repeats = any(
            v.label == "periodic" and v.lines is not None and v.lines.kind == "periodic"
            for v in voters.values()
        )
        alone = (
            no_section
            and repeats
            and labels <= {"periodic", "undetermined"}
            and positive is not True
            and say != "chaotic"
        )
        # tight clusters with a clearly growing joint exponent are a narrow chaotic band as
        # much as a noisy orbit: the clusters alone do not decide
        return (kind == "clusters" and "periodic" in labels and positive is not True) or alone
    if label == "quasi-periodic":
        return (
            kind == "closed-curve"
            and positive is not True
            and say != "chaotic"
            and "quasi-periodic" in labels
        )
    if label == "chaotic":
        deterministic = "chaotic" in labels or any(
            v.surrogates is not None and v.surrogates.rejected for v in voters.values()
        )
        regular_said = labels & {"periodic", "quasi-periodic", "noise-like"}
        # a variable that is chaotic by its own full evidence (both exponents clearly
        # positive, surrogates rejected) stands when no other says regular or noise
        unopposed = "chaotic" in labels and not regular_said and say != "regular"
        alone = no_section and unopposed and (positive is True or say == "chaotic")
        return alone or (
            kind == "scattered"
            and (positive is True or say == "chaotic" or unopposed)
            and deterministic
            and ("chaotic" in labels or not regular_said)
        )
    return False


def _orbit_label(
    orbit: PeriodicOrbitEvidence, structure: SectionStructure | None, say: Arbiter | None
) -> tuple[Label, str, list[str]]:
    """The label when the equations give a converged, stable, attracting orbit: periodic
    unless the joint section or the equations' exponent contradicts it."""
    section = "none" if structure is None else structure.kind
    k = orbit.period
    said_orbit = (
        f"the equations say regular: periodic with period {k} (a converged, stable "
        f"orbit, largest multiplier |μ| = {orbit.largest_multiplier:.3g}, that the motion "
        f"approaches to {orbit.approach:.2g})"
    )
    conflict = None
    if section in ("scattered", "closed-curve"):
        conflict = f"the joint section of the data is {section}"
    elif section == "clusters" and structure is not None and structure.n_clusters != k:
        conflict = f"the joint section is {structure.n_clusters} tight clusters, not {k}"
    elif say == "chaotic":
        conflict = "the equations' exponent says chaotic"
    if conflict is None:
        reason = said_orbit + (
            f"; the joint section is {k} tight cluster{'s' * (k != 1)}"
            if section == "clusters"
            else ""
        )
        return "periodic", reason, []
    needs = [
        "a longer series after the transient or a tighter integration tolerance (the "
        "motion may not have settled on the orbit, or another attractor coexists "
        "with it)"
    ]
    return "undetermined", f"{said_orbit}, but {conflict}", needs


def _agreed_label(
    voters: Mapping[str, Verdict],
    candidate: str,
    *,
    structure: SectionStructure | None,
    say: Arbiter | None,
    decided_jointly: bool,
    section_need: str | None,
) -> tuple[Label, str, list[str]]:
    """The label when every variable decides the same ``candidate``: it stands unless the
    joint section or the equations oppose it and the joint evidence does not decide it."""
    section = "none" if structure is None else structure.kind
    section_vote = _section_vote(candidate, structure, count_bases(voters))
    against_section = section_vote == "opposes" and candidate != "noise-like"
    against_equations = _equations_vote(candidate, say) == "opposes"
    every = (
        f"every variable says {candidate}"
        if len(voters) > 1
        else f"the one voting variable says {candidate}"
    )
    if candidate == "equilibrium" or not (against_section or against_equations) or decided_jointly:
        reason = every
        if (against_section or against_equations) and decided_jointly:
            reason += "; the joint section decides against the equations"
        return candidate, reason, []  # type: ignore[return-value]
    needs: list[str] = []
    reason = every + ", but "
    if against_section:
        reason += f"the joint section is {section}"
        needs.append(
            f"a longer series or a tighter integration tolerance: every variable says "
            f"{candidate} but the joint section of all variables is {section}"
        )
    else:
        reason += f"the equations say {say}"
        if section_need:
            needs.append(section_need)
        needs.append(
            f"a longer series or finer sampling: the equations say {say}, the data "
            f"say {candidate}, and the joint section does not decide ({section})"
        )
    return "undetermined", reason, needs


def _split_needs(
    voters: Mapping[str, Verdict],
    *,
    structure: SectionStructure | None,
    positive: bool | None,
    say: Arbiter | None,
    n_cycles: float,
    cycle_unit: str,
    rule: VerdictRule,
    section_need: str | None,
) -> list[str]:
    """What would decide when the variables do not agree and the joint evidence cannot."""
    section = "none" if structure is None else structure.kind
    decided = {n: v.label for n, v in voters.items() if v.label != "undetermined"}
    needs: list[str] = []
    if n_cycles < rule.min_cycles:
        needs.append(f"≥ {rule.min_cycles} {cycle_unit}; the series has {n_cycles:.0f}")
    if section == "too-few-points":
        assert structure is not None
        needs.append(
            f"≥ {rule.min_cycles} joint section points; the joint section has {structure.n_points}"
        )
    elif section in ("clusters", "closed-curve"):
        assert structure is not None
        shape = (
            f"{structure.n_clusters} tight cluster{'s' * (structure.n_clusters != 1)}"
            if section == "clusters"
            else "a closed curve"
        )
        chaotic = [n for n, lab in decided.items() if lab == "chaotic"]
        against = (
            f"{', '.join(chaotic)} says chaotic"
            if chaotic
            else "the joint exponent is clearly positive"
            if positive
            else "no variable's own evidence says regular"
        )
        needs.append(
            f"more {cycle_unit} or a tighter integration tolerance: the joint section "
            f"is {shape} but {against}"
        )
    elif section == "scattered" and positive is not True and say != "chaotic":
        needs.append(
            "a clearly positive exponent of the joint embedding (or from the "
            "equations of motion), or more "
            f"{cycle_unit}: the joint section is scattered"
        )
    if section_need:
        needs.append(section_need)
    if len(voters) == 1:
        needs.append("another variable of the motion (only one variable votes)")
    for n, v in voters.items():
        needs.extend(f"{n}: {need}" for need in v.needs)
    if not needs:
        needs.append(f"a longer series (more {cycle_unit}) or another variable")
    return needs


def _motion_period(
    label: str,
    voters: Mapping[str, Verdict],
    structure: SectionStructure | None,
    orbit: PeriodicOrbitEvidence | None,
) -> int | None:
    """The period of a periodic motion: the orbit's, the joint clusters' or the least
    common multiple of the variables' periods."""
    if label != "periodic":
        return None
    if orbit is not None and orbit.problem() is None:
        return orbit.period
    if structure is not None and structure.kind == "clusters":
        return structure.n_clusters
    periods = [v.period for v in voters.values() if v.period]
    return math.lcm(*periods) if periods else None


def _motion_votes(
    target: str,
    voters: Mapping[str, Verdict],
    *,
    structure: SectionStructure | None,
    positive: bool | None,
    say: Arbiter | None,
    orbit: PeriodicOrbitEvidence | None,
) -> dict[str, Vote]:
    """Each piece of the evidence for or against the decided label ``target``."""
    votes: dict[str, Vote] = {
        "section": _section_vote(target, structure, count_bases(voters)),
        "exponent": _exponent_vote(target, positive),
        "equations": _equations_vote(target, say),
    }
    if orbit is not None:
        votes["orbit"] = (
            "neutral"
            if orbit.problem() is not None
            else "supports"
            if target == "periodic"
            else "opposes"
        )
    for n, v in voters.items():
        lab = v.label
        votes[f"variable {n}"] = (
            "neutral" if lab == "undetermined" else ("supports" if lab == target else "opposes")
        )
    return votes


def combine_motion(
    voters: Mapping[str, Verdict],
    *,
    structure: SectionStructure | None,
    positive: bool | None,
    say: Arbiter | None,
    n_cycles: float,
    cycle_unit: str,
    rule: VerdictRule,
    section_need: str | None = None,
    orbit: PeriodicOrbitEvidence | None = None,
) -> RuleOutcome:
    """The motion rule of :func:`classify_motion` on the voters' verdicts and the joint
    evidence; returns its label, period, confidence, reason, votes and needs. ``section_need``
    says what the joint section lacks when it is not used (``structure`` None); ``orbit``
    is the equations' periodic orbit (used only when it is converged, stable and
    attracting)."""
    labels = {n: v.label for n, v in voters.items()}
    decided = {n: lab for n, lab in labels.items() if lab != "undetermined"}

    def decides(lab: str) -> bool:
        return _decides(lab, structure=structure, positive=positive, say=say, voters=voters)

    label: Label
    needs: list[str] = []
    if orbit is not None and orbit.problem() is None:
        label, reason, needs = _orbit_label(orbit, structure, say)
    elif len(decided) == len(labels) and len(set(decided.values())) == 1:
        candidate = next(iter(decided.values()))
        label, reason, needs = _agreed_label(
            voters,
            candidate,
            structure=structure,
            say=say,
            decided_jointly=decides(candidate),
            section_need=section_need,
        )
    else:
        options = sorted({lab for lab in [*decided.values(), "chaotic"] if decides(lab)})
        said = ", ".join(f"{n}: {lab}" for n, lab in labels.items())
        if not decided:
            split = f"no variable decides on its own ({said})"
        elif len(set(decided.values())) == 1:
            split = f"not every variable decides ({said})"
        else:
            split = f"the variables disagree ({said})"
        if len(options) == 1:
            label = options[0]  # type: ignore[assignment]
            reason = f"{split}; the joint evidence decides {label}"
        else:
            label = "undetermined"
            reason = f"{split} and the joint evidence cannot decide"
            needs = _split_needs(
                voters,
                structure=structure,
                positive=positive,
                say=say,
                n_cycles=n_cycles,
                cycle_unit=cycle_unit,
                rule=rule,
                section_need=section_need,
            )
    period = _motion_period(label, voters, structure, orbit)
    votes: dict[str, Vote] = {}
    if label != "undetermined":
        votes = _motion_votes(
            label, voters, structure=structure, positive=positive, say=say, orbit=orbit
        )
        counted = [v for v in votes.values() if v in ("supports", "opposes")]
        confidence = sum(v == "supports" for v in counted) / len(counted) if counted else 0.0
    else:
        confidence = float("nan")
        reason += ": needs " + "; ".join(dict.fromkeys(needs))
    return RuleOutcome(
        label=label,
        period=period,
        confidence=confidence,
        reason=reason,
        votes=votes,
        needs=tuple(dict.fromkeys(needs)),
    )
