"""Tables of rig files: the series a reader found, before and after indexing.

The readers of :mod:`chaoskit._formats` and :mod:`chaoskit._matlab` return a
:class:`RigTable`: equally long 1-D series in a DataFrame (names as in the file), their units
as written, the file's own time axis as a float index when it has one (a waveform increment,
a sample rate) and the resolution of its time stamps. :func:`series_table` builds one from
the entries of a file (vectors, and matrices split into one column per channel);
:func:`rig_dataset` indexes it with :func:`chaoskit._tables.from_table`, so the options and
messages are the same as for a CSV file.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ._contract import ParameterError, variable_name
from ._tables import TIME_NAMES, Origin, from_table
from ._units import seconds_per, split_header

__all__ = [
    "COMPLEX",
    "NAME_LISTS",
    "NUMERIC",
    "UNIT_LISTS",
    "RigTable",
    "Unusable",
    "as_text",
    "as_texts",
    "choose",
    "datetimes_as_seconds",
    "lookup",
    "rig_dataset",
    "series_table",
    "set_sampling_index",
    "stated_sampling",
]


_LOAD = "load_trajectory"
_lit = ParameterError.literal
# scalars that state the sampling of the series beside them (MATLAB variables, HDF5 attributes)
_DT_NAMES = ("dt", "Ts", "sample_time", "sampling_interval")
_RATE_NAMES = ("fs", "Fs", "FS", "sample_rate", "sampling_rate", "srate")
# char arrays (MATLAB) or attributes (HDF5) that name the columns of a matrix, or give units
NAME_LISTS = ("names", "channel_names", "channels", "labels", "varnames", "variable_names")
UNIT_LISTS = ("units", "channel_units", "unit")
NUMERIC = "fiub"
COMPLEX = "is complex; chaoskit reads real series: save real and imaginary parts as two variables"


@dataclass
class RigTable:
    """Series read from a rig file, before the index is chosen."""

    frame: pd.DataFrame  # one column per series, named as in the file; float index: time, s
    what: str  # the file (and its group or struct) for messages
    kind: str = "variable"  # what messages call a column: variable, channel, dataset, column
    where: str = ""  # the group or struct read, for the history (" (group 'rig')")
    units: dict[str, str] = field(default_factory=dict)  # column -> units as written
    attrs: dict[str, dict[str, Any]] = field(default_factory=dict)  # column -> more attrs
    time: str | None = None  # the time column when the user names none and no TIME_NAMES
    time_attrs: dict[str, Any] = field(default_factory=dict)  # of the time, by column or ""
    quantum: dict[str, float] = field(default_factory=dict)  # stamp resolution ("": index)
    global_attrs: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Unusable:
    """An entry of a file that is not a numeric series; ``fatal`` if it looks like data."""

    reason: str
    fatal: bool


def choose(names: list[str], group: str | None, path: Path, noun: str) -> str | None:
    """The group (or struct) of ``names`` that ``group`` names, else the only one (``None``
    for none)."""
    if group is not None and group not in names:
        raise ParameterError(
            f"{_lit(path)} has no {noun} {_lit(group)!r}; its {noun}s are {_lit(names)}; pass "
            "one of them with {group}{to}.",
            function=_LOAD,
        )
    if group is None and len(names) > 1:
        # a name a shell or the message template would misread is quoted after the option
        plain = re.fullmatch(r"[\w.\-/]+", names[0]) is not None
        pick = (
            f"{{group={names[0]}}}{{to}}" if plain else f"{{group}}{{to}}, e.g. {_lit(names[0])!r}"
        )
        raise ParameterError(
            f"{_lit(path)} holds the {noun}s {_lit(names)}; pick one with {pick}.",
            function=_LOAD,
        )
    return group if group is not None else (names[0] if names else None)


# ---------------------------------------------------------------- series into a table


def _key(text: Any) -> str:
    return variable_name(str(text).split("(")[0].split("[")[0])


def _wanted(name: str, item: Any, keep: Sequence[str] | None, columns: Any = None) -> bool:
    """True if ``keep`` names the entry ``name`` or, for a matrix, one of its ``columns``
    (or ``name_1``, ``name_2``, ...)."""
    if keep is None:
        return True
    keys = {_key(k) for k in keep} | {str(k).strip() for k in keep}
    if name in keys or _key(name) in keys:
        return True
    if not isinstance(item, np.ndarray) or item.ndim != 2:
        return False
    named = any(c in keys or _key(c) in keys for c in columns or ())
    return named or any(k.startswith(f"{name}_") for k in keys)


def _seconds(values: np.ndarray) -> tuple[np.ndarray, str, float]:
    """Datetimes or timedeltas as seconds (datetimes: since the first), a comment saying
    since when, and their resolution in seconds."""
    unit, count = np.datetime_data(values.dtype)
    quantum = float(np.ones(1, dtype=f"m8[{count}{unit}]")[0] / np.timedelta64(1, "s"))
    if values.dtype.kind == "M":
        first = pd.Timestamp(values[0])
        seconds = (values - values[0]) / np.timedelta64(1, "s")
        return np.asarray(seconds, dtype=np.float64), f"seconds since {first.isoformat()}", quantum
    return np.asarray(values / np.timedelta64(1, "s"), dtype=np.float64), "", quantum


def as_text(value: Any) -> str | None:
    """An attribute or MATLAB char array as a string (``None`` for anything else)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace").strip()
    if isinstance(value, str):
        return value.strip()
    if isinstance(value, np.ndarray) and value.dtype.kind in "SU" and value.size == 1:
        return as_text(value.reshape(-1)[0])
    return None


