"""Force elements in scenes: springs, dampers, actuators and applied loads against closed
forms (a mass on a spring–damper, a torsional pendulum, a quasi-static slider-crank),
energy conservation, the scene keys' validation and the built-in scene with force
elements through ``simulate``, ``lyapunov_exponent`` and ``mechanism sweep``.

The motions checked against closed forms are linear (or quasi-static) and not chaotic, so
their agreement survives any rounding of the initial state."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import least_squares
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.core.model import assemble
from mechanism.core.scene import (
    Effects,
    ForceDeflectionTable,
    Outputs,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    RotationalSpringDamper,
    Scene,
    SceneError,
    SolverSettings,
    SpringDamper,
    scene_from_dict,
    validate_scene,
)

TIGHT = SolverSettings(rtol=1e-11, atol=1e-13, output_step=1e-3)
NO_GRAVITY = Effects(gravity=False, clearance=False, friction=False)


def mass_on_spring(k: float, c: float, *, x0: float = 0.15, free_length: float = 0.1) -> Scene:
    """A 2 kg slider on a horizontal prismatic joint, tied to the ground point at the
    origin by a spring–damper along the guide."""
    return validate_scene(
        Scene(
            name="mass-spring-damper",
            effects=NO_GRAVITY,
            ground_points={"O": (0.0, 0.0)},
            bodies={"mass": RigidBody(mass=2.0, position=(x0, 0.0), points={"P": (0.0, 0.0)})},
            joints={"S": PrismaticJoint(bodies=("ground", "mass"), points=("O", "P"))},
            forces={
                "spring": SpringDamper(
                    bodies=("ground", "mass"),
                    points=("O", "P"),
                    stiffness=k,
                    damping=c,
                    free_length=free_length,
                )
            },
            solver=TIGHT,
        )
    )


def _damped(t, amplitude, sigma, omega, phase, offset):
    return offset + amplitude * np.exp(-sigma * t) * np.cos(omega * t + phase)


def _fit(t: np.ndarray, x: np.ndarray, guess: tuple[float, ...]) -> np.ndarray:
    """Least-squares (amplitude, decay rate, frequency, phase, offset) of a damped cosine."""
    fit = least_squares(lambda p: _damped(t, *p) - x, guess, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return fit.x


def test_mass_on_a_linear_spring_damper_has_the_closed_form_frequency_and_decay() -> None:
    """m ẍ = −k (x − L₀) − c ẋ: the fitted decay rate c/2m and damped frequency
    √(k/m − (c/2m)²) agree with the closed form within 1e-6 relative (measured 1e-10)."""
    m, k, c = 2.0, 800.0, 4.0
    ds = mechanism.simulate(mass_on_spring(k, c), t_end=1.0)
    t = ds.time.values
    x = ds.slider_position.values
    sigma = c / (2.0 * m)
    omega = math.sqrt(k / m - sigma**2)
    _, s_fit, w_fit, _, offset = _fit(t, x, (0.05, 1.0, 20.0, 0.0, 0.1))
    assert s_fit == pytest.approx(sigma, rel=1e-6)
    assert w_fit == pytest.approx(omega, rel=1e-6)
    assert offset == pytest.approx(0.1, abs=1e-9)
    # and the whole trajectory: x = L₀ + (x₀ − L₀) e^(−σt) (cos ωt + σ/ω sin ωt)
    exact = 0.1 + 0.05 * np.exp(-sigma * t) * (
        np.cos(omega * t) + sigma / omega * np.sin(omega * t)
    )
    assert np.max(np.abs(x - exact)) < 1e-10


def test_element_forces_on_request_are_the_spring_law_along_the_run() -> None:
    """``Model.force_element_values`` on a recorded run: tension k (x − L₀) + c ẋ,
    deflection x − L₀ and rate ẋ of the spring (exact up to rounding)."""
    scene = mass_on_spring(800.0, 4.0)
    ds = mechanism.simulate(scene, t_end=0.2)
    model = assemble(scene)
    n = ds.time.size
    values = model.force_element_values(
        ds.time.values, ds.position.values.reshape(n, -1), ds.velocity.values.reshape(n, -1)
    )
    x = ds.slider_position.values
    xd = ds.slider_velocity.values
    assert values.shape == (n, 1, 3)
    np.testing.assert_allclose(values[:, 0, 1], x - 0.1, rtol=0, atol=1e-15)
    np.testing.assert_allclose(values[:, 0, 2], xd, rtol=0, atol=1e-13)
    np.testing.assert_allclose(values[:, 0, 0], 800.0 * (x - 0.1) + 4.0 * xd, rtol=0, atol=1e-10)


def torsional_pendulum(k: float, c: float, angle: float = 0.2) -> Scene:
    """A bar pinned to the ground at its centre of mass with a torsional spring–damper in
    the pin: J θ̈ = −k θ − c θ̇ exactly (gravity has no moment about the centre)."""
    return validate_scene(
        Scene(
            name="torsional-pendulum",
            ground_points={"O": (0.0, 0.0)},
            bodies={
                "bar": RigidBody(
                    mass=1.0, inertia=0.02, angle=angle, points={"O": (0.0, 0.0), "E": (0.2, 0.0)}
                )
            },
            joints={"O": RevoluteJoint(bodies=("ground", "bar"), points=("O", "O"))},
            forces={"coil": RotationalSpringDamper(joint="O", stiffness=k, damping=c)},
            outputs=Outputs(crank_joint="O"),
            solver=TIGHT,
        )
    )


def test_torsional_spring_pendulum_has_the_closed_form_frequency_and_decay() -> None:
    """J θ̈ = −k θ − c θ̇ with J = 0.02 kg m², k = 2 N m/rad, c = 0.01 N m s/rad: fitted
    σ = c/2J and ω = √(k/J − σ²) within 1e-6 relative."""
    j, k, c = 0.02, 2.0, 0.01
    ds = mechanism.simulate(torsional_pendulum(k, c), t_end=1.0)
    t = ds.time.values
    theta = ds.position.sel(body="bar").isel(axis=2).values
    sigma = c / (2.0 * j)
    omega = math.sqrt(k / j - sigma**2)
    _, s_fit, w_fit, _, offset = _fit(t, theta, (0.2, 0.2, 10.0, 0.0, 0.0))
    assert s_fit == pytest.approx(sigma, rel=1e-6)
    assert w_fit == pytest.approx(omega, rel=1e-6)
    assert abs(offset) < 1e-9


def conservative_scene() -> Scene:
    """Undamped, with gravity: an elastic pendulum (a free body on a spring from the
    ground, the spring at a point off its centre of mass, with a stiffening tabulated law
    and an actuator force) and a bar on a torsional spring with an actuator torque."""
    table = ForceDeflectionTable(deflection=(-0.1, 0.0, 0.05, 0.2), force=(-30.0, 0.0, 10.0, 80.0))
    return validate_scene(
        Scene(
            name="conservative-springs",
            ground_points={"O": (0.0, 0.0), "H": (0.5, 0.0)},
            bodies={
                "bob": RigidBody(
                    mass=1.5,
                    inertia=0.01,
                    position=(0.05, -0.3),
                    angle=0.3,
                    points={"P": (0.05, 0.02)},
                ),
                "bar": RigidBody(
                    mass=1.0,
                    inertia=0.02,
                    position=(0.6, 0.0),
                    angle=0.4,
                    points={"H": (-0.1, 0.0)},
                ),
            },
            joints={"H": RevoluteJoint(bodies=("ground", "bar"), points=("H", "H"))},
            forces={
                "spring": SpringDamper(
                    bodies=("ground", "bob"),
                    points=("O", "P"),
                    stiffness=200.0,
                    free_length=0.25,
                    actuator_force=2.0,
                    force_deflection=table,
                ),
                "coil": RotationalSpringDamper(
                    joint="H", stiffness=3.0, reference_angle=0.1, actuator_torque=0.2
                ),
            },
            solver=SolverSettings(rtol=1e-10, atol=1e-12, output_step=1e-3),
        )
    )


def test_undamped_springs_conserve_the_mechanical_energy() -> None:
    """Springs (linear + tabulated), actuator force and torque store their work as
    potential energy: over 2 s at rtol 1e-10 the mechanical energy stays within 5e-7 of
    its initial value relative to the kinetic energy exchanged (measured 5e-8). A drift
    bound, so it holds whatever rounding does to the (possibly chaotic) elastic pendulum."""
    ds = mechanism.simulate(conservative_scene(), t_end=2.0)
    energy = ds.mechanical_energy.values
    bob = ds.velocity.sel(body="bob").values
    kinetic = 0.5 * 1.5 * (bob[:, 0] ** 2 + bob[:, 1] ** 2)
    swing = float(np.ptp(kinetic))
    assert swing > 0.1  # the springs exchange energy with the motion
    assert np.max(np.abs(energy - energy[0])) < 5e-7 * swing


def test_constant_slider_load_balances_the_quasi_static_driving_torque() -> None:
    """A slider-crank at 1 rpm without gravity and a constant 100 N load against the
    slider: the driving torque is the virtual-work balance T = −F ds/dθ,
    ds/dθ = −r sin θ − r² sin θ cos θ / √(l² − r² sin² θ), within 1e-5 of 100 N × r
    (inertia forces are 1e-6 of the load at this speed)."""
    scene = mechanism.load_scene("slider-crank").replace(
        {
            "effects.gravity": False,
            "drive.speed_rpm": 1.0,
            "solver.output_step": 0.05,
            "forces": {
                "load": {"type": "load", "body": "slider", "point": "B", "force": [-100.0, 0.0]}
            },
        }
    )
    ds = mechanism.simulate(scene, revolutions=1.0, record="full")
    theta = ds.crank_angle.values
    r, length = 0.05, 0.12
    sin, cos = np.sin(theta), np.cos(theta)
    ds_dtheta = -r * sin - r * r * sin * cos / np.sqrt(length**2 - (r * sin) ** 2)
    expected = 100.0 * ds_dtheta
    torque = ds.driving_torque.values
    assert np.max(np.abs(torque - expected)) < 1e-5 * 100.0 * r


# ----------------------------------------------------------------------- scene keys


def _slider_crank_with(forces: dict) -> dict:
    data = mechanism.load_scene("slider-crank").to_dict()
    data["forces"] = forces
    return data


@pytest.mark.parametrize(
    ("forces", "message"),
    [
        (
            {
                "s": {
                    "type": "spring_damper",
                    "bodies": ["ground", "slider"],
                    "points": ["O", "B"],
                    "stiffness": -1.0,
                    "free_length": 0.1,
                }
            },
            "forces.s.stiffness: must be in [0, 1e+12] (N m-1); got -1.0",
        ),
        (
            {
                "s": {
                    "type": "spring_damper",
                    "bodies": ["ground", "slider"],
                    "points": ["O", "X"],
                    "free_length": 0.1,
                }
            },
            "forces.s.points[1]: body 'slider' has no point 'X'; its points: B",
        ),
        (
            {"r": {"type": "rotational_spring_damper", "joint": "P"}},
            "forces.r.joint: joint 'P' is 'prismatic'; it must be a 'revolute' or "
            "'clearance_revolute' joint",
        ),
        (
            {
                "l": {
                    "type": "load",
                    "body": "slider",
                    "point": "B",
                    "coordinate_profile": {
                        "joint": "P",
                        "coordinate": [0.2, 0.1],
                        "factor": [0.0, 1.0],
                    },
                }
            },
            "forces.l.coordinate_profile.coordinate: must be strictly increasing",
        ),
        (
            {
                "l": {
                    "type": "load",
                    "body": "slider",
                    "point": "B",
                    "time_profile": {
                        "type": "table",
                        "period": 1.0,
                        "time": [0.0, 1.0],
                        "factor": [0.0, 1.0],
                    },
                }
            },
            "forces.l.time_profile.time: the samples must span less than one period (1 s); got 1 s",
        ),
        (
            {"l": {"type": "weight", "body": "slider", "point": "B"}},
            "forces.l.type: must be one of 'spring_damper', 'rotational_spring_damper', "
            "'load'; got 'weight'",
        ),
    ],
)
def test_invalid_force_elements_are_one_line_errors(forces: dict, message: str) -> None:
    with pytest.raises(SceneError) as info:
        scene_from_dict(_slider_crank_with(forces))
    assert info.value.problems == (message,)


def test_scene_without_force_elements_has_empty_tables() -> None:
    model = assemble(mechanism.load_scene("slider-crank"))
    assert model.kernel.fe_i.shape == (0, 17) and model.kernel.fe_t.shape == (0,)
    assert model.force_elements == ()


# --------------------------------------------------------------- the built-in scene


def test_builtin_spring_load_scene_simulates_and_keeps_its_energy_balance() -> None:
    """Half a revolution of ``slider-crank-spring-load``: the run completes and the press
    force acts (the driving torque differs from the run without force elements)."""
    scene = mechanism.load_scene("slider-crank-spring-load")
    ds = mechanism.simulate(scene, revolutions=0.5, record="full")
    bare = mechanism.simulate(scene.replace({"forces": {}}), revolutions=0.5, record="full")
    assert np.all(np.isfinite(ds.driving_torque.values))
    # the return spring alone pulls with 20–220 N: the torques differ by far more than noise
    assert np.max(np.abs(ds.driving_torque.values - bare.driving_torque.values)) > 1.0


@pytest.mark.parametrize(
    ("scene", "t_end", "sigma"),
    [(mass_on_spring(800.0, 4.0), 10.0, 1.0), (torsional_pendulum(2.0, 0.04), 20.0, 1.0)],
    ids=["mass-spring-damper", "torsional-pendulum"],
)
def test_lyapunov_exponent_sees_the_damping_of_force_elements(scene, t_end, sigma) -> None:
    """The tangent integration differentiates the right-hand side, force elements
    included: the exponent of a damped linear oscillator is −σ (σ = c/2m, c/2J), inside
    the estimate's interval (measured −0.73 and −0.90 s⁻¹ with intervals of about ±0.7)."""
    result = mechanism.lyapunov_exponent(scene, t_end=t_end)
    assert result.exponent < 0.0
    assert result.ci[0] <= -sigma <= result.ci[1]


