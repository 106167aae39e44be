"""Integrators as strategy objects.

Each integrator takes an assembled :class:`~mechanism.core.model._assemble.Model`, a consistent
initial state and a uniform output grid, and returns an :class:`Integration`: the raw
output arrays (``Recording``) and :class:`SolverStats`.

* :class:`Dopri5` — Dormand–Prince 5(4) with dense output, the whole time loop compiled
  (the MATLAB ``ode45`` scheme; default).
* :class:`ScipyIVP` — scipy's ``RK45``, ``DOP853``, ``Radau``, ``BDF``, ``LSODA`` stepping
  the compiled right-hand side from Python (one Python callback per evaluation: slower;
  a cross-check).
* :class:`GeneralizedAlpha` — implicit generalized-α (Chung & Hulbert 1993) with Newton
  iterations on a hybrid (finite-difference + analytic ANCF) Jacobian whose clearance-contact
  columns are re-linearised at every iterate (semi-smooth Newton), and step rejection on
  deep contact entry, for stiff contact and  stiff axial modes.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

import numpy as np

from mechanism.core._status import (
    MESSAGES,
    STATUS_MAX_STEPS,
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.joints import ANGLE_RIGID, ANGLE_SLOPE, POINT_LINEAR, POINT_RIGID
from mechanism.core.model import kernels as k

from . import _dopri_kernels as dk
from . import _genalpha_kernels as gk
from . import _step_kernels as sk
from . import _tangent_kernels as tk

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = [
    "METHODS",
    "Dopri5",
    "GeneralizedAlpha",
    "Integration",
    "Integrator",
    "RecordPlan",
    "Recording",
    "ScipyIVP",
    "SolverStats",
    "interrupt_integrations",
    "resolve_method",
]

ScipyMethodName = Literal["RK45", "DOP853", "Radau", "BDF", "LSODA"]

_MESSAGES = MESSAGES

#: attempted steps of a compiled loop per call before control returns to Python, where a
#: pending Ctrl-C is raised: well under a second of work on the scenes of the package
#: (docs/simulator.md, *Interrupting a run*); the results do not depend on it
CHUNK_STEPS = {"dopri5": 5_000, "generalized-alpha": 1_000, "tangent": 2_000}

#: share of its gap to the bearing wall a separated journal may travel in one step (at
#: its current speed and acceleration); the approach floor bounds the last steps before
#: contact, so the value sets the cost of the approach, not how an impact is entered
APPROACH_FRACTION = 1.0


class Recording(NamedTuple):
    """Raw output arrays on the output grid (filled by the compiled loops)."""

    t: np.ndarray  # (N,)
    q: np.ndarray  # (N, n) positions
    v: np.ndarray  # (N, n) velocities
    a: np.ndarray  # (N, n) accelerations
    lam: np.ndarray  # (N, m) Lagrange multipliers
    cj: np.ndarray  # (N, n_cj, CJ_COLUMNS) clearance-joint kinematics and forces
    out: np.ndarray  # (N, OUT_COLUMNS) crank angle, slider s/ṡ/s̈, energy, max|Φ|
    jf: np.ndarray  # (N, n_ideal_joints, 2) reaction force on each ideal joint's bodies[1]

    @classmethod
    def empty(cls, model: Model, n_out: int) -> Recording:
        n = model.n_dof
        return cls(
            t=np.zeros(n_out),
            q=np.zeros((n_out, n)),
            v=np.zeros((n_out, n)),
            a=np.zeros((n_out, n)),
            lam=np.zeros((n_out, model.n_rows)),
            cj=np.zeros((n_out, model.kernel.cj_i.shape[0], k.CJ_COLUMNS)),
            out=np.zeros((n_out, k.OUT_COLUMNS)),
            jf=np.zeros((n_out, model.kernel.jt_i.shape[0], 2)),
        )

    def head(self, count: int) -> Recording:
        """The first ``count`` samples."""
        return Recording(*(a[:count] for a in self))


@dataclass(frozen=True, kw_only=True)
class SolverStats:
    """What an integration cost and whether it succeeded.

    Attributes
    ----------
    method : str
        Integrator name.
    status : int
        0 success; negative: failure (see ``message``).
    message : str
    steps, rejected_steps, function_evaluations, jacobian_evaluations, newton_iterations
        Solver work (right-hand-side evaluations made only to record outputs are not
        counted).
    contact_events : int
        Transitions separated → contact of any clearance joint among accepted states.
    contact_evaluations : int
        Calls of the contact law made by the solver.
    wall_time : float
        Seconds spent in the integrator.
    """

    method: str
    status: int
    message: str
    steps: int = 0
    rejected_steps: int = 0
    function_evaluations: int = 0
    jacobian_evaluations: int = 0
    newton_iterations: int = 0
    contact_events: int = 0
    contact_evaluations: int = 0
    wall_time: float = 0.0

    @property
    def success(self) -> bool:
        return self.status == 0

    def as_attrs(self, prefix: str = "solver_") -> dict[str, Any]:
        """Flat attributes for a Dataset (``solver_steps``, ...)."""
        return {
            f"{prefix}method": self.method,
            f"{prefix}status": int(self.status),
            f"{prefix}message": self.message,
            f"{prefix}steps": int(self.steps),
            f"{prefix}rejected_steps": int(self.rejected_steps),
            f"{prefix}function_evaluations": int(self.function_evaluations),
            f"{prefix}jacobian_evaluations": int(self.jacobian_evaluations),
            f"{prefix}newton_iterations": int(self.newton_iterations),
            f"{prefix}contact_events": int(self.contact_events),
            f"{prefix}contact_evaluations": int(self.contact_evaluations),
            f"{prefix}wall_time": float(self.wall_time),
        }


@dataclass(frozen=True, kw_only=True)
class RecordPlan:
    """What an integration records besides its statistics.

    Parameters
    ----------
    grid : {"full", "light"}
        On the output grid: full samples (state, accelerations, multipliers, contact
        quantities and derived outputs; one right-hand-side evaluation each) or light
        samples (crank angle, slider position and velocity from the dense output alone).
    sections : int
        Capacity of the stroboscopic recording (0: none): a full sample wherever the
        crank angle passes ``phase`` + 2πk, located on the integrator's dense output.
    phase : float
        Strobe phase (rad).
    discard : float
        Crank revolutions from the start before the first section.
    metrics_from : float or None
        Time (s) from which running extremes (peak contact force, deepest penetration,
        driving torque) are taken at every accepted state; None: none.
    peak_step : float
        A step during which a clearance joint touches is also evaluated at interior
        points of its dense output no farther apart than this (at most 7), since an
        impact peaks between accepted states (s; default: every such step, 7 points).
    """

    grid: Literal["full", "light"] = "full"
    sections: int = 0
    phase: float = 0.0
    discard: float = 0.0
    metrics_from: float | None = None
    peak_step: float = 0.0


FULL = RecordPlan()


@dataclass(frozen=True, kw_only=True)
class Integration:
    """Result of an integrator run: the recorded samples (possibly fewer than requested
    when the run failed) and the statistics.

    ``recording`` holds the full grid samples (empty with a light plan), ``light`` the
    light grid samples (N, 3 + 2 × clearance joints: crank angle, slider s, ṡ, then e_x,
    e_y of each clearance joint), ``sections`` the section samples
    and ``metrics`` the running extremes (``mechanism.core.integrate.kernels.MET_*``).
    ``final_step`` is the step size (s) the integrator would have tried next (NaN when
    not known) and ``final_contact`` the clearance joints in contact at ``final_time``
    (one flag per joint of ``Model.clearance_joints``), so that a failure can say what
    held the step down."""

    recording: Recording
    stats: SolverStats
    final_state: np.ndarray
    final_time: float = math.nan
    light: np.ndarray | None = None
    sections: Recording | None = None
    metrics: np.ndarray | None = None
    final_step: float = math.nan
    final_contact: np.ndarray | None = None


def _output(
    model: Model, ws: Any, y0: np.ndarray, vimp: np.ndarray, t_out: np.ndarray, plan: RecordPlan
) -> sk.Output:
    """The kernels' Output tuple for ``plan``, with the first grid sample (and a section
    at the start when the initial crank angle is a strobe angle) recorded."""
    full = plan.grid == "full"
    mode = sk.REC_FULL if full else sk.REC_LIGHT
    if plan.sections:
        mode |= sk.REC_SECTIONS
    if plan.metrics_from is not None:
        mode |= sk.REC_METRICS
    light = np.zeros((0 if full else t_out.size, k.LIGHT_COLUMNS + 2 * model.kernel.cj_i.shape[0]))
    strobe = np.zeros(sk.STROBE_COLUMNS)
    metrics = np.array([-np.inf, -np.inf, -np.inf, np.inf])
    drive_row = -1 if model.drive_row is None else int(model.drive_row)
    out = sk.Output(
        mode=mode,
        t_out=t_out,
        cursor=np.zeros(2, dtype=np.int64),
        rec=Recording.empty(model, t_out.size if full else 0),
        light=light,
        sections=Recording.empty(model, int(plan.sections)),
        strobe=strobe,
        metrics=metrics,
        t_window=math.inf if plan.metrics_from is None else float(plan.metrics_from),
        peak_step=float(plan.peak_step),
        drive_row=drive_row,
    )
    y = np.ascontiguousarray(y0, dtype=np.float64)
    scratch = np.empty_like(y)
    t0 = float(t_out[0])
    if full:
        sk.record_sample(model.kernel, ws, out.rec, 0, t0, y, vimp, scratch,
                         np.zeros(k.CNT_COLUMNS, dtype=np.int64))  # fmt: skip
    else:
        k.light_outputs(model.kernel, ws, y, light[0])
    out.cursor[0] = 1
    if plan.sections:
        start = np.empty(3)
        k.light_outputs(model.kernel, ws, y, start)
        sense = -1.0 if getattr(model.scene.drive, "speed_rpm", 1.0) < 0 else 1.0
        two_pi = 2.0 * math.pi
        first = start[0] + sense * two_pi * plan.discard - plan.phase
        turns = math.ceil(first / two_pi - 1e-9) if sense > 0 else math.floor(first / two_pi + 1e-9)
        target = plan.phase + two_pi * turns
        if abs(target - start[0]) <= 1e-9:
            sk.record_sample(model.kernel, ws, out.sections, 0, t0, y, vimp, scratch,
                             np.zeros(k.CNT_COLUMNS, dtype=np.int64))  # fmt: skip
            out.cursor[1] = 1
            target += sense * two_pi
        strobe[sk.STROBE_TARGET] = target
        strobe[sk.STROBE_DIRECTION] = sense
        strobe[sk.STROBE_ANGLE] = start[0]
    return out


def _integration(
    name: str,
    out: sk.Output,
    status: int,
    counters: np.ndarray,
    wall: float,
    y: np.ndarray,
    t: float,
    loop: sk.LoopState | None = None,
    message: str = "",
) -> Integration:
    """Package a compiled loop's outputs (truncated to what was recorded)."""
    if status == STATUS_RUNNING:
        status = 0
    n_grid = int(out.cursor[0])
    full = bool(out.mode & sk.REC_FULL)
    return Integration(
        recording=out.rec.head(n_grid) if status != 0 else out.rec,
        stats=solver_stats(name, status, counters, wall, message),
        final_state=y,
        final_time=float(t),
        light=None if full else (out.light[:n_grid] if status != 0 else out.light),
        sections=out.sections.head(int(out.cursor[1])) if out.mode & sk.REC_SECTIONS else None,
        metrics=out.metrics.copy() if out.mode & sk.REC_METRICS else None,
        final_step=math.nan if loop is None else float(loop.step[1]),
        final_contact=None if loop is None else loop.contact.copy(),
    )


