"""Reference trajectory and renormalised deviation on one step sequence (Python layer).

:func:`integrate_tangent` drives the compiled loop of ``_tangent_kernels``: it advances a
state and a deviation of fixed size by the same Dormand–Prince steps (its rate the
derivative of the right-hand side along it, by finite differences of that size),
renormalising the deviation every few accepted steps, and returns the accumulated log growth at the
requested stop times. The largest Lyapunov exponent of a scene
(:func:`mechanism.lyapunov_exponent`) is built on it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from chaoskit.contract import check_int, check_positive
from mechanism.core._status import STATUS_RUNNING
from mechanism.core.joints import PC_X, PC_Y, update_points
from mechanism.core.model import kernels as model_kernels

from . import _dopri_kernels as dopri_kernels
from . import _tangent_kernels as tangent_kernels
from ._interface import StepSettings
from ._methods import (
    APPROACH_FRACTION,
    CHUNK_STEPS,
    ProgressBar,
    SolverStats,
    advance_to,
    check_chunk_steps,
    initial_latch,
    interruptions,
    solver_stats,
)

if TYPE_CHECKING:
    from collections.abc import Callable

    from mechanism.core.model import Model

__all__ = [
    "TangentIntegration",
    "TangentSettings",
    "deviation_size",
    "initial_deviation",
    "integrate_tangent",
    "length_scale",
]


#: how :class:`TangentSettings` differences the deviation's rate
DIFFERENCES = ("split", "directional")


@dataclass(frozen=True, kw_only=True)
class TangentSettings:
    """How :func:`integrate_tangent` and :func:`integrate_tangent_flexible` advance a
    reference and its deviation: the reference's step control and the deviation's options,
    built once per run and checked on construction (a ValueError names the field and its
    accepted range).

    Parameters
    ----------
    steps : StepSettings
        Step control of the reference (``rtol``, ``atol``, ``max_step``,
        ``approach_floor``, ``projection``), as for :func:`mechanism.simulate`;
        ``step_budget`` bounds the generalized-α reference only (``max_steps`` bounds
        the Dormand–Prince tangent loop).
    time_scale : float
        τ (s, > 0) of the deviation norm ``√((δqᵀMδq + τ²δq̇ᵀMδq̇)/m_total)``.
    renormalize_every : int
        Accepted steps between renormalisations (≥ 1; also done at every stop). The
        dynamics are linear in the deviation, so ``final_deviation`` × exp of the last
        ``log_growth`` is the deviation carried without renormalisation.
    deviation_rtol : float
        In [0, 1]. > 0: a step is also rejected when the deviation's error estimate
        exceeds this fraction of its size (mass-weighted norm); 0: the reference's error
        alone decides, and the steps are those of ``simulate`` at the same settings (and
        the same for every deviation of one reference). Dormand–Prince only.
    neutral_latch_after : float, optional
        Duration (s, > 0) of uninterrupted contact after which a clearance joint's latch
        deviation is zeroed (None: never). A latch frozen by a lasting contact is a
        neutral direction of the linearised flow (while the contact lasts its multiplier
        is exactly 1, the latch feeding the motion but nothing feeding it): left in, it
        holds the renormalised deviation at zero growth once every other direction
        contracts. Zeroing it keeps the deviation in the invariant subspace without the
        latch, whose growth is the exponent of the motion. Contact is checked whenever
        the compiled loop returns (every ``chunk_steps`` attempted steps and at the
        stops), which does not change the integration; impacts and contacts shorter than
        the duration are untouched. Dormand–Prince only.
    max_steps : int
        Upper bound on attempted steps (≥ 1). Dormand–Prince only (the generalized-α
        loop takes its method's).
    chunk_steps : int
        Attempted steps per call of the compiled loop (≥ 1): between calls Python runs, so
        Ctrl-C stops even a run held at tiny steps. The results do not depend on it.
        Dormand–Prince only (the generalized-α loop takes its method's).
    difference : {"split", "directional"}
        How the deviation's rate is differenced at every stage: ``"split"``, one
        difference along its position part and one along its velocity part, each scaled
        to the deviation's size (two right-hand sides per stage); ``"directional"``, one
        difference along the whole deviation, scaled so that its smaller part moves by the
        deviation's size unless its larger one would move by more than ten times that (one
        right-hand side per stage; the rate at the start of a step is the last stage's of
        the step before unless a renormalisation or a projection moved the deviation).
        Dormand–Prince only.

    Examples
    --------
    >>> from mechanism.core.integrate import StepSettings, TangentSettings
    >>> steps = StepSettings(rtol=1e-8, atol=1e-8, max_step=1e-4)
    >>> TangentSettings(steps=steps, time_scale=0.0637).renormalize_every
    1
    >>> TangentSettings(steps=steps, time_scale=0.0637, deviation_rtol=2.0)
    Traceback (most recent call last):
    ...
    ValueError: deviation_rtol must be in [0, 1]; got 2.0.
    """

    steps: StepSettings
    time_scale: float
    renormalize_every: int = 1
    deviation_rtol: float = 0.0
    neutral_latch_after: float | None = None
    max_steps: int = 200_000_000
    chunk_steps: int = CHUNK_STEPS["tangent"]
    difference: str = "split"

    def __post_init__(self) -> None:
        if not isinstance(self.steps, StepSettings):
            raise TypeError(
                f"steps must be a mechanism.core.integrate.StepSettings; got "
                f"{type(self.steps).__name__}."
            )
        deviation_rtol = check_positive(self.deviation_rtol, name="deviation_rtol", allow_zero=True)
        if deviation_rtol > 1.0:
            raise ValueError(f"deviation_rtol must be in [0, 1]; got {deviation_rtol!r}.")
        after = self.neutral_latch_after
        check_chunk_steps(self.chunk_steps)
        if self.difference not in DIFFERENCES:
            raise ValueError(
                f"difference must be one of {', '.join(DIFFERENCES)}; got {self.difference!r}."
            )
        checked = {
            "time_scale": check_positive(self.time_scale, name="time_scale"),
            "renormalize_every": check_int(
                self.renormalize_every, name="renormalize_every", minimum=1
            ),
            "deviation_rtol": deviation_rtol,
            "neutral_latch_after": (
                None if after is None else check_positive(after, name="neutral_latch_after")
            ),
            "max_steps": check_int(self.max_steps, name="max_steps", minimum=1),
            "chunk_steps": int(self.chunk_steps),
        }
        for name, value in checked.items():
            object.__setattr__(self, name, value)


@dataclass(frozen=True, kw_only=True)
class TangentIntegration:
    """Log growth of a renormalised deviation along a reference trajectory.

    Attributes
    ----------
    t : numpy.ndarray
        Times (s) at which the growth was read: the requested stops reached (the last
        step before each stop is shortened to land on it; the deviation is renormalised
        there).
    log_growth : numpy.ndarray
        ``Σ ln(|d|/size)`` from the start up to each ``t`` (natural log, dimensionless);
        for a block of deviations (``d0`` of shape (2n, k)) one column per deviation.
    renormalizations : int
        Renormalisations done (of each deviation).
    stats : SolverStats
        Reference integration cost; ``function_evaluations`` counts both copies.
    final_state, final_deviation : numpy.ndarray
        The reference's state and the deviation (for a block, one column per deviation).
    newton_iterations, unconverged_steps : int
        Generalized-α only: the perturbed copy's Newton iterations, and the steps whose
        copy ended its iterations with an update above 1e-3 of the deviation's size (0
        for Dormand–Prince).
    final_latch, final_latch_deviation : numpy.ndarray
        Latched impact velocity (m/s) of each clearance joint at the end, and its
        deviation (rescaled with the deviation, like it; for a block, (joints, k)).
    final_contact : numpy.ndarray
        1 for a clearance joint in contact at the end, else 0.
    states : numpy.ndarray
        With ``record_states``: the reference state [q; q̇] at each ``t`` (rows), else
        empty.
    contact : numpy.ndarray
        With ``record_states``: the contact flags of the clearance joints at each ``t``.
    contact_events : numpy.ndarray
        With ``record_states``: contact entries counted from the start up to each ``t``.
    latches : numpy.ndarray
        With ``record_states``: the latched impact velocities (m/s) at each ``t``.
    step_times : numpy.ndarray
        With ``record_steps``: the start and the time of every accepted step.
    latch_drops : int
        Latch deviations removed as neutral (``drop_persistent_latch``).
    """

    t: np.ndarray
    log_growth: np.ndarray
    renormalizations: int
    stats: SolverStats
    final_state: np.ndarray
    final_deviation: np.ndarray
    newton_iterations: int = 0
    unconverged_steps: int = 0
    final_latch: np.ndarray = field(default_factory=lambda: np.zeros(0))
    final_latch_deviation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    final_contact: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    states: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    contact: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), dtype=np.int64))
    contact_events: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    latches: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    step_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    latch_drops: int = 0


def inverse_total_mass(model: Model) -> float:
    """1 / total mass: of the rigid bodies from their x-coordinates; with ANCF beams uᵀMu
    for the unit translation u along x (1 on every body's and node's x-coordinate)."""
    if not model.beams:
        mass = sum(float(model.kernel.mass[o, o]) for o in model.body_offsets)
        return 1.0 / mass
    u = np.array([1.0 if name.endswith(".x") else 0.0 for name in model.dof_names])
    return 1.0 / float(u @ model.kernel.mass @ u)


def deviation_size(model: Model, d: np.ndarray, *, time_scale: float) -> float:
    """Mass-weighted size (m) √((δqᵀMδq + τ²δq̇ᵀMδq̇)/m_total) of a state deviation ``d``."""
    d = np.ascontiguousarray(d, dtype=np.float64)
    return float(
        tangent_kernels.deviation_size(model.kernel, d, time_scale**2, inverse_total_mass(model))
    )


def length_scale(model: Model, y0: np.ndarray) -> float:
    """Length (m) a deviation size is relative to: the smallest radial clearance of the
    active clearance joints, else the mechanism's size (largest extent of its points at
    state ``y0``)."""
    if model.clearance_joints:
        return float(np.min(model.kernel.cj_f[:, model_kernels.CF_C]))
    ws = model.workspace()
    n = model.n_dof
    y = np.ascontiguousarray(y0, dtype=np.float64)
    update_points(y[:n], y[n:], model.kernel.pt_i, model.kernel.pt_f, ws.pci, ws.pcf)
    xy = ws.pcf[:, [PC_X, PC_Y]]
    span = float(np.max(np.ptp(xy, axis=0))) if xy.shape[0] > 1 else 0.0
    return span if span > 0.0 else 1.0


def _check_rigid(model: Model) -> None:
    if model.beams:
        raise ValueError(
            "integrate_tangent needs a rigid model: flexible (ANCF) bodies are integrated "
            "with generalized-alpha; use integrate_tangent_flexible."
        )


def initial_deviation(
    model: Model, y0: np.ndarray, *, t0: float, size: float, time_scale: float, seed: int = 0
) -> np.ndarray:
    """A random deviation of ``y0`` tangent to the constraint manifold, of the given size.

    Raises
    ------
    ValueError
        When the constraints leave the scene no degree of freedom (its motion is
        prescribed, so no deviation exists).
    """
    free = model.n_dof - model.n_rows
    if free <= 0:
        raise ValueError(
            f"the scene has no degree of freedom ({model.n_dof} coordinates, "
            f"{model.n_rows} constraint equations): its motion is prescribed by the drive, "
            "so it has no Lyapunov exponent; give it a clearance joint or a free body."
        )
    y = np.ascontiguousarray(y0, dtype=np.float64)
    d = np.random.default_rng(seed).standard_normal(y.size)
    ws, ws2 = model.workspace(), model.workspace()
    if not tangent_kernels.project_tangent(
        model.kernel, ws, ws2, float(t0), y, d, np.empty(y.size)
    ):
        raise ValueError("the constraint Jacobian is singular at the initial state.")
    r = tangent_kernels.deviation_size(model.kernel, d, time_scale**2, inverse_total_mass(model))
    return np.ascontiguousarray(d * (size / r))


def _start_latch(
    model: Model, y: np.ndarray, latch: tuple[np.ndarray, np.ndarray] | None
) -> tuple[np.ndarray, np.ndarray]:
    """(latched impact velocities, contact flags) to start from: the given ones, else
    those of ``y`` as :func:`mechanism.simulate` starts."""
    if latch is None:
        return initial_latch(model, y)
    vimp = np.ascontiguousarray(latch[0], dtype=np.float64).copy()
    contact = np.ascontiguousarray(latch[1], dtype=np.int64).copy()
    n_cj = model.kernel.cj_i.shape[0]
    if vimp.shape != (n_cj,) or contact.shape != (n_cj,):
        raise ValueError(
            f"latch must hold {n_cj} impact velocities and {n_cj} contact flags "
            f"(one per clearance joint); got shapes {vimp.shape} and {contact.shape}."
        )
    return vimp, contact


def _deviation_rows(d0: np.ndarray, n2: int) -> np.ndarray:
    """A deviation (2n,) or a block (2n, k) as the compiled loop's rows (k, 2n)."""
    d = np.asarray(d0, dtype=np.float64)
    if d.ndim not in (1, 2) or d.shape[0] != n2 or (d.ndim == 2 and d.shape[1] < 1):
        raise ValueError(
            f"d0 must be a deviation of {n2} values or a block of shape ({n2}, k), k >= 1; "
            f"got shape {d.shape}."
        )
    return np.ascontiguousarray(np.atleast_2d(d.T) if d.ndim == 2 else d[None, :]).copy()


