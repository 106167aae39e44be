"""The effects table: an effect that is off takes its cheap path and costs nothing."""

from __future__ import annotations

import numpy as np

import mechanism
from mechanism.core.model import assemble
from tests.mechanism.scenes import s3


def _run(scene, **kw):
    return mechanism.simulate(scene, t_end=0.01, output_step=1e-5, rtol=1e-6, atol=1e-6, **kw)


def test_clearance_off_takes_the_ideal_joint_path_and_evaluates_no_contact_code() -> None:
    on = s3(friction=0.1)
    off = on.replace({"effects.clearance": False})
    model = assemble(off)
    assert model.clearance_joints == () and model.kernel.cj_i.shape[0] == 0
    assert "B" in [j.name for j in model.ideal_joints]
    ds_on = _run(on)
    ds_off = _run(off)
    # the counter of contact-law calls works ...
    assert ds_on.attrs["solver_contact_evaluations"] > 0
    # ... and the clearance-off run never called it
    assert ds_off.attrs["solver_contact_evaluations"] == 0
    assert ds_off.attrs["solver_contact_events"] == 0
    assert "joint" not in ds_off.dims and "contact_force" not in ds_off
    # the ideal companion is the run itself, so the errors vanish identically
    assert np.all(ds_off.displacement_error.values == 0.0)
    # and it is the rigid slider-crank
    rigid = _run(mechanism.load_scene("slider-crank"))
    np.testing.assert_allclose(
        ds_off.slider_position.values, rigid.slider_position.values, rtol=0, atol=1e-12
    )


def test_friction_off_means_no_friction_force() -> None:
    with_friction = _run(s3(friction=0.1))
    assert np.abs(with_friction.friction_force.values).max() > 100.0
    without = _run(s3(friction=0.1).replace({"effects.friction": False}))
    assert np.all(without.friction_force.values == 0.0)
    assert np.abs(without.contact_force.values).max() > 1e3


def test_gravity_off_means_no_gravity() -> None:
    scene = mechanism.load_scene("slider-crank")
    off = scene.replace({"effects.gravity": False})
    assert np.all(assemble(off).kernel.gravity_force == 0.0)
    assert np.any(assemble(scene).kernel.gravity_force != 0.0)
    # gravity changes the pin reactions by the weights (the motion is prescribed)
    ds_on = mechanism.simulate(scene, revolutions=0.2, output_step=scene.drive.period / 200)
    ds_off = mechanism.simulate(off, revolutions=0.2, output_step=scene.drive.period / 200)
    np.testing.assert_allclose(
        ds_on.slider_position.values, ds_off.slider_position.values, atol=1e-9
    )
    weight = 9.81 * sum(b.mass for b in scene.bodies.values())
    ground = ds_on.joint_force_y.sel(ideal_joint=["O", "P"]).sum("ideal_joint")
    ground_off = ds_off.joint_force_y.sel(ideal_joint=["O", "P"]).sum("ideal_joint")
    # forces the frame exerts on the mechanism (pivot O and guide P) carry the total weight
    np.testing.assert_allclose((ground - ground_off).values, weight, rtol=1e-6)
