"""The scene data model: frozen dataclasses that a TOML scene is validated into.

The parts of a scene; :class:`Scene` itself and its loading live in ``_scene.py``.
This module is the contract between scene loading (``_scene.py``) and assembly
(``mechanism/core/model/_assemble.py``). All quantities are SI (m, kg, s, rad, N, Pa); rpm appears
only in :class:`ConstantSpeedDrive` as the user-facing ``speed_rpm``.

The TOML keys are exactly the dataclass field names, so a TOML file, the JSON form
(:meth:`Scene.to_json`) and the dotted keys of :meth:`Scene.replace` use the same names
(full reference: ``docs/scenes.md``)::

    name = "..."                     # Scene.name
    description = "..."
    gravity = [gx, gy]               # m s-2
    [effects]                        # clearance, friction, gravity, flexibility, wear
    [ground_points]                  # NAME = [x, y] on the frame ("ground"), m
    [bodies.NAME]                    # type = "rigid" (default) or "ancf_beam", ...
    [joints.NAME]                    # type = "revolute" | "prismatic" | "fixed"
                                     #      | "clearance_revolute" | "clearance_prismatic"
    [joints.NAME.contact]            # clearance joints: normal force law
    [joints.NAME.friction]           #                   tangential force law
    [joints.NAME.wear]               #                   Archard wear settings
    [joints.NAME.lubrication]        #                   oil film (absent: dry)
    [forces.NAME]                    # type = "spring_damper" | "rotational_spring_damper"
                                     #      | "load"
    [drive]                          # type = "constant_speed" (default), "angle_profile"
                                     #      or "motor"
    [solver]                         # method, rtol, atol, max_step, output_step, baumgarte_*
    [outputs]                        # slider_joint, crank_joint

e.g. ``joints.C.clearance``, ``joints.C.contact.law``, ``drive.speed_rpm``,
``effects.clearance``. Field annotations carry the accepted range (``annotated_types``
bounds, enforced by pydantic when a scene is loaded) and the unit (:class:`Unit`, used in
error messages and the documentation). Constructing the dataclasses directly in Python
does not validate; pass the result through :func:`mechanism.core.scene.validate_scene` to check it.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import astuple, dataclass, field
from typing import Annotated, Any, Literal

from annotated_types import Ge, Gt, Le, Lt, MaxLen, MinLen
from pydantic import (
    AfterValidator,
    ConfigDict,
    Discriminator,
    PlainValidator,
    Strict,
    Tag,
    with_config,
)

__all__ = [
    "GROUND",
    "AncfBeam",
    "AngleProfileDrive",
    "ClearancePrismatic",
    "ClearanceRevolute",
    "ConstantSpeedDrive",
    "ContactLaw",
    "Effects",
    "FixedJoint",
    "ForceDeflectionTable",
    "ForceVelocityTable",
    "FourierProfile",
    "FrictionLaw",
    "JointCoordinateProfile",
    "Load",
    "Lubrication",
    "Material",
    "MotorDrive",
    "MotorTorqueTable",
    "Outputs",
    "PrismaticJoint",
    "RevoluteJoint",
    "RigidBody",
    "RotationalSpringDamper",
    "SolverSettings",
    "SpringDamper",
    "TimeTableProfile",
    "WearSettings",
]

GROUND = "ground"


@dataclass(frozen=True)
class Unit:
    """Annotation marker: the SI unit of a field ("1" = dimensionless, "" = mixed)."""

    symbol: str


def _no_control(value: str) -> str:
    """A name is one line of printable text: control characters (NUL, line breaks, ...)
    cannot be stored in the netCDF attributes of a run, nor shown on one line."""
    bad = next((ch for ch in value if ord(ch) < 0x20 or 0x7F <= ord(ch) < 0xA0), None)
    if bad is not None:
        raise ValueError(
            f"must not contain control characters (U+{ord(bad):04X} at position {value.index(bad)})"
        )
    return value


def _text(value: str) -> str:
    """Free text may hold line breaks and tabs, but no other control character."""
    _no_control(value.replace("\n", " ").replace("\t", " ").replace("\r", " "))
    return value


# Strict scalars: a TOML string "0.5" or a boolean is not silently taken for a number.
Real = Annotated[float, Strict()]
Count = Annotated[int, Strict()]
Flag = Annotated[bool, Strict()]
Name = Annotated[str, Strict(), MinLen(1), AfterValidator(_no_control)]
Text = Annotated[str, Strict(), AfterValidator(_text)]
Vec2 = tuple[Real, Real]

# Accepted ranges of the physical keys (docs/scenes.md, "Accepted ranges", says why).
# Masses and inertias span twelve decades each: the constraint matrix Φq M⁻¹ Φqᵀ that
# every step factorises has entries 1/m and r²/J, and twelve decades between them leave
# about four significant digits of the constraint forces in double precision (a
# mass of 1e300 kg made those entries fall below the factorisation's pivot floor, and
# the run was reported as a singular, locked configuration).
MASS_RANGE = (1e-6, 1e6)  # kg
INERTIA_RANGE = (1e-12, 1e6)  # kg m2
COORDINATE_LIMIT = 1e3  # m, |x| and |y| of every point and position
ANGLE_LIMIT = 1e3  # rad, |angle| of an initial pose
# the largest integer keys: each sizes arrays that the simulator holds per joint or rod
MAX_REGIONS = 36_000  # wear regions per part (0.01° each)
MAX_ELEMENTS = 256  # ANCF elements per rod (1028 coordinates)
MAX_SAMPLES = 100_000  # entries of a drive's angle profile and of a beam's sine modes
SPEED_RPM_RANGE = (1e-3, 1e6)  # |drive.speed_rpm|, rpm

Mass = Annotated[Real, Ge(MASS_RANGE[0]), Le(MASS_RANGE[1]), Unit("kg")]
Inertia = Annotated[Real, Ge(INERTIA_RANGE[0]), Le(INERTIA_RANGE[1]), Unit("kg m2")]
Coordinate = Annotated[Real, Ge(-COORDINATE_LIMIT), Le(COORDINATE_LIMIT)]
Point = tuple[Coordinate, Coordinate]
Angle = Annotated[Real, Ge(-ANGLE_LIMIT), Le(ANGLE_LIMIT), Unit("rad")]
Modulus = Annotated[Real, Ge(1e3), Le(1e13), Unit("Pa")]
GRAVITY_LIMIT = 1e3  # m s-2, |g_x| and |g_y| (about 100 g)
Acceleration = Annotated[Real, Ge(-GRAVITY_LIMIT), Le(GRAVITY_LIMIT)]

# Unknown keys are errors; TOML accepts inf/nan literals, a scene never does.
MODEL_CONFIG = ConfigDict(extra="forbid", allow_inf_nan=False)


def _speed(value: float) -> float:
    low, high = SPEED_RPM_RANGE
    if not low <= abs(value) <= high:
        raise ValueError(
            f"must be nonzero, with |speed_rpm| in [{low:g}, {high:g}] "
            "(rpm; negative turns clockwise)"
        )
    return value


STIFFNESS_FORMS = ("conformal", "sum-of-radii")
STIFFNESS_RANGE = (1e3, 1e16)  # N m^-n: from rubber pads to the hardest steel contacts


def _stiffness(value: Any) -> str | float:
    if isinstance(value, str) and value in STIFFNESS_FORMS:
        return value
    low, high = STIFFNESS_RANGE
    if (
        isinstance(value, int | float)
        and not isinstance(value, bool)
        and math.isfinite(value)
        and low <= value <= high
    ):
        return float(value)
    raise ValueError(
        f"must be 'conformal', 'sum-of-radii' or a number in [{low:g}, {high:g}] (N m^-n)"
    )


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Effects:
    """Which physical effects the simulation evaluates; an effect that is off costs nothing.

    ``clearance=False`` turns every clearance joint into an ideal revolute joint.
    ``flexibility=False`` turns every ANCF beam into an equivalent rigid body.
    """

    clearance: Flag = True
    friction: Flag = True
    gravity: Flag = True
    flexibility: Flag = False
    wear: Flag = False


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Material:
    """Elastic constants of one part of a clearance joint."""

    youngs_modulus: Modulus
    poisson_ratio: Annotated[Real, Ge(0), Lt(0.5), Unit("1")]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class RigidBody:
    """A rigid body with its reference point at the centre of mass.

    ``points`` are named points in body coordinates (m, relative to the centre of mass);
    ``position`` and ``angle`` are the initial guess of the pose, refined by assembly.
    ``inertia`` (about the centre of mass) may be left out (None) for a body that cannot
    rotate — one held to the ground by a prismatic or fixed joint, such as a slider —;
    validation then sets it to ``mass`` × (1 m)², which has no effect on the motion.
    """

    type: Literal["rigid"] = "rigid"
    mass: Mass
    inertia: Inertia | None = None  # about the centre of mass
    position: Annotated[Point, Unit("m")] = (0.0, 0.0)
    angle: Angle = 0.0
    points: Annotated[dict[str, Point], Unit("m")] = field(default_factory=dict)

    @property
    def point_names(self) -> tuple[str, ...]:
        """Names a joint may refer to on this body."""
        return tuple(self.points)


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class AncfBeam:
    """A 2-D gradient-deficient ANCF beam  between two named end points.

    The beam is straight and unstressed at t = 0 from ``start`` to ``end`` (global, m);
    its points are ``"start"`` (node 1) and ``"end"`` (last node). ``length`` is the
    unstressed length; ``|end − start|`` must agree with it to 0.1 % (assembly places the
    nodes exactly). With ``effects.flexibility = False`` it is replaced by a rigid bar of
    mass :attr:`total_mass` and centroidal inertia :attr:`centroidal_inertia`
    (m L²/12 unless ``rigid_inertia`` overrides it).
    """

    type: Literal["ancf_beam"] = "ancf_beam"
    length: Annotated[Real, Ge(1e-4), Le(COORDINATE_LIMIT), Unit("m")]
    elements: Annotated[Count, Ge(1), Le(MAX_ELEMENTS), Unit("1")] = 16
    area: Annotated[Real, Ge(1e-12), Le(1.0), Unit("m2")]
    second_moment: Annotated[Real, Ge(1e-24), Le(1.0), Unit("m4")]
    youngs_modulus: Modulus
    density: Annotated[Real, Ge(1.0), Le(1e5), Unit("kg m-3")]
    damping: Annotated[Real, Ge(0), Le(1.0), Unit("s")] = 0.0  # stiffness-proportional
    start: Annotated[Point, Unit("m")]  # initial global position of node 1
    end: Annotated[Point, Unit("m")]  # initial global position of the last node
    mass: Mass | None = None  # default density*area*length
    rigid_inertia: Inertia | None = None  # about the centroid
    # formulation (docs/ancf.md §1): Biot strain + material curvature pass S4/S5; the
    # paper's literal form is axial_strain = "green", curvature = "linear"
    axial_strain: Literal["biot", "green"] = "biot"
    curvature: Literal["material", "geometric", "linear"] = "material"
    # elastic initial velocities (m/s) on sin(k pi s/L), k = 1, 2, ..., along the left
    # normal of the chord, added to the rigid motion (Simeon's slider-crank, S6)
    initial_sine_velocities: Annotated[
        tuple[Annotated[Real, Ge(-1e3), Le(1e3)], ...], MaxLen(MAX_SAMPLES), Unit("m s-1")
    ] = ()

    @property
    def point_names(self) -> tuple[str, ...]:
        """Names a joint may refer to on this body."""
        return ("start", "end")

    @property
    def total_mass(self) -> float:
        """Mass in kg: ``mass`` if given, else ``density * area * length``."""
        return self.mass if self.mass is not None else self.density * self.area * self.length

    @property
    def centroidal_inertia(self) -> float:
        """Inertia of the rigid fallback about its centroid in kg m²: m L²/12 or the override."""
        if self.rigid_inertia is not None:
            return self.rigid_inertia
        return self.total_mass * self.length**2 / 12.0


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class RevoluteJoint:
    """Ideal pin between ``points[0]`` of ``bodies[0]`` and ``points[1]`` of ``bodies[1]``."""

    type: Literal["revolute"] = "revolute"
    bodies: tuple[Name, Name]
    points: tuple[Name, Name]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class PrismaticJoint:
    """Ideal slide: ``bodies[1]``'s point moves along ``axis`` (unit, in ``bodies[0]``'s frame)
    through ``bodies[0]``'s point, with no relative rotation."""

    type: Literal["prismatic"] = "prismatic"
    bodies: tuple[Name, Name]
    points: tuple[Name, Name]
    axis: Annotated[Vec2, Unit("1")] = (1.0, 0.0)


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class FixedJoint:
    """Welds two bodies at their current relative pose (3 constraints)."""

    type: Literal["fixed"] = "fixed"
    bodies: tuple[Name, Name]
    points: tuple[Name, Name]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ContactLaw:
    """Normal contact force law of a clearance joint.

    ``law``: ``"lankarani-nikravesh"`` (F = Kδⁿ[1 + 3(1−cₑ²)δ̇/(4δ̇⁻)]), ``"hertz"`` (no
    damping), ``"flores"`` (Flores et al. 2011, D = 8(1−cₑ)/(5cₑ)·Kδⁿ/δ̇⁻), ``"hu-guo"``.
    ``stiffness``: ``"conformal"`` (R* = R_b R_j/(R_b − R_j)), ``"sum-of-radii"``
    (R* = R_b R_j/(R_b + R_j), the form the paper's tables imply) or a number in N m^-n.
    ``impact_velocity_floor`` (m/s) bounds ``|δ̇⁻|`` from below for impacts at near-zero speed.
    ``approach_speed``: the δ̇⁻ that divides the damping term. ``"latched"`` (default, until
    the sample data are regenerated) is the textbook form, the approach speed latched at
    contact entry. ``"bounded"`` (recommended after wear) uses
    max(latched, δ̇/2) while compressing: a contact entered at a grazing speed and then
    driven in fast (sustained sliding on a worn surface) is damped like an impact at its
    current rate, so the force stays below (1 + 2χ̂)Kδⁿ instead of a multiple of the
    elastic force; a free impact never has δ̇ above its approach speed, so its restitution
    is unchanged (``docs/contact-and-wear.md`` §2).
    """

    law: Literal["lankarani-nikravesh", "hertz", "flores", "hu-guo"] = "lankarani-nikravesh"
    stiffness: Annotated[
        Literal["conformal", "sum-of-radii"] | float, PlainValidator(_stiffness), Unit("N m^-n")
    ] = "conformal"
    exponent: Annotated[Real, Ge(1), Le(3), Unit("1")] = 1.5
    impact_velocity_floor: Annotated[Real, Ge(1e-6), Le(1.0), Unit("m s-1")] = 1e-3
    approach_speed: Literal["latched", "bounded"] = "latched"


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class FrictionLaw:
    """Tangential force law: ``"none"``, ``"coulomb"`` (regularised, tanh over ``v0``) or
    ``"ambrosio"`` (c_d ramps 0 → 1 between ``v0`` and ``v1``; needs ``v1 > v0``)."""

    law: Literal["none", "coulomb", "ambrosio"] = "ambrosio"
    coefficient: Annotated[Real, Ge(0), Le(5.0), Unit("1")] = 0.1
    v0: Annotated[Real, Ge(1e-7), Le(10.0), Unit("m s-1")] = 1e-4
    v1: Annotated[Real, Ge(1e-7), Le(10.0), Unit("m s-1")] = 2e-4


