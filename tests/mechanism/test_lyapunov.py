"""Largest Lyapunov exponent of a scene (``mechanism.lyapunov_exponent``).

The smooth check compares the scene computation of a double pendulum of two uniform bars
with an independent implementation written here: its closed-form equations of motion in
the two joint angles, their variational equations (analytic Jacobian) and QR (Benettin)
renormalisation, measured in the same mass-weighted norm from the same initial deviation.
The non-smooth checks run the rigid paper scene.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate as si
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.core.integrate import initial_deviation
from mechanism.core.model import assemble, initial_state
from mechanism.core.scene import RevoluteJoint, RigidBody, Scene, SolverSettings
from tests.mechanism.scenes import rigid_paper

MASS = (1.0, 1.0)  # kg
LENGTH = (0.5, 0.5)  # m
GRAVITY = 9.81  # m s-2
# released at rest with both bars at 135° from the downward vertical: chaotic
THETA0 = (0.75 * math.pi, 0.75 * math.pi)


def double_pendulum(theta1: float, theta2: float, *, tol: float = 1e-10) -> Scene:
    """Two uniform bars, pinned to the frame and to each other, released at rest with
    angles θ₁, θ₂ from the downward vertical (bar frame x-axis along the bar)."""
    (m1, m2), (l1, l2) = MASS, LENGTH
    a1, a2 = theta1 - math.pi / 2, theta2 - math.pi / 2
    elbow = (l1 * math.cos(a1), l1 * math.sin(a1))
    return Scene(
        name="double-pendulum",
        ground_points={"O": (0.0, 0.0)},
        bodies={
            "bar1": RigidBody(
                mass=m1, inertia=m1 * l1**2 / 12, angle=a1,
                position=(0.5 * l1 * math.cos(a1), 0.5 * l1 * math.sin(a1)),
                points={"O": (-l1 / 2, 0.0), "A": (l1 / 2, 0.0)},
            ),
            "bar2": RigidBody(
                mass=m2, inertia=m2 * l2**2 / 12, angle=a2,
                position=(elbow[0] + 0.5 * l2 * math.cos(a2), elbow[1] + 0.5 * l2 * math.sin(a2)),
                points={"A": (-l2 / 2, 0.0)},
            ),
        },
        joints={
            "O": RevoluteJoint(bodies=("ground", "bar1"), points=("O", "O")),
            "A": RevoluteJoint(bodies=("bar1", "bar2"), points=("A", "A")),
        },
        solver=SolverSettings(rtol=tol, atol=tol),
    )  # fmt: skip


# --------------------------------------------------------------- independent implementation
_A = MASS[0] * LENGTH[0] ** 2 / 3 + MASS[1] * LENGTH[0] ** 2
_C = MASS[1] * LENGTH[1] ** 2 / 3
_B = 0.5 * MASS[1] * LENGTH[0] * LENGTH[1]
_K1 = (0.5 * MASS[0] + MASS[1]) * GRAVITY * LENGTH[0]
_K2 = 0.5 * MASS[1] * GRAVITY * LENGTH[1]


def _flow(_t: float, z: np.ndarray) -> np.ndarray:
    """Lagrange's equations of the two-bar pendulum and their variational equations.

    [A, B cos Δ; B cos Δ, C] θ̈ = [−B sin Δ ω₂² − K₁ sin θ₁, B sin Δ ω₁² − K₂ sin θ₂],
    Δ = θ₁ − θ₂; the tangent frame P (4 × 4) obeys Ṗ = J P with the analytic Jacobian.
    """
    t1, t2, w1, w2 = z[:4]
    delta = t1 - t2
    cd, sd = math.cos(delta), math.sin(delta)
    det = _A * _C - (_B * cd) ** 2
    r1 = -_B * sd * w2**2 - _K1 * math.sin(t1)
    r2 = _B * sd * w1**2 - _K2 * math.sin(t2)
    al1 = (_C * r1 - _B * cd * r2) / det
    al2 = (_A * r2 - _B * cd * r1) / det
    # d(r − M(θ)θ̈)/d(θ₁, θ₂, ω₁, ω₂) at fixed θ̈, then θ̈' = M⁻¹ of it
    dr = np.array(
        [
            [-_B * cd * w2**2 - _K1 * math.cos(t1) + _B * sd * al2, _B * cd * w2**2 - _B * sd * al2,
             0.0, -2.0 * _B * sd * w2],
            [_B * cd * w1**2 + _B * sd * al1, -_B * cd * w1**2 - _K2 * math.cos(t2) - _B * sd * al1,
             2.0 * _B * sd * w1, 0.0],
        ]
    )  # fmt: skip
    minv = np.array([[_C, -_B * cd], [-_B * cd, _A]]) / det
    frame = z[4:].reshape(4, 4)
    d_frame = np.empty((4, 4))
    d_frame[:2] = frame[2:]
    d_frame[2:] = minv @ dr @ frame
    return np.concatenate([[w1, w2, al1, al2], d_frame.ravel()])


def _cartesian(x: np.ndarray) -> np.ndarray:
    """(12 × 4) map of (δθ₁, δθ₂, δω₁, δω₂) to the bars' (δx, δy, δφ) and their rates."""
    t1, t2, w1, w2 = x
    (l1, l2) = LENGTH
    jac = np.array(
        [[0.5 * l1 * math.cos(t1), 0.0], [0.5 * l1 * math.sin(t1), 0.0], [1.0, 0.0],
         [l1 * math.cos(t1), 0.5 * l2 * math.cos(t2)], [l1 * math.sin(t1), 0.5 * l2 * math.sin(t2)],
         [0.0, 1.0]]
    )  # fmt: skip
    # ∂(J ω)/∂θ
    djw = np.array(
        [[-0.5 * l1 * math.sin(t1) * w1, 0.0], [0.5 * l1 * math.cos(t1) * w1, 0.0], [0.0, 0.0],
         [-l1 * math.sin(t1) * w1, -0.5 * l2 * math.sin(t2) * w2],
         [l1 * math.cos(t1) * w1, 0.5 * l2 * math.cos(t2) * w2], [0.0, 0.0]]
    )  # fmt: skip
    out = np.zeros((12, 4))
    out[:6, :2] = jac
    out[6:, :2] = djw
    out[6:, 2:] = jac
    return out