def _latch_rows(
    latch_deviation: np.ndarray | None, joints: int, columns: int, block: bool
) -> np.ndarray:
    """Initial latch deviations (m/s) as rows (k, joints); zero when not given."""
    out = np.zeros((columns, joints))
    if latch_deviation is None:
        return out
    dl = np.asarray(latch_deviation, dtype=np.float64)
    want = (joints, columns) if block else (joints,)
    if dl.shape != want:
        raise ValueError(
            f"latch_deviation must have shape {want} (joints, and one column per deviation "
            f"of a block); got {dl.shape}."
        )
    out[:] = dl.T if block else dl[None, :]
    return out


def integrate_tangent(
    model: Model,
    y0: np.ndarray,
    d0: np.ndarray,
    t_stops: np.ndarray,
    *,
    settings: TangentSettings,
    latch: tuple[np.ndarray, np.ndarray] | None = None,
    latch_deviation: np.ndarray | None = None,
    step_schedule: np.ndarray | None = None,
    record_states: bool = False,
    record_steps: bool = False,
    until: Callable[[np.ndarray, np.ndarray], bool] | None = None,
    progress: bool | str = False,
) -> TangentIntegration:
    """Integrate ``y0`` from ``t_stops[0]`` and its deviation ``d0`` to ``t_stops[-1]``.

    Parameters
    ----------
    model
        Assembled rigid mechanism.
    y0, d0
        Initial state [q; q̇] and deviation (its size, :func:`deviation_size`, is kept at
        every renormalisation). A zero ``d0`` integrates the reference alone, at a third
        of the cost (its growth stays 0). A (2n, k) ``d0`` is a block of k deviations
        carried in lock-step on the one reference: the same steps (with
        ``deviation_rtol`` > 0 the error norm is the largest of the reference's and the
        deviations'), the same contact, friction-ramp and latch rules, each column
        renormalised on its own to its own size; a column's numbers are those of a
        lone run of it whenever the steps are (a ``step_schedule``, or
        ``deviation_rtol`` = 0), and one reference serves them all (the monodromy
        matrix of :func:`mechanism.periodic_orbit`). The results then carry one
        column per deviation.
    t_stops
        Increasing times (s); the first is the start. The growth is read at each.
    settings
        The reference's step control (``settings.steps``, as
        :class:`~mechanism.integrate.Dopri5`; ``approach_floor`` > 0: the clearance
        joints' approach bounds the step, never below it) and the deviation's options
        (:class:`TangentSettings`).
    latch
        (impact velocities (m/s), contact flags) of the clearance joints at the start;
        default: those :func:`mechanism.simulate` starts from (a journal in contact holds
        the floor). A state taken from inside a run needs the run's latch.
    latch_deviation
        Initial deviation (m/s) of the latched impact velocities (for a block, (joints, k),
        one column per deviation); default 0.
    step_schedule
        Increasing times holding ``t_stops`` (e.g. ``step_times`` of a run from a nearby
        state): step exactly from one to the next, accepting every step.
    record_states
        Keep the reference state, the contact flags and the count of contact entries at
        every stop (``states``, ``contact``, ``contact_events``).
    record_steps
        Keep the time of every accepted step (``step_times``); the compiled loop then
        returns after each attempted step (slower, the same integration). Passed back as
        ``step_schedule`` they freeze the steps, so the end state is a smooth function
        of the start (the adaptive choice of steps, otherwise a source of jumps at the
        tolerance's level, is frozen).
    until
        Called at every stop before the last with the times and log growths read so far
        (as the result's ``t`` and ``log_growth``); a true return ends the run there, a
        successful run with fewer rows than ``t_stops``. The steps never depend on the
        stops ahead, so the rows are those of the whole run.
    progress
        Show a progress bar: True, or its label (default ``"lyapunov"``).

    Returns
    -------
    TangentIntegration
        Fewer rows than ``t_stops`` when the run failed (``stats.status`` < 0) or
        ``until`` ended it.

    Examples
    --------
    >>> import numpy as np
    >>> import mechanism
    >>> from mechanism.core.integrate import StepSettings, TangentSettings, integrate_tangent
    >>> from mechanism.core.model import assemble, initial_state
    >>> scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    >>> model = assemble(scene)
    >>> y0 = np.concatenate(initial_state(model))
    >>> steps = StepSettings(rtol=1e-8, atol=1e-8, max_step=4e-5)
    >>> settings = TangentSettings(steps=steps, time_scale=0.0637)
    >>> run = integrate_tangent(model, y0, np.zeros_like(y0), np.array([0.0, 1e-3]),
    ...                         settings=settings)
    >>> run.stats.success
    True
    """
    _check_rigid(model)
    if not isinstance(settings, TangentSettings):
        raise TypeError(f"settings must be a TangentSettings; got {type(settings).__name__}.")
    steps_in = settings.steps
    rtol, atol, max_step = steps_in.rtol, steps_in.atol, steps_in.max_step
    time_scale = settings.time_scale
    chunk_steps = settings.chunk_steps
    directional = settings.difference == "directional"
    km = model.kernel
    ws, ws2 = model.workspace(), model.workspace()
    stops = np.ascontiguousarray(t_stops, dtype=np.float64)
    y = np.ascontiguousarray(y0, dtype=np.float64).copy()
    block = np.ndim(d0) == 2
    # the compiled loop holds the deviations as rows: (k, 2n)
    d = _deviation_rows(d0, y.size)
    tau2 = float(time_scale) ** 2
    inv_mass = inverse_total_mass(model)
    size = np.array([tangent_kernels.deviation_size(km, row, tau2, inv_mass) for row in d])
    k1 = np.zeros_like(y)
    kd1 = np.zeros_like(d)
    state = np.zeros(5)
    counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    counters_p = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    growth = np.zeros((d.shape[0], tangent_kernels.GROWTH_COLUMNS))
    vimp, contact = _start_latch(model, y, latch)
    # deviations of the latched impact velocities (m/s), one row per deviation
    dvimp = _latch_rows(latch_deviation, vimp.size, d.shape[0], block)
    t0, t_end = float(stops[0]), float(stops[-1])
    times, logs = [t0], [np.zeros(d.shape[0])]
    record = _StopRecord(record_states, y, contact, vimp)
    since = interruptions()
    start = time.perf_counter()
    status = model_kernels.rhs(km, ws, t0, y, vimp, k1, counters)
    if status == model_kernels.STATUS_OK:
        state[0] = t0
        state[1] = dopri_kernels.initial_step(
            km, ws, t0, y, k1, vimp, counters, rtol, atol, max_step
        )
        state[2] = 1e-4
        status = STATUS_RUNNING

    def rate() -> int:
        return int(tangent_kernels.tangent_start(
            km, ws, float(state[0]), y, d, k1, kd1, vimp, dvimp, counters, counters_p,
            size, float(time_scale), inv_mass, directional,
        ))  # fmt: skip

    if status == STATUS_RUNNING:
        status = rate()
    hold = _ContactHold(settings.neutral_latch_after, t0, contact, counters)
    steps = [t0]
    schedule = (
        np.zeros(0)
        if step_schedule is None
        else np.ascontiguousarray(step_schedule, dtype=np.float64)
    )
    compiled_steps = record_steps and settings.neutral_latch_after is None
    if record_steps and not compiled_steps:
        chunk_steps = 1
    taken = _StepTimes()

    def stepped(stop: float) -> int:
        st = int(tangent_kernels.tangent_steps(
            km, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters, counters_p,
            growth, stop, t_end, rtol, atol, max_step, steps_in.projection,
            settings.max_steps, settings.renormalize_every, size, tau2, inv_mass,
            float(steps_in.approach_floor), APPROACH_FRACTION, settings.deviation_rtol,
            chunk_steps, schedule, directional, taken.buffer, taken.count,
        ))  # fmt: skip
        taken.drain(steps)
        return st

    def advance(stop: float) -> int:
        if compiled_steps:
            return stepped(stop)
        st = int(tangent_kernels.tangent_advance(
            km, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters,
            counters_p, growth, stop, t_end, rtol, atol, max_step, steps_in.projection,
            settings.max_steps, settings.renormalize_every, size, tau2, inv_mass,
            float(steps_in.approach_floor), APPROACH_FRACTION, settings.deviation_rtol,
            chunk_steps, schedule, directional,
        ))  # fmt: skip
        if hold.drop(float(state[0]), contact, counters, dvimp) and st == STATUS_RUNNING:
            st = rate()  # the deviation's rate without the dropped latch
        if record_steps and state[0] > steps[-1]:
            steps.append(float(state[0]))
        return st

    # recording at many stops (e.g. every step of a schedule): one compiled loop over
    # them, the same numbers without a return to Python at each stop
    compiled_stops = (
        record_states and settings.neutral_latch_after is None and not record_steps
        and until is None
    )  # fmt: skip
    rows = _StopRows(stops.size - 1, y.size, d.shape[0], contact.size)

    def through(_: float) -> int:
        return int(tangent_kernels.tangent_stops(
            km, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters, counters_p,
            growth, stops[1:], t_end, rtol, atol, max_step, steps_in.projection,
            settings.max_steps, settings.renormalize_every, size, tau2, inv_mass,
            float(steps_in.approach_floor), APPROACH_FRACTION, settings.deviation_rtol,
            chunk_steps, schedule, directional, rows.cursor, rows.t, rows.log, rows.y,
            rows.contact, rows.events, rows.latch,
        ))  # fmt: skip

    bar = ProgressBar(bool(progress), t0, t_end, progress_label(progress))
    try:
        if compiled_stops and status == STATUS_RUNNING and stops.size > 1:
            status = advance_to(through, state, t_end, bar, since)
            rows.into(times, logs, record)
        for t_stop in [] if compiled_stops else stops[1:]:
            if status != STATUS_RUNNING:
                break
            status = advance_to(advance, state, float(t_stop), bar, since)
            if status in (STATUS_RUNNING, 0):
                times.append(float(state[0]))
                logs.append(growth[:, tangent_kernels.GROWTH_LOG].copy())
                record.add(y, contact, vimp, counters)
                if status == STATUS_RUNNING and until is not None:
                    read = np.array(logs)
                    if until(np.array(times), read if block else read[:, 0]):
                        status = 0
    finally:
        bar.close()
    wall = time.perf_counter() - start
    if status == STATUS_RUNNING:
        status = 0
    counters[model_kernels.CNT_FEV] += counters_p[model_kernels.CNT_FEV]
    stats = solver_stats("dopri5", status, counters, wall)
    log_growth = np.array(logs)
    return TangentIntegration(
        t=np.array(times),
        log_growth=log_growth if block else log_growth[:, 0],
        renormalizations=int(growth[0, tangent_kernels.GROWTH_COUNT]),
        stats=stats,
        final_state=y,
        final_deviation=d.T.copy() if block else d[0],
        final_latch=vimp,
        final_latch_deviation=dvimp.T.copy() if block else dvimp[0],
        final_contact=contact,
        latch_drops=hold.drops,
        step_times=np.array(steps) if record_steps else np.zeros(0),
        **record.arrays(),
    )