Depth = Annotated[Real, Ge(0), Le(1.0)]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class WearSettings:
    """Archard wear of a clearance joint .

    A non-empty profile always shapes the contact (local clearance and stiffness); wear is
    accumulated during a simulation only when ``effects.wear`` is on.

    A profile is empty (unworn) or holds one depth per region, region n covering the
    angles [n, n + 1)·2π/``regions`` of that part's own frame.
    """

    coefficient: Annotated[Real, Ge(0), Le(1e-8), Unit("m2 N-1")] = 1.827e-13  # V = k F s
    regions: Annotated[Count, Ge(3), Le(MAX_REGIONS), Unit("1")] = 360
    surfaces: Literal["bearing", "both"] = "both"
    spread_over_contact_width: Flag = True
    smoothing_regions: Annotated[Count, Ge(1), Le(MAX_REGIONS), Unit("1")] = 5
    bearing_profile: Annotated[tuple[Depth, ...], MaxLen(MAX_REGIONS), Unit("m")] = ()
    journal_profile: Annotated[tuple[Depth, ...], MaxLen(MAX_REGIONS), Unit("m")] = ()
    # bound of the worn local R* relative to the unworn one (flat or bulging worn patches)
    radius_ratio_limit: Annotated[Real, Ge(1), Le(1e6), Unit("1")] = 10.0


