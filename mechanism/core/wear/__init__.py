"""Archard wear of clearance revolute joints and the worn geometry it produces.

:class:`WornProfile` holds the wear depth per angular region of the bearing and journal and
gives the local clearance, smoothed curvature, effective radius and stiffness;
:func:`archard_wear` accumulates wear from a history of contact samples with exact volume
bookkeeping; :func:`run_wear` applies it to a simulated run. The compiled per-step kernels
(``local_clearance``, ``local_stiffness``, ``archard_increment``) are called by the
integrator. See ``docs/contact-and-wear.md``.
"""

# the compiled per-step kernels, for the model and its assembly; not public API
from . import _kernels as kernels
from ._archard import ArchardResult, archard_wear, hertz_half_width
from ._kernels import local_clearance, local_stiffness_tabulated, surface_slope
from ._profile import DEFAULT_RADIUS_RATIO_LIMIT, WornProfile
from ._run import SURFACES, JointWear, add_run_wear, clearance_joint, run_wear, surface_angle

__all__ = [
    "DEFAULT_RADIUS_RATIO_LIMIT",
    "SURFACES",
    "ArchardResult",
    "JointWear",
    "WornProfile",
    "add_run_wear",
    "archard_wear",
    "clearance_joint",
    "hertz_half_width",
    "run_wear",
    "surface_angle",
]
