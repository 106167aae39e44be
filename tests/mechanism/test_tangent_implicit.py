"""The implicit deviation update (``TangentSettings(deviation_scheme="rosenbrock")``).

On a linear system the deviation's growth is known in closed form: a bar pinned to the
ground at its centre of mass with a torsional spring–damper in the pin, at rest at its
equilibrium, obeys J δθ̈ = −k δθ − c δθ̇ exactly (gravity has no moment about the pin), so
the deviation is exp(At) applied to its start, A = [[0, 1], [−k/J, −c/J]]. The rigid
paper scene checks the estimate where the implicit update is inaccurate on the
reference's steps (a nearly undamped contact oscillation of the deviation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

import mechanism
from mechanism.core.integrate import (
    StepSettings,
    TangentSettings,
    deviation_size,
    initial_deviation,
    integrate_tangent,
)
from mechanism.core.model import assemble, initial_state
from mechanism.core.scene import (
    Outputs,
    RevoluteJoint,
    RigidBody,
    RotationalSpringDamper,
    Scene,
    SolverSettings,
)

INERTIA = 0.02  # kg m², about the pin (the centre of mass)
STIFFNESS = 2.0  # N m/rad: ω₀ = 10 rad/s
THETA = 2  # index of the bar's angle in q = (x, y, θ)


def torsional_pendulum(damping: float) -> Scene:
    """The bar at rest at the spring's reference angle: the reference never moves."""
    return Scene(
        name="torsional-pendulum",
        ground_points={"O": (0.0, 0.0)},
        bodies={
            "bar": RigidBody(
                mass=1.0, inertia=INERTIA, angle=0.0, points={"O": (0.0, 0.0), "E": (0.2, 0.0)}
            )
        },
        joints={"O": RevoluteJoint(bodies=("ground", "bar"), points=("O", "O"))},
        forces={"coil": RotationalSpringDamper(joint="O", stiffness=STIFFNESS, damping=damping)},
        outputs=Outputs(crank_joint="O"),
        solver=SolverSettings(rtol=1e-10, atol=1e-10),
    )


def exact_log_growth(damping: float, d0: np.ndarray, t: np.ndarray, tau: float) -> np.ndarray:
    """ln(|d(t)|/|d0|) of the closed-form flow, in the norm √(δθ² + τ²δθ̇²) (the
    mass-weighted norm up to a constant factor: the pin holds the centre of mass)."""
    n = d0.size // 2
    a = np.array([[0.0, 1.0], [-STIFFNESS / INERTIA, -damping / INERTIA]])
    z0 = np.array([d0[THETA], d0[n + THETA]])
    norm = np.array([1.0, tau])
    sizes = [np.linalg.norm(norm * (scipy.linalg.expm(a * ti) @ z0)) for ti in t]
    return np.log(np.array(sizes) / np.linalg.norm(norm * z0))


def run(damping: float, scheme: str, *, max_step: float, t: np.ndarray, tau: float, **kw):
    model = assemble(torsional_pendulum(damping))
    y0 = np.concatenate(initial_state(model))
    d0 = initial_deviation(model, y0, t0=0.0, size=1e-9, time_scale=tau, seed=1)
    steps = StepSettings(rtol=1e-10, atol=1e-10, max_step=max_step)
    settings = TangentSettings(steps=steps, time_scale=tau, deviation_scheme=scheme, **kw)
    return d0, integrate_tangent(model, y0, d0, t, settings=settings)


def test_damped_oscillator_growth_matches_the_closed_form() -> None:
    """σ = c/2J = 1 1/s, ω₀ = 10 rad/s, τ = 1/ω₀, steps of 2e-5 s (the update is second
    order: its error grows as (hω₀)² per radian): the log growth at every stop within
    1e-6 of the closed form, so the exponent over 2 s (−1 1/s up to the norm's
    oscillation) within 1e-6."""
    damping, tau = 0.04, 0.1
    t = np.linspace(0.0, 2.0, 9)
    d0, result = run(damping, "rosenbrock", max_step=2e-5, t=t, tau=tau)
    assert result.stats.success
    exact = exact_log_growth(damping, d0, t, tau)
    np.testing.assert_allclose(result.log_growth, exact, rtol=0, atol=1e-6)
    assert abs(exact[-1] / 2.0 + 1.0) < 0.06  # the closed form: −σ up to the norm's swing


