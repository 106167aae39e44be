"""The tables of a scene's force elements (layout: ``mechanism.core.forces._kernels``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from mechanism.core.scene import (
    ClearanceRevolute,
    FourierProfile,
    Load,
    MotorDrive,
    PrismaticJoint,
    RevoluteJoint,
    RotationalSpringDamper,
    Scene,
    SpringDamper,
    TimeTableProfile,
)

from . import _kernels as force_kernels

__all__ = ["MOTOR_ELEMENT", "ForceTables", "force_tables"]

#: name of the motor drive's torque among the force elements (its last row)
MOTOR_ELEMENT = "drive"

#: point-table row of (body, point), with the scene key path for its error message
PointRow = Callable[[str, str, str], int]
_ACTIVE = {
    "always": force_kernels.ACTIVE_ALWAYS,
    "increasing": force_kernels.ACTIVE_INCREASING,
    "decreasing": force_kernels.ACTIVE_DECREASING,
}


class ForceTables(NamedTuple):
    """The arrays of the force elements and their names in row order."""

    names: tuple[str, ...]
    fe_i: np.ndarray
    fe_f: np.ndarray
    fe_t: np.ndarray


def force_tables(scene: Scene, point: PointRow) -> ForceTables:
    """Rows of every element of ``scene.forces`` (tables with no rows when there is none).

    ``point(body, point, where)`` returns the point-table row of a body point, adding it
    when new.
    """
    flat: list[float] = []
    rows_i: list[list[int]] = []
    rows_f: list[list[float]] = []

    def store(*columns: tuple[float, ...]) -> tuple[int, int]:
        offset = len(flat)
        for column in columns:
            flat.extend(float(x) for x in column)
        return offset, len(columns[0])

    for name, element in scene.forces.items():
        where = f"forces.{name}"
        ri = [0] * force_kernels.FI_COLUMNS
        rf = [0.0] * force_kernels.FF_COLUMNS
        if isinstance(element, SpringDamper):
            ri[force_kernels.FI_KIND] = force_kernels.FE_SPRING
            ri[force_kernels.FI_A] = point(element.bodies[0], element.points[0], where)
            ri[force_kernels.FI_B] = point(element.bodies[1], element.points[1], where)
            rf[force_kernels.FF_K] = element.stiffness
            rf[force_kernels.FF_C] = element.damping
            rf[force_kernels.FF_REF] = element.free_length
            rf[force_kernels.FF_ACT] = element.actuator_force
            if element.force_deflection is not None:
                table = element.force_deflection
                ri[force_kernels.FI_TK_OFF], ri[force_kernels.FI_TK_N] = store(
                    table.deflection, table.force
                )
            if element.force_velocity is not None:
                table = element.force_velocity
                ri[force_kernels.FI_TC_OFF], ri[force_kernels.FI_TC_N] = store(
                    table.velocity, table.force
                )
        elif isinstance(element, RotationalSpringDamper):
            ri[force_kernels.FI_KIND] = force_kernels.FE_TORSION
            ri[force_kernels.FI_A], ri[force_kernels.FI_B], _ = _joint_points(
                scene, element.joint, point, where
            )
            rf[force_kernels.FF_K] = element.stiffness
            rf[force_kernels.FF_C] = element.damping
            rf[force_kernels.FF_REF] = element.reference_angle
            rf[force_kernels.FF_ACT] = element.actuator_torque
        elif isinstance(element, Load):
            ri[force_kernels.FI_KIND] = force_kernels.FE_LOAD
            ri[force_kernels.FI_A] = point(element.body, element.point, where)
            ri[force_kernels.FI_FRAME] = 1 if element.frame == "body" else 0
            rf[force_kernels.FF_FX], rf[force_kernels.FF_FY] = element.force
            rf[force_kernels.FF_TORQUE] = element.torque
            _time_profile(element, ri, rf, store)
            profile = element.coordinate_profile
            if profile is not None:
                a, b, axis = _joint_points(
                    scene, profile.joint, point, f"{where}.coordinate_profile"
                )
                ri[force_kernels.FI_COORD] = (
                    force_kernels.COORD_ANGLE if axis is None else force_kernels.COORD_SLIDE
                )
                ri[force_kernels.FI_CA], ri[force_kernels.FI_CB] = a, b
                rf[force_kernels.FF_UX], rf[force_kernels.FF_UY] = (
                    axis if axis is not None else (0.0, 0.0)
                )
                ri[force_kernels.FI_CT_OFF], ri[force_kernels.FI_CT_N] = store(
                    profile.coordinate, profile.factor
                )
                ri[force_kernels.FI_ACTIVE] = _ACTIVE[profile.active]
        else:
            raise TypeError(f"{where}: unsupported force element {type(element).__name__}.")
        rows_i.append(ri)
        rows_f.append(rf)
    names = tuple(scene.forces)
    drive = scene.drive
    if isinstance(drive, MotorDrive):
        # the linear torque–speed curve T_s (1 − ω/ω₀) is a torsional damper of
        # c = T_s/ω₀ with the actuator torque T_s; a tabulated curve is the element's
        # torque–rate table (rpm → rad/s); reported as the element "drive"
        ri = [0] * force_kernels.FI_COLUMNS
        rf = [0.0] * force_kernels.FF_COLUMNS
        ri[force_kernels.FI_KIND] = force_kernels.FE_TORSION
        ri[force_kernels.FI_A], ri[force_kernels.FI_B], _ = _joint_points(
            scene, drive.joint, point, "drive"
        )
        table = drive.torque_speed
        if table is None:
            rf[force_kernels.FF_C] = drive.damping
            rf[force_kernels.FF_ACT] = float(drive.stall_torque or 0.0)
        else:
            speeds = tuple(w * (2.0 * math.pi / 60.0) for w in table.speed_rpm)
            ri[force_kernels.FI_TC_OFF], ri[force_kernels.FI_TC_N] = store(speeds, table.torque)
        rows_i.append(ri)
        rows_f.append(rf)
        names = (*names, MOTOR_ELEMENT)
    return ForceTables(
        names=names,
        fe_i=np.ascontiguousarray(
            np.array(rows_i, dtype=np.int64).reshape(-1, force_kernels.FI_COLUMNS)
        ),
        fe_f=np.ascontiguousarray(
            np.array(rows_f, dtype=np.float64).reshape(-1, force_kernels.FF_COLUMNS)
        ),
        fe_t=np.ascontiguousarray(np.array(flat, dtype=np.float64)),
    )


def _time_profile(
    load: Load, ri: list[int], rf: list[float], store: Callable[..., tuple[int, int]]
) -> None:
    profile = load.time_profile
    if isinstance(profile, FourierProfile):
        n = max(len(profile.cosine), len(profile.sine))
        cosine = [*profile.cosine, *[0.0] * (n - len(profile.cosine))]
        sine = [*profile.sine, *[0.0] * (n - len(profile.sine))]
        ri[force_kernels.FI_TIME] = force_kernels.PROFILE_FOURIER
        ri[force_kernels.FI_TT_OFF], _ = store((profile.mean, *cosine, *sine))
        ri[force_kernels.FI_TT_N] = n
        rf[force_kernels.FF_PERIOD] = profile.period
    elif isinstance(profile, TimeTableProfile):
        ri[force_kernels.FI_TIME] = force_kernels.PROFILE_TABLE
        ri[force_kernels.FI_TT_OFF], ri[force_kernels.FI_TT_N] = store(profile.time, profile.factor)
        rf[force_kernels.FF_PERIOD] = profile.period


def _joint_points(
    scene: Scene, name: str, point: PointRow, where: str
) -> tuple[int, int, tuple[float, float] | None]:
    """(first point, second point, unit axis or None) of a revolute, clearance revolute or
    prismatic joint."""
    joint = scene.joints.get(name)
    if isinstance(joint, ClearanceRevolute):
        return point(*joint.bearing, where), point(*joint.journal, where), None
    if isinstance(joint, RevoluteJoint | PrismaticJoint):
        a = point(joint.bodies[0], joint.points[0], where)
        b = point(joint.bodies[1], joint.points[1], where)
        if isinstance(joint, RevoluteJoint):
            return a, b, None
        ux, uy = joint.axis
        norm = math.hypot(ux, uy)
        return a, b, (ux / norm, uy / norm)
    raise ValueError(f"{where}: joint {name!r} must be a revolute or prismatic joint.")