class _ContactHold:
    """Which clearance joints have stayed in contact for ``after`` seconds; zeroes their
    latch deviation (the neutral direction of a lasting contact)."""

    def __init__(
        self, after: float | None, t0: float, contact: np.ndarray, counters: np.ndarray
    ) -> None:
        self.after = after
        self.drops = 0
        self.t = t0
        self.contact = contact.copy()
        self.events = int(counters[model_kernels.CNT_CONTACT_EVENTS])
        self.since = np.where(contact != 0, t0, np.nan)

    def drop(self, t: float, contact: np.ndarray, counters: np.ndarray, dvimp: np.ndarray) -> bool:
        """Update at time ``t``; True when a latch deviation was zeroed (``dvimp``: one
        row per deviation)."""
        if self.after is None:
            return False
        events = int(counters[model_kernels.CNT_CONTACT_EVENTS])
        # in contact at both checks with no entry between: in contact all along
        held = (self.contact != 0) & (contact != 0) & (events == self.events)
        self.since = np.where(held, np.fmin(self.since, self.t), np.nan)
        self.t, self.contact, self.events = t, contact.copy(), events
        lasting = held & (t - self.since >= self.after) & (dvimp != 0.0)
        if not np.any(lasting):
            return False
        dvimp[lasting] = 0.0
        self.drops += int(np.count_nonzero(lasting))
        return True