VISCOSITY_RANGE = (1e-6, 100.0)  # Pa s: from gases (1.8e-5) to the heaviest gear oils


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Lubrication:
    """Oil film of a clearance joint: the short-bearing force while the minimum film
    thickness c(1 − ε) is above ``film_breakdown`` (faded out linearly from twice it), the
    dry contact law below. ``length``: the bearing's (None: the joint's ``length``);
    ``cavitation``: ``"pi-film"`` (the Pinkus–Sternlicht form, as Flores et al. 2006) or
    ``"positive-pressure"`` (``docs/contact-and-wear.md``, "Lubricated joints")."""

    viscosity: Annotated[Real, Ge(VISCOSITY_RANGE[0]), Le(VISCOSITY_RANGE[1]), Unit("Pa s")]
    length: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")] | None = None
    film_breakdown: Annotated[Real, Ge(0), Le(1.0), Unit("m")] = 1e-6  # < clearance
    cavitation: Literal["pi-film", "positive-pressure"] = "pi-film"


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ClearanceRevolute:
    """Revolute joint with radial clearance: a journal (pin) inside a bearing (hole).

    No kinematic constraint; the journal and bearing interact through contact and friction
    forces. ``journal_radius = bearing_radius − clearance``.
    """

    type: Literal["clearance_revolute"] = "clearance_revolute"
    bearing: tuple[Name, Name]  # (body, point)
    journal: tuple[Name, Name]  # (body, point)
    bearing_radius: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")]
    clearance: Annotated[Real, Ge(1e-8), Le(1.0), Unit("m")]  # radial, < bearing_radius
    length: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")]  # axial contact length
    bearing_material: Material
    journal_material: Material
    restitution: Annotated[Real, Ge(0.01), Le(1), Unit("1")] = 0.9
    contact: ContactLaw = field(default_factory=ContactLaw)
    friction: FrictionLaw = field(default_factory=FrictionLaw)
    wear: WearSettings = field(default_factory=WearSettings)
    # journal centre − bearing centre at t = 0, global frame; |.| <= clearance
    initial_eccentricity: Annotated[Vec2, Unit("m")] = (0.0, 0.0)
    lubrication: Lubrication | None = None  # None: a dry joint

    @property
    def journal_radius(self) -> float:
        return self.bearing_radius - self.clearance


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ClearancePrismatic:
    """Translational joint with clearance: a ``slider_length`` × ``slider_width`` slider on
    ``slider`` in a guide through ``guide`` along ``axis``, ``clearance`` wider on each side;
    no constraint, contact at its four corners (``docs/contact-and-wear.md`` §9)."""

    type: Literal["clearance_prismatic"] = "clearance_prismatic"
    guide: tuple[Name, Name]  # (body, point on the guide's centre line)
    slider: tuple[Name, Name]  # (body, point at the centre of the slider)
    axis: Annotated[Vec2, Unit("1")] = (1.0, 0.0)
    slider_length: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")]
    slider_width: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")]
    clearance: Annotated[Real, Ge(1e-8), Le(1.0), Unit("m")]  # per side
    guide_material: Material
    slider_material: Material
    corner_radius: Annotated[Real, Ge(1e-6), Le(10.0), Unit("m")] | None = None
    restitution: Annotated[Real, Ge(0.01), Le(1), Unit("1")] = 0.9
    contact: ContactLaw = field(default_factory=ContactLaw)
    friction: FrictionLaw = field(default_factory=FrictionLaw)
    initial_offset: Annotated[Real, Ge(-1.0), Le(1.0), Unit("m")] = 0.0


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ConstantSpeedDrive:
    """Relative angle of a revolute ``joint`` (bodies[1] w.r.t. bodies[0]) driven at a
    constant speed: θ_rel − θ₀ − ωt = 0."""

    type: Literal["constant_speed"] = "constant_speed"
    joint: Name
    speed_rpm: Annotated[Real, AfterValidator(_speed), Unit("rpm")]
    initial_angle: Angle = 0.0

    @property
    def speed(self) -> float:
        """Angular speed in rad/s."""
        return self.speed_rpm * 2.0 * math.pi / 60.0

    @property
    def period(self) -> float:
        """Duration of one revolution in s."""
        return 2.0 * math.pi / abs(self.speed)


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class AngleProfileDrive:
    """Relative angle of ``joint`` prescribed by a periodic cubic spline through
    (``time``, ``angle``) samples; ``period`` is the drive period used for outputs."""

    type: Literal["angle_profile"] = "angle_profile"
    joint: Name
    time: Annotated[tuple[Real, ...], MaxLen(MAX_SAMPLES), Unit("s")]  # increasing, <= period
    angle: Annotated[tuple[Angle, ...], MaxLen(MAX_SAMPLES), Unit("rad")]  # one per time
    period: Annotated[Real, Ge(6e-5), Le(6e4), Unit("s")]  # the speed range's periods


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class SolverSettings:
    """Integrator settings; ``method`` names are those ``mechanism.simulate`` accepts
    (``mechanism.core.integrate.METHODS``: ``"dopri5"``, the scipy ``solve_ivp`` methods, the
    implicit ``"generalized-alpha"`` and ``"generalized-alpha-fixed"``).

    The default ``"auto"`` is resolved once the scene is assembled: the fixed-step
    generalized-α (step ``max_step``, else the output step) when the model has ANCF beams
    (``effects.flexibility`` on), else ``"dopri5"`` (docs/ancf.md §8). Switching
    flexibility off therefore gives the rigid model at rigid-model cost. ``rho_inf`` is
    the spectral radius at infinite frequency of the generalized-α methods (their
    numerical damping; ignored by the others).
    """

    method: Name = "auto"
    rtol: Annotated[Real, Ge(1e-13), Lt(1), Unit("1")] = 1e-5
    atol: Annotated[Real, Ge(1e-15), Le(1.0), Unit("")] = 1e-5
    max_step: Annotated[Real, Gt(0), Unit("s")] | None = None  # unset: approach bound
    output_step: Annotated[Real, Gt(0), Unit("s")] | None = None  # default period / 10000
    baumgarte_alpha: Annotated[Real, Ge(0), Le(1e4), Unit("s-1")] = 50.0
    baumgarte_beta: Annotated[Real, Ge(0), Le(1e4), Unit("s-1")] = 50.0
    projection: Flag = False
    rho_inf: Annotated[Real, Ge(0), Le(1), Unit("1")] = 0.8


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Outputs:
    """Which joints define the slider and crank outputs (``slider_position``, ...)."""

    slider_joint: Name | None = None  # a prismatic joint; its bodies[1] is the slider
    crank_joint: Name | None = None  # a revolute joint; default: the drive joint


