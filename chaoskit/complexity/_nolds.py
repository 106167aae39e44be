"""Sample entropy, DFA and the Hurst exponent, computed by nolds behind chaoskit's checks.

nolds (Schölzel 2019) implements these measures in plain numpy; chaoskit adds validation,
result objects with the curve each value was fitted from, and a length limit per measure
(``MAX_SAMPLES``), checked before the call so that a long series gives a clear error
instead of a stall or a MemoryError. The limits, and the time and memory they bound, are
in ``docs/estimators.md`` ("Sample entropy, DFA and Hurst through nolds").
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from .._validate import as_series, check_int, check_positive

__all__ = [
    "MAX_SAMPLES",
    "ComplexityResult",
    "detrended_fluctuation",
    "hurst_exponent",
    "sample_entropy",
]

#: Longest series each measure accepts (the time and memory they bound: docs/estimators.md).
MAX_SAMPLES = {"sample_entropy": 20_000, "dfa": 50_000, "hurst_rs": 10_000_000}
_MIN_SAMPLES = {"sample_entropy": 50, "dfa": 100, "hurst_rs": 100}
_DESCRIPTION = {
    "sample_entropy": "O(N²) pair comparisons in Python",
    "dfa": "a least-squares fit per window in Python",
    "hurst_rs": "a rescaled range per window",
}


@dataclass(frozen=True, kw_only=True)
class ComplexityResult:
    """A complexity measure with the curve it was read from.

    Attributes
    ----------
    measure
        ``"sample_entropy"``, ``"dfa"`` or ``"hurst_rs"``.
    value
        Sample entropy (nats), DFA exponent α or Hurst exponent H (dimensionless).
    units
        Units of ``value``: ``"nat"`` or ``"1"``.
    scale, curve
        Sample entropy: ``scale`` is ``(m,)`` and ``curve`` the entropy itself (nolds
        reports the match counts only together with every pair distance, O(N²) memory).
        DFA: ``scale`` the window lengths (samples) and ``curve``
        the fluctuation F(n). Hurst: the window lengths and the rescaled range (R/S)(n)
        (corrected by its Anis–Lloyd–Peters expectation, as nolds does).
    fit
        Slope and intercept of the line fitted to ``ln curve`` over ``ln scale`` (DFA,
        Hurst); NaN for sample entropy.
    params
        Parameters passed to nolds, as a plain dict.
    n_samples
        Length of the input series.
    """

    measure: str
    value: float
    units: str
    scale: np.ndarray
    curve: np.ndarray
    fit: tuple[float, float]
    params: dict = field(default_factory=dict)
    n_samples: int = 0

    def to_dataset(self) -> xr.Dataset:
        """The curve over ``scale`` with the value and parameters in the attributes."""
        if self.measure == "sample_entropy":
            scale_attrs = {"units": "1", "long_name": "template length"}
            curve_attrs = {"units": "nat", "long_name": "sample entropy"}
            name = "sample_entropy"
        elif self.measure == "dfa":
            scale_attrs = {"units": "1", "long_name": "window length in samples"}
            curve_attrs = {"units": "1", "long_name": "detrended fluctuation F(n)"}
            name = "fluctuation"
        else:
            scale_attrs = {"units": "1", "long_name": "window length in samples"}
            curve_attrs = {"units": "1", "long_name": "rescaled range (R/S)(n)"}
            name = "rescaled_range"
        attrs: dict[str, Any] = {
            "measure": self.measure,
            "value": self.value,
            "value_units": self.units,
            "fit_slope": self.fit[0],
            "fit_intercept": self.fit[1],
            "n_samples": self.n_samples,
        }
        attrs.update({f"param_{k}": v for k, v in self.params.items()})
        return xr.Dataset(
            {name: ("scale", self.curve, curve_attrs)},
            coords={"scale": ("scale", self.scale, scale_attrs)},
            attrs=attrs,
        )


def _series(x: Any, measure: str) -> np.ndarray:
    arr = as_series(x, min_length=_MIN_SAMPLES[measure])
    limit = MAX_SAMPLES[measure]
    if arr.size > limit:
        raise ValueError(
            f"x has {arr.size} samples; nolds' {measure} ({_DESCRIPTION[measure]}) is limited "
            f"here to {limit} samples. Pass a shorter segment or subsample the series."
        )
    return arr


def _windows(windows: Any, n: int) -> list[int] | None:
    if windows is None:
        return None
    w = np.asarray(windows)
    if w.ndim != 1 or w.size < 2 or w.dtype.kind not in "iu":
        raise ValueError(f"windows must be at least two integer window lengths; got {windows!r}.")
    if w.min() < 4 or w.max() >= n:
        raise ValueError(f"windows must lie in [4, {n - 1}] samples; got {w.min()} … {w.max()}.")
    return sorted({int(v) for v in w})


def _fitted(
    measure: str, value: float, log_n: Any, log_y: Any, poly: Any, params: dict, n: int
) -> ComplexityResult:
    """A result from nolds' debug data ``(ln n, ln y, [slope, intercept])``."""
    return ComplexityResult(
        measure=measure,
        value=float(value),
        units="1",
        scale=np.rint(np.exp(np.asarray(log_n, dtype=np.float64))),
        curve=np.exp(np.asarray(log_y, dtype=np.float64)),
        fit=(float(poly[0]), float(poly[1])),
        params=params,
        n_samples=n,
    )


