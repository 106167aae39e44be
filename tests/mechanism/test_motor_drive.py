"""A motor drive: a linear torque–speed curve and a flywheel on a free crank angle.

A rigid crank (with a flywheel) on a frictionless pivot, driven by T(ω) = T_s (1 − ω/ω₀)
from rest: J ω̇ = T_s − (T_s/ω₀) ω, so ω = ω₀ (1 − e^(−t/τ)) with the steady speed ω₀
(where T = 0) and the time constant τ = J/(T_s/ω₀) = J/|dT/dω|, and the crank angle
θ = ω₀ (t − τ (1 − e^(−t/τ))). The motion is linear and stable: the checks survive any
rounding of the initial state."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares

import mechanism
from mechanism.core.model import assemble
from mechanism.core.scene import (
    AncfBeam,
    Effects,
    MotorDrive,
    RevoluteJoint,
    RigidBody,
    Scene,
    SceneError,
    SolverSettings,
    scene_from_dict,
    validate_scene,
)

STALL = 2.0  # N m
NO_LOAD_RPM = 600.0
W0 = NO_LOAD_RPM * 2.0 * math.pi / 60.0  # rad/s
CRANK_INERTIA = 0.01  # kg m2
FLYWHEEL = 0.04  # kg m2
TAU = (CRANK_INERTIA + FLYWHEEL) / (STALL / W0)  # s


def motor_crank(flywheel: float = FLYWHEEL) -> Scene:
    """A rigid crank pinned to the frame at its centre of mass, driven from rest by the
    linear motor with ``flywheel`` (kg m²) on it; no gravity, no friction."""
    return validate_scene(
        Scene(
            name="motor-flywheel",
            effects=Effects(gravity=False, clearance=False, friction=False),
            ground_points={"O": (0.0, 0.0)},
            bodies={
                "crank": RigidBody(
                    mass=1.0, inertia=CRANK_INERTIA, position=(0.0, 0.0), points={"O": (0.0, 0.0)}
                )
            },
            joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
            drive=MotorDrive(
                joint="O", stall_torque=STALL, no_load_speed_rpm=NO_LOAD_RPM,
                flywheel_inertia=flywheel,
            ),
            solver=SolverSettings(rtol=1e-11, atol=1e-13, output_step=1e-3),
        )
    )  # fmt: skip


def _angle(t: np.ndarray, w: float, tau: float) -> np.ndarray:
    return w * (t - tau * -np.expm1(-t / tau))


def test_linear_motor_reaches_the_steady_speed_with_the_time_constant() -> None:
    """The least-squares (ω_ss, τ) of the recorded crank angle over 5τ are ω₀ and
    J/(T_s/ω₀) within 1e-6 relative; the model has no drive row and the motor's torque
    is the force element "drive"."""
    scene = motor_crank()
    model = assemble(scene)
    assert model.drive_row is None
    assert model.force_elements == ("drive",)
    ds = mechanism.simulate(scene, t_end=5.0 * TAU)
    t = ds.time.values
    theta = ds.crank_angle.values
    fit = least_squares(
        lambda p: _angle(t, *p) - theta, (0.9 * W0, 1.1 * TAU), xtol=1e-15, ftol=1e-15,
        gtol=1e-15,
    )  # fmt: skip
    w_ss, tau = fit.x
    assert w_ss == pytest.approx(W0, rel=1e-6)
    assert tau == pytest.approx(TAU, rel=1e-6)


def test_sections_of_a_motor_driven_crank_are_at_crank_angle_crossings() -> None:
    """``SectionsRecord`` on a motor-driven crank samples where the crank angle passes
    2πk (located on the integrator's dense output), not at multiples of a period: the
    section times are the closed form's crossing times within 1e-9 s (measured 3e-12 s)
    and the recorded angles 2πk within 1e-9 rad (measured 3e-14); ``discard`` counts
    revolutions of the crank, so the first section is k = 1."""
    ds = mechanism.simulate(motor_crank(), t_end=3.0, record=mechanism.SectionsRecord(discard=1.0))
    k = ds.drive_cycle.values
    assert k[0] == 1
    assert np.array_equal(k, np.arange(1, k.size + 1))
    exact = [brentq(lambda s, n=n: _angle(s, W0, TAU) - 2.0 * math.pi * n, 1e-9, 10.0,
                    xtol=1e-15) for n in k]  # fmt: skip
    assert k.size == math.floor(_angle(3.0, W0, TAU) / (2.0 * math.pi))
    assert np.max(np.abs(ds.time.values - exact)) < 1e-9
    assert np.max(np.abs(ds.crank_angle.values - 2.0 * math.pi * k)) < 1e-9


def test_exponent_of_a_motor_driven_crank_is_zero() -> None:
    """An autonomous motion: the deviation along the flow (a shift of the crank angle)
    neither grows nor decays, so the largest exponent is 0 (the speed's deviation decays
    at −1/τ); measured 1.3e-3 1/s over 5–20 s."""
    result = mechanism.lyapunov_exponent(motor_crank(), t_end=20.0, discard=5.0)
    assert abs(result.exponent) < 0.01
    assert result.ci[0] <= 0.0 <= result.ci[1]


def _with_drive(drive: dict, forces: dict | None = None) -> dict:
    return {
        "name": "motor",
        "ground_points": {"O": [0.0, 0.0]},
        "bodies": {"crank": {"mass": 1.0, "inertia": 0.01, "points": {"O": [0.0, 0.0]}}},
        "joints": {"O": {"type": "revolute", "bodies": ["ground", "crank"], "points": ["O"] * 2}},
        "drive": {"type": "motor", "joint": "O", **drive},
        "forces": forces or {},
    }


def test_motor_scene_from_toml_keys() -> None:
    """``[drive] type = "motor"`` with its keys gives the MotorDrive."""
    drive = {"stall_torque": 2.0, "no_load_speed_rpm": 600.0, "flywheel_inertia": 0.04}
    scene = scene_from_dict(_with_drive(drive))
    assert scene.drive == MotorDrive(
        joint="O", stall_torque=2.0, no_load_speed_rpm=600.0, flywheel_inertia=0.04
    )
    assert scene.drive.damping == pytest.approx(2.0 / W0, rel=1e-15)


@pytest.mark.parametrize(
    ("drive", "forces", "message"),
    [
        (
            {"stall_torque": -1.0, "no_load_speed_rpm": 600.0},
            None,
            "drive.stall_torque: must be in [0, 1e+09] (N m); got -1.0",
        ),
        (
            {"stall_torque": 2.0, "no_load_speed_rpm": 600.0, "initial_speed_rpm": 2e6},
            None,
            "drive.initial_speed_rpm: must be in [-1e+06, 1e+06] (rpm); got 2000000.0",
        ),
        (
            {"stall_torque": 2.0, "no_load_speed_rpm": 0.0},
            None,
            "drive.no_load_speed_rpm: must be in [0.001, 1e+06] (rpm); got 0.0",
        ),
        (
            {"stall_torque": 2.0, "no_load_speed_rpm": 600.0, "flywheel_inertia": -1.0},
            None,
            "drive.flywheel_inertia: must be in [0, 1e+06] (kg m2); got -1.0",
        ),
        (
            {"stall_torque": 2.0, "no_load_speed_rpm": 600.0},
            {"drive": {"type": "rotational_spring_damper", "joint": "O", "damping": 1.0}},
            "forces.drive: the name is taken by the motor drive's torque; rename the element",
        ),
    ],
)
def test_invalid_motor_drives_are_one_line_errors(
    drive: dict, forces: dict | None, message: str
) -> None:
    with pytest.raises(SceneError) as info:
        scene_from_dict(_with_drive(drive, forces))
    assert info.value.problems == (message,)


def test_flywheel_on_a_flexible_body_is_a_one_line_error() -> None:
    """The flywheel adds to a rigid body's moment of inertia; on an ANCF rod it is
    refused, naming the key."""
    rod = AncfBeam(
        length=0.5, elements=2, area=1e-3, second_moment=1e-7, youngs_modulus=2.07e11,
        density=2000.0, start=(0.0, 0.0), end=(0.5, 0.0),
    )  # fmt: skip
    scene = Scene(
        name="motor-rod",
        ground_points={"O": (0.0, 0.0)},
        bodies={"rod": rod},
        joints={"O": RevoluteJoint(bodies=("ground", "rod"), points=("O", "start"))},
        drive=MotorDrive(joint="O", stall_torque=1.0, no_load_speed_rpm=60.0, flywheel_inertia=0.1),
    )
    with pytest.raises(SceneError) as info:
        validate_scene(scene)
    assert info.value.problems == (
        "drive.flywheel_inertia: the flywheel needs a rigid second body of joint 'O'; got 'rod'",
    )


def test_a_crank_driven_past_the_reserved_sections_says_so() -> None:
    """A constant torque of 5 T_s on the crank overruns the motor: the crank settles at
    ω₀ (1 + 5) = 6 ω₀, beyond the room reserved for sections (4 × the no-load speed), so
    the run warns and keeps the first sections, all at 2πk; at the motor's own speed it
    does not warn (the test suite turns such warnings into errors)."""
    overrun = motor_crank(flywheel=0.0).replace(
        {"forces": {"push": {"type": "load", "body": "crank", "point": "O", "torque": 5 * STALL}}}
    )
    record = mechanism.SectionsRecord(discard=0.0)
    with pytest.warns(mechanism.SimulationWarning, match=r"only the first \d+ sections are kept"):
        ds = mechanism.simulate(overrun, t_end=2.0, record=record)
    k = ds.drive_cycle.values
    assert k.size > 0 and np.array_equal(k, np.arange(k[0], k[0] + k.size))
    assert np.max(np.abs(ds.crank_angle.values - 2.0 * math.pi * k)) < 1e-6
    mechanism.simulate(motor_crank(flywheel=0.0), t_end=2.0, record=record)
