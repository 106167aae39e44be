"""How long a sweep point runs for its ``revolutions``: drive periods of a periodic drive,
periods of the no-load speed for a motor-driven crank (as :func:`mechanism.bifurcation`)."""

from __future__ import annotations

from typing import Any

from mechanism.core import drive_period

from .._turns import revolution_time

__all__ = ["revolution_time", "simulated_span"]


def simulated_span(scene: Any, revolutions: float) -> dict[str, float]:
    """The duration keyword of :func:`mechanism.simulate` for ``revolutions``:
    ``revolutions`` itself for a periodic drive, ``t_end`` = ``revolutions`` × 2π/ω₀ for a
    motor-driven crank (a scene with neither gets ``revolutions`` and simulate's error)."""
    if drive_period(scene) is None and (turn := revolution_time(scene)) is not None:
        return {"t_end": revolutions * turn}
    return {"revolutions": revolutions}
