"""The :class:`~mechanism.Scene`: its validation and its plain-data, JSON and TOML forms
(``load_scene`` and the built-in scenes are in ``_load.py``).

Validation has two stages. Field validation (pydantic ``TypeAdapter`` over the frozen
dataclasses of ``_model.py``) checks types, ranges and unknown keys; every error is
reported with its key path, the accepted range and the unit (``_messages.py``), e.g.
``joints.C.clearance: must be > 0 (m); got -0.001``. Cross-checks then check what one
field cannot know: bodies and points named by joints exist, a clearance is smaller than
its bearing radius, the drive acts on an ideal revolute joint, and so on.
"""

from __future__ import annotations

import dataclasses
import functools
import itertools
import json
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import TypeAdapter, ValidationError, with_config

from chaoskit.contract import atomic_write

from ._force_checks import force_problems
from ._messages import SceneError, describe_errors, format_number
from ._model import (
    GROUND,
    INERTIA_RANGE,
    MASS_RANGE,
    MODEL_CONFIG,
    Acceleration,
    AncfBeam,
    AngleProfileDrive,
    Body,
    ClearancePrismatic,
    ClearanceRevolute,
    Drive,
    Effects,
    FixedJoint,
    ForceElement,
    Joint,
    MotorDrive,
    Name,
    Outputs,
    Point,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    SolverSettings,
    Text,
    Unit,
)
from ._replace import assign_dotted
from ._toml_writer import toml_document

#: the force-element name under which a motor drive's torque is recorded (the model's
#: force tables add it as their last element)
_MOTOR_ELEMENT = "drive"

__all__ = [
    "GYRATION_RATIO",
    "Scene",
    "replace_scene",
    "save_scene",
    "scene_from_dict",
    "scene_to_dict",
    "scene_to_json",
    "scene_to_toml",
    "validate_scene",
]

_NAME = re.compile(r"^[A-Za-z0-9_-]+$")
_BEAM_LENGTH_RTOL = 1e-3  # |end − start| vs length: catches unit slips, allows rounded input
#: the radius of gyration of a rigid body that can rotate lies within this factor of its
#: farthest point: the constraint matrix then keeps its entries 1/m and r²/J within eight
#: decades, half the digits of double precision (docs/scenes.md, "Accepted ranges")
GYRATION_RATIO = 1e4
_AXIS_TOL = 1e-6