def as_texts(value: Any) -> list[str] | None:
    """A list of strings (a cellstr, a char matrix, a string array attribute), else None."""
    if isinstance(value, list) and all(isinstance(v, str) for v in value):
        return [v.strip() for v in value]
    if isinstance(value, np.ndarray) and value.dtype.kind in "SUO" and value.ndim == 1:
        out = [text for v in value if (text := as_text(v)) is not None]
        return out if len(out) == len(value) else None
    return None


def lookup(space: dict[str, Any], names: Sequence[str]) -> tuple[str, Any] | None:
    lower = {k.lower(): k for k in space}
    for name in names:
        key = name if name in space else lower.get(name.lower())
        if key is not None:
            return key, space[key]
    return None


def stated_sampling(space: dict[str, Any], *, what: str) -> tuple[float, str] | None:
    """A sampling interval stated by a scalar named dt, Ts, fs, ... and where it came from."""
    for names, rate in ((_DT_NAMES, False), (_RATE_NAMES, True)):
        hit = lookup(space, names)
        if hit is None:
            continue
        value = np.asarray(hit[1])
        if value.size != 1 or value.dtype.kind not in "fiu":
            continue
        number = float(value.reshape(-1)[0])
        if not np.isfinite(number) or number <= 0:
            raise ValueError(
                f"{hit[0]} = {number!r} in {what} is not a sampling "
                f"{'rate' if rate else 'interval'}; it must be finite and > 0."
            )
        if rate:
            return 1.0 / number, f"from the sampling rate {hit[0]} = {number:g} Hz"
        return number, f"from the sampling interval {hit[0]} = {number:g} s"
    return None


def _orient(name: str, arr: np.ndarray, n: int | None, *, kind: str, what: str) -> np.ndarray:
    """A matrix as samples × channels: one column per channel, unless its rows match no
    length and its columns do."""
    rows, cols = arr.shape
    if n is not None and rows != n and cols == n:
        return arr.T
    if n is None and rows < cols:
        raise ValueError(
            f"{kind} {name!r} of {what} is a {rows} × {cols} matrix: chaoskit reads one "
            f"column per channel (samples down the rows); store its transpose."
        )
    return arr


