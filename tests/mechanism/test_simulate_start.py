"""``mechanism.simulate(start=...)``: a run that starts from the last state of an earlier run.

A run records its last state (``final_q``, ``final_v`` at ``final_time``); a run of the same
scene started from it after whole drive periods continues the motion from there (the drive
restarts at t = 0; body angles are taken modulo whole turns). A state that does not fit the
scene at t = 0 is refused in one line naming ``start``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

import mechanism
from mechanism.core.scene import ConstantSpeedDrive, RevoluteJoint, RigidBody, Scene
from tests.mechanism.scenes import rigid_paper


def _crank(speed_rpm: float = 60.0) -> Scene:
    """A crank turning about the ground at ``speed_rpm`` (three coordinates)."""
    return Scene(
        name="crank",
        ground_points={"O": (0.0, 0.0)},
        bodies={"crank": RigidBody(mass=1.0, inertia=0.01, position=(0.05, 0.0),
                                   points={"O": (-0.05, 0.0)})},
        joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
        drive=ConstantSpeedDrive(joint="O", speed_rpm=speed_rpm),
    )  # fmt: skip


def test_a_run_records_its_last_state():
    ds = mechanism.simulate(_crank(), revolutions=2, output_step=0.01)
    assert ds.attrs["final_time"] == pytest.approx(2.0, rel=1e-12)
    q, v = ds.attrs["final_q"], ds.attrs["final_v"]
    assert q.shape == v.shape == (3,)
    # the crank has turned twice about its pivot: (x, y, θ) = (0.05 m, 0, 4π), within the
    # drift the constraint stabilisation leaves (6.5e-8 m, 4.7e-6 m/s measured)
    np.testing.assert_allclose(q, [0.05, 0.0, 4.0 * math.pi], rtol=0.0, atol=1e-6)
    np.testing.assert_allclose(v, [0.0, 0.1 * math.pi, 2.0 * math.pi], rtol=0.0, atol=1e-4)


def test_a_started_run_begins_at_the_last_state_of_the_earlier_one():
    """The worn-free paper scene at 150 rpm: the journal of the started run begins exactly
    where the earlier run's journal ended (the first sample is the start state), the
    crank at the drive's angle of t = 0, and the run goes on without failing."""
    scene = rigid_paper({"drive.speed_rpm": 150.0})
    first = mechanism.simulate(scene, revolutions=1, record="wear")
    on = mechanism.simulate(scene, revolutions=1, record="wear", start=first)
    for name in ("eccentricity_x", "eccentricity_y"):
        end = first[name].isel(time=-1).values
        np.testing.assert_allclose(on[name].isel(time=0).values, end, rtol=0.0, atol=1e-12)
    cold = mechanism.simulate(scene, revolutions=1, record="wear")
    assert float(on["crank_angle"][0]) == pytest.approx(float(cold["crank_angle"][0]), abs=1e-12)
    # a (q, v) pair is the same start as the Dataset that carries it
    pair = (first.attrs["final_q"], first.attrs["final_v"])
    again = mechanism.simulate(scene, revolutions=0.1, record="wear", start=pair)
    np.testing.assert_allclose(
        again["eccentricity_x"].isel(time=0).values,
        on["eccentricity_x"].isel(time=0).values, rtol=0.0, atol=0.0,
    )  # fmt: skip


def test_an_ideal_mechanism_continues_as_if_never_stopped():
    """Without clearance the motion is a function of the crank angle: a run started from
    the end of two revolutions repeats a run from the scene's initial state."""
    first = mechanism.simulate(_crank(), revolutions=2, output_step=0.01)
    on = mechanism.simulate(_crank(), revolutions=1, output_step=0.01, start=first)
    cold = mechanism.simulate(_crank(), revolutions=1, output_step=0.01)
    np.testing.assert_allclose(on["crank_angle"].values, cold["crank_angle"].values, atol=1e-9)


@pytest.mark.parametrize(
    ("start", "error", "message"),
    [
        (
            (np.zeros(2), np.zeros(2)),
            ValueError,
            "start must hold 3 positions and 3 velocities (the coordinates of scene "
            "'crank', crank.x, crank.y, crank.theta); got 2 and 2.",
        ),
        (
            xr.Dataset(),
            ValueError,
            "start must be a Dataset returned by mechanism.simulate (it carries the run's "
            "last state in the attributes final_q and final_v) or a (q, v) pair; this "
            "Dataset has no final_q / final_v.",
        ),
        (
            5.0,
            TypeError,
            "start must be a Dataset returned by mechanism.simulate or a (q, v) pair of "
            "arrays; got float.",
        ),
        (
            (np.array([0.05, 0.0, np.nan]), np.zeros(3)),
            ValueError,
            "start must hold finite positions and velocities.",
        ),
    ],
)
def test_a_bad_start_is_refused_in_one_line(start, error, message):
    with pytest.raises(error) as info:
        mechanism.simulate(_crank(), revolutions=1, output_step=0.01, start=start)
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("revolutions", "speed_rpm"),
    [(1.5, 60.0), (1.0, 30.0)],  # not after whole periods; another speed
)
def test_a_state_that_misses_the_joints_at_t0_is_refused(revolutions, speed_rpm):
    earlier = mechanism.simulate(_crank(speed_rpm), revolutions=revolutions, output_step=0.01)
    with pytest.raises(ValueError) as info:
        mechanism.simulate(_crank(60.0), revolutions=1, output_step=0.01, start=earlier)
    text = str(info.value)
    assert text.startswith("start does not satisfy the joints of scene 'crank' at t = 0")
    assert text.endswith(
        "at most 0.0001): pass the last state of a run of the same scene that ended after "
        "whole drive periods."
    )