# ---------------------------------------------------------------------------------------
# Force elements (docs/force-elements.md): springs, dampers, actuators and applied loads

STIFFNESS_LIMIT = 1e12  # N/m of a translational spring (a steel rod of 1 cm² over 20 µm)
DAMPING_LIMIT = 1e9  # N s/m
TORSION_STIFFNESS_LIMIT = 1e9  # N m/rad
TORSION_DAMPING_LIMIT = 1e6  # N m s/rad
FORCE_LIMIT = 1e9  # N, |actuator force|, |load|, |table force|
TORQUE_LIMIT = 1e9  # N m
FACTOR_LIMIT = 1e6  # |profile factor| and |Fourier coefficient|
MAX_HARMONICS = 1000  # Fourier terms of a time profile

Force = Annotated[Real, Ge(-FORCE_LIMIT), Le(FORCE_LIMIT), Unit("N")]
Torque = Annotated[Real, Ge(-TORQUE_LIMIT), Le(TORQUE_LIMIT), Unit("N m")]
Factor = Annotated[Real, Ge(-FACTOR_LIMIT), Le(FACTOR_LIMIT), Unit("1")]


# table columns: at most MAX_SAMPLES numbers each
Deflections = Annotated[tuple[Coordinate, ...], MaxLen(MAX_SAMPLES), Unit("m")]
Velocities = Annotated[
    tuple[Annotated[Real, Ge(-1e4), Le(1e4)], ...], MaxLen(MAX_SAMPLES), Unit("m s-1")
]
Forces = Annotated[tuple[Force, ...], MaxLen(MAX_SAMPLES), Unit("N")]
Times = Annotated[tuple[Annotated[Real, Ge(0), Le(1e6)], ...], MaxLen(MAX_SAMPLES), Unit("s")]
Factors = Annotated[tuple[Factor, ...], MaxLen(MAX_SAMPLES), Unit("1")]
JointCoordinates = Annotated[tuple[Coordinate, ...], MaxLen(MAX_SAMPLES), Unit("m or rad")]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ForceDeflectionTable:
    """Nonlinear spring law: tension (N) at each deflection L − L₀ (m), interpolated
    linearly; outside the table the end values hold (clamped). ``deflection`` strictly
    increasing, one ``force`` per deflection, at least 2 entries."""

    deflection: Deflections
    force: Forces


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class ForceVelocityTable:
    """Nonlinear damper law: tension (N) at each extension rate L̇ (m/s), interpolated
    linearly; outside the table the end values hold (clamped). ``velocity`` strictly
    increasing, one ``force`` per velocity, at least 2 entries."""

    velocity: Velocities
    force: Forces


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class SpringDamper:
    """Translational spring–damper–actuator between ``points[0]`` of ``bodies[0]`` and
    ``points[1]`` of ``bodies[1]``, acting along the line through them.

    Tension T = k (L − L₀) + f_k(L − L₀) + c L̇ + f_c(L̇) + ``actuator_force``, with L the
    distance of the points and f_k, f_c the optional tables (they add to the linear
    terms; set ``stiffness = 0`` for a purely tabulated law). A positive tension pulls
    the points together. The spring and the actuator force store potential energy; the
    damper dissipates.
    """

    type: Literal["spring_damper"] = "spring_damper"
    bodies: tuple[Name, Name]
    points: tuple[Name, Name]
    stiffness: Annotated[Real, Ge(0), Le(STIFFNESS_LIMIT), Unit("N m-1")] = 0.0
    damping: Annotated[Real, Ge(0), Le(DAMPING_LIMIT), Unit("N s m-1")] = 0.0
    free_length: Annotated[Real, Ge(0), Le(COORDINATE_LIMIT), Unit("m")]
    actuator_force: Force = 0.0
    force_deflection: ForceDeflectionTable | None = None
    force_velocity: ForceVelocityTable | None = None


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class RotationalSpringDamper:
    """Torsional spring–damper at a revolute (or clearance revolute) ``joint``.

    With φ the angle of the joint's second body relative to its first (the journal's
    relative to the bearing's), the moment on the second body is
    −k (φ − ``reference_angle``) − c φ̇ + ``actuator_torque`` (counter-clockwise positive),
    and its opposite acts on the first.
    """

    type: Literal["rotational_spring_damper"] = "rotational_spring_damper"
    joint: Name
    stiffness: Annotated[Real, Ge(0), Le(TORSION_STIFFNESS_LIMIT), Unit("N m rad-1")] = 0.0
    damping: Annotated[Real, Ge(0), Le(TORSION_DAMPING_LIMIT), Unit("N m s rad-1")] = 0.0
    reference_angle: Angle = 0.0
    actuator_torque: Torque = 0.0


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class FourierProfile:
    """Periodic factor a₀ + Σₖ aₖ cos(2πkt/P) + bₖ sin(2πkt/P), k = 1, 2, ...
    (``mean`` = a₀, ``cosine`` = a₁..., ``sine`` = b₁...)."""

    type: Literal["fourier"] = "fourier"
    period: Annotated[Real, Ge(1e-6), Le(1e6), Unit("s")]
    mean: Factor = 0.0
    cosine: Annotated[tuple[Factor, ...], MaxLen(MAX_HARMONICS), Unit("1")] = ()
    sine: Annotated[tuple[Factor, ...], MaxLen(MAX_HARMONICS), Unit("1")] = ()


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class TimeTableProfile:
    """Periodic factor through (``time``, ``factor``) samples over one ``period``,
    interpolated linearly and closed from the last sample back to the first (which
    repeats at ``time[0]`` + ``period``)."""

    type: Literal["table"] = "table"
    period: Annotated[Real, Ge(1e-6), Le(1e6), Unit("s")]
    time: Times
    factor: Factors


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class JointCoordinateProfile:
    """Factor as a function of a joint coordinate: the slider position s along a
    prismatic ``joint``'s axis (m, as the ``slider_position`` output) or the relative
    angle of a revolute joint (rad, unwrapped), interpolated linearly through
    (``coordinate``, ``factor``); outside the table the end values hold (clamped).

    ``active``: ``"always"``, or only while the coordinate ``"increasing"`` (ṡ > 0) or
    ``"decreasing"`` (ṡ < 0) — a press's working force acts on the working stroke only.
    """

    joint: Name
    coordinate: JointCoordinates
    factor: Factors
    active: Literal["always", "increasing", "decreasing"] = "always"


