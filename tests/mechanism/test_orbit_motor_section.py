"""Periodic orbits of motor-driven scenes on a Poincaré section of the crank angle.

The reference is a crank pinned to the frame off its centre of mass, under gravity,
driven by the linear motor T(ω) = T_s (1 − ω/ω₀) with a flywheel: one degree of freedom,
J φ̈ = T_s (1 − φ̇/ω₀) − m g r cos φ with J = I + m r² + J_f constant. With the crank
angle as the independent variable, J ω ω' = T_s − c ω − m g r cos φ (c = T_s/ω₀);
linearised, δω' = −δω (c + J ω')/(J ω), so over one turn
ln(δω(2π)/δω(0)) = −(c/J) ∫ dφ/ω − ln(ω(2π)/ω(0)) = −c T/J on the periodic orbit
(ω(2π) = ω(0)): the section map's one multiplier is exp(−c T/J), T the period. The
period itself is checked against scipy on the same equation. The orbit is strongly
stable (|μ| ≈ 0.96 per turn, no contact), so the checks survive a 1e-12 perturbation of
the start.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import mechanism
from mechanism.core.scene import (
    Effects,
    MotorDrive,
    RevoluteJoint,
    RigidBody,
    Scene,
    validate_scene,
)

MASS, ARM, INERTIA, FLYWHEEL = 2.0, 0.1, 0.01, 0.04  # kg, m, kg m2, kg m2
STALL, NO_LOAD_RPM, G = 2.0, 600.0, 9.81  # N m, rpm, m s-2
W0 = NO_LOAD_RPM * math.pi / 30.0
J = INERTIA + MASS * ARM**2 + FLYWHEEL
C = STALL / W0


def _pendulum_crank() -> Scene:
    return validate_scene(
        Scene(
            name="motor-pendulum",
            effects=Effects(gravity=True, clearance=False, friction=False),
            ground_points={"O": (0.0, 0.0)},
            bodies={
                "crank": RigidBody(mass=MASS, inertia=INERTIA, position=(ARM, 0.0),
                                   points={"O": (-ARM, 0.0)})
            },
            joints={"O": RevoluteJoint(bodies=("ground", "crank"), points=("O", "O"))},
            drive=MotorDrive(joint="O", stall_torque=STALL, no_load_speed_rpm=NO_LOAD_RPM,
                             flywheel_inertia=FLYWHEEL, initial_speed_rpm=NO_LOAD_RPM),
        )
    )  # fmt: skip


def _reference_period(phi0: float) -> float:
    """Period of the periodic orbit of J ω ω' = T_s − c ω − m g r cos φ (scipy)."""

    def rhs(phi: float, u: np.ndarray) -> list[float]:
        w = u[0]
        return [(STALL - C * w - MASS * G * ARM * math.cos(phi)) / (J * w), 1.0 / w]

    def turn(w: float) -> np.ndarray:
        run = solve_ivp(rhs, (phi0, phi0 + 2.0 * math.pi), [w, 0.0], rtol=1e-12, atol=1e-14)
        return run.y[:, -1]

    w = brentq(lambda w: turn(w)[0] - w, 0.9 * W0, 1.1 * W0, xtol=1e-13)
    return float(turn(w)[1])


@pytest.mark.slow  # the motor scene's tangent kernels: about 45 s to compile
def test_motor_crank_orbit_period_and_multiplier_match_the_closed_form() -> None:
    """The section map's period agrees with scipy's within 1e-8 relative and its one
    multiplier with exp(−c T/J) within 1e-6 (finite-difference tangent at ε = 1e-9 of
    the length scale; the error is linear in ε: 4.6e-6 at the default 1e-7)."""
    orbit = mechanism.periodic_orbit(_pendulum_crank(), settle=5, perturbation=1e-9)
    assert orbit.converged and orbit.residual < 1e-9
    assert orbit.section == "crank angle"
    assert orbit.period == 1
    assert orbit.multipliers.shape == (1,)  # the crank speed; none along the flow
    assert orbit.neutral_multipliers.size == 0
    phi0 = float(orbit.section_state[2])
    assert orbit.drive_period == pytest.approx(_reference_period(phi0), rel=1e-8)
    closed = math.exp(-C * orbit.drive_period / J)
    assert orbit.multipliers[0].real == pytest.approx(closed, rel=1e-6)
    assert orbit.exponent == pytest.approx(-C / J, rel=2e-5)
    assert orbit.to_dataset().attrs["setting_section"] == "crank angle"


