"""The on-disk layout of a sweep: manifest, point names, per-point summaries.

A store is a folder::

    STORE/sweep.json              manifest: scene, grid, revolutions, analysis, simulator
    STORE/points/<id>.nc          trajectory of one grid point (chaoskit.save_trajectory)
    STORE/points/<id>.summary.nc  its summary: status, message, metrics, analysis fields
    STORE/summary.nc              the gathered Dataset (rewritten by every run)
    STORE/.lock                   held by the running sweep (two sweeps never share a store)

Every file is written under a temporary name in its folder and then renamed, so a worker
that dies mid-write never leaves a half-written file for a resumed run to trust.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import socket
import uuid
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

try:
    import fcntl
except ImportError:  # Windows: no advisory locks; the exclusive manifest still guards
    fcntl = None  # type: ignore[assignment]

from chaoskit.contract import safe_filename
from chaoskit.contract import write_netcdf as _write_netcdf

__all__ = [
    "MANIFEST_FORMAT",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "check_or_write_manifest",
    "locked",
    "point_file",
    "point_id",
    "read_summary",
    "readable_trajectory",
    "remove_stale_temporaries",
    "summary_path",
    "trajectory_path",
    "write_summary",
]

MANIFEST_FORMAT = "mechanism.sweep/1"
MANIFEST = "sweep.json"
POINTS = "points"
SUMMARY = "summary.nc"
LOCK = ".lock"

_READABLE_MAX = 80


class SweepStoreMismatch(ValueError):
    """The store holds a sweep with another scene, grid or settings than the one requested."""


class SweepStoreBusy(ValueError):
    """Another sweep is running into the same store."""


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
    """``STORE/points/<id>.nc``."""
    return store / POINTS / f"{pid}.nc"


def point_file(store: Path, relative: str) -> Path:
    """A point file named in a summary, as a path that cannot leave the store.

    Raises
    ------
    ValueError
        If ``relative`` is absolute or climbs out of the store (a damaged or foreign summary).
    """
    root = Path(store).resolve()
    path = (root / relative).resolve()
    if Path(relative).is_absolute() or not path.is_relative_to(root):
        raise ValueError(f"the store {store} names a point file outside itself: {relative!r}.")
    return path


def summary_path(store: Path, pid: str) -> Path:
    """``STORE/points/<id>.summary.nc``."""
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


def _create_exclusively(path: Path, text: str) -> bool:
    """Create ``path`` holding ``text`` unless it exists; True if this call created it.

    The text is written to a temporary file first and hard-linked to ``path``: the link
    fails if ``path`` exists and, when it succeeds, ``path`` is complete from its first
    instant, so a concurrent reader never sees half a manifest. On a filesystem without
    hard links, ``O_CREAT | O_EXCL`` decides instead.
    """
    tmp = path.parent / f".{path.name}.{uuid.uuid4().hex[:12]}.tmp"
    tmp.write_text(text, encoding="utf-8")
    try:
        os.link(tmp, path)
        return True
    except FileExistsError:
        return False
    except OSError:
        try:
            fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            return False
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        return True
    finally:
        tmp.unlink(missing_ok=True)


def check_or_write_manifest(store: Path, manifest: Mapping[str, Any]) -> bool:
    """Create ``STORE/sweep.json`` or check that the one there describes the same sweep.

    The manifest is created exclusively: of two sweeps that start into one new store at the
    same instant, one writes it and the other compares against it.

    Returns True when the store already held this sweep (a resume).

    Raises
    ------
    SweepStoreMismatch
        Naming the first field that differs (scene key, grid key or value, setting).
    """
    path = store / MANIFEST
    wanted = json.loads(json.dumps(dict(manifest)))  # the form it takes on disk
    if _create_exclusively(path, json.dumps(wanted, indent=2) + "\n"):
        return False
    try:
        stored = json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise SweepStoreMismatch(
            f"{path} is not a readable sweep manifest ({exc}); use another store."
        ) from None
    if not isinstance(stored, dict) or stored.get("format") != MANIFEST_FORMAT:
        raise SweepStoreMismatch(f"{path} is not a {MANIFEST_FORMAT} manifest; use another store.")
    diff = _first_difference(stored, wanted)
    if diff:
        raise SweepStoreMismatch(
            f"the store {store} holds a different sweep ({diff}); results would mix. "
            "Use another store, or delete this one to start over."
        )
    return True


@contextlib.contextmanager
def locked(store: Path) -> Iterator[None]:
    """Hold an exclusive lock on the store (``STORE/.lock``) for the duration of a sweep.

    Raises
    ------
    SweepStoreBusy
        If another sweep (in this or another process) holds it.
    """
    store.mkdir(parents=True, exist_ok=True)
    path = store / LOCK
    with path.open("a+", encoding="utf-8") as fh:
        if fcntl is not None:
            try:
                fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                fh.seek(0)
                holder = fh.read().strip() or "another process"
                raise SweepStoreBusy(
                    f"the store {store} is in use by another sweep ({holder}); wait for it to "
                    "finish or use another store."
                ) from None
        fh.seek(0)
        fh.truncate()
        fh.write(f"process {os.getpid()} on {socket.gethostname()}\n")
        fh.flush()
        try:
            yield
        finally:
            if fcntl is not None:
                fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def remove_stale_temporaries(store: Path) -> int:
    """Delete temporary files that interrupted writes left in the store; returns how many.

    Call it under :func:`locked`: then no writer of this store is running.
    """
    removed = 0
    for folder in (store, store / POINTS):
        if folder.is_dir():
            for tmp in folder.glob(".*.tmp"):
                with contextlib.suppress(FileNotFoundError):
                    tmp.unlink()
                    removed += 1
    return removed


def readable_trajectory(path: Path) -> bool:
    """True if ``path`` opens as netCDF-4 and its index coordinate reads (not merely exists)."""
    if not path.is_file():
        return False
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            index = "time" if "time" in ds.coords else "step"
            np.asarray(ds[index].values)
    except (OSError, ValueError, KeyError, RuntimeError):
        return False
    return True


def write_netcdf(ds: xr.Dataset, path: str | Path) -> None:
    """Write any Dataset atomically as netCDF-4 through h5netcdf (temporary file, rename),
    after checking the free space; a full disk raises ``OSError(ENOSPC)``."""
    _write_netcdf(ds, Path(path))


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
    """The ``status`` of a point summary, or None without one."""
    if ds is None or "status" not in ds:
        return None
    return str(np.asarray(ds["status"].values).item())
