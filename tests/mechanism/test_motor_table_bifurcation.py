"""Orbit diagrams of a motor-driven scene: no prescribed period, sections at crank-angle
crossings.

The clearance slider-crank driven by a linear motor from rest: a value runs for
``revolutions`` periods of the motor's no-load speed, its points are where the crank angle
passes 2πk after ``discard`` crank revolutions, exactly the sections ``simulate`` records
for the same run. Every check compares the diagram with that run on the same machine, or
bounds what any rounding leaves unchanged (the crank angle at a crossing, the count of
crossings of a crank that spins up monotonically).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechanism

NO_LOAD_RPM = 3000.0
PERIOD = 60.0 / NO_LOAD_RPM  # s, a crank turn at the no-load speed
REVOLUTIONS, DISCARD = 8, 2


def _motor_crank() -> mechanism.Scene:
    scene = mechanism.load_scene("slider-crank-clearance")
    return scene.replace(
        {"drive": {"type": "motor", "joint": "O", "stall_torque": 5.0,
                   "no_load_speed_rpm": NO_LOAD_RPM}}
    )  # fmt: skip


def test_orbit_diagram_of_a_motor_scene_sections_at_crank_angle_crossings() -> None:
    scene = _motor_crank()
    ds = mechanism.bifurcation(
        scene, parameter="drive.stall_torque", values=[5.0], revolutions=REVOLUTIONS,
        discard=DISCARD, variables=("eccentricity", "crank_angle"), client="serial",
    )  # fmt: skip
    assert ds.status.values.tolist() == ["ok"]
    k = ds.crossing.values
    assert k[0] == DISCARD
    assert np.array_equal(k, np.arange(DISCARD, DISCARD + k.size))
    assert k[-1] <= REVOLUTIONS  # at most one turn per no-load period
    angle = ds.crank_angle.values[0]
    assert np.max(np.abs(angle - 2.0 * math.pi * k)) < 1e-9
    settings = mechanism.BifurcationSettings()
    sections = mechanism.simulate(
        scene, t_end=REVOLUTIONS * PERIOD, rtol=settings.rtol, atol=settings.atol,
        record=mechanism.SectionsRecord(discard=DISCARD, companion=False),
    )  # fmt: skip
    assert np.array_equal(sections.drive_cycle.values, k)
    np.testing.assert_array_equal(ds.time.values[0], sections.time.values)
    ecc = np.hypot(sections.eccentricity_x.values, sections.eccentricity_y.values)
    np.testing.assert_array_equal(ds.eccentricity.values[0], ecc)


def test_continuation_refuses_a_motor_scene() -> None:
    with pytest.raises(ValueError, match="constant crank speed"):
        mechanism.bifurcation(
            _motor_crank(), parameter="drive.stall_torque", values=[4.0, 5.0], revolutions=4,
            discard=2, settings=mechanism.BifurcationSettings(direction="up"),
        )  # fmt: skip