@with_config(MODEL_CONFIG)
@dataclass(frozen=True, kw_only=True)
class Scene:
    """A planar mechanism as data: bodies, joints, force elements, drive, effects and solver
    settings.

    Load one with :func:`mechanism.load_scene` (built-in name or TOML path), change it with
    :meth:`replace`, store it with :func:`mechanism.save_scene` or :meth:`to_json`.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("slider-crank")
    >>> faster = scene.replace({"drive.speed_rpm": 6000.0})
    >>> faster.drive.speed_rpm, scene.drive.speed_rpm
    (6000.0, 5000.0)
    """

    name: Name
    description: Text = ""
    effects: Effects = field(default_factory=Effects)
    gravity: Annotated[tuple[Acceleration, Acceleration], Unit("m s-2")] = (0.0, -9.81)
    ground_points: Annotated[dict[str, Point], Unit("m")] = field(default_factory=dict)
    bodies: dict[str, Body] = field(default_factory=dict)
    joints: dict[str, Joint] = field(default_factory=dict)
    forces: dict[str, ForceElement] = field(default_factory=dict)
    drive: Drive | None = None
    solver: SolverSettings = field(default_factory=SolverSettings)
    outputs: Outputs = field(default_factory=Outputs)

    def replace(self, changes: Mapping[str, Any]) -> Scene:
        """A new validated scene with dotted keys replaced, e.g. ``{"joints.C.clearance": 2e-4}``.

        A table value (a dict) replaces the whole table. Unknown keys raise
        :class:`~mechanism.SceneError` listing the valid keys at that level.
        """
        return replace_scene(self, changes)

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dicts and lists (unset optional fields as ``None``)."""
        return scene_to_dict(self)

    def to_json(self) -> str:
        """The resolved scene as JSON text (read back with ``scene_from_json``)."""
        return scene_to_json(self)

    def to_toml(self) -> str:
        """The resolved scene as TOML text (what ``save_scene`` writes)."""
        return scene_to_toml(self)

    def save(self, path: str | Path) -> None:
        """Write the scene as TOML to ``path`` (same as ``mechanism.save_scene``)."""
        save_scene(self, path)


# ---------------------------------------------------------------------------------------
# Public functions


def save_scene(scene: Scene, path: str | Path) -> Path:
    """Validate ``scene`` and write it as TOML; :func:`load_scene` reads it back identical.

    Unset optional keys (``None``) are omitted, since TOML has no null; they load back
    as ``None``. Floats are written with the shortest repr that round-trips exactly. The
    file is written atomically (temporary file, then rename): if writing fails, e.g. on a
    full disk, an existing file at ``path`` is left as it was.

    Examples
    --------
    >>> import tempfile, pathlib, mechanism
    >>> scene = mechanism.load_scene("slider-crank")
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "sc.toml"
    >>> mechanism.load_scene(mechanism.save_scene(scene, path)) == scene
    True
    """
    validate_scene(scene)
    path = Path(path)
    header = (
        f"# mechanism scene {scene.name!r}, written by mechanism.save_scene.\n"
        "# Keys, units and accepted ranges: docs/scenes.md\n\n"
    )
    text = header + scene_to_toml(scene)
    # atomic: a failed write (a full disk) leaves the old scene file, never half a TOML
    atomic_write(path, lambda p: p.write_text(text, encoding="utf-8"), nbytes=len(text))
    return path


def scene_from_dict(data: Mapping[str, Any], *, source: str | None = None) -> Scene:
    """Validate nested mappings (TOML/JSON layout, keys = field names) into a
    :class:`~mechanism.Scene`."""
    if not isinstance(data, Mapping):
        raise SceneError(
            f"a scene must be a table of keys; got {type(data).__name__}", source=source
        )
    try:
        scene = _adapter().validate_python(_plain(dict(data)))
    except ValidationError as exc:
        raise SceneError(describe_errors(exc, Scene), source=source) from None
    problems = _cross_check(scene)
    if problems:
        raise SceneError(problems, source=source)
    return _resolve_inertias(scene)


def validate_scene(scene: Scene) -> Scene:
    """Validate a scene built in Python (the dataclasses do not check themselves)."""
    return scene_from_dict(scene_to_dict(scene), source=f"scene {scene.name!r}")


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """Nested dicts/lists of plain Python values; unset optional fields are ``None``."""
    out = _plain(scene)
    assert isinstance(out, dict)
    return out


def scene_to_json(scene: Scene) -> str:
    """JSON text of :func:`scene_to_dict` (floats exact, unset optionals as ``null``)."""
    return json.dumps(scene_to_dict(scene), allow_nan=False)


def scene_to_toml(scene: Scene) -> str:
    """TOML text of the scene in the layout of ``docs/scenes.md``."""
    return toml_document(scene_to_dict(scene))


def replace_scene(scene: Scene, changes: Mapping[str, Any]) -> Scene:
    """A new validated scene with the dotted keys of ``changes`` replaced.

    Keys are applied in order; a dict value replaces the whole table at that key. Numpy
    scalars and arrays are accepted (as Python numbers and lists).

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper")
    >>> worn = scene.replace({"joints.C.clearance": 5e-4, "effects.friction": False})
    >>> worn.joints["C"].clearance, worn.effects.friction
    (0.0005, False)
    """
    if not isinstance(changes, Mapping):
        raise TypeError(f"changes must be a mapping of dotted keys; got {type(changes).__name__}")
    data = scene_to_dict(scene)
    for key, value in changes.items():
        parts = key.split(".") if isinstance(key, str) else []
        if not parts or not all(parts):
            raise SceneError(f"{key!r}: not a dotted key such as 'joints.C.clearance'")
        assign_dotted(data, parts, _plain(value), Scene)
    return scene_from_dict(data, source=f"scene {scene.name!r} after replace")


# ---------------------------------------------------------------------------------------
# Plain data


def _plain(obj: Any) -> Any:
    """Dataclasses → dicts, tuples/arrays → lists, numpy scalars → Python scalars."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}
    if isinstance(obj, Mapping):
        return {key: _plain(value) for key, value in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(value) for value in obj]
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


