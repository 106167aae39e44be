"""``mechanism.simulate``: assemble a scene, integrate it and its ideal companion, record."""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal, get_args

import numpy as np
import xarray as xr

from chaoskit.contract import check_choice, check_positive
from mechanism.core.model._assemble import Model, assemble, initial_state
from mechanism.core.record._record import (
    LIGHT_VARIABLES,
    light_dataset,
    metrics_dataset,
    sections_dataset,
    to_dataset,
)

from ._run_checks import warn_if_deep_penetration, warn_if_large
from .integrate import GeneralizedAlpha, Integration, Integrator, RecordPlan, resolve_method
from .scene import AngleProfileDrive, ConstantSpeedDrive, Scene
from .wear import add_run_wear

__all__ = [
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
    count = math.floor(t_end / output_step * (1.0 + 1e-12))
    if count < 1:
        raise ValueError(
            f"output_step ({output_step!r} s) must not exceed the simulated time ({t_end!r} s)."
        )
    return output_step * np.arange(count + 1, dtype=np.float64)


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
            f"got {variables!r}."
        )
    absent = {
        "crank_angle": model.crank_points is None,
        "slider_position": model.slider is None,
        "slider_velocity": model.slider is None,
        "eccentricity_x": not model.clearance_joints,
        "eccentricity_y": not model.clearance_joints,
    }
    missing = [v for v in variables if absent[v]]
    if missing:
        raise ValueError(
            f"variables {missing} are not outputs of scene {model.scene.name!r} "
            "(no crank, slider or clearance joint to measure them on)."
        )
    return tuple(dict.fromkeys(variables))


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
    record = check_choice(record, name="record", choices=RECORD_MODES)  # type: ignore[assignment]
    solver = scene.solver
    duration = _duration(scene, revolutions, t_end)
    rtol = check_positive(solver.rtol if rtol is None else rtol, name="rtol")
    atol = check_positive(solver.atol if atol is None else atol, name="atol")
    period = drive_period(scene)
    discard = check_positive(discard, name="discard", allow_zero=True)
    if isinstance(phase, bool) or not isinstance(phase, int | float) or not math.isfinite(phase):
        raise ValueError(f"phase must be a finite angle in rad; got {phase!r}.")
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
                f"got {discard!r}."
            )
    scene_step = default_step(scene, duration)
    if output_step is None:
        output_step = scene_step if record == "full" or period is None else period / 1000.0
    output_step = check_positive(output_step, name="output_step")
    if solver.max_step is not None:
        check_positive(solver.max_step, name="solver.max_step")
    t_out = output_grid(duration, output_step)
    if record == "sections":
        # run a hair past the end so the strobe at the last revolution is always taken
        # (the crank angle at t_end may fall short of it by round-off); it is kept only
        # if within the simulated revolutions
        assert period is not None
        t_out = np.append(t_out, duration + 1e-6 * period)

    model = assemble(scene)
    integrator = resolve_method(solver.method if method is None else method, model)
    max_step, approach_floor = step_limits(model, integrator, scene_step)
    light = None if variables is None else _light_variables(variables, model)
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
        sections = math.ceil(duration / period - discard) + 2 if record == "sections" else 0
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
