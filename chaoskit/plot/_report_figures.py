"""Figures for reports: the wear profile as a polar plot and a chaos map over a 2-D grid.

Same conventions as ``_figures``: each function draws on an Axes (a new one if ``ax`` is
None), returns it, imports matplotlib only when called and never calls ``show()``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ._figures import _label

__all__ = ["chaos_map", "wear_profile"]

#: Length units drawn in micrometres (wear depths are a few µm to a few hundred µm).
_MICRO = {"m": 1e6, "mm": 1e3, "um": 1.0, "µm": 1.0}


def _profile_dataset(profile: Any) -> xr.Dataset:
    to_dataset = getattr(profile, "to_dataset", None)
    if callable(to_dataset) and not isinstance(profile, (xr.Dataset, xr.DataArray)):
        profile = to_dataset()  # e.g. a wear-profile object of the simulator
    if isinstance(profile, xr.DataArray):
        profile = profile.to_dataset(name=str(profile.name or "wear_depth"))
    if not isinstance(profile, xr.Dataset) or "angle" not in profile.dims:
        raise ValueError(
            "wear_profile() needs a Dataset or DataArray along the dimension 'angle' (rad), or "
            "an object with a to_dataset() method that returns one."
        )
    return profile


def _profile_variables(ds: xr.Dataset, variables: Sequence[str] | str | None) -> list[str]:
    along = [str(k) for k, v in ds.data_vars.items() if v.dims == ("angle",)]
    if variables is None:
        names = [n for n in along if "depth" in n] or along
    else:
        names = [variables] if isinstance(variables, str) else list(variables)
    missing = [n for n in names if n not in along]
    if missing or not names:
        raise ValueError(
            f"variables {missing or names} are not 1-D along 'angle'; available: {along}."
        )
    return names


def wear_profile(
    profile: Any,
    *,
    variables: Sequence[str] | str | None = None,
    sectors: Sequence[tuple[float, float]] | None = None,
    sector_label: str = "highlighted sectors",
    ax: Any = None,
    **kwargs: Any,
) -> Any:
    """Draw wear depth against angle on polar axes.

    The radius is the depth :math:`h(\\varphi)` of each angular region (in µm when the
    variable's ``units`` are a length), the angle :math:`\\varphi` the region centre in the
    surface's own frame, counter-clockwise from the +x axis. The curve is closed over
    :math:`2\\pi`.

    Parameters
    ----------
    profile
        A Dataset along ``angle`` (rad) — e.g. the ``to_dataset()`` of a worn profile, with
        ``wear_depth`` (bearing) and ``journal_wear_depth`` — a DataArray along ``angle``,
        or any object with a ``to_dataset()`` method returning such a Dataset.
    variables
        The depth variables to draw (default: every 1-D variable along ``angle`` whose name
        contains ``depth``, or all of them if none does).
    sectors
        Angular intervals ``(start, stop)`` in degrees to shade, e.g. the wear zones
        reported in a paper; ``stop < start`` wraps through 0°.
    sector_label
        Legend entry of the shaded sectors.
    ax
        Polar Axes to draw on (``projection="polar"``); a new figure when None.
    **kwargs
        Passed to ``Axes.plot``.

    Returns
    -------
    matplotlib.axes.Axes
        The polar Axes.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> from chaoskit import plot
    >>> phi = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    >>> depth = xr.DataArray(1e-6 * (1 + np.cos(phi) ** 2), dims="angle",
    ...                      coords={"angle": phi}, name="wear_depth",
    ...                      attrs={"units": "m", "long_name": "bearing wear depth"})
    >>> ax = plot.wear_profile(depth, sectors=[(75, 132), (252, 310)])
    >>> ax.name
    'polar'
    """
    ds = _profile_dataset(profile)
    names = _profile_variables(ds, variables)
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(
            figsize=(4.6, 4.6), layout="constrained", subplot_kw={"projection": "polar"}
        )
    elif getattr(ax, "name", "") != "polar":
        raise ValueError("wear_profile() draws on polar axes; pass ax=... with projection='polar'.")
    angle = np.asarray(ds["angle"].values, dtype=np.float64)
    order = np.argsort(np.mod(angle, 2.0 * np.pi))
    phi = np.mod(angle, 2.0 * np.pi)[order]
    phi = np.append(phi, phi[0] + 2.0 * np.pi)
    top = 0.0
    unit_text = ""
    for i, name in enumerate(names):
        var = ds[name]
        units = str(var.attrs.get("units", ""))
        scale = _MICRO.get(units, 1.0)
        unit_text = "µm" if units in _MICRO else units
        r = np.asarray(var.values, dtype=np.float64)[order] * scale
        r = np.append(r, r[0])
        style = {"lw": 1.2, "color": f"C{i}"}
        style.update(kwargs)
        ax.plot(phi, r, label=str(var.attrs.get("long_name", name)), **style)
        top = max(top, float(np.nanmax(r)) if r.size else 0.0)
    top = top if top > 0 else 1.0
    for k, (start, stop) in enumerate(sectors or ()):
        a0, a1 = np.deg2rad(float(start)), np.deg2rad(float(stop))
        if a1 < a0:
            a1 += 2.0 * np.pi
        ax.bar(
            (a0 + a1) / 2.0,
            1.05 * top,
            width=a1 - a0,
            bottom=0.0,
            color="0.6",
            alpha=0.25,
            linewidth=0,
            label=sector_label if k == 0 else None,
        )
    ax.set_theta_zero_location("E")
    ax.set_theta_direction(1)
    ax.set_ylim(0.0, 1.1 * top)
    ax.set_title(f"wear depth [{unit_text}]" if unit_text else "wear depth", fontsize=9)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.15, -0.15))
    return ax


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
    ax.figure.colorbar(mesh, ax=ax, label=_label(field, mle))
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
    ax.set_xlabel(_label(xc, xdim) if xdim in data.coords else xdim)
    ax.set_ylabel(_label(yc, ydim) if ydim in data.coords else ydim)
    ax.set_title(f"{field.attrs.get('long_name', mle)}", fontsize=9)
    return ax


def _new_axes() -> Any:
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=(5.0, 4.0), layout="constrained")
    return ax
