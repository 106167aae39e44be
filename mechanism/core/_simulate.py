"""``mechanism.simulate``: assemble a scene, integrate it and its ideal companion, record."""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Literal, get_args

import numpy as np
import psutil
import xarray as xr

from chaoskit.contract import check_choice, check_positive
from mechanism.core.model._assemble import Model, assemble, initial_state
from mechanism.core.model._kernels import LIGHT_COLUMNS
from mechanism.core.record._record import (
    LIGHT_VARIABLES,
    light_dataset,
    metrics_dataset,
    sections_dataset,
    to_dataset,
)

from ._run_checks import estimated_run_bytes, warn_if_deep_penetration, warn_if_large
from .integrate import (
    Dopri5,
    GeneralizedAlpha,
    Integration,
    Integrator,
    Recording,
    RecordPlan,
    ScipyIVP,
    resolve_method,
)
from .scene import AngleProfileDrive, ConstantSpeedDrive, Scene, validate_scene
from .wear import add_run_wear

__all__ = [
    "MEMORY_FRACTION",
    "RECORD_MODES",
    "RecordMode",
    "SimulationError",
    "default_step",
    "drive_period",
    "output_grid",
    "simulate",
    "step_limits",
]

RecordMode = Literal["full", "metrics", "sections"]
RECORD_MODES: tuple[str, ...] = get_args(RecordMode)

#: A run estimated to hold more than this fraction of the memory available when it starts
#: (``psutil.virtual_memory().available``) is refused unless ``force=True``: the rest is
#: left to the interpreter, the netCDF writer and the other processes of the machine.
MEMORY_FRACTION = 0.8


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


def _light_variables(variables: Any, model: Model) -> tuple[str, ...]:
    """Validated ``variables`` of a full record taken from the light samples."""
    ok = (
        isinstance(variables, Sequence)
        and not isinstance(variables, str)
        and len(variables) > 0
        and all(isinstance(v, str) and v in LIGHT_VARIABLES for v in variables)
    )
    if not ok:
        raise ValueError(
            f"variables must be a non-empty list of names from {list(LIGHT_VARIABLES)}; "
            f"got {_show(variables)}."
        )
    present = _available_light(model)
    missing = [v for v in variables if v not in present]
    if missing:
        raise ValueError(
            f"variables {missing} are not outputs of scene {model.scene.name!r} "
            "(no crank, slider or clearance joint to measure them on)."
        )
    return tuple(dict.fromkeys(variables))


def _available_light(model: Model) -> tuple[str, ...]:
    """The light variables ``model`` has (crank, slider and clearance joints present)."""
    absent = {
        "crank_angle": model.crank_points is None,
        "slider_position": model.slider is None,
        "slider_velocity": model.slider is None,
        "eccentricity_x": not model.clearance_joints,
        "eccentricity_y": not model.clearance_joints,
    }
    return tuple(v for v in LIGHT_VARIABLES if not absent.get(v, False))


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
    and acceleration (:func:`~mechanism.core.model._kernels.approach_step`), and never
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
class _RunSize:
    """What a run will hold and take, estimated before anything large is allocated."""

    model: Model
    integrator: Integrator
    duration: float  # s
    n_out: int  # output grid samples
    output_step: float  # s
    output_key: str  # the key that set the output step and its value, for messages
    output_fix: str  # the option that changes it
    largest_step: float  # s; inf: the error control's
    step_key: str  # the key that set the largest step and its value
    step_fix: str  # the option that changes it
    record: str
    light: tuple[str, ...] | None
    companion: bool
    sections: int
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
    scene: Scene, record: str, given: float | None, scene_step: float
) -> tuple[float, str, str]:
    """The output step of a run (s), the key that set it with its value, and the option
    that changes it."""
    period = drive_period(scene)
    if given is not None:
        step = check_positive(given, name="output_step")
        return step, f"output_step = {step:g} s", "output_step (--output-step)"
    if record == "full" or period is None:
        fix = "solver.output_step (or pass output_step, --output-step)"
        return scene_step, _scene_step_text(scene, scene_step), fix
    step = period / 1000.0
    text = f"the default output_step (drive period / 1000) = {step:g} s"
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


