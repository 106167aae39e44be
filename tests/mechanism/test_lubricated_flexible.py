"""The oil film in the implicit integrator of flexible scenes: its force is re-linearised at
the Newton iterates like a dry contact (``film_engaged``/``film_moved``), so a flexible
scene with a lubricated joint converges in about as many Newton iterations per step as
the dry one, and its energy balance holds: the mechanical energy never exceeds what the
drive has put in.
"""

from __future__ import annotations

import numpy as np
import pytest

import mechanism

REVOLUTIONS = 0.25  # of the paper scene at 150 rpm: 0.1 s


def _energy_excess(ds) -> float:
    """Largest E(t) − E(0) − W(t) (J), W the drive's work ∫ T ω dt on the crank."""
    t = ds.time.values
    power = ds.driving_torque.values * np.gradient(ds.crank_angle.values, t)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t))])
    energy = ds.mechanical_energy.values
    return float(np.max(energy - energy[0] - work))


def _iterations_per_step(ds) -> float:
    attempted = ds.attrs["solver_steps"] + ds.attrs["solver_rejected_steps"]
    return ds.attrs["solver_newton_iterations"] / attempted


@pytest.mark.slow
def test_a_flexible_lubricated_scene_converges_like_the_dry_one() -> None:
    """The flexible paper scene (two 16-element ANCF rods) with oil at C (0.04 Pa s) over
    a quarter revolution: Newton iterations per attempted step within 1.5× of the dry
    scene's, rejected steps fewer than a tenth of the accepted ones, and no energy
    created beyond 1e-3 of the drive's work."""
    scene = mechanism.load_scene("paper")
    dry = mechanism.simulate(scene, revolutions=REVOLUTIONS)
    oil = mechanism.simulate(
        scene.replace({"joints.C.lubrication": {"viscosity": 0.04}}), revolutions=REVOLUTIONS
    )
    assert _iterations_per_step(oil) <= 1.5 * _iterations_per_step(dry)
    assert oil.attrs["solver_rejected_steps"] < 0.1 * oil.attrs["solver_steps"]
    for ds in (dry, oil):
        t = ds.time.values
        power = ds.driving_torque.values * np.gradient(ds.crank_angle.values, t)
        scale = float(np.sum(np.abs(power[1:]) * np.diff(t)))
        assert _energy_excess(ds) <= 1e-3 * scale
