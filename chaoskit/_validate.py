"""Validation at the public boundary: turn user input into contiguous float64 arrays.

Every public numeric function calls one of these helpers first, so kernels can assume
finite, contiguous float64 data and never validate again.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np

#: Largest and smallest peak magnitude ``max |x|`` a series may have. Beyond these, sums,
#: differences and squares of samples leave the float64 range (overflow near 1.8e308,
#: subnormal loss of precision below 2.2e-308) before the estimators can standardise it.
MAX_AMPLITUDE = 1e300
MIN_AMPLITUDE = 1e-300

__all__ = [
    "MAX_AMPLITUDE",
    "MIN_AMPLITUDE",
    "as_series",
    "check_choice",
    "check_int",
    "check_positive",
    "check_probability",
    "extreme_peak_exponent",
    "shown",
]


def as_series(x: Any, *, name: str = "x", min_length: int = 2) -> np.ndarray:
    """Return ``x`` as a finite, non-constant, contiguous 1-D float64 array.

    Accepts a numpy array, a list, a pandas Series or a 1-D xarray DataArray.

    Raises
    ------
    ValueError
        If ``x`` is not 1-D, not numeric, shorter than ``min_length``, contains NaN or inf,
        is constant, or its peak magnitude lies outside [``MIN_AMPLITUDE``,
        ``MAX_AMPLITUDE``].
    """
    values = getattr(x, "values", x)  # pandas Series, xarray DataArray
    arr = np.asarray(values)
    if arr.dtype == object or arr.dtype.kind in "USOVMm":
        raise ValueError(
            f"{name} must be numeric; got dtype {arr.dtype}. Convert it with "
            "np.asarray(..., dtype=float) after removing non-numeric entries."
        )
    if arr.dtype.kind == "c":
        raise ValueError(f"{name} must be real; got complex dtype {arr.dtype}.")
    if arr.ndim == 2 and 1 in arr.shape:
        arr = arr.reshape(-1)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional; got shape {arr.shape}.")
    if arr.size < min_length:
        raise ValueError(
            f"{name} is too short: {arr.size} samples, the minimum here is {min_length}."
        )
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    finite = np.isfinite(arr)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        kind = "NaN" if np.isnan(arr[bad]) else "inf"
        raise ValueError(
            f"{name} contains {(~finite).sum()} non-finite value(s) (first: {kind} at index "
            f"{bad}); remove or interpolate them first."
        )
    hi, lo = float(arr.max()), float(arr.min())
    if hi == lo:  # not np.ptp: hi - lo overflows for samples near the float64 limit
        raise ValueError(
            f"{name} is constant (every sample equals {shown(arr[0])}); delay, dimension and "
            "Lyapunov estimates are undefined for a constant series."
        )
    peak = max(hi, -lo)
    if not MIN_AMPLITUDE <= peak <= MAX_AMPLITUDE:
        raise ValueError(
            f"{name} has peak magnitude {peak:.3g}, outside the accepted range "
            f"[{MIN_AMPLITUDE:g}, {MAX_AMPLITUDE:g}] where differences and squares of samples "
            "stay finite; rescale it first (e.g. x / np.max(np.abs(x))): the estimators are "
            "scale-invariant."
        )
    return arr


def extreme_peak_exponent(x: np.ndarray) -> int:
    """0 if ``max |x|`` is ordinary, else the ``e`` that brings the peak of ``np.ldexp(x, -e)``
    into [0.5, 1).

    Ordinary means within [1e-100, 1e100]: there sums of squares of samples neither overflow
    nor underflow. Scaling by a power of two is exact in floating point, so the scaled series
    carries the same information, and ordinary data are left untouched (bit-identical
    results).
    """
    peak = float(np.max(np.abs(x))) if x.size else 0.0
    if peak == 0.0 or not np.isfinite(peak) or 1e-100 <= peak <= 1e100:
        return 0
    return int(np.frexp(peak)[1])


def shown(value: Any) -> str:
    """``value`` as a message shows it: numpy scalars as plain numbers, not
    ``np.float64(…)``."""
    if isinstance(value, np.generic):
        value = value.item()
    return repr(value)


def check_int(value: Any, *, name: str, minimum: int, maximum: int | None = None) -> int:
    """Return ``value`` as an int in ``[minimum, maximum]`` or raise a ValueError naming it."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer; got {shown(value)}.")
    value = int(value)
    if value < minimum or (maximum is not None and value > maximum):
        upper = "∞" if maximum is None else str(maximum)
        raise ValueError(f"{name} must be in [{minimum}, {upper}]; got {value}.")
    return value


def check_positive(value: Any, *, name: str, allow_zero: bool = False) -> float:
    """Return ``value`` as a finite positive float or raise a ValueError naming it."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number; got {shown(value)}.") from None
    if not np.isfinite(out) or out < 0.0 or (out == 0.0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {bound}; got {shown(value)}.")
    return out


def check_probability(value: Any, *, name: str) -> float:
    """Return ``value`` as a float in (0, 1) or raise a ValueError naming it."""
    out = check_positive(value, name=name)
    if out >= 1.0:
        raise ValueError(f"{name} must be in (0, 1); got {shown(value)}.")
    return out


def check_choice(value: Any, *, name: str, choices: tuple[str, ...]) -> str:
    """Return ``value`` if it is one of ``choices``, else raise a ValueError listing them."""
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}; got {value!r}.")
    return str(value)