def _metric(x: np.ndarray) -> np.ndarray:
    """Gram matrix of the mass-weighted norm (τ = 1 s) in joint-angle coordinates."""
    (m1, m2), (l1, l2) = MASS, LENGTH
    w = np.array([m1, m1, m1 * l1**2 / 12, m2, m2, m2 * l2**2 / 12] * 2) / (m1 + m2)
    c = _cartesian(x)
    return c.T @ (w[:, None] * c)


def benettin_closed_form(
    theta: tuple[float, float],
    first: np.ndarray,
    t_end: float,
    *,
    interval: float = 0.25,
    tol: float = 1e-11,
) -> np.ndarray:
    """Log growth of the first tangent vector ``first`` over each ``interval`` of [0,
    t_end] (its sum over t_end is the largest exponent, 1/s): the frame [first, e₂, e₃,
    e₄] is re-orthonormalised by QR (in the mass metric) every ``interval`` s and the log
    of R₁₁ recorded."""
    frame = np.eye(4)
    frame[:, 0] = first
    x = np.array([theta[0], theta[1], 0.0, 0.0])
    chol = np.linalg.cholesky(_metric(x))
    q, r = np.linalg.qr(chol.T @ frame)
    frame = np.linalg.solve(chol.T, q * np.sign(np.diag(r)))
    z = np.concatenate([x, frame.ravel()])
    logs = []
    for t0 in np.arange(0.0, t_end - 1e-12, interval):
        sol = si.solve_ivp(_flow, (t0, t0 + interval), z, method="DOP853", rtol=tol, atol=tol)
        z = sol.y[:, -1].copy()
        chol = np.linalg.cholesky(_metric(z[:4]))
        q, r = np.linalg.qr(chol.T @ z[4:].reshape(4, 4))
        logs.append(math.log(abs(r[0, 0])))
        z[4:] = np.linalg.solve(chol.T, q * np.sign(np.diag(r))).ravel()
    return np.asarray(logs)


