"""Contact and friction laws of clearance joints (revolute and translational).

Normal force laws (Lankarani–Nikravesh, Hertz, Flores et al. 2011, Hu–Guo 2015), the Hertz
stiffness in its conformal and sum-of-radii forms, and the Coulomb and Ambrósio friction
laws. The compiled laws (imported from here by the model and the integrators) are called in
the time loop; the functions here resolve and validate a scene's settings once. See
``docs/contact-and-wear.md``.
"""

# the settings of a translational clearance joint, for the model's tables; not public API
from ._guide import corner_stiffness, guide_contact_parameters

# compiled laws and their codes, for the model, wear and integrator kernels; not public API
from ._kernels import (
    APPROACH_BOUNDED,
    APPROACH_RATIO,
    FRICTION_AMBROSIO,
    FRICTION_NONE,
    contact_potential,
    effective_curvature,
    friction_force,
    friction_force_derivatives,
    hertz_half_width,
    normal_force,
    normal_force_derivatives,
)
from ._laws import (
    APPROACH_SPEEDS,
    CONTACT_LAWS,
    FRICTION_LAWS,
    LOW_RESTITUTION_LIMIT,
    STIFFNESS_FORMS,
    ContactParameters,
    StiffnessForm,
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

# the oil film of a lubricated revolute clearance joint, for the model; not public API
from ._lubrication import (
    film_engaged,
    film_factor,
    film_moved,
    positive_film_force,
    short_bearing_force,
)
