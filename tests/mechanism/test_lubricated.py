"""Lubricated revolute clearance joint: the short-bearing film force and its use in scenes.

The compiled force is checked against the Reynolds pressure of a short bearing integrated
numerically over the π-film, against its closed-form limits (pure squeeze, pure rotation,
half-speed whirl) and for dissipation; a rotor whirling under a rotating load settles at
the eccentricity of the Ocvirk load relation; scenes validate the keys.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import mechanism
from mechanism.core.contact import film_factor, positive_film_force, short_bearing_force
from mechanism.core.scene import Scene, SceneError, scene_from_dict, scene_from_toml
from mechanism.core.wear import run_wear
from tests.mechanism.scenes import rigid_paper

MU, R, L, C = 0.04, 0.015, 0.011, 2.0e-4  # Pa s, m, m, m
K = MU * R * L**3 / (2.0 * C * C)  # N s, the scale of the short-bearing force


def _reynolds_force(
    eps: float, eps_dot: float, w: float, *, positive: bool = False
) -> tuple[float, float]:
    """(F_r, F_t) from the short-bearing Reynolds pressure integrated numerically over the
    Pinkus–Sternlicht π-film: ψ from the thinnest film in the sense of rotation, the film
    over ψ in (−π, 0), from the thickest film to the thinnest; with ``positive``, over the
    whole circumference with the negative pressures set to 0, split at the two angles
    where the pressure vanishes."""

    def line_load(psi: float) -> float:  # ∫ p dz over the bearing length
        return (
            MU * L**3 / (2.0 * C * C)
            * (2.0 * eps_dot * math.cos(psi) - w * eps * math.sin(psi))
            / (1.0 - eps * math.cos(psi)) ** 3
        )  # fmt: skip

    opts = {"epsabs": 1e-14, "epsrel": 1e-13, "limit": 200}  # forces of 0.1 to 20 N
    if not positive:
        f_r = -R * quad(lambda p: line_load(p) * math.cos(p), -math.pi, 0.0, **opts)[0]
        f_t = -R * quad(lambda p: line_load(p) * math.sin(p), -math.pi, 0.0, **opts)[0]
        return f_r, f_t
    # 2ε̇ cos ψ − εW sin ψ = ρ cos(ψ + α) vanishes at ψ = −α ± π/2
    alpha = math.atan2(eps * w, 2.0 * eps_dot)
    lo = -alpha - math.pi / 2.0
    opts["epsabs"] = 1e-11  # a symmetric film's F_t is 0: no relative accuracy to reach
    f_r = -R * quad(lambda p: line_load(p) * math.cos(p), lo, lo + math.pi, **opts)[0]
    f_t = -R * quad(lambda p: line_load(p) * math.sin(p), lo, lo + math.pi, **opts)[0]
    return f_r, f_t


@pytest.mark.parametrize(
    ("eps", "eps_dot", "w"),
    [(0.3, 5.0, 20.0), (0.8, -3.0, 50.0), (0.6, 2.0, -30.0), (0.95, 0.0, 10.0), (0.5, 7.0, 0.0)],
)
def test_film_force_is_the_integrated_short_bearing_pressure(eps, eps_dot, w) -> None:
    f_r, f_t = short_bearing_force(MU, R, L, C, eps, eps_dot, eps * w)
    ref_r, ref_t = _reynolds_force(eps, eps_dot, w)
    assert f_r == pytest.approx(ref_r, rel=1e-9)
    assert f_t == pytest.approx(ref_t, rel=1e-9, abs=1e-12 * abs(ref_r))


@pytest.mark.parametrize(
    ("eps", "eps_dot", "w"),
    [
        (0.3, 5.0, 20.0), (0.8, -3.0, 50.0), (0.6, 2.0, -30.0), (0.95, 0.0, 10.0),
        (0.5, 7.0, 0.0), (0.5, -7.0, 0.0), (0.7, 0.0, -40.0), (0.99, 0.4, 3.0),
    ],
)  # fmt: skip
def test_positive_pressure_film_is_the_integrated_positive_pressure(eps, eps_dot, w) -> None:
    f_r, f_t = positive_film_force(MU, R, L, C, eps, eps_dot, eps * w)
    ref_r, ref_t = _reynolds_force(eps, eps_dot, w, positive=True)
    scale = math.hypot(ref_r, ref_t)
    assert f_r == pytest.approx(ref_r, rel=1e-9, abs=1e-12 * scale)
    assert f_t == pytest.approx(ref_t, rel=1e-9, abs=1e-12 * scale)
    if eps_dot == 0.0 and w >= 0.0:  # the π-film is the positive-pressure region
        assert (f_r, f_t) == pytest.approx(short_bearing_force(MU, R, L, C, eps, 0.0, eps * w),
                                           rel=1e-12)  # fmt: skip


def test_pure_squeeze_limits() -> None:
    """W = 0: F_r = −K π(1 + 2ε²) ε̇/(1 − ε²)^(5/2), F_t = 4Kεε̇/(1 − ε²)²; at ε = 0 the
    squeeze film of a short bearing, F = −π μ R L³ ė/(2c³)."""
    e_dot = 0.01  # m/s
    f_r, f_t = short_bearing_force(MU, R, L, C, 0.0, e_dot / C, 0.0)
    assert f_r == pytest.approx(-math.pi * MU * R * L**3 * e_dot / (2.0 * C**3), rel=1e-12)
    assert f_t == 0.0
    eps, eps_dot = 0.7, 30.0
    f_r, f_t = short_bearing_force(MU, R, L, C, eps, eps_dot, 0.0)
    one = 1.0 - eps * eps
    assert f_r == pytest.approx(-K * math.pi * (1 + 2 * eps * eps) * eps_dot / one**2.5, rel=1e-12)
    assert f_t == pytest.approx(4.0 * K * eps * eps_dot / one**2, rel=1e-12)


def test_pure_rotation_gives_the_ocvirk_load_and_attitude() -> None:
    """ε̇ = 0, γ̇ = 0: |F| = K ε ω √(16ε² + π²(1 − ε²))/(2(1 − ε²)²) and the attitude angle
    tan φ = π√(1 − ε²)/(4ε) between the load line and the line of centres."""
    omega = 300.0
    for eps in (0.1, 0.5, 0.9, 0.99):
        f_r, f_t = short_bearing_force(MU, R, L, C, eps, 0.0, eps * omega)
        one = 1.0 - eps * eps
        load = K * eps * omega * math.sqrt(16 * eps * eps + math.pi**2 * one) / (2 * one * one)
        assert math.hypot(f_r, f_t) == pytest.approx(load, rel=1e-12)
        assert math.atan2(f_t, -f_r) == pytest.approx(
            math.atan(math.pi * math.sqrt(one) / (4.0 * eps)), rel=1e-12
        )


def test_half_speed_whirl_carries_no_load() -> None:
    """A journal whirling at half its spin (γ̇ = ω/2, ε̇ = 0) sees W = 0: no film force."""
    eps, omega = 0.6, 400.0
    f_r, f_t = short_bearing_force(MU, R, L, C, eps, 0.0, eps * omega - 2.0 * eps * omega / 2.0)
    assert (f_r, f_t) == (0.0, 0.0)


def test_film_without_surface_rotation_only_dissipates() -> None:
    """With ω_j + ω_b = 0 the film's power F·ė = c(F_r ε̇ + F_t ε γ̇) is < 0 for every
    non-zero motion of the journal centre: the quadratic form in (ε̇, εγ̇) is negative
    definite (16ε² < π²(1 + 2ε²) for every ε)."""
    rng = np.random.default_rng(1)
    for _ in range(2000):
        eps = rng.uniform(0.0, 0.999)
        eps_dot, eps_gdot = rng.normal(0.0, 50.0, 2)
        f_r, f_t = short_bearing_force(MU, R, L, C, eps, eps_dot, -2.0 * eps_gdot)
        power = C * (f_r * eps_dot + f_t * eps_gdot)
        assert power < 0.0


def test_film_fades_linearly_to_breakdown() -> None:
    hb = 2e-6
    assert film_factor(C, hb, 1.0 - 2.5 * hb / C) == 1.0
    assert film_factor(C, hb, 0.0) == 1.0
    assert film_factor(C, hb, 1.0 - 1.5 * hb / C) == pytest.approx(0.5, rel=1e-9)
    assert film_factor(C, hb, 1.0 - 1.25 * hb / C) == pytest.approx(0.25, rel=1e-9)
    assert film_factor(C, hb, 1.0 - 0.5 * hb / C) == 0.0
    assert film_factor(C, hb, 1.2) == 0.0
    assert short_bearing_force(MU, R, L, C, 1.0, 1.0, 1.0) == (0.0, 0.0)


# --------------------------------------------------------------------------- rotating load

OMEGA = 1000.0  # rad/s, spin of the rotor
WHIRL = 250.0  # rad/s, rotation of the load
LOAD = 10.0  # N
ROTOR_MASS = 0.1  # kg


def _rotor_scene(cavitation: str = "pi-film") -> Scene:
    """A rotor on a lubricated clearance journal in a fixed bearing, spun to OMEGA by a
    torsional actuator against a damper, loaded by a force of LOAD turning at WHIRL."""
    period = 2.0 * math.pi / WHIRL
    return scene_from_dict(
        {
            "name": "lubricated-rotor",
            "gravity": [0.0, 0.0],
            "effects": {"gravity": False, "friction": False},
            "ground_points": {"O": [0.0, 0.0]},
            "bodies": {
                "rotor": {
                    "mass": ROTOR_MASS,
                    "inertia": 1e-4,
                    "position": [0.0, 0.0],
                    "angle": 0.0,
                    "points": {"O": [0.0, 0.0]},
                },
            },
            "joints": {
                "J": {
                    "type": "clearance_revolute",
                    "bearing": ["ground", "O"],
                    "journal": ["rotor", "O"],
                    "bearing_radius": R + C,
                    "clearance": C,
                    "length": L,
                    "friction": {"law": "none"},
                    "bearing_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                    "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                    "lubrication": {"viscosity": MU, "length": L, "cavitation": cavitation},
                },
            },
            "forces": {
                "spin": {
                    "type": "rotational_spring_damper",
                    "joint": "J",
                    "damping": 1e-2,
                    "actuator_torque": 1e-2 * OMEGA,
                },
                "load_x": {
                    "type": "load",
                    "body": "rotor",
                    "point": "O",
                    "force": [LOAD, 0.0],
                    "time_profile": {"type": "fourier", "period": period, "cosine": [1.0]},
                },
                "load_y": {
                    "type": "load",
                    "body": "rotor",
                    "point": "O",
                    "force": [0.0, LOAD],
                    "time_profile": {"type": "fourier", "period": period, "sine": [1.0]},
                },
            },
            "solver": {"method": "dopri5", "rtol": 1e-10, "atol": 1e-13},
        }
    )


def _ocvirk_eccentricity() -> float:
    """ε of the steady whirl: the film (ε̇ = 0, W = ω − 2Ω) and the load hold the rotor on
    its circle, |load|² = (F_r + m e Ω²)² + F_t² (F_r < 0 points to the centre)."""

    def residual(eps: float) -> float:
        f_r, f_t = short_bearing_force(MU, R, L, C, eps, 0.0, eps * (OMEGA - 2.0 * WHIRL))
        return math.hypot(f_r + ROTOR_MASS * eps * C * WHIRL**2, f_t) - LOAD

    return brentq(residual, 1e-6, 0.999, xtol=1e-15, rtol=1e-15)


@pytest.mark.parametrize("cavitation", ["pi-film", "positive-pressure"])
def test_rotating_load_settles_at_the_ocvirk_eccentricity(cavitation) -> None:
    """Both cavitation conditions give the same steady whirl: ε̇ = 0 and W > 0 there."""
    ds = mechanism.simulate(_rotor_scene(cavitation), t_end=0.4, output_step=1e-3)
    t = ds.time.values
    late = t > 0.3
    eps = np.hypot(ds.eccentricity_x.values[late, 0], ds.eccentricity_y.values[late, 0]) / C
    expected = _ocvirk_eccentricity()
    assert 0.3 < expected < 0.9
    np.testing.assert_allclose(eps, expected, rtol=1e-6)
    # the film carries the load alone: no dry contact, so no wear
    assert np.all(ds.contact_force.values == 0.0)
    wear = run_wear(_rotor_scene(), ds)["J"]
    assert wear.volume == (0.0, 0.0)
    assert not np.any(wear.depth)


# --------------------------------------------------------------------------- scenes


@pytest.mark.parametrize("cavitation", ["pi-film", "positive-pressure"])
def test_lubricated_paper_scene_simulates_and_has_an_exponent(cavitation) -> None:
    """The rigid paper scene with oil at C runs (explicit Dormand–Prince) and its
    Lyapunov exponent estimate is finite."""
    lub = {"joints.C.lubrication": {"viscosity": 0.04, "cavitation": cavitation}}
    wet = mechanism.simulate(rigid_paper(lub), revolutions=0.2, record="full")
    assert wet.attrs["solver_method"] == "dopri5"
    assert np.all(np.isfinite(wet.eccentricity_x.values))
    assert np.all(np.isfinite(wet.eccentricity_y.values))
    result = mechanism.lyapunov_exponent(rigid_paper(lub), revolutions=0.2)
    assert math.isfinite(result.exponent)


@pytest.mark.parametrize(
    ("lubrication", "message"),
    [
        (
            {"viscosity": 0.0},
            "joints.C.lubrication.viscosity: must be in [1e-06, 100] (Pa s); got 0.0",
        ),
        (
            {"viscosity": 0.04, "length": 20.0},
            "joints.C.lubrication.length: must be in [1e-06, 10] (m); got 20.0",
        ),
        (
            {"viscosity": 0.04, "film_breakdown": 1e-4},
            "joints.C.lubrication.film_breakdown: must be < clearance/2 = 0.0001 (m); got 0.0001",
        ),
    ],
)
def test_lubrication_keys_are_validated(lubrication, message) -> None:
    with pytest.raises(SceneError) as info:
        rigid_paper({"joints.C.lubrication": lubrication})
    assert message in str(info.value)


def test_a_dry_scene_has_no_film_in_its_tables() -> None:
    """Without a lubrication table the film columns are zero: the force is never called."""
    model = mechanism.core.model.assemble(rigid_paper())
    km = model.kernel
    from_kernels = mechanism.core.model.kernels
    assert np.all(km.cj_f[:, from_kernels.CF_VISC] == 0.0)
    wet = mechanism.core.model.assemble(rigid_paper({"joints.C.lubrication": {"viscosity": 0.04}}))
    row = wet.kernel.cj_f[0]
    assert row[from_kernels.CF_VISC] == 0.04
    assert row[from_kernels.CF_LUB_L] == 0.011  # the joint's length
    assert row[from_kernels.CF_FILM] == 1e-6


def test_lubrication_round_trips_through_toml() -> None:
    scene = rigid_paper({"joints.C.lubrication": {"viscosity": 0.04, "length": 0.01}})
    assert scene_from_toml(scene.to_toml()) == scene
    assert scene.joints["C"].lubrication.length == 0.01
    assert rigid_paper().joints["C"].lubrication is None
