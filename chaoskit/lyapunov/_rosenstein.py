"""Largest Lyapunov exponent from the mean log divergence of nearest neighbours."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from .._neighbors import GridSearch, check_theiler_window
from .._progress import stage
from .._validate import check_choice, check_int
from . import _kernels as _k
from ._common import (
    Prepared,
    batch_edges,
    batch_half_width,
    batch_means_ci,
    prepare,
    prepare_vectors,
    references,
    result_fields,
    with_systematic,
)
from ._result import LyapunovResult
from ._scaling import TOLERANCES, family_spread, saturation_index, scaling_region

__all__ = ["lyapunov_rosenstein"]

_LN2 = float(np.log(2.0))
DEFAULT_MAX_POINTS = 10_000
_PILOT_POINTS = 1000
_PLATEAU_PAIRS = 4000
_MAX_CURVE_POINTS = 400
_SLOPE_POINTS = 32
_MIN_HORIZON = 8
WEAK_CHAOS = 0.7  # nats per mean period below which the along-flow separation dominates
SPAN_PERIODS = 0.5  # shortest automatic fit window, in mean periods
_NEIGHBOR_MODES = {"sample": _k.EUCLIDEAN, "orbit": _k.ORBIT, "mean": _k.SAMPLE_ORBIT}
_TRANSVERSE_RULE = "transverse distance: nearest sample (the projection drops the offset)"
_MODE_NAMES = {
    _k.EUCLIDEAN: "sample",
    _k.ORBIT: "orbit",
    _k.SAMPLE_ORBIT: "mean",
    _k.TRANSVERSE: "sample",
}


def plateau_level(pts: np.ndarray, w: int, rng: np.random.Generator, transverse: bool) -> float:
    """Mean ln distance between random, time-separated pairs: the saturation level."""
    n = pts.shape[0]
    i = rng.integers(0, n, _PLATEAU_PAIRS)
    j = rng.integers(0, n, _PLATEAU_PAIRS)
    keep = np.abs(i - j) > w
    return float(_k.mean_log_distance(pts, i[keep], j[keep], transverse))


def _mean_curve(pts, ref, nbr, ks, mode, shift) -> tuple[np.ndarray, np.ndarray]:
    """Mean log divergence over ``ks`` and whether each horizon has any term."""
    total, count = _k.log_divergence(pts, ref, nbr, ks, mode, shift)
    ok = count > 0
    return np.where(ok, total / np.maximum(count, 1), np.nan), ok


def _slope(ks: np.ndarray, curve: np.ndarray, a: int, b: int) -> float:
    return float(np.polyfit(ks[a : b + 1].astype(np.float64), curve[a : b + 1], 1)[0])


def window_spread(ks, curve, a, b, end, slope, min_span) -> tuple[float, float]:
    """Sensitivity of the estimate to the fit range, below and above the slope: the largest
    change of the slope when either end of the fit window moves by a fifth of its length
    (within 0 … ``end``), or how far the slopes of the other plausible windows reach
    (:func:`family_spread`), whichever is larger on each side."""
    step = max(1, round(0.2 * (b - a)))
    spread = 0.0
    for lo, hi in ((a - step, b), (a + step, b), (a, b - step), (a, b + step)):
        lo, hi = max(lo, 0), min(hi, end)
        if hi - lo >= 2:
            spread = max(spread, abs(_slope(ks, curve, lo, hi) - slope))
    below, above = family_spread(ks, curve, a, b, end, min_span=min_span)
    return max(spread, below), max(spread, above)


def _fit(pts, ref, nbr, ks, fixed, w, period, mode, shift, sample_plateau) -> dict:
    """Divergence curve over ``ks``, fit range (given or automatic), slope, r², interval.

    ``mode`` is a distance mode of :mod:`._kernels`; for SAMPLE_ORBIT the curve is the mean
    of the sample and orbit curves and half their slope difference is kept as a systematic
    uncertainty (``nbr_half``).
    """
    nbr_pair = None
    if mode == _k.SAMPLE_ORBIT:
        # both curves in one pass over the pairs (each bit for bit its own pass's)
        total, count = _k.sample_orbit_log_divergence(pts, ref, nbr, ks, shift)
        y_sample, y_orbit = np.where(count > 0, total / np.maximum(count, 1), np.nan)
        ok = (count[0] > 0) & (count[1] > 0)
        nbr_pair = (y_sample[ok], y_orbit[ok])
        curve = 0.5 * (y_sample + y_orbit)
    else:
        curve, ok = _mean_curve(pts, ref, nbr, ks, mode, shift)
    if ok.sum() < 2:
        raise ValueError(
            "fewer than two horizons have a non-zero neighbour distance: the series repeats "
            "exactly, so the divergence (and the exponent) is undefined."
        )
    ks, curve = ks[ok], curve[ok]
    plateau = sample_plateau  # the level of :func:`plateau_level`, computed once
    if mode == _k.TRANSVERSE:
        plateau = plateau_level(pts, w, np.random.default_rng(12345), True)
    if fixed:
        a = int(np.searchsorted(ks, fixed[0]))
        b = int(np.searchsorted(ks, fixed[1], side="right")) - 1
        found = True
        if b - a < 1:
            raise ValueError(f"fit_range {fixed!r} holds fewer than two usable horizons.")
    else:
        a, b, found = scaling_region(
            ks, curve, plateau=plateau, min_span=max(3.0, SPAN_PERIODS * period)
        )
    kfit = ks[a : b + 1].astype(np.float64)
    yfit = curve[a : b + 1]
    slope, intercept = np.polyfit(kfit, yfit, 1)
    resid = yfit - (slope * kfit + intercept)
    sst = float(((yfit - yfit.mean()) ** 2).sum())
    r2 = 1.0 - float((resid**2).sum()) / sst if sst > 0 else 0.0
    # per-pair slopes only feed the spread (the centre is the curve's slope): 32 horizons
    # spread over the fit range estimate them well at a fraction of the cost
    kw = ks[a : b + 1]
    kw = kw[np.unique(np.linspace(0, kw.size - 1, min(kw.size, _SLOPE_POINTS)).astype(int))]
    half, n_batches, n_valid = slope_spread(pts, ref, nbr, kw, mode, shift)
    fit_half = (0.0, 0.0)
    if not fixed and found:
        end = max(b, saturation_index(curve, plateau))
        fit_half = window_spread(
            ks, curve, a, b, end, float(slope), max(3.0, SPAN_PERIODS * period)
        )
    nbr_half = 0.0
    if nbr_pair is not None:
        nbr_half = 0.5 * abs(_slope(ks, nbr_pair[1], a, b) - _slope(ks, nbr_pair[0], a, b))
    return {
        "ks": ks,
        "curve": curve,
        "a": a,
        "b": b,
        "found": found,
        "slope": float(slope),
        "r2": r2,
        "half": half,
        "fit_half": fit_half,
        "nbr_half": nbr_half,
        "n_batches": n_batches,
        "n_valid": n_valid,
        "plateau": plateau,
    }


def slope_spread(pts, ref, nbr, ks, mode, shift) -> tuple[float, int, int]:
    """Batch-means half-width of the per-pair slopes over ``ks``, the number of batches
    and of valid pairs (:func:`batch_means_ci` of :func:`~._kernels.pair_slopes`).

    For the sample and sample-and-orbit distances the batch sums come from
    :func:`~._kernels.batch_slope_sums` (one log per horizon and 512 pairs instead of one
    per pair and horizon; the same half-width within 1e-12 relative), unless some pair
    has a zero distance.
    """
    if mode in (_k.EUCLIDEAN, _k.SAMPLE_ORBIT):
        edge = 1 if mode == _k.SAMPLE_ORBIT else 0
        inside = (ref + ks[-1] < pts.shape[0]) & (nbr + ks[-1] + edge < pts.shape[0])
        n_valid = int(inside.sum())
        edges = batch_edges(n_valid)
        if edges.size:
            sums, ok = _k.batch_slope_sums(
                pts, ref[inside], nbr[inside], ks, mode, shift[inside], edges
            )
            if ok:
                return batch_half_width(sums / np.diff(edges)), edges.size - 1, n_valid
    slopes, valid = _k.pair_slopes(pts, ref, nbr, ks, mode, shift)
    _, half, n_batches = batch_means_ci(slopes[valid])
    return half, n_batches, int(valid.sum())


def _grid(h: int) -> np.ndarray:
    """Horizons 0 … h, thinned to at most ~400 evenly spaced samples."""
    step = max(1, int(np.ceil(h / _MAX_CURVE_POINTS)))
    ks = np.arange(0, h + 1, step, dtype=np.int64)
    if ks[-1] != h:
        ks = np.append(ks, h)
    return ks


def grid_search(prep: Prepared) -> GridSearch:
    """The nearest-neighbour grid over ``prep.pts`` with its Theiler window: the automatic
    dimension's own when it has that window, else a new one."""
    if prep.neighbors is not None:
        return prep.neighbors[0]
    return GridSearch(prep.pts, theiler_window=prep.theiler_window)


