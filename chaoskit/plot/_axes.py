"""Helpers shared by the figure modules: the Axes to draw on, an axis label from attrs."""

from __future__ import annotations

from typing import Any

import xarray as xr

__all__ = ["axes_or_new", "axis_label"]


def axes_or_new(ax: Any) -> Any:
    """``ax`` itself, or the Axes of a new 5 x 4 inch pyplot figure when it is None."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    _, ax = plt.subplots(figsize=(5.0, 4.0), layout="constrained")
    return ax


def axis_label(var: xr.DataArray, fallback: str) -> str:
    """``long_name [units]`` of ``var`` (its name, else ``fallback``, without a long name)."""
    name = str(var.attrs.get("long_name", var.name or fallback))
    units = var.attrs.get("units")
    return f"{name} [{units}]" if units not in (None, "", "1", "unknown") else name
