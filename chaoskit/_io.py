"""Reading and writing trajectories: the one place where files and foreign containers enter.

Formats
-------
netCDF-4 (``.nc``, ``.nc4``, ``.h5``)
    Written with ``engine="h5netcdf"``; every attribute is kept.
CSV (``.csv``, ``.txt``, ``.tsv``)
    One column per variable. ``save_trajectory`` writes the attributes as a JSON comment
    line (``# chaoskit-attrs: {...}``) above the header so a round trip keeps them; CSV files
    from elsewhere need no such line. Their headers may carry units (``time (s)``,
    ``acc y [m/s^2]``, ``x / mm``), title lines may be skipped (``skip_rows``), numbers may
    use a decimal comma (``decimal=","``) and missing values are refused, dropped or
    interpolated (``nan``).
npz (``.npz``)
    One array per variable; ``save_trajectory`` adds a ``__chaoskit_attrs__`` JSON entry.
Files from test rigs (read only)
    MATLAB ``.mat`` (v4, v5, v7.3), NI TDMS, HDF5, WAV and Parquet, read by
    :mod:`chaoskit._formats` and :mod:`chaoskit._matlab` into tables that are indexed like a
    CSV file; a file whose content does not match its suffix is read by its content.

pandas objects with a ``DatetimeIndex``, ``TimedeltaIndex`` or float index, and xarray
objects with a datetime ``time``, are indexed by their time in seconds.

This module holds the entry points and the dispatch by source, chaoskit's own netCDF and npz
files, and the atomic writes. The reading steps are :mod:`chaoskit._tables` (tables and
labelled containers into indexed Datasets, with :mod:`chaoskit._units` for the units in
headers), :mod:`chaoskit._csvfiles` (text tables), :mod:`chaoskit._missing` (missing values)
and :mod:`chaoskit._resample` (irregular time stamps).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import uuid
import zipfile
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from . import _formats
from ._contract import ParameterError, append_history, validate_trajectory
from ._csvfiles import ATTRS_LINE, apply_payload, read_csv
from ._missing import NAN_POLICIES, missing_values
from ._resample import RESAMPLE_METHODS, time_axis
from ._rig import rig_dataset
from ._tables import Origin, from_array, from_table, index_labelled, one_line, resolve_variables
from ._validate import check_choice, check_int

__all__ = [
    "IN_MEMORY_LIMIT",
    "NAN_POLICIES",
    "RESAMPLE_METHODS",
    "SPACE_MARGIN",
    "check_free_space",
    "load_trajectory",
    "save_trajectory",
    "write_netcdf",
]


NETCDF_SUFFIXES = {".nc", ".nc4", ".netcdf", ".h5", ".hdf5"}
CSV_SUFFIXES = {".csv", ".txt", ".tsv"}
NPZ_SUFFIXES = {".npz"}
_NPZ_ATTRS = "__chaoskit_attrs__"
_LOAD = "load_trajectory"
_lit = ParameterError.literal


def _format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in NETCDF_SUFFIXES:
        return "netcdf"
    if suffix in CSV_SUFFIXES:
        return "csv"
    if suffix in NPZ_SUFFIXES:
        return "npz"
    accepted = sorted(NETCDF_SUFFIXES | CSV_SUFFIXES | NPZ_SUFFIXES)
    raise ValueError(f"unknown file format {suffix!r} for {path}; accepted suffixes: {accepted}.")


def _read_format(path: Path) -> str:
    """The reader of ``path`` by its suffix: ``netcdf``, ``csv``, ``npz`` or a rig format of
    :data:`chaoskit._formats.SUFFIXES`; :func:`_formats.content_format` then corrects a
    suffix that does not match the content."""
    suffix = path.suffix.lower()
    if suffix in _formats.SUFFIXES:
        return _formats.SUFFIXES[suffix]
    if suffix in NETCDF_SUFFIXES | CSV_SUFFIXES | NPZ_SUFFIXES:
        return _format_of(path)
    accepted = sorted(NETCDF_SUFFIXES | CSV_SUFFIXES | NPZ_SUFFIXES | set(_formats.SUFFIXES))
    raise ValueError(f"unknown file format {suffix!r} for {path}; accepted suffixes: {accepted}.")


def _attrs_payload(ds: xr.Dataset) -> dict[str, Any]:
    return {
        "global": dict(ds.attrs),
        "variables": {str(k): dict(v.attrs) for k, v in ds.variables.items()},
    }


def _read_npz(
    path: Path, *, time: str | None, dt: float | None, step: str | None, keep: Any
) -> xr.Dataset:
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ValueError(f"{path} is not a readable npz file ({one_line(exc)}).") from None
    payload = None
    if _NPZ_ATTRS in arrays:
        payload = json.loads(str(arrays.pop(_NPZ_ATTRS)))
    bad = [k for k, v in arrays.items() if v.ndim != 1]
    if bad:
        raise ValueError(f"npz entries must be 1-D series; {bad} are not.")
    lengths = {k: len(v) for k, v in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"npz entries have different lengths: {lengths}.")
    if not arrays:
        raise ValueError(f"{path} holds no arrays.")
    ds = from_table(
        pd.DataFrame(arrays),
        time=time,
        dt=dt,
        step=step,
        origin=Origin(str(path)),
        keep=keep,
        parse_header=payload is None,
    )
    return apply_payload(ds, payload) if payload else ds


def _read_netcdf(path: Path) -> xr.Dataset:
    try:
        with xr.open_dataset(path, engine="h5netcdf") as opened:
            return opened.load()
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(
            f"{path} is not a readable netCDF-4 file ({one_line(exc)}); is it truncated, or "
            "another format with a .nc suffix?"
        ) from None


# ---------------------------------------------------------------- load_trajectory


def _read_source(
    source: Any,
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    variables: Sequence[str] | None,
    require_uniform: bool,
    skip_rows: int,
    decimal: str,
    group: str | None = None,
) -> tuple[xr.Dataset, Origin, str]:
    """The source as a Dataset (not yet checked), where its rows come from, and a phrase
    saying what it was."""
    is_path = isinstance(source, (str, os.PathLike))
    if (skip_rows or decimal != ".") and not (
        is_path and Path(source).suffix.lower() in CSV_SUFFIXES
    ):
        raise ParameterError(
            "{skip_rows} and {decimal} apply to text tables (.csv, .txt, .tsv) only.",
            function=_LOAD,
        )
    if group is not None and not is_path:
        raise ParameterError(
            "{group} applies to files with groups or structs (.mat, .tdms, .h5) only.",
            function=_LOAD,
        )
    if is_path:
        path = Path(source)
        fmt = _read_format(path)
        if not path.exists():
            raise FileNotFoundError(f"no such trajectory file: {path}")
        if path.is_dir():
            raise ValueError(f"{path} is a folder; pass a trajectory file.")
        fmt = _formats.content_format(path, fmt)
        if group is not None and fmt not in ("mat", "mat73", "tdms", "hdf5"):
            raise ParameterError(
                "{group} applies to files with groups or structs (.mat, .tdms, .h5) only.",
                function=_LOAD,
            )
        if fmt not in ("netcdf", "csv", "npz"):
            table = _formats.read_rig(
                path, fmt, group=group, keep=variables, time=time, dt=dt, step=step
            )
            ds, origin = rig_dataset(
                table, time=time, dt=dt, step=step, keep=variables, require_uniform=require_uniform
            )
            return ds, origin, f"loaded from {path.name}{table.where}"
        origin = Origin(str(path), kind="variable" if fmt == "netcdf" else "column")
        if fmt == "netcdf":
            ds = index_labelled(_read_netcdf(path), time=time, dt=dt, step=step)
        elif fmt == "csv":
            ds, origin = read_csv(
                path,
                time=time,
                dt=dt,
                step=step,
                keep=variables,
                skip_rows=skip_rows,
                decimal=decimal,
            )
        else:
            ds = _read_npz(path, time=time, dt=dt, step=step, keep=variables)
        return ds, origin, f"loaded from {path.name}"
    if isinstance(source, (xr.Dataset, xr.DataArray)):
        if isinstance(source, xr.DataArray):
            ds, text = source.to_dataset(name=str(source.name or "x")), "an xarray.DataArray"
        else:
            ds, text = source.copy(), "an xarray.Dataset"
        ds = index_labelled(ds, time=time, dt=dt, step=step)
        return ds, Origin(f"the {text.split()[1]}", kind="variable"), f"taken from {text}"
    if isinstance(source, (pd.DataFrame, pd.Series)):
        kind = type(source).__name__
        frame = source if kind == "DataFrame" else source.to_frame(str(source.name or "x"))
        origin = Origin(f"the {kind}")
        ds = from_table(
            frame,
            time=time if kind == "DataFrame" else None,
            dt=dt,
            step=step,
            origin=origin,
            keep=variables,
            require_uniform=require_uniform,
        )
        return ds, origin, f"taken from a pandas.{kind}"
    if isinstance(source, (np.ndarray, list, tuple)):
        arr = np.asarray(source)
        if arr.dtype.kind not in "fiub":
            raise ValueError(f"the array is not numeric (dtype {arr.dtype}).")
        ds = from_array(arr, dt=dt, step=step, variables=variables)
        return ds, Origin("the array"), "taken from a numpy array"
    raise TypeError(
        f"cannot load a trajectory from {type(source).__name__}; pass a file path, "
        "DataFrame, xarray object or numpy array."
    )


def load_trajectory(
    source: Any,
    *,
    time: str | None = None,
    dt: float | None = None,
    step: str | None = None,
    variables: Sequence[str] | None = None,
    require_uniform: bool = False,
    skip_rows: int = 0,
    decimal: str = ".",
    nan: str = "refuse",
    group: str | None = None,
    resample: str | None = None,
) -> xr.Dataset:
    """Load a trajectory from a file or an in-memory container and validate it.

    Parameters
    ----------
    source
        A path to a netCDF (``.nc``), CSV (``.csv``/``.txt``/``.tsv``) or ``.npz`` file, a
        file from a test rig (MATLAB ``.mat`` v4/v5/v7.3, NI ``.tdms``, HDF5 ``.h5``/
        ``.hdf5``, ``.wav``, ``.parquet``; see "Files from a test rig" in
        ``docs/data-model.md``), a :class:`pandas.DataFrame` or ``Series``, an
        :class:`xarray.Dataset` or ``DataArray``, or a numpy array (1-D, or 2-D with one
        column per variable). A file whose content does not match its suffix (a v7.3
        ``.mat`` is HDF5) is read by its content.
    time
        Name of the time column of a table (its header as written, e.g. ``"time (ms)"``, or
        its name part ``"time"``), or of the time variable of a Dataset without a ``time``
        coordinate. Default: the first of ``time``, ``t``, ... found; else a pandas
        ``DatetimeIndex``, ``TimedeltaIndex`` or float index (seconds).
    dt
        Sampling interval in seconds, for sources without a time column. Refused when it
        contradicts a time index or time coordinate the source has.
    step
        For a map: the name of the integer iteration column of a table, which becomes the
        ``step`` coordinate. ``step="step"`` on a source without such a column (a numpy array,
        a table of map values) numbers the samples 0, 1, ... A table with a ``step`` column and
        no time column is read as a map without asking. Give at most one of ``time``,
        ``dt`` and ``step``.
    variables
        Names of the variables to keep (for a numpy array: the column names). Columns of a
        table not named here may hold text.
    require_uniform
        Raise if the sampling is not uniform (the estimators need uniform sampling).
    skip_rows
        Text tables: lines to skip at the top of the file (title lines) before the header.
    decimal
        Text tables: the decimal mark, ``"."`` or ``","`` (then columns are separated by
        ``;``, tab, ``|`` or blanks).
    nan
        What to do with missing values (NaN, empty cells): ``"refuse"`` (raise, naming the
        column and the line of the file), ``"drop"`` (drop the rows; refused when that
        would leave gaps in a uniform sampling: rows at the ends only) or ``"interpolate"``
        (linear in time; rows at either end with nothing to interpolate from are dropped;
        each variable records the bridged samples in its ``interpolated_samples`` and
        ``interpolated_gaps`` attributes, and ``history`` says what was done).
        Infinite values are always refused.
    group
        Rig files with several groups or structs: the TDMS group, the HDF5 group
        (``"run1"`` or ``"/rig/run1"``) or the MATLAB struct (``"rig"``, ``"rig.run1"``) to
        read. Default: the file's top level, or its only group or struct.
    resample
        ``"linear"``: interpolate onto a uniform time grid, of interval ``dt`` if given
        (then ``dt`` is the new interval, not the file's), else the median interval of the
        time stamps. Rig files with irregular time stamps (jitter, dropped samples) are
        refused without it. The method and interval are recorded in the global attributes
        ``resample_method`` and ``resample_interval`` and in ``history``; missing values
        are handled (``nan``) before.

    Returns
    -------
    xarray.Dataset
        A Dataset following the data contract (``docs/data-model.md``); missing ``units``
        are filled with ``"unknown"`` and missing ``long_name`` with the variable name.
        Table headers with units (``acc y [m/s^2]``) give the variable ``acc_y`` with
        ``long_name`` ``"acc y"`` and ``units`` ``"m s-2"``; a time column in ms, min, ...
        is converted to seconds.

    Raises
    ------
    FileNotFoundError
        If the path does not exist.
    ValueError
        With a one-line message for every problem with the content: a folder instead of a
        file, an unknown suffix, a truncated or foreign file, an undetectable CSV delimiter
        (a title line: use ``skip_rows``), duplicate column names, no data rows, a missing
        time column, non-numeric values (a decimal comma: use ``decimal``), missing values;
        for rig files also a file with no numeric array, series of unequal lengths, complex
        or 3-D arrays, a channel without time increment (use ``dt``), irregular time
        stamps (use ``resample``). A :class:`~chaoskit.contract.ParameterError` when an
        option fixes the problem; an ``ImportError`` (also a ``ValueError``) naming the
        ``formats`` extra when a reader's optional package is missing.

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> ds = chaoskit.load_trajectory(np.sin(np.arange(100) * 0.1), dt=0.1)
    >>> float(ds.time[1])
    0.1
    >>> chaoskit.load_trajectory(chaoskit.systems.logistic(50), step="step").sizes["step"]
    50
    """
    if dt is not None:
        if not np.isfinite(dt) or dt <= 0:
            raise ValueError(f"dt must be a finite positive number of seconds; got {dt!r}.")
    if step is not None and (not isinstance(step, str) or not step.strip()):
        raise ValueError(f"step must name a column (or be 'step'); got {step!r}.")
    skip_rows = check_int(skip_rows, name="skip_rows", minimum=0)
    decimal = check_choice(decimal, name="decimal", choices=(".", ","))
    nan = check_choice(nan, name="nan", choices=NAN_POLICIES)
    if group is not None and (not isinstance(group, str) or not group.strip()):
        raise ValueError(f"group must name a group or struct of the file; got {group!r}.")
    if resample is not None:
        resample = check_choice(resample, name="resample", choices=RESAMPLE_METHODS)
        if step is not None or isinstance(source, (np.ndarray, list, tuple)):
            raise ParameterError(
                "{resample} interpolates between time stamps and "
                + ("a map has none" if step is not None else "a numpy array has none")
                + "; pass {dt} alone for evenly spaced samples{to}.",
                function=_LOAD,
            )
    ds, origin, text = _read_source(
        source,
        time=time,
        dt=None if resample else dt,  # with resample, dt is the new grid's interval
        step=step,
        variables=variables,
        require_uniform=require_uniform and not resample,
        skip_rows=skip_rows,
        decimal=decimal,
        group=group,
    )
    if variables is not None and not isinstance(source, (np.ndarray, list, tuple)):
        ds = ds[resolve_variables(variables, ds, origin)]
    ds, note = missing_values(ds, nan, origin)
    ds, timing = time_axis(ds, origin, method=resample, dt=dt)
    had_history = "history" in ds.attrs
    ds = validate_trajectory(ds, require_uniform=require_uniform, fill_attrs=True)
    if not had_history:  # foreign data: say where it came from; our own files keep theirs
        append_history(ds, f"chaoskit.load_trajectory: {text}")
    for line in (note, timing):
        if line:
            append_history(ds, f"chaoskit.load_trajectory: {line}")
    return ds


# ---------------------------------------------------------------- save_trajectory


def _check_attr_values(ds: xr.Dataset) -> None:
    for owner, attrs in [("the dataset", ds.attrs)] + [
        (f"variable {k!r}", v.attrs) for k, v in ds.variables.items()
    ]:
        for key, value in attrs.items():
            ok = isinstance(value, (str, int, float, np.number)) and not isinstance(value, bool)
            ok = ok or (
                isinstance(value, (np.ndarray, list, tuple))
                and np.asarray(value).dtype.kind in "fiu"
            )
            if not ok:
                raise TypeError(
                    f"attribute {key!r} of {owner} has type {type(value).__name__}; netCDF "
                    "attributes must be strings, numbers or numeric arrays (store dicts as JSON)."
                )


#: Files up to this size are serialised in memory and written with plain file I/O: HDF5
#: never touches a disk that may fill up (after ENOSPC, h5netcdf's flush can crash Python).
IN_MEMORY_LIMIT = 512 * 2**20


#: Free space required beyond the estimated size of a file (fraction, then bytes).
SPACE_MARGIN = (0.05, 2**20)


def check_free_space(folder: Path, nbytes: int) -> None:
    """Raise ``OSError(ENOSPC)`` with a one-line message if ``folder`` lacks ``nbytes`` free.

    The check keeps a margin (5 % and 1 MiB) for metadata and for the temporary file of an
    atomic write, which exists beside the old file until the rename.
    """
    folder = Path(folder)
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    free = shutil.disk_usage(folder).free
    need = int(nbytes * (1.0 + SPACE_MARGIN[0])) + SPACE_MARGIN[1]
    if need > free:
        raise OSError(
            errno.ENOSPC,
            f"not enough free space in {folder} to write {nbytes / 1e6:.1f} MB "
            f"({free / 1e6:.1f} MB free)",
        )


def atomic_write(path: Path, writer: Any, *, nbytes: int | None = None) -> None:
    """Write through ``writer(tmp)`` to a temporary file beside ``path``, then rename.

    With ``nbytes`` (the expected size), the free space is checked first. On any error the
    temporary file is removed and an old ``path`` stays as it was.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    if nbytes is not None:
        check_free_space(path.parent, nbytes)
    tmp = path.parent / f".{path.name}.{uuid.uuid4().hex[:12]}.tmp"
    try:
        writer(Path(tmp))
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            Path(tmp).unlink(missing_ok=True)
        raise


def _local_scheduler() -> contextlib.AbstractContextManager[Any]:
    """Inside a dask worker, xarray would guard an in-memory write with a distributed lock
    named after the buffer, which the scheduler does not know; compute locally instead."""
    try:
        import dask
    except ImportError:  # pragma: no cover - dask is a dependency
        return contextlib.nullcontext()
    return dask.config.set(scheduler="synchronous")


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """Write any Dataset as netCDF-4 (h5netcdf) atomically, after checking the free space.

    Up to ``IN_MEMORY_LIMIT`` bytes the file is built in memory and written with plain
    file I/O, so a full disk raises ``OSError(ENOSPC)`` instead of failing inside HDF5.
    """
    path = Path(path)
    if ds.nbytes <= IN_MEMORY_LIMIT:
        with _local_scheduler():
            data = bytes(ds.to_netcdf(engine="h5netcdf", invalid_netcdf=False))
        atomic_write(path, lambda p: p.write_bytes(data), nbytes=len(data))
    else:
        atomic_write(
            path,
            lambda p: ds.to_netcdf(p, engine="h5netcdf", invalid_netcdf=False),
            nbytes=int(ds.nbytes),
        )
    return path


def save_trajectory(ds: xr.Dataset, path: str | os.PathLike[str]) -> Path:
    """Write a trajectory atomically (temporary file in the same folder, then rename).

    The format follows the suffix: netCDF-4 through h5netcdf (``.nc``), CSV with the
    attributes in a JSON comment line (``.csv``; 1-D variables only) or ``.npz``. Whatever
    :func:`load_trajectory` accepts, this writes: missing ``units``, ``long_name`` and
    global attributes (``Conventions``, ``title``, ``source``, ``history``, ``created``) are
    filled as on loading, and present ones are kept as they are.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    path = Path(path)
    fmt = _format_of(path)
    if path.is_dir():
        raise ValueError(f"{path} is a folder; pass a file name to write.")
    # as load_trajectory does: fill missing units, long names and provenance attributes,
    # keep the ones that are there (a foreign ``source`` stays)
    ds = validate_trajectory(ds.copy(), fill_attrs=True)
    _check_attr_values(ds)
    if fmt == "netcdf":
        return write_netcdf(ds, path)
    index = "time" if "time" in ds.coords else "step"
    multi = [k for k, v in ds.data_vars.items() if v.dims != (index,)]
    if multi:
        raise ValueError(
            f"{fmt} files hold 1-D series along {index!r} only; {multi} have other dims. "
            "Save to netCDF (.nc) instead."
        )
    payload = json.dumps(_attrs_payload(ds), default=_json_default)
    if fmt == "csv":
        frame = ds.to_dataframe().reset_index()

        def write_csv(p: Path) -> None:
            with p.open("w", encoding="utf-8", newline="") as fh:
                fh.write(ATTRS_LINE + payload + "\n")
                frame.to_csv(fh, index=False, float_format="%.17g")

        atomic_write(path, write_csv, nbytes=int(ds.nbytes) * 3)  # ~25 characters a value
    else:
        arrays = {str(k): np.asarray(v.values) for k, v in ds.variables.items()}
        arrays[_NPZ_ATTRS] = np.asarray(payload)

        def write_npz(p: Path) -> None:
            with p.open("wb") as fh:
                np.savez(fh, **arrays)  # type: ignore[arg-type]

        atomic_write(path, write_npz, nbytes=int(ds.nbytes))
    return path


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"cannot store {type(obj).__name__} as JSON")
