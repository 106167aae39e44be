"""Figures of wear paths over a scene key: exponent, strobe spread, orbit diagram, depth.

:func:`plot_wear_life` draws one of four views of a :class:`mechanism.WearLifeMap` (or its
Dataset, e.g. read back from ``wear-life-map.nc``) against the cycles of wear, one line
(or panel) per value. The convention of :mod:`chaoskit.plot`: ``ax=None`` makes a figure,
the Axes are returned, matplotlib is imported only when drawing.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ._wear_life_map import WearLifeMap, value_label

__all__ = ["WEAR_LIFE_VIEWS", "plot_wear_life", "strobe_spread"]

#: The views of :func:`plot_wear_life` and what each shows.
WEAR_LIFE_VIEWS = {
    "exponent": "largest Lyapunov exponent from the equations with its 95 % interval",
    "spread": "spread of the stroboscopic points of the journal",
    "orbit": "stroboscopic points of the journal (wear-driven orbit diagram)",
    "depth": "largest wear depth of the bearing (solid) and the journal (dashed)",
}
_MICRO = 1e6


def _dataset(life: Any) -> xr.Dataset:
    if isinstance(life, WearLifeMap):
        return life.to_dataset()
    if isinstance(life, xr.Dataset) and {"value", "checkpoint"} <= set(life.dims):
        return life
    raise ValueError(
        "plot_wear_life() needs a mechanism.WearLifeMap or its Dataset (dims value and "
        f"checkpoint); got {type(life).__name__}."
    )


def strobe_spread(ds: xr.Dataset) -> xr.DataArray:
    """Root-mean-square distance of the stroboscopic points from their mean (m).

    Over the crossings of each (value, checkpoint, joint) of a map Dataset (or of each
    (checkpoint, joint) of one path): near 0 for a period-1 motion, the size of the band
    for a chaotic one. NaN where a checkpoint has no points.
    """
    x, y = ds["strobe_x"], ds["strobe_y"]
    with np.errstate(invalid="ignore"):
        dx = x - x.mean("crossing", skipna=True)
        dy = y - y.mean("crossing", skipna=True)
        out = np.sqrt((dx**2 + dy**2).mean("crossing", skipna=True))
    out.attrs = {"units": "m", "long_name": "rms distance of the strobe points from their mean"}
    return out


def _labels(ds: xr.Dataset) -> list[str]:
    units = str(ds["value"].attrs.get("units", ""))
    parameter = str(ds.attrs.get("parameter", "value"))
    return [value_label(parameter, float(v), units) for v in ds["value"].values]


def _new_axes(panels: int = 1) -> Any:
    import matplotlib.pyplot as plt  # plotting is optional

    _, axes = plt.subplots(
        panels, 1, figsize=(6.4, 3.6 if panels == 1 else 1.6 * panels + 1.0),
        layout="constrained", sharex=True, squeeze=False,
    )  # fmt: skip
    return list(axes[:, 0])


def _cycles_axis(ax: Any) -> None:
    ax.set_xlabel("crank cycles of wear")
    ax.grid(True, alpha=0.3)


def _exponent(ds: xr.Dataset, ax: Any, labels: list[str]) -> None:
    n = ds["checkpoint"].values
    for i, label in enumerate(labels):
        lam = ds["lyapunov_exponent"].values[i]
        (line,) = ax.plot(n, lam, marker="o", ms=3, label=label)
        ax.fill_between(n, ds["lyapunov_ci_low"].values[i], ds["lyapunov_ci_high"].values[i],
                        color=line.get_color(), alpha=0.18, lw=0)  # fmt: skip
        chaos = float(ds["cycles_to_chaos"].values[i])
        if np.isfinite(chaos):
            ax.axvline(chaos, color=line.get_color(), ls=":", lw=1)
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_ylabel("λ₁ (1/s), 95 % interval")


def _spread(ds: xr.Dataset, ax: Any, labels: list[str]) -> None:
    spread = strobe_spread(ds)
    joints = [str(j) for j in ds["joint"].values]
    for i, label in enumerate(labels):
        for j, joint in enumerate(joints):
            name = label if len(joints) == 1 else f"{label}, joint {joint}"
            ax.plot(ds["checkpoint"].values, spread.values[i, :, j] * _MICRO, marker="o", ms=3,
                    label=name)  # fmt: skip
    ax.set_ylabel("strobe spread (µm)")


def _depth(ds: xr.Dataset, ax: Any, labels: list[str]) -> None:
    depth = ds["max_wear_depth"].max("joint", skipna=True)
    for i, label in enumerate(labels):
        (line,) = ax.plot(ds["checkpoint"].values, depth.sel(surface="bearing").values[i] * _MICRO,
                          marker="o", ms=3, label=label)  # fmt: skip
        ax.plot(ds["checkpoint"].values, depth.sel(surface="journal").values[i] * _MICRO,
                ls="--", color=line.get_color())  # fmt: skip
    ax.set_ylabel("largest wear depth (µm)")


def _orbit(ds: xr.Dataset, axes: Sequence[Any], labels: list[str]) -> None:
    e = np.hypot(ds["strobe_x"], ds["strobe_y"]) * _MICRO  # (value, checkpoint, joint, crossing)
    n = ds["checkpoint"].values
    for i, (ax, label) in enumerate(zip(axes, labels, strict=True)):
        points = e.values[i].reshape(n.size, -1)
        xs = np.repeat(n, points.shape[1])
        ax.plot(xs, points.ravel(), ls="none", marker=".", ms=2.5, color="k")
        chaos = float(ds["cycles_to_chaos"].values[i])
        if np.isfinite(chaos):
            ax.axvline(chaos, color="C3", ls=":", lw=1)
        ax.set_ylabel("|e| (µm)")
        ax.set_title(label, fontsize="small", loc="left")
        _cycles_axis(ax)


def plot_wear_life(life: Any, *, view: str = "exponent", ax: Any = None) -> Any:
    """Draw one view of wear paths against the cycles of wear, one line or panel per value.

    Views (``WEAR_LIFE_VIEWS``):

    * ``"exponent"``: λ₁ from the equations with its 95 % interval (band); a dotted line
      at each value's cycles to chaos;
    * ``"spread"``: the root-mean-square distance of the journal's stroboscopic points
      from their mean, in µm — near 0 while the motion is period-1, the size of the band
      once it is chaotic;
    * ``"orbit"``: the wear-driven orbit diagram: the journal's eccentricity :math:`|e|`
      at every stroboscopic point against the cycles of wear (µm), one panel per value;
    * ``"depth"``: the largest wear depth of the bearing (solid) and of the journal
      (dashed), in µm.

    Parameters
    ----------
    life
        A :class:`mechanism.WearLifeMap` or its Dataset (``to_dataset()``, or
        ``wear-life-map.nc`` read back).
    view
        One of ``"exponent"``, ``"spread"``, ``"orbit"``, ``"depth"``.
    ax
        Axes to draw on (for ``"orbit"``: a sequence of one Axes per value); a new figure
        when None.

    Returns
    -------
    matplotlib.axes.Axes or list of Axes
        The Axes (a list for ``"orbit"``).
    """
    if view not in WEAR_LIFE_VIEWS:
        raise ValueError(f"view must be one of {sorted(WEAR_LIFE_VIEWS)}; got {view!r}.")
    ds = _dataset(life)
    labels = _labels(ds)
    if view == "orbit":
        axes = _new_axes(len(labels)) if ax is None else list(ax)
        if len(axes) != len(labels):
            raise ValueError(f"ax must hold one Axes per value ({len(labels)}); got {len(axes)}.")
        _orbit(ds, axes, labels)
        return axes
    if ax is None:
        (ax,) = _new_axes()
    {"exponent": _exponent, "spread": _spread, "depth": _depth}[view](ds, ax, labels)
    _cycles_axis(ax)
    ax.legend(fontsize="small")
    return ax
