"""The result of :func:`chaoskit.classify_motion`: :class:`MotionVerdict` and its fields."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from .._contract import stamp
from ._motion_arbiters import Arbiter, arbiter_values
from ._orbit import PeriodicOrbitEvidence
from ._result import Verdict
from ._rule import LABELS, Label, VerdictRule, Vote
from ._section_structure import SectionStructure
from ._table import stack_verdicts

__all__ = ["MotionVerdict"]


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
        eq = arbiter_values(self.equations) if self.equations is not None else (nan,) * 3
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
            if key in MOTION_STRINGS:
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
MOTION_STRINGS = ("motion_label", "motion_section_structure", "motion_needs")