def joint_angle_deviation(scene: Scene) -> np.ndarray:
    """The scene's initial deviation (seed 0) as (δθ₁, δθ₂, δω₁, δω₂), unit length."""
    model = assemble(scene)
    q0, v0 = initial_state(model)
    d = initial_deviation(model, np.concatenate([q0, v0]), t0=0.0, size=1.0, time_scale=1.0)
    n = model.n_dof
    return np.array([d[2], d[5], d[n + 2], d[n + 5]])


def test_double_pendulum_matches_closed_form_variational_equations() -> None:
    """Same trajectory, same initial deviation, same norm: the two computations agree
    while their trajectories coincide (8 s, about 12 nats of growth). Measured: 1.61160
    against 1.61166 s⁻¹, 3.5e-5 apart, and 2.8e-5 – 4.6e-5 from release angles changed by
    up to 2e-12 of themselves (bound 1e-3)."""
    scene = double_pendulum(*THETA0)
    horizon = 8.0
    result = mechanism.lyapunov_exponent(
        scene, t_end=horizon, settings=mechanism.LyapunovSettings(perturbation=1e-9)
    )
    reference = benettin_closed_form(THETA0, joint_angle_deviation(scene), horizon).sum() / horizon
    assert reference > 1.0  # chaotic: ≥ 8 nats over the horizon
    np.testing.assert_allclose(result.exponent, reference, rtol=1e-3)
    assert result.drive_period is None
    assert result.settings["time_scale"] == 1.0


