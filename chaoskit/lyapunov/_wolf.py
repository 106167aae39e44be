"""Largest Lyapunov exponent by Wolf's fixed-evolution algorithm with replacement."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from .._neighbors import nearest_neighbors
from .._progress import stage
from .._validate import check_choice, check_int, check_positive
from . import _kernels as _k
from ._common import batch_means_ci, prepare, references, with_systematic
from ._result import LyapunovResult
from ._rosenstein import WEAK_CHAOS

__all__ = ["lyapunov_wolf"]

_LN2 = float(np.log(2.0))
_SCALE_PAIRS = 20_000
_SCALE_POINTS = 10_000
_WIDEN = 5
_MAX_ANGLE = np.pi / 4
_WEAK_MAX_ANGLE = 0.2  # rad, for flows with less than WEAK_CHAOS nats per mean period
_POOL_POINTS = 50_000
_POOL_POINTS_PER_EVOLVE = 20_000
_CELL_FACTOR = 1.0 / 3.0  # grid cell side / band upper bound (fastest on the maps)
# Share of the evolution intervals that may end above the scale band with no replacement
# before the estimate bounds the exponent from below only (docs/estimators.md, "Wolf's
# saturated runs"): 0.3 brings the interval's coverage of the corpus's tangent exponents
# above 90 % at both lengths; covered series run at a median share of 0.07.
SATURATED_SHARE = 0.3


def _scale_band(pts: np.ndarray, w: int, rng: np.random.Generator) -> tuple[float, float, float]:
    """Paper rule: dlt = 0.02 (d_mean − d_min), band [d_min + dlt/2, d_min + 2 dlt].

    d_mean from random pairs, d_min from nearest-neighbour distances of up to 10,000 points.
    Returns (lower, upper, dlt).
    """
    n = pts.shape[0]
    i = rng.integers(0, n, _SCALE_PAIRS)
    j = rng.integers(0, n, _SCALE_PAIRS)
    d_mean = float(np.linalg.norm(pts[i] - pts[j], axis=1).mean())
    _, dist = nearest_neighbors(pts, theiler_window=w, query=references(n, _SCALE_POINTS))
    d_min = float(dist.min())
    dlt = 0.02 * (d_mean - d_min)
    return d_min + 0.5 * dlt, d_min + 2.0 * dlt, dlt


def _pool_grid(pts: np.ndarray, cell: float, max_points: int) -> tuple:
    """Replacement candidates bucketed on a uniform grid (see ``_kernels.wolf_loop``).

    Long series use an evenly strided subset of at most ``max_points`` points: the scale
    band is a fixed fraction of the attractor size, so the band holds plenty of candidates
    anyway and a search stays cheap instead of growing with N. The grid spans all points (so every
    fiducial point falls inside it) over the first ``min(m, 3)`` coordinates, with cells of
    side ``cell`` (enlarged if more than 2^20 cells per axis would be needed).

    Returns (grid_lo, cell, ncell, stride, keys, starts, members, pool): ``members`` are
    the candidates' indices in grid order and ``pool`` their coordinates, contiguous in that
    order so that a cell is scanned without random memory access.
    """
    n, m = pts.shape
    step = max(1, int(np.ceil(n / max_points)))
    index = np.arange(0, n, step, dtype=np.int64)
    g = min(m, 3)
    lo = pts[:, :g].min(axis=0)
    span = pts[:, :g].max(axis=0) - lo
    cell = max(float(cell), float(span.max()) / 2**20, 1e-300)
    ncell = np.floor(span / cell).astype(np.int64) + 1
    stride = np.concatenate(([1], np.cumprod(ncell)[:-1])).astype(np.int64)
    coords = np.floor((pts[index, :g] - lo) / cell).astype(np.int64)
    ids = np.minimum(coords, ncell - 1) @ stride
    order = np.argsort(ids, kind="stable")
    keys, starts = np.unique(ids[order], return_index=True)
    starts = np.append(starts, index.size).astype(np.int64)
    return (
        np.ascontiguousarray(lo, dtype=np.float64),
        cell,
        ncell,
        stride,
        keys.astype(np.int64),
        starts,
        index[order],
        np.ascontiguousarray(pts[index[order]]),
    )


def lyapunov_wolf(
    x: Any,
    *,
    embedding_dim: int | None = None,
    lag: int | None = None,
    dt: float = 1.0,
    theiler_window: int | None = None,
    scale: tuple[float, float] | None = None,
    max_angle: float | None = None,
    evolve: int | None = None,
    replace: Literal["out_of_band", "always"] = "out_of_band",
) -> LyapunovResult:
    r"""Largest Lyapunov exponent by Wolf's algorithm (fixed evolution with replacement).

    A fiducial trajectory :math:`\mathbf y_i` and a neighbour :math:`\mathbf y_j` (with
    :math:`|i-j| >` ``theiler_window``) are evolved for ``evolve`` samples and the stretching
    :math:`\ln(L'/L)` of their separation is summed sample by sample. At the end of each
    evolution interval the neighbour is replaced when its separation has left the scale
    band (``replace="out_of_band"``, default; an in-band neighbour is kept, which adds no
    new misalignment) or always (``replace="always"``; with ``evolve=1`` this is the widely
    used MATLAB variant described in the seed paper). The replacement is the point in the
    band whose separation vector makes the smallest angle with the old one, if that angle is
    below ``max_angle``; otherwise the upper bound is widened by ``dlt`` up to five times;
    if still none qualifies the evolved neighbour is kept (Wolf 1985), unless it ran off the
    data or coincides with the fiducial point, when the nearest point beyond the lower bound
    is taken. Then

    .. math:: \lambda_1 = \frac{1}{T\,\Delta t} \sum_{\text{steps}} \ln \frac{L'}{L}

    over all ``T`` evolution steps. ``curve`` is the running estimate (nats per sample).

    Defaults (only ``dt`` given): lag, dimension and Theiler window as in
    :func:`~chaoskit.lyapunov_rosenstein`; ``evolve`` = 1 sample when ``lag == 1`` (maps and
    coarsely sampled flows), else one mean period; scale band from the paper rule
    ``dlt = 0.02 (d_mean − d_min)``, band ``[d_min + dlt/2, d_min + 2 dlt]``;
    ``max_angle`` = 45°, except for flows whose 45° estimate per mean period is below 0.7
    nats, which are rerun with 0.2 rad (a misaligned replacement puts part of the separation
    in the neutral flow direction). Long series draw replacement candidates from an evenly
    strided subset (at most 20,000 × ``evolve`` and 50,000 points); the compiled loop only
    prefilters candidates on a grid, so the chosen neighbour does not depend on it. The
    rules and their measured bias (Lorenz, Rössler) are in ``docs/estimators.md``.

    The 95 % interval ``ci`` is a Student-t interval over 20 contiguous batches of the
    per-step stretching (batch means absorb the correlation along the trajectory),
    combined in quadrature with the method's systematic error measured against
    tangent-space exponents on a public corpus (``benchmarks/estimator_corpus.py``): 5 % of
    the estimate for maps, 75 % for flows (``params["ci_systematic_half_width"]``). When
    more than 30 % of the evolution intervals end with the separation above the scale band
    and no replacement (``params["saturated_fraction"]``), the separations ran near the
    attractor's size, where they stop growing: the estimate is then biased low and the
    interval's upper end is +inf (it bounds the exponent from below only).

    Parameters
    ----------
    x
        Scalar series (≥ 100 samples), finite and not constant.
    embedding_dim, lag
        Embedding dimension and delay (samples); estimated when ``None``.
    dt
        Sampling interval (> 0); ``mle`` is per unit of ``dt``.
    theiler_window
        Exclude replacement candidates with ``|i − j| <= theiler_window`` (samples).
    scale
        ``(lower, upper)`` separation band in the units of ``x``; paper rule when ``None``.
    max_angle
        Largest accepted angle (rad) between old and new separation vectors, in (0, π];
        automatic when ``None`` (see above; the rule is in ``params["max_angle_rule"]``).
    evolve
        Evolution interval in samples between replacement checks (default: 1 if
        ``lag == 1``, else one mean period).
    replace
        ``"out_of_band"`` (default: replace only when the separation has left the band) or
        ``"always"``.

    Returns
    -------
    LyapunovResult
        ``fit_range`` is the averaging window (first and last evolution index), ``r2`` is
        NaN, ``n_points`` the number of replacements, ``params`` holds the band, the angle
        and the fraction of replacements that met the angle condition.

    References
    ----------
    A. Wolf, J. B. Swift, H. L. Swinney, J. A. Vastano, "Determining Lyapunov exponents from a
    time series", Physica D 16 (1985) 285–317.

    Examples
    --------
    >>> from chaoskit import lyapunov_wolf, systems
    >>> res = lyapunov_wolf(systems.logistic(10_000))
    >>> bool(abs(res.mle - 0.6931) < 0.02)
    True
    """
    stage("wolf")
    check_choice(replace, name="replace", choices=("out_of_band", "always"))
    if evolve is not None:
        evolve = check_int(evolve, name="evolve", minimum=1)
    if max_angle is not None:
        max_angle = check_positive(max_angle, name="max_angle")
        if max_angle > np.pi:
            raise ValueError(f"max_angle must be in (0, π] rad; got {max_angle!r}.")
    prep = prepare(
        x, embedding_dim=embedding_dim, lag=lag, dt=dt, theiler_window=theiler_window, min_future=1
    )
    pts, w = prep.pts, prep.theiler_window
    n = pts.shape[0]
    rng = np.random.default_rng(12345)
    if scale is None:
        lower, upper, dlt = _scale_band(pts, w, rng)
    else:
        try:
            lower, upper = (float(v) for v in scale)
        except (TypeError, ValueError):
            raise ValueError(f"scale must be a pair (lower, upper); got {scale!r}.") from None
        if not (np.isfinite(lower) and np.isfinite(upper) and 0.0 <= lower < upper):
            raise ValueError(f"scale must satisfy 0 <= lower < upper (finite); got {scale!r}.")
        lower, upper = lower / prep.scale, upper / prep.scale  # to standardised units
        dlt = 0.5 * (upper - lower)
    if evolve is None:
        evolve = 1 if prep.lag == 1 else int(np.ceil(prep.period))
    # a search costs ∝ candidates in the band ∝ pool size and runs about once per
    # ``evolve`` samples: maps (evolve = 1) get the smaller pool, flows the larger one
    pool_points = min(_POOL_POINTS, _POOL_POINTS_PER_EVOLVE * evolve)
    grid = _pool_grid(pts, _CELL_FACTOR * upper, pool_points)

    def run(angle: float) -> tuple:
        inc = np.full(n - 1, np.nan)
        always = replace == "always"
        cos_max = float(np.cos(angle))
        counts = _k.wolf_loop(pts, w, lower, upper, dlt, _WIDEN, cos_max, evolve, always, grid, inc)
        return inc[~np.isnan(inc)], *counts

    if max_angle is None:
        max_angle, angle_rule = _MAX_ANGLE, "auto: 45°"
        steps, replacements, angle_ok, kept, kept_above = run(max_angle)
        growth = float(steps.mean()) * prep.period if steps.size else np.inf
        if prep.lag > 1 and growth < WEAK_CHAOS:
            # weak chaos per orbit: a replacement's misalignment (its neutral along-flow
            # part never grows) costs a large share of the little growth per interval
            max_angle = _WEAK_MAX_ANGLE
            angle_rule = (
                f"auto: exponent × mean period = {growth:.3g} nats < {WEAK_CHAOS} at 45°, "
                f"rerun with {_WEAK_MAX_ANGLE} rad"
            )
            steps, replacements, angle_ok, kept, kept_above = run(max_angle)
    else:
        angle_rule = "given"
        steps, replacements, angle_ok, kept, kept_above = run(max_angle)
    if steps.size == 0:
        raise ValueError("no evolution step could be made; the series is too short.")
    running = np.cumsum(steps) / np.arange(1, steps.size + 1)
    rate = float(steps.mean())
    _, half, n_batches = batch_means_ci(steps)
    ci, sys_half, sys_note = with_systematic(
        rate / prep.dt, half / prep.dt, half / prep.dt, method="wolf", flow=prep.lag > 1
    )
    # a kept neighbour above the band grows from near the attractor's size, where
    # separations stop growing: with many such intervals the mean stretching is low
    intervals = max(1, -(-steps.size // evolve))
    saturated = kept_above / intervals
    if saturated > SATURATED_SHARE:
        ci = (ci[0], float("inf"))
        sys_note += (
            f"; upper end +inf: {saturated:.0%} of the evolution intervals ended above the "
            f"scale band with no replacement (more than {SATURATED_SHARE:.0%}), so the "
            f"separations ran near saturation and the estimate bounds the exponent from below"
        )
    return LyapunovResult(
        method="wolf",
        mle=rate / prep.dt,
        mle_bits_per_sample=rate / _LN2,
        ci=ci,
        ci_method=(
            f"Student-t 95 % interval over {n_batches} contiguous batches of the per-step "
            f"stretching ({steps.size} steps){sys_note}"
        ),
        dt=prep.dt,
        embedding_dim=prep.embedding_dim,
        lag=prep.lag,
        theiler_window=w,
        lag_rule=prep.lag_rule,
        dim_rule=prep.dim_rule,
        fit_range=(0, int(steps.size)),
        fit_found=True,
        r2=float("nan"),
        horizon=np.arange(1, steps.size + 1),
        curve=running,
        n_points=replacements,
        n_samples=int(prep.arr.size),
        subsampled=False,
        params={
            "scale_lower": lower * prep.scale,
            "scale_upper": upper * prep.scale,
            "scale_step": dlt * prep.scale,
            "max_angle": max_angle,
            "max_angle_rule": angle_rule,
            "replace": replace,
            "evolve": evolve,
            "angle_ok_fraction": angle_ok / replacements if replacements else 1.0,
            "kept_without_replacement": kept,
            "saturated_fraction": saturated,
            "ci_sampling_half_width": half / prep.dt,
            "ci_systematic_half_width": sys_half,
        },
    )
