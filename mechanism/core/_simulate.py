"""``mechanism.simulate``: assemble a scene, integrate it and its ideal companion, record."""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import psutil
import xarray as xr

from chaoskit.contract import check_positive

from ._status import STATUS_MAX_STEPS
from .integrate import (
    Dopri5,
    GeneralizedAlpha,
    Integration,
    Integrator,
    RecordPlan,
    ScipyIVP,
    StepSettings,
    resolve_method,
)
from .model import Model, assemble, initial_state
from .model import kernels as model_kernels
from .record import FullRecord, MetricsRecord, RecordMode, RunTimes, SectionsRecord, record_mode
from .scene import AngleProfileDrive, ConstantSpeedDrive, Scene, validate_scene

__all__ = [
    "MEMORY_FRACTION",
    "START_TOLERANCE",
    "STEP_BUDGET",
    "SimulationError",
    "default_step",
    "drive_period",
    "output_grid",
    "simulate",
    "step_limits",
]

#: A run estimated to hold more than this fraction of the memory available when it starts
#: (``psutil.virtual_memory().available``) is refused unless ``force=True``: the rest is
#: left to the interpreter, the netCDF writer and the other processes of the machine.
MEMORY_FRACTION = 0.8

#: A run whose attempted steps, extrapolated from its progress after each compiled chunk,
#: exceed this is stopped there unless ``force=True``: so many steps take from a quarter
#: of an hour to hours (``docs/simulator.md``, *Runs refused up front*), so such a run is
#: more likely a slip of a key than a wish. Above ``max_steps`` (2e8) a run is stopped
#: anyway.
STEP_BUDGET = 20_000_000

#: The ideal companion of a flexible model steps at this multiple of the main run's fixed
#: step. It supplies only the ideal slider on the output grid (the displacement and speed
#: errors, the full record's ``*_ideal`` variables), which its rods' unresolved axial
#: vibration leaves uncertain by a few µm at any such step (its accuracy and cost:
#: docs/performance.md, *Flexible rods*).
FLEXIBLE_IDEAL_STEP = 2.0


class SimulationError(RuntimeError):
    """The integrator failed (its status and message are in the exception text);
    ``time`` is the simulated time (s) it reached, NaN when not known."""

    def __init__(self, message: str, *, time: float = math.nan) -> None:
        super().__init__(message)
        self.time = float(time)

    def __reduce__(self) -> tuple[Any, ...]:  # keeps ``time`` across processes
        return (_simulation_error, (str(self), self.time))


def _simulation_error(message: str, time: float) -> SimulationError:
    return SimulationError(message, time=time)


def drive_period(scene: Scene) -> float | None:
    """Duration (s) of one drive period, or None for a scene without a periodic drive."""
    drive = scene.drive
    if isinstance(drive, ConstantSpeedDrive):
        if drive.speed_rpm == 0:
            return None
        return drive.period
    if isinstance(drive, AngleProfileDrive):
        return float(drive.period)
    return None


def output_grid(t_end: float, output_step: float) -> np.ndarray:
    """Uniform output times 0, Δt, 2Δt, … up to the last multiple of Δt not beyond t_end."""
    return output_step * np.arange(_grid_count(t_end, output_step), dtype=np.float64)


def _grid_count(t_end: float, output_step: float) -> int:
    """Samples of :func:`output_grid`, counted without allocating them (the count may be
    astronomically large: the run-size check refuses it)."""
    ratio = t_end / output_step * (1.0 + 1e-12)
    if not ratio >= 1.0:
        raise ValueError(
            f"output_step ({float(output_step):g} s) must not exceed the simulated time "
            f"({float(t_end):g} s)."
        )
    return math.floor(min(ratio, 1e300)) + 1