@functools.cache
def _adapter() -> TypeAdapter[Scene]:
    return TypeAdapter(Scene)


# ---------------------------------------------------------------------------------------
# Cross-checks (after field validation)


def _cross_check(scene: Scene) -> list[str]:
    """Every problem that one field cannot know, in the order of the scene's tables."""
    problems = [
        *_bad_names("ground_points", scene.ground_points),
        *_bad_names("bodies", scene.bodies),
        *_bad_names("joints", scene.joints),
    ]
    if GROUND in scene.bodies:
        problems.append(
            f"bodies.{GROUND}: {GROUND!r} is the frame; use [ground_points] for its points"
        )
    problems.extend(_body_problems(scene))
    for joint_name, joint in scene.joints.items():
        problems.extend(_joint_problems(scene, f"joints.{joint_name}", joint))
    if scene.drive is not None:
        problems.extend(_drive_problems(scene, scene.drive))
    problems.extend(_bad_names("forces", scene.forces))
    problems.extend(force_problems(scene, functools.partial(_body_points, scene)))
    outputs = scene.outputs
    if outputs.slider_joint is not None:
        problems.extend(
            _joint_ref_problems(
                scene,
                "outputs.slider_joint",
                outputs.slider_joint,
                (PrismaticJoint, ClearancePrismatic),
            )
        )
    if outputs.crank_joint is not None:
        kinds = (RevoluteJoint, ClearanceRevolute)
        problems.extend(
            _joint_ref_problems(scene, "outputs.crank_joint", outputs.crank_joint, kinds)
        )
    return problems


def _bad_names(table: str, mapping: Mapping[str, Any]) -> list[str]:
    """Names that would make dotted keys ambiguous."""
    return [
        f"{table}.{name}: a name may use only letters, digits, '_' and '-' "
        "(so that dotted keys stay unambiguous)"
        for name in mapping
        if not _NAME.match(name)
    ]


def _body_points(scene: Scene, body_name: str) -> tuple[str, ...] | None:
    """The point names of a body (the ground's are ``ground_points``); None if no such body."""
    if body_name == GROUND:
        return tuple(scene.ground_points)
    body = scene.bodies.get(body_name)
    return None if body is None else body.point_names


def _end_problems(
    scene: Scene, path: str, point_path: str, body_name: str, point: str
) -> list[str]:
    """A joint end (body, point) that names no body or no point of that body."""
    points = _body_points(scene, body_name)
    if points is None:
        known = ", ".join([GROUND, *scene.bodies])
        return [f"{path}: no body {body_name!r}; bodies: {known}"]
    if point not in points:
        return [
            f"{point_path}: body {body_name!r} has no point {point!r}; "
            f"its points: {', '.join(points) or '(none)'}"
        ]
    return []


def _body_problems(scene: Scene) -> list[str]:
    """Point names, missing inertias and gyration radii of rigid bodies; mass and chord of
    ANCF beams."""
    problems: list[str] = []
    held = _held_bodies(scene)
    for body_name, body in scene.bodies.items():
        if isinstance(body, RigidBody):
            problems.extend(_bad_names(f"bodies.{body_name}.points", body.points))
            if body.inertia is None and body_name not in held:
                low, high = INERTIA_RANGE
                problems.append(
                    f"bodies.{body_name}.inertia: required key is missing (expected a number "
                    f"in [{low:g}, {high:g}] (kg m2)); only a body held to the ground by a "
                    "prismatic or fixed joint, which cannot rotate, may leave it out"
                )
            elif body.inertia is not None and body_name not in held:
                problems.extend(_gyration_problems(body_name, body))
        elif isinstance(body, AncfBeam):
            problems.extend(_beam_problems(body_name, body))
    return problems


