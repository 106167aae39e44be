"""Integrators: compiled Dormand–Prince 5(4) (default), scipy ``solve_ivp`` methods and an
implicit generalized-α method for stiff contact. Pass a name or a strategy object as
``method=`` to :func:`mechanism.simulate`. :func:`integrate_tangent` advances a state and
a renormalised deviation on one step sequence (the largest Lyapunov exponent), and
:func:`integrate_tangent_flexible` does so on generalized-α steps (flexible models);
both take their step control and deviation options as one :class:`TangentSettings`.
The compiled loops return to Python every ``chunk_steps`` attempted steps, so Ctrl-C
stops a run promptly; :func:`interrupt_integrations` stops the runs of other threads."""

# the layout of what the compiled loops record (``MET_*``, ``REC_*``), for the recorder; not
# public API
from . import _step_kernels as kernels
from ._driver import interrupt_integrations
from ._interface import (
    Integration,
    Integrator,
    Recording,
    RecordPlan,
    SolverStats,
    StepSettings,
)
from ._methods import METHODS, Dopri5, GeneralizedAlpha, resolve_method
from ._scipy_ivp import ScipyIVP
from ._tangent import (
    TangentIntegration,
    TangentSettings,
    deviation_size,
    initial_deviation,
    integrate_tangent,
    length_scale,
)
from ._tangent_flexible import integrate_tangent_flexible
from ._tangent_space import (
    clearance_kinematics,
    project_state,
    section_latch,
    state_derivative,
    tangent_basis,
)

__all__ = [
    "METHODS",
    "Dopri5",
    "GeneralizedAlpha",
    "Integration",
    "Integrator",
    "RecordPlan",
    "Recording",
    "ScipyIVP",
    "SolverStats",
    "StepSettings",
    "TangentIntegration",
    "TangentSettings",
    "clearance_kinematics",
    "deviation_size",
    "initial_deviation",
    "integrate_tangent",
    "integrate_tangent_flexible",
    "interrupt_integrations",
    "length_scale",
    "project_state",
    "resolve_method",
    "section_latch",
    "state_derivative",
    "tangent_basis",
]