def solver_stats(
    method: str, status: int, counters: np.ndarray, wall: float, msg: str = ""
) -> SolverStats:
    """The :class:`SolverStats` of a finished run from its status code and kernel counters
    (``msg`` overrides the status code's standard message)."""
    return SolverStats(
        method=method,
        status=int(status),
        message=msg or _MESSAGES.get(int(status), f"status {status}"),
        steps=int(counters[k.CNT_STEPS]),
        rejected_steps=int(counters[k.CNT_REJECTED]),
        function_evaluations=int(counters[k.CNT_FEV]),
        jacobian_evaluations=int(counters[k.CNT_JAC]),
        newton_iterations=int(counters[k.CNT_NEWTON]),
        contact_events=int(counters[k.CNT_CONTACT_EVENTS]),
        contact_evaluations=int(counters[k.CNT_CONTACT_EVALS]),
        wall_time=wall,
    )


class ProgressBar:
    """Optional tqdm bar over the simulated time, in percent (library calls are silent)."""

    def __init__(self, enabled: bool, t0: float, t_end: float, label: str):
        self.bar = None
        self.t0 = t0
        self.span = max(t_end - t0, 1e-300)
        self.done = 0
        if enabled:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=100, desc=label, unit="%")

    def update(self, t: float) -> None:
        if self.bar is not None:
            pct = min(100, round(100.0 * (t - self.t0) / self.span))
            if pct > self.done:
                self.bar.update(pct - self.done)
                self.done = pct

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _chunks(t0: float, t_end: float, progress: bool) -> list[float]:
    """Chunk boundaries for progress updates (a single chunk without progress)."""
    if not progress:
        return [t_end]
    return [t0 + (t_end - t0) * (i + 1) / 100.0 for i in range(100)]


