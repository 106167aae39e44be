"""Runs measured in crank revolutions: drive periods of a periodic drive, turns of the
crank itself for a motor-driven one (whose turns take no fixed time).

Shared by the sweeps (``sweep/_revolution.py``), the wear prediction and the wear life:
a wear cycle is one revolution of the crank, so on a motor-driven scene the cycles are
counted on the crank angle (its crossings of 2πk), as the sweeps count them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr

from mechanism.core import Scene, SimulationError, drive_period, simulate
from mechanism.core.scene import MotorDrive

__all__ = [
    "MAX_EXTENSIONS",
    "crank_turns",
    "cut_at_turns",
    "exponent_revolutions",
    "exponent_span",
    "revolution_time",
    "simulate_turns",
]

#: Longest a motor-driven run is extended to reach its revolutions (each try simulates
#: afresh, long enough at the crank's mean speed so far, plus 10 %).
MAX_EXTENSIONS = 6

#: Samples per revolution of a motor-driven run without an ``output_step`` (the default
#: of a periodic drive: period / 10000).
SAMPLES_PER_TURN = 10000


def revolution_time(scene: Any) -> float | None:
    """The time (s) counted as one revolution: the drive period, or 2π/ω₀ at the motor's
    no-load speed ω₀ for a motor-driven crank (which turns at most about once in it,
    slower under load); None when the scene has neither."""
    period = drive_period(scene)
    if period is not None:
        return period
    drive = scene.drive
    if isinstance(drive, MotorDrive) and drive.no_load_speed > 0.0:
        return 2.0 * math.pi / drive.no_load_speed
    return None


def crank_turns(traj: xr.Dataset) -> np.ndarray:
    """Revolutions the crank has turned at each sample, |θ − θ₀|/2π (``crank_angle``)."""
    angle = np.asarray(traj["crank_angle"].values, dtype=np.float64)
    return np.abs(angle - angle[0]) / (2.0 * math.pi)


def cut_at_turns(traj: xr.Dataset, revolutions: float) -> xr.Dataset:
    """``traj`` up to its first sample at which the crank has turned ``revolutions``
    (whole when it never does): the record of exactly that many turns, ending where the
    last one completes."""
    done = np.flatnonzero(crank_turns(traj) >= revolutions * (1.0 - 1e-12))
    return traj.isel(time=slice(0, int(done[0]) + 1)) if done.size else traj


def simulate_turns(scene: Scene, revolutions: float, **kwargs: Any) -> xr.Dataset:
    """:func:`mechanism.simulate` over ``revolutions`` crank revolutions.

    A periodic drive runs ``revolutions`` drive periods. A motor-driven crank runs until
    its angle has turned ``revolutions`` × 2π: first for ``revolutions`` periods of the
    no-load speed, then, while it falls short, again for the time its mean speed so far
    needs, plus 10 % (at most ``MAX_EXTENSIONS`` times); the run is cut at the first
    sample past the last turn, so the record ends where the crank completes it. Without an
    ``output_step`` the motor's runs sample a no-load revolution 10000 times (the default
    of a periodic drive).

    Raises
    ------
    SimulationError
        When the simulation fails, or the motor-driven crank does not complete the
        revolutions (a stalled crank: the load exceeds the motor's torque).
    """
    turn = revolution_time(scene)
    if drive_period(scene) is not None or turn is None:
        return simulate(scene, revolutions=revolutions, **kwargs)
    if kwargs.get("output_step") is None:
        kwargs = {**kwargs, "output_step": turn / SAMPLES_PER_TURN}
    t_end = simulated = revolutions * turn
    turned = 0.0
    for _ in range(MAX_EXTENSIONS + 1):
        traj = simulate(scene, t_end=t_end, **kwargs)
        simulated = t_end
        turned = float(crank_turns(traj).max())
        if turned >= revolutions * (1.0 - 1e-12):
            return cut_at_turns(traj, revolutions)
        if turned < 1e-3 * revolutions:
            break  # the crank hardly moves: no speed to extrapolate from
        t_end *= 1.1 * revolutions / turned
    raise SimulationError(
        f"the motor-driven crank turned {turned:.3g} of the {revolutions:g} revolutions "
        f"asked for in {simulated:.3g} s; its load holds it (raise the motor's torque or "
        "lower the load).",
        time=simulated,
    )


def exponent_span(scene: Scene, revolutions: float, discard: float) -> dict[str, float]:
    """The span keywords of :func:`mechanism.lyapunov_exponent` for ``revolutions`` with
    ``discard`` left out: drive periods of a periodic drive, ``t_end`` and ``discard`` in
    seconds (periods of the no-load speed) for a motor-driven crank."""
    if drive_period(scene) is None and (turn := revolution_time(scene)) is not None:
        return {"t_end": revolutions * turn, "discard": discard * turn}
    return {"revolutions": revolutions, "discard": discard}


def exponent_revolutions(settings: dict[str, Any], scene: Scene) -> float:
    """The revolutions an exponent's run covered, from its ``settings`` (``t_end`` over
    the revolution time for a motor-driven crank)."""
    if settings.get("revolutions") is not None:
        return float(settings["revolutions"])
    turn = revolution_time(scene)
    return float(settings["t_end"]) / turn if turn else math.nan
