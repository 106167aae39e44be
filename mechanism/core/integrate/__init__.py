"""Integrators: compiled Dormand–Prince 5(4) (default), scipy ``solve_ivp`` methods and an
implicit generalized-α method for stiff contact. Pass a name or a strategy object as
``method=`` to :func:`mechanism.simulate`."""

from ._methods import (
    METHODS,
    Dopri5,
    GeneralizedAlpha,
    Integration,
    Integrator,
    Recording,
    RecordPlan,
    ScipyIVP,
    SolverStats,
    resolve_method,
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
    "resolve_method",
]
