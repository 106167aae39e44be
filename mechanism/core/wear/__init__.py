"""Archard wear of clearance revolute joints and the worn geometry it produces.

:class:`WornProfile` holds the wear depth per angular region of the bearing and journal and
gives the local clearance, smoothed curvature, effective radius and stiffness;
:func:`archard_wear` accumulates wear from a history of contact samples with exact volume
bookkeeping. The compiled per-step kernels (``mechanism.core.wear._kernels``: ``local_clearance``,
``local_stiffness``, ``archard_increment``) are called by the integrator. See
``docs/contact-and-wear.md``.
"""

from ._archard import ArchardResult, archard_wear, hertz_half_width
from ._profile import DEFAULT_RADIUS_RATIO_LIMIT, WornProfile

__all__ = [
    "DEFAULT_RADIUS_RATIO_LIMIT",
    "ArchardResult",
    "WornProfile",
    "archard_wear",
    "hertz_half_width",
]
