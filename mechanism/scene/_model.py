"""The scene data model: frozen dataclasses that a TOML scene is validated into.

This module is the contract between scene loading (``_load.py``) and assembly
(``mechanism/_assemble.py``). All quantities are SI (m, kg, s, rad, N, Pa); rpm appears
only in :class:`ConstantSpeedDrive` as the user-facing ``speed_rpm``.

Layout of a scene TOML (see ``docs/scenes.md``)::

    [scene]        name, description
    [effects]      clearance, friction, gravity, flexibility, wear (booleans)
    [gravity]      vector = [gx, gy]
    [ground]       points = { NAME = [x, y], ... }
    [bodies.NAME]  type = "rigid", mass, inertia, position, angle, points = {...}
    [joints.NAME]  type = "revolute" | "prismatic" | "fixed" | "clearance_revolute", ...
    [drive]        type = "constant_speed" | "angle_profile", joint, speed_rpm, ...
    [solver]       method, rtol, atol, max_step, output_step, baumgarte_alpha, ...
    [outputs]      slider_joint, crank_joint
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

__all__ = [
    "GROUND",
    "AncfBeam",
    "AngleProfileDrive",
    "ClearanceRevolute",
    "ConstantSpeedDrive",
    "ContactLaw",
    "Effects",
    "FixedJoint",
    "FrictionLaw",
    "Material",
    "Outputs",
    "PrismaticJoint",
    "RevoluteJoint",
    "RigidBody",
    "Scene",
    "SolverSettings",
    "WearSettings",
]

GROUND = "ground"

Vec2 = tuple[float, float]


@dataclass(frozen=True, kw_only=True)
class Effects:
    """Which physical effects the simulation evaluates; an effect that is off costs nothing.

    ``clearance=False`` turns every clearance joint into an ideal revolute joint.
    ``flexibility=False`` turns every ANCF beam into an equivalent rigid body.
    """

    clearance: bool = True
    friction: bool = True
    gravity: bool = True
    flexibility: bool = False
    wear: bool = False


@dataclass(frozen=True, kw_only=True)
class Material:
    youngs_modulus: float  # Pa, > 0
    poisson_ratio: float  # in [0, 0.5)


@dataclass(frozen=True, kw_only=True)
class RigidBody:
    """A rigid body with its reference point at the centre of mass.

    ``points`` are named points in body coordinates (m, relative to the centre of mass);
    ``position`` and ``angle`` are the initial guess of the pose, refined by assembly.
    """

    type: Literal["rigid"] = "rigid"
    mass: float  # kg, > 0
    inertia: float  # kg m2 about the centre of mass, > 0
    position: Vec2 = (0.0, 0.0)  # m
    angle: float = 0.0  # rad
    points: dict[str, Vec2] = field(default_factory=dict)


@dataclass(frozen=True, kw_only=True)
class AncfBeam:
    """A 2-D gradient-deficient ANCF beam (issue 6) between two named end points.

    The beam is straight and unstressed at t = 0 from ``start`` to ``end`` (global, m);
    its points are ``"start"`` (node 1) and ``"end"`` (last node). With
    ``effects.flexibility = False`` it is replaced by a rigid bar of the same mass and
    centroidal inertia m L²/12 (+ any ``rigid_inertia`` override).
    """

    type: Literal["ancf_beam"] = "ancf_beam"
    length: float  # m
    elements: int = 16
    area: float  # m2
    second_moment: float  # m4
    youngs_modulus: float  # Pa
    density: float  # kg m-3
    damping: float = 0.0  # structural (stiffness-proportional) damping, s
    start: Vec2  # initial global position of node 1, m
    end: Vec2  # initial global position of the last node, m
    mass: float | None = None  # kg; default density * area * length
    rigid_inertia: float | None = None  # kg m2 about the centroid when rigid


@dataclass(frozen=True, kw_only=True)
class RevoluteJoint:
    """Ideal pin between ``points[0]`` of ``bodies[0]`` and ``points[1]`` of ``bodies[1]``."""

    type: Literal["revolute"] = "revolute"
    bodies: tuple[str, str]
    points: tuple[str, str]


@dataclass(frozen=True, kw_only=True)
class PrismaticJoint:
    """Ideal slide: ``bodies[1]``'s point moves along ``axis`` (unit, in ``bodies[0]``'s frame)
    through ``bodies[0]``'s point, with no relative rotation."""

    type: Literal["prismatic"] = "prismatic"
    bodies: tuple[str, str]
    points: tuple[str, str]
    axis: Vec2 = (1.0, 0.0)


@dataclass(frozen=True, kw_only=True)
class FixedJoint:
    """Welds two bodies at their current relative pose (3 constraints)."""

    type: Literal["fixed"] = "fixed"
    bodies: tuple[str, str]
    points: tuple[str, str]


