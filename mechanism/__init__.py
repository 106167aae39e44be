"""mechanism — a planar multibody simulator for rigid-flexible mechanisms with clearance and wear.

Scenes are data (TOML); trajectories are :class:`xarray.Dataset` objects following the
chaoskit data contract (``docs/data-model.md``).
"""

from __future__ import annotations

from chaoskit._version import __version__

__all__ = ["__version__"]
