"""Joints of a mechanism: ideal revolute, prismatic and fixed joints and drivers as
constraint rows, and the kinematics of clearance joints (a journal in a bearing, the
corners of a slider in a guide).
The compiled kernels live in ``_kernels.py``; scenes describe joints as data."""

# compiled kernels and their table layouts, for the other folders of the core (assembly,
# bodies, integrators); not part of the public API
from ._guide_kernels import guide_acceleration, guide_force_add, guide_kinematics
from ._kernels import (
    ANGLE_NONE,
    ANGLE_RIGID,
    ANGLE_SLOPE,
    CON_ANGLE,
    CON_COINCIDE,
    CON_DRIVE,
    CON_NORMAL,
    CON_ROWS,
    DRIVE_CONSTANT_SPEED,
    DRIVE_NONE,
    DRIVE_PROFILE,
    PC_ANG,
    PC_RATE,
    PC_VX,
    PC_VY,
    PC_X,
    PC_Y,
    PCF_COLUMNS,
    PCI_COLUMNS,
    POINT_GROUND,
    POINT_LINEAR,
    POINT_RIGID,
    angle_acceleration,
    apply_point_force,
    clearance_force_add,
    clearance_kinematics,
    constraint_columns,
    constraint_rows,
    point_acceleration,
    update_point_rows,
    update_points,
)

__all__: list[str] = []
