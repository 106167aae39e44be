"""Wear on motor-driven scenes: a wear cycle is a revolution of the crank, counted on the
crank angle (its crossings of 2πk from the start), as the sweeps count a motor-driven
crank's revolutions; a lubricated joint wears only while the film is broken down.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechanism
from mechanism.core.record import window_start
from mechanism.core.wear import run_wear

NO_LOAD_RPM = 3000.0
TURN = 60.0 / NO_LOAD_RPM  # s, a crank turn at the no-load speed


def _motor_crank() -> mechanism.Scene:
    """The dry clearance slider-crank driven from rest by a 5 N m motor (0.67 turns in its
    first two no-load periods)."""
    scene = mechanism.load_scene("slider-crank-clearance")
    return scene.replace(
        {"drive": {"type": "motor", "joint": "O", "stall_torque": 5.0,
                   "no_load_speed_rpm": NO_LOAD_RPM}}
    )  # fmt: skip


def test_predict_wear_counts_the_cycles_of_a_motor_driven_crank_by_its_turns() -> None:
    """The wear per cycle is the mean of the wear of crank turns 2 and 3 (after one turn of
    settle): ``run_wear`` over the windows between the crank angle's crossings of 2π, 4π
    and 6π in a run long enough for three turns gives it within 2 % (measured 0.1 %: the
    two runs end at different times, so their steps differ), the depth summed over the
    regions (which the profile's smoothing keeps)."""
    scene = _motor_crank()
    pred = mechanism.predict_wear(
        scene, updates=1, cycles_per_update=100.0, settle_revolutions=1.0,
        averaged_revolutions=2,
    )  # fmt: skip
    rate = pred.to_dataset()["wear_rate"].isel(update=0).sel(joint="B")
    per_cycle = rate.sum("angle").values  # m per cycle, bearing and journal
    worn = scene.replace({"effects.wear": True})
    run = mechanism.simulate(worn, t_end=12 * TURN, output_step=TURN / 10000)
    turns = np.abs(run.crank_angle.values - run.crank_angle.values[0]) / (2 * math.pi)
    assert 3.0 < turns[-1] < 12.0  # the crank turns slower than the motor's no-load speed
    bounds = [window_start(run, k) for k in (1, 2, 3)]
    depths = [
        run_wear(worn, run.isel(time=slice(0, bounds[k + 1] + 1)), start=bounds[k])["B"].depth
        for k in (0, 1)
    ]
    expected = 0.5 * (depths[0] + depths[1]).sum(axis=1)
    assert expected[0] > 0.0
    np.testing.assert_allclose(per_cycle, expected, rtol=2e-2)


@pytest.mark.slow
def test_wear_life_runs_on_a_motor_driven_crank() -> None:
    """The wear path of a motor-driven crank: its cycles are crank turns; the checkpoint's
    analysis runs ``settle + analysis`` turns of the crank and the exponent over periods of
    the no-load speed."""
    settings = mechanism.WearLifeSettings(
        settle_revolutions=1.0, analysis_revolutions=4, lyapunov_revolutions=2.0,
        lyapunov_discard=1.0, averaged_revolutions=1, lyapunov_first_revolutions=None,
    )  # fmt: skip
    life = mechanism.wear_life(
        _motor_crank(), cycles=200.0, checkpoints=[100.0], settings=settings, exponent=True
    )
    ds = life.to_dataset()
    assert ds["checkpoint"].values.tolist() == [0.0, 100.0, 200.0]
    assert np.all(np.isfinite(ds.peak_contact_force.values))
    assert np.all(np.isfinite(ds.lyapunov_exponent.values))
    np.testing.assert_allclose(ds.lyapunov_run_revolutions.values, 2.0, rtol=1e-12)


def test_wear_life_refuses_a_scene_without_a_drive() -> None:
    scene = _motor_crank()
    undriven = dataclasses.replace(scene, drive=None)
    with pytest.raises(ValueError) as info:
        mechanism.wear_life(undriven, cycles=1000.0, checkpoints=[500.0])
    assert str(info.value) == (
        "wear_life needs a scene with a periodic drive or a motor drive (cycles are crank turns)."
    )


def test_a_lubricated_joint_of_a_motor_driven_crank_wears_only_in_dry_contact() -> None:
    """``slider-crank-motor-lubricated``: with its film (breakdown at 20 µm) the journal
    touches the bearing and wears; with a viscous oil (2 Pa s, breakdown at 1 µm) the film
    carries the load, the journal never touches and the wear per cycle is exactly 0."""
    scene = mechanism.load_scene("slider-crank-motor-lubricated")
    thick = scene.replace(
        {"joints.B.lubrication.viscosity": 2.0, "joints.B.lubrication.film_breakdown": 1e-6}
    )
    for oil, worn in ((scene, True), (thick, False)):
        pred = mechanism.predict_wear(
            oil, updates=1, cycles_per_update=10.0, settle_revolutions=1.0,
            averaged_revolutions=1,
        )  # fmt: skip
        rate = pred.to_dataset()["wear_rate"].isel(update=0).sel(joint="B").values
        assert (float(rate.max()) > 0.0) == worn
        assert float(rate.min()) >= 0.0
