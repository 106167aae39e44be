"""Input handling shared by the Lyapunov estimators: validation, lag, dimension, window."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._neighbors import mean_period
from .._tables import check_index_interval
from .._validate import as_series, check_int, check_positive
from ..embedding import DEFAULT_FNN_THRESHOLD, embed, fnn_curve, lag_or_estimate, standardize

MIN_SAMPLES = 100
_DIM_POINTS = 5000  # FNN reference points for the automatic dimension (s.e. < 0.2 % at 1 %)


@dataclass(frozen=True)
class Prepared:
    arr: np.ndarray
    pts: np.ndarray
    dt: float
    lag: int
    embedding_dim: int
    theiler_window: int
    lag_rule: str
    dim_rule: str
    period: float
    scale: float
    # the automatic dimension's grid over ``pts`` (Theiler window ``theiler_window``), the
    # neighbours it found and their candidate limit (see ``fnn_curve``); None otherwise
    neighbors: tuple | None = None


def _theiler_window(period: float, n_points: int) -> int:
    """:func:`~chaoskit._neighbors.default_theiler_window` from the mean period."""
    return int(max(1, min(int(np.ceil(period)), n_points // 10)))


def _too_short(n: int, need: int, what: str) -> ValueError:
    return ValueError(f"x is too short: {n} samples, but {what} needs at least {need} samples.")


def prepare(
    x: Any,
    *,
    embedding_dim: Any,
    lag: Any,
    dt: Any,
    theiler_window: Any,
    min_future: int,
) -> Prepared:
    """Validate, estimate missing lag/dimension, embed, choose the Theiler window.

    ``min_future`` is the number of samples each reference point must have after it (the
    horizon or evolution length) and enters the minimum-length check.
    """
    dt = check_positive(dt, name="dt")
    check_index_interval(x, dt)
    arr = as_series(x, min_length=MIN_SAMPLES)
    # work in units of the standard deviation: exact scale invariance and no overflow of
    # squared distances for huge amplitudes
    peak = float(np.max(np.abs(arr)))
    scale = float((arr / peak).std()) * peak
    arr = standardize(arr)
    n = arr.size
    # one periodogram for the period and both default Theiler windows
    period = mean_period(arr)
    lag, lag_rule = lag_or_estimate(arr, lag)
    searches: dict[int, tuple] = {}
    if embedding_dim is None:
        max_dim = min(10, (n - 10) // lag - 1)
        if max_dim < 1:
            raise _too_short(n, 2 * lag + 11, f"estimating the embedding dimension at lag={lag}")
        w_fnn = _theiler_window(period, n - max_dim * lag)
        dim = fnn_curve(
            arr,
            lag,
            max_dim,
            15.0,
            2.0,
            w_fnn,
            DEFAULT_FNN_THRESHOLD,
            _DIM_POINTS,
            stop_early=True,
            searches=searches,
        )
        embedding_dim, dim_rule = dim.embedding_dim, f"estimated: FNN, {dim.rule}"
    else:
        embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1, maximum=64)
        dim_rule = "given"
    span = (embedding_dim - 1) * lag
    n_points = n - span
    if theiler_window is None:
        w = _theiler_window(period, max(n_points - min_future, 1))
    else:
        w = check_int(theiler_window, name="theiler_window", minimum=0)
    need = span + min_future + 2 * w + 2
    if n < need:
        raise _too_short(
            n,
            need,
            f"embedding_dim={embedding_dim}, lag={lag}, a horizon of {min_future} samples and "
            f"theiler_window={w} (every reference point needs an admissible neighbour)",
        )
    # the dimension's search reused when its window is the estimator's
    neighbors = searches.get(embedding_dim)
    if neighbors is not None and neighbors[0].theiler_window != w:
        neighbors = None
    return Prepared(
        arr=arr,
        pts=embed(arr, embedding_dim, lag) if neighbors is None else neighbors[0].points,
        dt=dt,
        lag=lag,
        embedding_dim=embedding_dim,
        theiler_window=w,
        lag_rule=lag_rule,
        dim_rule=dim_rule,
        period=period,
        scale=scale,
        neighbors=neighbors,
    )


def prepare_vectors(
    points: Any, *, embedding_dim: Any, lag: Any, dt: Any, theiler_window: Any, min_future: int
) -> Prepared:
    """Validate state vectors (rows in time order) given instead of a scalar series.

    Each column is standardised (zero mean, unit standard deviation) and no embedding is
    made. ``lag`` (samples) only tells a flow (``lag > 1``) from a map; by default it is
    estimated on the first column. The mean period and the default Theiler window are
    taken over the columns (the longest mean period).
    """
    dt = check_positive(dt, name="dt")
    pts = np.asarray(getattr(points, "values", points))
    if pts.dtype.kind not in "fiu" or pts.ndim != 2:
        raise ValueError(f"state vectors must be a numeric (n, d) array; got shape {pts.shape}.")
    if not np.all(np.isfinite(pts)):
        raise ValueError("state vectors contain NaN or inf values.")
    n, d = pts.shape
    if embedding_dim is not None and check_int(embedding_dim, name="embedding_dim", minimum=1) != d:
        raise ValueError(
            f"embedding_dim={embedding_dim} but the state vectors have {d} coordinates; "
            "leave embedding_dim=None for state vectors."
        )
    if n < MIN_SAMPLES:
        raise _too_short(n, MIN_SAMPLES, "a set of state vectors")
    columns = [as_series(pts[:, j], name=f"column {j} of the state vectors") for j in range(d)]
    arr = standardize(columns[0])
    lag, lag_rule = lag_or_estimate(arr, lag)
    period = max(mean_period(standardize(c)) for c in columns)
    if theiler_window is None:
        w = int(max(1, min(np.ceil(period), max(n - min_future, 1) // 10)))
    else:
        w = check_int(theiler_window, name="theiler_window", minimum=0)
    need = min_future + 2 * w + 2
    if n < need:
        raise _too_short(
            n, need, f"a horizon of {min_future} samples and theiler_window={w} (state vectors)"
        )
    return Prepared(
        arr=arr,
        pts=np.ascontiguousarray(np.column_stack([standardize(c) for c in columns])),
        dt=dt,
        lag=lag,
        embedding_dim=d,
        theiler_window=w,
        lag_rule=lag_rule,
        dim_rule=f"given: {d} coordinates of state vectors",
        period=period,
        scale=1.0,
    )


def result_fields(prep: Prepared) -> dict[str, Any]:
    """The :class:`LyapunovResult` fields every estimator takes from its prepared input."""
    return {
        "dt": prep.dt,
        "embedding_dim": prep.embedding_dim,
        "lag": prep.lag,
        "theiler_window": prep.theiler_window,
        "lag_rule": prep.lag_rule,
        "dim_rule": prep.dim_rule,
        "n_samples": int(prep.arr.size),
    }


def references(n: int, max_points: int) -> np.ndarray:
    """All of ``0 … n−1`` or ``max_points`` of them evenly spaced."""
    if n <= max_points:
        return np.arange(n, dtype=np.int64)
    # increasing, so the duplicates (none when n > max_points) are consecutive: no sort
    ref = np.linspace(0, n - 1, max_points).astype(np.int64)
    return ref[np.r_[True, ref[1:] != ref[:-1]]]


def batch_edges(n: int, n_batches: int = 20) -> np.ndarray:
    """Boundaries of the contiguous batches of ``n`` time-ordered values (at most
    ``n_batches``, at least two values each; fewer than two batches: empty)."""
    b = int(min(n_batches, n // 2))
    if b < 2:
        return np.empty(0, dtype=np.int64)
    return np.linspace(0, n, b + 1).astype(np.int64)


@functools.lru_cache(maxsize=64)
def _t975(dof: int) -> float:
    """97.5 % quantile of Student's t (a scipy call costs ≈ 0.4 ms; a few are ever asked)."""
    from scipy.stats import t as student_t

    return float(student_t.ppf(0.975, dof))