def test_stiff_linear_system_on_large_steps() -> None:
    """Overdamped, c = 200 N m s/rad: roots −0.0100000 and −9999.99 1/s. On steps of
    1e-2 s (h·λ_fast = −100) the implicit update gives the slow root's growth from 1 s to
    5 s within 4e-6 (the exponent within 1e-6). The explicit deviation on the same steps
    grows (the method's amplification of the fast root), and with its own error control
    it takes over 20 times the steps."""
    damping, tau = 200.0, 0.1
    slow = (-damping + math.sqrt(damping**2 - 4.0 * STIFFNESS * INERTIA)) / (2.0 * INERTIA)
    t = np.array([0.0, 1.0, 5.0])
    d0, implicit = run(damping, "rosenbrock", max_step=1e-2, t=t, tau=tau)
    exact = exact_log_growth(damping, d0, t, tau)
    growth = implicit.log_growth[2] - implicit.log_growth[1]
    assert abs(growth - (exact[2] - exact[1])) < 4e-6
    assert abs(growth / 4.0 - slow) < 1e-6
    assert implicit.stats.steps <= 510
    _, unstable = run(damping, "dopri5", max_step=1e-2, t=t, tau=tau)
    assert unstable.log_growth[2] - unstable.log_growth[1] > 1.0
    _, explicit = run(damping, "dopri5", max_step=1e-2, t=t, tau=tau, deviation_rtol=1e-4)
    assert explicit.stats.steps > 20 * implicit.stats.steps


def test_unknown_deviation_scheme_raises_one_line() -> None:
    steps = StepSettings(rtol=1e-8, atol=1e-8, max_step=1e-4)
    with pytest.raises(ValueError) as info:
        TangentSettings(steps=steps, time_scale=0.1, deviation_scheme="radau")
    assert str(info.value) == "deviation_scheme must be one of dopri5, rosenbrock; got 'radau'."
    with pytest.raises(ValueError) as info:
        mechanism.LyapunovSettings(deviation_scheme="implicit")
    assert str(info.value) == (
        "deviation_scheme must be one of dopri5, rosenbrock; got 'implicit'."
    )


def test_deviation_size_is_the_closed_form_norm() -> None:
    """The mass-weighted norm of a deviation of the pinned bar is √(J/m)·√(δθ² + τ²δθ̇²)
    (the norm the closed form above measures in)."""
    model = assemble(torsional_pendulum(0.04))
    y0 = np.concatenate(initial_state(model))
    d = initial_deviation(model, y0, t0=0.0, size=1.0, time_scale=0.1, seed=1)
    n = d.size // 2
    expected = math.sqrt(INERTIA) * math.hypot(d[THETA], 0.1 * d[n + THETA])
    assert deviation_size(model, d, time_scale=0.1) == pytest.approx(expected, rel=1e-12)


def paper_at(rpm: float) -> mechanism.Scene:
    return mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )


def test_paper_orbit_implicit_update_on_the_reference_steps_damps_too_much() -> None:
    """Rigid paper scene at 30 rpm (a stable period-1 orbit: the numbers survive a 1e-12
    change of the start), one revolution kept after one: the implicit update on the
    reference's own steps damps the deviation's nearly undamped contact oscillation and
    lies more than 10 1/s below the explicit update (measured −29.0 against −3.17 over 15
    kept revolutions); the reason it is not the default."""
    scene = paper_at(30.0)
    explicit = mechanism.lyapunov_exponent(scene, revolutions=2, discard=1)
    implicit = mechanism.lyapunov_exponent(
        scene, revolutions=2, discard=1,
        settings=mechanism.LyapunovSettings(deviation_scheme="rosenbrock", deviation_rtol=0.0),
    )  # fmt: skip
    assert -6.0 < explicit.exponent < 0.0  # the orbit: −3.1 1/s, nearer 0 in its approach
    assert implicit.exponent < explicit.exponent - 10.0
    assert implicit.settings["deviation_scheme"] == "rosenbrock"
    assert implicit.stats.steps < 1.2 * explicit.stats.steps


@pytest.mark.slow
def test_paper_orbit_implicit_update_with_error_control_agrees() -> None:
    """Rigid paper scene at 30 rpm, revolutions 6 – 8 after 5 discarded: with its error
    control (``deviation_rtol`` 1e-3) the implicit update gives the explicit update's λ₁
    within 3 % (measured −3.245 against −3.174), at about 8 times the steps."""
    scene = paper_at(30.0)
    explicit = mechanism.lyapunov_exponent(scene, revolutions=8, discard=5)
    implicit = mechanism.lyapunov_exponent(
        scene, revolutions=8, discard=5,
        settings=mechanism.LyapunovSettings(deviation_scheme="rosenbrock", deviation_rtol=1e-3),
    )  # fmt: skip
    assert implicit.exponent == pytest.approx(explicit.exponent, rel=0.03)