#: interruptions seen by the integrations of this process (one element, a count)
_INTERRUPTS = [0]


def interrupt_integrations() -> None:
    """Stop the integrations running in this process at their next return to Python.

    Each compiled loop returns to Python every ``chunk_steps`` attempted steps. The
    thread that receives Ctrl-C raises ``KeyboardInterrupt`` there by itself; the
    integrations running in other threads (the ideal companion of
    :func:`mechanism.simulate`) cannot see the signal, and raise ``KeyboardInterrupt``
    at their next return once this has been called. An interrupted integration calls it
    too; a command line's SIGINT handler calls it before raising, so that runs in other
    threads stop also while the main thread is waiting for them. Integrations started
    afterwards are not affected.
    """
    _INTERRUPTS[0] += 1


def interruptions() -> int:
    """The count of :func:`interrupt_integrations` calls; an integration records it when
    it starts and passes it to :func:`advance_to`."""
    return _INTERRUPTS[0]


#: attempted steps before a run's step count is extrapolated (fewer say little about it)
FORECAST_AFTER = 1_000


@dataclass
class StepForecast:
    """The attempted steps a run will need, extrapolated from its progress so far.

    After every return of a compiled loop (from ``FORECAST_AFTER`` attempted steps on),
    the attempted steps so far (accepted and rejected, from ``counters``) are scaled by the
    share of ``[t0, t_end]`` covered. A run whose forecast exceeds ``max_steps`` would
    reach the step cap long after it started, and one above ``budget`` would run for
    hours: either is stopped at once with
    :data:`~mechanism.core._status.STATUS_MAX_STEPS` and ``message`` saying why. The
    forecast reads the counters only: a run that is not stopped takes the same steps as
    without it.
    """

    t0: float
    t_end: float
    max_steps: int
    counters: np.ndarray
    budget: float = math.inf
    message: str = ""

    def exceeded(self, t: float) -> bool:
        """True (and ``message`` set) when the forecast at time ``t`` exceeds the cap or
        the budget."""
        attempted = int(self.counters[k.CNT_STEPS] + self.counters[k.CNT_REJECTED])
        done = t - self.t0
        span = self.t_end - self.t0
        if attempted < FORECAST_AFTER or not done < span:
            return False
        estimate = attempted * span / done if done > 0.0 else math.inf
        needs = (
            f"the run would need about {estimate:.3g} attempted steps to reach "
            f"t = {self.t_end:.6g} s ({attempted} took it to t = {t:.6g} s)"
        )
        if estimate > self.max_steps:
            self.message = f"{needs}, more than max_steps = {self.max_steps:.3g}; stopped early."
        elif estimate > self.budget:
            self.message = (
                f"{needs}, more than the {self.budget:.3g} a run takes unless forced; "
                "stopped early, force=True (--force) runs it anyway."
            )
        else:
            return False
        return True


