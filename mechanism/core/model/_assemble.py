"""Assembly: a :class:`~mechanism.core.scene.Scene` compiled once into contiguous arrays.

The time loop never sees the scene; it evaluates the kernels of ``mechanism.core.model._kernels`` on
the :class:`KernelModel` tables built here:

* **coordinates** — each body owns a contiguous slice of q starting at its offset: a rigid
  body (x, y, θ) of its centre of mass (docs/paper-model.md §3); an ANCF beam  4 DOF
  per node. Everything else addresses coordinates through *points*.
* **points** — ground points, rigid-body points (offset + local vector, nonlinear in θ)
  and linear points (weighted node positions of a flexible body); see
  ``mechanism.core.joints._kernels`` for the table layout.
* **mass** — the constant block-diagonal mass matrix, its inverse (used for the Schur
  complement of the equations of motion) and the per-coordinate block bounds.
* **constraints** — ideal joints as primitive rows (coincident points, relative angle,
  normal distance, driven angle), a clearance joint as a force element (or, with
  ``effects.clearance = False``, as an ideal revolute: no contact code at all).
* **clearance joints** — bearing/journal points, radii, contact and friction laws.

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
import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from mechanism.core.bodies import (
    BEAM_F_COLUMNS,
    BEAM_I_COLUMNS,
    AncfLayout,
    RigidLayout,
    rigid_bar_from_beam,
)
from mechanism.core.contact import contact_parameters
from mechanism.core.joints import (
    ANGLE_NONE,
    CON_ANGLE,
    CON_COINCIDE,
    CON_DRIVE,
    CON_NORMAL,
    CON_ROWS,
    DRIVE_CONSTANT_SPEED,
    DRIVE_NONE,
    DRIVE_PROFILE,
    PCF_COLUMNS,
    PCI_COLUMNS,
    POINT_GROUND,
)
from mechanism.core.scene import (
    GROUND,
    AncfBeam,
    AngleProfileDrive,
    ClearanceRevolute,
    ConstantSpeedDrive,
    FixedJoint,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    Scene,
)
from mechanism.core.wear import WornProfile
from mechanism.core.wear import kernels as wk

from . import _kernels as k

__all__ = ["KernelModel", "Model", "Workspace", "assemble", "initial_state"]


class KernelModel(NamedTuple):
    """The arrays the compiled kernels read (contiguous int64 / float64)."""

    n_dof: int
    n_rows: int
    mass: np.ndarray  # (n, n) constant mass matrix
    minv: np.ndarray  # (n, n) its inverse (block diagonal)
    blk_lo: np.ndarray  # (n,) first coordinate of the mass block of coordinate i
    blk_hi: np.ndarray  # (n,) one past its last coordinate
    gravity_force: np.ndarray  # (n,) constant generalised gravity
    pt_i: np.ndarray
    pt_f: np.ndarray
    con_i: np.ndarray
    con_f: np.ndarray
    drive_i: np.ndarray  # [kind, constraint index]
    drive_f: np.ndarray  # [θ₀, ω, period, ramp per period]
    spline_x: np.ndarray
    spline_c: np.ndarray
    cj_i: np.ndarray  # (n_cj, 4) [bearing point, journal point, law code, friction code]
    cj_f: np.ndarray  # (n_cj, CF_COLUMNS)
    cw_i: np.ndarray  # (n_cj, CW_COLUMNS) worn-profile layout
    cw_f: np.ndarray  # (n_cj, 2) [E*, radius ratio limit]
    cw_h: np.ndarray  # flat wear depths (m) of all worn surfaces
    cw_k: np.ndarray  # flat tabulated curvatures (1/m) of the same regions
    out_i: np.ndarray  # [crank point a, crank point b, guide point, slider point] (−1: none)
    out_f: np.ndarray  # [ux, uy] slider guide axis in the guide body's frame
    jt_i: np.ndarray  # (n_ideal, 3) [JOINT_PIN | JOINT_PRISMATIC, first row, guide point]
    jt_f: np.ndarray  # (n_ideal, 2) prismatic guide normal in the guide body's frame
    alpha: float
    beta: float
    # flexible bodies : one row per ANCF beam, see ``beams_force_add``
    beam_i: np.ndarray  # (n_beams, BEAM_I_COLUMNS) int64
    beam_f: np.ndarray  # (n_beams, BEAM_F_COLUMNS) float64


class Workspace(NamedTuple):
    """Scratch arrays of one right-hand-side evaluation (allocated once per run)."""

    phi: np.ndarray
    phiq: np.ndarray
    phit: np.ndarray
    gam: np.ndarray
    gen: np.ndarray
    a0: np.ndarray
    w: np.ndarray
    s: np.ndarray
    lam: np.ndarray
    cj: np.ndarray
    pci: np.ndarray
    pcf: np.ndarray
    nz_n: np.ndarray
    nz_j: np.ndarray


@dataclass(frozen=True, kw_only=True)
class IdealJointRows:
    """Where an ideal joint's reaction lives in λ.

    ``kind``: ``"revolute"`` (rows r, r+1 = force on ``bodies[1]`` in x, y),
    ``"prismatic"`` (row r = relative angle → reaction moment, r+1 = normal force),
    ``"fixed"`` (r, r+1 force, r+2 moment). ``normal`` is the guide normal in the frame
    of ``bodies[0]`` for prismatic joints.
    """

    name: str
    kind: str
    row: int
    normal: tuple[float, float] = (0.0, 0.0)
    guide_point: int = -1


@dataclass(frozen=True, kw_only=True)
class SliderMap:
    """Slider output of a prismatic joint: s = u·(r_b − r_a), u = A(θ_a) ū."""

    joint: str
    guide_point: int
    slider_point: int
    axis: tuple[float, float]


@dataclass(frozen=True, kw_only=True)
class Model:
    """A scene compiled for the time loop (immutable; arrays are not to be modified).

    Attributes
    ----------
    scene : Scene
        The scene it was assembled from.
    kernel : KernelModel
        The compiled tables.
    body_names, body_offsets
        Bodies in coordinate order and the index of each body's first coordinate.
    rigid_bodies
        Names of the bodies with (x, y, θ) coordinates (outputs ``position``/``velocity``).
    beams
        Layout of every flexible ANCF beam by body name (empty when
        ``effects.flexibility`` is off); its coordinates start at its body offset.
    dof_names
        ``"body.coordinate"`` for every coordinate.
    ideal_joints
        Reaction layout of every ideal joint (including clearance joints made ideal).
    clearance_joints
        Names of the clearance joints that act through contact forces (empty when
        ``effects.clearance`` is off).
    drive_row
        Row of the driving constraint in λ (driving torque T = −λ), or None.
    crank_points
        (point a, point b) whose relative angle is the crank angle, or None.
    slider
        Slider output map, or None.
    q_guess
        Initial coordinates from the scene's pose guesses.
    """

    scene: Scene
    kernel: KernelModel
    body_names: tuple[str, ...]
    body_offsets: tuple[int, ...]
    rigid_bodies: tuple[str, ...]
    beams: dict[str, AncfLayout]
    dof_names: tuple[str, ...]
    point_index: dict[tuple[str, str], int]
    ideal_joints: tuple[IdealJointRows, ...]
    clearance_joints: tuple[str, ...]
    drive_row: int | None
    crank_points: tuple[int, int] | None
    slider: SliderMap | None
    q_guess: np.ndarray

    @property
    def n_dof(self) -> int:
        return self.kernel.n_dof

    @property
    def n_rows(self) -> int:
        return self.kernel.n_rows

    def workspace(self) -> Workspace:
        """Fresh scratch arrays for the kernels."""
        n = self.n_dof
        m = self.n_rows
        n_points = self.kernel.pt_i.shape[0]
        return Workspace(
            phi=np.zeros(m),
            phiq=np.zeros((m, n)),
            phit=np.zeros(m),
            gam=np.zeros(m),
            gen=np.zeros(n),
            a0=np.zeros(n),
            w=np.zeros((n, m)),
            s=np.zeros((m, m)),
            lam=np.zeros(m),
            cj=np.zeros((self.kernel.cj_i.shape[0], k.CJ_COLUMNS)),
            pci=np.zeros((n_points, PCI_COLUMNS), dtype=np.int64),
            pcf=np.zeros((n_points, PCF_COLUMNS)),
            nz_n=np.zeros(m, dtype=np.int64),
            nz_j=np.zeros((m, n), dtype=np.int64),
        )


def _layouts(scene: Scene) -> list[Any]:
    layouts: list[Any] = []
    for name, body in scene.bodies.items():
        if name == GROUND:
            raise ValueError(f"bodies.{GROUND} is reserved for the frame; rename that body.")
        if isinstance(body, RigidBody):
            layouts.append(RigidLayout(name=name, body=body))
        elif isinstance(body, AncfBeam):
            if scene.effects.flexibility:
                layouts.append(
                    AncfLayout(
                        name=name,
                        beam=body,
                        axial_strain=body.axial_strain,
                        curvature=body.curvature,
                    )
                )
            else:
                layouts.append(RigidLayout(name=name, body=rigid_bar_from_beam(body)))
        else:
            raise TypeError(f"bodies.{name}: unsupported body type {type(body).__name__}.")
    return layouts


class _Builder:
    """Accumulates the point and constraint tables."""

    def __init__(self, scene: Scene, layouts: list[Any], offsets: dict[str, int]):
        self.scene = scene
        self.layouts = {lay.name: lay for lay in layouts}
        self.offsets = offsets
        self.pt_i: list[list[int]] = []
        self.pt_f: list[list[float]] = []
        self.point_index: dict[tuple[str, str], int] = {}
        self.con_i: list[list[int]] = []
        self.con_f: list[list[float]] = []
        self.rows = 0

    def point(self, body: str, point: str, where: str) -> int:
        key = (body, point)
        if key in self.point_index:
            return self.point_index[key]
        if body == GROUND:
            if point not in self.scene.ground_points:
                raise ValueError(
                    f"{where}: ground point {point!r} is not defined; ground points are "
                    f"{sorted(self.scene.ground_points)}."
                )
            x, y = self.scene.ground_points[point]
            row_i = [POINT_GROUND, -1, ANGLE_NONE, -1, -1, -1, -1, -1]
            row_f = [float(x), float(y), 0.0, 0.0, 0.0, 0.0]
        else:
            if body not in self.layouts:
                raise ValueError(
                    f"{where}: body {body!r} is not defined; bodies are "
                    f"{sorted(self.layouts)} (and {GROUND!r})."
                )
            layout = self.layouts[body]
            try:
                row_i, row_f = layout.point_row(point, self.offsets[body])
            except KeyError:
                raise ValueError(
                    f"{where}: body {body!r} has no point {point!r}; its points are "
                    f"{sorted(layout.point_names)}."
                ) from None
        self.point_index[key] = len(self.pt_i)
        self.pt_i.append(list(row_i))
        self.pt_f.append(list(row_f))
        return self.point_index[key]

    def add(self, typ: int, a: int, b: int, floats: tuple[float, ...] = ()) -> int:
        row = self.rows
        f = [0.0, 0.0, 0.0, 0.0]
        f[: len(floats)] = [float(x) for x in floats]
        self.con_i.append([typ, a, b, row])
        self.con_f.append(f)
        self.rows += CON_ROWS[typ]
        return row


def _angle_guess(layouts: dict[str, Any], body: str) -> float:
    if body == GROUND:
        return 0.0
    layout = layouts[body]
    if isinstance(layout, AncfLayout):
        # a beam's frame angle is the slope angle of its (straight) initial chord
        return layout.chord_angle
    return float(layout.initial_coordinates()[2])


def _profile_tables(drive: AngleProfileDrive) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Periodic cubic spline of an angle profile: f(t) = ramp·t/P + s((t − t₀) mod P).

    ``ramp`` is the angle gained per period: a[-1] − a[0] when the samples span the whole
    period, else the mean rate extrapolated to a period and rounded to whole turns (0 for
    an oscillating profile, 2π per turn for a rotating crank); the spline is closed at
    t₀ + P with a[0] + ramp.
    """
    from scipy.interpolate import CubicSpline

    t = np.asarray(drive.time, dtype=np.float64)
    a = np.asarray(drive.angle, dtype=np.float64)
    period = float(drive.period)
    if t.ndim != 1 or t.size < 2 or t.size != a.size or np.any(np.diff(t) <= 0):
        raise ValueError(
            "drive.time and drive.angle must be equally long (≥ 2 samples) with strictly "
            "increasing times."
        )
    span = float(t[-1] - t[0])
    if span > period * (1.0 + 1e-12):
        raise ValueError(
            f"drive.time must span at most one drive.period ({period!r} s); got {span!r} s."
        )
    if math.isclose(span, period, rel_tol=1e-9):
        ramp = float(a[-1] - a[0])
    else:
        turns = (a[-1] - a[0]) * period / span / (2.0 * math.pi)
        ramp = 2.0 * math.pi * round(turns)
        t = np.append(t, t[0] + period)
        a = np.append(a, a[0] + ramp)
    periodic = a - ramp * t / period
    periodic[-1] = periodic[0]
    if t.size < 3:
        x = np.array([t[0], t[0] + period])
        c = np.zeros((4, 1))
        c[3, 0] = periodic[0]
        return np.array([0.0, 0.0, period, ramp]), x, c
    spline = CubicSpline(t, periodic, bc_type="periodic")
    return (
        np.array([0.0, 0.0, period, ramp]),
        np.ascontiguousarray(spline.x, dtype=np.float64),
        np.ascontiguousarray(spline.c, dtype=np.float64),
    )


