"""Studies that count revolutions, on a motor-driven scene (no prescribed drive period).

A sweep runs each point for ``revolutions`` periods of the motor's no-load speed (as the
orbit diagram does) and gives exactly the run ``simulate`` makes over that time on the
same machine; periodic orbits and continuation, which need a fixed drive period, refuse
the scene with a one-line error that names the reason (the wear path counts its cycles on
the crank angle: ``test_motor_wear.py``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

import mechanism

NO_LOAD_RPM = 3000.0
PERIOD = 60.0 / NO_LOAD_RPM  # s, a crank turn at the no-load speed
REFUSAL = (
    "{caller} needs a periodic drive: a motor-driven crank moves autonomously, so a "
    "periodic orbit's period is an unknown, which shooting over fixed drive periods "
    "does not solve for; use a constant_speed drive at the speed the motor reaches."
)


def _motor_crank() -> mechanism.Scene:
    scene = mechanism.load_scene("slider-crank-clearance")
    return scene.replace(
        {"drive": {"type": "motor", "joint": "O", "stall_torque": 5.0,
                   "no_load_speed_rpm": NO_LOAD_RPM}}
    )  # fmt: skip


def test_sweep_of_a_motor_scene_runs_revolutions_of_the_no_load_period(tmp_path) -> None:
    """Two no-load periods per point, the output step a 200th of one
    (``samples_per_revolution``); the metrics are those of the same run by ``simulate``."""
    scene = _motor_crank()
    ds = mechanism.sweep(
        scene, grid={"drive.stall_torque": [5.0], "samples_per_revolution": [200]},
        revolutions=2, analysis=mechanism.Analysis(variables=(), discard_revolutions=0.0),
        client="serial",
        store=tmp_path / "store",
    )  # fmt: skip
    assert ds.status.values.ravel().tolist() == ["ok"]
    path = tmp_path / "store" / str(ds.trajectory_file.values.ravel()[0])
    with xr.open_dataset(path) as traj:
        t = traj.time.values
    step = PERIOD / 200
    assert t[1] - t[0] == pytest.approx(step, rel=1e-12)
    assert t[-1] == pytest.approx(2.0 * PERIOD, rel=1e-9)
    run = mechanism.simulate(
        scene.replace({"solver.output_step": step}), t_end=2.0 * PERIOD, throw=False
    )
    assert run.time.size == t.size
    peak = float(ds.peak_contact_force.values.ravel()[0])
    assert peak == float(run.contact_force.max())
    assert math.isfinite(peak)
    torque = float(ds.driving_torque_extreme.values.ravel()[0])
    assert np.isnan(torque)  # a motor has no driving constraint: no reaction torque


def test_continuation_refuses_a_motor_scene() -> None:
    with pytest.raises(ValueError) as info:
        mechanism.continuation(_motor_crank(), parameter="drive.stall_torque", span=(5.0, 6.0))
    assert str(info.value) == REFUSAL.format(caller="continuation")
