"""Missing values (NaN) of a trajectory being loaded: refused, dropped or interpolated.

``load_trajectory(nan=...)`` picks the policy (:data:`NAN_POLICIES`); infinite values are
always refused. Messages name the column and the line of the file (or the row) through the
:class:`chaoskit._tables.Origin` of the data, and what was done is recorded for the history.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._contract import UNIFORM_RTOL, ParameterError
from ._tables import Origin

__all__ = ["NAN_POLICIES", "missing_values"]


#: What ``load_trajectory(nan=...)`` does with missing values (NaN).
NAN_POLICIES = ("refuse", "drop", "interpolate")
_LOAD = "load_trajectory"
_lit = ParameterError.literal


def _rows(var: xr.DataArray, index: str) -> np.ndarray:
    """The values of ``var`` as (samples, everything else)."""
    axis = var.dims.index(index)
    values = np.asarray(var.values)
    return np.moveaxis(values, axis, 0).reshape(values.shape[axis], -1)


def _from_rows(var: xr.DataArray, index: str, rows: np.ndarray) -> xr.DataArray:
    axis = var.dims.index(index)
    shape = list(np.moveaxis(np.asarray(var.values), axis, 0).shape)
    return var.copy(data=np.moveaxis(rows.reshape(shape), 0, axis))


def _regular(values: np.ndarray) -> bool:
    """True if the finite ``values`` lie on one uniform grid over their row numbers."""
    rows = np.flatnonzero(np.isfinite(values))
    if rows.size < 3:
        return True
    slope = np.diff(values[rows]) / np.diff(rows)
    ref = float(np.median(slope))
    return ref != 0 and float(np.max(np.abs(slope - ref))) <= UNIFORM_RTOL * abs(ref)


def _run_text(a: int, b: int, origin: Origin) -> str:
    if origin.lines is not None:
        first, last = int(origin.lines[a]), int(origin.lines[b])
        return f"line {first}" if a == b else f"lines {first}-{last}"
    return f"row {a} (0-based)" if a == b else f"rows {a}-{b} (0-based)"


def _spans(rows: np.ndarray, origin: Origin, t: np.ndarray | None, limit: int = 8) -> str:
    """``rows`` as runs, e.g. ``lines 6-8 (t = 0.05 to 0.07 s), line 13 (t = 0.12 s)``."""
    runs = np.split(rows, np.flatnonzero(np.diff(rows) != 1) + 1) if rows.size else []
    parts = []
    for run in runs[:limit]:
        a, b = int(run[0]), int(run[-1])
        text = _run_text(a, b, origin)
        if t is not None and np.isfinite(t[a]) and np.isfinite(t[b]):
            text += f" (t = {t[a]:.6g} s)" if a == b else f" (t = {t[a]:.6g} to {t[b]:.6g} s)"
        parts.append(text)
    if len(runs) > limit:
        parts.append(f"and {len(runs) - limit} more")
    return ", ".join(parts)


def _nonfinite(ds: xr.Dataset, index: str) -> dict[str, np.ndarray]:
    """(samples, k) masks of the non-finite values of the index and of each float variable."""
    out: dict[str, np.ndarray] = {}
    idx = np.asarray(ds[index].values)
    if idx.dtype.kind == "f" and not np.isfinite(idx).all():
        out[index] = ~np.isfinite(idx)[:, None]
    for name, var in ds.data_vars.items():
        if index in var.dims and var.dtype.kind == "f":
            mask = ~np.isfinite(_rows(var, index))
            if mask.any():
                out[str(name)] = mask
    return out


def _refuse_missing(
    ds: xr.Dataset, bad: dict[str, np.ndarray], index: str, origin: Origin, nan: str
) -> None:
    """Raise for an infinite value (always) or, with ``nan='refuse'``, a missing one."""
    what = _lit(origin.what)
    for name, mask in bad.items():
        values = _rows(ds[name], index) if name != index else np.asarray(ds[index].values)[:, None]
        inf = np.isinf(values) & mask
        if inf.any():
            row = int(np.flatnonzero(inf.any(axis=1))[0])
            raise ParameterError(
                f"{origin.kind} {_lit(origin.label(name))!r} of {what} holds an infinite "
                f"value at {origin.where(row)} ({int(inf.sum())} in all); replace them: "
                "{nan} handles missing values (NaN) only.",
                function=_LOAD,
            )
    if nan != "refuse":
        return
    name, row = min(
        ((n, int(np.flatnonzero(m.any(axis=1))[0])) for n, m in bad.items()), key=lambda p: p[1]
    )
    total = sum(int(m.sum()) for m in bad.values())
    more = f" ({total} missing values in {len(bad)} {origin.kind}(s))" if total > 1 else ""
    raise ParameterError(
        f"{origin.kind} {_lit(origin.label(name))!r} of {what} has a missing value (NaN) at "
        f"{origin.where(row)}{more}; fill the gaps, or pass {{nan=interpolate}} (linear in "
        "time) or {nan=drop}{to}.",
        function=_LOAD,
    )


def _drop_missing(
    ds: xr.Dataset, bad: dict[str, np.ndarray], index: str, origin: Origin
) -> tuple[xr.Dataset, str]:
    """Rows with a missing value dropped, if the sampling stays as uniform as it was."""
    rows_bad = np.zeros(ds.sizes[index], dtype=bool)
    for mask in bad.values():
        rows_bad |= mask.any(axis=1)
    keep = ~rows_bad
    if not keep.any():
        raise ValueError(f"every row of {origin.what} has a missing value; nothing is left.")
    idx = np.asarray(ds[index].values, dtype=np.float64)
    kept = np.flatnonzero(keep)
    inner = np.flatnonzero(rows_bad[kept[0] : kept[-1]]) + kept[0]
    if inner.size and _regular(idx):
        raise ParameterError(
            f"{{nan=drop}} would leave gaps in the uniform sampling of {_lit(origin.what)}: "
            f"{int(inner.size)} row(s) with missing values inside the record, the first at "
            f"{origin.where(int(inner[0]))}; pass {{nan=interpolate}}{{to}} to bridge them, or "
            "resample the data first.",
            function=_LOAD,
        )
    t = idx if index == "time" else None
    note = f"dropped {int(rows_bad.sum())} row(s) with missing values: "
    note += _spans(np.flatnonzero(rows_bad), origin, t)
    return ds.isel({index: keep}), note


def _interpolate_missing(
    ds: xr.Dataset, bad: dict[str, np.ndarray], index: str, origin: Origin
) -> tuple[xr.Dataset, str]:
    """Missing values bridged linearly in time; rows at either end where some variable has
    no value yet (nothing to interpolate from) dropped. Each variable records what was
    bridged in ``interpolated_samples`` and ``interpolated_gaps``."""
    if index != "time":
        raise ParameterError(
            "{nan=interpolate} needs a time axis: the iterations of a map cannot be "
            "interpolated; pass {nan=drop}{to} or fill the gaps.",
            function=_LOAD,
        )
    n = ds.sizes[index]
    lead, trail = 0, n - 1
    for name, mask in bad.items():
        good = ~mask
        if not good.any(axis=0).all():
            raise ValueError(
                f"{origin.kind} {origin.label(name)!r} of {origin.what} has no value at all; "
                "leave it out."
            )
        lead = max(lead, int(np.argmax(good, axis=0).max()))
        trail = min(trail, n - 1 - int(np.argmax(good[::-1], axis=0).max()))
    if lead >= trail:
        raise ValueError(f"{origin.what} has no two rows where every value is present.")
    t_all = np.asarray(ds[index].values, dtype=np.float64)
    ds = ds.isel({index: slice(lead, trail + 1)})
    t = np.asarray(ds[index].values, dtype=np.float64).copy()
    notes = []
    if lead or trail < n - 1:
        ends = np.r_[np.arange(lead), np.arange(trail + 1, n)]
        notes.append(f"dropped {ends.size} row(s) at the ends: {_spans(ends, origin, t_all)}")
    for name, mask in bad.items():
        m = mask[lead : trail + 1]
        if not m.any():
            continue
        rows = np.flatnonzero(m.any(axis=1))
        gaps = _spans(rows + lead, origin, t_all if name != index else None)
        if name == index:
            r = np.arange(t.size)
            t[m[:, 0]] = np.interp(r[m[:, 0]], r[~m[:, 0]], t[~m[:, 0]])
            ds = ds.assign_coords(time=("time", t, ds[index].attrs))
            notes.append(f"{int(m.sum())} missing time(s) interpolated by row at {gaps}")
            continue
        values = _rows(ds[name], index).astype(np.float64)
        for c in np.flatnonzero(m.any(axis=0)):
            hole = m[:, c]
            values[hole, c] = np.interp(t[hole], t[~hole], values[~hole, c])
        ds[name] = _from_rows(ds[name], index, values)
        ds[name].attrs["interpolated_samples"] = int(m.sum())
        ds[name].attrs["interpolated_gaps"] = gaps
        notes.append(f"{name}: {int(m.sum())} missing value(s) interpolated at {gaps}")
    return ds, "; ".join(notes)


def missing_values(ds: xr.Dataset, nan: str, origin: Origin) -> tuple[xr.Dataset, str | None]:
    """Refuse, drop or interpolate the missing values (NaN) along the index; a line for the
    history saying what was done."""
    index = "time" if "time" in ds.coords else "step" if "step" in ds.coords else None
    if index is None or ds[index].ndim != 1:
        return ds, None  # the contract check says what is wrong
    bad = _nonfinite(ds, index)
    if not bad:
        return ds, None
    _refuse_missing(ds, bad, index, origin, nan)
    if nan == "drop":
        return _drop_missing(ds, bad, index, origin)
    return _interpolate_missing(ds, bad, index, origin)
