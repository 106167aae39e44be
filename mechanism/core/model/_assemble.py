"""Assembly: a :class:`~mechanism.core.scene.Scene` compiled once into contiguous arrays,
and the consistent initial state of the assembled mechanism.

The time loop never sees the scene; it evaluates the kernels of
``mechanism.core.model._kernels`` on the :class:`~mechanism.core.model.KernelModel` tables
built from it (``_tables.py`` describes them: coordinates, points, mass, constraints,
clearance joints).

Examples
--------
>>> from mechanism.core.scene import Scene, RigidBody, RevoluteJoint, ConstantSpeedDrive
>>> scene = Scene(name="crank", ground_points={"O": (0.0, 0.0)},
...     bodies={"crank": RigidBody(mass=1.0, inertia=0.01, position=(0.05, 0.0),
...                                points={"O": (-0.05, 0.0)})},
...     joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
...     drive=ConstantSpeedDrive(joint="O", speed_rpm=60.0))
>>> model = assemble(scene)
>>> model.n_dof, model.n_rows, model.dof_names[2]
(3, 3, 'crank.theta')
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mechanism.core.bodies import AncfLayout, RigidLayout
from mechanism.core.forces import force_tables, motor_speed_row
from mechanism.core.scene import Scene

from . import _kernels as model_kernels

# numba's cache index names the types of compiled arguments by the module that defined
# them, and is unpickled whole before its freshness is checked: these tables were defined
# here, so an index written by an older source (another process) must still find them here
from ._compiled import KernelModel as KernelModel
from ._compiled import Model, with_effect_switches
from ._compiled import Workspace as Workspace
from ._tables import (
    TableBuilder,
    body_layouts,
    drive_rows,
    joint_tables,
    kernel_model,
    mass_tables,
    output_crank_points,
    slider_map,
)

__all__ = ["assemble", "initial_state"]


def assemble(scene: Scene, *, ideal: bool = False, eccentricity_offsets: bool = False) -> Model:
    """Compile a scene into a :class:`Model`.

    The steps: lay out the bodies' coordinates (:func:`mass_tables`), turn every joint into
    constraint rows or a clearance-joint row (:func:`joint_tables`), add the drive and the
    output points (:func:`drive_rows`, :func:`output_crank_points`, :func:`slider_map`), and
    pack everything into the flat arrays of a :class:`KernelModel` (:func:`kernel_model`).

    Parameters
    ----------
    scene
        The mechanism.
    ideal
        Treat every clearance joint as an ideal revolute (the *ideal mechanism* of the
        outputs ``*_ideal``). ``effects.clearance = False`` has the same effect.
    eccentricity_offsets
        With ``ideal``: the ideal revolute keeps the journal at the clearance joint's
        ``initial_eccentricity`` from the bearing (used to assemble the initial state).

    Returns
    -------
    Model

    Raises
    ------
    ValueError
        Naming the joint or body whose reference is invalid.
    """
    layouts = body_layouts(scene)
    offsets: dict[str, int] = {}
    n = 0
    for lay in layouts:
        offsets[lay.name] = n
        n += lay.n_dof
    if n == 0:
        raise ValueError("the scene has no bodies.")
    mass = mass_tables(scene, layouts, offsets, n)
    b = TableBuilder(scene, layouts, offsets)
    joints = joint_tables(
        scene,
        b,
        {lay.name: lay for lay in layouts},
        use_clearance=scene.effects.clearance and not ideal,
        eccentricity_offsets=eccentricity_offsets,
    )
    drive = drive_rows(scene, b)
    crank_points = output_crank_points(scene, b, drive.crank_points)
    slider = slider_map(scene, b)
    # after every joint's points, so a scene without force elements keeps its point table
    forces = force_tables(scene, b.point)
    if b.rows > n:
        raise ValueError(
            f"the scene has {b.rows} constraint equations for {n} coordinates; it is "
            "over-constrained (remove a redundant joint)."
        )
    kernel = kernel_model(
        scene, layouts, offsets, mass, b, joints, drive, crank_points, slider, forces
    )
    # the kernels compile only the effects the scene has (docs/performance.md, "Compiling")
    kernel = with_effect_switches(kernel, scene)
    return Model(
        scene=scene,
        kernel=kernel,
        body_names=tuple(lay.name for lay in layouts),
        body_offsets=tuple(offsets[lay.name] for lay in layouts),
        rigid_bodies=tuple(lay.name for lay in layouts if isinstance(lay, RigidLayout)),
        beams={lay.name: lay for lay in layouts if isinstance(lay, AncfLayout)},
        dof_names=tuple(mass.dof_names),
        point_index=dict(b.point_index),
        ideal_joints=tuple(joints.ideal_rows),
        clearance_joints=tuple(joints.clearance_names),
        force_elements=forces.names,
        drive_row=drive.row,
        crank_points=crank_points,
        slider=slider,
        q_guess=mass.q_guess,
    )


def initial_state(
    model: Model,
    *,
    t0: float = 0.0,
    eccentricity: bool = True,
    tol: float = 1e-12,
    max_iter: int = 50,
) -> tuple[np.ndarray, np.ndarray]:
    """Consistent initial positions and velocities of ``model``'s scene.

    Positions: Newton on Φ(q, t₀) = 0 from the scene's pose guesses with the minimum-norm
    step Δq = −Φq⁺Φ, on the mechanism whose clearance joints are ideal revolutes holding
    their ``initial_eccentricity``. Velocities: the minimum-kinetic-energy solution of
    Φq q̇ = −Φt (unique when the drive makes the ideal mechanism determinate), i.e. the
    ideal-mechanism velocities with the journal at rest relative to the bearing; a motor
    drive's ``initial_speed_rpm`` adds the condition that its joint turns at that speed.
    ``eccentricity=False`` centres every journal (the ideal mechanism).

    With flexible ANCF beams the state is that of the rigid mechanism
    (``effects.flexibility = False``) mapped onto straight, unstressed beams moving
    rigidly (:meth:`~mechanism.core.bodies.AncfLayout.from_rigid_state`), plus each beam's
    ``initial_sine_velocities``; the minimum-norm velocity projection would give
    interior nodes a non-rigid velocity field that excites the axial modes.

    Returns
    -------
    (q0, v0) : tuple of numpy.ndarray

    Raises
    ------
    ValueError
        If the constraints cannot be satisfied from the guesses.
    """
    if model.beams:
        return _flexible_initial_state(
            model, t0=t0, eccentricity=eccentricity, tol=tol, max_iter=max_iter
        )
    assembly = assemble(model.scene, ideal=True, eccentricity_offsets=eccentricity)
    km = assembly.kernel
    ws = assembly.workspace()
    q = model.q_guess.copy()
    v = np.zeros_like(q)
    m = km.n_rows
    if m == 0:
        return q, v
    err = np.inf
    for _ in range(max_iter):
        model_kernels.evaluate_constraints(km, ws, t0, q, v)
        err = float(np.max(np.abs(ws.phi)))
        if err < tol:
            break
        dq = np.linalg.lstsq(ws.phiq, -ws.phi, rcond=None)[0]
        q += dq
    else:
        model_kernels.evaluate_constraints(km, ws, t0, q, v)
        err = float(np.max(np.abs(ws.phi)))
    if not err < max(tol, 1e-9):
        raise ValueError(
            f"the scene's joints cannot be assembled from its pose guesses (largest constraint "
            f"violation {err:.3g} after {max_iter} Newton iterations); check the body "
            "positions, angles and joint points."
        )
    model_kernels.evaluate_constraints(km, ws, t0, q, v)
    phiq, phit = ws.phiq.copy(), ws.phit.copy()
    speed = motor_speed_row(model.scene, model.body_names, model.body_offsets, q.size)
    if speed is not None:  # a motor started at its initial speed: r · q̇ = ω
        phiq, phit = np.vstack([phiq, speed[0]]), np.append(phit, -speed[1])
    w = km.minv @ phiq.T
    s = phiq @ w
    lam = np.linalg.lstsq(s, phit, rcond=None)[0]
    v = -w @ lam
    return q, v


def _flexible_initial_state(
    model: Model, *, t0: float, eccentricity: bool, tol: float, max_iter: int
) -> tuple[np.ndarray, np.ndarray]:
    """Rigid-mechanism initial state mapped onto the ANCF beams (docs/ancf.md §6.6)."""
    scene = model.scene
    rigid_scene = dataclasses.replace(
        scene, effects=dataclasses.replace(scene.effects, flexibility=False)
    )
    rigid = assemble(rigid_scene)
    qr, vr = initial_state(rigid, t0=t0, eccentricity=eccentricity, tol=tol, max_iter=max_iter)
    rigid_offsets = dict(zip(rigid.body_names, rigid.body_offsets, strict=True))
    q = np.zeros(model.n_dof)
    v = np.zeros(model.n_dof)
    for name, o in zip(model.body_names, model.body_offsets, strict=True):
        r = rigid_offsets[name]
        layout = model.beams.get(name)
        if layout is None:
            q[o : o + 3] = qr[r : r + 3]
            v[o : o + 3] = vr[r : r + 3]
            continue
        e, e_dot = layout.from_rigid_state(qr[r : r + 2], qr[r + 2], vr[r : r + 2], vr[r + 2])
        amplitudes = layout.beam.initial_sine_velocities
        if amplitudes:
            e_dot = e_dot + layout.mesh.sine_modes(amplitudes, angle=float(qr[r + 2]))
        q[o : o + layout.n_dof] = e
        v[o : o + layout.n_dof] = e_dot
    return q, v
