"""One verdict per motion: all variables of a trajectory, their joint section and exponent.

Chaos is a property of the motion, not of one coordinate. :func:`classify_motion` runs
:func:`chaoskit.classify` on every chosen variable, sets aside the variables that follow the
drive alone (a prescribed crank angle, a forcing phase) or are constant, and weighs what is
left against the evidence that belongs to the whole state: the joint section of all
variables together, the largest exponent of a mixed delay embedding of all of them, and —
for simulated systems — the exponent from the equations of motion.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import xarray as xr
from scipy.interpolate import CubicSpline

from .._contract import stamp
from .._io import load_trajectory
from .._tables import has_time_index
from ..lyapunov import lyapunov_rosenstein
from ..sections import stroboscopic_map
from ._analyze import classify_variables, series_dataset
from ._clusters import SectionStructure, section_structure
from ._orbit import PeriodicOrbitEvidence
from ._table import stack_verdicts
from ._verdict import (
    LABELS,
    Label,
    Verdict,
    VerdictRule,
    Vote,
    clearly_positive,
    describe_error,
)

__all__ = ["MotionVerdict", "classify_motion"]

#: A drive follower's stroboscopic set is one point to round-off: its RMS radius is at most
#: this fraction of the variable's standard deviation (a response converged to a period-1
#: orbit meets it as well, and is then periodic with the drive, which is what it says).
DRIVE_TOL = 1e-6
Arbiter = Literal["chaotic", "regular"]


@dataclass(frozen=True, kw_only=True)
class MotionVerdict:
    """One label for the motion of a trajectory, with the evidence of all its variables.

    Attributes
    ----------
    label
        One of ``chaoskit.verdict.LABELS``; ``"undetermined"`` when the evidence, variables and
        joint evidence together, cannot decide.
    period
        :math:`k` of a period-:math:`k` motion (points of the joint section per period:
        drive periods for a forced system, iterations for a map), else None.
    confidence
        Fraction of the pieces of evidence that could have decided (joint section, joint
        exponent, the equations' exponent, each voting variable's label) that agree with
        the label; NaN when undetermined. See ``votes``.
    reason
        The rule that fired, in one line.
    reasons
        Everything a user should know, one line each: the rule, which variables were set
        aside and why, each variable's verdict, the data's and the equations' exponents and
        any disagreement between them.
    needs
        When undetermined: what would decide (more drive periods, a tighter tolerance,
        another variable).
    votes
        ``section``, ``exponent``, ``equations`` and ``variable NAME`` for each voting
        variable: ``"supports"``, ``"opposes"``, ``"neutral"`` or ``"missing"``.
    variables
        ``{name: Verdict}`` for every chosen variable (including those set aside).
    voting, drive_variables, constant_variables
        Names of the variables that voted, that follow the drive alone, and that are
        constant.
    kind, dt, n_samples
        ``"map"``, ``"flow"`` or ``"forced"``, the sampling interval (s; 1 for maps) and
        the series length.
    characteristic_time, n_cycles
        :math:`T` of the growth test (s, or iterations) and the characteristic times the
        series spans, from the variable whose section sets the joint section's instants.
    structure, section
        The :class:`SectionStructure` of the joint section and its points (a Dataset along
        ``crossing``: every voting variable, scaled to unit standard deviation, at crossing
        :math:`n` and :math:`n + 1`).
    exponent, exponent_positive
        The Rosenstein :class:`~chaoskit.LyapunovResult` of the mixed delay embedding of
        the voting variables, and whether it is clearly positive (None if missing).
    equations, equations_say
        The exponent object given as ``exponent=`` (from the equations of motion) and
        what it says: ``"chaotic"`` (95 % interval above 0), ``"regular"`` or None.
    orbit, orbit_says_periodic
        The :class:`PeriodicOrbitEvidence` given as ``orbit=`` and whether it is evidence
        (converged, stable and attracting); when it is not, ``reasons`` says why.
    errors
        Joint evidence that could not be computed, with the message.
    rule
        The :class:`VerdictRule` applied.
    """

    label: Label
    period: int | None
    confidence: float
    reason: str
    reasons: tuple[str, ...]
    needs: tuple[str, ...]
    votes: dict[str, Vote]
    variables: dict[str, Verdict] = field(repr=False)
    voting: tuple[str, ...]
    drive_variables: tuple[str, ...] = ()
    constant_variables: tuple[str, ...] = ()
    kind: str
    dt: float
    n_samples: int
    characteristic_time: float = float("nan")
    n_cycles: float = float("nan")
    structure: SectionStructure | None = field(default=None, repr=False)
    section: xr.Dataset | None = field(default=None, repr=False)
    exponent: Any = field(default=None, repr=False)
    exponent_positive: bool | None = None
    equations: Any = field(default=None, repr=False)
    equations_say: Arbiter | None = None
    orbit: PeriodicOrbitEvidence | None = field(default=None, repr=False)
    orbit_says_periodic: bool = False
    errors: dict[str, str] = field(default_factory=dict, repr=False)
    rule: VerdictRule = field(default_factory=VerdictRule, repr=False)

    def summary(self) -> dict[str, Any]:
        """Scalar fields of the motion (NaN where undefined), each prefixed ``motion_``."""
        nan = float("nan")
        res = self.exponent
        eq = _arbiter_values(self.equations) if self.equations is not None else (nan,) * 3
        st = self.structure
        orb = self.orbit
        return {
            "motion_label": self.label,
            "motion_period": nan if self.period is None else float(self.period),
            "motion_confidence": float(self.confidence),
            "motion_section_points": nan if st is None else float(st.n_points),
            "motion_section_structure": "none" if st is None else st.kind,
            "motion_mle": nan if res is None else float(res.mle),
            "motion_mle_low": nan if res is None else float(res.ci[0]),
            "motion_mle_high": nan if res is None else float(res.ci[1]),
            "motion_mle_equations": eq[0],
            "motion_mle_equations_low": eq[1],
            "motion_mle_equations_high": eq[2],
            "motion_n_cycles": float(self.n_cycles),
            "motion_orbit_period": nan if orb is None else float(orb.period),
            "motion_orbit_multiplier": nan if orb is None else orb.largest_multiplier,
            "motion_orbit_residual": nan if orb is None else orb.residual,
            "motion_orbit_approach": nan if orb is None else orb.approach,
            "motion_orbit_evidence": float(self.orbit_says_periodic),
            "motion_needs": "; ".join(self.needs),
        }

    def to_dataset(self) -> xr.Dataset:
        """The motion's scalars beside the per-variable table (dimension ``variable``).

        ``motion_*`` fields are the motion verdict (exponents in s⁻¹ for flows, per
        iteration for maps); the other fields are :func:`chaoskit.analyze`'s rows;
        the attribute ``motion_reasons`` holds ``reasons``.
        """
        table = stack_verdicts(self.variables, LABELS)
        unit = "1" if self.kind == "map" else "s"
        for key, value in self.summary().items():
            long_name, units = MOTION_FIELDS[key]
            attrs = {"long_name": long_name}
            if key in _MOTION_STRINGS:
                table[key] = xr.DataArray(np.array(value, dtype=object), attrs=attrs)
            else:
                attrs["units"] = units.replace("T-1", f"{unit}-1" if unit == "s" else "1")
                table[key] = xr.DataArray(np.float64(value), attrs=attrs)
        table["motion_label"].attrs["flag_meanings"] = " ".join(LABELS)
        table.attrs["motion_reasons"] = " | ".join(self.reasons)
        return stamp(table, title="chaoskit.classify_motion", history="chaoskit.classify_motion")


#: The motion fields of :meth:`MotionVerdict.summary`: (long_name, units).
MOTION_FIELDS: dict[str, tuple[str, str]] = {
    "motion_label": ("verdict of the motion (all variables)", ""),
    "motion_period": ("period k of the motion (joint section points per period)", "1"),
    "motion_confidence": ("fraction of the joint evidence agreeing with the motion verdict", "1"),
    "motion_section_points": ("points in the joint section", "1"),
    "motion_section_structure": ("structure of the joint section", ""),
    "motion_mle": ("largest Lyapunov exponent of the mixed embedding, Rosenstein", "T-1"),
    "motion_mle_low": ("lower end of the 95% interval, mixed embedding", "T-1"),
    "motion_mle_high": ("upper end of the 95% interval, mixed embedding", "T-1"),
    "motion_mle_equations": ("largest Lyapunov exponent from the equations of motion", "T-1"),
    "motion_mle_equations_low": ("lower end of the 95% interval, equations", "T-1"),
    "motion_mle_equations_high": ("upper end of the 95% interval, equations", "T-1"),
    "motion_n_cycles": ("characteristic times spanned by the series", "1"),
    "motion_orbit_period": ("period k of the periodic orbit of the equations", "1"),
    "motion_orbit_multiplier": ("largest modulus of the orbit's non-neutral multipliers", "1"),
    "motion_orbit_residual": ("relative closing error of the orbit", "1"),
    "motion_orbit_approach": ("relative distance of the motion from the orbit", "1"),
    "motion_orbit_evidence": ("1 if the orbit is converged, stable and attracting", "1"),
    "motion_needs": ("what would decide an undetermined motion", ""),
}
_MOTION_STRINGS = ("motion_label", "motion_section_structure", "motion_needs")


# ---------------------------------------------------------------- the equations' exponent


def _arbiter_values(obj: Any) -> tuple[float, float, float]:
    """(exponent, low, high) of an exponent object: ``exponent`` or ``mle``, and a 95 %
    interval ``ci`` or ``interval``."""
    value = getattr(obj, "exponent", None)
    if value is None:
        value = getattr(obj, "mle", None)
    interval = getattr(obj, "ci", None)
    if interval is None:
        interval = getattr(obj, "interval", None)
    try:
        lo, hi = (float(v) for v in interval)  # type: ignore[union-attr]
        value = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(
            "exponent must have 'exponent' (1/s) and a 95 % interval 'ci' (or 'interval') "
            f"of two numbers; got {type(obj).__name__}."
        ) from None
    if lo > hi:
        raise ValueError(f"exponent's interval must have low <= high; got [{lo!r}, {hi!r}].")
    return value, lo, hi


def _arbiter(obj: Any) -> tuple[Arbiter | None, str]:
    value, lo, hi = _arbiter_values(obj)
    if not (math.isfinite(value) and math.isfinite(lo) and math.isfinite(hi)):
        return None, (
            f"the equations' exponent λ₁ = {value:.4g} [{lo:.4g}, {hi:.4g}] has no finite 95 % "
            "interval (too few renormalisation intervals); it is not used as evidence"
        )
    say: Arbiter = "chaotic" if lo > 0.0 else "regular"
    why = "95 % interval above 0" if say == "chaotic" else "95 % interval not above 0"
    return say, f"the equations say {say}: λ₁ = {value:.4g} [{lo:.4g}, {hi:.4g}] ({why})"


# ---------------------------------------------------------------- joint evidence


def _is_drive_follower(v: Verdict) -> bool:
    """Periodic with period 1 and a stroboscopic set that is one point to round-off."""
    st = v.structure
    return (
        v.kind == "forced"
        and v.label == "periodic"
        and v.period == 1
        and st is not None
        and st.kind == "clusters"
        and st.n_clusters == 1
        and st.cluster_radius <= DRIVE_TOL
    )


def _unit(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    peak = float(np.max(np.abs(x)))
    if peak == 0.0:
        return np.zeros_like(x)  # constant: no spread to scale (never a voter)
    y = x / peak - float(np.mean(x / peak))
    spread = float(np.std(y))
    return y / spread if spread > 0.0 else y


def _reference(voters: Mapping[str, Verdict]) -> str:
    """The voter whose section sets the instants of the joint section: most points."""

    def points(name: str) -> int:
        st = voters[name].structure
        return -1 if st is None else st.n_points

    return max(voters, key=points)


def _joint_section(
    ds: xr.Dataset,
    voters: Mapping[str, Verdict],
    ref: str,
    *,
    kind: str,
    drive_period: float | None,
    phase_variable: str | None,
) -> tuple[xr.Dataset, np.ndarray]:
    """Every voter (unit spread) at the joint section's instants n and n + 1."""
    names = list(voters)
    scaled = {n: _unit(ds[n].values) for n in names}
    resolution = 0.0  # the instants are samples (maps) or interpolated to 1e-8 (strobes)
    if kind == "map":
        at = np.column_stack([scaled[n] for n in names])
        crossing_time = np.asarray(ds["step"].values, dtype=np.float64)
    elif kind == "forced":
        strobe_in = xr.Dataset(
            {n: ("time", scaled[n]) for n in names}, coords={"time": ds["time"].values}
        )
        if phase_variable is not None:
            strobe_in["__angle"] = ("time", np.asarray(ds[phase_variable].values, float))
            sec = stroboscopic_map(strobe_in, phase_variable="__angle")
        else:
            sec = stroboscopic_map(strobe_in, period=drive_period)
        at = np.column_stack([sec[n].values for n in names])
        crossing_time = np.asarray(sec["time"].values, dtype=np.float64)
    else:
        ref_section = voters[ref].section
        if ref_section is None or "time" not in ref_section.coords:
            raise ValueError(f"no section of {ref!r} to take the joint section's instants from.")
        crossing_time = np.asarray(ref_section["time"].values, dtype=np.float64)
        t = np.asarray(ds["time"].values, dtype=np.float64)
        at = np.column_stack([CubicSpline(t, scaled[n])(crossing_time) for n in names])
        # what the sampling cannot resolve between samples: cubic against linear interpolation
        linear = np.column_stack([np.interp(crossing_time, t, scaled[n]) for n in names])
        resolution = float(np.sqrt(np.mean((at - linear) ** 2))) if at.size else 0.0
    m = max(at.shape[0] - 1, 0)
    data_vars: dict[str, Any] = {}
    for j, n in enumerate(names):
        data_vars[n] = ("crossing", at[:m, j], {"units": "1", "long_name": f"{n} / std"})
        data_vars[f"{n}_next"] = (
            "crossing",
            at[1 : m + 1, j],
            {"units": "1", "long_name": f"{n} / std at the next crossing"},
        )
    sec_ds = xr.Dataset(
        data_vars,
        coords={"crossing": np.arange(m), "time": ("crossing", crossing_time[:m])},
    )
    sec_ds.attrs["interpolation_rms"] = resolution
    sec_ds.attrs["section_kind"] = {
        "map": "iterates of every variable",
        "forced": "stroboscopic map of every variable",
        "flow": f"every variable at the maxima of {ref}",
    }[kind]
    points = np.column_stack([sec_ds[k].values for k in data_vars])
    return sec_ds, points


