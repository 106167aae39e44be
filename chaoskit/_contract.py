"""The trajectory data contract, checked and stamped in one place.

A trajectory is an :class:`xarray.Dataset` with

* a float64 ``time`` coordinate in seconds, strictly increasing (or an integer ``step``
  coordinate for maps);
* numeric data variables, each with ``units`` and ``long_name`` attributes;
* global attributes ``Conventions``, ``title``, ``source``, ``history``, ``created`` and, for
  simulated data, ``scene`` (the resolved scene as JSON).

See ``docs/data-model.md``.
"""

from __future__ import annotations

import datetime as _dt
import functools
import re
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from ._version import __version__

__all__ = [
    "CONVENTIONS",
    "REQUIRED_GLOBAL_ATTRS",
    "ParameterError",
    "append_history",
    "sampling_interval",
    "stamp",
    "validate_trajectory",
    "variable",
    "variable_name",
]

CONVENTIONS = "CF-1.10"
REQUIRED_GLOBAL_ATTRS = ("Conventions", "title", "source", "history", "created")
UNKNOWN_UNITS = "unknown"
UNIFORM_RTOL = 1e-6


_PLACEHOLDER = re.compile(r"\{\{|\}\}|\{([a-z_]+)(?:=([^{}]*))?\}")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


class ParameterError(ValueError):
    """A :class:`ValueError` whose message names parameters, worded for Python or a command line.

    The message is a template: ``{name}`` names a parameter and ``{name=value}`` a parameter
    with a value; ``{to}`` says where the parameters go. ``str(error)`` reads as Python
    (``dt=``, ``skip_rows=1``, ``nan='drop'``, `` to load_trajectory``);
    :meth:`render` with ``command_line=True`` reads as options (``--dt``, ``--skip-rows 1``,
    ``--nan drop``, nothing for ``{to}``). ``{{`` and ``}}`` stand for literal braces, so
    text from user data goes through :meth:`literal` first.

    Parameters
    ----------
    template
        The message with its placeholders.
    function
        The function whose parameters these are (``{to}`` names it), e.g. ``"load_trajectory"``.

    Examples
    --------
    >>> err = ParameterError("no time: pass {dt}{to}.", function="load_trajectory")
    >>> str(err)
    'no time: pass dt= to load_trajectory.'
    >>> err.render(command_line=True)
    'no time: pass --dt.'
    >>> ParameterError("skip it with {skip_rows=1}").render(command_line=True)
    'skip it with --skip-rows 1'
    """

    def __init__(self, template: str, *, function: str | None = None) -> None:
        self.template = template
        self.function = function
        super().__init__(self.render())

    def __reduce__(self) -> Any:  # pickles (dask workers) keep the template, not its rendering
        return (functools.partial(type(self), self.template, function=self.function), ())

    @staticmethod
    def literal(text: Any) -> str:
        """``text`` with its braces doubled, to be put into a template as it is."""
        return str(text).replace("{", "{{").replace("}", "}}")

    def render(
        self, *, command_line: bool = False, options: Mapping[str, str] | None = None
    ) -> str:
        """The message for Python callers, or with ``command_line`` for a command line whose
        option for parameter ``name`` is ``options[name]`` (default ``--name-with-dashes``)."""
        options = options or {}

        def one(match: re.Match[str]) -> str:
            text = match.group(0)
            if text in ("{{", "}}"):
                return text[0]
            name, value = match.group(1), match.group(2)
            if name == "to":
                return "" if command_line or not self.function else f" to {self.function}"
            if command_line:
                option = options.get(name, "--" + name.replace("_", "-"))
                return option if value is None else f"{option} {value}"
            if value is None:
                return f"{name}="
            return f"{name}={value if _NUMBER.fullmatch(value) else repr(value)}"

        return _PLACEHOLDER.sub(one, self.template)


_NOT_NAME = re.compile(r"\W+")


def variable_name(text: Any) -> str:
    """``text`` as a variable name of the data contract: letters, digits and underscores,
    starting with a letter.

    Runs of other characters become one underscore (leading and trailing ones are dropped)
    and a name that would start with a digit gets the prefix ``x_``. Letters include
    accented ones. Names that already qualify are returned unchanged.

    Examples
    --------
    >>> variable_name("acc y"), variable_name("x-position"), variable_name("2nd sensor")
    ('acc_y', 'x_position', 'x_2nd_sensor')
    """
    name = _NOT_NAME.sub("_", str(text).strip()).strip("_")
    if not name:
        return "x"
    return name if name[0].isalpha() else f"x_{name}"


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()


def append_history(ds: xr.Dataset, line: str) -> None:
    """Append a time-stamped line to ``ds.attrs['history']`` (in place)."""
    entry = f"{_now()} {line}"
    old = ds.attrs.get("history", "")
    ds.attrs["history"] = f"{old}\n{entry}" if old else entry