@dataclass(frozen=True, kw_only=True)
class ContactLaw:
    """Normal contact force law of a clearance joint.

    ``law``: ``"lankarani-nikravesh"`` (F = Kδⁿ[1 + 3(1−cₑ²)δ̇/(4δ̇⁻)]), ``"hertz"`` (no
    damping), ``"flores"`` (Flores et al. 2011, D = 8(1−cₑ)/(5cₑ)·Kδⁿ/δ̇⁻), ``"hu-guo"``.
    ``stiffness``: ``"conformal"`` (R* = R_b R_j/(R_b − R_j)), ``"sum-of-radii"``
    (R* = R_b R_j/(R_b + R_j), the form the paper's tables imply) or a number in N m^-n.
    ``impact_velocity_floor`` (m/s) bounds |δ̇⁻| from below for impacts at near-zero speed.
    """

    law: Literal["lankarani-nikravesh", "hertz", "flores", "hu-guo"] = "lankarani-nikravesh"
    stiffness: Literal["conformal", "sum-of-radii"] | float = "conformal"
    exponent: float = 1.5
    impact_velocity_floor: float = 1e-3  # m/s


@dataclass(frozen=True, kw_only=True)
class FrictionLaw:
    """Tangential force law: ``"none"``, ``"coulomb"`` (regularised, tanh over ``v0``) or
    ``"ambrosio"`` (c_d ramps 0 → 1 between ``v0`` and ``v1``)."""

    law: Literal["none", "coulomb", "ambrosio"] = "ambrosio"
    coefficient: float = 0.1
    v0: float = 1e-4  # m/s
    v1: float = 2e-4  # m/s


@dataclass(frozen=True, kw_only=True)
class WearSettings:
    """Archard wear of a clearance joint (issue 7); used only when ``effects.wear`` is on."""

    coefficient: float = 1.827e-13  # m2 N-1 (Archard k, V = k F s)
    regions: int = 360
    surfaces: Literal["bearing", "both"] = "both"
    spread_over_contact_width: bool = True
    smoothing_regions: int = 5
    bearing_profile: tuple[float, ...] = ()  # wear depth per region, m (empty = unworn)
    journal_profile: tuple[float, ...] = ()


@dataclass(frozen=True, kw_only=True)
class ClearanceRevolute:
    """Revolute joint with radial clearance: a journal (pin) inside a bearing (hole).

    No kinematic constraint; the journal and bearing interact through contact and friction
    forces. ``journal_radius = bearing_radius − clearance``.
    """

    type: Literal["clearance_revolute"] = "clearance_revolute"
    bearing: tuple[str, str]  # (body, point)
    journal: tuple[str, str]  # (body, point)
    bearing_radius: float  # m
    clearance: float  # radial clearance, m
    length: float  # axial contact length, m
    bearing_material: Material
    journal_material: Material
    restitution: float = 0.9
    contact: ContactLaw = field(default_factory=ContactLaw)
    friction: FrictionLaw = field(default_factory=FrictionLaw)
    wear: WearSettings = field(default_factory=WearSettings)
    initial_eccentricity: Vec2 = (0.0, 0.0)  # journal centre − bearing centre at t = 0, m

    @property
    def journal_radius(self) -> float:
        return self.bearing_radius - self.clearance


@dataclass(frozen=True, kw_only=True)
class ConstantSpeedDrive:
    """Relative angle of a revolute ``joint`` (bodies[1] w.r.t. bodies[0]) driven at a
    constant speed: θ_rel − θ₀ − ωt = 0."""

    type: Literal["constant_speed"] = "constant_speed"
    joint: str
    speed_rpm: float
    initial_angle: float = 0.0  # rad

    @property
    def speed(self) -> float:
        """Angular speed in rad/s."""
        return self.speed_rpm * 2.0 * math.pi / 60.0

    @property
    def period(self) -> float:
        """Duration of one revolution in s."""
        return 2.0 * math.pi / abs(self.speed)


@dataclass(frozen=True, kw_only=True)
class AngleProfileDrive:
    """Relative angle of ``joint`` prescribed by a periodic cubic spline through
    (``time``, ``angle``) samples; ``period`` is the drive period used for outputs."""

    type: Literal["angle_profile"] = "angle_profile"
    joint: str
    time: tuple[float, ...]
    angle: tuple[float, ...]
    period: float


@dataclass(frozen=True, kw_only=True)
class SolverSettings:
    method: str = "dopri5"
    rtol: float = 1e-5
    atol: float = 1e-5
    max_step: float | None = None  # s; default output_step
    output_step: float | None = None  # s; default drive period / 10000
    baumgarte_alpha: float = 50.0
    baumgarte_beta: float = 50.0
    projection: bool = False


@dataclass(frozen=True, kw_only=True)
class Outputs:
    """Which joints define the slider and crank outputs (``slider_position``, ...)."""

    slider_joint: str | None = None  # a prismatic joint; its bodies[1] is the slider
    crank_joint: str | None = None  # default: the drive joint


@dataclass(frozen=True, kw_only=True)
class Scene:
    name: str
    description: str = ""
    effects: Effects = field(default_factory=Effects)
    gravity: Vec2 = (0.0, -9.81)  # m s-2
    ground_points: dict[str, Vec2] = field(default_factory=dict)
    bodies: dict[str, RigidBody | AncfBeam] = field(default_factory=dict)
    joints: dict[str, RevoluteJoint | PrismaticJoint | FixedJoint | ClearanceRevolute] = field(
        default_factory=dict
    )
    drive: ConstantSpeedDrive | AngleProfileDrive | None = None
    solver: SolverSettings = field(default_factory=SolverSettings)
    outputs: Outputs = field(default_factory=Outputs)
