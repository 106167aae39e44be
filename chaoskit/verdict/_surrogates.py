"""IAAFT surrogates and a surrogate-data test for nonlinear determinism."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from scipy.spatial import cKDTree

from .._progress import stage
from .._validate import as_series, check_int, check_probability, extreme_peak_exponent
from ._rng import as_generator

__all__ = [
    "SurrogateResult",
    "check_surrogates",
    "iaaft_surrogates",
    "min_surrogates",
    "prediction_error",
    "surrogate_test",
]


def min_surrogates(alpha: float) -> int:
    """Fewest surrogates with which a one-sided rank test can reach ``alpha``.

    The smallest p-value is :math:`1 / (n + 1)`, so :math:`n \\ge 1/\\alpha - 1`
    (19 for :math:`\\alpha = 0.05`, 99 for 0.01).
    """
    return max(1, math.ceil(1.0 / alpha - 1.0 - 1e-9))


def check_surrogates(n_surrogates: int, alpha: float) -> int:
    """``n_surrogates`` if the rank test can reach ``alpha`` with it, else a ValueError."""
    n_surrogates = check_int(n_surrogates, name="n_surrogates", minimum=1)
    need = min_surrogates(alpha)
    if n_surrogates < need:
        raise ValueError(
            f"n_surrogates = {n_surrogates} cannot reach alpha = {alpha:g} (the smallest "
            f"p-value is 1/(n_surrogates + 1) = {1 / (n_surrogates + 1):.3g}); "
            f"use n_surrogates >= {need}."
        )
    return n_surrogates


def iaaft_surrogates(
    x: Any,
    *,
    n_surrogates: int = 19,
    max_iter: int = 200,
    rng: Any = None,
) -> np.ndarray:
    r"""Iterative amplitude-adjusted Fourier-transform (IAAFT) surrogates.

    Each surrogate starts as a random shuffle of ``x`` and alternates two projections until
    the rank order stops changing (or ``max_iter``): impose the Fourier amplitudes
    :math:`|X_k|` of ``x`` keeping the surrogate's phases, then impose the value distribution
    of ``x`` by rank ordering. The result has exactly the values of ``x`` and very nearly its
    power spectrum (so its linear autocorrelation), with everything else randomised: a
    realisation of the null hypothesis "a stationary linear Gaussian process, observed
    through a static monotonic function".

    Parameters
    ----------
    x
        The series (1-D). Mismatched end points leak spurious high frequencies into the
        surrogates; :func:`surrogate_test` trims the series so its ends match first.
    n_surrogates
        Number of surrogates.
    max_iter
        Largest number of iterations per surrogate.
    rng
        Seed or :class:`numpy.random.Generator`.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_surrogates, len(x))``.

    References
    ----------
    T. Schreiber and A. Schmitz, "Improved surrogate data for nonlinearity tests",
    Phys. Rev. Lett. 77, 635–638 (1996).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import iaaft_surrogates
    >>> x = np.random.default_rng(0).standard_normal(256).cumsum()
    >>> s = iaaft_surrogates(x, n_surrogates=3, rng=1)
    >>> s.shape, bool(np.array_equal(np.sort(s[0]), np.sort(x)))
    ((3, 256), True)
    """
    x = as_series(x, name="x", min_length=16)
    n_surrogates = check_int(n_surrogates, name="n_surrogates", minimum=1)
    max_iter = check_int(max_iter, name="max_iter", minimum=1)
    gen = as_generator(rng)
    n = x.size
    sorted_x = np.sort(x)
    amplitude = np.abs(np.fft.rfft(x))
    s = np.stack([gen.permutation(x) for _ in range(n_surrogates)])
    order = np.argsort(s, axis=1)
    active = np.arange(n_surrogates)
    for _ in range(max_iter):
        spectrum = np.fft.rfft(s[active], axis=1)
        magnitude = np.abs(spectrum)
        phase = np.divide(spectrum, magnitude, out=np.ones_like(spectrum), where=magnitude > 0)
        spectrum = amplitude * phase
        new_order = np.argsort(np.fft.irfft(spectrum, n=n, axis=1), axis=1)
        block = np.empty((active.size, n))
        np.put_along_axis(block, new_order, np.broadcast_to(sorted_x, block.shape), axis=1)
        s[active] = block
        converged = np.all(new_order == order[active], axis=1)
        order[active] = new_order
        active = active[~converged]
        if active.size == 0:
            break
    return s


def _smooth_lengths(low: int, high: int) -> np.ndarray:
    """Lengths in [low, high] with no prime factor above 5 (fast FFT sizes)."""
    out = []
    p2 = 1
    while p2 <= high:
        p3 = p2
        while p3 <= high:
            p5 = p3
            while p5 <= high:
                if p5 >= low:
                    out.append(p5)
                p5 *= 5
            p3 *= 3
        p2 *= 2
    return np.array(sorted(out), dtype=np.int64)


def match_ends(x: np.ndarray, *, max_trim: float = 0.1) -> slice:
    """The sub-series, trimmed by at most ``max_trim`` of its length at each end, whose end
    points best match in value and slope, among lengths with no prime factor above 5.

    Matching ends reduce the spectral leakage of Fourier surrogates (Schreiber & Schmitz,
    Physica D 142, 346, 2000); 5-smooth lengths keep every FFT of the iteration fast.
    """
    n = x.size
    trim = max(1, int(max_trim * n))
    lengths = _smooth_lengths(max(n - 2 * trim, 3), n - 1)
    if lengths.size == 0:
        return slice(0, n)
    starts = np.arange(0, trim)
    stops = starts[:, None] + lengths[None, :] - 1  # index of the last sample kept
    valid = stops <= n - 2  # the slope at the last sample needs one more sample
    stops_c = np.minimum(stops, n - 2)
    jump = x[starts][:, None] - x[stops_c]
    slope = (x[starts + 1] - x[starts])[:, None] - (x[stops_c + 1] - x[stops_c])
    cost = np.where(valid, jump**2 + slope**2, np.inf)
    i, j = np.unravel_index(int(np.argmin(cost)), cost.shape)
    if not np.isfinite(cost[i, j]):
        return slice(0, n)
    return slice(int(starts[i]), int(stops[i, j]) + 1)


def prediction_error(
    x: np.ndarray,
    *,
    embedding_dim: int,
    lag: int,
    horizon: int,
    theiler_window: int,
    n_neighbors: int = 5,
    n_reference: int = 500,
) -> float:
    r"""Normalised error of a locally constant predictor in delay space.

    For reference points :math:`s_i = (x_i, x_{i-\tau}, \ldots, x_{i-(m-1)\tau})`, the
    forecast of :math:`x_{i+h}` is the mean of :math:`x_{j+h}` over the ``n_neighbors``
    nearest :math:`s_j` with :math:`|i-j| >` ``theiler_window``; the statistic is the RMS
    forecast error divided by the standard deviation of ``x`` (1 = no better than the mean).
    ``n_reference`` evenly spaced reference points are used. Kantz & Schreiber, *Nonlinear
    Time Series Analysis*, 2nd ed. (Cambridge, 2004), §4.2.
    """
    n = x.size
    first = (embedding_dim - 1) * lag
    last = n - 1 - horizon  # last index with a known future
    n_points = last - first + 1
    need = 2 * theiler_window + n_neighbors + 2
    if n_points < need:
        raise ValueError(
            f"series too short for the prediction statistic: {n} samples leave {n_points} "
            f"embedded points with a known future, fewer than the {need} needed with this "
            "Theiler window."
        )
    idx = np.arange(first, last + 1)
    points = np.stack([x[idx - k * lag] for k in range(embedding_dim)], axis=1)
    tree = cKDTree(points)
    ref = np.unique(np.linspace(0, n_points - 1, min(n_reference, n_points)).astype(np.int64))
    forecast = _forecast(x[idx + horizon], points, tree, ref, theiler_window, n_neighbors)
    err = forecast - x[idx[ref] + horizon]
    spread = float(np.std(x))
    # a series constant over the part used (its ends trimmed) is predicted exactly
    return float(np.sqrt(np.mean(err**2)) / spread) if spread > 0.0 else 0.0


def _forecast(
    future: np.ndarray,
    points: np.ndarray,
    tree: cKDTree,
    ref: np.ndarray,
    theiler_window: int,
    n_neighbors: int,
) -> np.ndarray:
    """Mean ``future`` of the ``n_neighbors`` nearest points outside the Theiler window of
    each reference point (rows ``ref`` of ``points``).

    At most 2w + 1 points fall inside the window, so that many candidates more than
    ``n_neighbors`` always suffice; a few are tried first and the rows they leave short
    are asked again with four times as many. Only a smooth series, whose nearest points
    are its own neighbours in time, needs the long lists: a noise-like surrogate's
    nearest points are far apart in time. A short list decides a row only when the next
    admissible candidate lies strictly farther than the last one taken: with a tie there
    (repeated points: a periodic series sampled a whole number of times per period), which
    of the tied points the tree lists first depends on how many it is asked for, so such a
    row is decided by the full list, as if it had been asked for at once.
    """
    k_full = min(n_neighbors + 2 * theiler_window + 1, points.shape[0])
    k = min(4 * n_neighbors + 4, k_full)
    out = np.empty(ref.size)
    pending = np.arange(ref.size)
    while pending.size:
        rows = ref[pending]
        dist, cand = tree.query(points[rows], k=k)
        dist, cand = dist.reshape(rows.size, k), cand.reshape(rows.size, k)
        admissible = np.abs(cand - rows[:, None]) > theiler_window
        order = np.cumsum(admissible, axis=1)
        keep = admissible & (order <= n_neighbors)
        # summed over rows as long as the full list's (zeros after the k candidates): the
        # pairwise sum groups the terms as it did over that list, so the sums are the same
        terms = np.zeros((rows.size, k_full))
        terms[:, :k] = np.where(keep, future[cand], 0.0)
        mean = np.sum(terms, axis=1) / n_neighbors
        last = np.take_along_axis(dist, np.argmax(order >= n_neighbors, axis=1)[:, None], 1)
        after = np.take_along_axis(dist, np.argmax(order > n_neighbors, axis=1)[:, None], 1)
        done = (order[:, -1] > n_neighbors) & (after[:, 0] > last[:, 0])
        done |= k >= k_full
        out[pending[done]] = mean[done]
        pending = pending[~done]
        k = min(4 * k, k_full)
    return out


@dataclass(frozen=True, kw_only=True)
class SurrogateResult:
    """Outcome of :func:`surrogate_test`.

    Attributes
    ----------
    statistic
        Normalised prediction error of the data (``prediction_error``).
    surrogate_statistics
        The same statistic for each IAAFT surrogate.
    p_value
        One-sided rank p-value, :math:`(1 + \\#\\{s_k \\le s_0\\}) / (n + 1)`.
    effect
        Relative improvement of the data over the median surrogate,
        :math:`1 - s_0 / \\mathrm{median}(s_k)`.
    rejected
        True if ``p_value <= alpha`` and ``effect >= min_effect``: the data are more
        predictable than linear noise with the same spectrum and distribution.
    alpha, min_effect, n_surrogates, embedding_dim, lag, horizon, theiler_window
        The settings used.
    null
        The null hypothesis the surrogates realise: ``"linear noise"`` (IAAFT,
        :func:`surrogate_test`) or ``"noisy periodic orbit"`` (cycle-shuffled,
        :func:`~chaoskit.cycle_surrogate_test`).
    """

    statistic: float
    surrogate_statistics: np.ndarray
    p_value: float
    effect: float
    rejected: bool
    alpha: float
    min_effect: float
    n_surrogates: int
    embedding_dim: int
    lag: int
    horizon: int
    theiler_window: int
    null: str = "linear noise"

    def to_dataset(self) -> xr.Dataset:
        """The surrogate statistics over the dimension ``surrogate``; the rest as attributes."""
        ds = xr.Dataset(
            {
                "prediction_error": (
                    "surrogate",
                    self.surrogate_statistics,
                    {"units": "1", "long_name": "normalised prediction error of the surrogate"},
                )
            },
            coords={"surrogate": np.arange(self.n_surrogates)},
        )
        ds.attrs.update(
            {
                "statistic": self.statistic,
                "p_value": self.p_value,
                "effect": self.effect,
                "rejected": int(self.rejected),
                "alpha": self.alpha,
                "min_effect": self.min_effect,
                "embedding_dim": self.embedding_dim,
                "lag": self.lag,
                "horizon": self.horizon,
                "theiler_window": self.theiler_window,
                "null": self.null,
            }
        )
        return ds


def surrogate_test(
    x: Any,
    *,
    embedding_dim: int,
    lag: int,
    horizon: int | None = None,
    theiler_window: int | None = None,
    n_surrogates: int = 19,
    alpha: float = 0.05,
    min_effect: float = 0.1,
    n_neighbors: int = 5,
    max_iter: int = 100,
    rng: Any = None,
) -> SurrogateResult:
    r"""Test the null hypothesis "linear Gaussian noise" with IAAFT surrogates.

    The discriminating statistic is the normalised error of a locally constant predictor
    (``prediction_error``), which deterministic dynamics keep well below that of
    surrogates sharing the data's spectrum and value distribution. The series is first
    trimmed so that its ends match (:func:`iaaft_surrogates`). The test is one-sided and
    rank-based: with ``n_surrogates = 19`` the smallest p-value is 0.05. Rejection also
    needs an effect size (``effect >= min_effect``), so that a marginal rank on noise is not
    mistaken for determinism.

    Parameters
    ----------
    x
        The series.
    embedding_dim, lag
        Delay embedding used by the predictor (``lag`` in samples).
    horizon
        Forecast horizon in samples (default ``lag``).
    theiler_window
        Temporal exclusion for neighbours, samples (default ``embedding_dim * lag``).
    n_surrogates
        Number of IAAFT surrogates: at least :math:`1/\\alpha - 1` (19 for
        :math:`\\alpha = 0.05`), or the test could never reject (a ValueError says so).
    alpha
        Significance level.
    min_effect
        Smallest relative improvement over the median surrogate that counts.
    n_neighbors
        Neighbours averaged by the predictor.
    max_iter
        Largest number of IAAFT iterations per surrogate (the spectrum error is within a
        few per cent of its converged value after about 50).
    rng
        Seed or :class:`numpy.random.Generator`.

    Returns
    -------
    SurrogateResult

    References
    ----------
    J. Theiler, S. Eubank, A. Longtin, B. Galdrikian and J. D. Farmer, "Testing for
    nonlinearity in time series: the method of surrogate data", Physica D 58, 77–94 (1992);
    T. Schreiber and A. Schmitz, Phys. Rev. Lett. 77, 635 (1996).

    Examples
    --------
    >>> from chaoskit import systems, surrogate_test
    >>> res = surrogate_test(systems.henon(1000)[:, 0], embedding_dim=2, lag=1, rng=0)
    >>> res.rejected, res.p_value
    (True, 0.05)
    """
    stage("surrogates")
    x = as_series(x, name="x", min_length=64)
    embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1)
    lag = check_int(lag, name="lag", minimum=1)
    horizon = lag if horizon is None else check_int(horizon, name="horizon", minimum=1)
    if theiler_window is None:
        theiler_window = embedding_dim * lag
    theiler_window = check_int(theiler_window, name="theiler_window", minimum=0)
    alpha = check_probability(alpha, name="alpha")
    n_surrogates = check_surrogates(n_surrogates, alpha)
    min_effect = float(min_effect)
    if not 0.0 <= min_effect < 1.0:
        raise ValueError(f"min_effect must be in [0, 1); got {min_effect!r}.")
    n_neighbors = check_int(n_neighbors, name="n_neighbors", minimum=1)
    # the statistic is an error in the units of x: compute it on x * 2**-e (exact), scale back
    exponent = extreme_peak_exponent(x)
    x = np.ldexp(x, -exponent)
    x = x[match_ends(x)]
    if x.max() == x.min():  # e.g. a lone spike trimmed away with the ends
        raise ValueError(
            "x is constant over the end-matched window of the surrogate test; there is "
            "nothing to predict."
        )
    options = {
        "embedding_dim": embedding_dim,
        "lag": lag,
        "horizon": horizon,
        "theiler_window": theiler_window,
        "n_neighbors": n_neighbors,
    }
    stat = prediction_error(x, **options)
    surrogates = iaaft_surrogates(x, n_surrogates=n_surrogates, max_iter=max_iter, rng=rng)
    stats = np.array([prediction_error(s, **options) for s in surrogates])
    p_value = (1.0 + np.count_nonzero(stats <= stat)) / (n_surrogates + 1.0)
    median = float(np.median(stats))
    effect = 1.0 - stat / median if median > 0 else 0.0
    return SurrogateResult(
        statistic=float(np.ldexp(stat, exponent)),
        surrogate_statistics=np.ldexp(stats, exponent),
        p_value=float(p_value),
        effect=float(effect),
        rejected=bool(p_value <= alpha and effect >= min_effect),
        alpha=alpha,
        min_effect=min_effect,
        n_surrogates=n_surrogates,
        embedding_dim=embedding_dim,
        lag=lag,
        horizon=horizon,
        theiler_window=theiler_window,
    )
