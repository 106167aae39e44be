"""The built-in ``paper`` scene is flexible by default; ``effects.flexibility =
false`` gives the rigid model at rigid-model cost; ``solver.method = "auto"`` picks the
integrator from the assembled model."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechanism
from mechanism.core.integrate import METHODS, Dopri5, GeneralizedAlpha, resolve_method
from mechanism.core.model import assemble
from mechanism.core.scene import AncfBeam, SolverSettings
from tests.mechanism.scenes import rigid_paper

RIGID_DOF = 5 * 3  # crank, plate, rod 3, rod 4, slider as rigid bodies (x, y, θ)
BEAM_DOF = 4 * (16 + 1)  # 16 elements: 17 nodes of (r, r') in the plane


def test_auto_is_a_method_and_the_solver_default() -> None:
    assert "auto" in METHODS
    assert SolverSettings().method == "auto"
    with pytest.raises(ValueError, match="auto"):
        resolve_method("auto")  # needs the assembled model
    assert isinstance(resolve_method(Dopri5()), Dopri5)  # objects pass through


@pytest.mark.parametrize("name", ["paper", "paper-gc", "paper-clearance-b"])
def test_paper_scenes_default_to_flexible_rods_with_16_elements(name: str) -> None:
    scene = mechanism.load_scene(name)
    assert scene.effects.flexibility is True and scene.solver.method == "auto"
    for rod in ("rod3", "rod4"):
        body = scene.bodies[rod]
        assert isinstance(body, AncfBeam) and body.elements == 16
    model = assemble(scene)
    assert set(model.beams) == {"rod3", "rod4"}
    assert model.kernel.beam_i.shape[0] == 2
    assert all(lay.n_dof == BEAM_DOF for lay in model.beams.values())
    assert model.n_dof == 3 * 3 + 2 * BEAM_DOF  # crank, plate, slider rigid
    integrator = resolve_method(scene.solver.method, model)
    assert isinstance(integrator, GeneralizedAlpha) and integrator.step == "max_step"
    # the scene's numerical damping (docs/ancf.md §8: friction chatter at 0.8)
    assert integrator.rho_inf == scene.solver.rho_inf == 0.5
    assert integrator == resolve_method("generalized-alpha-fixed", model)
    assert resolve_method("generalized-alpha-fixed").rho_inf == 0.8  # without a scene


def test_rho_inf_is_validated_at_the_boundary() -> None:
    with pytest.raises(ValueError, match="rho_inf"):
        mechanism.load_scene("paper").replace({"solver.rho_inf": 1.5})


@pytest.fixture(scope="module")
def flexible_run():
    return mechanism.simulate(mechanism.load_scene("paper"), revolutions=0.02)


def test_default_paper_scene_runs_flexible(flexible_run) -> None:
    ds = flexible_run
    assert ds.attrs["solver_status"] == 0
    # the resolved integrator is recorded, never "auto"
    assert ds.attrs["solver_method"] == ds.attrs["ideal_solver_method"] == "generalized-alpha"
    assert ds.attrs["revolutions"] == pytest.approx(0.02)
    # fixed step at the output step T/10000: one step per output sample (200 measured)
    assert ds.sizes["time"] == 201
    assert 200 <= ds.attrs["solver_steps"] <= 210
    assert set(ds.rod.values) == {"rod3", "rod4"}
    for name in ("strain_rod3", "strain_rod4"):
        value = float(ds[name])
        # 8 ms after a start from unstressed rods: gravity and inertia strains of ~1 µε
        assert math.isfinite(value) and 0.1 < abs(value) < 100.0, (name, value)
    assert np.isfinite(ds.strain.values).all()
    # measured: max |Φ| 2.5e-10 m, penetration 6.3e-6 m (c = 2e-4 m)
    assert float(ds.constraint_violation.max()) < 1e-8
    assert float(ds.penetration.max()) < 1e-5


def test_rigid_switch_gives_the_rigid_model_at_rigid_cost() -> None:
    scene = rigid_paper()
    model = assemble(scene)
    assert model.n_dof == RIGID_DOF and model.kernel.beam_i.shape[0] == 0 and not model.beams
    assert isinstance(resolve_method(scene.solver.method, model), Dopri5)
    auto = mechanism.simulate(scene, revolutions=0.1)
    explicit = mechanism.simulate(scene, revolutions=0.1, method="dopri5")
    assert auto.attrs["solver_method"] == "dopri5"
    for key in ("steps", "rejected_steps", "function_evaluations"):
        assert auto.attrs[f"solver_{key}"] == explicit.attrs[f"solver_{key}"], key
    # the same computation: bit for bit
    np.testing.assert_array_equal(auto.slider_position.values, explicit.slider_position.values)
    np.testing.assert_array_equal(auto.contact_force.values, explicit.contact_force.values)
    assert "strain" not in auto
