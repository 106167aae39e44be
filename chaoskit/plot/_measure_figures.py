"""Figures of the measures toolbox: local slopes of the correlation sum, recurrence plots,
Lyapunov spectra. Each draws on an Axes (a new one if ``ax`` is None) and returns it."""

from __future__ import annotations

from typing import Any

import numpy as np

from ._axes import axes_or_new

__all__ = ["local_slopes", "lyapunov_spectrum", "recurrence_plot"]


def local_slopes(result: Any, *, ax: Any = None) -> Any:
    """Local slopes d ln C / d ln r against the radius, one line per embedding dimension.

    ``result`` is a :class:`chaoskit.CorrelationDimensionResult`. The scaling region is
    shaded and D2 drawn as a dashed line, as in TISEAN's ``c2d`` plots.
    """
    ax = axes_or_new(ax)
    dims = result.embedding_dims
    cmap = __import__("matplotlib").colormaps["viridis"]
    for k, m in enumerate(dims):
        colour = cmap(k / max(1, dims.size - 1))
        ax.plot(result.radius, result.local_slope[k], color=colour, lw=1.0, label=f"m = {m}")
    ax.set_xscale("log")
    ax.axvspan(*result.scaling_range, color="0.85", zorder=0, label="scaling region")
    ax.axhline(result.d2, color="k", ls="--", lw=0.8, label=f"D2 = {result.d2:.3g}")
    top = np.nanmax(result.local_slope) if np.isfinite(result.local_slope).any() else 1.0
    ax.set_ylim(0.0, min(float(top) * 1.05, float(dims[-1]) + 1.0))
    units = result.units if result.units not in ("", "1") else ""
    ax.set_xlabel(f"radius r [{units}]" if units else "radius r")
    ax.set_ylabel("local slope d ln C / d ln r")
    ax.set_title("correlation dimension", fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    return ax


def recurrence_plot(result: Any, *, ax: Any = None, max_pixels: int = 1000) -> Any:
    """The recurrence matrix of a :class:`chaoskit.RecurrenceResult` as an image.

    Matrices wider than ``max_pixels`` are shown as the share of recurrences in each
    pixel (so long series stay legible and cheap to draw).
    """
    ax = axes_or_new(ax)
    n = result.n_points
    bins = min(n, int(max_pixels))
    coo = result.matrix.tocoo()
    image, _, _ = np.histogram2d(coo.row, coo.col, bins=bins, range=[[0, n], [0, n]])
    image /= (n / bins) ** 2
    ax.imshow(
        image,
        origin="lower",
        cmap="Greys",
        vmin=0.0,
        vmax=max(float(image.max()), 1e-12),
        extent=(0, n, 0, n),
        interpolation="nearest",
    )
    ax.set_xlabel("sample i")
    ax.set_ylabel("sample j")
    ax.set_title(
        f"recurrence plot (RR = {result.recurrence_rate:.3g}, DET = {result.determinism:.3g})",
        fontsize=9,
    )
    return ax


def lyapunov_spectrum(result: Any, *, ax: Any = None) -> Any:
    """Running estimate of every exponent of a :class:`chaoskit.LyapunovSpectrumResult`.

    Exponents the spurious-exponent check flags are drawn dashed.
    """
    ax = axes_or_new(ax)
    steps = np.arange(1, result.running.shape[0] + 1)
    for k in range(result.embedding_dim):
        style = "--" if result.spurious[k] else "-"
        label = f"λ{k + 1} = {result.exponents[k]:.3g}" + (
            " (spurious)" if result.spurious[k] else ""
        )
        ax.plot(steps, result.running[:, k], style, lw=1.0, label=label)
    ax.axhline(0.0, color="0.5", lw=0.6)
    ax.set_xscale("log")
    ax.set_xlabel("local maps accumulated")
    ax.set_ylabel("exponent (natural log per unit of dt)")
    ax.set_title("Lyapunov spectrum", fontsize=9)
    ax.legend(fontsize=7)
    return ax
