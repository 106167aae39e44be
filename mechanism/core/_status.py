"""The one table of status codes returned by every compiled kernel of the simulator.

0 is success; positive codes are successful outcomes that say something more; negative
codes are failures. The system kernels (:mod:`mechanism.core.model._kernels`) return ``OK``,
``SINGULAR`` or ``NONFINITE``; the integrators (:mod:`mechanism.core.integrate`) add the loop
codes; the wear kernels (:mod:`mechanism.core.wear`) ``REDUCED`` and ``REJECTED``.
"""

from __future__ import annotations

__all__ = [
    "MESSAGES",
    "STATUS_MAX_STEPS",
    "STATUS_NEWTON",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_REDUCED",
    "STATUS_REJECTED",
    "STATUS_RUNNING",
    "STATUS_SINGULAR",
    "STATUS_STEP_TOO_SMALL",
]

STATUS_OK = 0
STATUS_RUNNING = 1  # an integration chunk ended before the end of the interval
STATUS_REDUCED = 2  # a wear increment was scaled down to respect the depth limits
STATUS_STEP_TOO_SMALL = -1
STATUS_SINGULAR = -2  # the constraint Jacobian (Φq M⁻¹ Φqᵀ) is singular
STATUS_NONFINITE = -3
STATUS_MAX_STEPS = -4
STATUS_NEWTON = -5
STATUS_REJECTED = -6  # a wear increment with non-finite input; nothing applied

MESSAGES: dict[int, str] = {
    STATUS_OK: "The solver reached the end of the interval.",
    STATUS_RUNNING: "running",
    STATUS_REDUCED: "The wear increment was scaled down to the depth limits.",
    STATUS_STEP_TOO_SMALL: "The step size became too small (stiffness or a discontinuity).",
    STATUS_SINGULAR: "The constraint Jacobian became singular (a locked or redundant "
    "configuration).",
    STATUS_NONFINITE: "The solution became non-finite.",
    STATUS_MAX_STEPS: "The maximum number of steps was reached.",
    STATUS_NEWTON: "Newton iterations did not converge.",
    STATUS_REJECTED: "The wear increment had non-finite input; nothing was applied.",
}
