"""The Python side of the compiled time loops: the loop's outputs and step control for a
run, its calls in chunks (progress, Ctrl-C and :func:`interrupt_integrations`, the
step-count forecast) and the packaging of what it recorded."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from mechanism.core._status import STATUS_MAX_STEPS, STATUS_RUNNING
from mechanism.core.model import kernels as model_kernels

from . import _step_kernels as step_kernels
from ._interface import Integration, Recording, RecordPlan, StepSettings, solver_stats

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = [
    "APPROACH_FRACTION",
    "CHUNK_STEPS",
    "FORECAST_AFTER",
    "ProgressBar",
    "StepForecast",
    "advance_to",
    "check_chunk_steps",
    "initial_latch",
    "interrupt_integrations",
    "interruptions",
    "loop_output",
    "loop_result",
    "progress_chunks",
    "step_control",
]

#: attempted steps of a compiled loop per call before control returns to Python, where a
#: pending Ctrl-C is raised: well under a second of work on the scenes of the package
#: (docs/simulator.md, *Interrupting a run*); the results do not depend on it
CHUNK_STEPS = {"dopri5": 5_000, "generalized-alpha": 1_000, "tangent": 2_000}

#: share of its gap to the bearing wall a separated journal may travel in one step (at
#: its current speed and acceleration); the approach floor bounds the last steps before
#: contact, so the value sets the cost of the approach, not how an impact is entered
APPROACH_FRACTION = 1.0


def loop_output(
    model: Model,
    ws: Any,
    y0: np.ndarray,
    vimp: np.ndarray,
    t_out: np.ndarray,
    plan: RecordPlan,
    *,
    in_kernel: bool = False,
) -> step_kernels.Output:
    """The kernels' Output tuple for ``plan``, with the first grid sample (and a section
    at the start when the initial crank angle is a strobe angle) recorded.

    With ``in_kernel`` nothing is recorded yet: the loop records the start itself on its
    first call (``_step_kernels.record_start``), so no recording kernel is compiled for a
    call from Python."""
    full = plan.grid == "full"
    mode = step_kernels.REC_FULL if full else step_kernels.REC_LIGHT
    if plan.sections:
        mode |= step_kernels.REC_SECTIONS
    if plan.metrics_from is not None:
        mode |= step_kernels.REC_METRICS
    light = np.zeros(
        (0 if full else t_out.size, model_kernels.LIGHT_COLUMNS + 2 * model.kernel.cj_i.shape[0])
    )
    strobe = np.zeros(step_kernels.STROBE_COLUMNS)
    metrics = np.array([-np.inf, -np.inf, -np.inf, np.inf])
    drive_row = -1 if model.drive_row is None else int(model.drive_row)
    out = step_kernels.Output(
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
    sense = -1.0 if getattr(model.scene.drive, "speed_rpm", 1.0) < 0 else 1.0
    two_pi = 2.0 * math.pi
    strobe[step_kernels.STROBE_DIRECTION] = sense
    strobe[step_kernels.STROBE_PHASE] = plan.phase
    strobe[step_kernels.STROBE_SHIFT] = sense * two_pi * plan.discard
    if in_kernel:
        return out
    y = np.ascontiguousarray(y0, dtype=np.float64)
    scratch = np.empty_like(y)
    t0 = float(t_out[0])
    if full:
        step_kernels.record_sample(model.kernel, ws, out.rec, 0, t0, y, vimp, scratch,
                         np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64))  # fmt: skip
    else:
        model_kernels.light_outputs(model.kernel, ws, y, light[0])
    out.cursor[0] = 1
    if plan.sections:
        start = np.empty(3)
        model_kernels.light_outputs(model.kernel, ws, y, start)
        first = start[0] + sense * two_pi * plan.discard - plan.phase
        turns = math.ceil(first / two_pi - 1e-9) if sense > 0 else math.floor(first / two_pi + 1e-9)
        target = plan.phase + two_pi * turns
        if abs(target - start[0]) <= 1e-9:
            step_kernels.record_sample(model.kernel, ws, out.sections, 0, t0, y, vimp, scratch,
                             np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64))  # fmt: skip
            out.cursor[1] = 1
            target += sense * two_pi
        strobe[step_kernels.STROBE_TARGET] = target
        strobe[step_kernels.STROBE_ANGLE] = start[0]
    return out


def loop_result(
    name: str,
    out: step_kernels.Output,
    status: int,
    counters: np.ndarray,
    wall: float,
    y: np.ndarray,
    t: float,
    loop: step_kernels.LoopState | None = None,
    message: str = "",
) -> Integration:
    """Package a compiled loop's outputs (truncated to what was recorded)."""
    if status == STATUS_RUNNING:
        status = 0
    n_grid = int(out.cursor[0])
    full = bool(out.mode & step_kernels.REC_FULL)
    return Integration(
        recording=out.rec.head(n_grid) if status != 0 else out.rec,
        stats=solver_stats(name, status, counters, wall, message),
        final_state=y,
        final_time=float(t),
        light=None if full else (out.light[:n_grid] if status != 0 else out.light),
        sections=out.sections.head(int(out.cursor[1]))
        if out.mode & step_kernels.REC_SECTIONS
        else None,
        metrics=out.metrics.copy() if out.mode & step_kernels.REC_METRICS else None,
        final_step=math.nan if loop is None else float(loop.step[1]),
        final_contact=None if loop is None else loop.contact.copy(),
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


def progress_chunks(t0: float, t_end: float, progress: bool) -> list[float]:
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
        attempted = int(
            self.counters[model_kernels.CNT_STEPS] + self.counters[model_kernels.CNT_REJECTED]
        )
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
    vimp = model.kernel.cj_f[:, model_kernels.CF_FLOOR].copy()
    contact = np.zeros(n_cj, dtype=np.int64)
    counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    model_kernels.update_latch(model.kernel, model.workspace(), y0, vimp, contact, counters, False)
    # an initial state in contact counts as no event
    return vimp, contact


def step_control(
    method: Any,
    t0: float,
    t_end: float,
    steps: StepSettings,
    *,
    max_step: float | None = None,
    fixed_step: float = 0.0,
) -> step_kernels.StepControl:
    """The kernels' StepControl of ``method`` (a Dopri5 or GeneralizedAlpha) for a run
    with ``steps``; ``max_step`` replaces ``steps.max_step`` (a fixed step's bound)."""
    max_step = steps.max_step if max_step is None else max_step
    entry = float(getattr(method, "contact_entry_depth", 0.0))
    # below this step an entry is accepted (a worn profile can make the penetration jump)
    floor = 1e-6 * max_step if math.isfinite(max_step) else 1e-10 * (t_end - t0)
    return step_kernels.StepControl(
        t_end=t_end,
        rtol=float(steps.rtol),
        atol=float(steps.atol),
        max_step=float(max_step),
        max_steps=int(method.max_steps),
        projection=bool(steps.projection),
        entry_depth=entry,
        entry_min_step=float(floor),
        rho_inf=float(getattr(method, "rho_inf", 0.0)),
        max_newton=int(getattr(method, "max_newton", 1)),
        fixed_step=float(fixed_step),
        approach_floor=float(steps.approach_floor),
        approach_fraction=APPROACH_FRACTION,
        chunk_steps=int(method.chunk_steps),
    )