def _bytes(size: _RunSize, *, n_out: int, record: str, light: tuple[str, ...] | None) -> int:
    """Memory (bytes) a run holds at its end for the given record (estimate, no allocation)."""
    model = size.model
    runs = 2 if model.clearance_joints and size.companion and light is None else 1
    light_row = 8 * (LIGHT_COLUMNS + 2 * len(model.clearance_joints))
    grid = 8 * n_out  # the output times
    if light is not None:  # the light samples of the run and the Dataset's variables
        return grid + n_out * (light_row + 8 * len(light))
    if record == "full":
        return grid + estimated_run_bytes([model] * runs, n_out)
    sample = sum(a.nbytes for a in Recording.empty(model, 1))
    # light samples of each run, and the sections recorded and then stored
    return grid + runs * n_out * light_row + (runs + 1) * size.sections * sample


def _refuse_absurd_step_counts(size: _RunSize) -> None:
    """Refuse a run whose output grid or step count exceeds the default step limit of the
    compiled integrators (an integrator built with a smaller ``max_steps`` still runs and
    fails as data when it reaches it)."""
    limit = Dopri5().max_steps
    steps = size.duration / size.largest_step
    if size.n_out > limit:
        raise ValueError(
            f"the output grid would hold {size.n_out:.3g} samples ({size.duration_text}, "
            f"{size.duration:.3g} s, at {size.output_key}), more than the {limit:.3g} steps "
            f"an integrator may take (max_steps; each sample costs about a step): raise "
            f"{size.output_fix}, or simulate less time."
        )
    if steps > limit:
        raise ValueError(
            f"the run would take at least {steps:.3g} steps ({size.duration_text}, "
            f"{size.duration:.3g} s, at {size.step_key}), more than the {limit:.3g} an "
            f"integrator may take (max_steps): it would fail after hours; raise "
            f"{size.step_fix}, or simulate less time."
        )


def _refuse_runs_larger_than_memory(size: _RunSize, period: float | None) -> None:
    """Refuse a run estimated above :data:`MEMORY_FRACTION` of the available memory."""
    nbytes = _bytes(size, n_out=size.n_out, record=size.record, light=size.light)
    available = int(psutil.virtual_memory().available)
    budget = MEMORY_FRACTION * available
    if nbytes <= budget:
        return
    fits = [f"output_step >= {_round_up(size.output_step * nbytes / budget)} s (--output-step)"]
    if size.record == "full" and size.light is None:
        light = _available_light(size.model)
        if light and _bytes(size, n_out=size.n_out, record="full", light=light) <= budget:
            fits.append(f"variables={list(light)} (--var; light samples only)")
        if period is not None:
            grid = _grid_count(size.duration, period / 1000.0)
            if _bytes(size, n_out=grid, record="metrics", light=None) <= budget:
                fits.append("record='metrics' or 'sections' (--record)")
    raise ValueError(
        f"this run would hold about {_size(nbytes)} ({size.n_out:.3g} samples of the "
        f"{size.record} record at {size.output_key}, {size.duration_text}), more than the "
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
) -> Integration:
    return method.integrate(
        model,
        y0,
        t_out,
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        approach_floor=approach_floor,
        projection=model.scene.solver.projection,
        progress=progress,
        label=label,
        record=record,
    )