def batch_half_width(means: np.ndarray) -> float:
    """95 % Student-t half-width of the mean of the batch ``means``."""
    b = means.size
    return float(_t975(b - 1) * means.std(ddof=1) / np.sqrt(b))


def batch_means_ci(values: np.ndarray, n_batches: int = 20) -> tuple[float, float, int]:
    """95 % t-interval half-width of the mean of time-ordered ``values`` by batch means.

    Contiguous batches absorb the correlation between neighbouring reference points.
    Returns (mean, half_width, batches used).
    """
    n = values.size
    edges = batch_edges(n, n_batches)
    if edges.size == 0:
        return (
            float(values.mean()) if n else float("nan"),
            float("inf"),
            int(min(n_batches, n // 2)),
        )
    means = np.add.reduceat(values, edges[:-1]) / np.diff(edges)
    return float(means.mean()), batch_half_width(means), edges.size - 1


# Relative systematic error of each estimator's default estimate, as a 95 % half-width over
# |estimate|: (maps, flows). Measured against tangent-space exponents on the public corpus
# (``benchmarks/estimator_corpus.py``; every dysts flow and five maps at N = 2000 and
# 20 000): the flow value is the smallest that brings the coverage of one half of the flows
# to 90 % at both lengths, checked on the other half (``docs/estimators.md``). Below 1, so
# it never moves a bound across zero by itself.
SYSTEMATIC = {"rosenstein": (0.05, 0.75), "kantz": (0.05, 0.9), "wolf": (0.05, 0.75)}


def with_systematic(
    estimate: float, below: float, above: float, *, method: str, flow: bool
) -> tuple[tuple[float, float], float, str]:
    """The 95 % interval of ``estimate`` whose half-widths ``below`` and ``above`` (sampling
    and fit choices) are combined in quadrature with the method's systematic term
    (:data:`SYSTEMATIC`), that term's half-width, and the words for ``ci_method``."""
    rel = SYSTEMATIC[method][1 if flow else 0]
    sys_half = rel * abs(estimate)
    low = estimate - float(np.hypot(below, sys_half))
    high = estimate + float(np.hypot(above, sys_half))
    note = (
        f", combined in quadrature with the method's systematic error on "
        f"{'flows' if flow else 'maps'} ({rel:.0%} of the estimate, measured on a public corpus)"
    )
    return (low, high), sys_half, note