def sample_entropy(
    x: Any, *, embedding_dim: int = 2, tolerance: float | None = None, lag: int = 1
) -> ComplexityResult:
    r"""Sample entropy SampEn(m, r) of a scalar series, computed by :func:`nolds.sampen`.

    .. math:: \mathrm{SampEn} = -\ln \frac{A}{B}

    with :math:`B` the pairs of templates of length :math:`m` within Chebyshev distance
    :math:`r` of each other and :math:`A` those of length :math:`m + 1`.

    Parameters
    ----------
    x
        Scalar series, at most 20 000 samples (the pair count is O(N²) in time).
    embedding_dim
        Template length :math:`m` (≥ 1).
    tolerance
        :math:`r` in units of ``x`` (default: nolds' ≈ 0.2 standard deviations, Lake et
        al. 2002).
    lag
        Delay between template samples.

    Returns
    -------
    ComplexityResult
        ``value`` in nats.

    Raises
    ------
    ValueError
        On bad input, a series longer than the limit, or no template matches (the entropy
        is then undefined: raise the tolerance or use a longer series).

    References
    ----------
    J. S. Richman and J. R. Moorman, "Physiological time-series analysis using approximate
    entropy and sample entropy", Am. J. Physiol. Heart Circ. Physiol. 278 (2000) H2039.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import sample_entropy
    >>> x = np.random.default_rng(0).standard_normal(2000)
    >>> round(sample_entropy(x, tolerance=0.2 * x.std()).value, 1)
    2.2
    """
    import nolds

    arr = _series(x, "sample_entropy")
    m = check_int(embedding_dim, name="embedding_dim", minimum=1, maximum=20)
    lag = check_int(lag, name="lag", minimum=1)
    if arr.size < (m + 1) * lag + 10:
        raise ValueError(f"x is too short for embedding_dim={m} and lag={lag}.")
    if tolerance is not None:
        tolerance = check_positive(tolerance, name="tolerance")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # zero matches: reported below
        # not debug_data: nolds then keeps every pair distance, O(N²) memory
        value = nolds.sampen(arr, emb_dim=m, tolerance=tolerance, lag=lag)
    if not np.isfinite(value):
        raise ValueError(
            "sample entropy is undefined: no pair of templates lies within the tolerance at "
            f"length {m} or {m + 1}; raise tolerance or use a longer series."
        )
    used = tolerance if tolerance is not None else _nolds_tolerance(arr, m)
    return ComplexityResult(
        measure="sample_entropy",
        value=float(value),
        units="nat",
        scale=np.array([m]),
        curve=np.array([float(value)]),
        fit=(float("nan"), float("nan")),
        params={"embedding_dim": m, "tolerance": float(used), "lag": lag},
        n_samples=arr.size,
    )