def _gyration_problems(body_name: str, body: RigidBody) -> list[str]:
    """The radius of gyration of a body that can rotate, against its farthest point."""
    # the constraint matrix Φq M⁻¹ Φqᵀ holds 1/m and r²/J side by side: their ratio,
    # (r/k)² with k = sqrt(J/m), must leave double precision digits to spare
    reach = max((math.hypot(*p) for p in body.points.values()), default=0.0)
    if reach == 0.0 or body.inertia is None:
        return []
    ratio = math.sqrt(body.inertia / body.mass) / reach
    if 1.0 / GYRATION_RATIO <= ratio <= GYRATION_RATIO:
        return []
    return [
        f"bodies.{body_name}.inertia: the radius of gyration sqrt(inertia / mass) = "
        f"{format_number(ratio * reach)} m must be within a factor "
        f"{GYRATION_RATIO:g} of the farthest point from the centre of mass "
        f"({format_number(reach)} m); got inertia {format_number(body.inertia)} "
        f"(kg m2) with mass {format_number(body.mass)} (kg)"
    ]


def _beam_problems(body_name: str, body: AncfBeam) -> list[str]:
    """An ANCF beam's derived mass within the mass range and its chord matching its length."""
    problems: list[str] = []
    low, high = MASS_RANGE
    if body.mass is None and not low <= body.total_mass <= high:
        problems.append(
            f"bodies.{body_name}.mass: density × area × length = "
            f"{format_number(body.total_mass)} kg is outside [{low:g}, {high:g}] (kg); "
            "change them or give mass"
        )
    chord = math.dist(body.start, body.end)
    if abs(chord - body.length) > _BEAM_LENGTH_RTOL * body.length:
        problems.append(
            f"bodies.{body_name}.length: {format_number(body.length)} m differs from "
            f"|end − start| = {format_number(chord)} m by more than "
            f"{_BEAM_LENGTH_RTOL:.1%}"
        )
    return problems


def _joint_problems(scene: Scene, base: str, joint: Joint) -> list[str]:
    """The ends of one joint exist and its geometry is consistent."""
    if isinstance(joint, ClearanceRevolute):
        return _clearance_revolute_problems(scene, base, joint)
    if isinstance(joint, ClearancePrismatic):
        return _clearance_prismatic_problems(scene, base, joint)
    problems: list[str] = []
    for i in (0, 1):
        path, point_path = f"{base}.bodies[{i}]", f"{base}.points[{i}]"
        problems.extend(_end_problems(scene, path, point_path, joint.bodies[i], joint.points[i]))
    if joint.bodies[0] == joint.bodies[1]:
        problems.append(
            f"{base}.bodies: a joint needs two different bodies; got {list(joint.bodies)}"
        )
    if isinstance(joint, PrismaticJoint):
        norm = math.hypot(*joint.axis)
        if abs(norm - 1.0) > _AXIS_TOL:
            problems.append(f"{base}.axis: must be a unit vector; got length {format_number(norm)}")
    return problems


