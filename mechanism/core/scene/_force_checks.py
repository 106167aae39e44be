"""Cross-checks of a scene's force elements (``[forces.NAME]``) that one field cannot make:
the bodies, points and joints they name exist, and their tables are well formed."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from typing import Any

from ._messages import format_number
from ._model import (
    GROUND,
    ClearanceRevolute,
    JointCoordinateProfile,
    Load,
    MotorDrive,
    PrismaticJoint,
    RevoluteJoint,
    RotationalSpringDamper,
    SpringDamper,
    TimeTableProfile,
)

__all__ = ["force_problems"]


def _table(add: Callable[[str], None], path: str, xs: Sequence[float], ys: Sequence[float],
           x_name: str, y_name: str) -> None:  # fmt: skip
    if len(xs) < 2 or len(xs) != len(ys):
        add(
            f"{path}.{x_name}: needs at least 2 entries and one {y_name} per {x_name}; "
            f"got {len(xs)} {x_name} and {len(ys)} {y_name} values"
        )
    elif any(b <= a for a, b in itertools.pairwise(xs)):
        add(f"{path}.{x_name}: must be strictly increasing")


def _time_profile(add: Callable[[str], None], path: str, profile: Any) -> None:
    if isinstance(profile, TimeTableProfile):
        _table(add, path, profile.time, profile.factor, "time", "factor")
        if len(profile.time) >= 2 and profile.time[-1] - profile.time[0] >= profile.period:
            add(
                f"{path}.time: the samples must span less than one period "
                f"({format_number(profile.period)} s); got "
                f"{format_number(profile.time[-1] - profile.time[0])} s"
            )


def force_problems(scene: Any, body_points: Callable[[str], tuple[str, ...] | None]) -> list[str]:
    """One line per problem of the scene's force elements (empty when they are valid).

    ``body_points(name)`` gives the point names of a body (the ground's for ``"ground"``),
    or None when no such body exists.
    """
    problems: list[str] = []
    add = problems.append

    def check_end(path: str, point_path: str, body: str, point: str) -> None:
        points = body_points(body)
        if points is None:
            add(f"{path}: no body {body!r}; bodies: {', '.join([GROUND, *scene.bodies])}")
        elif point not in points:
            add(
                f"{point_path}: body {body!r} has no point {point!r}; "
                f"its points: {', '.join(points) or '(none)'}"
            )

    def check_joint(path: str, name: str, kinds: tuple[type, ...], wanted: str) -> None:
        joint = scene.joints.get(name)
        if joint is None:
            add(f"{path}: no joint {name!r}; joints: {', '.join(scene.joints) or '(none)'}")
        elif not isinstance(joint, kinds):
            add(f"{path}: joint {name!r} is {joint.type!r}; it must be a {wanted} joint")

    for name, element in scene.forces.items():
        base = f"forces.{name}"
        if isinstance(element, SpringDamper):
            for i in (0, 1):
                check_end(
                    f"{base}.bodies[{i}]",
                    f"{base}.points[{i}]",
                    element.bodies[i],
                    element.points[i],
                )
            if element.bodies[0] == element.bodies[1]:
                add(
                    f"{base}.bodies: a spring needs two different bodies; "
                    f"got {list(element.bodies)}"
                )
            if element.force_deflection is not None:
                table = element.force_deflection
                _table(add, f"{base}.force_deflection", table.deflection, table.force,
                       "deflection", "force")  # fmt: skip
            if element.force_velocity is not None:
                table = element.force_velocity
                _table(add, f"{base}.force_velocity", table.velocity, table.force,
                       "velocity", "force")  # fmt: skip
        elif isinstance(element, RotationalSpringDamper):
            check_joint(
                f"{base}.joint", element.joint, (RevoluteJoint, ClearanceRevolute),
                "'revolute' or 'clearance_revolute'",
            )  # fmt: skip
        elif isinstance(element, Load):
            if element.body == GROUND:
                add(f"{base}.body: a load on the ground does nothing; name a moving body")
            else:
                check_end(f"{base}.body", f"{base}.point", element.body, element.point)
            if element.time_profile is not None:
                _time_profile(add, f"{base}.time_profile", element.time_profile)
            profile = element.coordinate_profile
            if isinstance(profile, JointCoordinateProfile):
                path = f"{base}.coordinate_profile"
                check_joint(
                    f"{path}.joint", profile.joint, (PrismaticJoint, RevoluteJoint),
                    "'prismatic' or 'revolute'",
                )  # fmt: skip
                _table(add, path, profile.coordinate, profile.factor, "coordinate", "factor")
    problems.extend(_motor_problems(scene.drive))
    problems.extend(_lubrication_problems(scene))
    return problems


def _motor_problems(drive: Any) -> list[str]:
    """A motor gives either its linear curve (both keys) or a torque–speed table."""
    if not isinstance(drive, MotorDrive):
        return []
    problems: list[str] = []
    linear = (drive.stall_torque is not None, drive.no_load_speed_rpm is not None)
    if drive.torque_speed is not None:
        if any(linear):
            problems.append(
                "drive.torque_speed: give either the table or stall_torque and "
                "no_load_speed_rpm, not both"
            )
        table = drive.torque_speed
        _table(problems.append, "drive.torque_speed", table.speed_rpm, table.torque,
               "speed_rpm", "torque")  # fmt: skip
    elif not all(linear):
        missing = "stall_torque" if not linear[0] else "no_load_speed_rpm"
        problems.append(
            f"drive.{missing}: a motor needs stall_torque and no_load_speed_rpm "
            "(the linear curve) or a torque_speed table"
        )
    return problems


def _lubrication_problems(scene: Any) -> list[str]:
    """The film breakdown thickness of a lubricated joint lies inside its clearance."""
    problems: list[str] = []
    for name, joint in scene.joints.items():
        lub = getattr(joint, "lubrication", None)
        if not isinstance(joint, ClearanceRevolute) or lub is None:
            continue
        if not lub.film_breakdown < 0.5 * joint.clearance:
            problems.append(
                f"joints.{name}.lubrication.film_breakdown: must be < clearance/2 = "
                f"{format_number(0.5 * joint.clearance)} (m); "
                f"got {format_number(lub.film_breakdown)}"
            )
    return problems