@pytest.mark.slow
def test_double_pendulum_converged_exponent_agrees_within_its_uncertainty() -> None:
    """1200 s runs. The two trajectories decorrelate after about 15 s (chaos amplifies the
    integrators' different errors), so the two estimates are independent time averages
    over the chaotic sea, each uncertain by about ±14 % (95 %, batch means): their
    difference is asserted within the combined 95 % interval, not within a fixed 5 %
    (measured: 1.899 [1.63, 2.17] against 2.140 s⁻¹, 11 % apart, both intervals holding
    the other estimate). The same-trajectory agreement is the test above (0.02 %)."""
    scene = double_pendulum(*THETA0, tol=1e-9)
    t_end, discard = 1200.0, 20.0
    result = mechanism.lyapunov_exponent(scene, t_end=t_end, discard=discard)
    first = joint_angle_deviation(scene)
    logs = benettin_closed_form(THETA0, first, t_end, interval=1.0, tol=1e-9)[int(discard) :]
    batches = logs[: logs.size // 10 * 10].reshape(10, -1).mean(axis=1)  # per second
    reference = float(logs.mean())
    half_reference = 2.262 * batches.std(ddof=1) / math.sqrt(10)  # t(0.975, 9)
    half_result = 0.5 * (result.ci[1] - result.ci[0])
    assert result.exponent > 1.0 and reference > 1.0  # both chaotic
    assert abs(result.exponent - reference) <= math.hypot(half_result, half_reference)
    assert half_result < 0.2 * result.exponent and half_reference < 0.2 * reference


def test_small_oscillation_is_regular() -> None:
    """A small in-phase swing (near a normal mode, quasi-periodic): the interval contains
    0 and the estimate is a few percent of the chaotic one. Measured: 0.0144 s⁻¹ (bound
    0.05), interval from −0.028, the same to 1e-10 from release angles changed by up to
    2e-12 of themselves."""
    result = mechanism.lyapunov_exponent(double_pendulum(0.2, 0.2, tol=1e-9), t_end=60.0,
                                         discard=10.0)  # fmt: skip
    assert result.ci[0] <= 0.0
    assert abs(result.exponent) < 0.05


# ------------------------------------------------------------------ rigid paper scene


def test_paper_deviation_is_linear_across_impacts() -> None:
    """1e-9 and 1e-7 of the clearance grow alike over the first revolution (its impacts
    included): the deviation stays in the linear regime. On the reference's own steps
    (``deviation_rtol=0``) the two runs share their reference trajectory. The revolution
    is chaotic: from starts whose crank angles differ by up to 2e-12 of a revolution the
    exponent ranges over 18.8 – 26.7 s⁻¹ and the contact events over 11 – 15 (bound 5),
    but the two sizes stay within 0.3 % (bound 2 %)."""
    small = deviation_is_linear(rigid_paper())
    assert small.settings["perturbation_size"] == pytest.approx(1e-9 * 2e-4)


def deviation_is_linear(scene: mechanism.Scene) -> mechanism.SceneLyapunov:
    """Assert that 1e-9 and 1e-7 of the clearance grow alike over the first revolution of
    ``scene`` on the same steps, through more than 5 contact events; the 1e-9 run."""
    small, large = (
        mechanism.lyapunov_exponent(
            scene,
            revolutions=1,
            settings=mechanism.LyapunovSettings(perturbation=eps, deviation_rtol=0.0),
        )
        for eps in (1e-9, 1e-7)
    )
    assert small.stats is not None and small.stats.contact_events > 5
    assert small.stats.steps == large.stats.steps
    np.testing.assert_allclose(large.exponent, small.exponent, rtol=0.02)
    return small


#: where the 250 rpm period-1 orbit of the rigid paper scene presses the journal of
#: joint C against its bearing at crank angle 0 (direction of its strobe, from +x)
HIGH_SPEED_CONTACT_ANGLE = math.radians(132.0)


def high_speed_on_the_wall(changes: dict | None = None) -> Scene:
    """The rigid paper scene at 250 rpm with the journal starting on the bearing's wall
    where its period-1 orbit holds it (``changes``: further dotted-key replacements)."""
    c = rigid_paper().joints["C"].clearance
    wall = (c * math.cos(HIGH_SPEED_CONTACT_ANGLE), c * math.sin(HIGH_SPEED_CONTACT_ANGLE))
    base: dict[str, object] = {"drive.speed_rpm": 250.0, "joints.C.initial_eccentricity": wall}
    return rigid_paper({**base, **(changes or {})})


def test_high_speed_period_one_orbit_has_no_positive_exponent() -> None:
    """At 250 rpm the rigid paper scene settles on a period-1 orbit with the journal in
    permanent contact (its strobe is one point to 1e-12 m): the orbit is stable, so λ₁ ≤ 0.
    The run starts with the journal on the wall where the orbit presses it, and is on
    the orbit from the first revolution. From the concentric start of the shipped scene a
    chaotic transient comes first, and its length depends on rounding: 0 to 13
    revolutions over 21 starts whose crank angles differ by multiples of 1e-12 of a
    revolution (9 of them longer than the 3 revolutions this test used to discard), so no
    fixed discard holds on every machine. Measured over revolutions 2–4: −35.37 s⁻¹,
    interval −35.49 to −35.25; −35.28 to −35.36 for starts shifted by 1e-12 to 5e-12 of
    a revolution (threshold 0.5: a margin of 35.8 s⁻¹; re-run in
    tests/mechanism/test_rounding_robustness.py). The latched impact velocity sits at its
    floor; when it settles above it (a concentric start may) it stays frozen while the
    contact lasts, a neutral direction, and λ₁ = 0.00 ± 0.04 (two runs 1e-9 m apart
    settle on period-1 orbits 0.5 µm apart). Before the deviation's latch was rescaled
    with it, its rate split into position and velocity parts and its error put in the
    step control: 781 s⁻¹ (docs/mechanism-lyapunov.md §2)."""
    result = mechanism.lyapunov_exponent(high_speed_on_the_wall(), revolutions=4, discard=1)
    # the interval contains 0 or lies below it
    assert result.ci[0] <= 0.0
    assert result.exponent < 0.5


@pytest.fixture(scope="module")
def paper_reference() -> mechanism.SceneLyapunov:
    """20 kept revolutions of the rigid paper scene at the default settings."""
    return mechanism.lyapunov_exponent(rigid_paper(), revolutions=22, discard=2)


def _agree(a: mechanism.SceneLyapunov, b: mechanism.SceneLyapunov) -> None:
    assert a.ci[0] <= b.exponent <= a.ci[1]
    assert b.ci[0] <= a.exponent <= b.ci[1]


@pytest.mark.slow
def test_paper_exponent_independent_of_perturbation_and_renormalisation(
    paper_reference: mechanism.SceneLyapunov,
) -> None:
    """1e-9 and 1e-7 of the clearance, renormalised every step or every 10 steps: each
    estimate inside the other's 95 % interval; on one reference trajectory, the same
    growth revolution by revolution from 1e-9 to 1e-5."""
    assert paper_reference.ci[0] > 0.0  # chaotic
    scene = rigid_paper()
    smaller = mechanism.lyapunov_exponent(
        scene, revolutions=22, discard=2, settings=mechanism.LyapunovSettings(perturbation=1e-9)
    )
    _agree(paper_reference, smaller)
    sparse = mechanism.lyapunov_exponent(
        scene, revolutions=22, discard=2, settings=mechanism.LyapunovSettings(renormalize_every=10)
    )
    _agree(paper_reference, sparse)
    # The linear regime, revolution by revolution. With the deviation's error in the step
    # control, round-off at different sizes flips a few accept/reject decisions and the
    # two runs follow different (chaotic) reference trajectories; on the reference's own
    # steps they share one, and must see the same growth in every revolution.
    runs = [
        mechanism.lyapunov_exponent(
            scene,
            revolutions=22,
            discard=2,
            settings=mechanism.LyapunovSettings(perturbation=eps, deviation_rtol=0.0),
        )
        for eps in (1e-9, 1e-7, 1e-5)
    ]
    assert runs[0].stats.steps == runs[1].stats.steps == runs[2].stats.steps
    np.testing.assert_allclose(
        runs[0].segment_exponent, runs[1].segment_exponent, rtol=0.05, atol=1.0
    )
    np.testing.assert_allclose(
        runs[2].segment_exponent, runs[1].segment_exponent, rtol=0.01, atol=0.5
    )


@pytest.mark.slow
def test_paper_exponent_independent_of_tolerance(paper_reference: mechanism.SceneLyapunov) -> None:
    """rtol = atol = 1e-9 against the default 1e-8: each inside the other's interval
    (measured 8.64 and 9.58 s⁻¹). At 1e-6 no runaway: the intervals overlap (measured
    4.71, 1.59 – 7.84, against 5.49 – 13.68 s⁻¹; two independent 20-revolution estimates
    of ±40 % each); before the deviation's error entered the step control 1e-6 gave
    3 900 s⁻¹ (3 300 – 4 500) against 135 at 1e-8 (docs/mechanism-lyapunov.md §3)."""
    tight = mechanism.lyapunov_exponent(
        rigid_paper(),
        revolutions=22,
        discard=2,
        settings=mechanism.LyapunovSettings(rtol=1e-9, atol=1e-9),
    )
    _agree(paper_reference, tight)
    loose = mechanism.lyapunov_exponent(
        rigid_paper(),
        revolutions=22,
        discard=2,
        settings=mechanism.LyapunovSettings(rtol=1e-6, atol=1e-6),
    )
    assert loose.ci[0] <= paper_reference.ci[1] and paper_reference.ci[0] <= loose.ci[1]


# --------------------------------------------------------------------------- errors / CLI


def test_prescribed_motion_has_no_exponent() -> None:
    with pytest.raises(ValueError, match="no degree of freedom"):
        mechanism.lyapunov_exponent(rigid_paper({"effects.clearance": False}), revolutions=1)


def test_flexible_scene_needs_generalized_alpha_without_projection() -> None:
    """A flexible scene's exponent rides on generalized-α steps (tests in
    test_lyapunov_flexible.py); an explicit method or a projection is refused clearly."""
    paper = mechanism.load_scene("paper")
    with pytest.raises(ValueError, match=r"solver\.method"):
        mechanism.lyapunov_exponent(paper.replace({"solver.method": "dopri5"}), revolutions=1)
    with pytest.raises(ValueError, match=r"solver\.projection = false"):
        mechanism.lyapunov_exponent(paper.replace({"solver.projection": True}), revolutions=1)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"revolutions": 2, "discard": 2}, "discard"),
        ({"revolutions": 2, "t_end": 1.0}, "exactly one"),
        ({"revolutions": -1}, "revolutions"),
    ],
)
def test_bad_arguments_name_the_parameter(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        mechanism.lyapunov_exponent(rigid_paper(), **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"perturbation": 0.1}, "perturbation must be in (0, 1e-4]; got 0.1."),
        ({"perturbation": 5e-4}, "perturbation must be in (0, 1e-4]; got 0.0005."),
        ({"renormalize_every": 0}, "renormalize_every"),
        ({"deviation_rtol": 0.5}, "deviation_rtol must be in [0, 0.1]; got 0.5."),
        ({"batches": 1}, "batches"),
        ({"seed": -1}, "seed"),
        ({"rtol": 0.0}, "rtol"),
        ({"max_step": -1e-3}, "max_step"),
    ],
)
def test_the_settings_name_the_bad_field(kwargs: dict, message: str) -> None:
    """The settings object checks its fields on construction, before any run."""
    with pytest.raises(ValueError) as info:
        mechanism.LyapunovSettings(**kwargs)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_the_settings_reach_the_result() -> None:
    """Every field of the settings is what the estimate records it ran with."""
    settings = mechanism.LyapunovSettings(
        perturbation=1e-8, renormalize_every=2, deviation_rtol=1e-3, batches=4, seed=5,
        rtol=1e-7, atol=1e-9, max_step=1e-3,
    )  # fmt: skip
    result = mechanism.lyapunov_exponent(
        double_pendulum(*THETA0, tol=1e-8), t_end=0.5, settings=settings
    )
    recorded = {k: result.settings[k] for k in ("perturbation", "renormalize_every",
                                                  "deviation_rtol", "seed", "rtol", "atol",
                                                  "max_step")}  # fmt: skip
    assert recorded == {"perturbation": 1e-8, "renormalize_every": 2, "deviation_rtol": 1e-3,
                        "seed": 5, "rtol": 1e-7, "atol": 1e-9, "max_step": 1e-3}  # fmt: skip
    assert result.batches == 4
    with pytest.raises(TypeError, match=r"^settings must be a mechanism\.LyapunovSettings"):
        mechanism.lyapunov_exponent(rigid_paper(), revolutions=2, settings={"seed": 1})


