"""Normal contact laws and stiffness.

Each law is checked against its closed form, and against the restitution it actually
produces on a single impact of a point mass integrated with scipy.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from mechanism.core.contact import (
    LOW_RESTITUTION_LIMIT,
    check_contact_law,
    contact_parameters,
    contact_stiffness,
    effective_modulus,
    effective_radius,
    friction_code,
    hertz_stiffness,
    law_code,
)
from mechanism.core.contact import _kernels as k
from mechanism.core.scene import ClearanceRevolute, ContactLaw, FrictionLaw, Material

pytestmark = pytest.mark.filterwarnings("error")

STEEL = Material(youngs_modulus=207e9, poisson_ratio=0.3)
E_STAR_STEEL = 207e9 / (2.0 * (1.0 - 0.3**2))


def joint(**overrides) -> ClearanceRevolute:
    settings = dict(
        bearing=("ground", "C"),
        journal=("rod3", "C"),
        bearing_radius=0.010,
        clearance=5e-4,
        length=0.04,
        bearing_material=STEEL,
        journal_material=STEEL,
    )
    settings.update(overrides)
    return ClearanceRevolute(**settings)


# --- stiffness (S1) --------------------------------------------------------------------


def test_s1_conformal_stiffness_of_the_flores_joint() -> None:
    K = hertz_stiffness(0.010, 0.0095, STEEL, STEEL, "conformal")
    assert_allclose(K, 6.6102e10, rtol=1e-4)


def test_s1_sum_of_radii_stiffness_of_the_paper_joint() -> None:
    # R1 = 15 mm, c = 0.2 mm: paper-model §2.5 gives 1.309e10, "K ≈ 1.31e10".
    K = hertz_stiffness(0.015, 0.0148, STEEL, STEEL, "sum-of-radii")
    assert_allclose(K, 1.309e10, rtol=1e-3)
    assert_allclose(K, 1.31e10, rtol=2e-3)


@pytest.mark.parametrize(
    ("clearance", "conformal", "summed"),
    [(1e-4, 2.27e11, 1.311e10), (2e-4, 1.60e11, 1.309e10), (5e-4, 1.00e11, 1.302e10)],
)
def test_both_forms_against_the_paper_model_table(clearance, conformal, summed) -> None:
    rb, rj = 0.015, 0.015 - clearance
    assert_allclose(hertz_stiffness(rb, rj, STEEL, STEEL, "conformal"), conformal, rtol=5e-3)
    assert_allclose(hertz_stiffness(rb, rj, STEEL, STEEL, "sum-of-radii"), summed, rtol=1e-3)


def test_stiffness_is_four_thirds_e_star_sqrt_r_star_from_first_principles() -> None:
    bronze = Material(youngs_modulus=110e9, poisson_ratio=0.34)
    e_star = 1.0 / ((1 - 0.34**2) / 110e9 + (1 - 0.3**2) / 207e9)
    assert_allclose(effective_modulus(bronze, STEEL), e_star, rtol=1e-14)
    assert_allclose(effective_modulus(STEEL, STEEL), E_STAR_STEEL, rtol=1e-14)
    rb, rj = 0.02, 0.0195
    for form, r_star in (
        ("conformal", rb * rj / (rb - rj)),
        ("sum-of-radii", rb * rj / (rb + rj)),
    ):
        assert_allclose(effective_radius(rb, rj, form), r_star, rtol=1e-12)
        K = hertz_stiffness(rb, rj, bronze, STEEL, form)
        assert_allclose(K, 4.0 / 3.0 * e_star * math.sqrt(r_star), rtol=1e-12)


def test_contact_stiffness_of_a_scene_joint() -> None:
    assert_allclose(contact_stiffness(joint()), 6.6102e10, rtol=1e-4)
    summed = joint(
        bearing_radius=0.015,
        clearance=2e-4,
        length=0.011,
        contact=ContactLaw(stiffness="sum-of-radii"),
    )
    assert_allclose(contact_stiffness(summed), 1.309e10, rtol=1e-3)
    assert contact_stiffness(joint(contact=ContactLaw(stiffness=2.5e10))) == 2.5e10


def test_contact_parameters_keep_r_star_consistent_with_k() -> None:
    for contact in (
        ContactLaw(stiffness="conformal"),
        ContactLaw(stiffness="sum-of-radii"),
        ContactLaw(stiffness=3.0e10),
    ):
        p = contact_parameters(joint(contact=contact))
        assert_allclose(
            4 / 3 * p.effective_modulus * math.sqrt(p.effective_radius), p.stiffness, rtol=1e-12
        )
    p = contact_parameters(joint())
    # an approach-speed rule other than "latched" travels as a flag in the law code
    assert (p.law_code & k.LAW_MASK, p.friction_code) == (
        k.LAW_LANKARANI_NIKRAVESH,
        k.FRICTION_AMBROSIO,
    )
    assert p.form == "conformal" and p.stiffness_form_code == k.FORM_CONFORMAL


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        (dict(bearing_material=Material(youngs_modulus=-1.0, poisson_ratio=0.3)), "youngs_modulus"),
        (dict(journal_material=Material(youngs_modulus=2e11, poisson_ratio=0.5)), "poisson_ratio"),
        (dict(clearance=0.02), "clearance"),
        (dict(length=0.0), "length"),
        (dict(contact=ContactLaw(stiffness=-3.0)), "contact.stiffness"),
        (dict(contact=ContactLaw(stiffness="concave")), "stiffness form"),
        (dict(contact=ContactLaw(law="kelvin")), "contact law"),
        (dict(contact=ContactLaw(impact_velocity_floor=0.0)), "impact_velocity_floor"),
        (dict(contact=ContactLaw(approach_speed="peak")), "approach_speed"),
        (dict(restitution=1.2), "restitution"),
        (dict(restitution=0.0, contact=ContactLaw(law="flores")), "restitution"),
        (dict(friction=FrictionLaw(law="stribeck")), "friction law"),
        (dict(friction=FrictionLaw(coefficient=-0.1)), "friction.coefficient"),
        (dict(friction=FrictionLaw(law="coulomb", v0=0.0)), "friction.v0"),
        (dict(friction=FrictionLaw(law="ambrosio", v0=2e-4, v1=1e-4)), "friction.v1"),
    ],
)
def test_contact_parameters_reject_bad_settings_by_name(overrides, match) -> None:
    with pytest.raises(ValueError, match=match):
        contact_parameters(joint(**overrides))


def test_codes() -> None:
    assert [law_code(n) for n in ("lankarani-nikravesh", "hertz", "flores", "hu-guo")] == [
        k.LAW_LANKARANI_NIKRAVESH,
        k.LAW_HERTZ,
        k.LAW_FLORES,
        k.LAW_HU_GUO,
    ]
    assert [friction_code(n) for n in ("none", "coulomb", "ambrosio")] == [
        k.FRICTION_NONE,
        k.FRICTION_COULOMB,
        k.FRICTION_AMBROSIO,
    ]
    with pytest.raises(ValueError, match="contact law"):
        law_code("LN")


# --- low-restitution warning ----------------------------------------------------------


def test_lankarani_nikravesh_warns_below_its_range_and_names_the_alternative() -> None:
    with pytest.warns(UserWarning, match="hu-guo"):
        contact_parameters(joint(restitution=0.3))
    with pytest.warns(UserWarning, match="Lankarani"):
        check_contact_law("lankarani-nikravesh", LOW_RESTITUTION_LIMIT - 0.01)


def test_laws_that_hold_at_low_restitution_do_not_warn() -> None:
    # pytestmark turns any warning into an error
    for law in ("flores", "hu-guo", "hertz"):
        contact_parameters(joint(restitution=0.3, contact=ContactLaw(law=law)))
    contact_parameters(joint(restitution=LOW_RESTITUTION_LIMIT))


# --- closed forms ----------------------------------------------------------------------

K_TEST = 6.6102e10
N_TEST = 1.5


@pytest.mark.parametrize("ce", [0.3, 0.7, 0.9, 1.0])
@pytest.mark.parametrize("delta_dot", [0.3, -0.2, 0.0])
def test_each_law_matches_its_closed_form(ce, delta_dot) -> None:
    delta, v_impact = 2.3e-5, 0.45
    hertz = K_TEST * delta**N_TEST
    expected = {
        k.LAW_HERTZ: hertz,
        k.LAW_LANKARANI_NIKRAVESH: hertz * (1 + 3 * (1 - ce**2) * delta_dot / (4 * v_impact)),
        # Flores et al. 2011: D = 8(1 − cₑ)/(5cₑ) K δⁿ/δ̇⁻
        k.LAW_FLORES: hertz + 8 * (1 - ce) / (5 * ce) * hertz / v_impact * delta_dot,
        # Hu & Guo 2015: D = 3(1 − cₑ)/(2cₑ) K δⁿ/δ̇⁻
        k.LAW_HU_GUO: hertz + 3 * (1 - ce) / (2 * ce) * hertz / v_impact * delta_dot,
    }
    for law, force in expected.items():
        got = k.normal_force(law, K_TEST, N_TEST, ce, delta, delta_dot, v_impact)
        assert_allclose(got, max(force, 0.0), rtol=1e-13, err_msg=f"law {law}")


def test_forces_vanish_out_of_contact_and_never_pull() -> None:
    for law in (0, 1, 2, 3):
        assert k.normal_force(law, K_TEST, N_TEST, 0.5, 0.0, 1.0, 1.0) == 0.0
        assert k.normal_force(law, K_TEST, N_TEST, 0.5, -1e-6, -1.0, 1.0) == 0.0
        assert k.normal_force(law, K_TEST, N_TEST, 0.5, math.nan, 1.0, 1.0) == 0.0
        # fast separation: the damping term exceeds the elastic one, the force clamps at 0
        pulled = k.normal_force(law, K_TEST, N_TEST, 0.3, 1e-5, -50.0, 1.0)
        assert pulled >= 0.0
    assert k.normal_force(k.LAW_FLORES, K_TEST, N_TEST, 0.3, 1e-5, -50.0, 1.0) == 0.0


def test_non_positive_impact_velocity_drops_damping_instead_of_dividing_by_zero() -> None:
    for v in (0.0, -1.0):
        f = k.normal_force(k.LAW_LANKARANI_NIKRAVESH, K_TEST, N_TEST, 0.9, 1e-5, 0.3, v)
        assert f == K_TEST * 1e-5**N_TEST


def test_contact_potential_is_the_integral_of_the_elastic_force() -> None:
    assert k.contact_potential(K_TEST, N_TEST, -1e-6) == 0.0
    delta = 3.7e-5
    assert_allclose(
        k.contact_potential(K_TEST, N_TEST, delta), K_TEST * delta**2.5 / 2.5, rtol=1e-14
    )
    h = 1e-9
    dU = (
        k.contact_potential(K_TEST, N_TEST, delta + h)
        - k.contact_potential(K_TEST, N_TEST, delta - h)
    ) / (2 * h)
    assert_allclose(
        dU, k.normal_force(k.LAW_HERTZ, K_TEST, N_TEST, 1.0, delta, 0.0, 1.0), rtol=1e-7
    )


# --- restitution of a single impact ----------------------------------------------------

MASS = 0.5  # kg
V_IN = 0.8  # m/s


def _rebound_ratio(law: int, ce: float, stiffness: float = K_TEST) -> float:
    """Integrate one impact of a point mass and return |v_out|/v_in (energy check inside)."""

    def rhs(t, y):
        delta, rate = y
        return [rate, -k.normal_force(law, stiffness, N_TEST, ce, delta, rate, V_IN) / MASS]

    def separated(t, y):
        return y[0]

    separated.terminal = True
    separated.direction = -1
    delta_max = (5 * MASS * V_IN**2 / (4 * stiffness)) ** 0.4
    t_scale = delta_max / V_IN
    sol = solve_ivp(
        rhs,
        (0.0, 50 * t_scale),
        [0.0, V_IN],
        method="DOP853",
        rtol=1e-11,
        atol=[1e-9 * delta_max, 1e-12],
        max_step=t_scale / 50,
        events=separated,
    )
    assert sol.status == 1, "the mass did not leave the contact"
    if law == k.LAW_HERTZ:  # no dissipation: kinetic + contact energy is conserved
        energy = 0.5 * MASS * sol.y[1] ** 2 + np.array(
            [k.contact_potential(stiffness, N_TEST, d) for d in sol.y[0]]
        )
        assert_allclose(energy, 0.5 * MASS * V_IN**2, rtol=1e-8)
    return -sol.y_events[0][0][1] / V_IN


# (law, cₑ, tolerance on |v_out/v_in − cₑ|). Tolerances are what each law achieves for
# n = 1.5 (table in docs/contact-and-wear.md; ratios measured to 1e-4): L-N is a
# first-order expansion about cₑ = 1 (0.913 at cₑ = 0.9); Flores et al. 2011 and Hu–Guo
# hold over the whole range, Hu–Guo closest.
RESTITUTION_CASES = [
    (k.LAW_LANKARANI_NIKRAVESH, 0.99, 0.001),
    (k.LAW_LANKARANI_NIKRAVESH, 0.95, 0.005),
    (k.LAW_LANKARANI_NIKRAVESH, 0.9, 0.015),
    (k.LAW_FLORES, 0.9, 0.008),
    (k.LAW_FLORES, 0.7, 0.02),
    (k.LAW_FLORES, 0.5, 0.035),
    (k.LAW_FLORES, 0.3, 0.05),
    (k.LAW_HU_GUO, 0.9, 0.002),
    (k.LAW_HU_GUO, 0.7, 0.005),
    (k.LAW_HU_GUO, 0.5, 0.015),
    (k.LAW_HU_GUO, 0.3, 0.035),
]


@pytest.mark.parametrize(("law", "ce", "tol"), RESTITUTION_CASES)
def test_single_impact_rebounds_at_the_restitution_the_law_promises(law, ce, tol) -> None:
    ratio = _rebound_ratio(law, ce)
    assert abs(ratio - ce) <= tol, f"law {law}: rebound ratio {ratio:.4f} for cₑ = {ce}"


def test_hertz_impact_is_perfectly_elastic() -> None:
    assert_allclose(_rebound_ratio(k.LAW_HERTZ, 0.5), 1.0, rtol=1e-7)


def test_restitution_does_not_depend_on_stiffness() -> None:
    # the laws are scale-free: the ratio depends on cₑ and n only
    a = _rebound_ratio(k.LAW_HU_GUO, 0.6, stiffness=1e9)
    b = _rebound_ratio(k.LAW_HU_GUO, 0.6, stiffness=1e11)
    assert_allclose(a, b, rtol=1e-6)


def test_lankarani_nikravesh_is_not_valid_at_low_restitution() -> None:
    # why the warning exists: at cₑ = 0.3 L-N rebounds at ≈ 0.68, Hu–Guo at ≈ 0.27
    assert _rebound_ratio(k.LAW_LANKARANI_NIKRAVESH, 0.3) > 0.6
    assert abs(_rebound_ratio(k.LAW_HU_GUO, 0.3) - 0.3) < 0.035
