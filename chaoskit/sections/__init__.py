"""Sections of continuous-time trajectories: Poincaré sections and stroboscopic maps."""

from __future__ import annotations

from ._poincare import poincare_section
from ._stroboscopic import stroboscopic_map

__all__ = ["poincare_section", "stroboscopic_map"]