def _nolds_tolerance(arr: np.ndarray, m: int) -> float:
    """nolds' default tolerance (Lake et al. 2002 fit), in units of the series."""
    return float(np.std(arr, ddof=1) * 0.1164 * (0.5627 * np.log(m) + 1.3334))


def detrended_fluctuation(
    x: Any, *, windows: Any = None, order: int = 1, overlap: bool = True
) -> ComplexityResult:
    r"""Detrended fluctuation analysis, computed by :func:`nolds.dfa`.

    The profile :math:`y_k = \sum_{i \le k} (x_i - \bar x)` is cut into windows of
    :math:`n` samples, a polynomial trend of degree ``order`` removed from each, and the
    root-mean-square residual :math:`F(n)` scales as :math:`n^\alpha`: α = 0.5 for white
    noise, 1 for 1/f noise, 1.5 for a random walk.

    Parameters
    ----------
    x
        Scalar series, at most 50 000 samples.
    windows
        Window lengths in samples, ≥ 4 (default: nolds' geometric series from 4 to N/10).
    order
        Degree of the detrending polynomial (1 = DFA1).
    overlap
        Windows overlap by half.

    Returns
    -------
    ComplexityResult
        ``value`` α; ``scale`` the window lengths and ``curve`` F(n).

    References
    ----------
    C.-K. Peng et al., "Mosaic organization of DNA nucleotides", Phys. Rev. E 49 (1994)
    1685.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import detrended_fluctuation
    >>> x = np.random.default_rng(0).standard_normal(5000)
    >>> round(detrended_fluctuation(x).value, 1)
    0.5
    """
    import nolds

    arr = _series(x, "dfa")
    order = check_int(order, name="order", minimum=1, maximum=5)
    nvals = _windows(windows, arr.size)
    value, (log_n, log_f, poly) = nolds.dfa(
        arr, nvals=nvals, overlap=bool(overlap), order=order, fit_exp="poly", debug_data=True
    )
    params = {"order": order, "overlap": int(bool(overlap))}
    return _fitted("dfa", value, log_n, log_f, poly, params, arr.size)


def hurst_exponent(x: Any, *, windows: Any = None) -> ComplexityResult:
    r"""Hurst exponent by rescaled-range (R/S) analysis, computed by :func:`nolds.hurst_rs`.

    :math:`(R/S)(n) \propto n^H` over windows of :math:`n` samples, with the Anis–Lloyd–Peters
    expectation for independent increments divided out (so white noise gives H = 0.5);
    H > 0.5 means persistent, H < 0.5 anti-persistent increments.

    Parameters
    ----------
    x
        Scalar series (increments, not a walk), at most 10 000 000 samples.
    windows
        Window lengths in samples, ≥ 4 (default: nolds' 15 lengths in the middle of the
        logarithmic range up to N/4).

    Returns
    -------
    ComplexityResult
        ``value`` H; ``scale`` the window lengths and ``curve`` the corrected (R/S)(n).

    References
    ----------
    H. E. Hurst, "Long-term storage capacity of reservoirs", Trans. Am. Soc. Civ. Eng. 116
    (1951) 770. A. A. Anis and E. H. Lloyd, Biometrika 63 (1976) 111; E. E. Peters,
    "Fractal market analysis" (1994).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import hurst_exponent
    >>> x = np.random.default_rng(0).standard_normal(20000)
    >>> round(hurst_exponent(x).value, 1)
    0.5
    """
    import nolds

    arr = _series(x, "hurst_rs")
    nvals = _windows(windows, arr.size)
    value, (log_n, log_rs, poly) = nolds.hurst_rs(arr, nvals=nvals, fit="poly", debug_data=True)
    return _fitted("hurst_rs", value, log_n, log_rs, poly, {"corrected": 1}, arr.size)
