"""Readers of the files test rigs write, into tables that ``load_trajectory`` indexes like a CSV.

NI TDMS (npTDMS), HDF5 (h5py), WAV (:mod:`scipy.io.wavfile`) and Parquet (pandas with
pyarrow) are read here, MATLAB ``.mat`` files by :mod:`chaoskit._matlab`. Each reader returns
a :class:`chaoskit._rig.RigTable`, which :func:`chaoskit._rig.rig_dataset` then indexes, so
the options and messages are the same as for a CSV file. :func:`content_format` picks the
reader by a file's first bytes when they contradict its suffix.
"""

from __future__ import annotations

import importlib.util
import logging
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn

import h5py
import numpy as np
import pandas as pd
import scipy.io.wavfile

from ._contract import ParameterError
from ._matlab import read_mat
from ._rig import (
    COMPLEX,
    NAME_LISTS,
    NUMERIC,
    UNIT_LISTS,
    RigTable,
    Unusable,
    as_text,
    as_texts,
    choose,
    datetimes_as_seconds,
    lookup,
    series_table,
    set_sampling_index,
    stated_sampling,
)
from ._tables import TIME_NAMES, one_line

try:  # optional: the ``formats`` extra
    import nptdms
except ImportError:  # pragma: no cover - exercised by monkeypatching in the tests
    nptdms = None
# pandas imports pyarrow itself when it reads Parquet
_HAS_PYARROW = importlib.util.find_spec("pyarrow") is not None

__all__ = ["SUFFIXES", "MissingPackageError", "content_format", "read_rig"]


#: Readable suffixes of rig files and their reader.
SUFFIXES = {
    ".mat": "mat",
    ".tdms": "tdms",
    ".h5": "hdf5",
    ".hdf5": "hdf5",
    ".he5": "hdf5",
    ".wav": "wav",
    ".parquet": "parquet",
    ".pq": "parquet",
}
_EXTRA = 'pip install "chaoskit[formats]"'
_LOAD = "load_trajectory"
_lit = ParameterError.literal
_HDF5 = b"\x89HDF\r\n\x1a\n"


class MissingPackageError(ImportError, ValueError):
    """An optional package a reader needs is not installed (also a ``ValueError``: a user's
    setup problem, reported in one line)."""


def _need(package: str, suffix: str) -> NoReturn:
    raise MissingPackageError(
        f"reading {suffix} files needs the {package} package, which is not installed: {_EXTRA}",
        name=package,
    )


# ---------------------------------------------------------------- what a file holds


def _hdf5_kind(path: Path) -> str | None:
    """``netcdf`` (netCDF-4), ``mat73`` (MATLAB variables) or ``hdf5`` for a readable HDF5
    file; ``None`` if h5py cannot open it."""
    try:
        with h5py.File(path, "r") as f:
            if "_NCProperties" in f.attrs:
                return "netcdf"
            found = {"netcdf": False, "mat73": False}

            def visit(_: str, obj: Any) -> None:
                if obj.attrs.get("CLASS") == b"DIMENSION_SCALE" or "DIMENSION_LIST" in obj.attrs:
                    found["netcdf"] = True
                if "MATLAB_class" in obj.attrs:
                    found["mat73"] = True

            f.visititems(visit)
    except (OSError, ValueError, KeyError):
        return None
    return "netcdf" if found["netcdf"] else "mat73" if found["mat73"] else "hdf5"


def content_format(path: Path, expected: str) -> str:
    """The reader for ``path``: the one its first bytes call for, else the suffix's
    ``expected`` one (text tables and MATLAB v4 files have no signature).

    A MATLAB v7.3 file is HDF5 with a MATLAB header; an HDF5 file is read as netCDF-4 when
    it has netCDF's dimension scales, as MATLAB v7.3 when its objects carry ``MATLAB_class``.
    """
    try:
        with path.open("rb") as fh:
            head = fh.read(128)
            if head.startswith(b"MATLAB") and head[126:128] in (b"IM", b"MI"):
                return "mat73" if head[124:126] in (b"\x00\x02", b"\x02\x00") else "mat"
            hdf5 = head.startswith(_HDF5)
            for offset in (512, 1024, 2048, 4096):  # after a user block
                fh.seek(offset)
                hdf5 = hdf5 or fh.read(8) == _HDF5
    except OSError:
        return expected
    if hdf5:
        kind = _hdf5_kind(path)
        if kind is None:  # damaged: let the suffix's reader say so
            return "mat73" if expected == "mat" else expected
        return kind
    if head[:4] == b"TDSm":
        return "tdms"
    if head[:4] in (b"RIFF", b"RF64") and head[8:12] == b"WAVE":
        return "wav"
    if head[:4] == b"PAR1":
        return "parquet"
    if head[:4] == b"PK\x03\x04":
        return "npz"
    if head[:4] in (b"CDF\x01", b"CDF\x02", b"CDF\x05"):
        return "netcdf"
    return expected


# ---------------------------------------------------------------- NI TDMS


