"""Figures for reports: a chaos map over a 2-D parameter grid.

Same conventions as ``_figures``: each function draws on an Axes (a new one if ``ax`` is
None), returns it, imports matplotlib only when called and never calls ``show()``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from ._axes import axis_label

__all__ = ["chaos_map"]


def _grid_labels(coord: xr.DataArray) -> list[str]:
    values = coord.values
    if values.dtype.kind in "fiu":
        return [format(float(v), ".4g") for v in values]
    return [str(v) for v in values]


def chaos_map(
    data: Any,
    *,
    mle: str | None = None,
    verdict: str | None = None,
    x: str | None = None,
    y: str | None = None,
    ax: Any = None,
    cmap: str = "RdBu_r",
    **kwargs: Any,
) -> Any:
    """Draw the largest Lyapunov exponent over a 2-D parameter grid, verdicts in the cells.

    One cell per grid point (grid values as tick labels, evenly spaced whatever their
    values), coloured by :math:`\\lambda_1` on a diverging scale centred on 0 (red: positive,
    blue: negative), with the verdict label written in each cell. Grid points without a
    value (failed runs) are left blank.

    Parameters
    ----------
    data
        A Dataset with a 2-D exponent variable and optionally a 2-D text verdict variable
        over the same two dimensions (e.g. the map of a sweep), or a 2-D DataArray of
        exponents.
    mle, verdict
        Variable names (default: ``mle`` or the first 2-D numeric variable; ``verdict`` or
        ``label`` when present).
    x, y
        The dimensions along the horizontal and vertical axes (default: the exponent's last
        and first dimension).
    ax
        Axes to draw on; a new figure when None.
    cmap
        Colormap name (diverging).
    **kwargs
        Passed to ``Axes.pcolormesh``.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> from chaoskit import plot
    >>> ds = xr.Dataset(
    ...     {"mle": (("c", "w"), np.array([[-0.5, 0.1], [0.2, 1.0]]), {"units": "s-1"}),
    ...      "verdict": (("c", "w"), np.array([["periodic", "chaotic"], ["chaotic", "chaotic"]],
    ...                                         dtype=object))},
    ...     coords={"c": [1e-4, 2e-4], "w": [30, 90]})
    >>> ax = plot.chaos_map(ds)
    >>> ax.get_xlabel()
    'w'
    """
    if isinstance(data, xr.DataArray):
        data = data.to_dataset(name=str(data.name or "mle"))
    if not isinstance(data, xr.Dataset):
        raise ValueError("chaos_map() needs a Dataset (or DataArray) of exponents over 2 dims.")
    numeric = [str(k) for k, v in data.data_vars.items() if v.ndim == 2 and v.dtype.kind in "fiu"]
    if mle is None:
        mle = "mle" if "mle" in numeric else (numeric[0] if numeric else None)
    if mle is None or mle not in data.data_vars or data[mle].ndim != 2:
        raise ValueError(f"no 2-D exponent variable {mle!r}; 2-D numeric variables: {numeric}.")
    field = data[mle]
    ydim, xdim = (str(d) for d in field.dims)
    if x is not None or y is not None:
        dims = [str(d) for d in field.dims]
        if (x is not None and x not in dims) or (y is not None and y not in dims):
            raise ValueError(f"x and y must be dimensions of {mle!r}: {dims}.")
        xdim = x if x is not None else next(d for d in dims if d != y)
        ydim = y if y is not None else next(d for d in dims if d != xdim)
        if xdim == ydim:
            raise ValueError("x and y must be two different dimensions.")
    field = field.transpose(ydim, xdim)
    if verdict is None:
        verdict = next((v for v in ("verdict", "label") if v in data.data_vars), None)
    elif verdict not in data.data_vars:
        raise ValueError(f"verdict variable {verdict!r} not found in {list(data.data_vars)}.")
    values = np.asarray(field.values, dtype=np.float64)
    finite = values[np.isfinite(values)]
    span = float(np.max(np.abs(finite))) if finite.size else 1.0
    span = span if span > 0 else 1.0
    ax = ax if ax is not None else _new_axes()
    ny, nx = values.shape
    style = {"cmap": cmap, "vmin": -span, "vmax": span, "shading": "flat"}
    style.update(kwargs)
    mesh = ax.pcolormesh(
        np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5, np.ma.masked_invalid(values), **style
    )
    ax.figure.colorbar(mesh, ax=ax, label=axis_label(field, mle))
    if verdict is not None:
        labels = np.asarray(data[verdict].transpose(ydim, xdim).values, dtype=object)
        for j in range(ny):
            for i in range(nx):
                text = "" if labels[j, i] is None else str(labels[j, i])
                if text:
                    # white on the dark ends of the colour scale, black elsewhere
                    dark = np.isfinite(values[j, i]) and abs(values[j, i]) > 0.6 * span
                    ax.text(
                        i,
                        j,
                        text.replace("-", "-\n"),
                        ha="center",
                        va="center",
                        fontsize=7,
                        color="white" if dark else "black",
                    )
    xc = data[xdim] if xdim in data.coords else xr.DataArray(np.arange(nx), dims=xdim)
    yc = data[ydim] if ydim in data.coords else xr.DataArray(np.arange(ny), dims=ydim)
    ax.set_xticks(np.arange(nx), _grid_labels(xc))
    ax.set_yticks(np.arange(ny), _grid_labels(yc))
    ax.set_xlabel(axis_label(xc, xdim) if xdim in data.coords else xdim)
    ax.set_ylabel(axis_label(yc, ydim) if ydim in data.coords else ydim)
    ax.set_title(f"{field.attrs.get('long_name', mle)}", fontsize=9)
    return ax


def _new_axes() -> Any:
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=(5.0, 4.0), layout="constrained")
    return ax
