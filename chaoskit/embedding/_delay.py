"""Delay selection: mutual information and autocorrelation curves, then a rule."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._progress import stage
from .._validate import as_series, check_choice, check_int
from . import _kernels as _k
from ._embed import standardize

_INV_E = 1.0 / math.e  # the 1/e level of the autocorrelation rules

__all__ = [
    "DelayCurve",
    "DelayResult",
    "autocorrelation",
    "estimate_delay",
    "mutual_information",
]

DelayMethod = Literal["mi_first_minimum", "acf_first_zero", "acf_1_over_e", "auto"]
_METHODS: tuple[str, ...] = ("mi_first_minimum", "acf_first_zero", "acf_1_over_e", "auto")
DEFAULT_BINS = 16
_MIN_SAMPLES = 16


@dataclass(frozen=True, kw_only=True)
class DelayCurve:
    """A curve over lag (mutual information in nats, or the autocorrelation).

    Attributes
    ----------
    quantity
        ``"mutual_information"`` or ``"autocorrelation"``.
    lags
        Lags in samples, ``0 … max_lag``.
    curve
        The value at each lag (nats for mutual information, dimensionless otherwise).
    units
        ``"nat"`` or ``"1"``.
    bins
        Histogram bins per axis (mutual information only, else 0).
    n_samples
        Length of the series.
    """

    quantity: str
    lags: np.ndarray
    curve: np.ndarray
    units: str
    bins: int = 0
    n_samples: int = 0

    def to_dataset(self) -> xr.Dataset:
        """The curve as an :class:`xarray.Dataset` over ``lag``."""
        long = {
            "mutual_information": "histogram mutual information I(x_t; x_t+lag)",
            "autocorrelation": "normalised autocorrelation",
        }[self.quantity]
        return xr.Dataset(
            {self.quantity: ("lag", self.curve, {"units": self.units, "long_name": long})},
            coords={"lag": ("lag", self.lags, {"units": "1", "long_name": "lag in samples"})},
            attrs={"bins": self.bins, "n_samples": self.n_samples},
        )


@dataclass(frozen=True, kw_only=True)
class DelayResult:
    """A chosen delay together with the curve it was chosen from.

    Attributes
    ----------
    lag
        The chosen delay in samples (≥ 1).
    method
        The requested method name.
    rule
        The rule that produced ``lag`` in words (says so when a fallback was used).
    found
        ``False`` when the method's feature (minimum, zero, 1/e crossing) was not found up to
        the largest lag and a fallback was used.
    lags, curve
        The curve the choice was made on (``quantity`` says which; MI in nats).
    quantity, units
        What ``curve`` holds.
    acf
        The autocorrelation curve as well, for ``method="auto"`` (else empty).
    """

    lag: int
    method: str
    rule: str
    found: bool
    lags: np.ndarray
    curve: np.ndarray
    quantity: str
    units: str
    acf: np.ndarray = field(default_factory=lambda: np.empty(0))

    def to_dataset(self) -> xr.Dataset:
        """Curve and choice as an :class:`xarray.Dataset` (choice in the attributes)."""
        ds = DelayCurve(
            quantity=self.quantity, lags=self.lags, curve=self.curve, units=self.units
        ).to_dataset()
        if self.acf.size:
            ds["autocorrelation"] = (
                "lag",
                self.acf,
                {"units": "1", "long_name": "normalised autocorrelation"},
            )
        ds.attrs = {
            "lag": self.lag,
            "method": self.method,
            "rule": self.rule,
            "found": int(self.found),
        }
        return ds


def _default_max_lag(n: int) -> int:
    return int(max(2, min(n // 4, 1000)))


def _check_max_lag(max_lag: Any, n: int) -> int:
    # at least a quarter of the series has to overlap at the largest lag
    return check_int(max_lag, name="max_lag", minimum=1, maximum=max(1, (3 * n) // 4))


def mutual_information(
    x: Any, *, max_lag: int | None = None, bins: int = DEFAULT_BINS
) -> DelayCurve:
    r"""Histogram estimate of the mutual information between ``x_t`` and ``x_{t+τ}``.

    .. math:: I(\tau) = \sum_{a,b} p_{ab}(\tau) \ln \frac{p_{ab}(\tau)}{p_a\,p_b}

    with ``bins`` equal-width bins over the data range on each axis and probabilities from
    the ``N − τ`` overlapping pairs (Fraser & Swinney 1986). Cost O(N · max_lag).

    Parameters
    ----------
    x
        Scalar series (≥ 16 samples).
    max_lag
        Largest lag in samples (default ``min(N // 4, 1000)``; at most ``3N/4``).
    bins
        Bins per axis, 2 … 1024 (default 16: enough resolution for the first minimum while
        keeping ≥ 4 samples per joint cell at N = 1000).

    Returns
    -------
    DelayCurve
        ``curve`` in nats over ``lags = 0 … max_lag``.

    References
    ----------
    A. M. Fraser, H. L. Swinney, "Independent coordinates for strange attractors from mutual
    information", Phys. Rev. A 33 (1986) 1134.

    Examples
    --------
    >>> from chaoskit import mutual_information, systems
    >>> mi = mutual_information(systems.lorenz(5000)[:, 0], max_lag=40)
    >>> mi.curve.shape
    (41,)
    """
    arr = as_series(x, min_length=_MIN_SAMPLES)
    max_lag = _default_max_lag(arr.size) if max_lag is None else _check_max_lag(max_lag, arr.size)
    bins = check_int(bins, name="bins", minimum=2, maximum=1024)
    curve = _k.mutual_information_curve(_k.bin_indices(arr, bins), bins, 0, max_lag + 1)
    return DelayCurve(
        quantity="mutual_information",
        lags=np.arange(max_lag + 1),
        curve=curve,
        units="nat",
        bins=bins,
        n_samples=arr.size,
    )


def _acf(arr: np.ndarray, max_lag: int) -> np.ndarray:
    y = standardize(arr)  # no overflow of the power for huge x
    nfft = 1 << int(np.ceil(np.log2(2 * y.size)))
    f = np.fft.rfft(y, nfft)
    r = np.fft.irfft(f.real**2 + f.imag**2, nfft)[: max_lag + 1]
    return r / r[0]


def autocorrelation(x: Any, *, max_lag: int | None = None) -> DelayCurve:
    r"""Normalised autocorrelation :math:`\rho(\tau) = \sum_t y_t y_{t+\tau} / \sum_t y_t^2`.

    ``y`` is ``x`` minus its mean; computed by FFT in O(N log N) (the biased estimator, which
    keeps :math:`|\rho| \le 1`).

    Parameters
    ----------
    x
        Scalar series (≥ 16 samples).
    max_lag
        Largest lag in samples (default ``min(N // 4, 1000)``).

    Returns
    -------
    DelayCurve
        Dimensionless ``curve`` over ``lags = 0 … max_lag``; ``curve[0] == 1``.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import autocorrelation
    >>> acf = autocorrelation(np.sin(0.1 * np.arange(2000)), max_lag=20)
    >>> bool(abs(acf.curve[16] - np.cos(1.6)) < 0.01)
    True
    """
    arr = as_series(x, min_length=_MIN_SAMPLES)
    max_lag = _default_max_lag(arr.size) if max_lag is None else _check_max_lag(max_lag, arr.size)
    return DelayCurve(
        quantity="autocorrelation",
        lags=np.arange(max_lag + 1),
        curve=_acf(arr, max_lag),
        units="1",
        n_samples=arr.size,
    )


def first_local_minimum(curve: np.ndarray) -> int:
    """First lag τ ≥ 1 with I(τ) < I(τ−1) and I(τ) ≤ I(τ+1); −1 if there is none."""
    d = np.diff(curve)
    # d[t-1] = c[t] - c[t-1] < 0 and d[t] = c[t+1] - c[t] >= 0
    hit = np.flatnonzero((d[:-1] < 0) & (d[1:] >= 0))
    return int(hit[0]) + 1 if hit.size else -1


def _first_below(curve: np.ndarray, level: float) -> int:
    hit = np.flatnonzero(curve[1:] <= level)
    return int(hit[0]) + 1 if hit.size else -1


def estimate_delay(
    x: Any,
    *,
    method: DelayMethod = "mi_first_minimum",
    max_lag: int | None = None,
    bins: int = DEFAULT_BINS,
) -> DelayResult:
    """Choose the embedding delay (in samples) from the MI or autocorrelation curve.

    Methods
    -------
    ``"mi_first_minimum"`` (default)
        First local minimum of the histogram mutual information (Fraser & Swinney 1986).
    ``"acf_first_zero"``
        First lag where the autocorrelation is ≤ 0.
    ``"acf_1_over_e"``
        First lag where the autocorrelation is ≤ 1/e.
    ``"auto"``
        The smaller of the first MI minimum and the 1/e autocorrelation time. For flows the
        MI minimum usually comes first; for maps and other series whose samples are already
        nearly uncorrelated, the MI curve only decays into its noise floor and its "first
        minimum" is an artefact, while the 1/e rule gives 1. Used by the Lyapunov estimators.

    The MI curve is computed in blocks and stops once the choice is settled: at twice the
    first minimum (``"mi_first_minimum"``) or just past the 1/e time (``"auto"``); use
    :func:`mutual_information` for the full curve. When the feature is not found up to
    ``max_lag`` the rule falls back (MI: the first lag
    with I ≤ I(0)/e, else the global minimum; ACF: the first lag ≤ 1/e, else ``max_lag``),
    ``found`` is ``False`` and ``rule`` says so.

    Parameters
    ----------
    x
        Scalar series (≥ 16 samples).
    method
        One of the names above.
    max_lag
        Largest lag searched (default ``min(N // 4, 1000)``).
    bins
        Histogram bins per axis for the MI methods (default 16).

    Returns
    -------
    DelayResult

    Examples
    --------
    >>> from chaoskit import estimate_delay, systems
    >>> estimate_delay(systems.lorenz(10_000, dt=0.01)[:, 0]).lag
    17
    """
    stage("delay")
    check_choice(method, name="method", choices=_METHODS)
    arr = as_series(x, min_length=_MIN_SAMPLES)
    max_lag = _default_max_lag(arr.size) if max_lag is None else _check_max_lag(max_lag, arr.size)
    bins = check_int(bins, name="bins", minimum=2, maximum=1024)
    # the MI-only method skips the autocorrelation; "auto" caps the MI curve at its 1/e time
    acf = np.empty(0) if method == "mi_first_minimum" else _acf(arr, max_lag)
    if method in ("mi_first_minimum", "auto"):
        lag_e = _first_below(acf, _INV_E) if acf.size else -1
        curve = _mi_until_minimum(arr, bins, max_lag, None if lag_e < 0 else lag_e + 1)
        lag, rule, found = _mi_choice(curve)
        if lag_e > 0 and (lag_e < lag or not found):
            lag, rule, found = (
                lag_e,
                f"autocorrelation 1/e time {lag_e} (before any MI minimum)",
                True,
            )
        return DelayResult(
            lag=lag,
            method=method,
            rule=rule,
            found=found,
            lags=np.arange(curve.size),
            curve=curve,
            quantity="mutual_information",
            units="nat",
            acf=acf[: curve.size],
        )
    lags = np.arange(max_lag + 1)
    level = 0.0 if method == "acf_first_zero" else _INV_E
    lag = _first_below(acf, level)
    found = lag > 0
    rule = f"first lag with autocorrelation <= {level:.4g}"
    if not found and method == "acf_first_zero":
        lag = _first_below(acf, _INV_E)
        rule = "no zero crossing up to max_lag; fell back to the 1/e time"
    if lag < 1:
        lag = max_lag
        rule = f"autocorrelation stays above {level:.4g} up to max_lag; used max_lag"
    return DelayResult(
        lag=lag,
        method=method,
        rule=rule,
        found=found,
        lags=lags,
        curve=acf,
        quantity="autocorrelation",
        units="1",
    )


def _mi_until_minimum(arr: np.ndarray, bins: int, max_lag: int, stop: int | None) -> np.ndarray:
    """MI curve computed in blocks of lags, ending early once the choice is settled.

    Without ``stop`` the curve runs to ``max_lag`` or to twice the first minimum (+2),
    whichever comes first; with ``stop`` it ends at lag ``stop`` (the caller's cap).
    """
    codes = _k.bin_indices(arr, bins)
    last = max_lag if stop is None else min(max_lag, stop)
    parts: list[np.ndarray] = []
    done = 0
    block = 32
    while done <= last:
        hi = min(last + 1, done + block)
        parts.append(_k.mutual_information_curve(codes, bins, done, hi))
        done = hi
        block *= 2
        if stop is None:
            tau = first_local_minimum(np.concatenate(parts))
            if tau > 0 and done >= 2 * tau + 3:
                break
    curve = np.concatenate(parts)
    if stop is None:
        tau = first_local_minimum(curve)
        if tau > 0:
            curve = curve[: min(curve.size, 2 * tau + 3)]
    return curve


def _mi_choice(curve: np.ndarray) -> tuple[int, str, bool]:
    lag = first_local_minimum(curve)
    if lag > 0:
        return lag, "first local minimum of the mutual information", True
    lag = _first_below(curve, curve[0] / np.e)
    if lag > 0:
        return (
            lag,
            "no MI minimum up to max_lag; fell back to the first lag with I <= I(0)/e",
            False,
        )
    lag = int(np.argmin(curve[1:])) + 1
    return lag, "no MI minimum or 1/e crossing up to max_lag; used the smallest MI", False


def lag_or_estimate(arr: np.ndarray, lag: Any) -> tuple[int, str]:
    """A given lag, validated, or the ``"auto"`` estimate; with the rule in words."""
    if lag is None:
        delay = estimate_delay(arr, method="auto", max_lag=max(1, min(arr.size // 4, 1000)))
        return delay.lag, f"estimated: {delay.rule}"
    return check_int(lag, name="lag", minimum=1), "given"
