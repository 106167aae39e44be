"""Contact and friction laws of clearance revolute joints: names, stiffness, validation.

The compiled laws live in ``_kernels.py``; this module is the Python boundary. It turns the
names of a scene into kernel codes, computes the Hertz stiffness from the radii and the
materials, validates the parameters once (when the scene is assembled, never inside the
time loop) and warns when a law is used outside the range it was derived for.

References
----------
.. [LN90] H. M. Lankarani, P. E. Nikravesh, "A contact force model with hysteresis damping
   for impact analysis of multibody systems", J. Mech. Des. 112 (1990) 369–376.
.. [F11] P. Flores, M. Machado, M. T. Silva, J. M. Martins, "On the continuous contact force
   models for soft materials in multibody dynamics", Multibody Syst. Dyn. 25 (2011) 357–375.
.. [HG15] S. Hu, X. Guo, "A dissipative contact force model for impact analysis in
   multibody dynamics", Multibody Syst. Dyn. 35 (2015) 131–151.
.. [A02] J. A. C. Ambrósio, "Impact of rigid and flexible multibody systems: deformation
   description and contact models", in Virtual Nonlinear Multibody Systems, NATO ASI
   (2003) 57–81.
.. [J85] K. L. Johnson, Contact Mechanics, Cambridge University Press (1985), §4–5.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

from chaoskit.contract import check_choice, check_positive

from . import _kernels as contact_kernels

if TYPE_CHECKING:
    from mechanism.core.scene import ClearanceRevolute

__all__ = [
    "APPROACH_SPEEDS",
    "CONTACT_LAWS",
    "FRICTION_LAWS",
    "LOW_RESTITUTION_LIMIT",
    "STIFFNESS_FORMS",
    "ContactParameters",
    "approach_speed_code",
    "check_contact_law",
    "contact_parameters",
    "contact_stiffness",
    "effective_modulus",
    "effective_radius",
    "form_code",
    "friction_code",
    "friction_settings",
    "hertz_stiffness",
    "law_code",
]

ContactLawName = Literal["lankarani-nikravesh", "hertz", "flores", "hu-guo"]
FrictionLawName = Literal["none", "coulomb", "ambrosio"]
StiffnessForm = Literal["conformal", "sum-of-radii"]
ApproachSpeed = Literal["latched", "bounded"]

CONTACT_LAWS: dict[str, int] = {
    "lankarani-nikravesh": contact_kernels.LAW_LANKARANI_NIKRAVESH,
    "hertz": contact_kernels.LAW_HERTZ,
    "flores": contact_kernels.LAW_FLORES,
    "hu-guo": contact_kernels.LAW_HU_GUO,
}
FRICTION_LAWS: dict[str, int] = {
    "none": contact_kernels.FRICTION_NONE,
    "coulomb": contact_kernels.FRICTION_COULOMB,
    "ambrosio": contact_kernels.FRICTION_AMBROSIO,
}
STIFFNESS_FORMS: dict[str, int] = {
    "conformal": contact_kernels.FORM_CONFORMAL,
    "sum-of-radii": contact_kernels.FORM_SUM_OF_RADII,
}
#: Approach-speed rules of the damping term (``ContactLaw.approach_speed``) → the flag added
#: to the kernel law code. ``"latched"``: δ̇⁻ is the speed latched at contact entry (floored
#: at ``impact_velocity_floor``); ``"bounded"``: δ̇⁻ = max(latched, δ̇/2) while compressing.
APPROACH_SPEEDS: dict[str, int] = {
    "latched": 0,
    "bounded": contact_kernels.APPROACH_BOUNDED,
}

#: Below this restitution the Lankarani–Nikravesh law dissipates far too little (it is a
#: first-order expansion about cₑ = 1): a single impact at cₑ = 0.7 rebounds at 0.80.
LOW_RESTITUTION_LIMIT = 0.7


def law_code(name: str) -> int:
    """Kernel code of a normal contact law name.

    Parameters
    ----------
    name : {"lankarani-nikravesh", "hertz", "flores", "hu-guo"}

    Examples
    --------
    >>> law_code("flores")
    2
    """
    return CONTACT_LAWS[check_choice(name, name="contact law", choices=tuple(CONTACT_LAWS))]


def friction_code(name: str) -> int:
    """Kernel code of a friction law name (``"none"``, ``"coulomb"``, ``"ambrosio"``).

    Examples
    --------
    >>> friction_code("ambrosio")
    2
    """
    return FRICTION_LAWS[check_choice(name, name="friction law", choices=tuple(FRICTION_LAWS))]


def approach_speed_code(rule: str) -> int:
    """Kernel flag of an approach-speed rule (``"latched"`` → 0, ``"bounded"`` → 8).

    The flag is or-ed into the law code that :func:`contact_parameters` hands to the time
    loop (``ContactParameters.law_code``); see ``ContactLaw.approach_speed``.

    Examples
    --------
    >>> law_code("lankarani-nikravesh") | approach_speed_code("bounded")
    8
    """
    return APPROACH_SPEEDS[
        check_choice(rule, name="contact.approach_speed", choices=tuple(APPROACH_SPEEDS))
    ]


def form_code(form: str) -> int:
    """Kernel code of a stiffness form name (``"conformal"``, ``"sum-of-radii"``)."""
    return STIFFNESS_FORMS[
        check_choice(form, name="stiffness form", choices=tuple(STIFFNESS_FORMS))
    ]


def _material(material: Any, name: str) -> tuple[float, float]:
    youngs = check_positive(
        getattr(material, "youngs_modulus", None), name=f"{name}.youngs_modulus"
    )
    poisson = getattr(material, "poisson_ratio", None)
    try:
        poisson = float(poisson)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name}.poisson_ratio must be a real number; got {poisson!r}.") from None
    if not 0.0 <= poisson < 0.5:
        raise ValueError(f"{name}.poisson_ratio must be in [0, 0.5); got {poisson!r}.")
    return youngs, poisson


def effective_modulus(bearing_material: Any, journal_material: Any) -> float:
    """Effective modulus E* (Pa) of two elastic bodies in contact.

    1/E* = (1 − ν_b²)/E_b + (1 − ν_j²)/E_j  ([J85] §4.2).

    Parameters
    ----------
    bearing_material, journal_material : mechanism.core.scene.Material
        Anything with ``youngs_modulus`` (Pa, > 0) and ``poisson_ratio`` (in [0, 0.5)).

    Examples
    --------
    >>> from mechanism.core.scene import Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> round(effective_modulus(steel, steel) / 1e9, 3)
    113.736
    """
    eb, nb = _material(bearing_material, "bearing_material")
    ej, nj = _material(journal_material, "journal_material")
    return 1.0 / ((1.0 - nb * nb) / eb + (1.0 - nj * nj) / ej)


def _radii(bearing_radius: float, journal_radius: float) -> tuple[float, float]:
    rb = check_positive(bearing_radius, name="bearing_radius")
    rj = check_positive(journal_radius, name="journal_radius")
    if rj >= rb:
        raise ValueError(
            f"journal_radius must be smaller than bearing_radius (a journal inside a bearing); "
            f"got journal_radius={rj!r} m, bearing_radius={rb!r} m."
        )
    return rb, rj


def effective_radius(
    bearing_radius: float, journal_radius: float, form: StiffnessForm = "conformal"
) -> float:
    """Effective radius R* (m) of a journal inside a bearing.

    ``"conformal"``: R* = R_b R_j/(R_b − R_j), the internal (conforming) contact of
    [J85] §4.2. ``"sum-of-radii"``: R* = R_b R_j/(R_b + R_j), the external-contact form that
    the paper's tables imply (docs/paper-model.md §5, "Contact stiffness").

    Examples
    --------
    >>> round(effective_radius(0.010, 0.0095), 6)
    0.19
    """
    rb, rj = _radii(bearing_radius, journal_radius)
    code = form_code(form)
    return 1.0 / contact_kernels.effective_curvature(code, 1.0 / rb, 1.0 / rj)


def hertz_stiffness(
    bearing_radius: float,
    journal_radius: float,
    bearing_material: Any,
    journal_material: Any,
    form: StiffnessForm = "conformal",
) -> float:
    """Generalised stiffness K = (4/3) E* √R* (N m^-1.5) of a journal in a bearing.

    Parameters
    ----------
    bearing_radius, journal_radius : float
        Radii (m), ``journal_radius < bearing_radius``.
    bearing_material, journal_material : mechanism.core.scene.Material
        Young's modulus (Pa) and Poisson ratio of each part.
    form : {"conformal", "sum-of-radii"}
        Which R* to use, see ``effective_radius``. ``"conformal"`` is the standard
        internal-contact form [LN90]; ``"sum-of-radii"`` reproduces the paper's tables
        (K ≈ 1.31e10 N m^-1.5 for R_b = 15 mm, c = 0.2 mm).

    Returns
    -------
    float
        K in N m^-1.5 (the exponent 1.5 of the Hertz point/line-contact approximation used
        by all laws here).

    Examples
    --------
    >>> from mechanism.core.scene import Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> f"{hertz_stiffness(0.010, 0.0095, steel, steel, 'conformal'):.4e}"
    '6.6102e+10'
    >>> f"{hertz_stiffness(0.015, 0.0148, steel, steel, 'sum-of-radii'):.3e}"
    '1.309e+10'
    """
    e_star = effective_modulus(bearing_material, journal_material)
    return 4.0 / 3.0 * e_star * math.sqrt(effective_radius(bearing_radius, journal_radius, form))


def _restitution(restitution: Any, law: str) -> float:
    try:
        ce = float(restitution)
    except (TypeError, ValueError):
        raise ValueError(f"restitution must be a real number; got {restitution!r}.") from None
    low_open = law in ("flores", "hu-guo")  # their damping factor divides by cₑ
    if not (0.0 < ce <= 1.0 if low_open else 0.0 <= ce <= 1.0):
        bound = "(0, 1]" if low_open else "[0, 1]"
        raise ValueError(f"restitution must be in {bound} for the {law!r} law; got {ce!r}.")
    return ce


def check_contact_law(law: str, restitution: float, *, stacklevel: int = 2) -> None:
    """Validate a (law, restitution) pair and warn where the law is not accurate.

    The Lankarani–Nikravesh damping is derived for cₑ near 1; below
    :data:`LOW_RESTITUTION_LIMIT` (0.7) it overestimates the rebound (cₑ = 0.3 rebounds at
    0.68). Use ``"hu-guo"`` (rebound within 0.015 of cₑ down to 0.5, 0.03 at 0.3) or
    ``"flores"`` there.

    Raises
    ------
    ValueError
        For an unknown law or a restitution outside [0, 1] ((0, 1] for Flores and Hu–Guo).

    Warns
    -----
    UserWarning
        Lankarani–Nikravesh with cₑ < 0.7.
    """
    law_code(law)
    ce = _restitution(restitution, law)
    if law == "lankarani-nikravesh" and ce < LOW_RESTITUTION_LIMIT:
        warnings.warn(
            f"The Lankarani-Nikravesh law is derived for restitution near 1; with "
            f"restitution={ce:g} (< {LOW_RESTITUTION_LIMIT}) it dissipates too little energy "
            f"per impact. Use contact law 'hu-guo' (or 'flores') for low restitution.",
            UserWarning,
            stacklevel=stacklevel + 1,
        )


def contact_stiffness(joint: ClearanceRevolute) -> float:
    """Stiffness K (N m^-n) of a clearance joint as its scene describes it.

    ``joint.contact.stiffness`` is either a number (used as given) or a form name, in which
    case K = (4/3) E* √R* from the radii and materials (:func:`hertz_stiffness`). Validates
    the joint's contact law and restitution (see ``check_contact_law``, which may warn).

    Examples
    --------
    >>> from mechanism.core.scene import ClearanceRevolute, ContactLaw, Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> joint = ClearanceRevolute(bearing=("ground", "C"), journal=("rod3", "C"),
    ...     bearing_radius=0.015, clearance=2e-4, length=0.011, bearing_material=steel,
    ...     journal_material=steel, contact=ContactLaw(stiffness="sum-of-radii"))
    >>> f"{contact_stiffness(joint):.3e}"
    '1.309e+10'
    """
    contact = joint.contact
    check_contact_law(contact.law, joint.restitution, stacklevel=2)
    stiffness = contact.stiffness
    if isinstance(stiffness, str):
        return hertz_stiffness(
            joint.bearing_radius,
            joint.journal_radius,
            joint.bearing_material,
            joint.journal_material,
            stiffness,
        )
    return check_positive(stiffness, name="contact.stiffness")


@dataclass(frozen=True, kw_only=True)
class ContactParameters:
    """Everything the time loop needs about one clearance joint's contact, resolved once.

    Attributes
    ----------
    law, friction : str
        Law names; ``law_code`` and ``friction_code`` are their kernel codes. ``law_code``
        carries the approach-speed flag (``law_code & contact_kernels.LAW_MASK`` is the law itself).
    approach_speed : {"latched", "bounded"}
        Rule for the approach speed δ̇⁻ that divides the damping term (see
        ``mechanism.core.scene.ContactLaw``).
    stiffness : float
        K, N m^-n.
    form : str or None
        Stiffness form the radii were combined with; ``None`` when K was given as a number.
    stiffness_form_code : int
        Kernel code of ``form`` (for worn-profile local stiffness); the sum-of-radii code
        when ``form`` is ``None`` is never used because K is then not recomputed.
    exponent, restitution, impact_velocity_floor : float
        n, cₑ and the floor of the latched approach speed (m/s).
    friction_coefficient, v0, v1 : float
        μ and the friction velocity thresholds (m/s).
    effective_modulus : float
        E*, Pa.
    effective_radius : float
        R* (m) consistent with K: from the radii for a named form, else (3K/(4E*))², so the
        Hertz half-width of the wear model uses the same R* as the force law
        (docs/paper-model.md, "Contact stiffness").
    """

    law: str
    law_code: int
    approach_speed: str
    stiffness: float
    form: str | None
    stiffness_form_code: int
    exponent: float
    restitution: float
    impact_velocity_floor: float
    friction: str
    friction_code: int
    friction_coefficient: float
    v0: float
    v1: float
    effective_modulus: float
    effective_radius: float


def friction_settings(friction: Any) -> tuple[str, float, float, float]:
    """(law, μ, v0, v1) of a clearance joint's friction table, checked."""
    name = friction.law
    friction_code(name)
    mu = check_positive(friction.coefficient, name="friction.coefficient", allow_zero=True)
    v0 = check_positive(friction.v0, name="friction.v0", allow_zero=name != "coulomb")
    v1 = check_positive(friction.v1, name="friction.v1")
    if name == "ambrosio" and not v1 > v0:
        raise ValueError(
            f"friction.v1 must be larger than friction.v0 for the Ambrosio law; "
            f"got v0={v0!r} m/s, v1={v1!r} m/s."
        )
    return name, mu, v0, v1


