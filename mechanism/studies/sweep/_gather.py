"""One Dataset over the grid from the per-point summaries in a store."""

from __future__ import annotations

import contextlib
import os
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import stamp
from mechanism.core.record import METRICS

from . import _store
from ._point import SOURCE, string_var
from ._transforms import grid_transforms


def key_attrs(scene: Any, key: str) -> dict[str, str]:
    """``units`` and ``long_name`` of a grid coordinate (units from the scene annotations)."""
    transform = grid_transforms().get(key)
    if transform is not None:
        return {"units": transform.units, "long_name": transform.long_name}
    units = "unknown"
    with contextlib.suppress(Exception):
        *path, last = key.split(".")
        obj = scene
        for part in path:
            obj = obj[part] if isinstance(obj, Mapping) else getattr(obj, part)
        hints = typing.get_type_hints(type(obj), include_extras=True)
        for meta in getattr(hints[last], "__metadata__", ()):
            if type(meta).__name__ == "Unit":
                units = meta.symbol or "unknown"
    return {"units": units, "long_name": f"scene key {key}"}


def _fill_value(kind: str) -> Any:
    return "" if kind == "U" else np.nan


def gather(
    store: Path,
    *,
    scene: Any,
    grid: Mapping[str, tuple[Any, ...]],
    ids: Sequence[str],
    attrs: Mapping[str, Any],
    history: str,
) -> xr.Dataset:
    """One Dataset over the grid from the per-point summaries on disk.

    Combine rule per field: numeric → float64 with NaN where a point has no value; text →
    strings, "" where missing; extra dimensions (``variable``, ``rod``) take the coordinate
    of the first point that has them.
    """
    shape = tuple(len(v) for v in grid.values())
    dims = tuple(grid)
    summaries: list[xr.Dataset] = []
    for pid in ids:
        summary = _store.read_summary(_store.summary_path(store, pid))
        if summary is None:
            summary = xr.Dataset(
                {
                    "status": string_var("failed", ""),
                    "message": string_var("no summary in the store for this point", ""),
                    "point_id": string_var(pid, ""),
                    "trajectory_file": string_var("", ""),
                }
            )
        summaries.append(summary)

    # the metrics are there even when no point succeeded, so a table of them never KeyErrors
    specs: dict[str, tuple[tuple[str, ...], str, dict[str, Any]]] = {
        name: ((), "f", {"units": units, "long_name": long_name})
        for name, (units, long_name) in METRICS.items()
    }
    extra_coords: dict[str, xr.DataArray] = {}
    for summary in summaries:
        for name, var in summary.data_vars.items():
            if name in specs:
                continue
            kind = "U" if var.dtype.kind in "OUS" else "f"
            specs[str(name)] = (tuple(map(str, var.dims)), kind, dict(var.attrs))
            for d in var.dims:
                if d not in extra_coords and d in summary.coords:
                    extra_coords[str(d)] = summary[d].copy()
    order = [n for n in specs if n not in {"status", "message", "point_id", "trajectory_file"}]
    order += ["status", "message", "point_id", "trajectory_file"]

    data_vars: dict[str, xr.Variable] = {}
    for name in order:
        extra, kind, var_attrs = specs[name]
        full = shape + tuple(extra_coords[d].size for d in extra)
        values = np.full(full, _fill_value(kind), dtype=object if kind == "U" else np.float64)
        for flat, summary in enumerate(summaries):
            if name not in summary:
                continue
            var = summary[name]
            if extra:
                var = var.reindex({d: extra_coords[d].values for d in extra})
            arr = np.asarray(var.values)
            if kind == "U":
                arr = arr.astype(str)
            elif arr.dtype.kind == "f" or arr.dtype.kind in "iub":
                arr = arr.astype(np.float64)
            values[np.unravel_index(flat, shape)] = arr
        if kind == "U":
            values = values.astype(str)
        data_vars[name] = xr.Variable(dims + extra, values, attrs=var_attrs)

    coords: dict[str, Any] = {
        key: xr.Variable((key,), np.asarray(values), attrs=key_attrs(scene, key))
        for key, values in grid.items()
    }
    coords.update({d: c.variable for d, c in extra_coords.items()})
    ds = xr.Dataset(data_vars, coords=coords)
    name = getattr(scene, "name", "scene")
    stamp(
        ds,
        title=f"parameter sweep of the {name!r} scene over {', '.join(grid)}",
        source=SOURCE,
        history=history,
        extra=dict(attrs),
    )
    return ds


def load_sweep(store: str | os.PathLike[str]) -> xr.Dataset:
    """The gathered Dataset of a sweep store (``STORE/summary.nc``), loaded into memory."""
    path = Path(store)
    file = path / _store.SUMMARY if path.is_dir() else path
    if not file.exists():
        raise FileNotFoundError(f"no sweep summary at {file}; run mechanism.sweep first.")
    with xr.open_dataset(file, engine="h5netcdf") as opened:
        return opened.load()