def _show(value: Any) -> str:
    """A value for a message: numbers as plain numbers (never ``np.float64(...)``)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list | tuple | np.ndarray):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    return repr(value)


def _duration(scene: Scene, revolutions: float | None, t_end: float | None) -> float:
    if revolutions is not None and t_end is not None:
        raise ValueError("pass either revolutions or t_end, not both.")
    period = drive_period(scene)
    if t_end is not None:
        return check_positive(t_end, name="t_end")
    if revolutions is None:
        revolutions = 1.0
    revolutions = check_positive(revolutions, name="revolutions")
    if period is None:
        raise ValueError(
            "the scene has no periodic drive, so revolutions cannot be converted to time; "
            "pass t_end (s)."
        )
    return revolutions * period


def default_step(scene: Scene, duration: float) -> float:
    """The scene's default output step (s): ``solver.output_step``, else a ten-thousandth of
    a drive period (of ``duration`` without a periodic drive)."""
    given = scene.solver.output_step
    if given is not None:
        return float(given)
    period = drive_period(scene)
    return (period if period is not None else duration) / 10000.0


def step_limits(model: Model, integrator: Integrator, scene_step: float) -> tuple[float, float]:
    """(largest step, approach floor) of a run of ``model``; a floor of 0: no approach bound.

    ``solver.max_step`` if set bounds every step, and nothing else does. Otherwise the
    fixed-step generalized-α steps at ``scene_step`` (:func:`default_step`); with
    clearance joints every other compiled integrator is bounded by their approach: no
    separated journal may travel more than its gap to the wall in one step, at its speed
    and acceleration (``mechanism.core.model.kernels.approach_step``), and never
    less than ``scene_step`` is imposed, so every impact is entered in steps of at most
    ``scene_step`` (as with that fixed limit) while free flight runs at the error control's
    step and contact at the error control's step (which sees the contact force in its
    stages). Without any bound Dormand–Prince steps across impacts on worn profiles
    (slider-crank with clearance after wear: peak force 165 kN instead of 26 kN,
    penetration 73 µm instead of 23 µm): the contact law's damping takes the approach
    speed of the last separated state, which a long entry step leaves far from the
    wall. The output grid a caller asks for never sets a bound, so a coarse grid or a
    record mode without a grid does not change the physics.
    """
    given = model.scene.solver.max_step
    if given is not None:
        return float(given), 0.0
    if _fixed_step(integrator):
        return float(scene_step), 0.0
    if model.clearance_joints:
        return math.inf, float(scene_step)
    return math.inf, 0.0


def _fixed_step(integrator: Integrator) -> bool:
    """True for the fixed-step generalized-α, whose step is the largest step."""
    return isinstance(integrator, GeneralizedAlpha) and integrator.step == "max_step"


@dataclass(frozen=True)
class _Run:
    """A run prepared: what it integrates and records, and how large it will be (estimated
    before anything of its size is allocated), with the keys that set its size."""

    model: Model
    integrator: Integrator
    mode: RecordMode
    times: RunTimes
    max_step: float  # s; inf: the error control's
    approach_floor: float  # s; 0: no approach bound
    output_key: str  # the key that set the output step and its value, for messages
    output_fix: str  # the option that changes it
    largest_step: float  # s; inf: the error control's
    step_key: str  # the key that set the largest step and its value
    step_fix: str  # the option that changes it
    duration_text: str  # how the duration came about, e.g. "revolutions = 3000 at ..."


def _duration_text(scene: Scene, revolutions: float | None, t_end: float | None) -> str:
    if t_end is not None:
        return f"t_end = {float(t_end):g} s"
    drive = scene.drive
    turns = 1.0 if revolutions is None else float(revolutions)
    if isinstance(drive, ConstantSpeedDrive):
        return f"revolutions = {turns:g} at drive.speed_rpm = {drive.speed_rpm:g}"
    if isinstance(drive, AngleProfileDrive):
        return f"revolutions = {turns:g} of drive.period = {drive.period:g} s"
    return f"revolutions = {turns:g}"


def _scene_step_text(scene: Scene, scene_step: float) -> str:
    """The scene's default output step and the key that sets it, for messages."""
    if scene.solver.output_step is not None:
        return f"solver.output_step = {scene_step:g} s"
    return f"the default output step (drive period / 10000) = {scene_step:g} s"