def advance_to(
    call: Callable[[float], int],
    clock: np.ndarray,
    t_stop: float,
    bar: ProgressBar,
    since: int,
    forecast: StepForecast | None = None,
) -> int:
    """Call the compiled loop ``call(t_stop)`` until ``clock[0]`` reaches ``t_stop`` or the
    loop ends; returns the status of the last call.

    A loop returns ``STATUS_RUNNING`` also when its step budget (``chunk_steps``) is
    spent before ``t_stop``; it is then called again and continues bit for bit. Between
    calls Python runs, so a Ctrl-C raises ``KeyboardInterrupt`` within one budget of
    steps however small the steps have become (compiled code never sees a signal), and
    so does an :func:`interrupt_integrations` call made since ``since`` (the count of
    :func:`interruptions` when the integration started). With a ``forecast``, a run whose
    extrapolated step count exceeds its cap ends there with ``STATUS_MAX_STEPS``.
    """
    try:
        while True:
            status = int(call(t_stop))
            bar.update(float(clock[0]))
            if _INTERRUPTS[0] != since:
                raise KeyboardInterrupt
            if status == STATUS_RUNNING and forecast is not None:
                if forecast.exceeded(float(clock[0])):
                    return STATUS_MAX_STEPS
            if status != STATUS_RUNNING or clock[0] >= t_stop:
                return status
    except KeyboardInterrupt:
        interrupt_integrations()
        raise


def check_chunk_steps(value: Any) -> None:
    """Raise ``ValueError`` unless ``value`` is an integer ≥ 1 (attempted steps per call of
    a compiled loop)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"chunk_steps must be an integer ≥ 1 (steps); got {value!r}.")


def initial_latch(model: Model, y0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Impact-velocity latch and contact flags of each clearance joint at the state ``y0``
    (a joint already in contact latches the velocity floor and counts as no event)."""
    n_cj = model.kernel.cj_i.shape[0]
    # a journal that starts in contact keeps the floor as its impact velocity
    vimp = model.kernel.cj_f[:, k.CF_FLOOR].copy()
    contact = np.zeros(n_cj, dtype=np.int64)
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    k.update_latch(model.kernel, model.workspace(), y0, vimp, contact, counters)
    # an initial state in contact counts as no event
    return vimp, contact


def _control(
    method: Any,
    t0: float,
    t_end: float,
    *,
    rtol: float,
    atol: float,
    max_step: float,
    projection: bool,
    fixed_step: float = 0.0,
    approach_floor: float = 0.0,
) -> sk.StepControl:
    """The kernels' StepControl of ``method`` (a Dopri5 or GeneralizedAlpha) for a run."""
    entry = float(getattr(method, "contact_entry_depth", 0.0))
    # below this step an entry is accepted (a worn profile can make the penetration jump)
    floor = 1e-6 * max_step if math.isfinite(max_step) else 1e-10 * (t_end - t0)
    return sk.StepControl(
        t_end=t_end,
        rtol=float(rtol),
        atol=float(atol),
        max_step=float(max_step),
        max_steps=int(method.max_steps),
        projection=bool(projection),
        entry_depth=entry,
        entry_min_step=float(floor),
        rho_inf=float(getattr(method, "rho_inf", 0.0)),
        max_newton=int(getattr(method, "max_newton", 1)),
        fixed_step=float(fixed_step),
        approach_floor=float(approach_floor),
        approach_fraction=APPROACH_FRACTION,
        chunk_steps=int(method.chunk_steps),
    )


