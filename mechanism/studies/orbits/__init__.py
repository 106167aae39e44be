"""Periodic orbits of rigid scenes through their impacts: Newton shooting on the
stroboscopic map and the orbit's Floquet multipliers (``docs/periodic-orbits.md``).

Built on :mod:`mechanism.core`'s public names (the tangent integration of the exponent),
like :func:`mechanism.lyapunov_exponent`, so it sits with the studies.
"""

from __future__ import annotations

from ._modes import ContactPhase
from ._orbit import PeriodicOrbit, periodic_orbit

__all__ = ["ContactPhase", "PeriodicOrbit", "periodic_orbit"]