def _known_neighbors(prep: Prepared, usable: int) -> np.ndarray | None:
    """The neighbours the automatic dimension found that hold for candidates ``j <
    usable`` (−1 elsewhere), or None. A nearest neighbour among the first ``limit`` points
    that lies below ``usable <= limit`` is also the nearest (ties: the smallest index)
    among the first ``usable``."""
    if prep.neighbors is None or usable > prep.neighbors[2]:
        return None
    answers = prep.neighbors[1]
    return np.where(answers < usable, answers, -1)


def _auto_horizon(search: GridSearch, period: float, plateau: float, cap: int) -> int:
    """Grow the horizon (doubling) on a pilot set until the curve nears its plateau."""
    pts = search.points
    n = pts.shape[0]
    ref = references(n, _PILOT_POINTS)
    nbr, _ = search.query(ref)
    h = int(min(cap, max(16, np.ceil(4 * period))))
    while True:
        ks = _grid(h)
        total, count = _k.log_divergence(pts, ref, nbr, ks, _k.EUCLIDEAN, np.zeros(ref.size))
        ok = count > 0
        y = total[ok] / count[ok]
        if y.size and plateau > y[0]:
            hit = np.flatnonzero(y >= y[0] + 0.9 * (plateau - y[0]))
            if hit.size:
                return int(min(cap, max(_MIN_HORIZON, np.ceil(1.25 * ks[ok][hit[0]]))))
        if h >= cap:
            return cap
        h = min(cap, 2 * h)