class _StepTimes:
    """Buffer of accepted step times the compiled loop fills (:func:`tangent_steps`)."""

    def __init__(self) -> None:
        self.buffer = np.empty(4096)
        self.count = np.zeros(1, dtype=np.int64)

    def drain(self, steps: list[float]) -> None:
        """Move the buffered times to ``steps``."""
        n = int(self.count[0])
        steps.extend(self.buffer[:n].tolist())
        self.count[0] = 0


class _StopRows:
    """Rows the compiled loop over the stops fills (:func:`tangent_stops`): one per stop
    reached after the start."""

    def __init__(self, stops: int, n2: int, columns: int, joints: int) -> None:
        self.cursor = np.zeros(2, dtype=np.int64)
        self.t = np.empty(stops)
        self.log = np.empty((stops, columns))
        self.y = np.empty((stops, n2))
        self.contact = np.empty((stops, joints), dtype=np.int64)
        self.events = np.empty(stops, dtype=np.int64)
        self.latch = np.empty((stops, joints))

    def into(self, times: list, logs: list, record: _StopRecord) -> None:
        """Append the filled rows to the stop times, the growth and the record."""
        n = int(self.cursor[1])
        times.extend(self.t[:n].tolist())
        logs.extend(self.log[:n])
        record.extend(self.y[:n], self.contact[:n], self.events[:n], self.latch[:n])


