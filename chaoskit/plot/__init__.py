"""Figures of chaoskit results.

Every function takes ``ax=None`` (a new figure is made when it is None), returns the
:class:`matplotlib.axes.Axes` it drew on, imports matplotlib only when called and never
calls ``show()``.
"""

from __future__ import annotations

from ._figures import (
    bifurcation,
    divergence,
    false_nearest_neighbors,
    mutual_information,
    phase_portrait,
    poincare,
)
from ._report_figures import chaos_map

__all__ = [
    "bifurcation",
    "chaos_map",
    "divergence",
    "false_nearest_neighbors",
    "mutual_information",
    "phase_portrait",
    "poincare",
]

# --- measures toolbox: add imports and names below this line only ---
from ._measures import local_slopes, lyapunov_spectrum, recurrence_plot

__all__ += ["local_slopes", "lyapunov_spectrum", "recurrence_plot"]
