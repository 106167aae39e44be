"""The initial crank speed of a motor-driven scene: one more velocity condition for the
consistent initial velocities (``mechanism.core.model.initial_state``)."""

from __future__ import annotations

import math

import numpy as np

from mechanism.core.scene import MotorDrive, Scene

__all__ = ["motor_speed_row"]


def motor_speed_row(
    scene: Scene, body_names: tuple[str, ...], body_offsets: tuple[int, ...], n_dof: int
) -> tuple[np.ndarray, float] | None:
    """The row r and rate ω with r · q̇ = ω for a motor drive's ``initial_speed_rpm``
    (the relative rate θ̇₁ − θ̇₀ of the drive joint's bodies, rad/s); None without a
    motor or when the motor starts from rest.

    Appended to the constraint rows Φq q̇ = −Φt, it makes the initial velocities those of
    the ideal mechanism turning at that speed (the drive joint's bodies are rigid: a
    flexible scene's initial state is its rigid mechanism's)."""
    drive = scene.drive
    if not isinstance(drive, MotorDrive) or drive.initial_speed_rpm == 0.0:
        return None
    offsets = dict(zip(body_names, body_offsets, strict=True))
    row = np.zeros(n_dof)
    first, second = scene.joints[drive.joint].bodies
    for body, sign in ((second, 1.0), (first, -1.0)):
        if body in offsets:  # the ground has no coordinates
            row[offsets[body] + 2] += sign
    return row, drive.initial_speed_rpm * (2.0 * math.pi / 60.0)
