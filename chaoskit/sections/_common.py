"""Shared plumbing for sections: take a trajectory apart into columns and put points back."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from .._contract import stamp
from .._io import load_trajectory
from .._validate import check_int

INTERPOLATION_ORDERS = (3, 5, 7, 9)


@dataclass(frozen=True, kw_only=True)
class Column:
    """Where one variable sits in the stacked ``(n_samples, n_columns)`` array."""

    name: str
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    attrs: dict[str, Any]
    start: int
    stop: int


def as_flow(data: Any, *, what: str) -> xr.Dataset:
    """Load ``data`` as a trajectory that has a ``time`` coordinate (flows, not maps)."""
    ds = load_trajectory(data)
    if "time" not in ds.coords:
        raise ValueError(
            f"{what} needs a continuous-time trajectory with a 'time' coordinate (s); this one "
            "is indexed by 'step' (a map), whose samples already are the points of a section."
        )
    return ds


def check_order(order: Any) -> int:
    order = check_int(order, name="order", minimum=3, maximum=9)
    if order not in INTERPOLATION_ORDERS:
        raise ValueError(f"order must be one of {INTERPOLATION_ORDERS} (odd); got {order}.")
    return order


def check_real(value: Any, *, name: str, units: str = "") -> float:
    """Return ``value`` as a finite float or raise a ValueError naming it (and its units)."""
    unit = f" ({units})" if units else ""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number{unit}; got {value!r}.") from None
    if not np.isfinite(out):
        raise ValueError(f"{name} must be finite{unit}; got {value!r}.")
    return out


def series(ds: xr.Dataset, name: str, *, what: str) -> np.ndarray:
    """One 1-D variable along ``time`` as a contiguous float64 array."""
    if name not in ds.data_vars:
        raise ValueError(f"{what} {name!r} not found; available: {list(ds.data_vars)}.")
    var = ds[name]
    if var.dims != ("time",):
        raise ValueError(f"{what} {name!r} must be 1-D along 'time'; it has dims {var.dims}.")
    return np.ascontiguousarray(var.values, dtype=np.float64)


def stack_columns(
    ds: xr.Dataset, names: Sequence[str] | None, *, exclude: Sequence[str] = ()
) -> tuple[np.ndarray, list[Column]]:
    """Stack the variables ``names`` (default: all along ``time`` except ``exclude``)."""
    if names is None:
        names = [str(k) for k, v in ds.data_vars.items() if "time" in v.dims and k not in exclude]
    elif isinstance(names, str):
        names = [names]
    names = list(names)
    missing = [k for k in names if k not in ds.data_vars]
    if missing:
        raise ValueError(f"coords {missing} not found; available: {list(ds.data_vars)}.")
    n = ds.sizes["time"]
    blocks: list[np.ndarray] = []
    columns: list[Column] = []
    start = 0
    for name in names:
        var = ds[name]
        if "time" not in var.dims:
            raise ValueError(f"coords entry {name!r} does not vary along 'time' (dims {var.dims}).")
        var = var.transpose("time", ...)
        block = np.asarray(var.values, dtype=np.float64).reshape(n, -1)
        blocks.append(block)
        columns.append(
            Column(
                name=name,
                dims=tuple(str(d) for d in var.dims[1:]),
                shape=tuple(var.shape[1:]),
                attrs=dict(var.attrs),
                start=start,
                stop=start + block.shape[1],
            )
        )
        start += block.shape[1]
    y = np.ascontiguousarray(np.hstack(blocks)) if blocks else np.empty((n, 0))
    return y, columns


def points_dataset(
    ds: xr.Dataset,
    *,
    values: np.ndarray,
    columns: list[Column],
    times: np.ndarray,
    title: str,
    history: str,
    attrs: dict[str, Any],
    extra_coords: dict[str, Any] | None = None,
) -> xr.Dataset:
    """Build the section Dataset: one row per point along the ``crossing`` dimension."""
    k = times.size
    data_vars = {}
    for col in columns:
        block = values[:, col.start : col.stop].reshape((k, *col.shape))
        data_vars[col.name] = (("crossing", *col.dims), block, dict(col.attrs))
    coords: dict[str, Any] = {
        "crossing": ("crossing", np.arange(k, dtype=np.int64), {"long_name": "point index"}),
        "time": (
            "crossing",
            times,
            {"units": "s", "long_name": "time of the point", "standard_name": "time"},
        ),
    }
    for col in columns:
        for dim in col.dims:
            if dim in ds.coords and dim not in coords:
                coords[dim] = ds.coords[dim].variable
    if extra_coords:
        coords.update(extra_coords)
    out = xr.Dataset(data_vars, coords=coords)
    out.attrs.update(attrs)
    if ds.attrs.get("history"):  # keep the provenance of the trajectory the points came from
        out.attrs["history"] = ds.attrs["history"]
    return stamp(out, title=title, history=history)