def _drive_tables(
    scene: Scene,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """(drive_f, spline_x, spline_c, kind, θ₀) of the scene's drive."""
    drive = scene.drive
    empty_x = np.zeros(2)
    empty_c = np.zeros((4, 1))
    if drive is None:
        return np.zeros(4), empty_x, empty_c, np.array(DRIVE_NONE), 0.0
    if isinstance(drive, ConstantSpeedDrive):
        w = drive.speed
        return (
            np.array([drive.initial_angle, w, drive.period, 0.0]),
            empty_x,
            empty_c,
            np.array(DRIVE_CONSTANT_SPEED),
            float(drive.initial_angle),
        )
    if isinstance(drive, AngleProfileDrive):
        return (*_profile_tables(drive), np.array(DRIVE_PROFILE), 0.0)
    raise TypeError(f"unsupported drive type {type(drive).__name__}.")


def _worn_tables(
    joint: ClearanceRevolute, p: Any, flat: list[np.ndarray]
) -> tuple[list[int], list[float]]:
    """Worn-profile row of one clearance joint; appends its depth and curvature arrays.

    ``flat`` alternates depth and curvature arrays; offsets index their concatenations.
    The kernels read both through the continuous surface of
    ``mechanism.core.wear._kernels.surface_value`` (and its slope for the rate of the local
    clearance while the contact moves over a worn flank).
    An unworn joint (both profiles empty) gets ``CW_WORN = 0`` and no arrays, so its
    contact runs the unworn code path.
    """
    row_i = [0] * k.CW_COLUMNS
    row_f = [p.effective_modulus, float(joint.wear.radius_ratio_limit)]
    if not (joint.wear.bearing_profile or joint.wear.journal_profile):
        return row_i, row_f
    profile = WornProfile.from_joint(joint)
    offset = sum(a.size for a in flat[0::2])
    row_i[k.CW_WORN] = 1
    row_i[k.CW_FORM] = p.stiffness_form_code if p.form is not None else -1
    for depth, radius, outward, col in (
        (profile.bearing_depth, joint.bearing_radius, True, k.CW_B_OFF),
        (profile.journal_depth, joint.journal_radius, False, k.CW_J_OFF),
    ):
        depth = np.ascontiguousarray(depth, dtype=np.float64)
        if not depth.any():
            continue  # an unworn surface: empty slice, nominal clearance and curvature
        kappa = np.empty(depth.size)
        wk.curvature_profile(radius, depth, profile.smoothing_regions, outward, kappa)
        row_i[col] = offset
        row_i[col + 1] = depth.size
        flat.extend((depth, kappa))
        offset += depth.size
    return row_i, row_f


def assemble(scene: Scene, *, ideal: bool = False, eccentricity_offsets: bool = False) -> Model:
    """Compile a scene into a :class:`Model`.

    The steps: lay out the bodies' coordinates (:func:`_mass_tables`), turn every joint into
    constraint rows or a clearance-joint row (:func:`_joint_tables`), add the drive and the
    output points (:func:`_drive_tables`, :func:`_crank_points`, :func:`_slider_map`), and
    pack everything into the flat arrays of a :class:`KernelModel` (:func:`_kernel_model`).

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
    layouts = _layouts(scene)
    offsets: dict[str, int] = {}
    n = 0
    for lay in layouts:
        offsets[lay.name] = n
        n += lay.n_dof
    if n == 0:
        raise ValueError("the scene has no bodies.")
    mass = _mass_tables(scene, layouts, offsets, n)
    b = _Builder(scene, layouts, offsets)
    joints = _joint_tables(
        scene,
        b,
        {lay.name: lay for lay in layouts},
        use_clearance=scene.effects.clearance and not ideal,
        eccentricity_offsets=eccentricity_offsets,
    )
    drive = _drive_rows(scene, b)
    crank_points = _crank_points(scene, b, drive.crank_points)
    slider = _slider_map(scene, b)
    if b.rows > n:
        raise ValueError(
            f"the scene has {b.rows} constraint equations for {n} coordinates; it is "
            "over-constrained (remove a redundant joint)."
        )
    kernel = _kernel_model(scene, layouts, offsets, mass, b, joints, drive, crank_points, slider)
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
        drive_row=drive.row,
        crank_points=crank_points,
        slider=slider,
        q_guess=mass.q_guess,
    )


@dataclass
class _MassTables:
    mass: np.ndarray
    minv: np.ndarray
    blk_lo: np.ndarray
    blk_hi: np.ndarray
    gravity: np.ndarray
    q_guess: np.ndarray
    dof_names: list[str]


def _mass_tables(scene: Scene, layouts: list[Any], offsets: dict[str, int], n: int) -> _MassTables:
    """Block-diagonal mass matrix and its inverse, gravity forces and the first guess of q."""
    t = _MassTables(
        mass=np.zeros((n, n)),
        minv=np.zeros((n, n)),
        blk_lo=np.zeros(n, dtype=np.int64),
        blk_hi=np.zeros(n, dtype=np.int64),
        gravity=np.zeros(n),
        q_guess=np.zeros(n),
        dof_names=[],
    )
    g = scene.gravity if scene.effects.gravity else (0.0, 0.0)
    for lay in layouts:
        o = offsets[lay.name]
        blk = lay.mass_block()
        sl = slice(o, o + lay.n_dof)
        t.mass[sl, sl] = blk
        inv = np.linalg.inv(blk)
        # exactly symmetric, so the kernels may read a column as the contiguous row
        t.minv[sl, sl] = 0.5 * (inv + inv.T)
        t.blk_lo[sl] = o
        t.blk_hi[sl] = o + lay.n_dof
        t.gravity[sl] = lay.gravity_block(g)
        t.q_guess[sl] = lay.initial_coordinates()
        t.dof_names.extend(f"{lay.name}.{c}" for c in lay.coordinate_names)
    return t


@dataclass
class _JointTables:
    ideal_rows: list[IdealJointRows] = field(default_factory=list)
    clearance_names: list[str] = field(default_factory=list)
    cj_i: list[list[int]] = field(default_factory=list)
    cj_f: list[list[float]] = field(default_factory=list)
    worn: list[tuple[list[int], list[float]]] = field(default_factory=list)
    cw_h: list[np.ndarray] = field(default_factory=list)


def _joint_tables(
    scene: Scene,
    b: _Builder,
    layout_map: dict[str, Any],
    *,
    use_clearance: bool,
    eccentricity_offsets: bool,
) -> _JointTables:
    """Constraint rows of the ideal joints and the table rows of the clearance joints."""
    t = _JointTables()
    for name, joint in scene.joints.items():
        where = f"joints.{name}"
        if isinstance(joint, ClearanceRevolute):
            pb = b.point(joint.bearing[0], joint.bearing[1], where)
            pj = b.point(joint.journal[0], joint.journal[1], where)
            if use_clearance:
                p = contact_parameters(joint)
                friction = p.friction_code if scene.effects.friction else 0
                t.cj_i.append([pb, pj, p.law_code, friction])
                t.cj_f.append(_clearance_row(joint, p))
                t.worn.append(_worn_tables(joint, p, t.cw_h))
                t.clearance_names.append(name)
            else:
                ex, ey = joint.initial_eccentricity if eccentricity_offsets else (0.0, 0.0)
                # Φ = r_b − r_j + e₀ keeps r_j − r_b = e₀
                row = b.add(CON_COINCIDE, pb, pj, (-ex, -ey))
                t.ideal_rows.append(IdealJointRows(name=name, kind="revolute", row=row))
            continue
        if not isinstance(joint, RevoluteJoint | PrismaticJoint | FixedJoint):
            raise TypeError(f"{where}: unsupported joint type {type(joint).__name__}.")
        (ba, bb), (na, nb) = joint.bodies, joint.points
        pa = b.point(ba, na, where)
        pb = b.point(bb, nb, where)
        rel = _angle_guess(layout_map, bb) - _angle_guess(layout_map, ba)
        if isinstance(joint, RevoluteJoint):
            row = b.add(CON_COINCIDE, pa, pb)
            t.ideal_rows.append(IdealJointRows(name=name, kind="revolute", row=row))
        elif isinstance(joint, FixedJoint):
            row = b.add(CON_COINCIDE, pa, pb)
            b.add(CON_ANGLE, pa, pb, (rel,))
            t.ideal_rows.append(IdealJointRows(name=name, kind="fixed", row=row))
        else:
            ux, uy = (float(c) for c in joint.axis)
            norm = math.hypot(ux, uy)
            if not norm > 0.0:
                raise ValueError(f"{where}.axis must be a non-zero vector; got {joint.axis!r}.")
            ux, uy = ux / norm, uy / norm
            row = b.add(CON_ANGLE, pa, pb, (rel,))
            b.add(CON_NORMAL, pa, pb, (-uy, ux, 0.0))
            t.ideal_rows.append(
                IdealJointRows(
                    name=name, kind="prismatic", row=row, normal=(-uy, ux), guide_point=pa
                )
            )
    return t


def _clearance_row(joint: ClearanceRevolute, p: Any) -> list[float]:
    """The ``CF_*`` row of a clearance joint: geometry and its contact and friction laws."""
    row_f = [0.0] * k.CF_COLUMNS
    row_f[k.CF_RB] = joint.bearing_radius
    row_f[k.CF_RJ] = joint.journal_radius
    row_f[k.CF_C] = joint.clearance
    row_f[k.CF_K] = p.stiffness
    row_f[k.CF_EXP] = p.exponent
    row_f[k.CF_CE] = p.restitution
    row_f[k.CF_MU] = p.friction_coefficient
    row_f[k.CF_V0] = p.v0
    row_f[k.CF_V1] = p.v1
    row_f[k.CF_FLOOR] = p.impact_velocity_floor
    return row_f


@dataclass
class _DriveRows:
    f: np.ndarray
    spline_x: np.ndarray
    spline_c: np.ndarray
    kind: int
    row: int | None = None
    con: int = -1
    crank_points: tuple[int, int] | None = None


def _drive_rows(scene: Scene, b: _Builder) -> _DriveRows:
    """The driving constraint (a prescribed angle of a revolute joint) and its tables."""
    drive_f, spline_x, spline_c, drive_kind, theta0 = _drive_tables(scene)
    out = _DriveRows(f=drive_f, spline_x=spline_x, spline_c=spline_c, kind=int(drive_kind))
    if scene.drive is not None:
        jname = scene.drive.joint
        driven = scene.joints.get(jname)
        if not isinstance(driven, RevoluteJoint):
            raise ValueError(
                f"drive.joint must name a revolute joint; got {jname!r} "
                f"({type(driven).__name__ if driven is not None else 'undefined'})."
            )
        pa = b.point(driven.bodies[0], driven.points[0], "drive")
        pb = b.point(driven.bodies[1], driven.points[1], "drive")
        out.con = len(b.con_i)
        out.row = b.add(CON_DRIVE, pa, pb, (theta0,))
        out.crank_points = (pa, pb)
    return out


def _crank_points(
    scene: Scene, b: _Builder, default: tuple[int, int] | None
) -> tuple[int, int] | None:
    """Points whose relative angle is the output ``crank_angle`` (default: the driven joint)."""
    crank_joint = scene.outputs.crank_joint
    if crank_joint is None:
        return default
    crank = scene.joints.get(crank_joint)
    if not isinstance(crank, RevoluteJoint | ClearanceRevolute):
        raise ValueError(f"outputs.crank_joint must name a revolute joint; got {crank_joint!r}.")
    if isinstance(crank, ClearanceRevolute):
        return (
            b.point(*crank.bearing, "outputs.crank_joint"),
            b.point(*crank.journal, "outputs.crank_joint"),
        )
    return (
        b.point(crank.bodies[0], crank.points[0], "outputs.crank_joint"),
        b.point(crank.bodies[1], crank.points[1], "outputs.crank_joint"),
    )


def _arr_i(rows: list[list[int]], width: int) -> np.ndarray:
    return np.ascontiguousarray(np.array(rows, dtype=np.int64).reshape(-1, width))


def _arr_f(rows: list[list[float]], width: int) -> np.ndarray:
    return np.ascontiguousarray(np.array(rows, dtype=np.float64).reshape(-1, width))


def _kernel_model(
    scene: Scene,
    layouts: list[Any],
    offsets: dict[str, int],
    mass: _MassTables,
    b: _Builder,
    joints: _JointTables,
    drive: _DriveRows,
    crank_points: tuple[int, int] | None,
    slider: SliderMap | None,
) -> KernelModel:
    """Pack the assembled tables into the contiguous arrays the kernels read."""
    beam_names = [lay.name for lay in layouts if isinstance(lay, AncfLayout)]
    beam_rows = {
        lay.name: lay.beam_row(offsets[lay.name]) for lay in layouts if isinstance(lay, AncfLayout)
    }
    cw_h = joints.cw_h
    solver = scene.solver
    return KernelModel(
        n_dof=mass.mass.shape[0],
        n_rows=b.rows,
        mass=mass.mass,
        minv=mass.minv,
        blk_lo=mass.blk_lo,
        blk_hi=mass.blk_hi,
        gravity_force=mass.gravity,
        pt_i=_arr_i(b.pt_i, 8),
        pt_f=_arr_f(b.pt_f, 6),
        con_i=_arr_i(b.con_i, 4),
        con_f=_arr_f(b.con_f, 4),
        drive_i=np.array([drive.kind, drive.con], dtype=np.int64),
        drive_f=np.ascontiguousarray(drive.f, dtype=np.float64),
        spline_x=drive.spline_x,
        spline_c=drive.spline_c,
        cj_i=_arr_i(joints.cj_i, 4),
        cj_f=_arr_f(joints.cj_f, k.CF_COLUMNS),
        cw_i=_arr_i([w[0] for w in joints.worn], k.CW_COLUMNS),
        cw_f=_arr_f([w[1] for w in joints.worn], 2),
        cw_h=np.ascontiguousarray(np.concatenate([np.zeros(0), *cw_h[0::2]])),
        cw_k=np.ascontiguousarray(np.concatenate([np.zeros(0), *cw_h[1::2]])),
        out_i=np.array(
            [
                *(crank_points if crank_points is not None else (-1, -1)),
                *((slider.guide_point, slider.slider_point) if slider is not None else (-1, -1)),
            ],
            dtype=np.int64,
        ),
        out_f=np.array(slider.axis if slider is not None else (1.0, 0.0), dtype=np.float64),
        jt_i=_arr_i(
            [
                [k.JOINT_PRISMATIC if j.kind == "prismatic" else k.JOINT_PIN, j.row, j.guide_point]
                for j in joints.ideal_rows
            ],
            3,
        ),
        jt_f=_arr_f([list(j.normal) for j in joints.ideal_rows], 2),
        alpha=float(solver.baumgarte_alpha),
        beta=float(solver.baumgarte_beta),
        beam_i=_arr_i([beam_rows[n][0] for n in beam_names], BEAM_I_COLUMNS),
        beam_f=_arr_f([beam_rows[n][1] for n in beam_names], BEAM_F_COLUMNS),
    )


def _slider_map(scene: Scene, b: _Builder) -> SliderMap | None:
    name = scene.outputs.slider_joint
    if name is None:
        prismatic = [n for n, j in scene.joints.items() if isinstance(j, PrismaticJoint)]
        if len(prismatic) != 1:
            return None
        name = prismatic[0]
    joint = scene.joints.get(name)
    if not isinstance(joint, PrismaticJoint):
        raise ValueError(f"outputs.slider_joint must name a prismatic joint; got {name!r}.")
    ux, uy = (float(c) for c in joint.axis)
    norm = math.hypot(ux, uy)
    return SliderMap(
        joint=name,
        guide_point=b.point(joint.bodies[0], joint.points[0], "outputs.slider_joint"),
        slider_point=b.point(joint.bodies[1], joint.points[1], "outputs.slider_joint"),
        axis=(ux / norm, uy / norm),
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
    ideal-mechanism velocities with the journal at rest relative to the bearing.
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
        k.evaluate_constraints(km, ws, t0, q, v)
        err = float(np.max(np.abs(ws.phi)))
        if err < tol:
            break
        dq = np.linalg.lstsq(ws.phiq, -ws.phi, rcond=None)[0]
        q += dq
    else:
        k.evaluate_constraints(km, ws, t0, q, v)
        err = float(np.max(np.abs(ws.phi)))
    if not err < max(tol, 1e-9):
        raise ValueError(
            f"the scene's joints cannot be assembled from its pose guesses (largest constraint "
            f"violation {err:.3g} after {max_iter} Newton iterations); check the body "
            "positions, angles and joint points."
        )
    k.evaluate_constraints(km, ws, t0, q, v)
    phiq = ws.phiq.copy()
    w = km.minv @ phiq.T
    s = phiq @ w
    lam = np.linalg.lstsq(s, ws.phit, rcond=None)[0]
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