def _clearance_revolute_problems(scene: Scene, base: str, joint: ClearanceRevolute) -> list[str]:
    """Ends, clearance, initial eccentricity and friction speeds of a clearance joint."""
    problems: list[str] = []
    add = problems.append
    ends = [(f"{base}.bearing", joint.bearing), (f"{base}.journal", joint.journal)]
    for path, (body_name, point) in ends:
        problems.extend(_end_problems(scene, f"{path}[0]", f"{path}[1]", body_name, point))
    if joint.bearing[0] == joint.journal[0]:
        add(f"{base}.journal[0]: bearing and journal must be on different bodies")
    if joint.clearance >= joint.bearing_radius:
        add(
            f"{base}.clearance: must be < bearing_radius = "
            f"{format_number(joint.bearing_radius)} (m); "
            f"got {format_number(joint.clearance)}"
        )
    ecc = math.hypot(*joint.initial_eccentricity)
    if ecc > joint.clearance:
        add(
            f"{base}.initial_eccentricity: |e| must be <= clearance = "
            f"{format_number(joint.clearance)} (m); got |e| = {format_number(ecc)}"
        )
    friction = joint.friction
    if friction.law == "ambrosio" and friction.v1 <= friction.v0:
        add(
            f"{base}.friction.v1: must be > v0 = {format_number(friction.v0)} "
            f"(m s-1); got {format_number(friction.v1)}"
        )
    problems.extend(_wear_problems(base, joint))
    return problems


def _clearance_prismatic_problems(scene: Scene, base: str, joint: ClearancePrismatic) -> list[str]:
    """Ends, bodies, axis, initial offset, stiffness and friction speeds of a translational
    clearance joint."""
    problems: list[str] = []
    add = problems.append
    for part in ("guide", "slider"):
        body_name, point = getattr(joint, part)
        problems.extend(
            _end_problems(scene, f"{base}.{part}[0]", f"{base}.{part}[1]", body_name, point)
        )
    guide_body, slider_body = joint.guide[0], joint.slider[0]
    if guide_body == slider_body:
        add(f"{base}.slider[0]: guide and slider must be on different bodies")
    if slider_body in scene.bodies and not isinstance(scene.bodies[slider_body], RigidBody):
        add(f"{base}.slider[0]: the slider must be a rigid body; {slider_body!r} is not")
    if slider_body == GROUND:
        add(f"{base}.slider[0]: the slider must be a rigid body, not the ground")
    if guide_body in scene.bodies and not isinstance(scene.bodies[guide_body], RigidBody):
        add(
            f"{base}.guide[0]: the guide must be on a rigid body or the ground; "
            f"{guide_body!r} is not rigid"
        )
    norm = math.hypot(*joint.axis)
    if abs(norm - 1.0) > _AXIS_TOL:
        add(f"{base}.axis: must be a unit vector; got length {format_number(norm)}")
    if abs(joint.initial_offset) > joint.clearance:
        add(
            f"{base}.initial_offset: |offset| must be <= clearance = "
            f"{format_number(joint.clearance)} (m); got {format_number(joint.initial_offset)}"
        )
    if isinstance(joint.contact.stiffness, str) and joint.corner_radius is None:
        add(
            f"{base}.corner_radius: required with contact.stiffness = "
            f"{joint.contact.stiffness!r} (K = (4/3) E* sqrt(corner_radius)); give a radius "
            "in [1e-06, 10] (m) or contact.stiffness as a number in [1000, 1e+16] (N m^-n)"
        )
    friction = joint.friction
    if friction.law == "ambrosio" and friction.v1 <= friction.v0:
        add(
            f"{base}.friction.v1: must be > v0 = {format_number(friction.v0)} "
            f"(m s-1); got {format_number(friction.v1)}"
        )
    if scene.effects.wear:
        add(
            f"{base}.type: wear is modelled in clearance_revolute joints only; set "
            "effects.wear = false for a scene with a clearance_prismatic joint"
        )
    return problems


def _wear_problems(base: str, joint: ClearanceRevolute) -> list[str]:
    """Profiles sized to the regions, the smoothing window, worn depths within the journal."""
    problems: list[str] = []
    wear = joint.wear
    for part in ("bearing_profile", "journal_profile"):
        n = len(getattr(wear, part))
        if n not in (0, wear.regions):
            problems.append(
                f"{base}.wear.{part}: must be empty or hold one depth per region "
                f"({wear.regions}) (m); got {n} values"
            )
    if wear.smoothing_regions > wear.regions // 2:
        # the smoothing window spans at most half the circumference
        problems.append(
            f"{base}.wear.smoothing_regions: must be <= regions // 2 "
            f"({wear.regions // 2}); got {wear.smoothing_regions}"
        )
    journal_radius = joint.bearing_radius - joint.clearance
    deepest = max(wear.journal_profile, default=0.0)
    if wear.journal_profile and 0.0 < journal_radius <= deepest:
        problems.append(
            f"{base}.wear.journal_profile: every depth must be < the journal radius "
            f"(bearing_radius - clearance = {format_number(journal_radius)} m); got "
            f"{format_number(deepest)}"
        )
    return problems


