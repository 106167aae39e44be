"""Reading MATLAB ``.mat`` files (v4 and v5 through :func:`scipy.io.loadmat`, v7.3 through
h5py) into a :class:`chaoskit._rig.RigTable`.

Variables (or the fields of a struct chosen with ``group``) become columns: vectors as they
are, matrices one column per channel, named by a ``names``/``channels`` char array when the
file has one; a ``units`` array or struct gives their units, and a scalar ``dt``, ``Ts`` or
``fs`` the sampling. Struct arrays, cell arrays, objects, sparse and complex matrices are
refused with a message saying how to save them instead.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import scipy.io

from ._contract import ParameterError
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
    lookup,
    series_table,
    set_sampling_index,
    stated_sampling,
)
from ._tables import TIME_NAMES, one_line

__all__ = ["read_mat"]


_LOAD = "load_trajectory"
_lit = ParameterError.literal
_ONE_STRUCT = "chaoskit reads a scalar struct: save one element as a struct of its own"
_OBJECT = (
    "is a MATLAB object chaoskit cannot read (a table, timeseries, ...: save its "
    "columns as numeric vectors, e.g. with table2struct(T, 'ToScalar', true))"
)


def _mat5_node(value: Any) -> Any:
    """A value of :func:`scipy.io.loadmat` as an array, str, list of str, dict (struct) or
    :class:`Unusable`."""
    if isinstance(value, scipy.io.matlab.mat_struct):
        return {k: _mat5_node(getattr(value, k)) for k in value._fieldnames}
    if isinstance(value, np.ndarray):
        if value.dtype.kind in NUMERIC:
            return value
        if value.dtype.kind == "c":
            return Unusable(COMPLEX, fatal=True)
        if value.dtype.kind == "U":
            if value.size <= 1:
                return value.item().strip() if value.size else ""
            return [v.strip() for v in value]
        if value.dtype.kind == "O" and value.size == 1:
            return _mat5_node(value.reshape(-1)[0])
        if value.dtype.kind == "O":
            cells = [_mat5_node(v) for v in value.reshape(-1, order="F")]
            if all(isinstance(c, str) for c in cells):
                return cells
            if all(isinstance(c, dict) for c in cells):
                return Unusable(
                    f"is a {value.shape[0]} × {value.shape[1]} struct array; {_ONE_STRUCT}",
                    fatal=True,
                )
            return Unusable("is a cell array", fatal=False)
    if hasattr(value, "tocsc"):
        return Unusable("is a sparse matrix; store full(...)", fatal=True)
    return Unusable(_OBJECT, fatal=False)


def _mat73_node(f: h5py.File, obj: Any) -> Any:
    """An object of a MATLAB v7.3 file as :func:`_mat5_node` gives it: MATLAB's column-major
    arrays are stored transposed, so the HDF5 shape is the MATLAB shape reversed."""
    cls = obj.attrs.get("MATLAB_class", b"")
    cls = cls.decode() if isinstance(cls, bytes) else str(cls)
    if isinstance(obj, h5py.Group):
        if "MATLAB_sparse" in obj.attrs:
            return Unusable("is a sparse matrix; store full(...)", fatal=True)
        order = obj.attrs.get("MATLAB_fields")
        keys = [b"".join(np.asarray(k)).decode() for k in order] if order is not None else []
        keys += [k for k in obj if k not in keys]
        if cls == "struct" and any(
            isinstance(obj[k], h5py.Dataset)
            and h5py.check_dtype(ref=obj[k].dtype) is not None
            and obj[k].attrs.get("MATLAB_class") != b"cell"
            for k in keys
        ):  # the fields of a struct array hold references to each element's value
            return Unusable(f"is a struct array; {_ONE_STRUCT}", fatal=True)
        return {k: _mat73_node(f, obj[k]) for k in keys if k in obj}
    if "MATLAB_object_decode" in obj.attrs:
        return Unusable(_OBJECT, fatal=False)
    if obj.attrs.get("MATLAB_empty", 0):
        return np.zeros((0,))
    if set(obj.dtype.names or ()) == {"real", "imag"}:
        return Unusable(COMPLEX, fatal=True)
    data = obj[()]
    if cls == "cell":
        cells = [_mat73_node(f, f[ref]) for ref in np.asarray(data).T.reshape(-1)]
        return (
            cells
            if all(isinstance(c, str) for c in cells)
            else Unusable("is a cell array", fatal=False)
        )
    if cls == "char":
        chars = np.atleast_2d(np.asarray(data, dtype=np.uint16)).T  # rows of characters
        lines = ["".join(map(chr, row)).strip() for row in chars]
        return lines[0] if len(lines) == 1 else lines
    if cls == "function_handle" or data.dtype.kind not in NUMERIC:
        return Unusable(f"is a MATLAB {cls or str(data.dtype)} value", fatal=False)
    return np.asarray(data).T


def _read_mat5(path: Path) -> tuple[dict[str, Any], str]:
    try:
        raw = scipy.io.loadmat(
            path, squeeze_me=False, struct_as_record=False, chars_as_strings=True
        )
    except Exception as exc:  # scipy raises many kinds on damaged files; all mean "unreadable"
        raise ValueError(
            f"{path} is not a readable MATLAB file ({one_line(exc)}); is it truncated, or "
            "another format with a .mat suffix?"
        ) from None
    header = as_text(raw.get("__header__", b"")) or ""
    return {k: _mat5_node(v) for k, v in raw.items() if not k.startswith("__")}, header


def _read_mat73(path: Path) -> tuple[dict[str, Any], str]:
    try:
        with h5py.File(path, "r") as f:
            space = {k: _mat73_node(f, f[k]) for k in f if not k.startswith("#")}
        with path.open("rb") as fh:
            header = fh.read(116).decode("ascii", "replace").rstrip("\x00 ")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(
            f"{path} is not a readable MATLAB v7.3 (HDF5) file ({one_line(exc)}); is it truncated?"
        ) from None
    return space, header if header.startswith("MATLAB") else ""


def _descend(space: dict[str, Any], group: str | None, *, path: Path) -> tuple[dict, str]:
    """The struct ``group`` names (``run1`` or ``rig.run1``), or the file's top level when
    it holds numeric arrays, else its only struct."""
    what = str(path)
    structs = sorted(k for k, v in space.items() if isinstance(v, dict))
    if group is not None and group not in structs:
        node: Any = space
        for part in re.split(r"[./]", group.strip("./")):
            if not isinstance(node, dict) or not isinstance(node.get(part), dict):
                raise ParameterError(
                    f"{_lit(path)} has no struct {_lit(group)!r}; its structs are "
                    f"{_lit(structs)}; pass one of them with {{group}}{{to}}.",
                    function=_LOAD,
                )
            node = node[part]
        return node, f"struct {group!r} of {what}"
    numeric = [k for k, v in space.items() if isinstance(v, np.ndarray) and v.size > 1]
    if group is None and (numeric or not structs):
        return space, what
    chosen = choose(structs, group, path, "struct") or ""  # structs is not empty here
    return space[chosen], f"struct {chosen!r} of {what}"


def read_mat(path: Path, fmt: str, *, group: str | None, keep: Any, time: str | None) -> RigTable:
    space, header = _read_mat73(path) if fmt == "mat73" else _read_mat5(path)
    space, what = _descend(space, group, path=path)
    labels: dict[str, Any] = {}
    matrices = [k for k, v in space.items() if isinstance(v, np.ndarray) and min(v.shape) > 1]
    for lists, key in ((NAME_LISTS, "names"), (UNIT_LISTS, "units")):
        hit = lookup(space, lists)
        if hit is None:
            continue
        texts = [hit[1]] if isinstance(hit[1], str) and key == "units" else as_texts(hit[1])
        if texts is not None and len(matrices) == 1:
            one = key == "units" and len(texts) == 1
            labels.setdefault(matrices[0], {})[key] = texts[0] if one else texts
        elif key == "units" and isinstance(hit[1], dict):
            for name, unit in hit[1].items():
                labels.setdefault(name, {})["units"] = as_text(unit)
        space = {k: v for k, v in space.items() if k != hit[0]}
    if time is None and "tout" in space and not any(n in space for n in TIME_NAMES):
        time = "tout"  # Simulink's time vector
    sampling = stated_sampling(space, what=what)
    table = series_table(
        space, what=what, kind="variable", keep=keep, time=time, labels=labels, first=1
    )
    set_sampling_index(table, sampling)
    table.time = time
    table.where = "" if what == str(path) else f" ({what.split(' of ')[0]})"
    if header:
        table.global_attrs["source"] = header
    return table