def test_undriven_scene_needs_t_end() -> None:
    with pytest.raises(ValueError, match="t_end"):
        mechanism.lyapunov_exponent(double_pendulum(*THETA0), revolutions=3)


def test_result_dataset_has_units_and_the_settings() -> None:
    result = mechanism.lyapunov_exponent(double_pendulum(*THETA0, tol=1e-8), t_end=2.0)
    ds = result.to_dataset()
    for name in ("running_exponent", "segment_exponent", "time"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    assert ds.sizes["time"] == 100
    assert ds.attrs["exponent"] == result.exponent
    assert ds.attrs["setting_perturbation"] == 1e-7
    assert ds.attrs["setting_deviation_rtol"] == 1e-4
    np.testing.assert_allclose(ds.running_exponent[-1], result.exponent, rtol=1e-12)
    # the running estimate is the time average of the segment exponents
    seg = result.segment_exponent
    np.testing.assert_allclose(np.mean(seg), result.exponent, rtol=1e-9)


def test_cli_bad_input_exits_2_without_traceback(tmp_path) -> None:
    runner = CliRunner()
    res = runner.invoke(
        app, ["lyapunov", "paper", "--set", "solver.method=dopri5", "--revolutions", "2"]
    )
    assert res.exit_code == 2
    assert "generalized-alpha" in res.output
    assert "Traceback" not in res.output
    res = runner.invoke(
        app,
        ["lyapunov", "paper", "--set", "effects.flexibility=false", "--revolutions", "2",
         "--perturbation", "0.5"],
    )  # fmt: skip
    assert res.exit_code == 2
    assert "perturbation" in res.output


def test_cli_prints_and_writes_the_estimate(tmp_path) -> None:
    out = tmp_path / "lyap.nc"
    res = CliRunner().invoke(
        app,
        ["lyapunov", "paper", "--set", "effects.flexibility=false", "--revolutions", "0.5",
         "--no-progress", "-o", str(out)],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "1/s" in res.output
    import xarray as xr

    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.attrs["scene"] == "paper"
        assert math.isfinite(ds.attrs["exponent"])


def test_a_decided_sign_ends_the_run_early() -> None:
    """The stable period-1 orbit at 30 rpm (λ₁ ≈ −3.17 s⁻¹, interval ±0.01): with
    ``decide_after=6`` the run of 10 revolutions ends after 6, whose interval lies below
    zero by far more than its half-width; its segments are the first four of the whole
    run, to the last bit. A look after 3 revolutions (one kept segment: no interval)
    decides nothing, so that run goes on and is the whole run exactly."""
    scene = rigid_paper({"drive.speed_rpm": 30.0})
    full = mechanism.lyapunov_exponent(scene, revolutions=10, discard=2)
    early = mechanism.lyapunov_exponent(scene, revolutions=10, discard=2, decide_after=6)
    assert full.sign_decided and full.ci[1] < 0.0
    assert early.sign_decided and early.ci[1] < 0.0
    assert early.time.size == 4 and early.settings["revolutions"] == 6.0
    assert early.settings["decide_after"] == 6.0
    np.testing.assert_array_equal(early.segment_exponent, full.segment_exponent[:4])
    assert early.stats.steps < 0.7 * full.stats.steps
    assert full.ci[0] <= early.exponent <= full.ci[1] + 0.02
    late = mechanism.lyapunov_exponent(scene, revolutions=10, discard=2, decide_after=3)
    assert late.settings["revolutions"] == 10.0
    assert late.exponent == full.exponent and late.ci == full.ci
    np.testing.assert_array_equal(late.segment_exponent, full.segment_exponent)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"revolutions": 10, "discard": 2, "decide_after": 2},
         "decide_after must lie in (discard, the run's length) = (2, 10); got 2."),
        ({"revolutions": 10, "discard": 2, "decide_after": 10.0},
         "decide_after must lie in (discard, the run's length) = (2, 10); got 10.0."),
        ({"t_end": 1.0, "decide_after": 1.5},
         "decide_after must lie in (discard, the run's length) = (0, 1); got 1.5."),
    ],
)  # fmt: skip
def test_decide_after_outside_the_run_is_refused(kwargs, message) -> None:
    with pytest.raises(ValueError) as info:
        mechanism.lyapunov_exponent(rigid_paper(), **kwargs)
    assert str(info.value) == message