def _output_step(
    scene: Scene, mode: RecordMode, given: float | None, scene_step: float
) -> tuple[float, str, str]:
    """The output step of a run (s), the key that set it with its value, and the option
    that changes it."""
    period = drive_period(scene)
    if given is not None:
        step = check_positive(given, name="output_step")
        return step, f"output_step = {step:g} s", "output_step (--output-step)"
    divisions = mode.grid_divisions
    if divisions is None or period is None:
        fix = "solver.output_step (or pass output_step, --output-step)"
        return scene_step, _scene_step_text(scene, scene_step), fix
    step = period / divisions
    text = f"the default output_step (drive period / {divisions}) = {step:g} s"
    return step, text, "output_step (--output-step)"


def _step_keys(
    scene: Scene, integrator: Integrator, max_step: float, approach_floor: float, given: str
) -> tuple[float, str, str]:
    """The largest step a run may take (s; inf: its error control's), the key that set it
    with its value, and the option that changes it."""
    if scene.solver.max_step is not None:
        return float(max_step), f"solver.max_step = {max_step:g} s", "solver.max_step"
    if _fixed_step(integrator):
        fix = "solver.max_step (or solver.output_step)"
        return float(max_step), f"the fixed step, {given}", fix
    if isinstance(integrator, ScipyIVP) and approach_floor > 0.0:
        # the scipy methods take the approach floor as their largest step
        return float(approach_floor), f"the approach floor, {given}", "solver.output_step"
    return math.inf, "", ""


def _refuse_absurd_step_counts(size: _Run) -> None:
    """Refuse a run whose output grid or step count exceeds the default step limit of the
    compiled integrators (an integrator built with a smaller ``max_steps`` still runs and
    fails as data when it reaches it)."""
    limit = Dopri5().max_steps
    duration, n_out = size.times.duration, size.times.n_out
    steps = duration / size.largest_step
    if n_out > limit:
        raise ValueError(
            f"the output grid would hold {n_out:.3g} samples ({size.duration_text}, "
            f"{duration:.3g} s, at {size.output_key}), more than the {limit:.3g} steps "
            f"an integrator may take (max_steps; each sample costs about a step): raise "
            f"{size.output_fix}, or simulate less time."
        )
    if steps > limit:
        raise ValueError(
            f"the run would take at least {steps:.3g} steps ({size.duration_text}, "
            f"{duration:.3g} s, at {size.step_key}), more than the {limit:.3g} an "
            f"integrator may take (max_steps): it would fail after hours; raise "
            f"{size.step_fix}, or simulate less time."
        )


def _refuse_runs_larger_than_memory(size: _Run) -> None:
    """Refuse a run estimated above ``MEMORY_FRACTION`` of the available memory."""
    times = size.times
    nbytes = size.mode.estimated_bytes(size.model, times)
    available = int(psutil.virtual_memory().available)
    budget = MEMORY_FRACTION * available
    if nbytes <= budget:
        return
    fits = [f"output_step >= {_round_up(times.output_step * nbytes / budget)} s (--output-step)"]
    for lighter, option in size.mode.lighter(size.model, times):
        divisions = lighter.grid_divisions
        grid = times  # the lighter mode at its own default grid
        if divisions is not None and times.period is not None:
            grid = replace(times, n_out=_grid_count(times.duration, times.period / divisions))
        if lighter.estimated_bytes(size.model, grid) <= budget:
            fits.append(option)
    raise ValueError(
        f"this run would hold about {_size(nbytes)} ({times.n_out:.3g} samples of the "
        f"{size.mode.name} record at {size.output_key}, {size.duration_text}), more than the "
        f"{_size(budget)} it may use ({MEMORY_FRACTION:.0%} of the {_size(available)} of "
        f"memory available); what fits: {'; '.join(fits)}; force=True (--force) runs it "
        "anyway."
    )


def _size(nbytes: float) -> str:
    return f"{nbytes / 1e9:.3g} GB" if nbytes >= 1e9 else f"{nbytes / 1e6:.3g} MB"


