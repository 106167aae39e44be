"""Correlation sum and correlation dimension D2 (Grassberger & Procaccia 1983)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._neighbors import default_theiler_window
from .._validate import as_series, check_choice, check_int, check_positive
from ..embedding import lag_or_estimate, min_length
from ._pairs import count_pairs

__all__ = ["CorrelationDimensionResult", "correlation_dimension"]

Norm = Literal["chebyshev", "euclidean"]
_NORMS: tuple[str, ...] = ("chebyshev", "euclidean")
DEFAULT_DIMS = (1, 2, 3, 4, 5, 6, 7, 8)
N_RADII = 48
MIN_PAIRS = 200  # fewest pairs for a radius to enter the scaling search (~7 % noise on C)
MAX_C = 0.1  # larger correlation sums feel the finite size of the attractor
TOLERANCE = 0.1  # largest relative difference of the slopes of the region's two halves
POINT_TOLERANCE = 0.25  # largest relative deviation of a local slope inside the region
MIN_DECADES = 0.5  # shortest scaling region, decades of radius
SATURATION_TOL = 0.1  # |D2(m_max) − D2(m_max − 1)| ≤ 0.1·D2(m_max): saturated


@dataclass(frozen=True, kw_only=True)
class CorrelationDimensionResult:
    """Correlation sums over radius and embedding dimension, and D2 from their scaling.

    Attributes
    ----------
    d2
        Correlation dimension: the slope of ln C(r) against ln r fitted over the scaling
        region at the largest embedding dimension (dimensionless).
    interval
        Range of the local slope at the largest embedding dimension inside the scaling
        region: the plateau's spread, the honest uncertainty of a D2 read off a plot.
    saturated
        Whether D2 stopped growing with the embedding dimension (the last two dimensions
        agree within 10 %); white noise and too-short series do not saturate.
    embedding_dims
        Embedding dimensions used.
    dimension_by_dim
        The fitted slope for each embedding dimension over the same scaling region.
    radius
        Radii, ascending, in units of the input series.
    correlation_sum
        ``C(m, r)``, shape ``(len(embedding_dims), len(radius))``: the fraction of
        admissible pairs closer than ``r``; NaN where no pair was that close.
    local_slope
        ``d ln C / d ln r``, same shape; NaN where ``C`` is zero.
    pairs
        Pairs counted for each ``C(m, r)`` (its relative statistical error is roughly
        ``1/sqrt(pairs)``).
    scaling_range
        First and last radius of the scaling region.
    scaling_found
        Whether the automatic rule found a flat plateau (``False``: the widest usable range
        was fitted; treat the number with care). ``True`` for a user-given range.
    lag, theiler_window
        Delay and Theiler window (samples) used.
    lag_rule
        ``"given"`` or how the delay was estimated.
    norm
        ``"chebyshev"`` (maximum norm) or ``"euclidean"``.
    pairs_per_radius
        Pairs collected per radius before it stopped (``None``: every pair, exact).
    n_samples
        Length of the input series.
    units
        Units of the input series (those of ``radius``).
    """

    d2: float
    interval: tuple[float, float]
    saturated: bool
    embedding_dims: np.ndarray
    dimension_by_dim: np.ndarray
    radius: np.ndarray
    correlation_sum: np.ndarray
    local_slope: np.ndarray
    pairs: np.ndarray
    scaling_range: tuple[float, float]
    scaling_found: bool
    lag: int
    theiler_window: int
    lag_rule: str
    norm: str
    pairs_per_radius: int | None
    n_samples: int
    units: str

    def to_dataset(self) -> xr.Dataset:
        """Curves over ``(embedding_dim, radius)`` with every scalar in the attributes."""
        dims = ("embedding_dim", "radius")
        return xr.Dataset(
            {
                "correlation_sum": (
                    dims,
                    self.correlation_sum,
                    {"units": "1", "long_name": "correlation sum C(m, r)"},
                ),
                "local_slope": (
                    dims,
                    self.local_slope,
                    {"units": "1", "long_name": "local slope d ln C / d ln r"},
                ),
                "pairs": (dims, self.pairs, {"units": "1", "long_name": "pairs counted"}),
                "dimension_by_dim": (
                    "embedding_dim",
                    self.dimension_by_dim,
                    {"units": "1", "long_name": "correlation dimension fitted at each m"},
                ),
            },
            coords={
                "embedding_dim": (
                    "embedding_dim",
                    self.embedding_dims,
                    {"units": "1", "long_name": "embedding dimension"},
                ),
                "radius": (
                    "radius",
                    self.radius,
                    {"units": self.units, "long_name": "neighbourhood radius"},
                ),
            },
            attrs={
                "d2": self.d2,
                "interval_low": self.interval[0],
                "interval_high": self.interval[1],
                "saturated": int(self.saturated),
                "scaling_start": self.scaling_range[0],
                "scaling_stop": self.scaling_range[1],
                "scaling_found": int(self.scaling_found),
                "lag": self.lag,
                "theiler_window": self.theiler_window,
                "lag_rule": self.lag_rule,
                "norm": self.norm,
                "pairs_per_radius": -1 if self.pairs_per_radius is None else self.pairs_per_radius,
                "n_samples": self.n_samples,
            },
        )


def _local_slope(log_r: np.ndarray, log_c: np.ndarray) -> np.ndarray:
    """Central differences of ln C over ln r, one-sided at the ends; NaN next to C = 0."""
    out = np.full(log_c.shape, np.nan)
    for row in range(log_c.shape[0]):
        y = log_c[row]
        ok = np.isfinite(y)
        idx = np.flatnonzero(ok)
        if idx.size >= 2:
            lo, hi = idx[0], idx[-1] + 1
            out[row, lo:hi] = np.gradient(y[lo:hi], log_r[lo:hi])
    return out


def _fit_slope(log_r: np.ndarray, log_c: np.ndarray) -> float:
    ok = np.isfinite(log_c)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(log_r[ok], log_c[ok], 1)[0])


def _scaling_region(
    log_r: np.ndarray, log_c: np.ndarray, slope: np.ndarray, usable: np.ndarray
) -> tuple[int, int, bool]:
    """Widest run of usable radii over which ln C is straight in ln r.

    A window ``[a, b]`` of consecutive usable radii spanning at least ``MIN_DECADES``
    qualifies when the slopes fitted to its two halves agree within ``TOLERANCE`` of the
    slope ``S`` fitted to the whole, and every local slope inside lies within
    ``POINT_TOLERANCE · S`` of it (lacunar attractors such as Hénon's make the local slope
    oscillate by ±10 %, so points are judged more loosely than halves). The widest window
    wins, ties go to the straighter. Without one, the whole usable range is returned with
    ``found = False``.
    """
    idx = np.flatnonzero(usable & np.isfinite(slope) & np.isfinite(log_c))
    if idx.size < 2:
        return 0, log_r.size - 1, False
    min_span = MIN_DECADES * np.log(10.0)
    best: tuple[float, float, int, int] | None = None
    runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
    for run in runs:
        for ia in range(run.size):
            for ib in range(run.size - 1, ia + 2, -1):
                a, b = int(run[ia]), int(run[ib])
                span = float(log_r[b] - log_r[a])
                if span < min_span or (best is not None and span < best[0]):
                    break
                x, y = log_r[a : b + 1], log_c[a : b + 1]
                whole = np.polyfit(x, y, 1)[0]
                if whole <= 0:
                    continue
                h = x.size // 2
                first = np.polyfit(x[: h + 1], y[: h + 1], 1)[0]
                second = np.polyfit(x[h:], y[h:], 1)[0]
                bend = abs(first - second)
                if bend > TOLERANCE * whole:
                    continue
                if np.max(np.abs(slope[a : b + 1] - whole)) > POINT_TOLERANCE * whole:
                    continue
                if best is None or (span, -bend) > best[:2]:
                    best = (span, -bend, a, b)
    if best is None:
        return int(idx[0]), int(idx[-1]), False
    return best[2], best[3], True


def correlation_dimension(
    x: Any,
    *,
    embedding_dims: Any = DEFAULT_DIMS,
    lag: int | None = None,
    theiler_window: int | None = None,
    radii: Any = None,
    scaling_range: tuple[float, float] | None = None,
    norm: Norm = "chebyshev",
    pairs_per_radius: int | None = 20_000,
    rng: Any = 0,
    units: str = "1",
) -> CorrelationDimensionResult:
    r"""Correlation sums :math:`C(m, r)` and the correlation dimension D2 of a scalar series.

    .. math:: C(m, r) = \frac{1}{N_p} \sum_{|i-j| > w} \Theta(r - \lVert \mathbf y_i -
              \mathbf y_j \rVert), \qquad D_2 = \lim_{r \to 0} \frac{d \ln C}{d \ln r}

    where :math:`\mathbf y_i` are delay vectors of dimension :math:`m`, :math:`w` the Theiler
    window and :math:`N_p` the number of admissible pairs. Pairs are counted with a KD-tree
    (memory O(N)); large radii use a random subset of reference points once they hold
    ``pairs_per_radius`` pairs, as TISEAN's ``d2`` does.

    The scaling region is chosen automatically (override with ``scaling_range``): among
    radii with at least 200 pairs and :math:`C \le 0.1`, the widest run of at least half a
    decade where the local slope at the largest embedding dimension varies by at most 10 %
    of its mean. D2 is the least-squares slope of :math:`\ln C` against :math:`\ln r` over
    that region.

    Parameters
    ----------
    x
        Scalar series (units ``units``).
    embedding_dims
        Embedding dimensions, increasing integers ≥ 1 (default 1 … 8).
    lag
        Delay in samples (default: estimated, the ``"auto"`` rule of
        :func:`chaoskit.estimate_delay`).
    theiler_window
        Pairs with :math:`|i - j| \le w` are excluded (default: one mean period of the
        signal; ``0`` excludes only the point itself).
    radii
        Increasing positive radii, units of ``x`` (default: 48 radii spaced geometrically
        from 1/1000 of the range of ``x`` to the range).
    scaling_range
        ``(r_min, r_max)`` of the fit, units of ``x`` (default: automatic).
    norm
        ``"chebyshev"`` (maximum norm, TISEAN's) or ``"euclidean"`` (nolds').
    pairs_per_radius
        Stop adding reference points for a radius once it holds this many pairs (≥ 100);
        ``None`` counts every pair (exact, slower for large radii).
    rng
        Seed or :class:`numpy.random.Generator` of the reference order.
    units
        Units of ``x``, stored with the radii.

    Returns
    -------
    CorrelationDimensionResult

    Raises
    ------
    ValueError
        On a non-finite or constant series, bad parameters, or a series too short for the
        largest embedding dimension and the Theiler window.

    References
    ----------
    P. Grassberger and I. Procaccia, "Measuring the strangeness of strange attractors",
    Physica D 9 (1983) 189–208. J. Theiler, "Spurious dimension from correlation
    algorithms applied to limited time-series data", Phys. Rev. A 34 (1986) 2427.
    R. Hegger, H. Kantz and T. Schreiber, "Practical implementation of nonlinear time
    series methods: the TISEAN package", Chaos 9 (1999) 413.

    Examples
    --------
    >>> from chaoskit import correlation_dimension, systems
    >>> x = systems.henon(5000)[:, 0]
    >>> res = correlation_dimension(x, embedding_dims=[1, 2, 3], lag=1, theiler_window=0)
    >>> round(res.d2, 1)
    1.2
    """
    dims = np.asarray(embedding_dims)
    if dims.ndim != 1 or dims.size == 0 or dims.dtype.kind not in "iu":
        raise ValueError(
            f"embedding_dims must be a non-empty sequence of integers; got {embedding_dims!r}."
        )
    dims = dims.astype(np.int64)
    if dims[0] < 1 or np.any(np.diff(dims) <= 0) or dims[-1] > 64:
        raise ValueError(
            f"embedding_dims must increase strictly within [1, 64]; got {dims.tolist()}."
        )
    norm = check_choice(norm, name="norm", choices=_NORMS)  # type: ignore[assignment]
    if pairs_per_radius is not None:
        pairs_per_radius = check_int(pairs_per_radius, name="pairs_per_radius", minimum=100)
    arr = as_series(x, min_length=16)
    n = arr.size
    lag_used, lag_rule = lag_or_estimate(arr, lag)
    n_points = n - (int(dims[-1]) - 1) * lag_used
    if theiler_window is None:
        w = default_theiler_window(arr, max(n_points, 1))
    else:
        w = check_int(theiler_window, name="theiler_window", minimum=0)
    need = min_length(int(dims[-1]), lag_used, 2 * w + 1 + 16)
    if n < need:
        raise ValueError(
            f"x is too short: {n} samples, but embedding_dim={int(dims[-1])}, lag={lag_used} "
            f"and theiler_window={w} need at least {need}."
        )
    if radii is None:
        span = float(np.ptp(arr))
        r = np.geomspace(span / 1000.0, span, N_RADII)
    else:
        r = np.asarray(radii, dtype=np.float64).ravel()
        if r.size < 3 or not np.all(np.isfinite(r)) or r[0] <= 0 or np.any(np.diff(r) <= 0):
            raise ValueError("radii must be at least 3 finite, positive, increasing values.")
    if scaling_range is not None:
        lo = check_positive(scaling_range[0], name="scaling_range[0]")
        hi = check_positive(scaling_range[1], name="scaling_range[1]")
        if not lo < hi:
            raise ValueError(
                f"scaling_range must be (low, high) with low < high; got {scaling_range}."
            )
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    count, total = count_pairs(
        arr,
        lag=lag_used,
        n_points=n_points,  # the same reference points for every dimension
        max_dim=int(dims[-1]),
        radii=r,
        theiler_window=w,
        maximum_norm=norm == "chebyshev",
        pairs_per_radius=pairs_per_radius,
        rng=gen,
    )
    pairs = count[dims - 1]
    total = total[dims - 1]
    csum = np.full(pairs.shape, np.nan)
    ok = (total > 0) & (pairs > 0)
    csum[ok] = pairs[ok] / total[ok]
    log_r = np.log(r)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_c = np.log(csum)
    slope = _local_slope(log_r, log_c)
    if scaling_range is None:
        usable = (pairs[-1] >= MIN_PAIRS) & (csum[-1] <= MAX_C)
        a, b, found = _scaling_region(log_r, log_c[-1], slope[-1], usable)
    else:
        inside = np.flatnonzero((r >= scaling_range[0]) & (r <= scaling_range[1]))
        if inside.size < 2:
            raise ValueError(
                f"scaling_range={scaling_range} holds fewer than 2 of the radii; widen it."
            )
        a, b, found = int(inside[0]), int(inside[-1]), True
    fitted = np.array([_fit_slope(log_r[a : b + 1], log_c[k, a : b + 1]) for k in range(dims.size)])
    plateau = slope[-1, a : b + 1]
    plateau = plateau[np.isfinite(plateau)]
    interval = (float(plateau.min()), float(plateau.max())) if plateau.size else (np.nan, np.nan)
    d2 = float(fitted[-1])
    saturated = bool(
        dims.size >= 2
        and np.isfinite(d2)
        and abs(fitted[-1] - fitted[-2]) <= SATURATION_TOL * abs(d2)
    )
    return CorrelationDimensionResult(
        d2=d2,
        interval=interval,
        saturated=saturated,
        embedding_dims=dims,
        dimension_by_dim=fitted,
        radius=r,
        correlation_sum=csum,
        local_slope=slope,
        pairs=pairs,
        scaling_range=(float(r[a]), float(r[b])),
        scaling_found=found,
        lag=lag_used,
        theiler_window=w,
        lag_rule=lag_rule,
        norm=norm,
        pairs_per_radius=pairs_per_radius,
        n_samples=n,
        units=str(units),
    )
