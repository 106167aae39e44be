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
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from .._io import load_trajectory
from .._tables import has_time_index
from ..lyapunov import lyapunov_rosenstein
from ._analyze import classify_variables, series_dataset
from ._evidence import clearly_positive, describe_error
from ._motion_arbiters import equations_arbiter
from ._motion_combine import combine_motion
from ._motion_evidence import (
    is_drive_follower,
    joint_section,
    mixed_embedding,
    reference_variable,
)
from ._motion_result import MotionVerdict
from ._orbit import PeriodicOrbitEvidence
from ._rule import Label, VerdictRule, Vote
from ._section_structure import section_structure

__all__ = ["MotionVerdict", "classify_motion"]

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
      clusters or a closed curve) or the equations do, and the joint evidence does not
      decide it — then *undetermined*;
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
    # the only random draws of the motion verdict: those of each variable's verdict
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
    say, say_text = equations_arbiter(exponent) if exponent is not None else (None, "")
    first = next(iter(verdicts.values()))
    kind = first.kind
    drive, constant, failed, voters, reasons = _set_aside(verdicts, known_drive)
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
        return _without_voters(verdicts, known_drive, drive, failed, reasons, orbit, base)
    ref = reference_variable(voters)
    ref_v = voters[ref]
    errors: dict[str, str] = {}
    time_scale = ref_v.characteristic_time
    if len(voters) == 1:
        structure, section = ref_v.structure, ref_v.section
        res, positive = ref_v.rosenstein, ref_v.rosenstein_positive
    else:
        structure, section, res, positive = _joint_evidence(
            ds, voters, ref, kind, drive_period, phase_variable, rule, errors
        )
    unit = {"map": "samples", "forced": "drive periods"}.get(kind, "oscillations (maxima)")
    section_need = _section_need(section, voters, rule, reasons)
    outcome = combine_motion(
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
    reasons.insert(0, outcome.reason)
    _add_evidence_reasons(reasons, verdicts, voters, orbit, kind, res, positive)
    if say is None and say_text:
        reasons.append(say_text)
    if say is not None:
        reasons.append(say_text)
        data_chaotic = positive is True
        if (say == "chaotic") != data_chaotic or (
            outcome.label != "undetermined" and outcome.votes.get("equations") == "opposes"
        ):
            reasons.append(
                f"the equations and the data disagree: the equations say {say}, the joint "
                "exponent of the data is "
                + ("clearly positive" if data_chaotic else "not clearly positive")
                + f", the motion verdict is {outcome.label}"
            )
    reasons.extend(f"joint {k} failed: {msg}" for k, msg in errors.items())
    return MotionVerdict(
        label=outcome.label,
        period=outcome.period,
        confidence=outcome.confidence,
        reason=outcome.reason,
        reasons=tuple(reasons),
        needs=outcome.needs,
        votes=outcome.votes,
        characteristic_time=float(time_scale),
        n_cycles=float(ref_v.n_cycles),
        structure=structure,
        section=section,
        exponent=res,
        exponent_positive=positive,
        errors=errors,
        **base,
    )


# --- the steps of the pipeline, in the order classify_motion calls them -------------------


def _set_aside(
    verdicts: dict[str, Any], known_drive: list[str]
) -> tuple[list[str], list[str], list[str], dict[str, Any], list[str]]:
    """The variables that follow the drive, are constant or failed, those left to vote,
    and the reasons naming what was set aside."""
    drive = [n for n, v in verdicts.items() if n in known_drive or is_drive_follower(v)]
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
    return drive, constant, failed, voters, reasons


def _without_voters(
    verdicts: dict[str, Any],
    known_drive: list[str],
    drive: list[str],
    failed: list[str],
    reasons: list[str],
    orbit: PeriodicOrbitEvidence | None,
    base: dict[str, Any],
) -> MotionVerdict:
    """The verdict when no variable votes: every one follows the drive, is constant or
    failed."""
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


def _joint_evidence(
    ds: xr.Dataset,
    voters: dict[str, Any],
    ref: str,
    kind: str,
    drive_period: float | None,
    phase_variable: str | None,
    rule: VerdictRule,
    errors: dict[str, str],
) -> tuple[Any, Any, Any, bool | None]:
    """The joint section of the voting variables with its structure, and the exponent of
    their mixed embedding with whether it is clearly positive; what fails is recorded in
    ``errors`` and left None."""
    structure = section = res = None
    time_scale = voters[ref].characteristic_time
    try:
        section, points = joint_section(
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
        res = lyapunov_rosenstein(vectors, dt=voters[ref].dt, lag=lag)
    except Exception as exc:  # failure is data, as in classify
        errors["exponent"] = describe_error(exc)
    positive = None if res is None else clearly_positive(res, time_scale, rule)
    return structure, section, res, positive


def _section_need(
    section: Any, voters: dict[str, Any], rule: VerdictRule, reasons: list[str]
) -> str | None:
    """What the joint section needs before it is read (None: it can be read); the need is
    added to ``reasons``."""
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
    return section_need


def _add_evidence_reasons(
    reasons: list[str],
    verdicts: dict[str, Any],
    voters: dict[str, Any],
    orbit: PeriodicOrbitEvidence | None,
    kind: str,
    res: Any,
    positive: bool | None,
) -> None:
    """Append the evidence behind the verdict to ``reasons``: an orbit that is not
    evidence, each variable's verdict, the joint and each voter's exponents."""
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
