"""Compiled hydrodynamic force of a lubricated revolute clearance joint.

Short-bearing (Ocvirk) theory in the Pinkus–Sternlicht form, as used for lubricated
clearance joints by Flores et al. (2006). With e the eccentricity of the journal centre
from the bearing centre, ε = |e|/c, ε̇ its rate, γ̇ the rotation rate of the line of
centres and W = ω_j + ω_b − 2γ̇ (the surfaces' rotation rates; W is the entrainment speed
seen from the line of centres), the film force on the journal along u = e/|e| (F_r) and
along t = k × u (F_t) is::

    F_r = −K [2ε² W/(1 − ε²)² + π(1 + 2ε²) ε̇/(1 − ε²)^(5/2)]
    F_t =  K [π ε W/(2(1 − ε²)^(3/2)) + 4 ε ε̇/(1 − ε²)²],    K = μ R L³/(2c²)

Cavitation: the π-film (Gümbel) condition of Pinkus and Sternlicht, pressure over the half
of the clearance from the thickest film to the thinnest in the sense of positive W (the
converging half for W > 0) and none over the other half. The half is fixed: the formulas
are smooth in the state, and exact (the positive-pressure region) for ε̇ = 0, W ≥ 0; with
W < 0 the radial wedge term reverses sign (the film's pressure would be negative there),
as in the published form. The derivation and its limits are in
``docs/contact-and-wear.md`` ("Lubricated joints").

Film breakdown: with h = c(1 − ε) the minimum film thickness and h_b the breakdown
thickness, the film force is multiplied by clamp((h − h_b)/h_b, 0, 1): whole for
h ≥ 2h_b, none for h ≤ h_b, linear between so that the force stays continuous (the
integrators' error control would otherwise meet a jump of the largest force the film ever
carries at every breakdown). Below h_b only the dry contact law acts (once |e| > c).
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_noalloc


@njit_noalloc()
def film_factor(clearance: float, breakdown: float, eps: float) -> float:
    """Weight in [0, 1] of the film force at eccentricity ratio ``eps``: 1 while the minimum
    film thickness h = c(1 − ε) is at least 2 ``breakdown``, 0 at or below ``breakdown``,
    linear between (``breakdown`` = 0: 1 for h > 0, else 0)."""
    h = clearance * (1.0 - eps)
    if not h > breakdown:
        return 0.0
    if h >= 2.0 * breakdown:
        return 1.0
    return (h - breakdown) / breakdown


@njit_noalloc()
def short_bearing_force(
    viscosity: float,
    radius: float,
    length: float,
    clearance: float,
    eps: float,
    eps_dot: float,
    eps_w: float,
) -> tuple[float, float]:
    """Film force (F_r, F_t) (N) on the journal of a short bearing, π-film.

    ``eps`` = ε in [0, 1), ``eps_dot`` = ε̇ (1/s), ``eps_w`` = ε W (1/s) with
    W = ω_j + ω_b − 2γ̇ (passed as a product so that it stays finite at ε = 0, where the
    direction of the line of centres is undefined). F_r acts along the eccentricity
    (negative: towards the bearing centre), F_t along k × e/|e|. Returns (0, 0) for
    ε ≥ 1 or a non-finite ε.
    """
    if not (eps >= 0.0 and eps < 1.0):
        return 0.0, 0.0
    k = viscosity * radius * length**3 / (2.0 * clearance * clearance)
    one = 1.0 - eps * eps
    sq = math.sqrt(one)
    one2 = one * one
    f_r = -k * (
        2.0 * eps * eps_w / one2 + math.pi * (1.0 + 2.0 * eps * eps) * eps_dot / (one2 * sq)
    )
    f_t = k * (math.pi * eps_w / (2.0 * one * sq) + 4.0 * eps * eps_dot / one2)
    return f_r, f_t


@njit_noalloc()
def positive_film_force(
    viscosity: float,
    radius: float,
    length: float,
    clearance: float,
    eps: float,
    eps_dot: float,
    eps_w: float,
) -> tuple[float, float]:
    """Film force (F_r, F_t) (N) of a short bearing whose film is the region of positive
    pressure (Gümbel's condition with the cavitation boundaries where the pressure
    vanishes, as in Daniel, Machado & Cavalca 2016): the same arguments and directions as
    :func:`short_bearing_force`, equal to it for ε̇ = 0, W ≥ 0.

    With the Sommerfeld angle φ (1 − ε cos ψ = (1 − ε²)/(1 + ε cos φ)) the pressure
    2ε̇ cos ψ − εW sin ψ is positive on the arc cos(φ + β) > −2ε̇ε/ρ, with
    ρ cos β = 2ε̇, ρ sin β = εW√(1 − ε²), and the force integrals are trigonometric
    polynomials in φ, exact over any arc.
    """
    if not (eps >= 0.0 and eps < 1.0):
        return 0.0, 0.0
    one = 1.0 - eps * eps
    sq = math.sqrt(one)
    a = 2.0 * eps_dot
    b = eps_w * sq
    rho = math.hypot(a, b)
    if not rho > 0.0:
        return 0.0, 0.0
    beta = math.atan2(b, a)
    half = math.acos(min(1.0, max(-1.0, -a * eps / rho)))
    lo = -beta - half
    hi = -beta + half
    # ∫cos²ψ/D³ dψ = ΔP/(1 − ε²)^(5/2), ∫sinψ cosψ/D³ = ΔQ/(1 − ε²)², ∫sin²ψ/D³ = ΔS/(1 − ε²)^(3/2)
    dp = (0.5 + eps * eps) * (hi - lo) + 0.25 * (math.sin(2.0 * hi) - math.sin(2.0 * lo))
    dp += 2.0 * eps * (math.sin(hi) - math.sin(lo))
    dq = 0.5 * (math.sin(hi) ** 2 - math.sin(lo) ** 2) - eps * (math.cos(hi) - math.cos(lo))
    ds = 0.5 * (hi - lo) - 0.25 * (math.sin(2.0 * hi) - math.sin(2.0 * lo))
    k = viscosity * radius * length**3 / (2.0 * clearance * clearance)
    i_cc = dp / (one * one * sq)
    i_sc = dq / (one * one)
    i_ss = ds / (one * sq)
    f_r = -k * (a * i_cc - eps_w * i_sc)
    f_t = -k * (a * i_sc - eps_w * i_ss)
    return f_r, f_t


@njit_noalloc()
def film_engaged(viscosity: float, breakdown: float, delta: float) -> bool:
    """Whether the film of a clearance joint carries load at the contact state ``delta``
    (|e| − c, negative while the journal floats): the joint is lubricated
    (``viscosity`` > 0) and its minimum film thickness −δ is above ``breakdown``.

    The implicit integrators re-linearise such a joint at every Newton iterate, as one in
    dry contact: near the wall the film's stiffness and damping grow as (1 − ε²)^(−5/2),
    so a Jacobian taken at the start of a step is stale at its end."""
    return viscosity > 0.0 and -delta > breakdown


@njit_noalloc()
def film_moved(
    viscosity: float,
    breakdown: float,
    delta: float,
    delta_lin: float,
    angle: float,
    angle_lin: float,
    fraction: float,
) -> bool:
    """Whether a linearisation of the film force taken at (``delta_lin``, ``angle_lin``)
    no longer holds at (``delta``, ``angle``): the film is engaged at either state
    (:func:`film_engaged`) and its minimum thickness changed by more than ``fraction`` of
    the thinner one, or the line of centres turned by more than ``fraction`` rad.

    The force is linear in the rates (ε̇ and the entrainment speed) at a fixed
    eccentricity, so its derivative with respect to the velocities changes only with the
    geometry checked here."""
    if not (
        film_engaged(viscosity, breakdown, delta) or film_engaged(viscosity, breakdown, delta_lin)
    ):
        return False
    thinner = min(-delta, -delta_lin)
    return abs(delta - delta_lin) > fraction * thinner or abs(angle - angle_lin) > fraction
