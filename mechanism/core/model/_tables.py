"""The tables of a scene's assembly: bodies laid out on the coordinates, the point and
constraint rows of the joints, the clearance-joint and worn-profile rows, the drive and
the output points, packed into the contiguous arrays of a :class:`KernelModel`.

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechanism.core.bodies import (
    BEAM_F_COLUMNS,
    BEAM_I_COLUMNS,
    AncfLayout,
    RigidLayout,
    rigid_bar_from_beam,
)
from mechanism.core.contact import contact_parameters, guide_contact_parameters
from mechanism.core.forces import ForceTables
from mechanism.core.joints import (
    ANGLE_NONE,
    ANGLE_RIGID,
    CON_ANGLE,
    CON_COINCIDE,
    CON_DRIVE,
    CON_NORMAL,
    CON_ROWS,
    DRIVE_CONSTANT_SPEED,
    DRIVE_NONE,
    DRIVE_PROFILE,
    POINT_GROUND,
    POINT_RIGID,
)
from mechanism.core.scene import (
    GROUND,
    AncfBeam,
    AngleProfileDrive,
    ClearancePrismatic,
    ClearanceRevolute,
    ConstantSpeedDrive,
    FixedJoint,
    MotorDrive,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    Scene,
)
from mechanism.core.wear import WornProfile
from mechanism.core.wear import kernels as wear_kernels

from . import _kernels as model_kernels
from ._compiled import IdealJointRows, KernelModel, SliderMap
from ._guide_tables import contact_row, corner_rows, guide_frame

__all__ = [
    "DriveRows",
    "JointTables",
    "MassTables",
    "TableBuilder",
    "body_layouts",
    "drive_rows",
    "joint_tables",
    "kernel_model",
    "mass_tables",
    "output_crank_points",
    "slider_map",
]


def body_layouts(scene: Scene) -> list[Any]:
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


class TableBuilder:
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

    def rigid_point(self, body: str, local: tuple[float, float]) -> int:
        """Add an unnamed point of the rigid body ``body`` at ``local`` (body frame, m) and
        return its row (a slider's corner, which no joint names)."""
        row = len(self.pt_i)
        self.pt_i.append([POINT_RIGID, self.offsets[body], ANGLE_RIGID, -1, -1, -1, -1, -1])
        self.pt_f.append([float(local[0]), float(local[1]), 0.0, 0.0, 0.0, 0.0])
        return row

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
    if drive is None or isinstance(drive, MotorDrive):
        # a motor prescribes no angle: its torque is a force element
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
    row_i = [0] * model_kernels.CW_COLUMNS
    row_f = [p.effective_modulus, float(joint.wear.radius_ratio_limit)]
    if not (joint.wear.bearing_profile or joint.wear.journal_profile):
        return row_i, row_f
    profile = WornProfile.from_joint(joint)
    offset = sum(a.size for a in flat[0::2])
    row_i[model_kernels.CW_WORN] = 1
    row_i[model_kernels.CW_FORM] = p.stiffness_form_code if p.form is not None else -1
    for depth, radius, outward, col in (
        (profile.bearing_depth, joint.bearing_radius, True, model_kernels.CW_B_OFF),
        (profile.journal_depth, joint.journal_radius, False, model_kernels.CW_J_OFF),
    ):
        depth = np.ascontiguousarray(depth, dtype=np.float64)
        if not depth.any():
            continue  # an unworn surface: empty slice, nominal clearance and curvature
        kappa = np.empty(depth.size)
        wear_kernels.curvature_profile(radius, depth, profile.smoothing_regions, outward, kappa)
        row_i[col] = offset
        row_i[col + 1] = depth.size
        flat.extend((depth, kappa))
        offset += depth.size
    return row_i, row_f


@dataclass
class MassTables:
    mass: np.ndarray
    minv: np.ndarray
    blk_lo: np.ndarray
    blk_hi: np.ndarray
    blk_st: np.ndarray
    minv_h: np.ndarray | None
    gravity: np.ndarray
    q_guess: np.ndarray
    dof_names: list[str]


def mass_tables(scene: Scene, layouts: list[Any], offsets: dict[str, int], n: int) -> MassTables:
    """Block-diagonal mass matrix and its inverse, gravity forces and the first guess of q."""
    t = MassTables(
        mass=np.zeros((n, n)),
        minv=np.zeros((n, n)),
        blk_lo=np.zeros(n, dtype=np.int64),
        blk_hi=np.zeros(n, dtype=np.int64),
        blk_st=np.ones(n, dtype=np.int64),
        minv_h=None,
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
    _add_flywheel(scene, layouts, offsets, t)
    _split_planes(t)
    return t


def _split_planes(t: MassTables) -> None:
    """Mark the mass blocks whose inverse couples only coordinates of the same parity (an
    ANCF rod's x and y DOFs alternate and its mass matrix does not couple them) and keep,
    for each of their coordinates, the row of M⁻¹ over that parity only (``minv_h``), so
    the kernels skip the exact zeros between the planes."""
    n = t.minv.shape[0]
    split = []
    lo = 0
    while lo < n:
        hi = int(t.blk_hi[lo])
        blk = t.minv[lo:hi, lo:hi]
        size = hi - lo
        parity = np.add.outer(np.arange(size), np.arange(size)) % 2
        if size >= 4 and size % 2 == 0 and not np.any(blk[parity == 1]):
            split.append((lo, hi))
        lo = hi
    if not split:
        t.minv_h = None  # the kernels then compile no code for such blocks
        return
    half = max((hi - lo) // 2 for lo, hi in split)
    t.minv_h = np.zeros((n, half))
    for lo, hi in split:
        t.blk_st[lo:hi] = 2
        for j in range(lo, hi):
            p = (j - lo) % 2
            t.minv_h[j, : (hi - lo) // 2] = t.minv[j, lo + p : hi : 2]


def _add_flywheel(scene: Scene, layouts: list[Any], offsets: dict[str, int], t: MassTables) -> None:
    """A motor drive's flywheel inertia on the rotation of the driven joint's second
    (rigid) body."""
    drive = scene.drive
    if not isinstance(drive, MotorDrive) or drive.flywheel_inertia == 0.0:
        return
    joint = scene.joints.get(drive.joint)
    body = joint.bodies[1] if isinstance(joint, RevoluteJoint) else None
    lay = next((lay for lay in layouts if lay.name == body), None)
    if not isinstance(lay, RigidLayout):
        raise ValueError(
            f"drive.flywheel_inertia: the flywheel needs a rigid second body of joint "
            f"{drive.joint!r}; got {body!r}."
        )
    i = offsets[lay.name] + 2  # (x, y, θ): the rotation
    t.mass[i, i] += drive.flywheel_inertia
    t.minv[i, i] = 1.0 / t.mass[i, i]


@dataclass
class JointTables:
    ideal_rows: list[IdealJointRows] = field(default_factory=list)
    clearance_names: list[str] = field(default_factory=list)
    cj_i: list[list[int]] = field(default_factory=list)
    cj_f: list[list[float]] = field(default_factory=list)
    worn: list[tuple[list[int], list[float]]] = field(default_factory=list)
    cw_h: list[np.ndarray] = field(default_factory=list)


def joint_tables(
    scene: Scene,
    b: TableBuilder,
    layout_map: dict[str, Any],
    *,
    use_clearance: bool,
    eccentricity_offsets: bool,
) -> JointTables:
    """Constraint rows of the ideal joints and the table rows of the clearance joints."""
    t = JointTables()
    for name, joint in scene.joints.items():
        where = f"joints.{name}"
        if isinstance(joint, ClearanceRevolute):
            pb = b.point(joint.bearing[0], joint.bearing[1], where)
            pj = b.point(joint.journal[0], joint.journal[1], where)
            if use_clearance:
                p = contact_parameters(joint)
                friction = p.friction_code if scene.effects.friction else 0
                t.cj_i.append([pb, pj, p.law_code, friction, model_kernels.CONTACT_JOURNAL])
                t.cj_f.append(_clearance_row(joint, p))
                t.worn.append(_worn_tables(joint, p, t.cw_h))
                t.clearance_names.append(name)
            else:
                ex, ey = joint.initial_eccentricity if eccentricity_offsets else (0.0, 0.0)
                # Φ = r_b − r_j + e₀ keeps r_j − r_b = e₀
                row = b.add(CON_COINCIDE, pb, pj, (-ex, -ey))
                t.ideal_rows.append(IdealJointRows(name=name, kind="revolute", row=row))
            continue
        if isinstance(joint, ClearancePrismatic):
            _guide_joint_tables(
                scene, name, joint, b, layout_map, t,
                use_clearance=use_clearance, eccentricity_offsets=eccentricity_offsets,
            )  # fmt: skip
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


def _guide_joint_tables(
    scene: Scene,
    name: str,
    joint: ClearancePrismatic,
    b: TableBuilder,
    layout_map: dict[str, Any],
    t: JointTables,
    *,
    use_clearance: bool,
    eccentricity_offsets: bool,
) -> None:
    """A translational clearance joint: four corner rows of the clearance table, or, with
    clearance off, an ideal prismatic joint (holding ``initial_offset`` with
    ``eccentricity_offsets``)."""
    where = f"joints.{name}"
    pg = b.point(joint.guide[0], joint.guide[1], where)
    ps = b.point(joint.slider[0], joint.slider[1], where)
    rel = _angle_guess(layout_map, joint.slider[0]) - _angle_guess(layout_map, joint.guide[0])
    if not use_clearance:
        _, _, nx, ny = guide_frame(joint)
        offset = joint.initial_offset if eccentricity_offsets else 0.0
        row = b.add(CON_ANGLE, pg, ps, (rel,))
        b.add(CON_NORMAL, pg, ps, (nx, ny, offset))
        t.ideal_rows.append(
            IdealJointRows(name=name, kind="prismatic", row=row, normal=(nx, ny), guide_point=pg)
        )
        return
    layout = layout_map.get(joint.slider[0])
    if not isinstance(layout, RigidLayout):
        raise ValueError(f"{where}.slider[0]: the slider must be a rigid body.")
    p = guide_contact_parameters(joint)
    rows = corner_rows(
        name,
        joint,
        p,
        slider_point=tuple(float(x) for x in layout.body.points[joint.slider[1]]),
        relative_angle=rel,
        friction_code=p.friction_code if scene.effects.friction else 0,
        guide_point=pg,
        add_point=lambda local: b.rigid_point(joint.slider[0], local),
    )
    for corner in rows:
        t.cj_i.append(corner.row_i)
        t.cj_f.append(corner.row_f)
        t.worn.append((corner.worn_i, corner.worn_f))
        t.clearance_names.append(corner.name)


def _clearance_row(joint: ClearanceRevolute, p: Any) -> list[float]:
    """The ``CF_*`` row of a clearance joint: geometry and its contact and friction laws."""
    row_f = contact_row(
        p, outer=joint.bearing_radius, inner=joint.journal_radius, clearance=joint.clearance
    )
    lub = joint.lubrication
    if lub is not None:
        row_f[model_kernels.CF_VISC] = lub.viscosity
        row_f[model_kernels.CF_LUB_L] = joint.length if lub.length is None else lub.length
        row_f[model_kernels.CF_FILM] = lub.film_breakdown
        row_f[model_kernels.CF_CAV] = 1.0 if lub.cavitation == "positive-pressure" else 0.0
    return row_f


@dataclass
class DriveRows:
    f: np.ndarray
    spline_x: np.ndarray
    spline_c: np.ndarray
    kind: int
    row: int | None = None
    con: int = -1
    crank_points: tuple[int, int] | None = None


def drive_rows(scene: Scene, b: TableBuilder) -> DriveRows:
    """The driving constraint (a prescribed angle of a revolute joint) and its tables;
    a motor drive adds no row, only the joint's points for ``crank_angle``."""
    drive_f, spline_x, spline_c, drive_kind, theta0 = _drive_tables(scene)
    out = DriveRows(f=drive_f, spline_x=spline_x, spline_c=spline_c, kind=int(drive_kind))
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
        out.crank_points = (pa, pb)
        if isinstance(scene.drive, MotorDrive):
            # the joint's angle stays free; crank_angle reads the same points
            return out
        out.con = len(b.con_i)
        out.row = b.add(CON_DRIVE, pa, pb, (theta0,))
        out.crank_points = (pa, pb)
    return out


def output_crank_points(
    scene: Scene, b: TableBuilder, default: tuple[int, int] | None
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


def kernel_model(
    scene: Scene,
    layouts: list[Any],
    offsets: dict[str, int],
    mass: MassTables,
    b: TableBuilder,
    joints: JointTables,
    drive: DriveRows,
    crank_points: tuple[int, int] | None,
    slider: SliderMap | None,
    forces: ForceTables,
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
        blk_st=mass.blk_st,
        minv_h=mass.minv_h,
        gravity_force=mass.gravity,
        pt_i=_arr_i(b.pt_i, 8),
        pt_f=_arr_f(b.pt_f, 6),
        con_i=_arr_i(b.con_i, 4),
        con_f=_arr_f(b.con_f, 4),
        drive_i=np.array([drive.kind, drive.con], dtype=np.int64),
        drive_f=np.ascontiguousarray(drive.f, dtype=np.float64),
        spline_x=drive.spline_x,
        spline_c=drive.spline_c,
        cj_i=_arr_i(joints.cj_i, model_kernels.CI_COLUMNS),
        cj_f=_arr_f(joints.cj_f, model_kernels.CF_COLUMNS),
        cw_i=_arr_i([w[0] for w in joints.worn], model_kernels.CW_COLUMNS),
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
                [
                    model_kernels.JOINT_PRISMATIC
                    if j.kind == "prismatic"
                    else model_kernels.JOINT_PIN,
                    j.row,
                    j.guide_point,
                ]
                for j in joints.ideal_rows
            ],
            3,
        ),
        jt_f=_arr_f([list(j.normal) for j in joints.ideal_rows], 2),
        alpha=float(solver.baumgarte_alpha),
        beta=float(solver.baumgarte_beta),
        beam_i=_arr_i([beam_rows[n][0] for n in beam_names], BEAM_I_COLUMNS),
        beam_f=_arr_f([beam_rows[n][1] for n in beam_names], BEAM_F_COLUMNS),
        fe_i=forces.fe_i,
        fe_f=forces.fe_f,
        fe_t=forces.fe_t,
    )


def slider_map(scene: Scene, b: TableBuilder) -> SliderMap | None:
    name = scene.outputs.slider_joint
    sliding = PrismaticJoint | ClearancePrismatic
    if name is None:
        prismatic = [n for n, j in scene.joints.items() if isinstance(j, sliding)]
        if len(prismatic) != 1:
            return None
        name = prismatic[0]
    joint = scene.joints.get(name)
    if not isinstance(joint, sliding):
        raise ValueError(f"outputs.slider_joint must name a prismatic joint; got {name!r}.")
    ux, uy = (float(c) for c in joint.axis)
    norm = math.hypot(ux, uy)
    guide, slider = (
        (joint.guide, joint.slider)
        if isinstance(joint, ClearancePrismatic)
        else ((joint.bodies[0], joint.points[0]), (joint.bodies[1], joint.points[1]))
    )
    return SliderMap(
        joint=name,
        guide_point=b.point(guide[0], guide[1], "outputs.slider_joint"),
        slider_point=b.point(slider[0], slider[1], "outputs.slider_joint"),
        axis=(ux / norm, uy / norm),
    )
