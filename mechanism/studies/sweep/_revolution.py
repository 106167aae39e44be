"""How long a sweep point runs for its ``revolutions``: drive periods of a periodic drive,
periods of the no-load speed for a motor-driven crank (as :func:`mechanism.bifurcation`)."""

from __future__ import annotations

import math
from typing import Any

from mechanism.core import drive_period
from mechanism.core.scene import MotorDrive

__all__ = ["revolution_time", "simulated_span"]


def revolution_time(scene: Any) -> float | None:
    """The time (s) a sweep counts as one revolution: the drive period, or 2π/ω₀ at the
    motor's no-load speed ω₀ for a motor-driven crank (which turns at most about once in
    it, slower under load); None when the scene has neither."""
    period = drive_period(scene)
    if period is not None:
        return period
    drive = scene.drive
    if isinstance(drive, MotorDrive) and drive.no_load_speed > 0.0:
        return 2.0 * math.pi / drive.no_load_speed
    return None


def simulated_span(scene: Any, revolutions: float) -> dict[str, float]:
    """The duration keyword of :func:`mechanism.simulate` for ``revolutions``:
    ``revolutions`` itself for a periodic drive, ``t_end`` = ``revolutions`` × 2π/ω₀ for a
    motor-driven crank (a scene with neither gets ``revolutions`` and simulate's error)."""
    if drive_period(scene) is None and (turn := revolution_time(scene)) is not None:
        return {"t_end": revolutions * turn}
    return {"revolutions": revolutions}
