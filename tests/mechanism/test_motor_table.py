"""A motor drive with a tabulated torque–speed curve.

A rigid crank on a frictionless pivot, driven from rest by T(ω) interpolated linearly
through measured (speed, torque) points against a constant load torque T_L: J ω̇ = T(ω) − T_L
settles at the speed where the tabulated curve crosses the load, a stable equilibrium
(T decreases through it) approached exponentially, so the check survives any rounding of
the initial state.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechanism
from mechanism.core.model import assemble
from mechanism.core.scene import SceneError, scene_from_dict

RPM = 2.0 * math.pi / 60.0  # rad/s per rpm
SPEEDS_RPM = [0.0, 500.0, 1000.0, 1500.0]
TORQUES = [5.0, 4.0, 2.0, 0.0]  # N m
LOAD = 3.0  # N m, opposing the rotation
INERTIA = 0.01  # kg m2
# T = 3 N m between (500 rpm, 4 N m) and (1000 rpm, 2 N m): 750 rpm
STEADY = 750.0 * RPM
# the slope there, −2 N m per 500 rpm, sets the time constant J/|dT/dω|
TAU = INERTIA / (2.0 / (500.0 * RPM))


def _scene(drive: dict | None = None, load: float = LOAD) -> dict:
    return {
        "name": "motor-table",
        "effects": {"gravity": False, "clearance": False, "friction": False},
        "ground_points": {"O": [0.0, 0.0]},
        "bodies": {"crank": {"mass": 1.0, "inertia": INERTIA, "points": {"O": [0.0, 0.0]}}},
        "joints": {"O": {"type": "revolute", "bodies": ["ground", "crank"], "points": ["O"] * 2}},
        "drive": drive
        or {
            "type": "motor",
            "joint": "O",
            "torque_speed": {"speed_rpm": SPEEDS_RPM, "torque": TORQUES},
        },
        "forces": {"load": {"type": "load", "body": "crank", "point": "O", "torque": -load}},
        "solver": {"rtol": 1e-11, "atol": 1e-13, "output_step": 1e-2},
    }


def test_tabulated_motor_settles_where_the_curve_crosses_the_load() -> None:
    """After 25 time constants the crank turns at the crossing speed within 1e-6
    relative (the remaining transient is e^-25 = 1.4e-11 of it)."""
    ds = mechanism.simulate(scene_from_dict(_scene()), t_end=25.0 * TAU)
    t = ds.time.values
    theta = ds.crank_angle.values
    rate = (theta[-1] - theta[-11]) / (t[-1] - t[-11])
    assert rate == pytest.approx(STEADY, rel=1e-6)


def test_torque_table_is_read_in_rad_per_second_and_clamped() -> None:
    """The motor's element holds the table in rad/s and N m; outside it the end values
    hold (a crank at 2000 rpm still gets the 0 N m of 1500 rpm, one at −100 rpm the 5 N m
    of 0 rpm)."""
    model = assemble(scene_from_dict(_scene()))
    assert model.force_elements == ("load", "drive")
    km = model.kernel
    row = km.fe_i[1]
    fk = mechanism.core.forces._kernels
    off, n = row[fk.FI_TC_OFF], row[fk.FI_TC_N]
    assert n == 4
    np.testing.assert_array_equal(km.fe_t[off : off + n], np.array(SPEEDS_RPM) * RPM)
    np.testing.assert_array_equal(km.fe_t[off + n : off + 2 * n], TORQUES)
    assert fk.table_value(km.fe_t, off, n, 2000.0 * RPM) == 0.0
    assert fk.table_value(km.fe_t, off, n, -100.0 * RPM) == 5.0
    assert fk.table_value(km.fe_t, off, n, STEADY) == pytest.approx(LOAD, rel=1e-12)
    assert km.fe_f[1, fk.FF_C] == 0.0 and km.fe_f[1, fk.FF_ACT] == 0.0


def test_no_load_speed_of_a_table_is_its_zero_crossing() -> None:
    scene = scene_from_dict(_scene())
    assert scene.drive.no_load_speed == pytest.approx(1500.0 * RPM, rel=1e-15)
    assert scene.drive.damping == 0.0


@pytest.mark.parametrize(
    ("drive", "message"),
    [
        (
            {"torque_speed": {"speed_rpm": [0.0, 0.0], "torque": [1.0, 0.0]}},
            "drive.torque_speed.speed_rpm: must be strictly increasing",
        ),
        (
            {"torque_speed": {"speed_rpm": [0.0, 100.0, 200.0], "torque": [1.0, 0.0]}},
            "drive.torque_speed.speed_rpm: needs at least 2 entries and one torque per "
            "speed_rpm; got 3 speed_rpm and 2 torque values",
        ),
        (
            {
                "stall_torque": 2.0,
                "torque_speed": {"speed_rpm": [0.0, 100.0], "torque": [1.0, 0.0]},
            },
            "drive.torque_speed: give either the table or stall_torque and no_load_speed_rpm, "
            "not both",
        ),
        (
            {"stall_torque": 2.0},
            "drive.no_load_speed_rpm: a motor needs stall_torque and no_load_speed_rpm "
            "(the linear curve) or a torque_speed table",
        ),
    ],
)
def test_motor_curve_keys_are_checked(drive, message) -> None:
    with pytest.raises(SceneError) as info:
        scene_from_dict(_scene({"type": "motor", "joint": "O", **drive}))
    assert message in str(info.value)