def _columns(
    items: dict[str, Any],
    *,
    what: str,
    kind: str,
    keep: Sequence[str] | None,
    time: str | None,
    labels: dict[str, Any] | None = None,
    first: int = 0,
) -> tuple[dict[str, np.ndarray], dict[str, str], dict[str, dict[str, Any]]]:
    """Equally long 1-D columns from the ``items`` of a file: vectors as they are, matrices
    split into one column per channel. ``labels`` maps an item to its units (a string, or a
    list for a matrix) under ``"units"`` and to the names of a matrix's columns under
    ``"names"``; unnamed columns are numbered from ``first``. Entries nobody asked for (not
    in ``keep``) are skipped when unusable."""
    labels = labels or {}
    timeish = {time, *TIME_NAMES} - {None}
    series: dict[str, np.ndarray] = {}
    skipped: list[str] = []
    for name, item in items.items():
        if isinstance(item, np.ndarray) and item.ndim == 2 and 1 in item.shape:
            item = item.reshape(-1)  # MATLAB keeps vectors as 1 × n or n × 1
        if isinstance(item, np.ndarray) and item.ndim > 2:
            shape = " × ".join(map(str, item.shape))
            item = Unusable(
                f"has {item.ndim} dimensions ({shape}); chaoskit reads vectors "
                "and matrices with one column per channel",
                fatal=True,
            )
        needed = name in timeish or _wanted(name, item, keep, labels.get(name, {}).get("names"))
        if isinstance(item, Unusable):
            if needed and (item.fatal or keep is not None):
                fix = "" if keep is not None else "; pass {variables} without it{to}"
                raise ParameterError(
                    f"{kind} {_lit(name)!r} of {_lit(what)} {_lit(item.reason)}" + fix + ".",
                    function=_LOAD,
                )
            skipped.append(f"{name!r} ({re.split(r'[;(]', item.reason)[0].strip()})")
            continue
        if not isinstance(item, np.ndarray) or item.dtype.kind not in NUMERIC + "mM":
            skipped.append(f"{name!r} ({'a struct' if isinstance(item, dict) else 'text'})")
            continue
        if item.size <= 1 or not needed:
            continue  # empty arrays and scalars (settings, a sample rate)
        series[name] = item
    lengths = {k: len(v) if v.ndim == 1 else None for k, v in series.items()}
    n_time = next((lengths[k] for k in (time, *TIME_NAMES) if k in lengths), None)
    vectors = {v for v in lengths.values() if v is not None}
    n = n_time if n_time is not None else (vectors.pop() if len(vectors) == 1 else None)
    columns: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    attrs: dict[str, dict[str, Any]] = {}
    for name, arr in series.items():
        unit = labels.get(name, {}).get("units")
        if arr.ndim == 1:
            columns[name] = arr
            if isinstance(unit, str) and unit:
                units[name] = unit
            continue
        matrix = _orient(name, arr, n, kind=kind, what=what)
        names = labels.get(name, {}).get("names")
        if names is None or len(names) != matrix.shape[1] or len(set(names)) != len(names):
            names = [f"{name}_{j + first}" for j in range(matrix.shape[1])]
            for j, col in enumerate(names):
                index = f"(:,{j + 1})" if first == 1 else f"[:, {j}]"
                attrs[col] = {"long_name": f"{name}{index}"}
        per_column = unit if isinstance(unit, list) and len(unit) == len(names) else None
        for j, col in enumerate(names):
            if col in columns or col in series:
                raise ValueError(
                    f"column {j + first} of {kind} {name!r} of {what} "
                    f"would be named {col!r}, which {what} already uses."
                )
            columns[col] = matrix[:, j]
            text = per_column[j] if per_column else unit if isinstance(unit, str) else None
            if text:
                units[col] = text
    if not columns:
        found = f" (it holds {', '.join(skipped)})" if skipped else ""
        raise ValueError(
            f"{what} holds no numeric series{found}; chaoskit reads vectors and "
            "matrices with one column per channel."
        )
    sizes = {k: len(v) for k, v in columns.items()}
    if len(set(sizes.values())) > 1:
        listed = ", ".join(f"{k}: {v}" for k, v in sizes.items())
        raise ParameterError(
            f"the {kind}s of {_lit(what)} have unequal lengths ({_lit(listed)}); pass "
            "{variables} with equally long ones{to}.",
            function=_LOAD,
        )
    return columns, units, attrs


