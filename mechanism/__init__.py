"""mechanism — a planar multibody simulator for rigid-flexible mechanisms with clearance and wear.

Scenes are data (TOML); trajectories are :class:`xarray.Dataset` objects following the
chaoskit data contract (``docs/data-model.md``).
"""

from __future__ import annotations

from chaoskit._version import __version__

_foundation = ["__version__"]

# --- scenes (issue 5, scene loading): add imports and names below this line only ---
_scenes: list[str] = []

# --- simulation (issue 5, core): add imports and names below this line only ---
_simulation: list[str] = []

# --- contact and wear (issues 5 and 7): add imports and names below this line only ---
_contact_wear: list[str] = []

# --- flexibility (issue 6): add imports and names below this line only ---
_flexibility: list[str] = []

__all__ = _foundation + _scenes + _simulation + _contact_wear + _flexibility
