"""Figures of chaoskit results.

Every figure function takes ``ax=None`` (a new figure is made when it is None), returns the
:class:`matplotlib.axes.Axes` it drew on, imports matplotlib only when called and never
calls ``show()``. :func:`panel_figure`, :func:`blank_panel` and :func:`label_axes` build and
finish multi-panel figures (one panel per state in :func:`chaoskit.report`).
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
from ._panels import blank_panel, label_axes, panel_figure
from ._report_figures import chaos_map

__all__ = [
    "bifurcation",
    "blank_panel",
    "chaos_map",
    "divergence",
    "false_nearest_neighbors",
    "label_axes",
    "mutual_information",
    "panel_figure",
    "phase_portrait",
    "poincare",
]

# --- measures toolbox: add imports and names below this line only ---
from ._measure_figures import local_slopes, lyapunov_spectrum, recurrence_plot

__all__ += ["local_slopes", "lyapunov_spectrum", "recurrence_plot"]
