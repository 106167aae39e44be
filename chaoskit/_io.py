"""Reading and writing trajectories: the one place where files and foreign containers enter.

Formats
-------
netCDF-4 (``.nc``, ``.nc4``, ``.h5``)
    Written with ``engine="h5netcdf"``; every attribute is kept.
CSV (``.csv``, ``.txt``, ``.tsv``)
    One column per variable. ``save_trajectory`` writes the attributes as a JSON comment
    line (``# chaoskit-attrs: {...}``) above the header so a round trip keeps them; CSV files
    from elsewhere need no such line.
npz (``.npz``)
    One array per variable; ``save_trajectory`` adds a ``__chaoskit_attrs__`` JSON entry.
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

from ._contract import append_history, validate_trajectory

__all__ = ["load_trajectory", "save_trajectory"]

_NETCDF = {".nc", ".nc4", ".netcdf", ".h5", ".hdf5"}
_CSV = {".csv", ".txt", ".tsv"}
_NPZ = {".npz"}
_ATTRS_LINE = "# chaoskit-attrs: "
_NPZ_ATTRS = "__chaoskit_attrs__"
_TIME_NAMES = ("time", "t", "Time", "TIME", "t_s", "time_s")


def _format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in _NETCDF:
        return "netcdf"
    if suffix in _CSV:
        return "csv"
    if suffix in _NPZ:
        return "npz"
    accepted = sorted(_NETCDF | _CSV | _NPZ)
    raise ValueError(f"unknown file format {suffix!r} for {path}; accepted suffixes: {accepted}.")


def _attrs_payload(ds: xr.Dataset) -> dict[str, Any]:
    return {
        "global": dict(ds.attrs),
        "variables": {str(k): dict(v.attrs) for k, v in ds.variables.items()},
    }


def _apply_payload(ds: xr.Dataset, payload: dict[str, Any]) -> xr.Dataset:
    ds.attrs.update(payload.get("global", {}))
    for name, attrs in payload.get("variables", {}).items():
        if name in ds.variables:
            ds[name].attrs.update(attrs)
    return ds


def _integer_steps(values: Any, *, name: str, what: str) -> np.ndarray:
    steps = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype=np.float64)
    if np.isnan(steps).any() or np.any(steps != np.round(steps)):
        raise ValueError(f"step column {name!r} in {what} must hold integers (iteration numbers).")
    return steps.astype(np.int64)


def _from_table(
    frame: pd.DataFrame,
    *,
    time: str | None,
    dt: float | None,
    step: str | None,
    what: str,
) -> xr.Dataset:
    """Build a Dataset from a table with one column per variable."""
    frame = frame.copy()
    frame.columns = [str(c).strip() for c in frame.columns]
    duplicated = sorted({c for c in frame.columns if list(frame.columns).count(c) > 1})
    if duplicated:
        raise ValueError(f"{what} has duplicate column names {duplicated}; rename them.")
    if len(frame) == 0:
        raise ValueError(f"{what} has a header but no data rows.")
    given = [k for k, v in (("time", time), ("dt", dt), ("step", step)) if v is not None]
    if len(given) > 1:
        raise ValueError(
            f"pass one of time= (a column), dt= (uniform sampling) or step= (a map), not "
            f"{' and '.join(given)}."
        )
    if step is None and time is None and dt is None and "step" in frame.columns:
        if not any(c in frame.columns for c in _TIME_NAMES):
            step = "step"  # a map, e.g. as save_trajectory writes it
    index: tuple[str, np.ndarray]
    if step is not None:
        if step in frame.columns:
            index = ("step", _integer_steps(frame[step], name=step, what=what))
            frame = frame.drop(columns=[step])
        elif step == "step":
            index = ("step", np.arange(len(frame), dtype=np.int64))
        else:
            raise ValueError(
                f"step column {step!r} not found in {what}; columns are {list(frame.columns)} "
                "(step='step' numbers the rows 0, 1, ...)."
            )
    else:
        tname: str | None
        if time is not None:
            if time not in frame.columns:
                raise ValueError(
                    f"time column {time!r} not found in {what}; columns are {list(frame.columns)}."
                )
            tname = time
        elif dt is None:
            tname = next((c for c in _TIME_NAMES if c in frame.columns), None)
        else:
            tname = None
        if tname is not None:
            t = pd.to_numeric(frame[tname], errors="coerce").to_numpy(dtype=np.float64)
            if np.isnan(t).any():
                raise ValueError(
                    f"time column {tname!r} in {what} has non-numeric or missing values."
                )
            frame = frame.drop(columns=[tname])
        elif dt is not None:
            t = float(dt) * np.arange(len(frame), dtype=np.float64)
        else:
            raise ValueError(
                f"no time column in {what} (looked for {list(_TIME_NAMES)}); pass "
                "time='column' (command line: --time), dt=<sampling interval in s> (--dt), or "
                "step='column' for a map (--step; step='step' numbers the rows)."
            )
        index = ("time", t)
    for col in frame.columns:
        if not pd.api.types.is_numeric_dtype(frame[col]) or pd.api.types.is_bool_dtype(frame[col]):
            if not pd.api.types.is_bool_dtype(frame[col]):
                raise ValueError(
                    f"column {col!r} in {what} is not numeric (dtype {frame[col].dtype}); "
                    "pass variables=[...] with the numeric columns only."
                )
    if not len(frame.columns):
        raise ValueError(f"{what} has no data column besides its {index[0]} column.")
    data_vars = {col: (index[0], frame[col].to_numpy()) for col in frame.columns}
    return xr.Dataset(data_vars, coords={index[0]: (index[0], index[1])})


_DELIMITERS = (",", "\t", ";", "|")


def _delimiter(lines: list[str], *, what: str) -> str:
    """The column delimiter of a header and its first data lines; "," for one column.

    A delimiter counts if every line has the same, non-zero number of it; failing all,
    whitespace if every line splits into the same number (> 1) of fields.
    """
    for sep in _DELIMITERS:
        counts = {line.count(sep) for line in lines}
        if len(counts) == 1 and counts.pop() > 0:
            return sep
    fields = {len(line.split()) for line in lines}
    if len(fields) == 1 and fields.pop() > 1:
        return r"\s+"
    if all(len(line.split()) <= 1 and not any(d in line for d in _DELIMITERS) for line in lines):
        return ","  # one column
    raise ValueError(
        f"cannot tell the column delimiter of {what}: its first lines do not all hold the "
        "same number of ',', tab, ';', '|' or blanks; write one column per variable, "
        "comma-separated, with one header line."
    )


def _read_csv(path: Path, *, time: str | None, dt: float | None, step: str | None) -> xr.Dataset:
    payload = None
    skip = 0
    head: list[str] = []
    try:
        with path.open("r", encoding="utf-8-sig") as fh:  # -sig: drop a byte-order mark
            for line in fh:
                if not head and line.startswith("#"):
                    skip += 1
                    if line.startswith(_ATTRS_LINE):
                        payload = json.loads(line[len(_ATTRS_LINE) :])
                    continue
                if line.strip():
                    head.append(line.rstrip("\r\n"))
                if len(head) > 5:
                    break
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path} is not a UTF-8 text file ({exc.reason}).") from None
    except json.JSONDecodeError:
        raise ValueError(f"{path} has a damaged {_ATTRS_LINE.strip()} line.") from None
    if not head:
        raise ValueError(f"{path} is empty: no header line and no data.")
    if len(head) == 1:
        raise ValueError(f"{path} has a header but no data rows.")
    sep = "\t" if path.suffix.lower() == ".tsv" else _delimiter(head, what=str(path))
    header = [c.strip() for c in (head[0].split() if sep == r"\s+" else head[0].split(sep))]
    duplicated = sorted({c for c in header if header.count(c) > 1})
    if duplicated:
        raise ValueError(f"{path} has duplicate column names {duplicated}; rename them.")
    try:
        frame = pd.read_csv(
            path, skiprows=skip, sep=sep, encoding="utf-8-sig", engine="python", comment=None
        )
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ValueError(f"cannot read {path} as a table: {first}") from None
    ds = _from_table(frame, time=time, dt=dt, step=step, what=str(path))
    return _apply_payload(ds, payload) if payload else ds


def _read_npz(path: Path, *, time: str | None, dt: float | None, step: str | None) -> xr.Dataset:
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ValueError(f"{path} is not a readable npz file ({_one_line(exc)}).") from None
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
    ds = _from_table(pd.DataFrame(arrays), time=time, dt=dt, step=step, what=str(path))
    return _apply_payload(ds, payload) if payload else ds


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _read_netcdf(path: Path) -> xr.Dataset:
    try:
        with xr.open_dataset(path, engine="h5netcdf") as opened:
            return opened.load()
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(
            f"{path} is not a readable netCDF-4 file ({_one_line(exc)}); is it truncated, or "
            "another format with a .nc suffix?"
        ) from None


def _index_labelled(ds: xr.Dataset, *, dt: float | None, step: str | None) -> xr.Dataset:
    """Give a labelled Dataset without ``time``/``step`` the index that dt= or step= asks for."""
    if "time" in ds.coords or "step" in ds.coords or not ds.dims:
        return ds
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


def _from_array(
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
    return _from_table(frame, time=None, dt=dt, step=step, what="the array")


def load_trajectory(
    source: Any,
    *,
    time: str | None = None,
    dt: float | None = None,
    step: str | None = None,
    variables: Sequence[str] | None = None,
    require_uniform: bool = False,
) -> xr.Dataset:
    """Load a trajectory from a file or an in-memory container and validate it.

    Parameters
    ----------
    source
        A path to a netCDF (``.nc``), CSV (``.csv``/``.txt``/``.tsv``) or ``.npz`` file, a
        :class:`pandas.DataFrame`, an :class:`xarray.Dataset` or ``DataArray``, or a numpy
        array (1-D, or 2-D with one column per variable).
    time
        Name of the time column (seconds) in a table. Default: the first of ``time``, ``t``
        found.
    dt
        Sampling interval in seconds, for sources without a time column.
    step
        For a map: the name of the integer iteration column of a table, which becomes the
        ``step`` coordinate. ``step="step"`` on a source without such a column (a numpy array,
        a table of map values) numbers the samples 0, 1, ... A table with a ``step`` column and
        no time column is read as a map without asking. Give at most one of ``time``,
        ``dt`` and ``step``.
    variables
        Names of the variables to keep (for a numpy array: the column names).
    require_uniform
        Raise if the sampling is not uniform (the estimators need uniform sampling).

    Returns
    -------
    xarray.Dataset
        A Dataset following the data contract (``docs/data-model.md``); missing ``units``
        are filled with ``"unknown"`` and missing ``long_name`` with the variable name.

    Raises
    ------
    FileNotFoundError
        If the path does not exist.
    ValueError
        With a one-line message for every problem with the content: a folder instead of a
        file, an unknown suffix, a truncated or foreign file, an undetectable CSV delimiter,
        duplicate column names, no data rows, a missing time column, non-numeric values.

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
    origin: str
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        fmt = _format_of(path)
        if not path.exists():
            raise FileNotFoundError(f"no such trajectory file: {path}")
        if path.is_dir():
            raise ValueError(f"{path} is a folder; pass a trajectory file.")
        if fmt == "netcdf":
            ds = _read_netcdf(path)
        elif fmt == "csv":
            ds = _read_csv(path, time=time, dt=dt, step=step)
        else:
            ds = _read_npz(path, time=time, dt=dt, step=step)
        origin = f"loaded from {path.name}"
    elif isinstance(source, xr.Dataset):
        ds, origin = source.copy(), "taken from an xarray.Dataset"
    elif isinstance(source, xr.DataArray):
        name = source.name or "x"
        ds, origin = source.to_dataset(name=str(name)), "taken from an xarray.DataArray"
    elif isinstance(source, pd.DataFrame):
        ds = _from_table(source, time=time, dt=dt, step=step, what="the DataFrame")
        origin = "taken from a pandas.DataFrame"
    elif isinstance(source, pd.Series):
        frame = source.to_frame(name=str(source.name or "x"))
        ds = _from_table(frame, time=None, dt=dt, step=step, what="the Series")
        origin = "taken from a pandas.Series"
    elif isinstance(source, (np.ndarray, list, tuple)):
        arr = np.asarray(source)
        if arr.dtype.kind not in "fiub":
            raise ValueError(f"the array is not numeric (dtype {arr.dtype}).")
        ds = _from_array(arr, dt=dt, step=step, variables=variables)
        origin, variables = "taken from a numpy array", None
    else:
        raise TypeError(
            f"cannot load a trajectory from {type(source).__name__}; pass a file path, "
            "DataFrame, xarray object or numpy array."
        )
    if isinstance(source, (xr.Dataset, xr.DataArray)) or (
        isinstance(source, (str, os.PathLike)) and _format_of(Path(source)) == "netcdf"
    ):
        ds = _index_labelled(ds, dt=dt, step=step)
    if variables is not None:
        missing = [v for v in variables if v not in ds.data_vars]
        if missing:
            raise ValueError(f"variables {missing} not found; available: {list(ds.data_vars)}.")
        ds = ds[list(variables)]
    had_history = "history" in ds.attrs
    ds = validate_trajectory(ds, require_uniform=require_uniform, fill_attrs=True)
    if not had_history:  # foreign data: say where it came from; our own files keep theirs
        append_history(ds, f"chaoskit.load_trajectory: {origin}")
    return ds


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


