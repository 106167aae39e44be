"""chaoskit — decide from a trajectory whether motion is periodic, quasi-periodic or chaotic.

The public API is re-exported here; everything in ``_``-prefixed modules is private.
``chaoskit`` never imports ``mechanism``.
"""

from __future__ import annotations

from . import systems
from ._contract import sampling_interval, validate_trajectory
from ._io import load_trajectory, save_trajectory
from ._version import __version__

_foundation = [
    "__version__",
    "load_trajectory",
    "sampling_interval",
    "save_trajectory",
    "systems",
    "validate_trajectory",
]

# --- estimators (issue 3): add imports and names below this line only ---
_estimators: list[str] = []

# --- views and verdict (issue 4): add imports and names below this line only ---
_views: list[str] = []

__all__ = _foundation + _estimators + _views