def _profile_tag(value: Any) -> str | None:
    return _tag(value, None)


TimeProfile = Annotated[
    Annotated[FourierProfile, Tag("fourier")] | Annotated[TimeTableProfile, Tag("table")],
    Discriminator(_profile_tag),
]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Load:
    """Applied force and torque at ``point`` of ``body``: (``force``, ``torque``) times the
    factor of ``time_profile`` (1 if absent) times the factor of ``coordinate_profile``
    (1 if absent). ``frame = "body"`` turns ``force`` with the body (a follower load);
    ``"global"`` keeps its direction fixed. Applied loads do work but store no energy.
    """

    type: Literal["load"] = "load"
    body: Name
    point: Name
    force: Annotated[tuple[Force, Force], Unit("N")] = (0.0, 0.0)
    torque: Torque = 0.0
    frame: Literal["global", "body"] = "global"
    time_profile: TimeProfile | None = None
    coordinate_profile: JointCoordinateProfile | None = None


RpmValue = Annotated[Real, Ge(-SPEED_RPM_RANGE[1]), Le(SPEED_RPM_RANGE[1])]
MotorSpeeds = Annotated[tuple[RpmValue, ...], MaxLen(MAX_SAMPLES), Unit("rpm")]
Torques = Annotated[tuple[Torque, ...], MaxLen(MAX_SAMPLES), Unit("N m")]


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class MotorTorqueTable:
    """Tabulated torque–speed curve of a motor: ``torque`` (N m) at each ``speed_rpm``
    (the joint's relative rate, rpm, counter-clockwise positive), interpolated linearly;
    outside the table the end values hold (clamped). ``speed_rpm`` strictly increasing,
    one ``torque`` per speed, at least 2 entries."""

    speed_rpm: MotorSpeeds
    torque: Torques


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class MotorDrive:
    """A motor at a revolute ``joint``: the torque T(ω) on bodies[1] (its opposite on
    bodies[0]), ω the joint's relative rate (counter-clockwise positive), either the
    linear curve T(ω) = ``stall_torque`` (1 − ω/ω₀), ω₀ the ``no_load_speed_rpm``, or a
    measured ``torque_speed`` (:class:`MotorTorqueTable`). ``flywheel_inertia`` (kg m²)
    adds to the moment of inertia of the rigid bodies[1]. The joint's angle is free: the
    motion is autonomous and starts from the scene's pose, at rest or with the joint
    turning at ``initial_speed_rpm`` (the other bodies at the velocities of the ideal
    mechanism). ``stall_torque = 0`` leaves the crank free (no torque): a mechanism
    launched at ``initial_speed_rpm`` that runs down or swings on its own."""

    type: Literal["motor"] = "motor"
    joint: Name
    stall_torque: Annotated[Real, Ge(0), Le(TORQUE_LIMIT), Unit("N m")] | None = None
    no_load_speed_rpm: (
        Annotated[Real, Ge(SPEED_RPM_RANGE[0]), Le(SPEED_RPM_RANGE[1]), Unit("rpm")] | None
    ) = None
    torque_speed: MotorTorqueTable | None = None
    flywheel_inertia: Annotated[Real, Ge(0), Le(INERTIA_RANGE[1]), Unit("kg m2")] = 0.0
    initial_speed_rpm: Annotated[
        Real, Ge(-SPEED_RPM_RANGE[1]), Le(SPEED_RPM_RANGE[1]), Unit("rpm")
    ] = 0.0

    @property
    def no_load_speed(self) -> float:
        """ω₀ in rad/s: of the linear curve, or the lowest positive speed at which the
        tabulated torque falls to 0 (the highest tabulated speed if it never does)."""
        rpm = 2.0 * math.pi / 60.0
        table = self.torque_speed
        if table is None:
            return float(self.no_load_speed_rpm or 0.0) * rpm
        for (w0, t0), (w1, t1) in itertools.pairwise(zip(*astuple(table), strict=True)):
            if w1 > 0.0 and t1 <= 0.0 < t0:
                return max(w0 + (w1 - w0) * t0 / (t0 - t1), 0.0) * rpm
        return max(table.speed_rpm, default=0.0) * rpm

    @property
    def damping(self) -> float:
        """−dT/dω = stall torque / ω₀ (N m s/rad) of the linear curve (0 for a table)."""
        if self.torque_speed is not None or not self.stall_torque:
            return 0.0
        return self.stall_torque / self.no_load_speed