def _round_up(x: float) -> str:
    """``x`` rounded up to two significant digits (a bound that still holds)."""
    unit = 10.0 ** (math.floor(math.log10(x)) - 1)
    return f"{math.ceil(x / unit * (1 - 1e-12)) * unit:.2g}"


def _failure_text(
    scene: Scene,
    model: Model,
    integrator: Integrator,
    run: Integration,
    duration: float,
    *,
    ideal: bool = False,
) -> str:
    """One line saying why ``run`` gave up, where, and the keys that change the outcome."""
    stats = run.stats
    what = f"the ideal mechanism of {scene.name!r}" if ideal else repr(scene.name)
    reason = " ".join(stats.message.split()).rstrip(".")
    reason = reason[:1].lower() + reason[1:]
    state = []
    if math.isfinite(run.final_step):
        state.append(f"step size {run.final_step:.3g} s")
    contact = run.final_contact
    flags = [False] * len(model.clearance_joints) if contact is None else list(contact)
    touching = [name for name, flag in zip(model.clearance_joints, flags, strict=True) if flag]
    if touching:
        state.append(
            ("joints " if len(touching) > 1 else "joint ") + ", ".join(touching) + " in contact"
        )
    elif model.clearance_joints and contact is not None:
        state.append("no clearance joint in contact")
    where = f"; {', '.join(state)}" if state else ""
    keys = ["solver.rtol", "solver.atol", "solver.max_step", "solver.method"]
    if stats.status == STATUS_MAX_STEPS:
        keys = ["revolutions (or t_end)"]
        if isinstance(scene.drive, ConstantSpeedDrive):
            keys.append("drive.speed_rpm")
        keys += ["solver.rtol", "solver.max_step", "solver.method"]
    # a contact in force when the step collapsed is the usual stiff part
    stiff = [f"joints.{name}.contact.stiffness" for name in touching]
    change = ", ".join(keys + stiff)
    return (
        f"simulation of {what} failed after t = {run.final_time:.6g} s of "
        f"{duration:.6g} s ({integrator.name}): {reason}{where}; the keys that change "
        f"the outcome: {change}."
    )


def _run(
    model: Model,
    method: Integrator,
    y0: np.ndarray,
    t_out: np.ndarray,
    *,
    rtol: float,
    atol: float,
    max_step: float,
    progress: bool,
    label: str,
    record: RecordPlan,
    approach_floor: float = 0.0,
    step_budget: float = math.inf,
) -> Integration:
    steps = StepSettings(
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        approach_floor=approach_floor,
        projection=model.scene.solver.projection,
        step_budget=step_budget,
    )
    return method.integrate(
        model, y0, t_out, steps=steps, record=record, progress=progress, label=label
    )


def _prepare(
    scene: Scene,
    mode: RecordMode,
    method: str | Integrator | None,
    duration: float,
    output_step: float | None,
    duration_text: str,
) -> _Run:
    """Assemble ``scene`` and size its run: integrator, step limits, output grid."""
    scene_step = default_step(scene, duration)
    output_step, output_text, output_fix = _output_step(scene, mode, output_step, scene_step)
    n_out = _grid_count(duration, output_step)
    model = assemble(scene)
    times = RunTimes(
        duration=duration, period=drive_period(scene), output_step=output_step, n_out=n_out,
        scene_step=scene_step,
    )  # fmt: skip
    mode.check(model, times)
    integrator = resolve_method(scene.solver.method if method is None else method, model)
    max_step, approach_floor = step_limits(model, integrator, scene_step)
    largest, largest_text, largest_fix = _step_keys(
        scene, integrator, max_step, approach_floor, _scene_step_text(scene, scene_step)
    )
    return _Run(
        model=model, integrator=integrator, mode=mode, times=times, max_step=max_step,
        approach_floor=approach_floor, output_key=output_text, output_fix=output_fix,
        largest_step=largest, step_key=largest_text, step_fix=largest_fix,
        duration_text=duration_text,
    )  # fmt: skip