class _Complaints(logging.Handler):
    """The warnings npTDMS logs about a damaged file."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage().split(",")[0])


def _read_tdms(
    path: Path, *, group: str | None, keep: Any, time: str | None, dt: Any, step: Any
) -> RigTable:
    if nptdms is None:
        _need("npTDMS", ".tdms")
    complaints = _Complaints()
    logger = logging.getLogger("nptdms")
    logger.addHandler(complaints)
    propagate, logger.propagate = logger.propagate, False  # the error below says it all
    try:
        tdms = nptdms.TdmsFile.read(path)
    except Exception as exc:  # npTDMS raises many kinds on damaged files; all mean "unreadable"
        complaints.messages.insert(0, one_line(exc))
    finally:
        logger.removeHandler(complaints)
        logger.propagate = propagate
    if complaints.messages:  # npTDMS reads what it can of a truncated file, and only logs
        raise ValueError(
            f"{path} is not a readable TDMS file ({complaints.messages[0]}); is it truncated, "
            "or another format with a .tdms suffix?"
        )
    chosen = choose([g.name for g in tdms.groups() if g.channels()], group, path, "group")
    if chosen is None:
        raise ValueError(f"{path} holds no channel with data.")
    grp = tdms[chosen]
    what = f"group {grp.name!r} of {path}"
    items: dict[str, Any] = {}
    labels: dict[str, Any] = {}
    waveform: dict[str, tuple[float, float, Any]] = {}
    for channel in grp.channels():
        name, props, data = channel.name, channel.properties, channel[:]
        if data.dtype.kind == "c":
            items[name] = Unusable(COMPLEX, fatal=True)
        elif data.dtype.kind in NUMERIC + "mM":
            items[name] = data
        else:
            items[name] = Unusable(f"holds {data.dtype} values", fatal=False)
        unit = as_text(props.get("unit_string"))
        if unit:
            labels[name] = {"units": unit}
        if "wf_increment" in props:
            offset = float(props.get("wf_start_offset", 0.0))
            waveform[name] = (float(props["wf_increment"]), offset, props.get("wf_start_time"))
    table = series_table(items, what=what, kind="channel", keep=keep, time=time, labels=labels)
    datetimes_as_seconds(table)
    used = [c for c in table.frame.columns if c in waveform]
    increments = {c: waveform[c][0] for c in used}
    if len({*increments.values()}) > 1:
        listed = ", ".join(f"{k}: {v:g} s" for k, v in increments.items())
        raise ParameterError(
            f"the channels of {_lit(what)} are sampled at different intervals "
            f"({_lit(listed)}); pass {{variables}} with channels of one interval{{to}}.",
            function=_LOAD,
        )
    if used:
        increment, offset, start = waveform[used[0]]
        if not np.isfinite(increment) or increment <= 0:
            raise ValueError(
                f"channel {used[0]!r} of {what} has the time increment "
                f"wf_increment = {increment!r}; it must be finite and > 0."
            )
        n = len(table.frame)
        table.frame.index = pd.Index(offset + increment * np.arange(n, dtype=np.float64))
        comment = "from the channel properties wf_increment and wf_start_offset"
        if start is not None:
            comment = f"seconds since {pd.Timestamp(start).isoformat()}, {comment}"
        table.time_attrs[""] = {"comment": comment}
    elif (time, dt, step, table.time) == (None,) * 4 and not set(TIME_NAMES) & set(table.frame):
        first = _lit(table.frame.columns[0])
        raise ParameterError(
            f"channel {first!r} of {_lit(what)} has no time increment (wf_increment) and "
            f"the group has no time channel (looked for {list(TIME_NAMES)}); pass {{dt}} (the "
            "sampling interval, s), {time} (the time channel) or {step} (a map){to}.",
            function=_LOAD,
        )
    table.where = f" (group {grp.name!r})"
    return table


# ---------------------------------------------------------------- HDF5, WAV, Parquet


def _h5_group(f: h5py.File, group: str | None, path: Path) -> h5py.Group:
    with_data = []
    f.visititems(
        lambda name, obj: (
            with_data.append(name)
            if isinstance(obj, h5py.Group)
            and any(isinstance(v, h5py.Dataset) for v in obj.values())
            else None
        )
    )
    if group is not None and isinstance(f.get(group.strip("/") or "/"), h5py.Group):
        return f[group.strip("/") or "/"]
    if group is None and any(isinstance(v, h5py.Dataset) for v in f.values()):
        return f
    chosen = choose(sorted(with_data), group, path, "group")
    return f if chosen is None else f[chosen]


def _h5_items(node: h5py.Group) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    items: dict[str, Any] = {}
    labels: dict[str, Any] = {}
    attrs: dict[str, Any] = {}
    for name, obj in node.items():
        if not isinstance(obj, h5py.Dataset):
            continue
        if obj.dtype.kind == "c" or set(obj.dtype.names or ()) in ({"r", "i"}, {"real", "imag"}):
            items[name] = Unusable(COMPLEX, fatal=True)
        elif obj.dtype.kind not in NUMERIC:
            items[name] = Unusable(f"holds {obj.dtype} values", fatal=False)
        else:
            items[name] = obj[()]
        settings = dict(obj.attrs)
        unit = (lookup(settings, UNIT_LISTS) or (None, None))[1]
        names = (lookup(settings, NAME_LISTS) or (None, None))[1]
        labels[name] = {
            "units": as_texts(unit) if isinstance(unit, np.ndarray) else as_text(unit),
            "names": as_texts(names) if isinstance(names, np.ndarray) else None,
        }
        long_name = as_text(obj.attrs.get("long_name"))
        if long_name:
            attrs[name] = {"long_name": long_name}
    return items, labels, attrs


def _read_hdf5(path: Path, *, group: str | None, keep: Any, time: str | None) -> RigTable:
    try:
        with h5py.File(path, "r") as f:
            node = _h5_group(f, group, path)
            items, labels, attrs = _h5_items(node)
            settings = {k: v for k, v in node.attrs.items()}
            where = node.name
    except (OSError, KeyError, TypeError) as exc:
        raise ValueError(
            f"{path} is not a readable HDF5 file ({one_line(exc)}); is it truncated?"
        ) from None
    what = str(path) if where == "/" else f"group {where!r} of {path}"
    time_attrs = {}
    for name, label in labels.items():  # CF time units: "seconds since 2024-05-01 10:00"
        unit = label.get("units")
        if isinstance(unit, str) and " since " in unit:
            label["units"], since = unit.split(" since ", 1)
            time_attrs[name] = {"comment": f"{label['units']} since {since}"}
    sampling = stated_sampling(settings, what=what)
    table = series_table(items, what=what, kind="dataset", keep=keep, time=time, labels=labels)
    set_sampling_index(table, sampling)
    table.time_attrs.update(time_attrs)
    for name, extra in attrs.items():
        if name in table.frame:
            table.attrs.setdefault(name, {}).update(extra)
    table.where = "" if where == "/" else f" (group {where!r})"
    return table


def _read_wav(path: Path, *, keep: Any) -> RigTable:
    try:
        rate, data = scipy.io.wavfile.read(path)
    except Exception as exc:  # scipy raises many kinds on damaged files; all mean "unreadable"
        raise ValueError(
            f"{path} is not a readable WAV file ({one_line(exc)}); is it truncated?"
        ) from None
    if rate <= 0:
        raise ValueError(f"{path} states a sample rate of {rate} Hz; it must be > 0.")
    samples = data.reshape(len(data), -1)
    kind = samples.dtype
    if kind.kind in "iu":  # PCM: counts to the fraction of full scale
        bits = 8 * kind.itemsize
        full = float(2 ** (bits - 1))
        offset = full if kind.kind == "u" else 0.0  # 8-bit PCM is unsigned, centred on 128
        values = (samples.astype(np.float64) - offset) / full
        counts = f"(counts - {offset:g})" if offset else "counts"
        extra = {
            "units": "1",
            "pcm_format": str(kind),
            "pcm_full_scale": full,
            "comment": f"fraction of full scale ({kind} PCM: {counts} / {full:g}); multiply "
            "by the logger's "
            "full-scale value for its units",
        }
    else:
        values = samples.astype(np.float64)
        extra = {"pcm_format": str(kind)}
    items = {f"ch{j + 1}": values[:, j] for j in range(values.shape[1])}
    table = series_table(items, what=str(path), kind="channel", keep=keep, time=None)
    for name in table.frame.columns:
        table.attrs[name] = {"long_name": f"channel {name[2:]}", **extra}
    table.frame.index = pd.Index(np.arange(len(table.frame), dtype=np.float64) / rate)
    table.time_attrs[""] = {"comment": f"from the sample rate of the file, {rate} Hz"}
    table.global_attrs["wav_sample_rate"] = int(rate)
    return table


def _read_parquet(path: Path) -> RigTable:
    if not _HAS_PYARROW:
        _need("pyarrow", ".parquet")
    try:
        frame = pd.read_parquet(path, engine="pyarrow")
    except Exception as exc:  # pyarrow raises many kinds on damaged files
        raise ValueError(
            f"{path} is not a readable Parquet file ({one_line(exc)}); is it truncated?"
        ) from None
    frame.columns = [str(c) for c in frame.columns]
    if not isinstance(frame.index, pd.RangeIndex) and frame.index.dtype.kind not in "fmM":
        frame = frame.reset_index()  # e.g. an integer step index: a column again
    table = RigTable(frame, what=str(path), kind="column")
    datetimes_as_seconds(table)
    return table


def read_rig(
    path: Path,
    fmt: str,
    *,
    group: str | None,
    keep: Sequence[str] | None,
    time: str | None,
    dt: float | None,
    step: str | None,
) -> RigTable:
    """Read a rig file with the reader ``fmt`` (see :func:`content_format`)."""
    if fmt in ("mat", "mat73"):
        return read_mat(path, fmt, group=group, keep=keep, time=time)
    if fmt == "tdms":
        return _read_tdms(path, group=group, keep=keep, time=time, dt=dt, step=step)
    if fmt == "hdf5":
        return _read_hdf5(path, group=group, keep=keep, time=time)
    if fmt == "wav":
        return _read_wav(path, keep=keep)
    return _read_parquet(path)