class Integrator:
    """Base of the integrator strategies (see the subclasses)."""

    name: str = "integrator"

    def integrate(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float = 0.0,
        projection: bool = False,
        progress: bool = False,
        label: str = "simulate",
        record: RecordPlan = FULL,
        step_budget: float = math.inf,
    ) -> Integration:
        """Integrate ``model`` from ``y0`` over the grid ``t_out``.

        ``step_budget``: a run whose attempted steps, extrapolated from its progress
        after each return of a compiled loop, exceed it is stopped early with the status
        of the step cap (the compiled integrators; default none: a run whose forecast
        exceeds ``max_steps`` is stopped early all the same).

        ``max_step`` (s) bounds every step. ``approach_floor`` (s) > 0 also bounds each
        step by the approach of the clearance joints — no separated journal travels more
        than ``APPROACH_FRACTION`` of its gap to the wall — but never below the floor
        (the model kernels' ``approach_step``); the scipy methods, whose
        step control has no such hook, take the floor as their largest step.
        """
        raise NotImplementedError


@dataclass(frozen=True, kw_only=True)
class Dopri5(Integrator):
    """Compiled adaptive Dormand–Prince 5(4) with 4th-order dense output.

    Parameters
    ----------
    contact_entry_depth : float
        With a value > 0, a step that passes the error test but takes a separated clearance
        joint deeper than this fraction of its radial clearance is retried with the step
        at which the penetration, interpolated from the start of the step, is half of it
        (as in :class:`GeneralizedAlpha`). Off by default: the error test already sees the
        contact force in the stages of a step that enters contact, and on the hard cases
        the check changed the latched impact velocity more than it helped (the peak force
        of the 1 µm slider-crank moved by 0.65 % between step caps T/4000 and T/8000 with
        it, 0.02 % without).
    max_steps : int
        Upper bound on attempted steps (accepted + rejected).
    chunk_steps : int, optional
        Attempted steps per call of the compiled loop (≥ 1; default 5 000): between calls
        Python runs, so Ctrl-C stops even a run held at tiny steps. The results do not
        depend on it.

    Notes
    -----
    Hairer's DOPRI5 step control (PI, β = 0.04) and continuous extension; the impact
    velocity latch is updated between accepted steps. Reference: J. R. Dormand,
    P. J. Prince, J. Comput. Appl. Math. 6 (1980) 19–26; E. Hairer, S. P. Nørsett,
    G. Wanner, *Solving Ordinary Differential Equations I*, §II.5–6.
    """

    contact_entry_depth: float = 0.0
    max_steps: int = 200_000_000
    chunk_steps: int = CHUNK_STEPS["dopri5"]
    name: str = field(default="dopri5", init=False)

    def __post_init__(self) -> None:
        if not float(self.contact_entry_depth) >= 0.0:
            raise ValueError(f"contact_entry_depth must be ≥ 0; got {self.contact_entry_depth!r}.")
        check_chunk_steps(self.chunk_steps)

    def integrate(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float = 0.0,
        projection: bool = False,
        progress: bool = False,
        label: str = "simulate",
        record: RecordPlan = FULL,
        step_budget: float = math.inf,
    ) -> Integration:
        km = model.kernel
        ws = model.workspace()
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
        vimp, contact = initial_latch(model, y)
        loop = sk.LoopState(
            y=y, f=np.zeros_like(y), apse=np.zeros(0), step=np.zeros(4), vimp=vimp,
            contact=contact, counters=counters,
        )  # fmt: skip
        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        ctl = _control(self, t0, t_end, rtol=rtol, atol=atol, max_step=max_step,
                       projection=projection, approach_floor=approach_floor)  # fmt: skip
        out = _output(model, ws, y, vimp, t_out, record)
        since = interruptions()
        start = time.perf_counter()
        status = dk.dopri5_start(km, ws, t0, y, loop.f, vimp, loop.step, counters, rtol, atol,
                                 ctl.max_step)  # fmt: skip
        forecast = StepForecast(
            t0=t0, t_end=t_end, max_steps=self.max_steps, counters=counters, budget=step_budget
        )
        if status == STATUS_RUNNING:
            bar = ProgressBar(progress, t0, t_end, label)
            try:
                for t_stop in _chunks(t0, t_end, progress):
                    status = advance_to(
                        lambda stop: dk.dopri5_advance(km, ws, loop, out, ctl, stop),
                        loop.step, t_stop, bar, since, forecast,
                    )  # fmt: skip
                    if status != STATUS_RUNNING:
                        break
            finally:
                bar.close()
        wall = time.perf_counter() - start
        return _integration(
            self.name, out, status, counters, wall, y, loop.step[0], loop, forecast.message
        )