class _StopRecord:
    """Reference states, contact flags and entry counts at the stops (when asked)."""

    def __init__(self, on: bool, y: np.ndarray, contact: np.ndarray, vimp: np.ndarray) -> None:
        self.on = on
        # blocks of rows: (states, contact flags, entry counts, latches)
        self.blocks: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
        if on:
            self.extend(y[None, :], contact[None, :], np.zeros(1, np.int64), vimp[None, :])

    def add(
        self, y: np.ndarray, contact: np.ndarray, vimp: np.ndarray, counters: np.ndarray
    ) -> None:
        events = np.array([counters[model_kernels.CNT_CONTACT_EVENTS]], dtype=np.int64)
        self.extend(y[None, :], contact[None, :], events, vimp[None, :])

    def extend(
        self, ys: np.ndarray, contact: np.ndarray, events: np.ndarray, latches: np.ndarray
    ) -> None:
        """Rows of states, contact flags, entry counts and latches at further stops."""
        if self.on:
            self.blocks.append((ys.copy(), contact.copy(), events.copy(), latches.copy()))

    def arrays(self) -> dict[str, np.ndarray]:
        if not self.on:
            return {}
        names = ("states", "contact", "contact_events", "latches")
        return {name: np.concatenate([b[i] for b in self.blocks]) for i, name in enumerate(names)}


def progress_label(progress: bool | str) -> str:
    """The label of a tangent integration's progress bar (``progress``: True or a label)."""
    return progress if isinstance(progress, str) else "lyapunov"
