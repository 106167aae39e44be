"""Contact and friction laws of clearance revolute joints.

Normal force laws (Lankarani–Nikravesh, Hertz, Flores et al. 2011, Hu–Guo 2015), the Hertz
stiffness in its conformal and sum-of-radii forms, and the Coulomb and Ambrósio friction
laws. The compiled laws (``mechanism.core.contact._kernels``) are called by the integrator; the
functions here resolve and validate a scene's settings once. See ``docs/contact-and-wear.md``.
"""

from ._laws import (
    APPROACH_SPEEDS,
    CONTACT_LAWS,
    FRICTION_LAWS,
    LOW_RESTITUTION_LIMIT,
    STIFFNESS_FORMS,
    ContactParameters,
    approach_speed_code,
    check_contact_law,
    contact_parameters,
    contact_stiffness,
    effective_modulus,
    effective_radius,
    form_code,
    friction_code,
    hertz_stiffness,
    law_code,
)

# the public names are those of ``_laws``, listed once there
from ._laws import __all__ as __all__