#: Largest violation of the joints at t = 0 a ``start`` state may have, relative to its
#: largest coordinate (m or rad; at least 1) for the positions and its largest velocity
#: (at least 1) for the velocities: a finished run's state keeps its joints far closer
#: (the constraint stabilisation leaves drifts of about 1e-6 of the velocities), while a
#: state of another scene, of another speed or not after whole drive periods misses them
#: by far more.
START_TOLERANCE = 1e-4


def _start_pair(start: Any) -> tuple[Any, Any]:
    """The (positions, velocities) of a ``start`` argument, before any check."""
    if isinstance(start, xr.Dataset):
        if "final_q" not in start.attrs or "final_v" not in start.attrs:
            raise ValueError(
                "start must be a Dataset returned by mechanism.simulate (it carries the "
                "run's last state in the attributes final_q and final_v) or a (q, v) "
                "pair; this Dataset has no final_q / final_v."
            )
        return start.attrs["final_q"], start.attrs["final_v"]
    if isinstance(start, tuple | list) and len(start) == 2:
        return start[0], start[1]
    raise TypeError(
        "start must be a Dataset returned by mechanism.simulate or a (q, v) pair of "
        f"arrays; got {type(start).__name__}."
    )


def _start_state(model: Model, start: Any) -> np.ndarray | None:
    """The state ``start`` as the integrators' y0 = (q, v), its body angles brought within
    a half turn of the scene's pose (whole turns change no joint but the drive's angle),
    or None for None; a ValueError when it does not fit ``model`` at t = 0."""
    if start is None:
        return None
    q_in, v_in = _start_pair(start)
    q = np.array(q_in, dtype=np.float64).ravel()
    v = np.array(v_in, dtype=np.float64).ravel()
    n = model.n_dof
    if q.shape != (n,) or v.shape != (n,):
        raise ValueError(
            f"start must hold {n} positions and {n} velocities (the coordinates of scene "
            f"{model.scene.name!r}, {', '.join(model.dof_names)}); got {q.size} and {v.size}."
        )
    if not (np.isfinite(q).all() and np.isfinite(v).all()):
        raise ValueError("start must hold finite positions and velocities.")
    turns = np.array([name.endswith(".theta") for name in model.dof_names])
    q[turns] -= 2.0 * math.pi * np.round((q[turns] - model.q_guess[turns]) / (2.0 * math.pi))
    if model.n_rows:
        ws = model.workspace()
        model_kernels.evaluate_constraints(model.kernel, ws, 0.0, q, v)
        position = float(np.max(np.abs(ws.phi))) / max(1.0, float(np.max(np.abs(q))))
        velocity = float(np.max(np.abs(ws.phiq @ v + ws.phit))) / max(1.0, float(np.max(np.abs(v))))
        if not max(position, velocity) <= START_TOLERANCE:
            raise ValueError(
                f"start does not satisfy the joints of scene {model.scene.name!r} at t = 0 "
                f"(largest relative violation {position:.3g} of the positions, "
                f"{velocity:.3g} of the velocities; at most {START_TOLERANCE:g}): pass the "
                "last state of a run of the same scene that ended after whole drive periods."
            )
    return np.concatenate([q, v])


@dataclass(frozen=True)
class _Outcome:
    """The integrations of a run: the main one and the ideal mechanism's (None: none ran;
    the main run itself for a model without clearance joints)."""

    run: Integration
    ideal_model: Model
    ideal_run: Integration | None
    ideal_max_step: float