@pytest.mark.slow  # the motor scene's tangent kernels: about 45 s to compile
def test_motor_crank_orbit_from_perturbed_starts_is_the_same() -> None:
    """Starts 1e-12 apart (relative) converge to the same orbit: period within 1e-10
    relative, multiplier within 1e-6, section state within 1e-9 of the length scale."""
    scene = _pendulum_crank()
    first = mechanism.periodic_orbit(scene, settle=5)
    rng = np.random.default_rng(3)
    for _ in range(2):
        start = first.section_state * (1.0 + 1e-12 * rng.standard_normal(first.section_state.size))
        again = mechanism.periodic_orbit(scene, guess=start)
        assert again.converged
        assert again.drive_period == pytest.approx(first.drive_period, rel=1e-10)
        # the finite-difference tangent's error (4.6e-6 at the default ε) moves with the
        # frozen steps of each start: measured 1.5e-7 relative
        assert again.multipliers[0].real == pytest.approx(first.multipliers[0].real, rel=1e-6)
        gap = np.abs(again.section_state[3:] - first.section_state[3:]).max()
        assert gap < 1e-9 * max(1.0, np.abs(first.section_state[3:]).max())


def test_motor_orbit_refuses_search_and_segments() -> None:
    message = (
        "periodic_orbit on a motor-driven scene shoots on the crank-angle section with single "
        "shooting from a settled run: search must be 0 and segments None or 1."
    )
    with pytest.raises(ValueError) as err:
        mechanism.periodic_orbit(_pendulum_crank(), segments=8)
    assert str(err.value) == message


@pytest.mark.slow
def test_stiff_motor_orbit_approaches_the_constant_speed_orbit() -> None:
    """The rigid paper scene at 30 rpm driven by a motor with a steep torque–speed curve
    (6283 N m stall at 30 rpm no-load: a slope of 2000 N m s/rad) turns at nearly constant
    speed: the period is 60/30 s within 1e-4 relative (measured 8.4e-6: the load slows the
    crank by its mean torque over the slope), the journal rides the same orbit as at a
    constant 30 rpm (section eccentricity within 1e-3 of the clearance), and both orbits
    are strongly stable (|μ_max| < 0.01: 1.95e-4 on the section, 1.88e-3 at constant
    speed). The largest multipliers differ: the monodromy of both is nearly of rank 1 and
    its largest eigenvalue ill conditioned (docs/periodic-orbits.md), and the motor adds the
    crank-speed direction; a finite-difference Jacobian of the section map (steps 1e-5 of
    the clearance) gave −1.4e-3."""
    base = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": 30.0}
    )
    fixed = mechanism.periodic_orbit(base)
    stiff = base.replace(
        {"drive": {"type": "motor", "joint": "O", "stall_torque": 6283.0,
                   "no_load_speed_rpm": 30.0, "initial_speed_rpm": 30.0}}
    )  # fmt: skip
    motor = mechanism.periodic_orbit(stiff)
    assert motor.converged and motor.section == "crank angle"
    assert fixed.converged and fixed.section == "time"
    assert motor.drive_period == pytest.approx(2.0, rel=1e-4)
    assert motor.multipliers.size == fixed.multipliers.size + 1  # and the crank speed
    assert motor.stable and fixed.stable
    assert abs(motor.multipliers[0]) < 0.01 and abs(fixed.multipliers[0]) < 0.01
    gap = np.abs(motor.section_eccentricity[0] - fixed.section_eccentricity[0]).max()
    assert gap < 1e-3 * fixed.clearance
