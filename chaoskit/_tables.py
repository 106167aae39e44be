"""Tables and labelled containers into indexed Datasets.

A table (a CSV file, a pandas object, an npz file, the series of a rig file, a numpy array)
has one column per variable; :func:`from_table` turns it into a Dataset with a ``time`` (or
``step``) index: a time column (in any time unit its header states), a pandas time index, a
sampling interval ``dt`` or iteration numbers. Headers with units (``acc y [m/s^2]``) give
the variable name, ``long_name`` and CF ``units``; cells that are not numbers end in a
one-line error naming the column and the line. :func:`index_labelled` does the same for
xarray objects and netCDF files. :class:`Origin` says where the rows came from, for the
messages of the later steps (missing values, irregular time stamps).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ._contract import UNIFORM_RTOL, ParameterError, variable_name
from ._units import cf_units, seconds_per, split_header

__all__ = [
    "MISSING_WORDS",
    "TIME_NAMES",
    "Origin",
    "check_index_interval",
    "from_array",
    "from_table",
    "has_time_index",
    "index_labelled",
    "one_line",
    "resolve_variables",
]


#: Names a time column or variable goes by when the user names none.
TIME_NAMES = ("time", "t", "Time", "TIME", "t_s", "time_s")
_LOAD = "load_trajectory"
_lit = ParameterError.literal


# ---------------------------------------------------------------- columns


@dataclass(frozen=True)
class _Column:
    raw: str  # the header as written
    name: str  # the variable name
    label: str  # the name part of the header (the long name)
    units: str | None  # the units part of the header, as written


@dataclass
class Origin:
    """Where the rows of a table come from, for messages that point at them."""

    what: str
    kind: str = "column"
    lines: np.ndarray | None = None  # 1-based line in the file of each row
    sep: str | None = None
    decimal: str = "."
    labels: dict[str, str] = field(default_factory=dict)  # variable name -> header
    time_source: str | None = None  # the column the time came from ("" for the index)
    strict_time: bool = False  # a rig file: irregular time stamps are refused
    time_quantum: float = 0.0  # resolution of its time stamps, s (0: exact)

    def where(self, row: int) -> str:
        if self.lines is not None:
            return f"line {int(self.lines[row])}"
        return f"row {row} (0-based)"

    def label(self, name: str) -> str:
        return self.labels.get(name, name)


def _columns(
    labels: Sequence[Any],
    *,
    what: str,
    parse_header: bool,
    units: dict[str, str] | None = None,
) -> list[_Column]:
    raw = [str(c).strip() for c in labels]
    duplicated = sorted({c for c in raw if raw.count(c) > 1})
    if duplicated:
        raise ValueError(f"{what} has duplicate column names {duplicated}; rename them.")
    out = []
    for text in raw:
        label, unit = split_header(text) if parse_header else (text, None)
        unit = (units or {}).get(text) or unit  # units the file states beside the name win
        out.append(_Column(text, variable_name(label) if parse_header else text, label, unit))
    names = [c.name for c in out]
    clash = next((n for n in names if names.count(n) > 1), None)
    if clash is not None:
        sources = [c.raw for c in out if c.name == clash]
        raise ValueError(
            f"columns {sources} of {what} all become the variable {clash!r} (variable names "
            "keep letters, digits and underscores); rename them."
        )
    return out


def _find(columns: Sequence[_Column], wanted: Any) -> _Column | None:
    """The column a user means by ``wanted``: its header, name part or variable name."""
    text = str(wanted).strip()
    hit = next((c for c in columns if text in (c.raw, c.name, c.label)), None)
    if hit is None:
        key = variable_name(split_header(text)[0])
        hit = next((c for c in columns if c.name == key), None)
    return hit


# ---------------------------------------------------------------- numbers in tables

_DECIMAL_COMMA = re.compile(r"[+-]?\d*,\d+([eE][+-]?\d+)?")
_DECIMAL_POINT = re.compile(r"[+-]?\d*\.\d+([eE][+-]?\d+)?")
MISSING_WORDS = {"", "nan", "na", "n/a", "null", "none", "#n/a"}


def _numeric(values: pd.Series, column: _Column, origin: Origin) -> np.ndarray:
    """The cells of one column as numbers (missing ones NaN), or a one-line error pointing at
    the first cell that is not a number."""
    dtype = values.dtype
    if pd.api.types.is_bool_dtype(dtype) or pd.api.types.is_numeric_dtype(dtype):
        if values.hasnans:
            return values.to_numpy(dtype=np.float64, na_value=np.nan)
        return values.to_numpy()
    what = _lit(origin.what)
    if not (pd.api.types.is_object_dtype(dtype) or pd.api.types.is_string_dtype(dtype)):
        raise ParameterError(
            f"column {_lit(column.raw)!r} of {what} is not numeric (dtype {dtype}); pass "
            "{variables} with the numeric columns only{to}.",
            function=_LOAD,
        )
    number = pd.to_numeric(values, errors="coerce")
    text = values.astype(str).str.strip()
    bad = number.isna() & values.notna() & ~text.str.lower().isin(MISSING_WORDS)
    if not bad.any():
        return number.to_numpy(dtype=np.float64, na_value=np.nan)
    row = int(np.flatnonzero(bad.to_numpy())[0])
    cell = str(text.iloc[row])
    if origin.decimal == "." and origin.sep != "," and _DECIMAL_COMMA.fullmatch(cell):
        hint = ", a number with a decimal comma (pass {decimal=,}{to})."
    elif origin.decimal == "," and _DECIMAL_POINT.fullmatch(cell):
        hint = ", a number with a decimal point (leave out {decimal})."
    else:
        hint = "; clean the file or pass {variables} with the numeric columns only{to}."
    raise ParameterError(
        f"column {_lit(column.raw)!r} of {what} is not numeric: {origin.where(row)} holds "
        f"{_lit(cell)!r}" + hint,
        function=_LOAD,
    )


# ---------------------------------------------------------------- the index of a table


def _integer_steps(values: Any, *, name: str, what: str) -> np.ndarray:
    steps = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype=np.float64)
    if np.isnan(steps).any() or np.any(steps != np.round(steps)):
        raise ValueError(f"step column {name!r} in {what} must hold integers (iteration numbers).")
    return steps.astype(np.int64)


def _time_index(index: pd.Index) -> tuple[np.ndarray, str | None] | None:
    """Seconds of a pandas time index (datetime, timedelta or float), and a comment naming
    the origin of a datetime index; ``None`` for any other index."""
    if isinstance(index, pd.DatetimeIndex):
        if index.hasnans:
            raise ValueError("the DatetimeIndex holds missing times (NaT); drop those rows.")
        seconds = (index - index[0]) / pd.Timedelta(seconds=1)
        return np.asarray(seconds, dtype=np.float64), f"seconds since {index[0].isoformat()}"
    if isinstance(index, pd.TimedeltaIndex):
        if index.hasnans:
            raise ValueError("the TimedeltaIndex holds missing times (NaT); drop those rows.")
        return np.asarray(index / pd.Timedelta(seconds=1), dtype=np.float64), None
    if index.dtype.kind == "f":
        return index.to_numpy(dtype=np.float64), None
    return None


def has_time_index(data: Any) -> bool:
    """True for a pandas Series or DataFrame indexed by time: a ``DatetimeIndex``, a
    ``TimedeltaIndex`` or a float index (seconds). :func:`load_trajectory` takes the time,
    and so the sampling interval, from such an index."""
    if not isinstance(data, (pd.Series, pd.DataFrame)):
        return False
    index = data.index
    return isinstance(index, (pd.DatetimeIndex, pd.TimedeltaIndex)) or index.dtype.kind == "f"


def check_index_interval(data: Any, dt: float, *, name: str = "x") -> None:
    """Refuse a series whose time index (see :func:`has_time_index`) is not uniform or
    whose sampling interval is not ``dt`` (s): an estimator that takes ``dt`` would
    otherwise measure time in the wrong unit without a word."""
    if not has_time_index(data):
        return
    found = _time_index(data.index)
    assert found is not None
    t = found[0]
    _check_uniform_index(t, what=name)
    if t.size < 2:
        return
    interval = float(np.median(np.diff(t)))
    if abs(interval - dt) > UNIFORM_RTOL * abs(interval):
        raise ValueError(
            f"dt={float(dt):g} contradicts the time index of {name} (sampling interval "
            f"{interval:.6g} s); pass dt={interval:.6g}."
        )


def _check_dt(t: np.ndarray, dt: float | None, *, what: str) -> None:
    """Refuse a ``dt`` that is not the sampling interval of the times ``t`` of ``what``."""
    if dt is None or t.size < 2:
        return
    d = np.diff(t)
    if np.max(np.abs(d - dt)) > UNIFORM_RTOL * dt:
        mid = float(np.median(d))
        uniform = np.max(np.abs(d - mid)) <= UNIFORM_RTOL * abs(mid)
        interval = (
            f"{mid:.6g} s" if uniform else f"{float(d.min()):.6g} s to {float(d.max()):.6g} s"
        )
        raise ValueError(
            f"dt={dt!r} contradicts {what} (sampling interval {interval}); leave dt out, the "
            "time is known."
        )


def _check_uniform_index(t: np.ndarray, *, what: str) -> None:
    d = np.diff(t)
    if d.size and np.max(np.abs(d - np.median(d))) > UNIFORM_RTOL * abs(float(np.median(d))):
        raise ValueError(
            f"the time index of {what} is not uniform (intervals from {float(d.min()):.6g} s "
            f"to {float(d.max()):.6g} s); resample it to a uniform grid first, e.g. "
            "data.resample('10ms').mean().interpolate()."
        )


def _table_index(
    frame: pd.DataFrame,
    columns: list[_Column],
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    origin: Origin,
    require_uniform: bool,
) -> tuple[str, np.ndarray, dict[str, Any], set[str]]:
    """The index of a table: its name, values, attributes and the columns it used up."""
    what = origin.what
    names = [c.name for c in columns]
    if step is None and time is None and dt is None and "step" in names:
        if not any(n in TIME_NAMES for n in names):
            step = "step"  # a map, e.g. as save_trajectory writes it
    if step is not None:
        col = _find(columns, step)
        if col is not None:
            return "step", _integer_steps(frame[col.name], name=col.raw, what=what), {}, {col.name}
        if step == "step":
            return "step", np.arange(len(frame), dtype=np.int64), {}, set()
        raise ValueError(
            f"step column {step!r} not found in {what}; columns are {[c.raw for c in columns]} "
            "(step='step' numbers the rows 0, 1, ...)."
        )
    col = None
    if time is not None:
        col = _find(columns, time)
        if col is None:
            raise ValueError(
                f"time column {time!r} not found in {what}; columns are {[c.raw for c in columns]}."
            )
    elif dt is None:
        col = next((c for key in TIME_NAMES for c in columns if c.name == key), None)
    if col is not None:
        origin.time_source = col.raw
        factor = seconds_per(col.units, what=f"{origin.kind} {col.raw!r} of {what}")
        t = np.asarray(_numeric(frame[col.name], col, origin), dtype=np.float64) * factor
        attrs = {} if factor == 1.0 else {"comment": f"converted from {col.units}"}
        return "time", t, attrs, {col.name}
    from_index = _time_index(frame.index)
    if from_index is not None:
        origin.time_source = ""
        t, comment = from_index
        _check_dt(t, dt, what=f"the time index of {what}")
        if require_uniform:
            _check_uniform_index(t, what=what)
        return "time", t, ({"comment": comment} if comment else {}), set()
    if dt is not None:
        return "time", float(dt) * np.arange(len(frame), dtype=np.float64), {}, set()
    raise ParameterError(
        f"no time column in {_lit(what)} (looked for {list(TIME_NAMES)}); pass {{time}} (the "
        "name of the time column), {dt} (the sampling interval, s) or, for a map, {step} "
        "({step=step} numbers the rows){to}.",
        function=_LOAD,
    )


def from_table(
    frame: pd.DataFrame,
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    origin: Origin,
    keep: Sequence[str] | None = None,
    parse_header: bool = True,
    require_uniform: bool = False,
    units: dict[str, str] | None = None,
) -> xr.Dataset:
    """Build a Dataset from a table with one column per variable.

    With ``parse_header``, headers with units (``acc y [m/s^2]``) give the variable name
    (``acc_y``), ``long_name`` and CF ``units``; ``units`` maps headers to units a file
    states beside them. With ``keep``, columns not asked for are left out when they are not
    numeric.
    """
    what = origin.what
    if len(frame) == 0:
        raise ValueError(f"{what} has a header but no data rows.")
    given = [k for k, v in (("time", time), ("dt", dt), ("step", step)) if v is not None]
    if len(given) > 1:
        raise ValueError(
            f"pass one of time= (a column), dt= (uniform sampling) or step= (a map), not "
            f"{' and '.join(given)}."
        )
    columns = _columns(frame.columns, what=what, parse_header=parse_header, units=units)
    origin.labels.update({c.name: c.raw for c in columns if c.raw != c.name})
    frame = frame.set_axis([c.name for c in columns], axis=1)
    index, values, index_attrs, used = _table_index(
        frame,
        columns,
        time=time,
        dt=dt,
        step=step,
        origin=origin,
        require_uniform=require_uniform,
    )
    wanted = None
    if keep is not None:
        wanted = {hit.name for k in keep if (hit := _find(columns, k)) is not None}
    data_vars: dict[str, Any] = {}
    for col in columns:
        if col.name in used:
            continue
        try:
            series = _numeric(frame[col.name], col, origin)
        except ValueError:
            if wanted is None or col.name in wanted:
                raise
            continue  # a text column nobody asked for
        attrs: dict[str, Any] = {}
        if col.label != col.name:
            attrs["long_name"] = col.label
        if col.units is not None:
            attrs["units"] = cf_units(col.units)
        data_vars[col.name] = (index, series, attrs)
    if not data_vars:
        raise ValueError(f"{what} has no data column besides its {index} column.")
    return xr.Dataset(data_vars, coords={index: (index, values, index_attrs)})


def from_array(
    arr: np.ndarray, *, dt: float | None, step: str | None, variables: Sequence[str] | None
) -> xr.Dataset:
    if arr.ndim == 1:
        arr = arr[:, None]
    if arr.ndim != 2:
        raise ValueError(
            f"a numpy array must be 1-D or 2-D (samples × variables); got {arr.shape}."
        )
    if dt is None and step is None:
        raise ValueError(
            "a numpy array carries no time: pass dt=<sampling interval in s> for a flow, or "
            "step='step' for a map (samples numbered 0, 1, ...)."
        )
    names = (
        list(variables)
        if variables is not None
        else (["x"] if arr.shape[1] == 1 else [f"x{i}" for i in range(arr.shape[1])])
    )
    if len(names) != arr.shape[1]:
        raise ValueError(f"variables names {len(names)} columns but the array has {arr.shape[1]}.")
    frame = pd.DataFrame(arr, columns=names)
    return from_table(
        frame, time=None, dt=dt, step=step, origin=Origin("the array"), parse_header=False
    )


# ---------------------------------------------------------------- labelled data


def _seconds(values: np.ndarray, units: Any, *, what: str) -> tuple[np.ndarray, dict[str, Any]]:
    """Times as float seconds: datetimes since the first, timedeltas, or numbers in
    ``units``; and the attributes that say where they came from."""
    if values.dtype.kind == "M":
        first = pd.Timestamp(values[0])
        seconds = (values - values[0]) / np.timedelta64(1, "s")
        return np.asarray(seconds, dtype=np.float64), {
            "comment": f"seconds since {first.isoformat()}"
        }
    if values.dtype.kind == "m":
        return np.asarray(values / np.timedelta64(1, "s"), dtype=np.float64), {}
    factor = seconds_per(None if units is None else str(units), what=what)
    attrs = {} if factor == 1.0 else {"comment": f"converted from {units}"}
    return np.asarray(values, dtype=np.float64) * factor, attrs


def index_labelled(
    ds: xr.Dataset, *, time: str | None, dt: float | None, step: str | None
) -> xr.Dataset:
    """Give a labelled Dataset the index that time=, dt= or step= asks for, and a datetime
    ``time`` its seconds."""
    if "time" in ds.coords:
        if time is not None and time != "time":
            raise ValueError(f"time={time!r}: the dataset already has a 'time' coordinate.")
        if ds["time"].dtype.kind in "mM":
            t, attrs = _seconds(ds["time"].values, None, what="the time coordinate")
            ds = ds.assign_coords(time=("time", t, attrs))
        if ds["time"].dtype.kind in "fiu":
            t = np.asarray(ds["time"].values, dtype=np.float64)
            _check_dt(t, dt, what="the time coordinate of the dataset")
        return ds
    if "step" in ds.coords or not ds.dims:
        return ds
    if time is not None:
        if time not in ds.variables or ds[time].ndim != 1:
            raise ValueError(
                f"time variable {time!r} not found (or not 1-D); available: {list(ds.variables)}."
            )
        dim = ds[time].dims[0]
        t, attrs = _seconds(ds[time].values, ds[time].attrs.get("units"), what=repr(time))
        ds = ds.drop_vars(time)
        if dim != "time":
            ds = ds.rename_dims({dim: "time"})
        return ds.assign_coords(time=("time", t, attrs))
    dim = next(iter(ds.dims))
    if dt is not None:
        return ds.rename({dim: "time"}).assign_coords(
            time=float(dt) * np.arange(ds.sizes[dim], dtype=np.float64)
        )
    if step is not None:
        if step != "step" and step not in ds.variables:
            raise ValueError(f"step variable {step!r} not found; available: {list(ds.variables)}.")
        if step == "step" or step not in ds.variables:
            steps = np.arange(ds.sizes[dim], dtype=np.int64)
        else:
            steps = _integer_steps(ds[step].values, name=step, what="the dataset")
            ds = ds.drop_vars(step)
        return ds.rename({dim: "step"}).assign_coords(step=steps)
    return ds


def resolve_variables(variables: Sequence[str], ds: xr.Dataset, origin: Origin | None) -> list[str]:
    """The variable names meant by ``variables``: names, or headers as written in a table."""
    out, missing = [], []
    by_header = {raw: name for name, raw in (origin.labels.items() if origin else [])}
    for v in variables:
        name = v if v in ds.data_vars else by_header.get(str(v).strip())
        if name is None and origin is not None:
            name = variable_name(split_header(v)[0])
        if name is None or name not in ds.data_vars:
            missing.append(v)
        else:
            out.append(name)
    if missing:
        raise ValueError(f"variables {missing} not found; available: {list(ds.data_vars)}.")
    return out


def one_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__
