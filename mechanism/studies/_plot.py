"""Figures of mechanism studies (matplotlib imported lazily; nothing is shown or saved)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ._orbit_diagram import EXPONENT_VARIABLES

__all__ = ["plot_bifurcation"]


def _label(var: xr.DataArray, name: str) -> str:
    units = var.attrs.get("units", "")
    text = str(var.attrs.get("long_name", name))
    return f"{text} ({units})" if units and units != "1" else text


def plot_bifurcation(
    ds: xr.Dataset,
    *,
    variable: str | None = None,
    joint: str | None = None,
    axes: Sequence[Any] | None = None,
    marker_size: float | None = None,
    continuation: Any | None = None,
) -> list[Any]:
    """Draw a :func:`mechanism.bifurcation` Dataset as the classic orbit diagram.

    The stroboscopic points of ``variable`` are scattered against the parameter (small
    dots, sized for thousands of points, rasterised); when the Dataset carries the
    largest Lyapunov exponent per value, a second panel underneath shows it with its 95 %
    interval against the same parameter axis, with λ = 0 marked, so regular (λ ≤ 0) and
    chaotic (λ > 0) windows line up with the orbit diagram above.

    Parameters
    ----------
    ds
        The Dataset returned by :func:`mechanism.bifurcation`.
    variable
        Section variable to draw (default: the first of the bifurcation's variables).
    joint
        Clearance joint for a per-joint variable (default: every joint, one colour each).
    axes
        One Axes (orbit diagram) or two (orbit diagram, exponent); default a new figure
        with one or two rows sharing the parameter axis.
    marker_size
        Dot area in points² (default: from the number of points N, 12 000/N between 1 and
        6).
    continuation
        A :class:`mechanism.Continuation` over the same parameter, drawn over the orbit
        diagram: each branch's ``|e|`` at its section times (stable solid, unstable dashed)
        and its labelled points (PD period doubling, F fold, NS Neimark–Sacker, G
        grazing). Only for ``variable="eccentricity"``.

    Returns
    -------
    list of matplotlib.axes.Axes
        The orbit-diagram axes, then the exponent axes when drawn.
    """
    parameter = str(ds.attrs.get("bifurcation_parameter", ""))
    if parameter not in ds.dims:
        raise ValueError("plot_bifurcation() needs the Dataset returned by mechanism.bifurcation.")
    if variable is None:
        variable = str(ds.attrs.get("bifurcation_variables", "")).split(",")[0]
    if variable not in ds:
        raise ValueError(f"variable {variable!r} is not in the Dataset.")
    var = ds[variable]
    if joint is not None:
        var = var.sel(joint=joint)
    has_exponent = EXPONENT_VARIABLES[0] in ds and bool(
        np.isfinite(ds[EXPONENT_VARIABLES[0]].values).any()
    )
    if axes is None:
        import matplotlib.pyplot as plt

        rows = 2 if has_exponent else 1
        heights = [3, 1.4] if has_exponent else [1]
        fig, made = plt.subplots(
            rows,
            1,
            sharex=True,
            figsize=(7.5, 4.8 if has_exponent else 3.6),
            gridspec_kw={"height_ratios": heights},
            squeeze=False,
        )
        axes = list(made[:, 0])
        fig.subplots_adjust(hspace=0.08)
    axes = list(axes)
    p = np.asarray(ds[parameter].values, dtype=np.float64)
    groups: list[tuple[str | None, xr.DataArray]] = [(None, var)]
    if "joint" in var.dims:
        groups = [(str(j), var.sel(joint=j)) for j in var["joint"].values]
    total = sum(int(np.isfinite(g.values).sum()) for _, g in groups)
    # area 12 000/N pt² between 1 and 6: 6 000 points are 2 pt² dots (about 3 px across at
    # 160 dpi), clearly visible; 100 000 points do not blacken the axes
    size = marker_size if marker_size is not None else float(np.clip(12000.0 / max(total, 1), 1, 6))
    ax = axes[0]
    for name, values in groups:
        v = np.asarray(values.transpose(parameter, ...).values, dtype=np.float64)
        x = np.broadcast_to(p[:, None], v.shape)
        keep = np.isfinite(v)
        color = "k" if len(groups) == 1 else None
        ax.scatter(
            x[keep], v[keep], s=size, c=color, linewidths=0, alpha=0.8, rasterized=True,
            label=None if name is None else f"joint {name}",
        )  # fmt: skip
    failed = np.asarray(ds["status"].values) != "ok" if "status" in ds else np.zeros(p.size, bool)
    for value in p[failed]:
        ax.axvline(value, color="tab:red", lw=0.6, alpha=0.5)
    ax.set_ylabel(_label(var, variable))
    ax.set_title(
        f"stroboscopic points ({total} points, {p.size} values)"
        + (f", {int(failed.sum())} failed (red)" if failed.any() else ""),
        fontsize=9,
    )
    if continuation is not None:
        if variable != "eccentricity":
            raise ValueError("continuation= overlays |e|: draw variable='eccentricity'.")
        _overlay_branches(ax, continuation, joint, var)
    if len(groups) > 1:
        ax.legend(fontsize=8, markerscale=4)
    if has_exponent and len(axes) > 1:
        lam = np.asarray(ds[EXPONENT_VARIABLES[0]].values, dtype=np.float64)
        low = np.asarray(ds[EXPONENT_VARIABLES[1]].values, dtype=np.float64)
        high = np.asarray(ds[EXPONENT_VARIABLES[2]].values, dtype=np.float64)
        bx = axes[1]
        chaotic = low > 0
        for mask, color, label in (
            (chaotic, "tab:red", "interval > 0"),
            (~chaotic, "tab:blue", "interval reaches 0 or below"),
        ):
            if mask.any():
                bx.errorbar(
                    p[mask], lam[mask], yerr=[lam[mask] - low[mask], high[mask] - lam[mask]],
                    fmt="o", ms=2.5, lw=0.8, color=color, label=label,
                )  # fmt: skip
        bx.axhline(0.0, color="0.4", lw=0.8)
        bx.set_ylabel("λ (1/s)")
        bx.legend(fontsize=7, loc="best")
        bottom = bx
    else:
        bottom = ax
    bottom.set_xlabel(_label(ds[parameter], parameter))
    return axes


#: short labels of the bifurcation kinds on the figure
_KIND_LABELS = {"period-doubling": "PD", "fold": "F", "neimark-sacker": "NS", "grazing": "G"}


def _overlay_branches(ax: Any, continuation: Any, joint: str | None, var: xr.DataArray) -> None:
    """Branches (stable solid, unstable dashed) and labelled points of a continuation."""
    joints = [str(j) for j in var["joint"].values] if "joint" in var.dims else []
    column = joints.index(joint) if joint is not None and joint in joints else 0
    for index, branch in enumerate(continuation.branches):
        p = branch.parameter
        e = [pt.eccentricity for pt in branch.points]
        if not e or any(x.ndim != 2 or x.shape[1] <= column for x in e):
            continue
        stable = branch.stable
        color = f"C{index % 10}"
        for k in range(branch.period):
            y = np.array([x[k, column] if x.shape[0] > k else np.nan for x in e])
            for mask, style in ((stable, "-"), (~stable, "--")):
                # runs of the mask, each joined to the next point so the line is continuous
                yy = np.where(mask | np.roll(mask, 1) & (np.arange(p.size) > 0), y, np.nan)
                ax.plot(p, yy, style, color=color, lw=1.2,
                        label=(f"period-{branch.period} branch" if k == 0 and style == "-"
                               and mask.any() else None))  # fmt: skip
    for bif in continuation.bifurcations:
        branch = continuation.branches[bif.branch]
        near = int(np.argmin(np.abs(branch.parameter - bif.parameter)))
        e = branch.points[near].eccentricity
        if e.ndim != 2 or e.shape[1] <= column:
            continue
        ax.plot(bif.parameter, e[0, column], "o", mfc="none", mec="tab:red", ms=7)
        ax.annotate(_KIND_LABELS.get(bif.kind, bif.kind), (bif.parameter, e[0, column]),
                    xytext=(3, 5), textcoords="offset points", fontsize=8,
                    color="tab:red")  # fmt: skip
    ax.legend(fontsize=8, loc="best")
