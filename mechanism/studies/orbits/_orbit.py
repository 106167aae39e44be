"""``mechanism.periodic_orbit``: periodic orbits of a rigid scene through its impacts, by
Newton shooting on the stroboscopic map, with their Floquet multipliers."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from chaoskit.contract import check_int, check_positive
from mechanism.core import default_step, drive_period, step_limits
from mechanism.core.integrate import (
    Dopri5,
    clearance_kinematics,
    length_scale,
    section_latch,
)
from mechanism.core.model import assemble, initial_state
from mechanism.core.scene import MotorDrive, Scene

from ._modes import ContactPhase, contact_phases
from ._multiple import REFREEZE_ABOVE
from ._newton import NewtonState, image_section, multiple, newton, refresh, run_ok
from ._poincare import (
    MOTOR_SECTION_LIMITS,
    crank_section_orbit,
    no_load_turn,
    section_start,
)
from ._shooting import (
    Section,
    StroboscopicMap,
    frozen_latches,
    sorted_by_modulus,
)

__all__ = ["ContactPhase", "PeriodicOrbit", "periodic_orbit"]

#: default rtol = atol of the map: at the exponent's 1e-8 the largest multiplier of the
#: rigid paper scene's 30 rpm orbit is still off by a fifth (docs/periodic-orbits.md)
DEFAULT_TOLERANCE = 1e-10
#: default ε / L of the tangent runs' finite differences (the exponent's default)
DEFAULT_PERTURBATION = 1e-7
#: default shooting tolerance: residual / clearance; the round-off of a period of the rigid
#: paper scene (16 000 steps at rtol 1e-10) leaves map(x) − x at 1e-10 – 1e-9 of it
DEFAULT_SHOOTING_TOL = 1e-9
#: settling stops once one orbit period moves the section state by at most this share of
#: the clearance: where the shooting freezes its steps, so settling further only samples
#: the adaptive steps' noise (about 1e-6 of the clearance at the default tolerances)
SETTLED = REFREEZE_ABOVE
#: share of the clearance within which a trajectory's section states count as on the orbit
DEFAULT_APPROACH_TOLERANCE = 1e-3
#: the monodromy matrix is recomputed at the converged state when the state it was
#: computed at lies farther than this share of the clearance from it
MONODROMY_OFFSET = 1e-5
#: segments of the multiple shooting that follows a stalled single shooting
AUTOMATIC_SEGMENTS = 8
#: most segments accepted (each costs a tangent run per unknown and Newton iteration)
MAX_SEGMENTS = 64

#: The refusal of a motor-driven scene: its motion is autonomous (no prescribed period),
#: so a periodic orbit's period is an unknown, and the shooting here integrates over a
#: fixed number of drive periods.
MOTOR_REFUSAL = (
    "{caller} needs a periodic drive: a motor-driven crank moves autonomously, so a "
    "periodic orbit's period is an unknown, which shooting over fixed drive periods "
    "does not solve for; use a constant_speed drive at the speed the motor reaches."
)


@dataclass(frozen=True, kw_only=True)
class PeriodicOrbit:
    """A periodic orbit of a rigid scene driven at a prescribed crank speed.

    Attributes
    ----------
    scene_name : str
    period : int
        Drive periods per orbit period (k).
    drive_period : float
        T (s).
    section_state : numpy.ndarray
        [q; q̇] (SI; angles in rad) at t = 0 (mod kT), on the constraint manifold.
    section_latch : numpy.ndarray
        Latched impact velocity (m/s) of each clearance joint at the section.
    section_contact : numpy.ndarray
        1 for a clearance joint in contact at the section.
    section_eccentricity : numpy.ndarray
        (k, joints, 2): the journals' eccentricity (m) at the k section times jT.
    residual : float
        Size of map(section) − section over the clearance (mass-weighted state norm, as
        the exponent's, and τ × the latch differences that are unknowns); with multiple
        shooting the root sum of squares of the segments' continuity defects.
    iterations : int
        Newton iterations done.
    converged : bool
        ``residual`` <= ``tolerance``.
    tolerance : float
        Shooting tolerance (share of the clearance).
    multipliers : numpy.ndarray
        Floquet multipliers (complex, largest modulus first) of the non-neutral
        directions: eigenvalues of the monodromy matrix on the tangent space of the
        constraint manifold (2f coordinates, f the degrees of freedom) and of the latches
        that the orbit renews.
    neutral_multipliers : numpy.ndarray
        Multipliers of the neutral directions (complex; 1).
    neutral_directions : tuple of str
        What each neutral multiplier is: the latched impact velocity of a clearance joint
        that stays in contact the whole period (the model's memory of the last impact,
        which nothing renews; not a bifurcation).
    monodromy : numpy.ndarray
        The monodromy matrix (tangent coordinates, then τ × latches of the joints in
        contact at the section).
    monodromy_offset : float
        Distance (share of the clearance) between the state the multipliers were computed
        at and ``section_state`` (0: at it).
    phases : tuple of ContactPhase
        Contact modes along the orbit with the times they start.
    time, position, velocity : numpy.ndarray
        One orbit period from the section at the integrator's steps (the map's fixed
        step schedule): times (s), [q] and [q̇] per sample.
    eccentricity, penetration, in_contact : numpy.ndarray
        Per sample and clearance joint: eccentricity (m, x and y), penetration (m) and
        contact flag.
    dof_names, joint_names : tuple of str
    clearance : float
        Smallest radial clearance (m): the scale of ``residual``.
    settings : dict
        What the orbit depends on (tolerances, steps, perturbation, settling, shooting).
    cpu_time : float
        Process CPU time of the computation (s).
    function_evaluations : int
        Right-hand-side evaluations of all runs.
    shooting : str
        ``"single"`` (Newton on the k-fold map) or ``"multiple"`` (on the continuity
        defects of ``segments`` segments).
    segments : int
        Segments of the period used (1 for single shooting).
    floquet_vectors : numpy.ndarray
        (2n, multipliers) complex: column i is the eigenvector of ``multipliers[i]`` as a
        section-state difference [δq; δq̇] (SI; tangent to the constraint manifold), of
        unit size in the metric of the shooting's coordinates (positions in m, velocities
        × τ = T/2π; mass-weighted) with its largest component real and positive. A real
        multiplier has a real vector: ``section_state + h * floquet_vectors[:, i].real``
        (h in m) starts a branch switch, e.g. to the period-2 orbit at a period doubling
        (μ = −1).
    floquet_latch_vectors : numpy.ndarray
        (joints, multipliers) complex: the same eigenvectors' latched impact velocity
        parts (m/s per unit of the vector; 0 for joints separated at the section).
    section : str
        ``"time"``: the stroboscopic section t ≡ 0 (mod kT) of a prescribed drive.
        ``"crank angle"``: the Poincaré section of a motor-driven scene, the state each
        time the crank angle has turned 2πk from its value in ``section_state``; then
        ``period`` counts crank turns, ``drive_period`` is the time per turn found with
        the orbit (the orbit's period is ``period`` × ``drive_period``, s), the
        monodromy is the section map's (corrected for the return time) on the section's
        tangent coordinates (δφ = 0), and the trivial multiplier 1 along the flow is not
        among ``multipliers``.
    """

    scene_name: str
    period: int
    drive_period: float
    section_state: np.ndarray
    section_latch: np.ndarray
    section_contact: np.ndarray
    section_eccentricity: np.ndarray
    residual: float
    iterations: int
    converged: bool
    tolerance: float
    multipliers: np.ndarray
    neutral_multipliers: np.ndarray
    neutral_directions: tuple[str, ...]
    monodromy: np.ndarray
    monodromy_offset: float
    phases: tuple[ContactPhase, ...]
    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    eccentricity: np.ndarray
    penetration: np.ndarray
    in_contact: np.ndarray
    dof_names: tuple[str, ...]
    joint_names: tuple[str, ...]
    clearance: float
    settings: dict[str, Any] = field(default_factory=dict)
    cpu_time: float = 0.0
    function_evaluations: int = 0
    shooting: str = "single"
    segments: int = 1
    floquet_vectors: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), complex))
    floquet_latch_vectors: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), complex))
    section: str = "time"

    @property
    def stable(self) -> bool:
        """All non-neutral multipliers strictly inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    @property
    def largest_multiplier(self) -> complex:
        """The non-neutral multiplier of largest modulus."""
        return complex(self.multipliers[0])

    @property
    def exponent(self) -> float:
        """ln|μ_max| / (kT) (1/s): the largest Lyapunov exponent of the orbit without its
        neutral directions."""
        return math.log(abs(self.multipliers[0])) / (self.period * self.drive_period)

    def evidence(
        self,
        trajectory: xr.Dataset,
        *,
        sections: int = 5,
        tolerance: float = DEFAULT_APPROACH_TOLERANCE,
    ) -> Any:
        """How close a simulated trajectory comes to this orbit, for the motion verdict.

        Parameters
        ----------
        trajectory : xarray.Dataset
            A run of the same scene from :func:`mechanism.simulate` (``record="full"``,
            sampled at the section times jT, or ``"sections"`` at phase 0) holding
            ``eccentricity_x`` and ``eccentricity_y``.
        sections : int
            Last section states compared (≥ 1).
        tolerance : float
            ``approach`` at or below which the trajectory is on the orbit (share of the
            clearance, > 0; default 1e-3).

        Returns
        -------
        chaoskit.PeriodicOrbitEvidence
            ``approach``: the largest, over the trajectory's last ``sections`` section
            states, of the distance of the journals' eccentricity to the nearest of the
            orbit's k section eccentricities, over the clearance.

        Raises
        ------
        ValueError
            When the trajectory has no eccentricity, fewer section states than
            ``sections``, or joints other than the orbit's.
        """
        sections = check_int(sections, name="sections", minimum=1)
        tolerance = check_positive(tolerance, name="tolerance")
        points = _section_points(trajectory, self.drive_period, len(self.joint_names))
        if points.shape[0] < sections:
            raise ValueError(
                f"the trajectory has {points.shape[0]} section states (samples at "
                f"multiples of the drive period {self.drive_period:.6g} s); sections must "
                f"be at most that, got {sections}."
            )
        last = points[-sections:]
        gaps = np.linalg.norm(
            last[:, None, :, :] - self.section_eccentricity[None, :, :, :], axis=-1
        ).max(axis=-1)
        approach = float(gaps.min(axis=1).max() / self.clearance)
        return chaoskit.PeriodicOrbitEvidence(
            period=self.period,
            multipliers=np.asarray(self.multipliers, dtype=np.complex128),
            neutral_multipliers=np.asarray(self.neutral_multipliers, dtype=np.complex128),
            residual=float(self.residual),
            approach=approach,
            tolerance=float(tolerance),
        )

    def to_dataset(self) -> xr.Dataset:
        """One orbit period as a Dataset (units and long names), with the section state,
        the multipliers and the contact phases."""
        return _orbit_dataset(self)


def _section_points(ds: xr.Dataset, period: float, n_joints: int) -> np.ndarray:
    """(sections, joints, 2) eccentricities of a trajectory at its section times."""
    for name in ("eccentricity_x", "eccentricity_y"):
        if name not in ds:
            raise ValueError(
                f"the trajectory has no {name}: pass a simulate() run of a scene with "
                "clearance joints (record 'full' or 'sections')."
            )
    ex = np.asarray(ds["eccentricity_x"].values, dtype=np.float64)
    ey = np.asarray(ds["eccentricity_y"].values, dtype=np.float64)
    ex = ex.reshape(ex.shape[0], -1)
    ey = ey.reshape(ey.shape[0], -1)
    if ex.shape[1] != n_joints:
        raise ValueError(
            f"the trajectory has {ex.shape[1]} clearance joints; the orbit has {n_joints}."
        )
    if "crossing" in ds["eccentricity_x"].dims:
        rows = np.arange(ex.shape[0])
    else:
        t = np.asarray(ds["time"].values, dtype=np.float64)
        dt = float(np.median(np.diff(t))) if t.size > 1 else period
        phase = t / period
        rows = np.flatnonzero(np.abs(phase - np.round(phase)) * period < 0.5 * dt)
        rows = rows[np.round(phase[rows]) >= 1]
    return np.stack([ex[rows], ey[rows]], axis=-1)


def _orbit_dataset(orbit: PeriodicOrbit) -> xr.Dataset:
    n = len(orbit.dof_names)
    per = {"dims": ("time", "dof")}
    data = {
        "position": (per["dims"], orbit.position, {
            "units": "m or rad", "long_name": "coordinates along the orbit"}),
        "velocity": (per["dims"], orbit.velocity, {
            "units": "m s-1 or rad s-1", "long_name": "velocities along the orbit"}),
        "eccentricity_x": (("time", "joint"), orbit.eccentricity[:, :, 0], {
            "units": "m", "long_name": "journal centre minus bearing centre, x"}),
        "eccentricity_y": (("time", "joint"), orbit.eccentricity[:, :, 1], {
            "units": "m", "long_name": "journal centre minus bearing centre, y"}),
        "penetration": (("time", "joint"), orbit.penetration, {
            "units": "m", "long_name": "penetration of the journal into the bearing"}),
        "in_contact": (("time", "joint"), orbit.in_contact.astype(np.int8), {
            "units": "1", "long_name": "clearance joint in contact"}),
        "section_state": (("state",), orbit.section_state, {
            "units": "SI (m, rad, m s-1, rad s-1)",
            "long_name": "state [q; dq/dt] at the section (t = 0 mod the orbit period)"}),
        "section_latch": (("joint",), orbit.section_latch, {
            "units": "m s-1", "long_name": "latched impact velocity at the section"}),
        "multiplier_real": (("multiplier",), orbit.multipliers.real, {
            "units": "1", "long_name": "Floquet multiplier (non-neutral), real part"}),
        "multiplier_imag": (("multiplier",), orbit.multipliers.imag, {
            "units": "1", "long_name": "Floquet multiplier (non-neutral), imaginary part"}),
        "multiplier_modulus": (("multiplier",), np.abs(orbit.multipliers), {
            "units": "1", "long_name": "modulus of the Floquet multiplier"}),
        "floquet_vector_real": (("state", "multiplier"), orbit.floquet_vectors.real, {
            "units": "SI (m, rad, m s-1, rad s-1) per unit size",
            "long_name": "Floquet vector of the multiplier at the section, real part"}),
        "floquet_vector_imag": (("state", "multiplier"), orbit.floquet_vectors.imag, {
            "units": "SI (m, rad, m s-1, rad s-1) per unit size",
            "long_name": "Floquet vector of the multiplier at the section, imaginary part"}),
        "neutral_multiplier": (("neutral",), orbit.neutral_multipliers.real, {
            "units": "1", "long_name": "multiplier of a neutral latch direction"}),
        "phase_start": (("phase",), np.array([p.start for p in orbit.phases]), {
            "units": "s", "long_name": "start of the contact phase from the section"}),
    }  # fmt: skip
    coords = {
        "time": ("time", orbit.time, {"units": "s", "long_name": "time from the section"}),
        "dof": ("dof", list(orbit.dof_names)),
        "joint": ("joint", list(orbit.joint_names)),
        "state": (
            "state",
            [f"q.{d}" for d in orbit.dof_names] + [f"v.{d}" for d in orbit.dof_names],
        ),
        "phase_mode": ("phase", [p.mode for p in orbit.phases]),
        "phase_joint": ("phase", [p.joint for p in orbit.phases]),
        "neutral_direction": ("neutral", list(orbit.neutral_directions)),
    }
    attrs: dict[str, Any] = {
        "scene_name": orbit.scene_name,
        "period": orbit.period,
        "drive_period": orbit.drive_period,
        "drive_period_units": "s",
        "residual": orbit.residual,
        "residual_units": "share of the clearance",
        "iterations": orbit.iterations,
        "converged": int(orbit.converged),
        "tolerance": orbit.tolerance,
        "stable": int(orbit.stable),
        "exponent": orbit.exponent,
        "exponent_units": "s-1",
        "clearance": orbit.clearance,
        "clearance_units": "m",
        "monodromy_offset": orbit.monodromy_offset,
        "cpu_time": orbit.cpu_time,
        "function_evaluations": orbit.function_evaluations,
        "coordinates": n,
    }
    for key, value in orbit.settings.items():
        attrs[f"setting_{key}"] = value
    return xr.Dataset(data, coords=coords, attrs=attrs)


def periodic_orbit(
    scene: Scene,
    *,
    period: int = 1,
    guess: PeriodicOrbit | np.ndarray | None = None,
    tol: float = DEFAULT_SHOOTING_TOL,
    max_iterations: int = 20,
    settle: int = 10,
    search: int = 0,
    rtol: float | None = None,
    atol: float | None = None,
    max_step: float | None = None,
    perturbation: float = DEFAULT_PERTURBATION,
    segments: int | None = None,
) -> PeriodicOrbit:
    r"""Periodic orbit of a rigid scene through its impacts, and its Floquet multipliers.

    Newton shooting on the k-fold stroboscopic map P: the state on the constraint
    manifold at t ≡ 0 (mod T, the drive period) and the latched impact velocities of the
    clearance joints in contact, taken to t = kT by the compiled Dormand–Prince
    integrator (the reference of :func:`mechanism.lyapunov_exponent`, at its default
    tolerances). The unknowns are the coordinates of the manifold's tangent space (2f,
    f = coordinates − constraint equations: for a scene whose clearance joints are its
    only freedom, their journals' relative positions and velocities) and the latches
    the orbit renews. The monodromy matrix ∂P is carried by one tangent deviation per
    unknown along the same steps (not renormalised over the period), with the contact,
    friction-ramp and latch rules of the exponent. Each Newton step solves
    (∂P − I) δz = −(P(z) − z) and is halved until the residual drops (damped Newton), so
    unstable orbits converge as well as stable ones; the matrix is reused while the
    residual falls at least fourfold per iteration and recomputed at the converged
    state when it was computed farther than 1e-5 of the clearance from it.
    Before the first matrix the map itself is iterated while each iteration cuts the
    residual tenfold, so a strongly attracting orbit needs one matrix, at the converged
    state (its run, recorded, is the orbit's record). Above 1e-5 of the clearance every
    run takes its own adaptive steps; below it the steps of a run from the current state
    are frozen, so the map is smooth.

    A latch that the orbit never renews (the journal stays in contact the whole period)
    is frozen: its multiplier is exactly 1 with the latch as eigenvector. It is held at
    its starting value, reported in ``neutral_multipliers`` and ``neutral_directions``,
    and left out of ``multipliers`` and ``stable``.

    Parameters
    ----------
    scene : mechanism.scene.Scene
        A rigid scene (``effects.flexibility = false`` for the paper scene) with a
        periodic drive (constant crank speed), or driven by a motor: then the map is the
        Poincaré section of the crank angle (its return after ``period`` crank turns,
        the return time an unknown; ``settle`` counts crank turns; single shooting only),
        and the result's ``section`` is ``"crank angle"`` (docs/periodic-orbits.md,
        *Sections for motor drives*).
    period : int
        Drive periods per orbit period k (≥ 1).
    guess : PeriodicOrbit or numpy.ndarray, optional
        Starting section state: an orbit (its state and latch; e.g. of a nearby speed) or
        a state [q; q̇] at t ≡ 0 (mod T) (journals in contact then start from the latch
        floor). Default: the state of a run from the scene's initial state after
        ``settle`` periods (or the closest k-return among the next ``search``).
    tol : float
        Shooting tolerance: residual / clearance (> 0; default 1e-9, just above the
        round-off floor of the map, docs/periodic-orbits.md).
    max_iterations : int
        Newton iterations at most (≥ 1).
    settle : int
        Most periods run before the guess is taken (≥ 0; ``guess=None`` only), in whole
        orbit periods: settling stops once one orbit period moves the section state by
        at most 1e-5 of the clearance (where the shooting freezes its steps), so a
        settled motion costs no more periods. With ``search`` > k or ``segments`` > 1 all
        are run.
    search : int
        With ``guess=None`` and ``search`` > k: after settling, the section state of the
        next ``search`` periods that returns closest to itself after k periods is the
        guess (the usual start for an unstable orbit inside a chaotic motion).
    rtol, atol : float, optional
        Tolerances of the map (default 1e-8, as the exponent).
    max_step : float, optional
        Largest step (s); default the step limits of :func:`mechanism.simulate`.
    perturbation : float
        ε / clearance of the tangent runs' finite differences, in (0, 1e-4].
    segments : int, optional
        Multiple shooting over this many segments of the orbit period (in [1, 64]; 1:
        single shooting only). Default: single shooting, then, when it stalls above
        ``tol``, multiple shooting over 8 segments from its best state: the states at
        the segment starts are the unknowns and the continuity defects the residuals,
        so an unstable impacting orbit (one-period growth of hundreds) converges.

    Returns
    -------
    PeriodicOrbit
        ``converged`` False when ``max_iterations`` ran out or no damped step reduced
        the residual (the last state and its multipliers are returned).

    Raises
    ------
    ValueError
        On bad arguments, a flexible scene, a scene without a periodic drive or without
        a degree of freedom.
    SimulationError
        When an integration fails.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper").replace(
    ...     {"effects.flexibility": False, "drive.speed_rpm": 30.0})
    >>> orbit = mechanism.periodic_orbit(scene)  # doctest: +SKIP
    >>> orbit.converged, orbit.stable  # doctest: +SKIP
    (True, True)
    """
    cpu0 = time.process_time()
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    period = check_int(period, name="period", minimum=1)
    tol = check_positive(tol, name="tol")
    max_iterations = check_int(max_iterations, name="max_iterations", minimum=1)
    settle = check_int(settle, name="settle", minimum=0)
    search = check_int(search, name="search", minimum=0)
    if segments is not None:
        segments = check_int(segments, name="segments", minimum=1, maximum=MAX_SEGMENTS)
    perturbation = check_positive(perturbation, name="perturbation")
    if perturbation > 1e-4:
        raise ValueError(f"perturbation must be in (0, 1e-4]; got {perturbation!r}.")
    motor = isinstance(scene.drive, MotorDrive)
    if motor and (search or segments not in (None, 1)):
        raise ValueError(MOTOR_SECTION_LIMITS)
    big_t = no_load_turn(scene) if motor else drive_period(scene)
    if big_t is None:
        raise ValueError(
            "periodic_orbit needs a periodic drive (a constant crank speed); the scene "
            f"{scene.name!r} has none."
        )
    model = assemble(scene)
    if model.beams:
        raise ValueError(
            "periodic_orbit needs a rigid scene; set effects.flexibility = false (flexible "
            "bodies are integrated with generalized-alpha, which has no shooting here)."
        )
    rtol = check_positive(DEFAULT_TOLERANCE if rtol is None else rtol, name="rtol")
    atol = check_positive(DEFAULT_TOLERANCE if atol is None else atol, name="atol")
    if max_step is None:
        max_step, floor = step_limits(model, Dopri5(), default_step(scene, big_t))
    else:
        max_step, floor = check_positive(max_step, name="max_step"), 0.0
    q0, v0 = initial_state(model)
    y_init = np.concatenate([q0, v0])
    clearance = length_scale(model, y_init)
    if motor:
        # a Poincaré section on the crank angle: the period is an unknown
        start = _motor_start(model, y_init, guess)
        smap, solved = crank_section_orbit(
            model, start, turns=period, settle=settle if guess is None else 0, tol=tol,
            max_iterations=max_iterations,
            map_settings={"rtol": rtol, "atol": atol, "max_step": max_step,
                          "approach_floor": floor, "perturbation": perturbation,
                          "clearance": clearance},
        )  # fmt: skip
        return _assemble_orbit(
            smap, scene, solved, tol, cpu0,
            {"rtol": rtol, "atol": atol, "max_step": max_step, "approach_floor": floor,
             "perturbation": perturbation, "settle": settle, "search": search,
             "guess": "given" if guess is not None else "settled", "shooting": "single",
             "segments": 1, "section": "crank angle"},
        )  # fmt: skip
    smap = StroboscopicMap(
        model, drive_period=big_t, period=period, rtol=rtol, atol=atol, max_step=max_step,
        approach_floor=floor, perturbation=perturbation, clearance=clearance,
    )  # fmt: skip
    # multiple shooting from scratch starts from all the settling periods: from the state
    # settling stops at (up to 1e-5 of the clearance off) it freezes its segments' steps
    # too far from the orbit and stalls (1.2e-8 against 3.4e-9 at 30 rpm)
    early = segments in (None, 1)
    start, first_image = _start(smap, y_init, guess, settle, search, early=early)
    shooting, used = "single", 1
    solved = None
    if segments in (None, 1):
        solved = newton(smap, start, tol, max_iterations, end=first_image)
    if segments not in (None, 1) or (segments is None and solved.residual > tol):
        used = AUTOMATIC_SEGMENTS if segments is None else segments
        solved = multiple(
            smap,
            solved.section if solved else start,
            used,
            tol,
            max_iterations,
            solved.iterations if solved else 0,
        )
        shooting = "multiple"
    return _assemble_orbit(
        smap, scene, solved, tol, cpu0,
        {"rtol": rtol, "atol": atol, "max_step": max_step, "approach_floor": floor,
         "perturbation": perturbation, "settle": settle, "search": search,
         "guess": "given" if guess is not None else "settled", "shooting": shooting,
         "segments": used},
    )  # fmt: skip


def _start(
    smap: StroboscopicMap,
    y_init: np.ndarray,
    guess: PeriodicOrbit | np.ndarray | None,
    settle: int,
    search: int,
    *,
    early: bool = True,
) -> tuple[Section, Any]:
    """The first section state (from ``guess``, else after settling: the closest return,
    or with ``early`` :func:`_settled`) and the map's run from it when settling made one
    (else None)."""
    model = smap.model
    if isinstance(guess, PeriodicOrbit):
        if guess.section_state.shape != y_init.shape:
            raise ValueError("guess is an orbit of a scene with other coordinates.")
        latch, contact = section_latch(model, guess.section_state, guess.section_latch)
        return Section(y=guess.section_state.copy(), latch=latch, contact=contact), None
    if guess is not None:
        y = np.asarray(guess, dtype=np.float64)
        if y.shape != y_init.shape or not np.all(np.isfinite(y)):
            raise ValueError(
                f"guess must be a finite state [q; dq/dt] of {y_init.size} values "
                f"(or a PeriodicOrbit); got shape {y.shape}."
            )
        latch, contact = section_latch(model, y)
        return Section(y=y.copy(), latch=latch, contact=contact), None
    latch0, contact0 = section_latch(model, y_init)
    first = Section(y=y_init, latch=latch0, contact=contact0)
    k = smap.period
    if search <= k and early:
        return _settled(smap, first, settle)
    total = settle + (search if search > k else 0)
    if total == 0:
        return first, None
    run = run_ok(
        smap, first, smap.drive_period * np.arange(total + 1, dtype=np.float64), record=True
    )
    pick = settle
    if search > k:
        gaps = [
            smap.distance(run.states[i + k], run.states[i]) for i in range(settle, total - k + 1)
        ]
        pick = settle + int(np.argmin(gaps))
    y = run.states[pick].copy()
    # the same phase of the drive at t = 0: angles back by whole turns
    turns = np.round((y - y_init)[smap.angles] / (2.0 * math.pi))
    y[smap.angles] -= 2.0 * math.pi * turns
    sec = Section(y=y, latch=run.latches[pick].copy(), contact=run.contact[pick].copy())
    return sec, None


def _settled(smap: StroboscopicMap, first: Section, settle: int) -> tuple[Section, Any]:
    """Iterate the map from ``first`` for up to ``settle`` periods (whole orbit periods),
    stopping once an iteration moves the section state by at most ``SETTLED`` of the
    clearance; returns the last state and the map's run from it (None when none was
    made)."""
    sec, end = first, None
    for _ in range(-(-settle // smap.period)):
        if end is not None:
            sec = image_section(smap, end)
        end = run_ok(smap, sec, smap.stops)
        if smap.residual(sec, end, sec.contact != 0) <= SETTLED:
            break
    if end is not None and smap.residual(sec, end, sec.contact != 0) > SETTLED:
        # settled for ``settle`` periods: the guess is the last image
        sec, end = image_section(smap, end), None
    return sec, end


def _motor_start(
    model: Any, y_init: np.ndarray, guess: PeriodicOrbit | np.ndarray | None
) -> Section:
    """The first crank-angle section state of a motor-driven scene: from ``guess``, else
    the scene's initial state (settled by the caller)."""
    if isinstance(guess, PeriodicOrbit):
        if guess.section_state.shape != y_init.shape:
            raise ValueError("guess is an orbit of a scene with other coordinates.")
        return section_start(model, guess.section_state, guess.section_latch)
    if guess is None:
        return section_start(model, y_init)
    y = np.asarray(guess, dtype=np.float64)
    if y.shape != y_init.shape or not np.all(np.isfinite(y)):
        raise ValueError(
            f"guess must be a finite state [q; dq/dt] of {y_init.size} values "
            f"(or a PeriodicOrbit); got shape {y.shape}."
        )
    return section_start(model, y)


def _multipliers(
    jac: np.ndarray, n_free: int, latches: np.ndarray, joints: tuple[str, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[str, ...]]:
    """(non-neutral multipliers, their eigenvectors in the monodromy's coordinates (one
    column each, zero on the frozen latches), neutral multipliers, what each neutral one
    is)."""
    frozen = frozen_latches(jac, n_free)
    keep = np.setdiff1d(np.arange(jac.shape[0]), n_free + frozen)
    values, vectors = np.linalg.eig(jac[np.ix_(keep, keep)])
    order = np.argsort(-np.abs(values), kind="stable")
    full = np.zeros((jac.shape[0], order.size), dtype=np.complex128)
    full[keep] = vectors[:, order]
    neutral = np.array([jac[n_free + f, n_free + f] for f in frozen], dtype=np.complex128)
    what = tuple(
        f"latched impact velocity of clearance joint {joints[latches[f]]!r}: in contact the "
        "whole period, nothing renews it (the model's memory of the last impact)"
        for f in frozen
    )
    return sorted_by_modulus(values[order]), full, neutral, what


def _floquet_vectors(
    smap: StroboscopicMap, state: NewtonState, vectors: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvectors of the monodromy's coordinates as section-state differences
    [δq; δq̇] (SI) and latch differences (m/s per joint), each of unit size in the tangent
    coordinates' metric (positions in m, velocities × τ) with its largest state component
    real and positive."""
    basis = smap.basis(state.jacobian_at)
    n_free = state.n_free
    states = basis[:, :n_free] @ vectors[:n_free]
    latch = np.zeros((state.jacobian_at.latch.size, vectors.shape[1]), dtype=np.complex128)
    latch[state.latches] = vectors[n_free:] / smap.tau
    for i in range(vectors.shape[1]):
        norm = float(np.linalg.norm(vectors[:, i]))
        big = states[np.argmax(np.abs(states[:, i])), i]
        turn = big / abs(big) if abs(big) > 0.0 else 1.0
        states[:, i] /= norm * turn
        latch[:, i] /= norm * turn
    return states, latch


def _assemble_orbit(
    smap: StroboscopicMap,
    scene: Scene,
    state: NewtonState,
    tol: float,
    cpu0: float,
    settings: dict[str, Any],
) -> PeriodicOrbit:
    model = smap.model
    sec = state.section
    if smap.schedule is None:
        # not converged to where the steps are frozen: the recording's own steps
        smap.freeze_steps(sec, smap.basis(sec))
    # the orbit on the map's own steps: it ends at the section state to the residual (and
    # serves the monodromy matrix as the map's run from the section)
    rec = smap.recorded_image(sec)
    if state.jacobian is None or smap.distance(state.jacobian_at.y, sec.y) > MONODROMY_OFFSET:
        refresh(smap, state, rec)
    offset = smap.distance(state.jacobian_at.y, sec.y)
    joints = tuple(model.clearance_joints)
    mult, vectors, neutral, what = _multipliers(state.jacobian, state.n_free, state.latches, joints)
    floquet, floquet_latch = _floquet_vectors(smap, state, vectors)
    k, big_t = smap.period, smap.drive_period
    n = model.n_dof
    kin = clearance_kinematics(model, rec.states, t=rec.t, latch=rec.latches)
    strobe = kin[np.searchsorted(rec.t, smap.sections[:-1])]
    phases = contact_phases(rec.t, rec.contact, rec.contact_events, joints, big_t)
    return PeriodicOrbit(
        scene_name=scene.name,
        period=k,
        drive_period=big_t,
        section_state=sec.y,
        section_latch=sec.latch,
        section_contact=sec.contact,
        section_eccentricity=strobe[:, :, :2],
        residual=float(state.residual),
        iterations=state.iterations,
        converged=bool(state.residual <= tol),
        tolerance=tol,
        multipliers=mult,
        neutral_multipliers=neutral,
        neutral_directions=what,
        monodromy=state.jacobian,
        monodromy_offset=float(offset),
        shooting=str(settings["shooting"]),
        segments=int(settings["segments"]),
        floquet_vectors=floquet,
        floquet_latch_vectors=floquet_latch,
        section=str(settings.get("section", "time")),
        phases=phases,
        time=rec.t,
        position=rec.states[:, :n],
        velocity=rec.states[:, n:],
        eccentricity=kin[:, :, :2],
        penetration=kin[:, :, 2],
        in_contact=rec.contact,
        dof_names=tuple(model.dof_names),
        joint_names=joints,
        clearance=smap.clearance,
        settings=settings,
        cpu_time=time.process_time() - cpu0,
        function_evaluations=smap.function_evaluations,
    )
