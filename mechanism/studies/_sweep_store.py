"""The on-disk layout of a sweep: manifest, point names, per-point summaries.

A store is a folder::

    STORE/sweep.json              manifest: scene, grid, revolutions, analysis, simulator
    STORE/points/<id>.nc          trajectory of one grid point (chaoskit.save_trajectory)
    STORE/points/<id>.summary.nc  its summary: status, message, metrics, analysis fields
    STORE/summary.nc              the gathered Dataset (rewritten by every run)

Every file is written under a temporary name in its folder and then renamed, so a worker
that dies mid-write never leaves a half-written file for a resumed run to trust.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from chaoskit._io import _atomic_write
from chaoskit._paths import safe_filename

__all__ = [
    "MANIFEST_FORMAT",
    "SweepStoreMismatch",
    "check_or_write_manifest",
    "point_id",
    "read_summary",
    "summary_path",
    "trajectory_path",
    "write_summary",
]

MANIFEST_FORMAT = "mechanism.sweep/1"
MANIFEST = "sweep.json"
POINTS = "points"
SUMMARY = "summary.nc"

_READABLE_MAX = 80


class SweepStoreMismatch(ValueError):
    """The store holds a sweep with another scene, grid or settings than the one requested."""


def _format_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _short_names(keys: Sequence[str]) -> list[str]:
    """Last dotted component of each key, or more components where that is ambiguous."""
    parts = [k.split(".") for k in keys]
    depth = [1] * len(keys)
    while True:
        names = [".".join(p[-d:]) for p, d in zip(parts, depth, strict=True)]
        clashes = {n for n in names if names.count(n) > 1}
        if not clashes:
            return names
        grown = False
        for i, n in enumerate(names):
            if n in clashes and depth[i] < len(parts[i]):
                depth[i] += 1
                grown = True
        if not grown:  # identical keys cannot occur (mapping); stop growing anyway
            return names


def point_id(params: Mapping[str, Any]) -> str:
    """A stable, readable file stem for one grid point.

    E.g. ``clearance-0.0001_speed_rpm-90_wear-after_3d78754d6a``: short key names (the last
    dotted component, longer where two keys would share it) with their values, cut at 80
    characters, then 10 hex digits of the SHA-1 of the full ``[[key, value], ...]`` list in
    grid order, which keeps the stems unique.
    """
    keys = list(params)
    short = _short_names(keys)
    readable = "_".join(f"{s}-{_format_value(params[k])}" for s, k in zip(short, keys, strict=True))
    readable = safe_filename(readable, replacement="~", max_length=_READABLE_MAX)
    canonical = json.dumps([[k, params[k]] for k in keys], separators=(",", ":"))
    digest = hashlib.sha1(canonical.encode("utf-8")).hexdigest()[:10]
    return f"{readable}_{digest}"


def trajectory_path(store: Path, pid: str) -> Path:
    return store / POINTS / f"{pid}.nc"


def summary_path(store: Path, pid: str) -> Path:
    return store / POINTS / f"{pid}.summary.nc"


def _first_difference(stored: Any, requested: Any, where: str = "") -> str | None:
    """Dotted path and values of the first difference between two JSON-like values."""
    if isinstance(stored, dict) and isinstance(requested, dict):
        for key in list(stored) + [k for k in requested if k not in stored]:
            sub = f"{where}.{key}" if where else str(key)
            if key not in stored or key not in requested:
                side = "requested" if key not in stored else "stored"
                return f"{sub} (only in the {side} sweep)"
            found = _first_difference(stored[key], requested[key], sub)
            if found:
                return found
        if list(stored) != list(requested):
            return f"{where or 'top level'}: key order {list(stored)} vs {list(requested)}"
        return None
    if isinstance(stored, list) and isinstance(requested, list):
        if len(stored) != len(requested):
            return f"{where}: {stored!r} vs {requested!r}"
        for i, (a, b) in enumerate(zip(stored, requested, strict=True)):
            found = _first_difference(a, b, f"{where}[{i}]")
            if found:
                return found
        return None
    same = stored == requested and type(stored) is type(requested)
    if not same and isinstance(stored, float) and isinstance(requested, float):
        same = math.isnan(stored) and math.isnan(requested)
    return None if same else f"{where}: stored {stored!r}, requested {requested!r}"


def check_or_write_manifest(store: Path, manifest: Mapping[str, Any]) -> bool:
    """Write ``STORE/sweep.json`` or check that the one there describes the same sweep.

    Returns True when the store already held this sweep (a resume).

    Raises
    ------
    SweepStoreMismatch
        Naming the first field that differs (scene key, grid key or value, setting).
    """
    path = store / MANIFEST
    wanted = json.loads(json.dumps(dict(manifest)))  # the form it takes on disk
    if path.exists():
        try:
            stored = json.loads(path.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise SweepStoreMismatch(
                f"{path} is not a readable sweep manifest ({exc}); use another store."
            ) from None
        if not isinstance(stored, dict) or stored.get("format") != MANIFEST_FORMAT:
            raise SweepStoreMismatch(
                f"{path} is not a {MANIFEST_FORMAT} manifest; use another store."
            )
        diff = _first_difference(stored, wanted)
        if diff:
            raise SweepStoreMismatch(
                f"the store {store} holds a different sweep ({diff}); results would mix. "
                "Use another store, or delete this one to start over."
            )
        return True
    text = json.dumps(wanted, indent=2) + "\n"
    _atomic_write(path, lambda p: p.write_text(text, encoding="utf-8"))
    return False


def write_netcdf(ds: xr.Dataset, path: str | Path) -> None:
    """Write any Dataset atomically as netCDF-4 through h5netcdf (temporary file, rename)."""
    _atomic_write(Path(path), lambda p: ds.to_netcdf(p, engine="h5netcdf"))


def write_summary(ds: xr.Dataset, path: Path) -> None:
    """Write one point's summary atomically (netCDF-4 through h5netcdf)."""
    write_netcdf(ds, path)


def read_summary(path: Path) -> xr.Dataset | None:
    """The summary at ``path`` loaded into memory, or None when missing or unreadable."""
    if not path.exists():
        return None
    try:
        with xr.open_dataset(path, engine="h5netcdf") as opened:
            return opened.load()
    except (OSError, ValueError):  # a foreign or damaged file: the point is simply rerun
        return None


def summary_status(ds: xr.Dataset | None) -> str | None:
    if ds is None or "status" not in ds:
        return None
    return str(np.asarray(ds["status"].values).item())
