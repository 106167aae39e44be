"""Figure functions: each draws on an Axes (a new one if ``ax`` is None) and returns it.

matplotlib is imported only when a function is called; nothing here calls ``show()``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from .._portraits import phase_portrait as make_portrait
from ._axes import axes_or_new, axis_label

__all__ = [
    "bifurcation",
    "divergence",
    "false_nearest_neighbors",
    "mutual_information",
    "phase_portrait",
    "poincare",
]


def phase_portrait(data: Any, *, variable: str | None = None, ax: Any = None, **kwargs: Any) -> Any:
    """Draw :math:`\\dot x` against :math:`x`.

    ``data`` is a portrait from :func:`chaoskit.phase_portrait`, or a trajectory together
    with ``variable`` (the portrait is then computed). Extra keyword arguments go to
    ``Axes.plot``.
    """
    if not (isinstance(data, xr.Dataset) and "portrait_variable" in data.attrs):
        if variable is None:
            raise ValueError("give variable= to draw the phase portrait of a trajectory.")
        data = make_portrait(data, variable=variable)
    x = data[data.attrs["portrait_variable"]]
    v = data[data.attrs["portrait_derivative"]]
    ax = axes_or_new(ax)
    style = {"lw": 0.6, "color": "C0"}
    style.update(kwargs)
    ax.plot(x.values, v.values, **style)
    ax.set_xlabel(axis_label(x, "x"))
    ax.set_ylabel(axis_label(v, "dx/dt"))
    ax.set_title(f"phase portrait ({data.attrs.get('derivative_source', '')})", fontsize=9)
    return ax


def _section_of(section: Any) -> xr.Dataset:
    found = getattr(section, "section", None)  # a Verdict carries its section points
    if found is not None:
        section = found
    if not isinstance(section, xr.Dataset) or "crossing" not in section.dims:
        raise ValueError(
            "poincare() needs a section Dataset (dimension 'crossing', from poincare_section or "
            "stroboscopic_map) or a Verdict that carries one."
        )
    return section


def poincare(
    section: Any,
    *,
    x: str | None = None,
    y: str | None = None,
    ax: Any = None,
    **kwargs: Any,
) -> Any:
    """Scatter the points of a Poincaré section or stroboscopic map.

    ``x`` and ``y`` name the plotted variables (default: the first two). With one variable
    the return map :math:`(s_n, s_{n+1})` is drawn.
    """
    sec = _section_of(section)
    names = [str(k) for k, v in sec.data_vars.items() if v.dims == ("crossing",)]
    if not names:
        raise ValueError("the section has no 1-D variable along 'crossing' to draw.")
    ax = axes_or_new(ax)
    style = {"s": 6, "color": "C3", "linewidths": 0}
    style.update(kwargs)
    xname = x or names[0]
    drawn = sec.sizes["crossing"]
    if y is None and len(names) == 1:
        vals = sec[xname].values
        drawn = max(vals.size - 1, 0)  # pairs of successive points
        ax.scatter(vals[:-1], vals[1:], **style)
        ax.set_xlabel(axis_label(sec[xname], xname) + " (n)")
        ax.set_ylabel(axis_label(sec[xname], xname) + " (n+1)")
    else:
        yname = y or next(n for n in names if n != xname)
        ax.scatter(sec[xname].values, sec[yname].values, **style)
        ax.set_xlabel(axis_label(sec[xname], xname))
        ax.set_ylabel(axis_label(sec[yname], yname))
    kind = sec.attrs.get("section_kind", "section")
    ax.set_title(f"{kind} ({drawn} point{'' if drawn == 1 else 's'} drawn)", fontsize=9)
    return ax


def divergence(result: Any, *, ax: Any = None, **kwargs: Any) -> Any:
    """Draw a Lyapunov curve with its fitted range.

    Rosenstein: mean log divergence :math:`\\langle \\ln d(k)\\rangle` over the horizon
    :math:`k\\,\\Delta t`, the fitted range shaded and the fitted line of slope
    :math:`\\lambda_1`. Wolf: the running estimate over evolution time with the averaging
    window shaded and :math:`\\lambda_1` as a horizontal line.
    """
    found = getattr(result, "rosenstein", None)  # a Verdict carries both results
    if found is not None:
        result = found
    ax = axes_or_new(ax)
    dt = float(result.dt)
    k = np.asarray(result.horizon, dtype=np.float64)
    curve = np.asarray(result.curve, dtype=np.float64)
    lo, hi = (int(v) for v in result.fit_range)
    style = {"lw": 1.0, "color": "C0"}
    style.update(kwargs)
    ax.axvspan(lo * dt, hi * dt, color="C1", alpha=0.2, label="fit range")
    mle_text = f"λ₁ = {result.mle:.4g} [{result.ci[0]:.3g}, {result.ci[1]:.3g}]"
    if result.method == "rosenstein":
        ax.plot(k * dt, curve, **style, label="⟨ln d(k)⟩")
        inside = (k >= lo) & (k <= hi) & np.isfinite(curve)
        if inside.any():
            slope = result.mle * dt  # nats per sample
            intercept = float(np.mean(curve[inside] - slope * k[inside]))
            span = np.array([lo, hi], dtype=np.float64)
            ax.plot(span * dt, intercept + slope * span, "--", color="C3", label=mle_text)
        ax.set_ylabel("mean log divergence")
    else:
        ax.plot(k * dt, curve / dt, **style, label="running estimate")
        ax.axhline(result.mle, ls="--", color="C3", label=mle_text)
        ax.set_ylabel("running λ₁ [per sample]" if dt == 1.0 else "running λ₁ [1/s]")
    what = "horizon" if result.method == "rosenstein" else "evolution time"
    ax.set_xlabel(f"{what} [samples]" if dt == 1.0 else f"{what} [s]")
    ax.set_title(f"{result.method}: m = {result.embedding_dim}, lag = {result.lag}", fontsize=9)
    ax.legend(fontsize=8)
    return ax


def mutual_information(result: Any, *, ax: Any = None, **kwargs: Any) -> Any:
    """Draw the delay curve (mutual information, or autocorrelation) and the chosen lag.

    ``result`` is a :class:`~chaoskit.DelayResult` (the chosen lag is marked), a delay
    curve with ``lags`` and ``curve``, or a Verdict (its delay result).
    """
    found = getattr(result, "delay", None)
    if found is not None:
        result = found
    ax = axes_or_new(ax)
    style = {"lw": 1.0, "marker": ".", "ms": 3, "color": "C0"}
    style.update(kwargs)
    ax.plot(result.lags, result.curve, **style)
    quantity = str(getattr(result, "quantity", "mutual_information")).replace("_", " ")
    units = getattr(result, "units", "")
    ax.set_ylabel(f"{quantity} [{units}]" if units not in ("", "1") else quantity)
    ax.set_xlabel("lag [samples]")
    lag = getattr(result, "lag", None)
    if lag is not None:
        ax.axvline(lag, ls="--", color="C3", label=f"lag = {lag}")
        ax.legend(fontsize=8)
    return ax


def false_nearest_neighbors(result: Any, *, ax: Any = None, **kwargs: Any) -> Any:
    """Draw the false-neighbour fraction (or Cao's E1) over dimension and the chosen one.

    ``result`` is a :class:`~chaoskit.DimensionResult` or a Verdict (its dimension result).
    """
    found = getattr(result, "dimension", None)
    if found is not None:
        result = found
    ax = axes_or_new(ax)
    style = {"lw": 1.0, "marker": "o", "ms": 4, "color": "C0"}
    style.update(kwargs)
    curve = np.asarray(result.curve, dtype=np.float64)
    method = str(getattr(result, "method", "fnn"))
    ax.plot(result.dims, curve, **style, label=method)
    ax.set_xlabel("embedding dimension")
    ax.set_ylabel("false nearest neighbours (fraction)" if method == "fnn" else "E1")
    ax.axvline(result.embedding_dim, ls="--", color="C3", label=f"m = {result.embedding_dim}")
    ax.legend(fontsize=8)
    return ax


def bifurcation(diagram: xr.Dataset, *, ax: Any = None, **kwargs: Any) -> Any:
    """Scatter a :func:`chaoskit.bifurcation_diagram` (points against the parameter)."""
    if not isinstance(diagram, xr.Dataset) or "diagram_parameter" not in diagram.attrs:
        raise ValueError("bifurcation() needs the Dataset returned by bifurcation_diagram.")
    p = diagram[diagram.attrs["diagram_parameter"]]
    x = diagram[diagram.attrs["diagram_variable"]]
    ax = axes_or_new(ax)
    style = {"s": 1.0, "color": "k", "linewidths": 0, "alpha": 0.6}
    style.update(kwargs)
    ax.scatter(p.values, x.values, **style)
    ax.set_xlabel(axis_label(p, "parameter"))
    ax.set_ylabel(axis_label(x, "x"))
    ax.set_title(f"{diagram.attrs.get('section_kind', '')} points", fontsize=9)
    return ax
