"""A block of deviations carried in lock-step on one reference run.

``integrate_tangent`` with a (2n, k) ``d0`` advances k deviations on the reference's
steps with the contact, friction-ramp and latch rules of a lone deviation; each column
is the lone run of it whenever the steps are the same (a frozen step schedule, or
``deviation_rtol`` = 0), and the step control takes the largest error otherwise.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechanism
from mechanism.core.integrate import (
    StepSettings,
    TangentSettings,
    initial_deviation,
    integrate_tangent,
    tangent_basis,
)
from mechanism.core.model import assemble, initial_state

TAU = 0.0637
STEPS = StepSettings(rtol=1e-8, atol=1e-8, max_step=4e-5, approach_floor=1e-7)


@pytest.fixture(scope="module")
def setup():
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": 150.0}
    )
    model = assemble(scene)
    y0 = np.concatenate(initial_state(model))
    basis = tangent_basis(model, y0, t=0.0, time_scale=TAU)
    block = basis[:, :3] * 2e-11
    block[:, 2] = initial_deviation(model, y0, t0=0.0, size=2e-11, time_scale=TAU)
    latch = np.zeros((model.kernel.cj_i.shape[0], 3))
    latch[:, 1] = 1e-9
    return model, y0, block, latch


def _columns(model, y0, block, latch, stops, settings, **kw):
    return [
        integrate_tangent(
            model, y0, block[:, c], stops, settings=settings, latch_deviation=latch[:, c], **kw
        )
        for c in range(block.shape[1])
    ]


@pytest.mark.parametrize("difference", ["split", "directional"])
def test_each_column_is_its_lone_run_bit_for_bit(setup, difference):
    """On the reference's own steps (``deviation_rtol`` = 0) every column of the block
    carries exactly the numbers of its lone run: growth, deviation and latch deviation,
    through the impacts of the first 60 ms at 150 rpm."""
    model, y0, block, latch = setup
    stops = np.array([0.0, 0.03, 0.06])
    settings = TangentSettings(steps=STEPS, time_scale=TAU, difference=difference)
    run = integrate_tangent(model, y0, block, stops, settings=settings, latch_deviation=latch)
    lone = _columns(model, y0, block, latch, stops, settings)
    assert run.stats.success and run.stats.contact_events > 0
    assert run.log_growth.shape == (3, 3) and run.final_deviation.shape == block.shape
    for c, one in enumerate(lone):
        assert one.stats.steps == run.stats.steps
        np.testing.assert_array_equal(run.log_growth[:, c], one.log_growth)
        np.testing.assert_array_equal(run.final_deviation[:, c], one.final_deviation)
        np.testing.assert_array_equal(run.final_latch_deviation[:, c], one.final_latch_deviation)
        np.testing.assert_array_equal(run.final_state, one.final_state)


def test_error_control_takes_the_largest_error_of_the_columns(setup):
    """With ``deviation_rtol`` > 0 the block steps at least as often as its most demanding
    column alone, and each column's growth agrees with its lone run to the tolerance's
    level (4.3077 against 4.3087 over 30 ms at 150 rpm, ln of a growth of about 75)."""
    model, y0, block, latch = setup
    stops = np.array([0.0, 0.03])
    settings = TangentSettings(steps=STEPS, time_scale=TAU, deviation_rtol=1e-4)
    run = integrate_tangent(model, y0, block, stops, settings=settings, latch_deviation=latch)
    lone = _columns(model, y0, block, latch, stops, settings)
    assert run.stats.steps >= max(one.stats.steps for one in lone)
    for c, one in enumerate(lone):
        assert run.log_growth[-1, c] == pytest.approx(one.log_growth[-1], rel=0.01)


def test_a_one_column_block_is_the_single_deviation(setup):
    model, y0, block, _ = setup
    stops = np.array([0.0, 0.01])
    settings = TangentSettings(steps=STEPS, time_scale=TAU)
    one = integrate_tangent(model, y0, block[:, :1], stops, settings=settings)
    single = integrate_tangent(model, y0, block[:, 0], stops, settings=settings)
    assert single.final_deviation.shape == (y0.size,) and single.log_growth.shape == (2,)
    np.testing.assert_array_equal(one.final_deviation[:, 0], single.final_deviation)
    np.testing.assert_array_equal(one.log_growth[:, 0], single.log_growth)


def test_bad_block_shapes_are_refused(setup):
    model, y0, block, latch = setup
    settings = TangentSettings(steps=STEPS, time_scale=TAU)
    stops = np.array([0.0, 1e-3])
    with pytest.raises(ValueError, match=r"d0 must be a deviation of 30 values or a block"):
        integrate_tangent(model, y0, block[:-1], stops, settings=settings)
    with pytest.raises(ValueError, match=r"latch_deviation must have shape \(1, 3\)"):
        integrate_tangent(model, y0, block, stops, settings=settings, latch_deviation=latch[:, 0])


def test_records_at_every_stop_and_steps_match_the_stop_by_stop_loop(setup):
    """Recorded at many stops, or keeping every step's time, a run takes one compiled loop
    over them; its numbers are those of one return to Python per stop or step (forced
    here by a contact duration no run reaches), bit for bit."""
    model, y0, block, latch = setup
    stops = np.linspace(0.0, 0.02, 120)
    settings = TangentSettings(steps=STEPS, time_scale=TAU, deviation_rtol=1e-4, chunk_steps=50)
    python = dataclasses.replace(settings, neutral_latch_after=1e9)
    runs = [
        integrate_tangent(
            model, y0, block, stops, settings=s, latch_deviation=latch, record_states=True
        )
        for s in (settings, python)
    ]
    for name in ("t", "log_growth", "states", "contact", "contact_events", "latches"):
        np.testing.assert_array_equal(getattr(runs[0], name), getattr(runs[1], name))
    np.testing.assert_array_equal(runs[0].final_deviation, runs[1].final_deviation)
    steps = [
        integrate_tangent(model, y0, block, stops[[0, -1]], settings=s, record_steps=True)
        for s in (settings, python)
    ]
    assert steps[0].step_times.size > 100
    np.testing.assert_array_equal(steps[0].step_times, steps[1].step_times)
    np.testing.assert_array_equal(steps[0].final_state, steps[1].final_state)
