"""The time axis of a trajectory being loaded: irregular time stamps refused, or resampled.

Rig files (:mod:`chaoskit._formats`) carry their own time stamps; the estimators need uniform
sampling, so :func:`time_axis` regularises stamps that are uniform up to their rounding and
refuses irregular ones unless ``load_trajectory(resample=...)`` asks to interpolate them onto
a uniform grid (:func:`resample`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ._contract import UNIFORM_RTOL, ParameterError
from ._tables import Origin

__all__ = ["RESAMPLE_METHODS", "regular_time", "resample", "time_axis"]


#: What ``load_trajectory(resample=...)`` does with irregular time stamps.
RESAMPLE_METHODS = ("linear",)
_LOAD = "load_trajectory"
_lit = ParameterError.literal


def _typical(d: np.ndarray) -> float:
    """The mean interval, gaps (intervals over 1.5 times the median) left out: robust to
    dropped samples, and to jitter that alternates (where the median is one extreme)."""
    return float(np.mean(d[d <= 1.5 * np.median(d)]))


def regular_time(
    t: np.ndarray, *, quantum: float, what: str
) -> tuple[np.ndarray | None, str | None]:
    """Check that the time stamps ``t`` are uniform.

    Returns ``(None, None)`` if they are; a uniform grid and a note if they are uniform up
    to the resolution ``quantum`` of the stamps (microsecond datetimes, single precision);
    raises a :class:`ParameterError` pointing at ``resample`` otherwise.
    """
    d = np.diff(t)
    if d.size == 0 or np.any(d <= 0):
        return None, None  # the contract check names duplicated or decreasing times
    mid = float(np.median(d))
    spread = float(np.max(np.abs(d - mid)))
    if spread <= UNIFORM_RTOL * mid:
        return None, None
    if quantum > 0 and spread <= 1.01 * quantum + UNIFORM_RTOL * mid:
        k = np.arange(t.size, dtype=np.float64)
        step = float(np.polyfit(k, t - t[0], 1)[0])  # least squares: rounding averages out
        grid = t[0] + step * k
        return grid, (
            f"time stamps of {what} rounded to {quantum:.3g} s; regularised to "
            f"a uniform grid of {step:.9g} s"
        )
    gaps = np.flatnonzero(d > 1.5 * mid)
    typical = _typical(d)
    gap = (
        f"; {gaps.size} gap(s) longer than 1.5 intervals, the first at t = {t[gaps[0]]:.6g} s"
        if gaps.size
        else ""
    )
    raise ParameterError(
        f"the time stamps of {_lit(what)} are irregular: intervals from {float(d.min()):.6g} s "
        f"to {float(d.max()):.6g} s (mean {typical:.6g} s){gap}; the estimators need uniform "
        "sampling: pass {resample=linear} to interpolate onto a uniform grid (with {dt} "
        "for its interval){to}.",
        function=_LOAD,
    )


def resample(ds: xr.Dataset, *, method: str, dt: float | None, what: str) -> tuple[xr.Dataset, str]:
    """``ds`` interpolated (``method``) onto a uniform time grid of interval ``dt`` (default:
    the mean interval of its stamps, gaps left out), from its first time to its last; the
    method and the interval are recorded in the global attributes ``resample_method`` and
    ``resample_interval``. Returns the Dataset and a line for the history."""
    if "time" not in ds.coords:
        raise ParameterError(
            f"{{resample}} needs time stamps and {_lit(what)} has none (a map, or samples "
            "without time); pass {dt} alone for evenly spaced samples{to}.",
            function=_LOAD,
        )
    t = np.asarray(ds["time"].values, dtype=np.float64)
    d = np.diff(t)
    if t.size < 2 or np.any(d <= 0) or not np.all(np.isfinite(t)):
        return ds, ""  # the contract check says what is wrong with the times
    step = _typical(d) if dt is None else float(dt)
    n = int(np.floor((t[-1] - t[0]) / step * (1 + 1e-12))) + 1
    if n < 2:
        raise ParameterError(
            f"{{dt={step:g}}} is longer than the record of {_lit(what)} "
            f"({t[-1] - t[0]:.6g} s); pass a shorter {{dt}}{{to}}.",
            function=_LOAD,
        )
    grid = t[0] + step * np.arange(n, dtype=np.float64)
    res = ds.interp(time=grid, method=method)  # type: ignore[arg-type]
    res.attrs["resample_method"] = method
    res.attrs["resample_interval"] = step
    note = (
        f"resampled {t.size} time stamps (intervals {float(d.min()):.6g} to "
        f"{float(d.max()):.6g} s) onto {n} samples every {step:.6g} s, {method} "
        "interpolation"
    )
    return res, note


def time_axis(
    ds: xr.Dataset, origin: Origin, *, method: str | None, dt: float | None
) -> tuple[xr.Dataset, str | None]:
    """Resample onto a uniform grid when asked (``method``, the ``resample`` option of
    ``load_trajectory``); else refuse the irregular time stamps of a rig file, after
    regularising stamps that are uniform up to their rounding."""
    if method is not None:
        return resample(ds, method=method, dt=dt, what=origin.what)
    if not origin.strict_time or "time" not in ds.coords or ds["time"].ndim != 1:
        return ds, None
    t = np.asarray(ds["time"].values, dtype=np.float64)
    grid, note = regular_time(t, quantum=origin.time_quantum, what=origin.what)
    if grid is None:
        return ds, None
    return ds.assign_coords(time=("time", grid, ds["time"].attrs)), note