def mixed_embedding(ds: xr.Dataset, voters: Mapping[str, Verdict]) -> tuple[np.ndarray, int]:
    """Mixed delay vectors of the voters (each at unit spread, its own delay) and the lag
    that tells a flow from a map.

    The dimension is the largest of the voters' embedding dimensions (at least one
    coordinate per variable), shared evenly among the variables (Cao, Mees & Judd 1998).
    """
    names = list(voters)
    lags = [int(voters[n].lag or 1) for n in names]
    total = max([len(names), *[int(voters[n].embedding_dim or 1) for n in names]])
    each = max(1, math.ceil(total / len(names)))
    span = max((each - 1) * lag for lag in lags)
    rows = ds.sizes[next(iter(ds[names[0]].dims))] - span
    if rows < 1:
        raise ValueError("the series is too short for the mixed embedding.")
    columns: list[np.ndarray] = []
    for n, lag in zip(names, lags, strict=True):
        x = _unit(ds[n].values)
        columns.extend(x[i * lag : i * lag + rows] for i in range(each))
    return np.ascontiguousarray(np.column_stack(columns)), max(lags)


# ---------------------------------------------------------------- the rule


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
) -> tuple[Label, int | None, float, str, dict[str, Vote], tuple[str, ...]]:
    """The motion rule of :func:`classify_motion` on the voters' verdicts and the joint
    evidence; returns label, period, confidence, reason, votes and needs. ``section_need``
    says what the joint section lacks when it is not used (``structure`` None); ``orbit``
    is the equations' periodic orbit (used only when it is converged, stable and
    attracting)."""
    labels = {n: v.label for n, v in voters.items()}
    decided = {n: lab for n, lab in labels.items() if lab != "undetermined"}
    said = ", ".join(f"{n}: {lab}" for n, lab in labels.items())
    section = "none" if structure is None else structure.kind
    enough = n_cycles >= rule.min_cycles

    def decides(lab: str) -> bool:
        return _decides(lab, structure=structure, positive=positive, say=say, voters=voters)

    label: Label = "undetermined"
    needs: list[str] = []
    agree = len(decided) == len(labels) and len(set(decided.values())) == 1
    orbit_ok = orbit is not None and orbit.problem() is None
    if orbit_ok:
        assert orbit is not None
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
            label = "periodic"
            reason = said_orbit + (
                f"; the joint section is {k} tight cluster{'s' * (k != 1)}"
                if section == "clusters"
                else ""
            )
        else:
            reason = f"{said_orbit}, but {conflict}"
            needs.append(
                "a longer series after the transient or a tighter integration tolerance (the "
                "motion may not have settled on the orbit, or another attractor coexists "
                "with it)"
            )
    elif agree:
        candidate = next(iter(decided.values()))
        section_vote = _section_vote(candidate, structure, _bases(voters))
        against_section = section_vote == "opposes" and candidate != "noise-like"
        against_equations = _equations_vote(candidate, say) == "opposes"
        # a periodic label with a clearly positive exponent of the joint embedding, and no
        # word from the equations, may be a narrow chaotic band under the cluster allowance
        against_exponent = candidate == "periodic" and positive is True and say is None
        decided_jointly = decides(candidate)
        if (
            candidate == "equilibrium"
            or not (against_section or against_equations or against_exponent)
            or decided_jointly
        ):
            label = candidate
            reason = (
                f"every variable says {candidate}"
                if len(labels) > 1
                else f"the one voting variable says {candidate}"
            )
            if (against_section or against_equations) and decided_jointly:
                reason += "; the joint section decides against the equations"
        else:
            reason = (
                f"every variable says {candidate}, but "
                if len(labels) > 1
                else f"the one voting variable says {candidate}, but "
            )
            if against_exponent and not (against_section or against_equations):
                reason += "the exponent of the joint embedding is clearly positive"
                if section_need:
                    needs.append(section_need)
                needs.append(
                    "a tighter integration tolerance, the equations' exponent or a periodic "
                    "orbit: every variable says periodic within the cluster allowance, but "
                    "the exponent of the joint embedding is clearly positive"
                )
            elif against_section:
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
    else:
        options = sorted({lab for lab in [*decided.values(), "chaotic"] if decides(lab)})
        if not decided:
            split = f"no variable decides on its own ({said})"
        elif len(set(decided.values())) == 1:
            split = f"not every variable decides ({said})"
        else:
            split = f"the variables disagree ({said})"
        if len(options) == 1:
            label = options[0]
            reason = f"{split}; the joint evidence decides {label}"
        else:
            reason = f"{split} and the joint evidence cannot decide"
            if not enough:
                needs.append(f"≥ {rule.min_cycles} {cycle_unit}; the series has {n_cycles:.0f}")
            if section == "too-few-points":
                assert structure is not None
                needs.append(
                    f"≥ {rule.min_cycles} joint section points; the joint section has "
                    f"{structure.n_points}"
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
    period = None
    if label == "periodic" and orbit_ok:
        assert orbit is not None
        period = orbit.period
    elif label == "periodic":
        if structure is not None and structure.kind == "clusters":
            period = structure.n_clusters
        else:
            periods = [v.period for v in voters.values() if v.period]
            period = math.lcm(*periods) if periods else None
    votes: dict[str, Vote] = {}
    target = label if label != "undetermined" else None
    if target is not None:
        votes["section"] = _section_vote(target, structure, _bases(voters))
        votes["exponent"] = _exponent_vote(target, positive)
        votes["equations"] = _equations_vote(target, say)
        if orbit is not None:
            votes["orbit"] = (
                "neutral" if not orbit_ok else "supports" if target == "periodic" else "opposes"
            )
        for n, lab in labels.items():
            votes[f"variable {n}"] = (
                "neutral" if lab == "undetermined" else ("supports" if lab == target else "opposes")
            )
        counted = [v for v in votes.values() if v in ("supports", "opposes")]
        confidence = sum(v == "supports" for v in counted) / len(counted) if counted else 0.0
    else:
        confidence = float("nan")
        reason += ": needs " + "; ".join(dict.fromkeys(needs))
    return label, period, confidence, reason, votes, tuple(dict.fromkeys(needs))


def _bases(voters: Mapping[str, Verdict]) -> int:
    return max(
        (int(v.lines.base_frequencies.size) for v in voters.values() if v.lines is not None),
        default=0,
    )


# ---------------------------------------------------------------- classify_motion


def _as_dataset(data: Any, dt: float | None) -> xr.Dataset:
    if isinstance(data, (xr.Dataset, xr.DataArray)):
        return load_trajectory(data, dt=dt if "time" not in data.coords else None)
    if has_time_index(data):  # the index sets dt; load_trajectory refuses a contradicting dt=
        return load_trajectory(data, dt=dt, require_uniform=True)
    arr = np.asarray(getattr(data, "values", data))
    if arr.ndim != 2:
        raise ValueError(f"data must be a Dataset or an (n, k) array; got shape {arr.shape}.")
    names = [f"x{j + 1}" for j in range(arr.shape[1])]
    if dt is None:
        return load_trajectory(arr, step="step", variables=names)
    return load_trajectory(arr, dt=dt, variables=names)


def classify_motion(
    data: Any,
    *,
    variables: Sequence[str] | None = None,
    dt: float | None = None,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    drive_variables: Sequence[str] = (),
    exponent: Any = None,
    orbit: PeriodicOrbitEvidence | None = None,
    n_surrogates: int = 19,
    rule: VerdictRule | None = None,
    rng: Any = None,
    progress: bool = False,
) -> MotionVerdict:
    r"""One verdict for the motion of a trajectory, from all its variables.

    Chaos is a property of the motion: every generic observable of one attractor must give
    the same answer. The motion verdict therefore weighs the verdict of each variable
    (:func:`chaoskit.classify`) against the evidence that belongs to the whole state.

    **Evidence.**

    1. each variable's :class:`Verdict`;
    2. the *joint section*: every voting variable, scaled to unit standard deviation, at
       the instants of one section — the drive period (stroboscopic map) for a forced
       system, each iteration for a map, the maxima of one variable (the one whose own
       section has the most points) for an autonomous flow — paired with the same at the
       next instant, :math:`(\mathbf v_n, \mathbf v_{n+1})`. A periodic motion makes it
       finite (:math:`k` tight clusters visited cyclically: period :math:`k`); a
       quasi-periodic one a closed curve; chaos a scattered set
       (:func:`section_structure`, cluster allowance as in :func:`classify`, at least
       ``rule.min_cycles`` points);
    3. the *joint exponent*: Rosenstein's estimate on mixed delay vectors (each variable at
       unit spread, with its own delay; the dimension is the largest per-variable
       embedding dimension, shared evenly; Cao, Mees & Judd 1998), clearly positive as in
       :func:`classify` (interval above 0, :math:`\lambda_1 T \ge` ``rule.min_growth``);
    4. ``exponent``: the largest exponent from the equations of motion (e.g.
       :func:`mechanism.lyapunov_exponent`): a 95 % interval above 0 says chaotic, one
       containing 0 or below says regular;
    5. ``orbit``: a periodic orbit of the equations (:class:`PeriodicOrbitEvidence`). One
       that is converged (closing error within its tolerance), stable (every non-neutral
       Floquet multiplier inside the unit circle) and attracting (the simulated motion
       within the tolerance of it) says "the equations say regular: periodic with period
       :math:`k`"; an unstable, unconverged or unapproached orbit is no evidence and the
       reasons say why.

    **Who votes.** A variable that follows the drive alone — listed in ``drive_variables``,
    or found to be periodic with period 1 with a stroboscopic set that is one point to
    round-off (RMS radius ≤ 10⁻⁶ of its spread: a prescribed crank angle, a forcing
    phase) — is periodic by construction and no evidence against chaos; a constant
    variable carries no evidence at all. Both are set aside and named in the reasons. If
    every variable follows the drive, the motion is periodic with period 1; if every one
    is constant, an equilibrium.

    **Rule.**

    * the voting variables *agree* on a label: that label, unless the joint section
      opposes it (a periodic label with a scattered joint set, a chaotic one with tight
      clusters or a closed curve), the equations do, or — for a periodic label with
      no word from the equations — the joint exponent is clearly positive (tight
      clusters may be a narrow chaotic band), and the joint evidence does not decide
      it — then *undetermined*;
    * they *disagree* (or some are undetermined): the one label the joint evidence
      decides — *periodic* if the joint section is tight clusters, a variable says
      periodic and the joint exponent is not clearly positive; *quasi-periodic* if it is a
      closed curve, a variable says so and neither
      exponent is clearly positive; *chaotic* if it is scattered, a variable says chaotic
      (or, with no regular or noise label said, a surrogate test rejected linear noise),
      and the joint exponent or the equations' exponent is clearly positive — or no other
      variable says regular or noise and the equations do not say regular; otherwise
      *undetermined*, with ``needs`` naming what would decide (more drive periods, more
      joint section points, finer sampling, a tighter tolerance, a clearly positive
      exponent, another variable) and each variable's own needs;
    * the joint section is used only where the sampling resolves it: for an autonomous
      flow its instants fall between samples, and when cubic and linear interpolation
      there differ by more than ``rule.max_noise_allowance / rule.noise_factor`` (0.1) of
      a variable's spread, it is set aside (``needs``: finer sampling). Without a usable
      joint section a variable's own decisive evidence stands only when every other
      variable is undetermined and the exponents agree: *periodic* from a series that
      repeats (its line analysis) with no clearly positive exponent, *chaotic* from a
      chaotic variable with a clearly positive joint or equations' exponent.

    * a periodic orbit that is evidence (item 5) decides *periodic* with its period
      :math:`k` before any of the above, unless the joint section is scattered or a closed
      curve, is tight clusters of another number than :math:`k`, or the equations'
      exponent says chaotic: then *undetermined* (the motion may not have settled on the
      orbit, or another attractor coexists with it), and the reason says which.

    **Confidence** is the fraction of the pieces that could have decided — the joint
    section, the joint exponent, the equations' exponent, the orbit and each voting
    variable's label
    (undetermined variables are neutral) — that agree with the label (``votes``). A
    disagreement the joint evidence leaves unresolved is undetermined (confidence NaN),
    never a confident label.

    Parameters
    ----------
    data
        A trajectory Dataset (``time`` in s: a flow; ``step``: a map), or an ``(n, k)``
        array (columns ``x1`` … ``xk``; a map unless ``dt`` is given).
    variables
        Variables of the motion, each ``NAME`` or ``NAME[DIM=VALUE,...]`` (default: every
        variable along ``time``/``step`` except ``phase_variable``; a variable with extra
        dimensions is expanded by label, e.g. ``eccentricity_x[joint=C]``).
    dt
        Sampling interval (s) for array input.
    drive_period, phase_variable
        The drive of a forced system (s, or the name of a drive-angle variable in rad).
    drive_variables
        Variables known to follow the drive alone (set aside without testing).
    exponent
        The largest exponent from the equations of motion: any object with ``exponent``
        (or ``mle``) in 1/s and a 95 % interval ``ci`` (or ``interval``); None if unknown.
    orbit
        A periodic orbit of the equations of motion (e.g. from
        ``mechanism.periodic_orbit``), or None.
    n_surrogates, rule
        As in :func:`classify`.
    rng
        Seed or Generator; each variable gets an independent stream.
    progress
        Show a progress bar over the variables.

    Returns
    -------
    MotionVerdict

    References
    ----------
    L. Cao, A. Mees, K. Judd, "Dynamics from multivariate time series", Physica D 121,
    75–88 (1998); M. T. Rosenstein, J. J. Collins, C. J. De Luca, Physica D 65, 117 (1993);
    J. Guckenheimer, P. Holmes, *Nonlinear Oscillations, Dynamical Systems, and
    Bifurcations of Vector Fields*, Springer (1983) (stroboscopic maps).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import classify_motion, systems
    >>> t, s = systems.duffing(4000, gamma=0.5, samples_per_period=40)
    >>> phase = np.cos(1.2 * t)                      # the forcing, periodic by construction
    >>> data = np.column_stack([s[:, 0], phase])
    >>> mv = classify_motion(data, dt=t[1] - t[0], drive_period=2 * np.pi / 1.2, rng=0)
    >>> mv.label, mv.drive_variables
    ('chaotic', ('x2',))
    """
    rule = VerdictRule() if rule is None else rule
    if orbit is not None and not isinstance(orbit, PeriodicOrbitEvidence):
        raise ValueError(
            f"orbit must be a chaoskit.PeriodicOrbitEvidence or None; got {type(orbit).__name__}."
        )
    ds, names = series_dataset(
        _as_dataset(data, dt), variables=variables, phase_variable=phase_variable
    )
    known_drive = [str(n) for n in drive_variables]
    verdicts = classify_variables(
        ds,
        variables=names,
        drive_period=drive_period,
        phase_variable=phase_variable,
        n_surrogates=n_surrogates,
        rule=rule,
        rng=rng,
        progress=progress,
    )
    unknown = [n for n in known_drive if n not in verdicts]
    if unknown:
        raise ValueError(f"drive_variables {unknown} are not among the variables {list(verdicts)}.")
    say, say_text = _arbiter(exponent) if exponent is not None else (None, "")
    first = next(iter(verdicts.values()))
    kind = first.kind
    drive = [n for n, v in verdicts.items() if n in known_drive or _is_drive_follower(v)]
    constant = [n for n, v in verdicts.items() if v.label == "equilibrium" and n not in drive]
    failed = [n for n, v in verdicts.items() if "classify" in v.errors and n not in drive]
    voters = {n: v for n, v in verdicts.items() if n not in drive and n not in constant + failed}
    reasons: list[str] = []
    if drive:
        reasons.append(
            f"set aside as following the drive alone: {', '.join(drive)} (periodic with the "
            "drive by construction, no evidence against chaos)"
        )
    if constant:
        reasons.append(f"set aside as constant: {', '.join(constant)}")
    if failed:
        reasons.append(
            f"set aside, its analysis failed: {', '.join(failed)} "
            f"({'; '.join(verdicts[n].errors['classify'] for n in failed)})"
        )
    base: dict[str, Any] = {
        "variables": verdicts,
        "voting": tuple(voters),
        "drive_variables": tuple(drive),
        "constant_variables": tuple(constant),
        "kind": kind,
        "dt": float(first.dt),
        "n_samples": int(first.n_samples),
        "equations": exponent,
        "equations_say": say,
        "orbit": orbit,
        "orbit_says_periodic": orbit is not None and orbit.problem() is None,
        "rule": rule,
    }
    if not voters:
        if known_drive and len(known_drive) == len(verdicts):
            raise ValueError("every variable is listed in drive_variables; nothing votes.")
        if failed:
            reason = "no variable could be analysed: needs " + "; ".join(
                f"{n}: {verdicts[n].errors['classify']}" for n in failed
            )
            return MotionVerdict(
                label="undetermined", period=None, confidence=float("nan"), reason=reason,
                reasons=(reason, *reasons), needs=(reason,), votes={}, **base,
            )  # fmt: skip
        label: Label = "periodic" if drive else "equilibrium"
        reason = (
            "every variable follows the drive: the motion is periodic with the drive"
            if drive
            else "every variable is constant"
        )
        votes: dict[str, Vote] = {}
        if orbit is not None:
            votes["orbit"] = "supports" if base["orbit_says_periodic"] else "neutral"
            if orbit.problem() is not None:
                reasons.append(
                    f"the equations' periodic orbit (period {orbit.period}) is not evidence: "
                    f"{orbit.problem()}"
                )
        return MotionVerdict(
            label=label, period=1 if drive else None, confidence=1.0, reason=reason,
            reasons=(reason, *reasons), needs=(), votes=votes, **base,
        )  # fmt: skip
    ref = _reference(voters)
    ref_v = voters[ref]
    errors: dict[str, str] = {}
    structure = section = res = None
    positive: bool | None
    time_scale = ref_v.characteristic_time
    if len(voters) == 1:
        structure, section = ref_v.structure, ref_v.section
        res, positive = ref_v.rosenstein, ref_v.rosenstein_positive
    else:
        try:
            section, points = _joint_section(
                ds[[*voters, *([phase_variable] if phase_variable else [])]],
                voters,
                ref,
                kind=kind,
                drive_period=drive_period,
                phase_variable=phase_variable,
            )
            tol = rule.cluster_tol
            if kind != "map":
                noise = max(float(np.nan_to_num(v.noise_level)) for v in voters.values())
                noise = max(noise, float(section.attrs["interpolation_rms"]))
                tol = max(tol, min(rule.noise_factor * noise, rule.max_noise_allowance))
            structure = section_structure(
                points,
                scale=1.0,
                cluster_tol=tol,
                max_clusters=rule.max_period,
                min_points=rule.min_cycles,
            )
        except ValueError as exc:
            errors["section"] = str(exc)
        try:
            vectors, lag = mixed_embedding(ds, voters)
            res = lyapunov_rosenstein(vectors, dt=ref_v.dt, lag=lag)
        except Exception as exc:  # failure is data, as in classify
            errors["exponent"] = describe_error(exc)
        positive = None if res is None else clearly_positive(res, time_scale, rule)
    unit = {"map": "samples", "forced": "drive periods"}.get(kind, "oscillations (maxima)")
    # the joint section is read only where the sampling resolves it: its cluster allowance
    # (noise_factor × the interpolation uncertainty) must stay below its cap
    resolution = 0.0 if section is None else float(section.attrs.get("interpolation_rms", 0.0))
    limit = rule.max_noise_allowance / rule.noise_factor
    section_need = None
    if len(voters) > 1 and resolution > limit:
        section_need = (
            "finer sampling: the joint section falls between samples (cubic and linear "
            f"interpolation differ by {resolution:.2g} of each variable's spread; at most "
            f"{limit:.2g} resolves it)"
        )
        reasons.append(f"the joint section is not used: {section_need}")
    label, period, confidence, reason, votes, needs = combine_motion(
        voters,
        structure=None if section_need else structure,
        section_need=section_need,
        positive=positive,
        say=say,
        n_cycles=ref_v.n_cycles,
        cycle_unit=unit,
        rule=rule,
        orbit=orbit,
    )
    reasons.insert(0, reason)
    if orbit is not None and orbit.problem() is not None:
        reasons.append(
            f"the equations' periodic orbit (period {orbit.period}) is not evidence: "
            f"{orbit.problem()}"
        )
    for n, v in verdicts.items():
        conf = "" if math.isnan(v.confidence) else f" ({v.confidence:.2f})"
        reasons.append(f"{n}: {v.label}{conf} — {v.reason}")
    t_unit = "1/iteration" if kind == "map" else "1/s"
    if res is not None:
        reasons.append(
            f"the data say: joint exponent (Rosenstein, mixed embedding) λ₁ = {res.mle:.4g} "
            f"[{res.ci[0]:.4g}, {res.ci[1]:.4g}] {t_unit}, "
            + ("clearly positive" if positive else "not clearly positive")
        )
    for n, v in voters.items():
        if v.rosenstein is not None or v.wolf is not None:
            parts = [
                f"{name} {r.mle:.4g} [{r.ci[0]:.4g}, {r.ci[1]:.4g}]"
                for name, r in (("Rosenstein", v.rosenstein), ("Wolf", v.wolf))
                if r is not None
            ]
            reasons.append(f"the data say ({n}): {', '.join(parts)} {t_unit}")
    if say is None and say_text:
        reasons.append(say_text)
    if say is not None:
        reasons.append(say_text)
        data_chaotic = positive is True
        if (say == "chaotic") != data_chaotic or (
            label not in ("undetermined",) and votes.get("equations") == "opposes"
        ):
            reasons.append(
                f"the equations and the data disagree: the equations say {say}, the joint "
                "exponent of the data is "
                + ("clearly positive" if data_chaotic else "not clearly positive")
                + f", the motion verdict is {label}"
            )
    reasons.extend(f"joint {k} failed: {msg}" for k, msg in errors.items())
    return MotionVerdict(
        label=label,
        period=period,
        confidence=confidence,
        reason=reason,
        reasons=tuple(reasons),
        needs=needs,
        votes=votes,
        characteristic_time=float(time_scale),
        n_cycles=float(ref_v.n_cycles),
        structure=structure,
        section=section,
        exponent=res,
        exponent_positive=positive,
        errors=errors,
        **base,
    )
