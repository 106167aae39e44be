"""Step limits of ``simulate``: the approach bound of the clearance joints.

Without ``solver.max_step`` a run with clearance joints is bounded only near contact: no
separated journal may travel its gap to the wall in one step (at its current speed and
acceleration), and the bound never goes below the scene's default output step, so impacts
are entered as with that step as a fixed limit while free flight and contact run at the
error control's step. The checks: the bound against the first-contact time of a run, the
first impacts of the clearance slider-crank (fresh and worn) against the fixed limit, and
the exponent's reference trajectory on the same steps as ``simulate``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import mechanism
from mechanism.core.integrate import (
    StepSettings,
    TangentSettings,
    initial_deviation,
    integrate_tangent,
)
from mechanism.core.integrate._driver import APPROACH_FRACTION
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state
from tests.mechanism.scenes import s3

CLEARANCE = 5e-4  # m, the slider-crank's joint B


def _worn(scene):
    """Joint B with a worn bearing: 0.3 c deep over ±40° about 0°, 0.2 c about 180°
    (where the first impact lands), unworn between: steps of the profile at 40° and 140°."""
    centres = np.arange(360) + 0.5
    off = np.abs((centres + 180.0) % 360.0 - 180.0)
    depth = np.where(off < 40.0, 0.3 * CLEARANCE, 0.0) + np.where(off > 140.0, 0.2 * CLEARANCE, 0.0)
    joint = scene.joints["B"]
    wear = dataclasses.replace(joint.wear, bearing_profile=tuple(depth))
    return dataclasses.replace(
        scene, joints={**scene.joints, "B": dataclasses.replace(joint, wear=wear)}
    )


def _first_impact(ds) -> tuple[float, float]:
    """(time of the first contact sample, peak force of the first impact)."""
    force = ds.contact_force.isel(joint=0).values
    start = int(np.argmax(force > 0))
    end = start + int(np.argmax(force[start:] == 0))
    assert end > start + 10, "the first impact must be resolved by the output grid"
    return float(ds.time[start]), float(force[start:end].max())


def test_bound_is_the_time_the_journal_takes_to_cross_its_gap() -> None:
    """From rest at the bearing centre the journal accelerates across the gap c: the bound
    √(2c/a) (fraction 1) predicts the first contact of the run within 2 %."""
    assert APPROACH_FRACTION == 1.0
    scene = s3()
    model = assemble(scene)
    q0, v0 = initial_state(model)
    y = np.concatenate([q0, v0])
    f = np.empty_like(y)
    ws = model.workspace()
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    vimp = np.full(1, 1e-3)
    assert k.rhs(model.kernel, ws, 0.0, y, vimp, f, counters) == 0
    n = model.n_dof
    bound = k.approach_step(model.kernel, ws, y, f[n:], APPROACH_FRACTION)
    ds = mechanism.simulate(scene, t_end=6e-4, output_step=2.5e-7)
    contact_time, _ = _first_impact(ds)
    assert bound == pytest.approx(contact_time, rel=0.02)
    # half the gap: the same acceleration crosses it in 1/√2 of the time
    assert k.approach_step(model.kernel, ws, y, f[n:], 0.5) == pytest.approx(
        bound / math.sqrt(2.0), rel=1e-12
    )
    # in contact the error control alone sets the step
    peak = ds.isel(time=int(np.argmax(ds.contact_force.isel(joint=0).values)))
    state = np.concatenate([peak.position.values.ravel(), peak.velocity.values.ravel()])
    assert k.approach_step(model.kernel, ws, state, f[n:], APPROACH_FRACTION) == math.inf


@pytest.mark.parametrize("friction", [0.0, 0.1])
@pytest.mark.parametrize("worn", [False, True])
def test_first_impact_as_with_the_fixed_limit_in_far_fewer_steps(friction, worn) -> None:
    """The first impact of the clearance slider-crank (45.9 kN fresh, 49.1 kN on the worn
    arc) within 0.5 % of the default output step as a fixed limit, in a tenth of its steps
    (61 and 41 of 834 without friction, fresh and worn)."""
    scene = s3(friction=friction)
    if worn:
        scene = _worn(scene)
    fixed = scene.replace({"solver.max_step": scene.drive.period / 10000})
    kw = {"t_end": 1e-3, "output_step": 2.5e-7}
    bounded = mechanism.simulate(scene, **kw)
    reference = mechanism.simulate(fixed, **kw)
    assert bounded.attrs["max_step"] == math.inf
    assert bounded.attrs["approach_floor"] == scene.drive.period / 10000
    assert reference.attrs["approach_floor"] == 0.0
    t_bounded, peak_bounded = _first_impact(bounded)
    t_fixed, peak_fixed = _first_impact(reference)
    assert t_bounded == t_fixed
    assert peak_fixed == pytest.approx(49.1e3 if worn else 45.9e3, rel=0.01)
    assert peak_bounded == pytest.approx(peak_fixed, rel=5e-3)
    share = 0.4 if worn else 0.1
    assert bounded.attrs["solver_steps"] < share * reference.attrs["solver_steps"]


def test_exponent_reference_takes_the_steps_of_simulate() -> None:
    """The tangent integration's reference follows the same rule: over 2 ms of rattling it
    takes exactly ``simulate``'s steps and ends in the same state."""
    scene = s3(friction=0.1)
    t_end = 2e-3
    ds = mechanism.simulate(scene, t_end=t_end, output_step=t_end / 4)
    model = assemble(scene)
    q0, v0 = initial_state(model)
    y0 = np.concatenate([q0, v0])
    d0 = initial_deviation(model, y0, t0=0.0, size=1e-12, time_scale=1e-3)
    steps = StepSettings(
        rtol=scene.solver.rtol, atol=scene.solver.atol, max_step=math.inf,
        approach_floor=ds.attrs["approach_floor"],
    )  # fmt: skip
    settings = TangentSettings(steps=steps, time_scale=1e-3)
    run = integrate_tangent(model, y0, d0, np.array([0.0, t_end]), settings=settings)
    assert run.stats.success and ds.attrs["solver_contact_events"] > 1
    assert run.stats.steps == ds.attrs["solver_steps"]
    n = model.n_dof
    np.testing.assert_allclose(
        run.final_state[:n], ds.position.isel(time=-1).values.ravel(), rtol=0, atol=1e-15
    )