def _integrate(
    size: _Run,
    t_out: np.ndarray,
    *,
    progress: bool,
    force: bool,
    start: np.ndarray | None = None,
    **tol: float,
) -> _Outcome:
    """Integrate the model of ``size`` on ``t_out`` from ``start`` (None: the scene's
    initial state) and, when its mode asks for it and the model has clearance joints, the
    ideal companion alongside (always from its own initial state)."""
    model, integrator, scene = size.model, size.integrator, size.model.scene
    plan, ideal_plan = size.mode.plans(model, size.times)
    budget = math.inf if force else STEP_BUDGET
    if start is None:
        q0, v0 = initial_state(model)
        start = np.concatenate([q0, v0])
    if not (model.clearance_joints and size.mode.companion):
        run = _run(
            model, integrator, start, t_out, max_step=size.max_step, progress=progress,
            label=f"{scene.name}", record=plan, approach_floor=size.approach_floor,
            step_budget=budget, **tol,
        )  # fmt: skip
        # without clearance joints the run is its own ideal mechanism; without the
        # companion there is none (the errors are NaN)
        ideal = run if not model.clearance_joints else None
        return _Outcome(run, model, ideal, size.max_step)
    ideal_model = assemble(scene, ideal=True)
    iq0, iv0 = initial_state(ideal_model, eccentricity=False)
    # the companion has no impacts: its step is the error control's (the fixed-step
    # generalized-α keeps the main run's step, FLEXIBLE_IDEAL_STEP times it for ANCF
    # rods), as for an ideal mechanism on its own
    ideal_max_step = math.inf
    if _fixed_step(integrator):
        flexible = ideal_model.kernel.beam_i.shape[0] > 0
        ideal_max_step = size.max_step * (FLEXIBLE_IDEAL_STEP if flexible else 1.0)
    # The ideal companion does not depend on the main run: it runs in a second thread
    # (the compiled integrators release the GIL), so on a machine with a free core it
    # adds no wall time.
    with ThreadPoolExecutor(max_workers=1) as pool:
        ideal_future = pool.submit(
            _run, ideal_model, integrator, np.concatenate([iq0, iv0]), t_out,
            max_step=ideal_max_step, progress=progress, label=f"{scene.name} (ideal)",
            record=ideal_plan, step_budget=budget, **tol,
        )  # fmt: skip
        run = _run(
            model, integrator, start, t_out, max_step=size.max_step, progress=progress,
            label=f"{scene.name}", record=plan, approach_floor=size.approach_floor,
            step_budget=budget, **tol,
        )  # fmt: skip
        ideal_run = ideal_future.result()
    return _Outcome(run, ideal_model, ideal_run, ideal_max_step)


def _raise_failure(size: _Run, done: _Outcome) -> None:
    """Raise :class:`SimulationError` if the run or its ideal companion failed."""
    duration, integrator = size.times.duration, size.integrator
    scene = size.model.scene
    run, ideal_run = done.run, done.ideal_run
    if not run.stats.success:
        raise SimulationError(
            _failure_text(scene, size.model, integrator, run, duration), time=run.final_time
        )
    if ideal_run is not None and not ideal_run.stats.success:
        raise SimulationError(
            _failure_text(scene, done.ideal_model, integrator, ideal_run, duration, ideal=True),
            time=ideal_run.final_time,
        )


def _attrs(
    size: _Run, done: _Outcome, t_out: np.ndarray, cpu_seconds: float, rtol: float, atol: float
) -> dict[str, Any]:
    """The settings of the run, as Dataset attributes."""
    solver = size.model.scene.solver
    period = size.times.period
    attrs: dict[str, Any] = {
        # CPU seconds of this process during the two integrations (the one-core cost)
        "solver_cpu_time": cpu_seconds,
        "record": size.mode.name,
        "t_end": size.mode.end_time(t_out, size.times),
        "output_step": float(size.times.output_step),
        "rtol": float(rtol),
        "atol": float(atol),
        "max_step": float(size.max_step),
        "approach_floor": float(size.approach_floor),
        "ideal_max_step": float(done.ideal_max_step),
        "baumgarte_alpha": float(solver.baumgarte_alpha),
        "baumgarte_beta": float(solver.baumgarte_beta),
        "projection": int(bool(solver.projection)),
    }
    if period is not None:
        attrs["drive_period"] = float(period)
        attrs["revolutions"] = float(attrs["t_end"] / period)
    if done.ideal_run is None:
        del attrs["ideal_max_step"]
    return attrs