def stamp(
    ds: xr.Dataset,
    *,
    title: str,
    source: str | None = None,
    history: str | None = None,
    extra: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """Set the contract's global attributes on ``ds`` (in place) and return it.

    ``source`` defaults to ``"chaoskit <version>"``; existing ``created`` and ``history``
    are kept (the new ``history`` line is appended).
    """
    ds.attrs["Conventions"] = CONVENTIONS
    ds.attrs["title"] = title
    ds.attrs["source"] = source or f"chaoskit {__version__}"
    ds.attrs.setdefault("created", _now())
    if history:
        append_history(ds, history)
    else:
        ds.attrs.setdefault("history", "")
    if extra:
        ds.attrs.update(extra)
    return ds


def _index_name(ds: xr.Dataset) -> str:
    if "time" in ds.coords:
        return "time"
    if "step" in ds.coords:
        return "step"
    raise ParameterError(
        "the dataset has no 'time' coordinate (float64 seconds) and no 'step' coordinate "
        "(integers, for maps); pass {time} (the variable holding the time, s), {dt} (the "
        "sampling interval, s) or {step} (a map){to}.",
        function="load_trajectory",
    )


def validate_trajectory(
    ds: xr.Dataset, *, require_uniform: bool = False, fill_attrs: bool = False
) -> xr.Dataset:
    """Check ``ds`` against the data contract and return it.

    Parameters
    ----------
    ds
        The candidate trajectory.
    require_uniform
        Also require uniform sampling (relative spread of the sampling interval below 1e-6).
    fill_attrs
        Fill missing ``units`` (``"unknown"``) and ``long_name`` (the variable's name) and the
        missing global attributes instead of raising. Used when importing foreign data.

    Raises
    ------
    ValueError
        Naming the problem: missing index coordinate, non-monotonic or duplicated time,
        NaN or inf values, non-numeric variables, non-uniform sampling, missing attributes.
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"expected an xarray.Dataset; got {type(ds).__name__}.")
    index = _index_name(ds)
    idx = ds[index].values
    if idx.ndim != 1:
        raise ValueError(f"coordinate {index!r} must be one-dimensional; got shape {idx.shape}.")
    if index == "time":
        if idx.dtype.kind not in "fiu":
            raise ValueError(f"time must be numeric seconds; got dtype {idx.dtype}.")
        if idx.dtype != np.float64:
            ds = ds.assign_coords(time=ds["time"].astype(np.float64))
            idx = ds["time"].values
        if not np.all(np.isfinite(idx)):
            raise ValueError("time contains NaN or inf values.")
    elif idx.dtype.kind not in "iu":
        raise ValueError(f"step must be integer; got dtype {idx.dtype}.")
    if idx.size >= 2:
        d = np.diff(idx)
        if np.any(d == 0):
            k = int(np.flatnonzero(d == 0)[0])
            raise ValueError(
                f"{index} has duplicated values (first: {idx[k]!r} at indices {k} and {k + 1})."
            )
        if np.any(d < 0):
            k = int(np.flatnonzero(d < 0)[0])
            raise ValueError(
                f"{index} is not monotonic increasing (first decrease at index {k + 1}: "
                f"{idx[k]!r} -> {idx[k + 1]!r}); sort the data first."
            )
    if require_uniform:
        sampling_interval(ds)
    if not ds.data_vars:
        raise ValueError("the dataset has no data variables.")
    for name, var in ds.data_vars.items():
        if var.dtype.kind not in "fiub":
            raise ValueError(
                f"variable {name!r} is not numeric (dtype {var.dtype}); drop it or pass "
                "variables=[...] with the numeric columns only."
            )
        values = np.asarray(var.values)
        if values.dtype.kind == "f" and not np.all(np.isfinite(values)):
            n_bad = int((~np.isfinite(values)).sum())
            raise ValueError(
                f"variable {name!r} contains {n_bad} NaN or inf value(s); clean or "
                "interpolate them first."
            )
        for key in ("units", "long_name"):
            if key not in var.attrs:
                if not fill_attrs:
                    raise ValueError(f"variable {name!r} has no {key!r} attribute.")
                var.attrs[key] = UNKNOWN_UNITS if key == "units" else str(name)
    if index == "time":
        ds["time"].attrs.setdefault("units", "s")
        ds["time"].attrs.setdefault("long_name", "time")
        ds["time"].attrs.setdefault("standard_name", "time")
    else:
        ds["step"].attrs.setdefault("units", "1")
        ds["step"].attrs.setdefault("long_name", "iteration")
    missing = [k for k in REQUIRED_GLOBAL_ATTRS if k not in ds.attrs]
    if missing:
        if not fill_attrs:
            raise ValueError(f"the dataset lacks the global attribute(s) {missing}.")
        # fill the missing ones only: a foreign ``source`` or ``title`` says where data came from
        ds.attrs.setdefault("Conventions", CONVENTIONS)
        ds.attrs.setdefault("title", "imported trajectory")
        ds.attrs.setdefault("source", f"chaoskit {__version__}")
        ds.attrs.setdefault("created", _now())
        ds.attrs.setdefault("history", "")
    return ds


def sampling_interval(ds: xr.Dataset) -> float:
    """Return the uniform sampling interval of ``ds`` (seconds, or 1.0 for ``step``).

    Raises
    ------
    ValueError
        If the sampling is not uniform (relative spread above 1e-6) or fewer than 2 samples.
    """
    index = _index_name(ds)
    idx = np.asarray(ds[index].values, dtype=np.float64)
    if idx.size < 2:
        raise ValueError(f"need at least 2 samples to define a sampling interval; got {idx.size}.")
    d = np.diff(idx)
    dt = float(np.median(d))
    spread = float(np.max(np.abs(d - dt))) / dt
    if spread > UNIFORM_RTOL:
        raise ValueError(
            f"{index} is not uniformly sampled (interval varies by {spread:.2e} relative, "
            f"between {d.min():.6g} and {d.max():.6g}); resample it to a uniform grid "
            "(e.g. ds.interp(time=np.arange(t0, t1, dt)))."
        )
    return dt


def variable(dims: str | tuple[str, ...], data: Any, units: str, long_name: str) -> xr.Variable:
    """An :class:`xarray.Variable` carrying the contract's ``units`` and ``long_name``.

    Examples
    --------
    >>> variable("time", [0.0, 1.0], "s", "time").attrs
    {'units': 's', 'long_name': 'time'}
    """
    return xr.Variable(dims, np.asarray(data), attrs={"units": units, "long_name": long_name})
