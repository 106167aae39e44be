"""Cheap deterministic stand-ins for sweep tests (importable by dask worker processes).

``analytic_simulator`` returns a contract-conforming trajectory whose response metrics are
known in closed form, so the sweep's reductions can be checked exactly; the grid transforms
make a point raise or kill its worker process.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from chaoskit._contract import stamp

SAMPLES_PER_REV = 200
FORCE_SCALE = 1e7  # N per m of clearance
SPIKE = 1e9  # N m-1 of clearance; a transient inside the first revolution only


def _clearance_and_speed(scene: Any) -> tuple[str, float, float]:
    name, joint = next((k, j) for k, j in scene.joints.items() if hasattr(j, "clearance"))
    return name, float(joint.clearance), float(scene.drive.speed)


def expected_metrics(clearance: float, speed: float) -> dict[str, float]:
    """Closed-form metrics of ``analytic_simulator`` after the first revolution."""
    return {
        "peak_contact_force": 2.5 * FORCE_SCALE * clearance,
        "max_penetration": 0.2 * clearance,
        "max_displacement_error": clearance,
        "max_speed_error": clearance * abs(speed),
        "driving_torque_extreme": -1.5 * (1.0 + 1e3 * clearance),
    }


def analytic_simulator(scene: Any, *, revolutions: float) -> xr.Dataset:
    """Periodic signals of the crank angle, scaled by the clearance and speed of ``scene``."""
    joint, c, w = _clearance_and_speed(scene)
    n = round(revolutions * SAMPLES_PER_REV) + 1
    period = 2.0 * math.pi / abs(w)
    t = np.arange(n) * (period / SAMPLES_PER_REV)
    phi = 2.0 * math.pi * np.arange(n) / SAMPLES_PER_REV
    force = FORCE_SCALE * c * (1.5 + np.sin(phi))
    force[SAMPLES_PER_REV // 3] += SPIKE * c  # must be discarded with the first revolution
    ecc_x = c * np.cos(phi) * (1.0 + 0.1 * np.sin(3.0 * phi))
    ecc_y = c * np.sin(phi)

    def joint_var(values: np.ndarray, units: str, long_name: str) -> tuple[Any, ...]:
        return (("time", "joint"), values[:, None], {"units": units, "long_name": long_name})

    ds = xr.Dataset(
        {
            "crank_angle": ("time", phi, {"units": "rad", "long_name": "crank angle"}),
            "contact_force": joint_var(force, "N", "contact force"),
            "penetration": joint_var(0.1 * c * (1.0 + np.cos(phi)), "m", "penetration"),
            "eccentricity_x": joint_var(ecc_x, "m", "journal eccentricity x"),
            "eccentricity_y": joint_var(ecc_y, "m", "journal eccentricity y"),
            "displacement_error": ("time", c * np.sin(2 * phi), {"units": "m", "long_name": "e"}),
            "speed_error": ("time", c * w * np.cos(2 * phi), {"units": "m s-1", "long_name": "v"}),
            "driving_torque": (
                "time",
                -(1.0 + 1e3 * c) * (1.0 + 0.5 * np.sin(phi)),
                {"units": "N m", "long_name": "driving torque"},
            ),
        },
        coords={"time": ("time", t), "joint": ("joint", [joint])},
    )
    stamp(ds, title="analytic stand-in", extra={"scene": scene.to_json(), "status": "ok"})
    return ds


def failing_simulator(scene: Any, *, revolutions: float) -> xr.Dataset:
    """Reports failure the way a simulator does (status attr), for clearances above 3e-4."""
    ds = analytic_simulator(scene, revolutions=revolutions)
    _, c, _ = _clearance_and_speed(scene)
    if c > 3e-4:
        ds.attrs["status"] = "diverged"
        ds.attrs["message"] = "step size collapsed"
    return ds


def raise_when(scene: Any, value: Any) -> Any:
    """Grid transform: ``"raise"`` raises, anything else leaves the scene alone."""
    if value == "raise":
        raise RuntimeError("deliberate failure of this grid point")
    return scene


def exit_once(scene: Any, value: Any) -> Any:
    """Grid transform: a non-empty value is a marker path; the first run kills the process."""
    if value:
        marker = Path(value)
        if not marker.exists():
            marker.write_text(f"killed worker process {os.getpid()}\n")
            os._exit(17)
    return scene


def fail_once(scene: Any, value: Any) -> Any:
    """Grid transform: a non-empty value is a marker path; the first run raises."""
    if value:
        marker = Path(value)
        if not marker.exists():
            marker.write_text("failed once\n")
            raise RuntimeError("transient failure (first attempt)")
    return scene
