"""End to end on the built-in ``slider-crank-motor-lubricated``: a motor-driven press
slider-crank with a return spring, a working force and an oil film in its clearance joint
runs through ``mechanism sweep`` (command line), ``lyapunov_exponent`` and the wear
prediction. Each check asserts what survives a 1e-12 perturbation of the initial state:
that the studies run and what they count, not the transient's values.
"""

from __future__ import annotations

import math

import numpy as np
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.core.scene import MotorDrive

BUILTIN = "slider-crank-motor-lubricated"


def test_the_scene_has_a_motor_force_elements_and_a_lubricated_joint() -> None:
    scene = mechanism.load_scene(BUILTIN)
    assert isinstance(scene.drive, MotorDrive)
    assert scene.drive.flywheel_inertia > 0.0
    assert set(scene.forces) == {"return_spring", "press"}
    assert scene.joints["B"].lubrication is not None


def test_sweep_from_the_command_line_runs_two_motor_torques(tmp_path) -> None:
    args = [
        "sweep", BUILTIN, "--grid", "drive.stall_torque=6,8", "--store",
        str(tmp_path / "store"), "--revolutions", "1", "--discard", "0", "--scheduler",
        "serial", "--no-analysis", "--no-progress",
    ]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "2 points: 2 to run, 0 already done" in result.output
    ds = mechanism.load_sweep(tmp_path / "store")
    assert ds.status.values.ravel().tolist() == ["ok", "ok"]


def test_lyapunov_exponent_runs_on_the_motor_driven_lubricated_crank() -> None:
    """Over 0.05 s (a few crank turns from rest) the estimate is finite; its sign is not
    asserted (a transient's exponent depends on rounding)."""
    result = mechanism.lyapunov_exponent(mechanism.load_scene(BUILTIN), t_end=0.05, discard=0.01)
    assert math.isfinite(result.exponent)
    assert np.all(np.isfinite(result.ci))