def _jacobian_columns(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(finite-difference columns, analytic columns) of the generalized-α Jacobian.

    A node of an ANCF beam that no point of the point table reads (no joint, contact or
    output touches it) enters q̈ only through its elastic and damping forces, whose
    Jacobian the element provides; every other coordinate is differenced.
    """
    km = model.kernel
    n = model.n_dof
    node_start = np.full(n, -1, dtype=np.int64)  # first coordinate of the node of a beam DOF
    for o, ne in km.beam_i[:, :2]:
        idx = np.arange(o, o + 4 * (ne + 1))
        node_start[idx] = o + 4 * ((idx - o) // 4)
    analytic = node_start >= 0
    for row in km.pt_i:
        for d in (row[1], row[3], *row[4:8]):
            if d >= 0 and node_start[d] >= 0:
                analytic[node_start[d] : node_start[d] + 4] = False
    cols = np.arange(n, dtype=np.int64)
    return np.ascontiguousarray(cols[~analytic]), np.ascontiguousarray(cols[analytic])


def _contact_columns(model: Model) -> np.ndarray:
    """The coordinates the clearance joints' bearing and journal points read (position,
    and the angle that sets the friction moment and the worn-profile region)."""
    km = model.kernel
    cols: set[int] = set()
    for point in km.cj_i[:, :2].ravel():
        kind, base, angle_kind, slope, *ds = (int(x) for x in km.pt_i[point])
        if kind == POINT_RIGID:
            cols.update((base, base + 1, base + 2))
        elif kind == POINT_LINEAR:
            for d in ds:
                if d >= 0:
                    cols.update((d, d + 1))
        if angle_kind == ANGLE_RIGID:
            cols.add(base + 2)
        elif angle_kind == ANGLE_SLOPE:
            cols.update((slope, slope + 1))
    return np.array(sorted(cols), dtype=np.int64)


@dataclass(frozen=True, kw_only=True)
class GeneralizedAlpha(Integrator):
    """Implicit generalized-α integrator for stiff contact (Chung & Hulbert 1993).

    Parameters
    ----------
    rho_inf : float
        Spectral radius at infinite frequency, in [0, 1]: 1 keeps all energy
        (trapezoidal), smaller values damp the unresolved high-frequency content.
    max_newton : int
        Newton iterations per step before the Jacobian is refreshed or the step is
        reduced.
    contact_entry_depth : float
        A step from a separated state is rejected when it ends deeper than this fraction
        of the radial clearance and retried with the step at which the penetration,
        interpolated from the start of the step, is half of it, so every impact starts
        with a short step; a step below 1e-6 × the maximum step is accepted (a worn
        profile can make the penetration jump). 0 disables the check.
    max_steps : int
        Upper bound on attempted steps.
    chunk_steps : int, optional
        Attempted steps per call of the compiled loop (≥ 1; default 1 000): between calls
        Python runs, so Ctrl-C stops even a run held at tiny steps. The results do not
        depend on it.
    step : float or "max_step", optional
        Fixed step (s), or ``"max_step"`` for the run's maximum step (``solver.max_step``,
        else the output step of a scene with clearance joints): no local error control
        or the output spacing when that is unbounded (the tolerances still set the
        Newton convergence test); a step whose Newton
        iteration fails, or that enters contact too deep, is retried with a fraction of
        it. For flexible (ANCF) bodies, whose stiff axial modes an error-controlled step
        would have to resolve (docs/ancf.md §8). Default: adaptive. The method name
        ``"generalized-alpha-fixed"`` is ``GeneralizedAlpha(step="max_step")``.

    Notes
    -----
    Second order; the local error estimate compares the acceleration change over the
    step (``e_q = h²|β − 1/6| Δq̈``, ``e_v = h(|γ − ½| + 1/12) Δq̈``). J. Chung, G. M. Hulbert,
    J. Appl. Mech. 60 (1993) 371–375; M. Arnold, O. Brüls, Multibody Syst. Dyn. 18 (2007)
    185–202.
    """

    rho_inf: float = 0.8
    max_newton: int = 8
    contact_entry_depth: float = 0.01
    max_steps: int = 200_000_000
    chunk_steps: int = CHUNK_STEPS["generalized-alpha"]
    step: float | Literal["max_step"] | None = None
    name: str = field(default="generalized-alpha", init=False)

    def __post_init__(self) -> None:
        if not 0.0 <= float(self.rho_inf) <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1]; got {self.rho_inf!r}.")
        if int(self.max_newton) < 1:
            raise ValueError(f"max_newton must be ≥ 1; got {self.max_newton!r}.")
        if not float(self.contact_entry_depth) >= 0.0:
            raise ValueError(f"contact_entry_depth must be ≥ 0; got {self.contact_entry_depth!r}.")
        if self.step is not None and self.step != "max_step":
            if not (isinstance(self.step, int | float) and math.isfinite(self.step)):
                raise ValueError(
                    f"step must be a number > 0 (s), 'max_step' or None; got {self.step!r}."
                )
            if not self.step > 0.0:
                raise ValueError(f"step must be > 0 (s); got {self.step!r}.")
        check_chunk_steps(self.chunk_steps)

    def integrate(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float = 0.0,
        projection: bool = False,
        progress: bool = False,
        label: str = "simulate",
        record: RecordPlan = FULL,
        step_budget: float = math.inf,
    ) -> Integration:
        return self._advance(
            model, y0, t_out, rtol=rtol, atol=atol, max_step=max_step,
            approach_floor=approach_floor, projection=projection, progress=progress,
            label=label, record=record, step_budget=step_budget,
        )  # fmt: skip

    def _advance(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float = 0.0,
        projection: bool = False,
        progress: bool = False,
        label: str = "simulate",
        record: RecordPlan = FULL,
        deviation: tk.Deviation | None = None,
        stops: np.ndarray | None = None,
        on_stop: Callable[[float], None] | None = None,
        step_budget: float = math.inf,
    ) -> Integration:
        """:meth:`integrate`, optionally carrying a :class:`~._kernels.Deviation` along
        (the largest Lyapunov exponent): the loop then stops at every time of ``stops``
        (the first accepted step at or after it; the steps do not depend on the stops)
        and calls ``on_stop`` with the time reached."""
        km = model.kernel
        n = model.n_dof
        ws = model.workspace()
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
        vimp, contact = initial_latch(model, y)
        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        out = _output(model, ws, y, vimp, t_out, record)
        since = interruptions()
        start = time.perf_counter()
        acc = np.zeros(n)
        t_now = t0
        loop = None
        forecast = StepForecast(
            t0=t0, t_end=t_end, max_steps=self.max_steps, counters=counters, budget=step_budget
        )
        status = k.accelerations(km, ws, t0, y[:n], y[n:], vimp, acc, counters)
        if status == STATUS_OK:
            status = STATUS_RUNNING
            fd_cols, an_cols = _jacobian_columns(model)
            jac = gk.jacobian_buffers(n, vimp.shape[0], fd_cols, an_cols, _contact_columns(model))
            if self.step == "max_step":
                # an unbounded run (e.g. the ideal companion) steps at the output spacing
                fixed = float(max_step)
                if not math.isfinite(fixed):
                    fixed = float(t_out[1] - t_out[0]) if t_out.size > 1 else t_end - t0
            else:
                fixed = 0.0 if self.step is None else float(self.step)
            if fixed > 0.0:
                max_step = min(max_step, fixed)
                h0 = max_step
            else:
                h0 = min(max_step, 1e-3 * (t_end - t0), 1e-4)
            ctl = _control(self, t0, t_end, rtol=rtol, atol=atol, max_step=max_step,
                           projection=projection, fixed_step=fixed,
                           approach_floor=approach_floor)  # fmt: skip
            loop = sk.LoopState(
                y=y, f=acc, apse=acc.copy(), step=np.array([t0, h0, 0.0, 0.0, 0.0]),
                vimp=vimp, contact=contact, counters=counters,
            )  # fmt: skip
            bar = ProgressBar(progress, t0, t_end, label)
            chunks = _chunks(t0, t_end, progress) if stops is None else [float(x) for x in stops]
            try:
                for t_stop in chunks:
                    status = advance_to(
                        lambda stop: gk.genalpha_advance(
                            km, ws, loop, out, ctl, jac, stop, deviation
                        ),
                        loop.step, t_stop, bar, since, forecast,
                    )  # fmt: skip
                    if on_stop is not None and status in (STATUS_RUNNING, STATUS_OK):
                        on_stop(float(loop.step[0]))
                    if status != STATUS_RUNNING:
                        break
            finally:
                bar.close()
            t_now = float(loop.step[0])
        wall = time.perf_counter() - start
        return _integration(
            self.name, out, status, counters, wall, y, t_now, loop, forecast.message
        )


@dataclass(frozen=True, kw_only=True)
class ScipyIVP(Integrator):
    """A :mod:`scipy.integrate` ``OdeSolver`` stepping the compiled right-hand side.

    Parameters
    ----------
    method : {"RK45", "DOP853", "Radau", "BDF", "LSODA"}
        The scipy solver class. The impact-velocity latch is updated between accepted
        steps; outputs come from the solver's dense output. Each right-hand-side call
        crosses from Python into numba, so this path is a cross-check, not the fast path.
    """

    method: ScipyMethodName = "RK45"
    name: str = field(default="", init=False)

    def __post_init__(self) -> None:
        if self.method not in ("RK45", "DOP853", "Radau", "BDF", "LSODA"):
            raise ValueError(
                f"method must be one of 'RK45', 'DOP853', 'Radau', 'BDF', 'LSODA'; "
                f"got {self.method!r}."
            )
        object.__setattr__(self, "name", self.method)

    def integrate(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float = 0.0,
        projection: bool = False,
        progress: bool = False,
        label: str = "simulate",
        record: RecordPlan = FULL,
        step_budget: float = math.inf,
    ) -> Integration:
        import scipy.integrate as si

        if record != FULL:
            raise ValueError(
                f"the scipy method {self.method!r} records the full trajectory only; use "
                "'dopri5' or a generalized-α method for metrics or sections."
            )
        km = model.kernel
        ws = model.workspace()
        rec = Recording.empty(model, t_out.size)
        counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        vimp, contact = initial_latch(model, y)
        status_box = [0]

        def fun(t: float, yy: np.ndarray) -> np.ndarray:
            out = np.empty_like(yy)
            st = k.rhs(km, ws, t, np.ascontiguousarray(yy, dtype=np.float64), vimp, out, counters)
            if st != 0:
                status_box[0] = int(st)
            return out

        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        solver_cls = getattr(si, self.method)
        options: dict[str, Any] = {"rtol": rtol, "atol": atol}
        if approach_floor > 0.0:
            # scipy's step control has no approach bound: the floor is the largest step
            max_step = min(max_step, approach_floor)
        if math.isfinite(max_step):
            options["max_step"] = max_step
        start = time.perf_counter()
        solver = solver_cls(fun, t0, y, t_end, **options)
        sk.record_sample(km, ws, rec, 0, t0, y, vimp, np.empty_like(y), counters.copy())
        cursor = 1
        bar = ProgressBar(progress, t0, t_end, label)
        status = 0
        message = ""
        out_counters = np.zeros_like(counters)
        try:
            while solver.status == "running":
                msg = solver.step()
                if solver.status == "failed":
                    status = STATUS_STEP_TOO_SMALL
                    message = str(msg)
                    break
                if status_box[0] != 0:
                    status = STATUS_SINGULAR
                    break
                counters[k.CNT_STEPS] += 1
                stop = int(np.searchsorted(t_out, solver.t, side="right"))
                if stop > cursor:
                    dense = solver.dense_output()
                    times = np.ascontiguousarray(t_out[cursor:stop])
                    states = np.ascontiguousarray(np.atleast_2d(dense(times)).reshape(y.size, -1))
                    sk.record_batch(km, ws, rec, cursor, times, states, vimp, out_counters)
                    cursor = stop
                yy = np.ascontiguousarray(solver.y, dtype=np.float64)
                k.update_latch(km, ws, yy, vimp, contact, counters)
                bar.update(solver.t)
        finally:
            bar.close()
        wall = time.perf_counter() - start
        counters[k.CNT_JAC] += int(getattr(solver, "njev", 0))
        return Integration(
            recording=rec.head(cursor) if status != 0 else rec,
            stats=solver_stats(self.name, status, counters, wall, message),
            final_state=np.asarray(solver.y, dtype=np.float64),
            final_time=float(solver.t),
            final_step=float(solver.step_size) if solver.step_size is not None else math.nan,
            final_contact=contact.copy(),
        )


METHODS: tuple[str, ...] = (
    "auto",
    "dopri5",
    "RK45",
    "DOP853",
    "Radau",
    "BDF",
    "LSODA",
    "generalized-alpha",
    "generalized-alpha-fixed",
)


def resolve_method(method: str | Integrator, model: Model | None = None) -> Integrator:
    """Turn a method name (see ``METHODS``) or an :class:`Integrator` into a strategy.

    ``"auto"`` picks by the assembled ``model``: the fixed-step generalized-α
    (``GeneralizedAlpha(step="max_step")``, as ``"generalized-alpha-fixed"``) when it has
    ANCF beam coordinates, whose axial modes (kHz to 0.1 MHz) hold every error-controlled
    method at their period (docs/ancf.md §8), and :class:`Dopri5` (the MATLAB ``ode45``
    scheme of the paper) for a rigid model.

    Parameters
    ----------
    method : str or Integrator
        A name of ``METHODS`` or an integrator object (returned unchanged).
    model : mechanism.core.model._assemble.Model, optional
        The assembled mechanism; required by ``"auto"``. Its ``solver.rho_inf`` sets the
        numerical damping of the generalized-α methods (0.8 without a model).

    Examples
    --------
    >>> resolve_method("Radau").name
    'Radau'
    >>> resolve_method(GeneralizedAlpha(rho_inf=0.5)).name
    'generalized-alpha'
    >>> import mechanism
    >>> from mechanism.core.model._assemble import assemble
    >>> rigid = assemble(mechanism.load_scene("slider-crank"))
    >>> resolve_method("auto", rigid).name
    'dopri5'
    >>> flexible = assemble(mechanism.load_scene("flexible-slider-crank"))
    >>> resolve_method("auto", flexible).step
    'max_step'
    """
    if isinstance(method, Integrator):
        return method
    # the scene's numerical damping for the generalized-α methods (default 0.8)
    rho_inf = 0.8 if model is None else float(model.scene.solver.rho_inf)
    if method == "auto":
        if model is None:
            raise ValueError("method 'auto' needs the assembled model to choose an integrator.")
        has_beams = model.kernel.beam_i.shape[0] > 0
        return GeneralizedAlpha(rho_inf=rho_inf, step="max_step") if has_beams else Dopri5()
    if method == "dopri5":
        return Dopri5()
    if method == "generalized-alpha":
        return GeneralizedAlpha(rho_inf=rho_inf)
    if method == "generalized-alpha-fixed":
        return GeneralizedAlpha(rho_inf=rho_inf, step="max_step")
    if method in ("RK45", "DOP853", "Radau", "BDF", "LSODA"):
        return ScipyIVP(method=method)  # type: ignore[arg-type]
    raise ValueError(f"method must be one of {list(METHODS)} or an Integrator; got {method!r}.")