#: The record options, each with the record mode objects that hold it: ``simulate`` takes
#: them only inside ``record=``.
_RECORD_OPTIONS: dict[str, tuple[type[RecordMode], ...]] = {
    "variables": (FullRecord,),
    "discard": (MetricsRecord, SectionsRecord),
    "phase": (SectionsRecord,),
    "companion": (MetricsRecord, SectionsRecord),
}


def _record_options_in_objects(func: Callable[..., xr.Dataset]) -> Callable[..., xr.Dataset]:
    """``func`` refusing a record option given as a keyword with a TypeError naming the
    record object that holds it (Python's own message names only the keyword)."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> xr.Dataset:
        loose = [key for key in kwargs if key in _RECORD_OPTIONS]
        if loose:
            key = loose[0]
            objects = " or ".join(f"record={m.__name__}({key}=...)" for m in _RECORD_OPTIONS[key])
            raise TypeError(
                f"simulate() got an unexpected keyword argument {key!r}; pass it in the "
                f"record object: {objects}."
            )
        return func(*args, **kwargs)

    return wrapper


@_record_options_in_objects
def simulate(
    scene: Scene,
    *,
    revolutions: float | None = None,
    t_end: float | None = None,
    method: str | Integrator | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    record: RecordMode | str = "full",
    progress: bool = False,
    throw: bool = True,
    force: bool = False,
    start: xr.Dataset | tuple[Any, Any] | None = None,
) -> xr.Dataset:
    """Simulate a mechanism and return its trajectory, its response metrics or its
    stroboscopic section.

    The initial state is the ideal-mechanism configuration at t = 0 with the journals at
    their ``initial_eccentricity``, at rest relative to their bearings (or ``start``, the
    last state of an earlier run); the same scene
    with every clearance joint ideal (the ideal companion) is integrated alongside, in a
    second thread, for the ``*_ideal`` outputs and the errors. What is recorded never
    changes the integration. Costs and sizes: ``docs/simulator.md``.

    Parameters
    ----------
    scene : mechanism.core.scene.Scene
        The mechanism (see ``mechanism.load_scene``).
    revolutions : float, optional
        Simulated time in drive periods (default 1 when neither this nor ``t_end`` is
        given).
    t_end : float, optional
        Simulated time in s.
    method : str or Integrator, optional
        A name of ``mechanism.core.integrate.METHODS`` (``"auto"``: fixed-step
        generalized-α with ANCF beams, else ``"dopri5"``; the scipy methods record the
        full trajectory only) or an integrator object from :mod:`mechanism.integrate`.
        Default: ``scene.solver.method``; ``solver_method`` in the attributes names the
        integrator that ran.
    rtol, atol : float, optional
        Tolerances; default ``scene.solver``.
    output_step : float, optional
        Spacing (s) of the uniform output grid (default: the record mode's). It never
        bounds the step (``step_limits``).
    record : RecordMode or {"full", "metrics", "sections", "wear"}
        What is kept of the run: a :class:`~mechanism.FullRecord` (the
        trajectory; default), :class:`~mechanism.MetricsRecord` (the response
        metrics), :class:`~mechanism.SectionsRecord` (stroboscopic points
        and metrics) or :class:`~mechanism.WearRecord` (what wear reads), which
        hold their options (``variables``; ``discard``, ``companion``; ``phase``):
        these are not keywords of ``simulate`` (a TypeError names the object).
        A name stands for that mode with its default options.
    progress : bool
        Show a progress bar (tqdm).
    throw : bool
        Raise :class:`SimulationError` when the integrator fails; False: return the
        samples so far, with ``solver_status`` < 0 and the reason in ``solver_message``.
    force : bool
        Run even when the run is estimated to hold more than ``MEMORY_FRACTION`` of
        the memory available, or to take more than ``STEP_BUDGET`` (2e7) attempted steps
        (default False: refused up front, or stopped after its first compiled chunk).
    start : xarray.Dataset or (q, v), optional
        Start from this state at t = 0 instead of the scene's initial state: a Dataset
        returned by ``simulate`` (its ``final_q``, ``final_v``) or a pair of arrays of
        the model's coordinates and velocities. The drive restarts at t = 0, so a run of
        a periodic drive continues where an earlier one of the same scene left off when
        that one ended after whole drive periods (body angles are taken modulo whole
        turns); a state that misses the scene's joints at t = 0 by more than
        ``START_TOLERANCE`` (relative) is refused (ValueError). The impact-velocity latch of a
        journal in contact restarts at its floor, and the ideal companion starts from its
        own initial state.

    Returns
    -------
    xarray.Dataset
        The variables the record mode lists; solver statistics in the ``solver_*``
        attributes, the mode's name in ``record``, and the last state of the run in
        ``final_q``, ``final_v`` (coordinates and velocities at ``final_time``, s; what
        ``start`` takes). See ``docs/simulator.md``.

    Raises
    ------
    mechanism.SceneError
        The scene is invalid (it is validated here too, for scenes built in Python).
    ValueError
        A bad argument or record option, or a run refused before it starts (more samples
        or steps than ``max_steps``, or above ``MEMORY_FRACTION`` of the available
        memory); the message names the keys that set the size and the options that fit.
    SimulationError
        The integrator failed (``throw=True``), or the run was stopped early (its
        forecast steps exceed ``max_steps`` or ``STEP_BUDGET``); the message gives
        the time reached and the keys that change the outcome.

    Examples
    --------
    >>> from mechanism.core.record import SectionsRecord
    >>> from mechanism.core.scene import Scene, RigidBody, RevoluteJoint, ConstantSpeedDrive
    >>> scene = Scene(name="crank", ground_points={"O": (0.0, 0.0)},
    ...     bodies={"crank": RigidBody(mass=1.0, inertia=0.01, position=(0.05, 0.0),
    ...                                points={"O": (-0.05, 0.0)})},
    ...     joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
    ...     drive=ConstantSpeedDrive(joint="O", speed_rpm=60.0))
    >>> ds = simulate(scene, revolutions=1, output_step=0.01)
    >>> round(float(ds.crank_angle[-1]), 6)
    6.283185
    >>> strobe = simulate(scene, revolutions=3, record=SectionsRecord(discard=1))
    >>> strobe.drive_cycle.values.tolist()
    [1, 2, 3]
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    scene = validate_scene(scene)  # a scene built in Python is checked like a loaded one
    mode = record_mode(record)
    revolutions, t_end, rtol, atol, output_step = (
        x.item() if isinstance(x, np.generic) else x
        for x in (revolutions, t_end, rtol, atol, output_step)
    )  # numpy scalars read as Python numbers, also in messages
    duration = _duration(scene, revolutions, t_end)
    rtol = check_positive(scene.solver.rtol if rtol is None else rtol, name="rtol")
    atol = check_positive(scene.solver.atol if atol is None else atol, name="atol")
    text = _duration_text(scene, revolutions, t_end)
    size = _prepare(scene, mode, method, duration, output_step, text)
    y0 = _start_state(size.model, start)
    # refused before anything of the run's size is allocated
    _refuse_absurd_step_counts(size)
    if not force:
        _refuse_runs_larger_than_memory(size)
    t_out = mode.output_times(output_grid(duration, size.times.output_step), size.times)
    cpu_start = time.process_time()
    done = _integrate(size, t_out, progress=progress, force=force, start=y0, rtol=rtol, atol=atol)
    if throw:
        _raise_failure(size, done)
    attrs = _attrs(size, done, t_out, time.process_time() - cpu_start, rtol, atol)
    ds = mode.dataset(
        size.model, done.run, done.ideal_model, done.ideal_run, t_out, size.times, attrs
    )
    n = size.model.n_dof
    final = np.asarray(done.run.final_state, dtype=np.float64)
    ds.attrs["final_q"], ds.attrs["final_v"] = final[:n].copy(), final[n : 2 * n].copy()
    ds.attrs["final_time"] = float(done.run.final_time)
    return ds
