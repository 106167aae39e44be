"""Compiled normal-contact and friction laws of a clearance revolute joint.

Scalars in, scalars out: the integrator calls these once per contact evaluation, so they
never allocate, never raise and never validate (the Python layer in ``_laws.py`` checks
parameters once, when the scene is assembled). Law and friction selectors are the integer
codes below; ``_laws.law_code`` / ``_laws.friction_code`` map the scene names to them. A
law code may carry the flag :data:`APPROACH_BOUNDED` (``law | APPROACH_BOUNDED``), which
selects the bounded approach speed of :func:`normal_force`; ``law & LAW_MASK`` is the law.

Sign conventions (docs/paper-model.md §5): ``delta`` is the penetration |e| − c (> 0 in contact),
``delta_dot`` its rate (> 0 while penetration grows), ``tangential_velocity`` the relative
sliding speed of the journal contact point with respect to the bearing along the tangent t.
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_inner, njit_noalloc

LAW_LANKARANI_NIKRAVESH = 0
LAW_HERTZ = 1
LAW_FLORES = 2
LAW_HU_GUO = 3
LAW_MASK = 7  # the law itself; higher bits are options
# option flag: while compressing, δ̇⁻ = max(latched, δ̇/APPROACH_RATIO), so the hysteresis
# term never exceeds APPROACH_RATIO·χ̂Kδⁿ (a free impact reaches χ̂Kδⁿ at most)
APPROACH_BOUNDED = 8
# The latch is taken one step before contact and the mechanism keeps pushing, so δ̇ passes
# δ̇⁻ a little in ordinary impacts (S3: 1.2×); a ratio of 1 put the kink of the bound inside
# them (docs/contact-and-wear.md §2).
APPROACH_RATIO = 2.0

FRICTION_NONE = 0
FRICTION_COULOMB = 1
FRICTION_AMBROSIO = 2

FORM_CONFORMAL = 0
FORM_SUM_OF_RADII = 1


@njit_inner()
def hysteresis_factor(law: int, restitution: float) -> float:
    """Dimensionless factor χ̂ of F = Kδⁿ(1 + χ̂ δ̇/δ̇⁻) for each law (0 for Hertz)."""
    ce = restitution
    law = law & LAW_MASK
    if law == LAW_LANKARANI_NIKRAVESH:
        return 0.75 * (1.0 - ce * ce)
    if law == LAW_FLORES:
        return 1.6 * (1.0 - ce) / ce
    if law == LAW_HU_GUO:
        return 1.5 * (1.0 - ce) / ce
    return 0.0


@njit_inner()
def normal_force(
    law: int,
    stiffness: float,
    exponent: float,
    restitution: float,
    delta: float,
    delta_dot: float,
    impact_velocity: float,
) -> float:
    """Normal contact force (N, ≥ 0) of a Hunt–Crossley-type law.

    F = Kδⁿ [1 + χ̂(cₑ) δ̇/δ̇⁻] clamped at F ≥ 0; 0 when δ ≤ 0. A non-positive
    ``impact_velocity`` (the integrator should never pass one; it floors the latched value)
    drops the damping term instead of dividing by zero. With the :data:`APPROACH_BOUNDED`
    flag in ``law`` the approach speed while compressing is
    δ̇⁻ = max(``impact_velocity``, δ̇/:data:`APPROACH_RATIO`), which bounds the force by
    (1 + 2χ̂)Kδⁿ; a free impact never has δ̇ above its approach speed, so its force is
    unchanged.
    """
    if not delta > 0.0:  # also catches NaN penetration
        return 0.0
    elastic = stiffness * delta**exponent
    base = law & LAW_MASK
    if base == LAW_HERTZ or not impact_velocity > 0.0:
        return elastic
    speed = impact_velocity
    # A contact entered at a grazing speed and then driven in is an impact at the current rate.
    if (law & APPROACH_BOUNDED) != 0 and delta_dot > APPROACH_RATIO * speed:
        speed = delta_dot / APPROACH_RATIO
    force = elastic * (1.0 + hysteresis_factor(base, restitution) * delta_dot / speed)
    # Fast restitution can make the damping term pull; a contact only pushes.
    return force if force > 0.0 else 0.0


@njit_inner()
def contact_potential(stiffness: float, exponent: float, delta: float) -> float:
    """Elastic energy K δ^(n+1)/(n+1) (J) stored in the contact; 0 when δ ≤ 0."""
    if not delta > 0.0:
        return 0.0
    return stiffness * delta ** (exponent + 1.0) / (exponent + 1.0)


@njit_inner()
def ambrosio_factor(speed: float, v0: float, v1: float) -> float:
    """Dynamic correction c_d(|v_t|): 0 below v0, linear to 1 at v1, 1 above."""
    if speed <= v0:
        return 0.0
    if speed >= v1:
        return 1.0
    return (speed - v0) / (v1 - v0)


@njit_inner()
def friction_force(
    law: int,
    coefficient: float,
    v0: float,
    v1: float,
    normal_force: float,
    tangential_velocity: float,
) -> float:
    """Friction force (N) on the journal along the tangent t, opposing ``tangential_velocity``.

    Coulomb: F = −μ Fₙ tanh(v_t/v0) (v1 unused). Ambrósio: F = −μ c_d(|v_t|) Fₙ sgn(v_t).
    """
    if law == FRICTION_NONE or not normal_force > 0.0:
        return 0.0
    vt = tangential_velocity
    if law == FRICTION_COULOMB:
        return -coefficient * normal_force * math.tanh(vt / v0)
    if law == FRICTION_AMBROSIO:
        cd = ambrosio_factor(abs(vt), v0, v1)
        if vt > 0.0:
            return -coefficient * cd * normal_force
        if vt < 0.0:
            return coefficient * cd * normal_force
        return 0.0
    return 0.0


@njit_noalloc()
def effective_curvature(form: int, bearing_curvature: float, journal_curvature: float) -> float:
    """1/R* (1/m) of a journal (convex) inside a bearing (concave), both curvatures > 0.

    Conformal: 1/R* = 1/R_j − 1/R_b. Sum of radii: 1/R* = 1/R_j + 1/R_b.
    """
    if form == FORM_SUM_OF_RADII:
        return journal_curvature + bearing_curvature
    return journal_curvature - bearing_curvature


@njit_noalloc()
def hertz_half_width(
    normal_force: float, effective_radius: float, length: float, effective_modulus: float
) -> float:
    """Half-width a = √(4 Fₙ R*/(π L E*)) (m) of a Hertz line contact; 0 without load."""
    if not normal_force > 0.0:
        return 0.0
    return math.sqrt(4.0 * normal_force * effective_radius / (math.pi * length * effective_modulus))