def horizon_for(
    prep: Prepared,
    plateau: float,
    min_future: int,
    max_horizon: int | None,
    fixed: tuple[int, int] | None,
    search: GridSearch | None = None,
) -> int:
    """``max_horizon`` if given, else the automatic horizon (capped at 20 mean periods, at
    least 64, and half the usable points), never short of a given fit range; the pilot's
    neighbours come from ``search`` (default: :func:`grid_search`)."""
    if max_horizon is not None:
        return max_horizon
    pts, w = prep.pts, prep.theiler_window
    cap = int(min((pts.shape[0] - 2 * w - 2) // 2, max(64, np.ceil(20 * prep.period))))
    search = grid_search(prep) if search is None else search
    horizon = _auto_horizon(search, prep.period, plateau, max(cap, min_future))
    return max(horizon, fixed[1]) if fixed else horizon


def prepare_curve(
    x: Any,
    embedding_dim: Any,
    lag: Any,
    dt: Any,
    theiler_window: Any,
    max_horizon: Any,
    fit_range: Any,
    *,
    vectors: bool = False,
) -> tuple[Prepared, tuple[int, int] | None, int | None, int]:
    """Validate the options of a divergence-curve estimator and prepare the input
    (``vectors``: ``x`` is an (n, d) array of state vectors, see :func:`prepare_vectors`).

    Returns the prepared input, the given fit range (``None`` for ``"auto"``), the validated
    ``max_horizon`` and the number of samples each reference point needs ahead of it.
    """
    if max_horizon is not None:
        max_horizon = check_int(max_horizon, name="max_horizon", minimum=2)
    fixed = _parse_fit_range(fit_range, max_horizon)
    min_future = max_horizon if max_horizon is not None else (fixed[1] if fixed else _MIN_HORIZON)
    prepare_input = prepare_vectors if vectors else prepare
    prep = prepare_input(
        x,
        embedding_dim=embedding_dim,
        lag=lag,
        dt=dt,
        theiler_window=theiler_window,
        min_future=min_future,
    )
    return prep, fixed, max_horizon, min_future


def _parse_fit_range(fit_range: Any, max_horizon: int | None) -> tuple[int, int] | None:
    """``None`` for ``"auto"``, else the validated pair ``(first, last)`` of horizons."""
    if isinstance(fit_range, str) and fit_range == "auto":
        return None
    try:
        first, last = (int(v) for v in fit_range)
    except (TypeError, ValueError):
        raise ValueError(
            f"fit_range must be 'auto' or a pair (first, last) of horizons; got {fit_range!r}."
        ) from None
    if not 0 <= first < last:
        raise ValueError(f"fit_range must satisfy 0 <= first < last; got {fit_range!r}.")
    if max_horizon is not None and last > max_horizon:
        raise ValueError(f"fit_range ends at {last}, beyond max_horizon={max_horizon}.")
    return first, last


def lyapunov_rosenstein(
    x: Any,
    *,
    embedding_dim: int | None = None,
    lag: int | None = None,
    dt: float = 1.0,
    theiler_window: int | None = None,
    max_horizon: int | None = None,
    fit_range: Literal["auto"] | tuple[int, int] = "auto",
    max_points: int = DEFAULT_MAX_POINTS,
    distance: Literal["auto", "euclidean", "transverse"] = "auto",
    neighbor: Literal["auto", "sample", "orbit", "mean"] = "auto",
) -> LyapunovResult:
    r"""Largest Lyapunov exponent by Rosenstein's nearest-neighbour divergence.

    Each reference point :math:`\mathbf y_i` of the delay embedding is paired with its
    nearest neighbour :math:`\mathbf y_j` (Euclidean, :math:`|i-j| >` ``theiler_window``);
    the mean log distance after :math:`k` samples

    .. math:: y(k) = \big\langle \ln \|\mathbf y_{i+k} - \mathbf y_{j+k}\| \big\rangle_i
              \approx y(0) + \lambda_1 \, k \, \Delta t

    grows linearly in the scaling region, and :math:`\lambda_1` is the least-squares slope
    there divided by ``dt``. Distances are measured in units of the standard deviation of
    ``x`` (the series is standardised first), so ``curve`` is dimensionless and the result
    does not depend on the amplitude or offset of ``x``.

    Defaults (only ``dt`` given):

    * ``lag``: :func:`~chaoskit.estimate_delay` with ``method="auto"``; ``embedding_dim``:
      smallest dimension with < 1 % false nearest neighbours;
    * ``theiler_window``: one mean period (1 / power-weighted mean frequency), at most a
      tenth of the points;
    * ``max_horizon``: grown until the curve nears its plateau, at most 20 mean periods and
      half the usable points; ``fit_range="auto"``: the longest, steepest straight window
      before saturation;
    * reference points: all, or ``max_points`` evenly spaced ones (``subsampled``);
    * ``distance="auto"``: Euclidean, but a flow whose exponent per mean period is below 0.7
      nats is refitted with the distance transverse to the flow (a neighbour's along-flow
      offset flattens the Euclidean curve of weakly chaotic flows such as Rössler);
    * ``neighbor="auto"``: maps use the nearest sample; flows the mean of the nearest-sample
      and closest-orbit-point curves, which bracket the exponent.

    ``ci`` is a 95 % interval: batch means of the per-pair slopes, plus the slope change
    when the fit window's ends move, plus (``neighbor="mean"``) half the difference of the
    two neighbour curves, combined in quadrature with the method's systematic error
    measured against tangent-space exponents on a public corpus of chaotic flows and maps
    (``benchmarks/estimator_corpus.py``): 5 % of the estimate for maps, 75 % for flows
    (``params["ci_systematic_half_width"]``). The rules, their bias on Lorenz and Rössler
    and the interval's coverage are measured in ``docs/estimators.md``.

    **State vectors.** ``x`` may instead be an ``(n, d)`` array whose rows are the states
    in time order (measured coordinates of a multivariate trajectory, or a mixed delay
    embedding built by the caller; Cao, Mees & Judd 1998). Each column is standardised and
    no embedding is made; ``embedding_dim`` must be None (or ``d``) and ``lag`` only tells
    a flow (``lag > 1``) from a map (default: estimated on the first column); the default
    Theiler window is the longest mean period of the columns.

    Parameters
    ----------
    x
        Scalar series (numpy, pandas or 1-D xarray), at least 100 samples, finite and not
        constant; or an ``(n, d)`` array of state vectors (see above).
    embedding_dim, lag
        Embedding dimension and delay (samples); estimated when ``None``.
    dt
        Sampling interval (> 0). ``mle`` is per unit of ``dt``; use ``dt=1`` for maps.
    theiler_window
        Exclude neighbours with ``|i − j| <= theiler_window`` (samples).
    max_horizon
        Largest horizon k (samples) of the divergence curve; automatic when ``None``.
    fit_range
        ``"auto"`` or ``(first, last)`` horizon in samples, ``0 <= first < last <= max_horizon``.
    max_points
        Largest number of reference points (default 10,000).
    distance
        ``"auto"`` (default, see above), ``"euclidean"`` or ``"transverse"``.
    neighbor
        ``"auto"`` (default, see above), ``"sample"`` (Rosenstein's nearest sample, as in
        ``nolds.lyap_r``), ``"orbit"`` or ``"mean"``; only the Euclidean distance uses it.

    Returns
    -------
    LyapunovResult
        ``mle`` (natural log per unit of ``dt``), ``mle_bits_per_sample``, ``ci``, the curve
        ``curve`` over ``horizon``, ``fit_range``, ``r2`` and all parameters used.

    Raises
    ------
    ValueError
        For non-numeric, non-finite or constant input, ``dt <= 0``, a series too short for
        the embedding, horizon and Theiler window (the message gives the minimum length), or
        a Theiler window that leaves no neighbours.

    References
    ----------
    M. T. Rosenstein, J. J. Collins, C. J. De Luca, "A practical method for calculating
    largest Lyapunov exponents from small data sets", Physica D 65 (1993) 117–134;
    L. Cao, A. Mees, K. Judd, "Dynamics from multivariate time series", Physica D 121
    (1998) 75–88 (mixed embeddings).

    Examples
    --------
    >>> from chaoskit import lyapunov_rosenstein, systems
    >>> res = lyapunov_rosenstein(systems.henon(10_000)[:, 0])
    >>> bool(abs(res.mle - 0.419) < 0.02)
    True
    """
    stage("rosenstein")
    max_points = check_int(max_points, name="max_points", minimum=10)
    check_choice(distance, name="distance", choices=("auto", "euclidean", "transverse"))
    check_choice(neighbor, name="neighbor", choices=("auto", "sample", "orbit", "mean"))
    vectors = np.ndim(getattr(x, "values", x)) == 2 and min(np.shape(x)) > 1
    prep, fixed, max_horizon, min_future = prepare_curve(
        x, embedding_dim, lag, dt, theiler_window, max_horizon, fit_range, vectors=vectors
    )
    pts, w = prep.pts, prep.theiler_window
    n_pts = pts.shape[0]
    plateau = plateau_level(pts, w, np.random.default_rng(12345), False)
    # one grid for the pilot and the main search (the dimension's, when it can be reused)
    search = grid_search(prep)
    horizon_max = horizon_for(prep, plateau, min_future, max_horizon, fixed, search)
    usable = n_pts - horizon_max
    ks = _grid(horizon_max)
    if fixed:
        ks = (
            np.union1d(ks, np.arange(fixed[0], fixed[1] + 1))
            if ks.size > 1 and (ks[1] - ks[0] > 1)
            else ks
        )
    ref = references(usable, max_points)
    check_theiler_window(w, usable)
    # candidates among the first ``usable`` points: those with a future of the horizon
    nbr, _ = search.query(ref, limit=usable, known=_known_neighbors(prep, usable))
    flow = prep.lag > 1
    shift = np.zeros(ref.size)
    if neighbor in ("orbit", "mean") or (neighbor == "auto" and flow):
        shift = _k.orbit_shifts(pts, ref, nbr)

    if distance == "transverse":
        mode, nbr_rule = _k.TRANSVERSE, _TRANSVERSE_RULE
    elif neighbor != "auto":
        mode, nbr_rule = _NEIGHBOR_MODES[neighbor], "given"
    elif flow:
        mode, nbr_rule = _k.SAMPLE_ORBIT, "auto: flow (lag > 1), mean of sample and orbit"
    else:
        mode, nbr_rule = _k.EUCLIDEAN, "auto: map (lag 1), nearest sample"
    used = distance
    rule = "given"
    fit = _fit(pts, ref, nbr, ks, fixed, w, prep.period, mode, shift, plateau)
    if distance == "auto":
        used, rule = "euclidean", "auto: maps (lag 1) and strongly chaotic flows keep euclidean"
        growth = fit["slope"] * prep.period
        if flow and growth < WEAK_CHAOS:
            used = "transverse"
            rule = (
                f"auto: euclidean exponent × mean period = {growth:.3g} nats < {WEAK_CHAOS}, "
                "so the neutral along-flow separation dominates; refitted transverse"
            )
            mode, nbr_rule = _k.TRANSVERSE, _TRANSVERSE_RULE
            fit = _fit(pts, ref, nbr, ks, fixed, w, prep.period, mode, shift, plateau)
    slope = fit["slope"]
    mle = slope / prep.dt
    below, above = (fit["half"] + f + fit["nbr_half"] for f in fit["fit_half"])
    ci, sys_half, sys_note = with_systematic(
        mle, below / prep.dt, above / prep.dt, method="rosenstein", flow=flow
    )
    ci_method = (
        f"Student-t 95 % interval over {fit['n_batches']} contiguous batches of per-pair "
        f"slopes ({fit['n_valid']} pairs) in the fit range, widened by the fit-range "
        "sensitivity (slope change when either end moves by a fifth of the window)"
    )
    if mode == _k.SAMPLE_ORBIT:
        ci_method += " and by half the sample-vs-orbit neighbour slope difference"
    ci_method += sys_note
    if not fit["found"]:
        # no scaling region: the slope is not an exponent, so claim no precision at all
        ci = (-np.inf, np.inf)
        ci_method = "no straight scaling region found: interval left unbounded"
    ks, curve, a, b = fit["ks"], fit["curve"], fit["a"], fit["b"]
    return LyapunovResult(
        method="rosenstein",
        mle=mle,
        mle_bits_per_sample=slope / _LN2,
        ci=ci,
        ci_method=ci_method,
        **result_fields(prep),
        fit_range=(int(ks[a]), int(ks[b])),
        fit_found=bool(fit["found"]),
        r2=float(fit["r2"]),
        horizon=ks,
        curve=curve,
        n_points=int(ref.size),
        subsampled=bool(ref.size < usable),
        params={
            "max_horizon": int(horizon_max),
            "fit_tolerances": str(TOLERANCES),
            "plateau": fit["plateau"],
            "mean_period": prep.period,
            "max_points": max_points,
            "distance": used,
            "distance_rule": rule,
            "neighbor": _MODE_NAMES[mode],
            "neighbor_rule": nbr_rule,
            "ci_sampling_half_width": fit["half"] / prep.dt,
            "ci_fit_range_half_width": max(fit["fit_half"]) / prep.dt,
            "ci_neighbor_half_width": fit["nbr_half"] / prep.dt,
            "ci_systematic_half_width": sys_half,
        },
    )