def _check_geometry(joint: ClearanceRevolute) -> None:
    rb = check_positive(joint.bearing_radius, name="bearing_radius")
    c = check_positive(joint.clearance, name="clearance")
    if c >= rb:
        raise ValueError(
            f"clearance must be smaller than bearing_radius; got clearance={c!r} m, "
            f"bearing_radius={rb!r} m."
        )
    check_positive(joint.length, name="length")


def contact_parameters(joint: ClearanceRevolute) -> ContactParameters:
    """Validate a clearance joint's contact and friction settings and resolve them.

    Call once per joint when the scene is assembled; the result holds plain floats and
    kernel codes for the time loop.

    Examples
    --------
    >>> from mechanism.core.scene import ClearanceRevolute, Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> joint = ClearanceRevolute(bearing=("ground", "C"), journal=("rod3", "C"),
    ...     bearing_radius=0.010, clearance=5e-4, length=0.04, bearing_material=steel,
    ...     journal_material=steel)
    >>> p = contact_parameters(joint)
    >>> p.law_code & 7, p.approach_speed, f"{p.stiffness:.4e}", round(p.effective_radius, 6)
    (0, 'latched', '6.6102e+10', 0.19)
    """
    _check_geometry(joint)
    contact = joint.contact
    stiffness = contact_stiffness(joint)
    exponent = check_positive(contact.exponent, name="contact.exponent")
    floor = check_positive(contact.impact_velocity_floor, name="contact.impact_velocity_floor")
    rule = contact.approach_speed
    flag = approach_speed_code(rule)
    e_star = effective_modulus(joint.bearing_material, joint.journal_material)
    if isinstance(contact.stiffness, str):
        form: str | None = contact.stiffness
        r_star = effective_radius(joint.bearing_radius, joint.journal_radius, contact.stiffness)
        code = form_code(contact.stiffness)
    else:
        form = None
        r_star = (3.0 * stiffness / (4.0 * e_star)) ** 2
        code = contact_kernels.FORM_SUM_OF_RADII
    name, mu, v0, v1 = friction_settings(joint.friction)
    return ContactParameters(
        law=contact.law,
        law_code=law_code(contact.law) | flag,
        approach_speed=rule,
        stiffness=stiffness,
        form=form,
        stiffness_form_code=code,
        exponent=exponent,
        restitution=float(joint.restitution),
        impact_velocity_floor=floor,
        friction=name,
        friction_code=friction_code(name),
        friction_coefficient=mu,
        v0=v0,
        v1=v1,
        effective_modulus=e_star,
        effective_radius=r_star,
    )