def test_lyapunov_exponent_runs_on_the_builtin_spring_load_scene() -> None:
    """Two revolutions, under 1 s once compiled (the working force is continuous in time:
    it is ramped out before the slider turns)."""
    result = mechanism.lyapunov_exponent(
        mechanism.load_scene("slider-crank-spring-load"), revolutions=2.0
    )
    assert math.isfinite(result.exponent)


def test_sweep_cli_runs_on_the_builtin_spring_load_scene(tmp_path) -> None:
    args = [
        "sweep",
        "slider-crank-spring-load",
        "--grid",
        "forces.return_spring.stiffness=1000,3000",
        "--store",
        str(tmp_path / "store"),
        "--revolutions",
        "2",
        "--scheduler",
        "serial",
        "--no-analysis",
        "--no-progress",
    ]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "2 points: 2 to run, 0 already done" in result.output


def test_a_press_load_acts_only_on_its_working_stroke() -> None:
    """The coordinate-profile load with ``active = "increasing"``: with the slider at the
    same position, the load acts while it moves out and not while it moves back."""
    scene = mechanism.load_scene("slider-crank-spring-load").replace(
        {"forces.return_spring.stiffness": 0.0, "forces.return_spring.damping": 0.0}
    )
    model = assemble(scene)
    km = model.kernel
    ws = model.workspace()
    q = model.q_guess.copy()
    slider = model.body_names.index("slider")
    o = model.body_offsets[slider]
    q[o] = 0.15
    for speed, factor in ((1.0, 1.0), (-1.0, 0.0)):
        v = np.zeros_like(q)
        v[o] = speed
        ws.gen[:] = 0.0
        mechanism.core.model.kernels.update_points(q, v, km.pt_i, km.pt_f, ws.pci, ws.pcf)
        from_forces = np.zeros_like(q)
        mechanism.core.forces.force_elements_add(
            km.fe_i, km.fe_f, km.fe_t, 0.0, ws.pci, ws.pcf, from_forces, ws.fe
        )
        assert ws.fe[1, 0] == factor
        assert from_forces[o] == pytest.approx(-500.0 * factor, abs=1e-12)
