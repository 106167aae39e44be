"""Embedding dimension: false nearest neighbours (Kennel 1992) and Cao's method (1997)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._neighbors import (
    GridSearch,
    check_theiler_window,
    default_theiler_window,
    grid_nearest_neighbors,
)
from .._progress import stage
from .._validate import as_series, check_choice, check_int, check_positive
from . import _kernels as _k
from ._embed import embed, standardize

__all__ = [
    "DimensionResult",
    "cao",
    "estimate_embedding_dim",
    "false_nearest_neighbors",
]

DEFAULT_FNN_THRESHOLD = 0.01
DEFAULT_CAO_THRESHOLD = 0.8
DEFAULT_MAX_POINTS = 20_000
#: references searched before the first check of an early-stopping FNN curve (doubling)
_FIRST_BLOCK = 64


@dataclass(frozen=True, kw_only=True)
class DimensionResult:
    """Embedding-dimension curve over ``dims`` and the chosen ``embedding_dim``.

    Attributes
    ----------
    embedding_dim
        The chosen dimension.
    method
        ``"fnn"`` or ``"cao"``.
    rule
        The selection rule in words (says so when no dimension met it).
    found
        ``False`` if no dimension up to ``max_dim`` met the rule (then ``embedding_dim`` is
        ``max_dim``).
    dims
        Dimensions ``1 … max_dim``.
    curve
        FNN: fraction of false nearest neighbours; Cao: E1(d) = E(d+1)/E(d).
    e2
        Cao's E2(d) = E*(d+1)/E*(d) (close to 1 at every d for stochastic data); empty for FNN.
    lag, theiler_window
        Delay (samples) and Theiler window (samples) used.
    n_reference
        Reference points per dimension (sub-sampled evenly when the series is long).
    """

    embedding_dim: int
    method: str
    rule: str
    found: bool
    dims: np.ndarray
    curve: np.ndarray
    lag: int
    theiler_window: int
    n_reference: int
    e2: np.ndarray = field(default_factory=lambda: np.empty(0))

    def to_dataset(self) -> xr.Dataset:
        """Curve (and E2) over ``embedding_dim`` with the choice in the attributes."""
        name, long = (
            ("false_fraction", "fraction of false nearest neighbours")
            if self.method == "fnn"
            else ("e1", "Cao E1(d) = E(d+1)/E(d)")
        )
        data = {name: ("dim", self.curve, {"units": "1", "long_name": long})}
        if self.e2.size:
            data["e2"] = ("dim", self.e2, {"units": "1", "long_name": "Cao E2(d)"})
        return xr.Dataset(
            data,
            coords={"dim": ("dim", self.dims, {"units": "1", "long_name": "embedding dimension"})},
            attrs={
                "embedding_dim": self.embedding_dim,
                "method": self.method,
                "rule": self.rule,
                "found": int(self.found),
                "lag": self.lag,
                "theiler_window": self.theiler_window,
                "n_reference": self.n_reference,
            },
        )


def _prepare(x: Any, lag: Any, max_dim: Any, theiler_window: Any, max_points: Any, extra: int):
    lag = check_int(lag, name="lag", minimum=1)
    max_dim = check_int(max_dim, name="max_dim", minimum=1, maximum=64)
    max_points = check_int(max_points, name="max_points", minimum=10)
    # the last dimension needs coordinate (max_dim + extra - 1)·lag and a few points
    need = (max_dim + extra - 1) * lag + 10
    arr = as_series(x, min_length=need)
    arr = standardize(arr)  # scale-free, and no overflow of squared distances
    n_last = arr.size - (max_dim + extra - 1) * lag
    if theiler_window is None:
        theiler_window = default_theiler_window(arr, n_last)
    else:
        theiler_window = check_int(theiler_window, name="theiler_window", minimum=0)
    check_theiler_window(theiler_window, n_last)
    return arr, lag, max_dim, theiler_window, max_points


def _references(n: int, max_points: int) -> np.ndarray:
    if n <= max_points:
        return np.arange(n, dtype=np.int64)
    # increasing, so the duplicates (none when n > max_points) are consecutive: no sort
    ref = np.linspace(0, n - 1, max_points).astype(np.int64)
    return ref[np.r_[True, ref[1:] != ref[:-1]]]


def _neighbours(arr, dim, lag, n_points, theiler_window, max_points, p):
    pts = embed(arr[: n_points + (dim - 1) * lag], dim, lag)
    ref = _references(n_points, max_points)
    # box-assisted: the same neighbours as a k-d tree, but a point inside the Theiler
    # window costs one comparison instead of a tree candidate
    nbr, dist = grid_nearest_neighbors(pts, theiler_window=theiler_window, query=ref, p=p)
    return ref, nbr, dist


def false_nearest_neighbors(
    x: Any,
    *,
    lag: int,
    max_dim: int = 10,
    rtol: float = 15.0,
    atol: float = 2.0,
    theiler_window: int | None = None,
    threshold: float = DEFAULT_FNN_THRESHOLD,
    max_points: int = DEFAULT_MAX_POINTS,
) -> DimensionResult:
    r"""Fraction of false nearest neighbours over embedding dimension (Kennel et al. 1992).

    For each reference point :math:`\mathbf y_i` in dimension :math:`d` and its nearest
    neighbour :math:`\mathbf y_j` (Euclidean, :math:`|i-j| >` ``theiler_window``) at distance
    :math:`R_d`, the pair is false if either test fails:

    .. math::
        \frac{|x_{i+d\tau} - x_{j+d\tau}|}{R_d} > R_{tol}
        \quad\text{or}\quad
        \frac{R_{d+1}}{R_A} > A_{tol},

    with :math:`R_A` the standard deviation of ``x``. The chosen dimension is the smallest
    :math:`d` whose false fraction is below ``threshold``.

    Parameters
    ----------
    x
        Scalar series; needs at least ``max_dim·lag + 10`` samples.
    lag
        Delay in samples.
    max_dim
        Largest dimension tested (1 … 64).
    rtol, atol
        Kennel's :math:`R_{tol}` (default 15) and :math:`A_{tol}` (default 2).
    theiler_window
        Neighbours with ``|i − j| <= theiler_window`` are excluded; default: one mean period
        of the series (capped at a tenth of the points).
    threshold
        False fraction regarded as zero (default 0.01).
    max_points
        Reference points per dimension; longer series are sub-sampled evenly (neighbours are
        still searched among all points). Default 20,000 (standard error of the fraction
        below 0.4 %).

    Returns
    -------
    DimensionResult
        ``curve`` = false fraction at ``dims = 1 … max_dim``.

    References
    ----------
    M. B. Kennel, R. Brown, H. D. I. Abarbanel, "Determining embedding dimension for
    phase-space reconstruction using a geometrical construction", Phys. Rev. A 45 (1992) 3403.

    Examples
    --------
    >>> from chaoskit import false_nearest_neighbors, systems
    >>> false_nearest_neighbors(systems.henon(5000)[:, 0], lag=1, max_dim=4).embedding_dim
    2
    """
    rtol = check_positive(rtol, name="rtol")
    atol = check_positive(atol, name="atol")
    threshold = check_positive(threshold, name="threshold")
    arr, lag, max_dim, w, max_points = _prepare(x, lag, max_dim, theiler_window, max_points, 1)
    return fnn_curve(arr, lag, max_dim, rtol, atol, w, threshold, max_points, stop_early=False)


def _decided_fraction(arr, d, lag, n_points, w, max_points, rtol, atol, size, threshold):
    """False fraction at dimension ``d``, or, once enough false neighbours are found for
    the fraction to reach ``threshold`` whatever the rest give, the fraction over the
    references examined so far (then at least ``threshold`` too: the choice is the same).

    The references are searched in growing blocks in time order; the answer to
    ``fraction < threshold`` is that of the full count. The grid is laid over every point
    of the dimension-``d`` embedding and the candidates limited to the first ``n_points``
    (the same neighbours), so that a caller embedding in ``d`` can search it again.
    Returns (fraction, references, (grid, answers)): ``answers`` holds the neighbour found
    for each row searched (−1 elsewhere), for candidates ``j < n_points``.
    """
    pts = embed(arr, d, lag)
    ref = _references(n_points, max_points)
    check_theiler_window(w, n_points)  # for the candidates searched, not the whole grid
    search = GridSearch(pts, theiler_window=w, p=2.0)
    known = np.full(pts.shape[0], -1, dtype=np.int64)
    false = used = 0
    start, block = 0, _FIRST_BLOCK
    while start < ref.size:
        part = ref[start : start + block]
        nbr, dist = search.query(part, limit=n_points, known=known)
        f, u = _k.fnn_counts(arr, part, nbr, dist, d, lag, rtol, atol, size)
        false, used = false + f, used + u
        start += block
        block *= 2
        # false only grows, so the full fraction is at least false / ref.size
        if start < ref.size and false / ref.size >= threshold:
            break
    return false / used, used, (search, known)


def fnn_curve(
    arr, lag, max_dim, rtol, atol, w, threshold, max_points, *, stop_early, searches=None
):
    """FNN fractions for d = 1 … max_dim on validated input.

    With ``stop_early``, the curve ends at the chosen dimension, and a dimension is left
    as soon as its false fraction is decided to reach ``threshold``
    (:func:`_decided_fraction`): the choice and the rule are those of the full curve, the
    entries of the rejected dimensions are fractions over the references examined (each
    at least ``threshold``). A dict ``searches`` (with ``stop_early``) receives, per
    dimension ``d`` tested, ``(grid, answers, limit)``: the
    :class:`~chaoskit._neighbors.GridSearch` over every point of ``embed(arr, d, lag)``
    with the Theiler window ``w``, and the neighbours it found among the first ``limit``
    points (−1 where not searched), which an estimator embedding in ``d`` reuses.
    """
    size = float(arr.std())
    fractions = []
    n_ref = 0
    for d in range(1, max_dim + 1):
        n_points = arr.size - d * lag  # the (d+1)-th coordinate must exist
        if stop_early:
            fraction, used, found = _decided_fraction(
                arr, d, lag, n_points, w, max_points, rtol, atol, size, threshold
            )
            if searches is not None:
                searches[d] = (*found, n_points)
        else:
            ref, nbr, dist = _neighbours(arr, d, lag, n_points, w, max_points, 2.0)
            false, used = _k.fnn_counts(arr, ref, nbr, dist, d, lag, rtol, atol, size)
            fraction = false / used
        fractions.append(fraction)
        n_ref = max(n_ref, used)
        if stop_early and fraction < threshold:
            break
    curve = np.asarray(fractions)
    return _select(
        curve,
        curve < threshold,
        "fnn",
        f"smallest dimension with false fraction < {threshold:g}",
        lag,
        w,
        n_ref,
    )


def _select(curve, ok, method, rule, lag, w, n_ref, e2=None) -> DimensionResult:
    dims = np.arange(1, curve.size + 1)
    hit = np.flatnonzero(ok)
    found = bool(hit.size)
    dim = int(dims[hit[0]]) if found else int(dims[-1])
    if not found:
        rule = f"no dimension up to max_dim met the rule ({rule}); used max_dim"
    return DimensionResult(
        embedding_dim=dim,
        method=method,
        rule=rule,
        found=found,
        dims=dims,
        curve=curve,
        lag=lag,
        theiler_window=w,
        n_reference=n_ref,
        e2=np.empty(0) if e2 is None else e2,
    )


def cao(
    x: Any,
    *,
    lag: int,
    max_dim: int = 10,
    theiler_window: int | None = None,
    threshold: float = DEFAULT_CAO_THRESHOLD,
    max_points: int = DEFAULT_MAX_POINTS,
) -> DimensionResult:
    r"""Cao's E1 and E2 over embedding dimension (Cao 1997).

    With :math:`n(i,d)` the nearest neighbour of :math:`\mathbf y_i(d)` in the maximum norm
    (Theiler window excluded),

    .. math::
        a(i,d) = \frac{\|\mathbf y_i(d+1) - \mathbf y_{n(i,d)}(d+1)\|_\infty}
                      {\|\mathbf y_i(d) - \mathbf y_{n(i,d)}(d)\|_\infty},\quad
        E(d) = \langle a(i,d)\rangle_i,\quad E_1(d) = \frac{E(d+1)}{E(d)},

    and :math:`E^*(d) = \langle |x_{i+d\tau} - x_{n(i,d)+d\tau}| \rangle_i`,
    :math:`E_2(d) = E^*(d+1)/E^*(d)`. E1 stops changing (≈ 1) once :math:`d` is large
    enough; the chosen dimension is the smallest :math:`d` with
    :math:`E_1(d) \ge` ``threshold``. Pairs closer than 1e-9 standard deviations (exact
    repeats, rounding noise) are skipped.

    Parameters
    ----------
    x
        Scalar series; needs at least ``(max_dim + 1)·lag + 10`` samples.
    lag
        Delay in samples.
    max_dim
        Largest dimension reported (E(max_dim + 1) is computed too).
    theiler_window
        As in :func:`false_nearest_neighbors`.
    threshold
        E1 level regarded as saturated (default 0.8, i.e. within 20 % of 1).
    max_points
        Reference points per dimension (even sub-sampling beyond it), default 20,000.

    Returns
    -------
    DimensionResult
        ``curve`` = E1 and ``e2`` = E2 at ``dims = 1 … max_dim``.

    References
    ----------
    L. Cao, "Practical method for determining the minimum embedding dimension of a scalar
    time series", Physica D 110 (1997) 43–50.

    Examples
    --------
    >>> from chaoskit import cao, systems
    >>> cao(systems.henon(5000)[:, 0], lag=1, max_dim=4).embedding_dim
    2
    """
    threshold = check_positive(threshold, name="threshold")
    arr, lag, max_dim, w, max_points = _prepare(x, lag, max_dim, theiler_window, max_points, 2)
    eps = 1e-9 * float(arr.std())  # closer pairs are rounding noise (exact repeats)
    e = np.empty(max_dim + 1)
    e_star = np.empty(max_dim + 1)
    n_ref = 0
    for d in range(1, max_dim + 2):
        n_points = arr.size - d * lag
        ref, nbr, dist = _neighbours(arr, d, lag, n_points, w, max_points, np.inf)
        sa, se, used = _k.cao_sums(arr, ref, nbr, dist, d, lag, eps)
        if used == 0:
            raise ValueError(
                f"every nearest-neighbour pair at dimension {d} is at (numerically) zero "
                "distance; the series repeats exactly and Cao's E1 is undefined."
            )
        e[d - 1] = sa / used
        e_star[d - 1] = se / used
        n_ref = max(n_ref, used)
    e1 = e[1:] / e[:-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        e2 = np.where(e_star[:-1] > 0, e_star[1:] / e_star[:-1], 1.0)
    return _select(
        e1,
        e1 >= threshold,
        "cao",
        f"smallest dimension with E1 >= {threshold:g}",
        lag,
        w,
        n_ref,
        e2,
    )


def estimate_embedding_dim(
    x: Any, *, lag: int, method: Literal["fnn", "cao"] = "fnn", max_dim: int = 10, **options
) -> DimensionResult:
    """Choose the embedding dimension with :func:`false_nearest_neighbors` or :func:`cao`.

    Parameters
    ----------
    x
        Scalar series.
    lag
        Delay in samples (for example from :func:`estimate_delay`).
    method
        ``"fnn"`` (default) or ``"cao"``.
    max_dim
        Largest dimension tested.
    **options
        Passed to the chosen function (``rtol``, ``atol``, ``theiler_window``,
        ``threshold``, ``max_points``).

    Returns
    -------
    DimensionResult

    Examples
    --------
    >>> from chaoskit import estimate_embedding_dim, systems
    >>> estimate_embedding_dim(systems.logistic(5000), lag=1, max_dim=3).embedding_dim
    1
    """
    stage("dimension")
    check_choice(method, name="method", choices=("fnn", "cao"))
    func = false_nearest_neighbors if method == "fnn" else cao
    return func(x, lag=lag, max_dim=max_dim, **options)