def _joint_ref_problems(
    scene: Scene, path: str, joint_name: str, kinds: tuple[type, ...]
) -> list[str]:
    """A reference to a joint that does not exist or is of the wrong type."""
    joint = scene.joints.get(joint_name)
    if joint is None:
        return [f"{path}: no joint {joint_name!r}; joints: {', '.join(scene.joints) or '(none)'}"]
    if not isinstance(joint, kinds):
        wanted = " or ".join(repr(_joint_type(kind)) for kind in kinds)
        return [f"{path}: joint {joint_name!r} is {joint.type!r}; it must be a {wanted} joint"]
    return []


def _drive_problems(scene: Scene, drive: Drive) -> list[str]:
    """The driven joint, an angle profile's samples and a motor's flywheel and name."""
    problems = _joint_ref_problems(scene, "drive.joint", drive.joint, (RevoluteJoint,))
    add = problems.append
    if isinstance(drive, AngleProfileDrive):
        t, a = drive.time, drive.angle
        if len(t) < 2 or len(t) != len(a):
            add(
                f"drive.time: needs at least 2 samples and one angle per time; "
                f"got {len(t)} times and {len(a)} angles"
            )
        elif any(t1 <= t0 for t0, t1 in itertools.pairwise(t)):
            add("drive.time: must be strictly increasing")
        elif t[-1] - t[0] > drive.period:
            add(
                f"drive.time: the samples must span at most one period "
                f"({format_number(drive.period)} s); got {format_number(t[-1] - t[0])} s"
            )
    if isinstance(drive, MotorDrive):
        driven = scene.joints.get(drive.joint)
        if (
            drive.flywheel_inertia > 0.0
            and isinstance(driven, RevoluteJoint)
            and not isinstance(scene.bodies.get(driven.bodies[1]), RigidBody)
        ):
            add(
                f"drive.flywheel_inertia: the flywheel needs a rigid second body of joint "
                f"{drive.joint!r}; got {driven.bodies[1]!r}"
            )
        if _MOTOR_ELEMENT in scene.forces:
            add(
                f"forces.{_MOTOR_ELEMENT}: the name is taken by the motor drive's torque; "
                "rename the element"
            )
    return problems


def _held_bodies(scene: Scene) -> set[str]:
    """Bodies that cannot rotate: held to the ground by a prismatic or fixed joint."""
    held = set()
    for joint in scene.joints.values():
        if isinstance(joint, PrismaticJoint | FixedJoint) and GROUND in joint.bodies:
            held.update(name for name in joint.bodies if name != GROUND)
    return held


def _resolve_inertias(scene: Scene) -> Scene:
    """Give every rigid body that left out its inertia (it cannot rotate) mass × (1 m)².

    The value does not change the motion: the joint that holds the body keeps its angle
    constant whatever the inertia. It gives the rotation row of the constraint matrix
    Φq M⁻¹ Φqᵀ (1/J) the scale of the translation rows (1/m), so that matrix stays as
    well conditioned as the rest of the mechanism makes it.
    """
    bodies = {
        name: dataclasses.replace(body, inertia=body.mass * 1.0)
        if isinstance(body, RigidBody) and body.inertia is None
        else body
        for name, body in scene.bodies.items()
    }
    if bodies == scene.bodies:
        return scene
    return dataclasses.replace(scene, bodies=bodies)


def _joint_type(cls: type) -> str:
    return str(next(f.default for f in dataclasses.fields(cls) if f.name == "type"))