def simulate(
    scene: Scene,
    *,
    revolutions: float | None = None,
    t_end: float | None = None,
    method: str | Integrator | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    record: RecordMode = "full",
    discard: float = 0.0,
    phase: float = 0.0,
    variables: Sequence[str] | None = None,
    companion: bool = True,
    progress: bool = False,
    throw: bool = True,
    force: bool = False,
) -> xr.Dataset:
    """Simulate a mechanism and return its trajectory, its response metrics or its
    stroboscopic section.

    The scene is assembled once (:func:`mechanism.core.model._assemble.assemble`); the initial state
    is the ideal-mechanism configuration at t = 0 with the journals at their
    ``initial_eccentricity``, at rest relative to their bearings. The equations of motion
    [M Φqᵀ; Φq 0][q̈; λ] = [Q; γ − 2αΦ̇ − β²Φ] (docs/paper-model.md §7) are integrated with the
    chosen method; the same scene with every clearance joint ideal is integrated alongside
    (in a second thread: the compiled integrators release the GIL, so the companion adds
    no wall time when a core is free) to give the ``*_ideal`` outputs and the errors.

    What is recorded does not change the integration: the step sequence, and so every
    recorded value, is the same whatever ``record`` and ``output_step`` are.

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
        ``"auto"`` (the scene default: fixed-step generalized-α when the assembled model
        has ANCF beams, i.e. ``effects.flexibility`` is on, else ``"dopri5"``),
        ``"dopri5"`` (compiled Dormand–Prince 5(4)), ``"RK45"``, ``"DOP853"``, ``"Radau"``,
        ``"BDF"``, ``"LSODA"`` (scipy; full record only), ``"generalized-alpha"``
        (implicit, adaptive), ``"generalized-alpha-fixed"`` (implicit, step
        ``solver.max_step``, else the scene's default output step), or an integrator
        object from :mod:`mechanism.core.integrate`. Default: ``scene.solver.method``;
        ``solver_method`` in the attributes names the integrator that ran.
    rtol, atol : float, optional
        Tolerances; default ``scene.solver``.
    output_step : float, optional
        Spacing (s) of the uniform output grid. ``record="full"``: the trajectory's
        samples, default ``scene.solver.output_step`` or the drive period / 10000.
        ``"metrics"`` and ``"sections"``: the grid on which the slider is compared with the
        ideal mechanism (``max_displacement_error``, ``max_speed_error``; nothing else is
        stored), default the drive period / 1000. The grid does not bound the step
        (:func:`step_limits`: ``scene.solver.max_step`` if set, else with clearance joints
        the journals' approach to their walls, never below the scene's default output
        step ``solver.output_step`` or the drive period / 10000), whatever grid is asked
        for.
    record : {"full", "metrics", "sections"}
        ``"full"``: the trajectory on the output grid (below). ``"metrics"``: the response
        metrics of ``mechanism._metrics.METRICS`` over the time after ``discard``
        revolutions, with peak contact force, penetration and driving torque taken at
        every accepted integrator state (not on a grid), as scalar variables.
        ``"sections"``: the metrics and the stroboscopic points — every variable of the
        full record, sampled where the crank angle passes ``phase`` + 2πk after
        ``discard`` revolutions, located on the integrator's dense output (not
        interpolated from a grid) — along the dimension ``crossing``.
    discard : float
        Revolutions treated as transient by ``"metrics"`` and ``"sections"`` (≥ 0, less
        than the simulated revolutions); must be 0 for ``"full"`` (slice the trajectory).
    phase : float
        Strobe phase (rad) of ``"sections"``.
    variables : sequence of str, optional
        ``record="full"`` only: record just these variables on the output grid, names
        from ``crank_angle``, ``slider_position``, ``slider_velocity``,
        ``eccentricity_x``, ``eccentricity_y``. They are read from
        the integrator's dense output without a right-hand-side evaluation and the ideal
        companion is not run, so a long run at a fine grid holds a few arrays of the
        grid's length instead of the full state (the chaos runs of the paper study:
        201 revolutions at T/1000 of the flexible paper scene, 9.6 MB instead of about
        2.3 GB) and costs about half the CPU time of a full record with flexible rods.
        The integration, and so every recorded value, is the same as with the full record.
    companion : bool
        Integrate the ideal companion (the ``*_ideal`` outputs and the errors against the
        ideal mechanism; default). False, for ``record="metrics"`` or ``"sections"`` only,
        leaves it out: ``max_displacement_error`` and ``max_speed_error`` are then NaN, and
        the run costs what the mechanism with clearance costs — at rtol = atol = 1e-8 the
        rigid paper scene's companion adds a third at 150 rpm and two thirds at 30 rpm,
        the orbit diagrams' case (:func:`mechanism.bifurcation` never runs it).
    progress : bool
        Show a progress bar (tqdm).
    throw : bool
        Raise :class:`SimulationError` when the integrator fails; with False, return the
        samples computed so far with ``solver_status`` < 0 and the reason in
        ``solver_message``.
    force : bool
        Run even when the run is estimated to hold more than :data:`MEMORY_FRACTION` of
        the memory available (default False: refused up front, see Raises).

    Returns
    -------
    xarray.Dataset
        ``record="full"``: variables ``crank_angle``, ``position``/``velocity`` (time, body,
        axis), ``slider_position``/``_velocity``/``_acceleration`` and their ``*_ideal``
        twins, ``displacement_error``, ``speed_error``, per clearance joint (dim ``joint``)
        ``eccentricity_x``/``_y``, ``penetration``, ``contact_force``,
        ``friction_force``, ``contact_angle``, ``in_contact``; ``driving_torque``;
        ``joint_force`` (time, ideal_joint); ``mechanical_energy``;
        ``constraint_violation``. ``"sections"``: the same variables (without the
        ideal twins and errors) along ``crossing`` with coordinates ``time`` and
        ``drive_cycle`` (the layout of :func:`chaoskit.stroboscopic_map`), plus the
        metrics. ``"metrics"``: the metrics. Solver statistics in the ``solver_*``
        attributes, the mode in ``record``. See ``docs/simulator.md``.

    Raises
    ------
    mechanism.SceneError
        The scene is invalid (it is validated here too, for scenes built in Python).
    ValueError
        A bad argument, or a run refused before it starts (``docs/simulator.md``, *Runs
        refused up front*): more output samples, or more steps at the largest step the
        solver may take, than the compiled integrators' default ``max_steps`` (2e8); or
        an estimated memory
        above :data:`MEMORY_FRACTION` of the available memory, unless ``force=True``. The
        message names the keys that set the size and the options that fit.
    SimulationError
        The integrator failed (``throw=True``).

    Examples
    --------
    >>> from mechanism.core.scene import Scene, RigidBody, RevoluteJoint, ConstantSpeedDrive
    >>> scene = Scene(name="crank", ground_points={"O": (0.0, 0.0)},
    ...     bodies={"crank": RigidBody(mass=1.0, inertia=0.01, position=(0.05, 0.0),
    ...                                points={"O": (-0.05, 0.0)})},
    ...     joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
    ...     drive=ConstantSpeedDrive(joint="O", speed_rpm=60.0))
    >>> ds = simulate(scene, revolutions=1, output_step=0.01)
    >>> round(float(ds.crank_angle[-1]), 6)
    6.283185
    >>> strobe = simulate(scene, revolutions=3, record="sections", discard=1)
    >>> strobe.drive_cycle.values.tolist()
    [1, 2, 3]
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    scene = validate_scene(scene)  # a scene built in Python is checked like a loaded one
    record = check_choice(record, name="record", choices=RECORD_MODES)  # type: ignore[assignment]
    solver = scene.solver
    revolutions, t_end, rtol, atol, discard, output_step = (
        x.item() if isinstance(x, np.generic) else x
        for x in (revolutions, t_end, rtol, atol, discard, output_step)
    )  # numpy scalars read as Python numbers, also in messages
    duration = _duration(scene, revolutions, t_end)
    rtol = check_positive(solver.rtol if rtol is None else rtol, name="rtol")
    atol = check_positive(solver.atol if atol is None else atol, name="atol")
    period = drive_period(scene)
    discard = check_positive(discard, name="discard", allow_zero=True)
    if isinstance(phase, bool) or not isinstance(phase, int | float) or not math.isfinite(phase):
        raise ValueError(f"phase must be a finite angle in rad; got {_show(phase)}.")
    phase = float(phase)
    if variables is not None and record != "full":
        raise ValueError(
            f"variables applies to record='full' only; got record={record!r} "
            "(the section and metrics records choose their own variables)."
        )
    if not companion and record == "full" and variables is None:
        raise ValueError(
            "companion=False applies to record='metrics' and 'sections' (the full record "
            "holds the ideal mechanism's twins; variables=... records without it)."
        )
    if record == "full" and discard != 0.0:
        raise ValueError(
            "discard applies to record='metrics' and 'sections'; slice the full trajectory."
        )
    if record != "full":
        if period is None:
            raise ValueError(
                f"record={record!r} needs a periodic drive (its revolutions and sections); "
                "use record='full'."
            )
        if not discard * period < duration:
            raise ValueError(
                f"discard must be below the simulated {duration / period:g} revolutions; "
                f"got {discard:g}."
            )
    scene_step = default_step(scene, duration)
    output_step, output_text, output_fix = _output_step(scene, record, output_step, scene_step)
    n_out = _grid_count(duration, output_step)

    model = assemble(scene)
    integrator = resolve_method(solver.method if method is None else method, model)
    max_step, approach_floor = step_limits(model, integrator, scene_step)
    light = None if variables is None else _light_variables(variables, model)
    largest, largest_text, largest_fix = _step_keys(
        scene, integrator, max_step, approach_floor, _scene_step_text(scene, scene_step)
    )
    sections = math.ceil(duration / period - discard) + 2 if record == "sections" and period else 0
    size = _RunSize(
        model=model, integrator=integrator, duration=duration, n_out=n_out,
        output_step=output_step, output_key=output_text, output_fix=output_fix,
        largest_step=largest, step_key=largest_text, step_fix=largest_fix, record=record,
        light=light, companion=companion, sections=sections,
        duration_text=_duration_text(scene, revolutions, t_end),
    )  # fmt: skip
    # refused before anything of the run's size is allocated
    _refuse_absurd_step_counts(size)
    if not force:
        _refuse_runs_larger_than_memory(size, period)
    t_out = output_grid(duration, output_step)
    if record == "sections":
        # run a hair past the end so the strobe at the last revolution is always taken
        # (the crank angle at t_end may fall short of it by round-off); it is kept only
        # if within the simulated revolutions
        assert period is not None
        t_out = np.append(t_out, duration + 1e-6 * period)
    if light is not None:
        # the named variables from the dense output alone; no ideal companion
        plan = ideal_plan = RecordPlan(grid="light")
    elif record == "full":
        plan = ideal_plan = RecordPlan()
        models = [model, model] if model.clearance_joints else [model]
        warn_if_large(models, t_out.size, output_step)
    else:
        assert period is not None
        window = discard * period
        # contact steps longer than the default output step are sampled inside, so the
        # extremes resolve an impact at least as finely as the default full record
        plan = RecordPlan(
            grid="light", sections=sections, phase=phase, discard=discard, metrics_from=window,
            peak_step=scene_step,
        )  # fmt: skip
        ideal_plan = RecordPlan(grid="light")
    q0, v0 = initial_state(model)
    cpu_start = time.process_time()
    main = functools.partial(
        _run, model, integrator, np.concatenate([q0, v0]), t_out, rtol=rtol, atol=atol,
        max_step=max_step, progress=progress, label=f"{scene.name}", record=plan,
        approach_floor=approach_floor,
    )  # fmt: skip
    ideal_run: Integration | None
    if model.clearance_joints and light is None and companion:
        ideal_model = assemble(scene, ideal=True)
        iq0, iv0 = initial_state(ideal_model, eccentricity=False)
        # the companion has no impacts: its step is the error control's (the fixed-step
        # generalized-α keeps the main run's step), as for an ideal mechanism on its own
        ideal_max_step = max_step if _fixed_step(integrator) else math.inf
        # The ideal companion does not depend on the main run: it runs in a second
        # thread (the compiled integrators release the GIL), so on a machine with a
        # free core it adds no wall time.
        with ThreadPoolExecutor(max_workers=1) as pool:
            ideal_future = pool.submit(
                _run, ideal_model, integrator, np.concatenate([iq0, iv0]), t_out, rtol=rtol,
                atol=atol, max_step=ideal_max_step, progress=progress,
                label=f"{scene.name} (ideal)", record=ideal_plan,
            )  # fmt: skip
            run = main()
            ideal_run = ideal_future.result()
    else:
        run = main()
        # without clearance joints the run is its own ideal mechanism; without the
        # companion there is none (the errors are NaN)
        ideal_model = model
        ideal_run = run if not model.clearance_joints else None
        ideal_max_step = max_step
    if not run.stats.success and throw:
        t_fail = run.final_time
        raise SimulationError(
            f"simulation of {scene.name!r} failed after t = {t_fail:.6g} s "
            f"({integrator.name}): {run.stats.message}",
            time=t_fail,
        )
    if ideal_run is not None and not ideal_run.stats.success and throw:
        raise SimulationError(
            f"simulation of the ideal mechanism of {scene.name!r} failed "
            f"({integrator.name}): {ideal_run.stats.message}"
        )
    attrs: dict[str, Any] = {
        # CPU seconds of this process during the two integrations (the one-core cost)
        "solver_cpu_time": time.process_time() - cpu_start,
        "record": record,
        "t_end": float(t_out[-1]) if record == "full" else float(duration),
        "output_step": float(output_step),
        "rtol": float(rtol),
        "atol": float(atol),
        "max_step": float(max_step),
        "approach_floor": float(approach_floor),
        "ideal_max_step": float(ideal_max_step),
        "baumgarte_alpha": float(solver.baumgarte_alpha),
        "baumgarte_beta": float(solver.baumgarte_beta),
        "projection": int(bool(solver.projection)),
    }
    if period is not None:
        attrs["drive_period"] = float(period)
        attrs["revolutions"] = float(attrs["t_end"] / period)
    if light is not None or ideal_run is None:
        del attrs["ideal_max_step"]
    if light is not None:
        attrs["variables"] = ", ".join(light)
        return light_dataset(model, run, t_out, light, attrs=attrs)
    if record == "full":
        ds = to_dataset(model, run, ideal_model, ideal_run, attrs=attrs)
        warn_if_deep_penetration(ds, scene)
    else:
        assert period is not None
        attrs["discard_revolutions"] = float(discard)
        ds = metrics_dataset(model, run, ideal_run, t_out, window=discard * period, attrs=attrs)
        if record == "sections":
            ds = sections_dataset(model, run, ideal_run, metrics=ds, phase=phase, attrs=attrs)
            ds = ds.isel(crossing=ds["time"].values <= duration * (1.0 + 1e-9))
        return ds
    if scene.effects.wear and model.clearance_joints:
        ds = add_run_wear(ds, scene)
    return ds
