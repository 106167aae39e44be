"""Multi-panel figures: a grid of panels drawn by a callback, blank panels, axis labels.

Unlike the figure functions, these build or finish a whole panel grid (e.g. one panel per
state of a report). matplotlib is imported only when a figure is made.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["blank_panel", "label_axes", "panel_figure"]


def panel_figure(
    draw: Callable[[Any], None],
    *,
    nrows: int,
    ncols: int,
    panel: tuple[float, float] = (4.2, 3.4),
) -> Any:
    """A figure of ``nrows`` x ``ncols`` panels, each ``panel`` inches, drawn by ``draw``.

    Parameters
    ----------
    draw
        Called once with the 2-D array of Axes (``axes[row, col]``, always 2-D).
    nrows, ncols
        Panel grid.
    panel
        Width and height of one panel, inches.

    Returns
    -------
    matplotlib.figure.Figure
        A figure with constrained layout, not attached to pyplot (nothing to close).
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(panel[0] * ncols, panel[1] * nrows), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    draw(axes)
    return fig


def blank_panel(ax: Any, text: str) -> Any:
    """Write ``text`` in the middle of ``ax`` and drop its ticks (a panel with no data)."""
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=8, wrap=True, transform=ax.transAxes)
    ax.set_xticks([])
    ax.set_yticks([])
    return ax


def label_axes(ax: Any, xlabel: str, ylabel: str) -> Any:
    """Short axis labels and compact scientific tick labels (long names go in captions)."""
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    try:
        ax.ticklabel_format(axis="both", style="sci", scilimits=(-3, 4), useMathText=True)
    except AttributeError:  # not a plain numeric axis
        pass
    return ax