def series_table(items: dict[str, Any], *, what: str, kind: str, **options: Any) -> RigTable:
    """The table of :func:`_columns`, with the resolution of its single-precision columns."""
    columns, units, attrs = _columns(items, what=what, kind=kind, **options)
    table = RigTable(pd.DataFrame(columns), what=what, kind=kind, units=units, attrs=attrs)
    for name, arr in columns.items():
        if arr.dtype == np.float32:  # stamps rounded to single precision
            table.quantum[name] = float(np.spacing(np.max(np.abs(arr)), dtype=np.float32))
    return table


def set_sampling_index(table: RigTable, sampling: tuple[float, str] | None) -> None:
    """The sampling interval a file states as the time index of its table."""
    if sampling is not None:
        step, origin = sampling
        table.frame.index = pd.Index(step * np.arange(len(table.frame), dtype=np.float64))
        table.time_attrs[""] = {"comment": f"{origin} in the file"}


def datetimes_as_seconds(table: RigTable) -> None:
    """Datetime and timedelta columns (and index) as float seconds, the time column by
    default if no other is named like time."""
    frame = table.frame
    for name in list(frame.columns):
        values = frame[name].to_numpy()
        if values.dtype.kind in "mM":
            seconds, comment, quantum = _seconds(values)
            frame[name] = seconds
            table.units[str(name)] = "s"
            table.quantum[str(name)] = quantum
            table.time_attrs[str(name)] = {"comment": comment} if comment else {}
            if table.time is None and not any(str(c) in TIME_NAMES for c in frame.columns):
                table.time = str(name)
    index = frame.index
    if isinstance(index, (pd.DatetimeIndex, pd.TimedeltaIndex)):
        seconds, comment, quantum = _seconds(index.to_numpy())
        frame.index = pd.Index(seconds)
        table.quantum[""] = quantum
        table.time_attrs[""] = {"comment": comment} if comment else {}


# ---------------------------------------------------------------- the table indexed


def rig_dataset(
    table: RigTable,
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    keep: Sequence[str] | None,
    require_uniform: bool,
) -> tuple[xr.Dataset, Origin]:
    """The table of a rig file indexed like any table: its own time axis (a time column, a
    waveform increment, a sample rate) unless ``time``, ``dt`` or ``step`` says otherwise;
    units and attributes the file states; and where its rows came from."""
    origin = Origin(table.what, kind=table.kind, strict_time=True)
    asked = time is not None or dt is not None or step is not None
    ds = from_table(
        table.frame,
        time=time if asked else table.time,
        dt=dt,
        step=step,
        origin=origin,
        keep=keep,
        require_uniform=require_uniform,
        units=table.units,
    )
    by_raw = {raw: name for name, raw in origin.labels.items()}
    for raw, extra in table.attrs.items():
        name = by_raw.get(raw, raw)
        if name in ds.data_vars:
            for key, value in extra.items():
                ds[name].attrs.setdefault(key, value)
    source = origin.time_source
    if "time" in ds.coords and source is not None:
        attrs = ds["time"].attrs
        for key, value in table.time_attrs.get(source, {}).items():
            attrs[key] = f"{value}; {attrs[key]}" if key in attrs else value
        units = table.units.get(source) or split_header(source)[1]
        per = seconds_per(units, what=source) if source else 1.0
        origin.time_quantum = table.quantum.get(source, 0.0) * per
    ds.attrs.update(table.global_attrs)
    return ds, origin