def _atomic_write(path: Path, writer: Any, *, nbytes: int | None = None) -> None:
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

    Up to :data:`IN_MEMORY_LIMIT` bytes the file is built in memory and written with plain
    file I/O, so a full disk raises ``OSError(ENOSPC)`` instead of failing inside HDF5.
    """
    path = Path(path)
    if ds.nbytes <= IN_MEMORY_LIMIT:
        with _local_scheduler():
            data = bytes(ds.to_netcdf(engine="h5netcdf", invalid_netcdf=False))
        _atomic_write(path, lambda p: p.write_bytes(data), nbytes=len(data))
    else:
        _atomic_write(
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
                fh.write(_ATTRS_LINE + payload + "\n")
                frame.to_csv(fh, index=False, float_format="%.17g")

        _atomic_write(path, write_csv, nbytes=int(ds.nbytes) * 3)  # ~25 characters a value
    else:
        arrays = {str(k): np.asarray(v.values) for k, v in ds.variables.items()}
        arrays[_NPZ_ATTRS] = np.asarray(payload)

        def write_npz(p: Path) -> None:
            with p.open("wb") as fh:
                np.savez(fh, **arrays)  # type: ignore[arg-type]

        _atomic_write(path, write_npz, nbytes=int(ds.nbytes))
    return path


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"cannot store {type(obj).__name__} as JSON")
