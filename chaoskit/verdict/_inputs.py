"""Reading the series to classify: the variable, its time axis and its kind."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import xarray as xr

from .._contract import sampling_interval
from .._io import load_trajectory
from .._tables import has_time_index
from .._validate import (
    check_positive,
    extreme_peak_exponent,
)
from ._rule import Kind


@dataclass(frozen=True)
class SeriesInput:
    x: np.ndarray
    t: np.ndarray
    dt: float
    kind: Kind
    variable: str | None
    angle: np.ndarray | None


def _pick_variable(ds: xr.Dataset, variable: str | None) -> str:
    if variable is None:
        names = [str(k) for k in ds.data_vars]
        if len(names) != 1:
            raise ValueError(f"the data hold several variables {names}; pass variable=...")
        return names[0]
    if variable not in ds.data_vars:
        raise ValueError(f"variable {variable!r} not found; available: {list(ds.data_vars)}.")
    return variable


def read_input(
    data: Any, *, variable: str | None, dt: float | None, phase_variable: str | None
) -> SeriesInput:
    if has_time_index(data):  # the index sets dt; load_trajectory refuses a contradicting dt=
        data, dt = load_trajectory(data, dt=dt, require_uniform=True), None
    if isinstance(data, (xr.Dataset, xr.DataArray)):
        ds = load_trajectory(data, dt=dt)  # refuses a dt= that contradicts a time coordinate
        name = _pick_variable(ds, variable)
        if ds[name].ndim != 1:
            raise ValueError(f"variable {name!r} must be one-dimensional; dims {ds[name].dims}.")
        x = np.asarray(ds[name].values, dtype=np.float64)
        angle = None
        if "time" in ds.coords:
            step = sampling_interval(ds)
            t = np.asarray(ds["time"].values, dtype=np.float64)
            if phase_variable is not None:
                angle = np.asarray(ds[_pick_variable(ds, phase_variable)].values, dtype=float)
            return SeriesInput(x, t, step, "flow", name, angle)
        return SeriesInput(x, np.arange(x.size, dtype=np.float64), 1.0, "map", name, None)
    if phase_variable is not None:
        raise ValueError("phase_variable needs a Dataset that holds the angle variable.")
    x = np.asarray(getattr(data, "values", data))
    given = variable if variable is not None else getattr(data, "name", None)
    label = None if given is None else str(given)
    if dt is None:
        return SeriesInput(x, np.arange(x.size, dtype=np.float64), 1.0, "map", label, None)
    step = check_positive(dt, name="dt")
    return SeriesInput(x, np.arange(x.size) * step, step, "flow", label, None)


def scaled_to_unit_peak(inp: SeriesInput) -> tuple[SeriesInput, int]:
    """``inp`` with x scaled by an exact power of two if its peak is extreme, and the exponent.

    Every piece of evidence is scale-invariant, but near the float64 limits the variance
    over- or underflows (a series of amplitude 1e-300 would look constant).
    """
    x = inp.x
    if x.dtype.kind != "f" or x.ndim != 1 or not np.all(np.isfinite(x)):
        return inp, 0  # as_series reports it
    e = extreme_peak_exponent(x)
    return (inp, 0) if e == 0 else (replace(inp, x=np.ldexp(x, -e)), e)


def is_equilibrium(x: np.ndarray, rtol: float) -> bool:
    if x.dtype.kind not in "fiu" or x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)):
        return False
    x = x.astype(np.float64)
    spread = float(np.std(x))
    return spread == 0.0 or spread <= rtol * float(np.abs(np.mean(x)))


def noise_level(x: np.ndarray) -> float:
    """Robust estimate of white measurement noise relative to the standard deviation.

    For a smooth, densely sampled signal the second difference is :math:`O(h^2)` and the
    noise contributes :math:`\\sqrt 6\\,\\sigma`; the median absolute deviation makes the
    estimate robust to the rare large curvature.
    """
    d2 = np.diff(x, 2)
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return 1.4826 * mad / np.sqrt(6.0) / float(np.std(x))
