"""Periodic orbits of rigid scenes through their impacts: Newton shooting on the
stroboscopic map and the orbit's Floquet multipliers (``docs/periodic-orbits.md``).

Built on :mod:`mechanism.core`'s public names (the tangent integration of the exponent),
like :func:`mechanism.lyapunov_exponent`, so it sits with the studies.
"""

from __future__ import annotations

from ._basins import Basins, basins, plot_basins
from ._continuation import (
    BifurcationPoint,
    ContinuationBranch,
    ContinuationPoint,
    ContinuationSettings,
)
from ._maps import continue_map
from ._modes import ContactPhase
from ._orbit import PeriodicOrbit, periodic_orbit
from ._route import RouteToChaos, regular_stretches, route
from ._scene import Continuation, continuation

__all__ = [
    "Basins",
    "BifurcationPoint",
    "ContactPhase",
    "Continuation",
    "ContinuationBranch",
    "ContinuationPoint",
    "ContinuationSettings",
    "PeriodicOrbit",
    "RouteToChaos",
    "basins",
    "continuation",
    "continue_map",
    "periodic_orbit",
    "plot_basins",
    "regular_stretches",
    "route",
]
