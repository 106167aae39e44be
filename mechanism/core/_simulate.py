"""``mechanism.simulate``: assemble a scene, integrate it and its ideal companion, record."""

from __future__ import annotations

import functools
import math
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import xarray as xr

from chaoskit._validate import check_positive
from mechanism.core.model._assemble import Model, assemble, initial_state
from mechanism.core.record._record import to_dataset

from ._run_checks import warn_if_deep_penetration, warn_if_large
from .integrate import Integration, Integrator, resolve_method
from .scene import AngleProfileDrive, ConstantSpeedDrive, Scene

__all__ = ["SimulationError", "drive_period", "output_grid", "simulate"]


class SimulationError(RuntimeError):
    """The integrator failed (its status and message are in the exception text)."""


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


def _max_step(model: Model, output_step: float) -> float:
    """Largest step of the main run.

    ``solver.max_step`` if set; else the output step while clearance joints are active (so
    that no impact is stepped over) and unlimited without them. (The ideal companion has
    no events at all: its step is always left to the error control, its outputs come from
    the dense output on the same grid.)
    """
    given = model.scene.solver.max_step
    if given is not None:
        return float(given)
    return float(output_step) if model.clearance_joints else math.inf


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
) -> Integration:
    return method.integrate(
        model,
        y0,
        t_out,
        rtol=rtol,
        atol=atol,
        max_step=max_step,
        projection=model.scene.solver.projection,
        progress=progress,
        label=label,
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
    progress: bool = False,
    throw: bool = True,
) -> xr.Dataset:
    """Simulate a mechanism and return its trajectory.

    The scene is assembled once (:func:`mechanism.core.model._assemble.assemble`); the initial state
    is the ideal-mechanism configuration at t = 0 with the journals at their
    ``initial_eccentricity``, at rest relative to their bearings. The equations of motion
    [M Φqᵀ; Φq 0][q̈; λ] = [Q; γ − 2αΦ̇ − β²Φ] (paper-model §2.8) are integrated with the
    chosen method; the same scene with every clearance joint ideal is integrated alongside
    (in a second thread: the compiled integrators release the GIL, so the companion adds
    no wall time when a core is free) to give the ``*_ideal`` outputs and the errors.

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
        ``"BDF"``, ``"LSODA"`` (scipy), ``"generalized-alpha"`` (implicit, adaptive),
        ``"generalized-alpha-fixed"`` (implicit, step ``solver.max_step``, else the output
        step), or an integrator object from :mod:`mechanism.core.integrate`. Default:
        ``scene.solver.method``; ``solver_method`` in the attributes names the integrator
        that ran.
    rtol, atol : float, optional
        Tolerances; default ``scene.solver``.
    output_step : float, optional
        Spacing (s) of the uniform output grid; default ``scene.solver.output_step`` or the
        drive period / 10000. The maximum step is ``scene.solver.max_step``, or by default
        this value for a mechanism with active clearance joints and unlimited for one
        without (``effects.clearance = false``); the ideal companion's step is left to the
        error control.
    progress : bool
        Show a progress bar (tqdm).
    throw : bool
        Raise :class:`SimulationError` when the integrator fails; with False, return the
        samples computed so far with ``solver_status`` < 0 and the reason in
        ``solver_message``.

    Returns
    -------
    xarray.Dataset
        Variables ``crank_angle``, ``position``/``velocity`` (time, body, axis),
        ``slider_position``/``_velocity``/``_acceleration`` and their ``*_ideal`` twins,
        ``displacement_error``, ``speed_error``, per clearance joint (dim ``joint``)
        ``eccentricity_x``/``_y``, ``penetration``, ``contact_force``, ``friction_force``,
        ``contact_angle``, ``in_contact``; ``driving_torque``; ``joint_force`` (time,
        ideal_joint); ``mechanical_energy``; ``constraint_violation``. Solver statistics in
        the ``solver_*`` attributes. See ``docs/simulator.md``.

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
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    solver = scene.solver
    duration = _duration(scene, revolutions, t_end)
    rtol = check_positive(solver.rtol if rtol is None else rtol, name="rtol")
    atol = check_positive(solver.atol if atol is None else atol, name="atol")
    period = drive_period(scene)
    if output_step is None:
        output_step = solver.output_step
    if output_step is None:
        output_step = (period if period is not None else duration) / 10000.0
    output_step = check_positive(output_step, name="output_step")
    if solver.max_step is not None:
        check_positive(solver.max_step, name="solver.max_step")
    t_out = output_grid(duration, output_step)

    model = assemble(scene)
    integrator = resolve_method(solver.method if method is None else method, model)
    max_step = _max_step(model, output_step)
    warn_if_large([model, model] if model.clearance_joints else [model], t_out.size, output_step)
    q0, v0 = initial_state(model)
    main = functools.partial(
        _run, model, integrator, np.concatenate([q0, v0]), t_out, rtol=rtol, atol=atol,
        max_step=max_step, progress=progress, label=f"{scene.name}",
    )  # fmt: skip
    if model.clearance_joints:
        ideal_model = assemble(scene, ideal=True)
        iq0, iv0 = initial_state(ideal_model, eccentricity=False)
        # The ideal companion does not depend on the main run: it runs in a second
        # thread (the compiled integrators release the GIL), so on a machine with a
        # free core it adds no wall time.
        with ThreadPoolExecutor(max_workers=1) as pool:
            ideal_future = pool.submit(
                _run, ideal_model, integrator, np.concatenate([iq0, iv0]), t_out, rtol=rtol,
                atol=atol, max_step=math.inf, progress=progress,
                label=f"{scene.name} (ideal)",
            )  # fmt: skip
            run = main()
            ideal_run = ideal_future.result()
    else:
        run = main()
        ideal_model, ideal_run = model, run
    if not run.stats.success and throw:
        t_fail = run.recording.t[-1] if run.recording.t.size else 0.0
        raise SimulationError(
            f"simulation of {scene.name!r} failed after t = {t_fail:.6g} s "
            f"({integrator.name}): {run.stats.message}"
        )
    if not ideal_run.stats.success and throw:
        raise SimulationError(
            f"simulation of the ideal mechanism of {scene.name!r} failed "
            f"({integrator.name}): {ideal_run.stats.message}"
        )
    attrs: dict[str, Any] = {
        "t_end": float(t_out[-1]),
        "output_step": float(output_step),
        "rtol": float(rtol),
        "atol": float(atol),
        "max_step": float(max_step),
        "ideal_max_step": math.inf if model.clearance_joints else float(max_step),
        "baumgarte_alpha": float(solver.baumgarte_alpha),
        "baumgarte_beta": float(solver.baumgarte_beta),
        "projection": int(bool(solver.projection)),
    }
    if period is not None:
        attrs["drive_period"] = float(period)
        attrs["revolutions"] = float(t_out[-1] / period)
    ds = to_dataset(model, run, ideal_model, ideal_run, attrs=attrs)
    warn_if_deep_penetration(ds, scene)
    if scene.effects.wear and model.clearance_joints:
        from mechanism.studies._wear_prediction import (
            add_run_wear,  # issue 7: the run's Archard wear
        )

        ds = add_run_wear(ds, scene)
    return ds