def _body_tag(value: Any) -> str | None:
    return _tag(value, "rigid")


def _joint_tag(value: Any) -> str | None:
    return _tag(value, None)


def _drive_tag(value: Any) -> str | None:
    return _tag(value, "constant_speed")


def _tag(value: Any, default: str | None) -> str | None:
    if isinstance(value, dict):
        tag = value.get("type", default)
        return tag if tag is None or isinstance(tag, str) else repr(tag)
    return getattr(value, "type", None)


Body = Annotated[
    Annotated[RigidBody, Tag("rigid")] | Annotated[AncfBeam, Tag("ancf_beam")],
    Discriminator(_body_tag),
]
Joint = Annotated[
    Annotated[RevoluteJoint, Tag("revolute")]
    | Annotated[PrismaticJoint, Tag("prismatic")]
    | Annotated[FixedJoint, Tag("fixed")]
    | Annotated[ClearanceRevolute, Tag("clearance_revolute")]
    | Annotated[ClearancePrismatic, Tag("clearance_prismatic")],
    Discriminator(_joint_tag),
]
Drive = Annotated[
    Annotated[ConstantSpeedDrive, Tag("constant_speed")]
    | Annotated[AngleProfileDrive, Tag("angle_profile")]
    | Annotated[MotorDrive, Tag("motor")],
    Discriminator(_drive_tag),
]
ForceElement = Annotated[
    Annotated[SpringDamper, Tag("spring_damper")]
    | Annotated[RotationalSpringDamper, Tag("rotational_spring_damper")]
    | Annotated[Load, Tag("load")],
    Discriminator(_joint_tag),
]
