"""Contact and friction settings of a translational clearance joint, resolved once.

A corner of the slider against a flat guide surface is the contact of a rounded corner
(radius r) with a half-space: the Hertz point contact of a sphere of radius r on a plane,
K = (4/3) E* √r ([J85] §4.2), when ``contact.stiffness`` names a form (a flat surface has
no curvature, so the conformal and the sum-of-radii forms agree); a numeric stiffness is
used as given. The normal force and friction laws are those of the revolute clearance joint
(``_laws.py``, ``_kernels.py``).

References
----------
.. [J85] K. L. Johnson, Contact Mechanics, Cambridge University Press (1985), §4.2.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from chaoskit.contract import check_positive

from . import _kernels as contact_kernels
from ._laws import (
    ContactParameters,
    approach_speed_code,
    check_contact_law,
    effective_modulus,
    friction_code,
    friction_settings,
    law_code,
)

if TYPE_CHECKING:
    from mechanism.core.scene import ClearancePrismatic

__all__ = ["corner_stiffness", "guide_contact_parameters"]


def corner_stiffness(
    corner_radius: float, guide_material: object, slider_material: object
) -> float:
    """Hertz stiffness K = (4/3) E* √r (N m^-1.5) of a rounded slider corner on a flat guide.

    Parameters
    ----------
    corner_radius : float
        Radius r of the corner's rounding (m, > 0).
    guide_material, slider_material : mechanism.core.scene.Material
        Young's modulus (Pa) and Poisson ratio of each part.

    Examples
    --------
    >>> from mechanism.core.scene import Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> f"{corner_stiffness(0.001, steel, steel):.4e}"
    '4.7955e+09'
    """
    radius = check_positive(corner_radius, name="corner_radius")
    e_star = effective_modulus(guide_material, slider_material)
    return 4.0 / 3.0 * e_star * math.sqrt(radius)


def guide_contact_parameters(joint: ClearancePrismatic) -> ContactParameters:
    """Validate a translational clearance joint's contact and friction settings and
    resolve them for the time loop (one set shared by its four corners).

    ``effective_radius`` is the corner radius (or, for a numeric stiffness, the radius
    (3K/(4E*))² that gives K); ``form`` is ``None`` for a numeric stiffness.

    Examples
    --------
    >>> from mechanism.core.scene import ClearancePrismatic, Material
    >>> steel = Material(youngs_modulus=207e9, poisson_ratio=0.3)
    >>> joint = ClearancePrismatic(guide=("ground", "O"), slider=("slider", "P"),
    ...     slider_length=0.1, slider_width=0.05, clearance=1e-3, corner_radius=1e-3,
    ...     guide_material=steel, slider_material=steel)
    >>> p = guide_contact_parameters(joint)
    >>> f"{p.stiffness:.4e}", p.effective_radius
    ('4.7955e+09', 0.001)
    """
    contact = joint.contact
    check_contact_law(contact.law, joint.restitution, stacklevel=2)
    check_positive(joint.clearance, name="clearance")
    e_star = effective_modulus(joint.guide_material, joint.slider_material)
    if isinstance(contact.stiffness, str):
        if joint.corner_radius is None:
            raise ValueError(
                f"corner_radius is required with contact.stiffness = {contact.stiffness!r}; "
                "give it, or the stiffness as a number."
            )
        form: str | None = contact.stiffness
        r_star = check_positive(joint.corner_radius, name="corner_radius")
        stiffness = corner_stiffness(r_star, joint.guide_material, joint.slider_material)
    else:
        form = None
        stiffness = check_positive(contact.stiffness, name="contact.stiffness")
        r_star = (3.0 * stiffness / (4.0 * e_star)) ** 2
    name, mu, v0, v1 = friction_settings(joint.friction)
    return ContactParameters(
        law=contact.law,
        law_code=law_code(contact.law) | approach_speed_code(contact.approach_speed),
        approach_speed=contact.approach_speed,
        stiffness=stiffness,
        form=form,
        stiffness_form_code=contact_kernels.FORM_SUM_OF_RADII,
        exponent=check_positive(contact.exponent, name="contact.exponent"),
        restitution=float(joint.restitution),
        impact_velocity_floor=check_positive(
            contact.impact_velocity_floor, name="contact.impact_velocity_floor"
        ),
        friction=name,
        friction_code=friction_code(name),
        friction_coefficient=mu,
        v0=v0,
        v1=v1,
        effective_modulus=e_star,
        effective_radius=r_star,
    )
