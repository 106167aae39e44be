"""Largest Lyapunov exponent by Kantz's neighbourhood-averaged divergence."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._neighbors import grid_nearest_neighbors, radius_grid
from .._validate import check_choice, check_int
from . import _kantz_kernels as _kk
from ._common import batch_means_ci, references, result_fields, with_systematic
from ._result import LyapunovResult
from ._rosenstein import (
    SPAN_PERIODS,
    WEAK_CHAOS,
    horizon_for,
    plateau_level,
    prepare_curve,
    window_spread,
)
from ._scaling import TOLERANCES, saturation_index, scaling_region

__all__ = ["KantzResult", "lyapunov_kantz"]

_LN2 = float(np.log(2.0))
DEFAULT_MAX_POINTS = 2000
DEFAULT_MAX_NEIGHBORS = 64
_N_EPSILON = 5
_EPSILON_RATIO = float(np.sqrt(2.0))
_NN_FACTOR = 2.0  # smallest radius / median nearest-neighbour distance
_NOISE_FACTOR = 4.0  # smallest radius / noise standard deviation
_NOISE_TRUSTED = 0.05  # noise estimates above this fraction of the std are not resolved
_MAX_CURVE_POINTS = 200
_PLATEAU_PAIRS = 4000
#: least reference points per call of the compiled kernel: each call is a fraction of a
#: second on 10^6 samples, and between calls Python runs, so Ctrl-C stops the estimate
#: promptly (the references are independent: the result does not depend on it)
REF_CHUNK = 256
#: calls per pass at most, above REF_CHUNK references each: a call's dispatch costs
#: ≈ 0.07 ms, a twelfth of the estimate on 10^4 samples when every call held 256
REF_CALLS = 8
_NO_SERIES = np.empty(0)
#: most per-reference values of the smallest radius the neighbourhood pass keeps for the
#: interval (64 MB; more are computed again by a pass of their own)
KEEP_VALUES = 2**23


@dataclass(frozen=True, kw_only=True)
class KantzResult(LyapunovResult):
    """:class:`LyapunovResult` of :func:`lyapunov_kantz` with the curve of every radius.

    Attributes
    ----------
    epsilon
        Neighbourhood radii (units of ``x``, in the norm ``params["norm"]``: maximum by
        default), ascending.
    curves
        ``S(k, ε)``: mean over reference points of ln of the mean distance (of the RMS
        distance with ``definition="rms"``) to their ε-neighbours after ``horizon`` samples,
        shape ``(epsilon.size, horizon.size)`` (distances in units of the standard
        deviation of ``x``). ``curve`` is the row of the chosen radius.
    slopes
        Exponent fitted to each row (per unit of ``dt``); NaN where no scaling region.
    epsilon_index
        Row of the chosen radius (the smallest one with a scaling region).
    noise_level
        Estimated standard deviation of additive white noise (units of ``x``); NaN when the
        sampling is too coarse to tell noise from dynamics (maps).
    """

    epsilon: np.ndarray
    curves: np.ndarray
    slopes: np.ndarray
    epsilon_index: int
    noise_level: float

    def to_dataset(self) -> xr.Dataset:
        """As :meth:`LyapunovResult.to_dataset`, plus ``log_divergence_by_epsilon``."""
        ds = super().to_dataset()
        norm = self.params.get("norm", "maximum")
        mean = "RMS" if self.params.get("average") == "rms" else "mean"
        ds = ds.assign_coords(
            epsilon=(
                "epsilon",
                self.epsilon,
                {"units": "1", "long_name": f"neighbourhood radius ({norm} norm, units of x)"},
            )
        )
        ds["log_divergence_by_epsilon"] = (
            ("epsilon", "horizon"),
            self.curves,
            {"units": "1", "long_name": f"mean ln of the {mean} neighbourhood distance S(k, eps)"},
        )
        ds["mle_by_epsilon"] = (
            "epsilon",
            self.slopes,
            {"units": "1", "long_name": "exponent fitted per radius (per unit of dt)"},
        )
        ds.attrs["epsilon_chosen"] = float(self.epsilon[self.epsilon_index])
        ds.attrs["noise_level"] = self.noise_level
        return ds


def noise_level(arr: np.ndarray, lag: int) -> float:
    """Standard deviation of additive white noise in a standardised, finely sampled series.

    The fourth difference of white noise has variance 70 σ²; that of a smooth signal sampled
    many times per oscillation is tiny (∝ (ω Δt)⁸), so ``std(Δ⁴x)/√70`` estimates σ. Maps and
    coarsely sampled flows (``lag == 1``) or estimates above 5 % of the standard deviation
    cannot be told from dynamics: NaN.
    """
    if lag < 2 or arr.size < 50:
        return float("nan")
    sigma = float(np.std(np.diff(arr, 4)) / np.sqrt(70.0))
    return sigma if sigma < _NOISE_TRUSTED else float("nan")


def _grid(h: int) -> np.ndarray:
    step = max(1, int(np.ceil(h / _MAX_CURVE_POINTS)))
    ks = np.arange(0, h + 1, step, dtype=np.int64)
    return ks if ks[-1] == h else np.append(ks, h)


def _fit_line(k: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    slope, intercept = np.polyfit(k.astype(np.float64), y, 1)
    resid = y - (slope * k + intercept)
    sst = float(((y - y.mean()) ** 2).sum())
    return float(slope), (1.0 - float((resid**2).sum()) / sst if sst > 0 else 0.0)


def _ref_slopes(logd: np.ndarray, ks: np.ndarray, a: int, b: int) -> np.ndarray:
    """Least-squares slope of each reference point's own curve over ``ks[a:b+1]``."""
    y = logd[:, a : b + 1]
    k = ks[a : b + 1].astype(np.float64)
    kc = k - k.mean()
    # the centred abscissae sum to zero, so the curve's own mean need not be removed; a
    # NaN anywhere in a row (no neighbour at some horizon) makes its slope NaN: dropped.
    # (einsum, not the matrix product: a threaded BLAS call cost 15× more CPU here)
    slopes = np.einsum("ij,j->i", y, kc) / float(kc @ kc)
    return slopes[np.isfinite(slopes)]


def _log_mean_distance(
    pts: np.ndarray, pairs: np.ndarray, transverse: bool, squared: bool = False
) -> float:
    """ln of the mean distance of random pairs (the saturation level of ``S``); with
    ``squared``, ln of their RMS distance."""
    i, j = pairs
    d = pts[j] - pts[i]
    d2 = (d * d).sum(axis=1)
    if transverse:
        v = pts[np.minimum(i + 1, pts.shape[0] - 1)] - pts[np.maximum(i - 1, 0)]
        v2 = (v * v).sum(axis=1)
        dv = (d * v).sum(axis=1)
        d2 = np.maximum(d2 - np.where(v2 > 0, dv * dv / np.where(v2 > 0, v2, 1.0), 0.0), 0.0)
    if squared:
        return 0.5 * float(np.log(d2.mean()))
    return float(np.log(np.sqrt(d2).mean()))


def _fit_all(total, count, used, ks, fixed, plateau, min_span) -> dict:
    """Curve and fit of every radius; the smallest radius with a scaling region is chosen.

    ``total[e, q]`` and ``count[e, q]``: sum and number of the finite per-reference
    values of ``S(k_q, ε_e)``.
    """
    have = (used > 0).sum(axis=0)
    if not have.any():
        raise ValueError(
            "no reference point has a neighbour within the largest epsilon; use larger radii."
        )
    fits: list[dict | None] = []
    for e in range(total.shape[0]):
        if have[e] < 2:
            fits.append(None)
            continue
        cnt = count[e]
        curve = np.where(cnt > 0, total[e] / np.maximum(cnt, 1), np.nan)
        if fixed:
            a = int(np.searchsorted(ks, fixed[0]))
            b = int(np.searchsorted(ks, fixed[1], side="right")) - 1
            found = b - a >= 1
        else:
            a, b, found = scaling_region(ks, curve, plateau=plateau, min_span=min_span)
        if b - a < 1 or not np.isfinite(curve[a : b + 1]).all():
            fits.append(None)
            continue
        slope, r2 = _fit_line(ks[a : b + 1], curve[a : b + 1])
        fits.append({"curve": curve, "a": a, "b": b, "found": found, "slope": slope, "r2": r2})
    valid = [e for e, f in enumerate(fits) if f is not None]
    if not valid:
        raise ValueError("no radius gives a usable divergence curve; use larger radii.")
    good = [e for e in valid if fits[e]["found"]]  # type: ignore[index]
    any_found = bool(good)
    cands = np.array(good if any_found else valid)
    pick = np.array([fits[e]["slope"] for e in cands])
    # the smallest radius is the least nonlinear one; it already lies above the noise
    e_star = int(cands[0])
    return {
        "fits": fits,
        "have": have,
        "any_found": any_found,
        "pick": pick,
        "e_star": e_star,
        "slope": fits[e_star]["slope"],  # type: ignore[index]
    }


def _check_epsilon(epsilon: Any) -> np.ndarray | None:
    """Given radii sorted ascending, or None."""
    if epsilon is None:
        return None
    eps = np.sort(np.atleast_1d(np.asarray(epsilon, dtype=np.float64)))
    if eps.ndim != 1 or not (np.isfinite(eps).all() and (eps > 0).all()):
        raise ValueError(f"epsilon must be positive finite radii; got {epsilon!r}.")
    return eps


def _radii(given, head, ref, w, sigma, scale, ball) -> tuple[np.ndarray, str]:
    """Radii in units of the standard deviation and the rule that chose them."""
    if given is not None:
        return given / scale, "given"
    p = 2.0 if ball else np.inf
    _, d_nn = grid_nearest_neighbors(head, theiler_window=w, query=ref, p=p)
    eps0 = _NN_FACTOR * float(np.median(d_nn))
    rule = f"auto: {_NN_FACTOR:g} × median nearest-neighbour distance"
    if np.isfinite(sigma) and _NOISE_FACTOR * sigma > eps0:
        eps0 = _NOISE_FACTOR * sigma
        rule = f"auto: {_NOISE_FACTOR:g} × noise level"
    eps = eps0 * _EPSILON_RATIO ** np.arange(_N_EPSILON)
    return eps, rule + f", {_N_EPSILON} radii in ratio √2"


class _Search:
    """The ε-neighbourhoods of the reference points, box-assisted, for either distance."""

    def __init__(
        self,
        pts,
        head,
        ref,
        w,
        eps,
        ks,
        max_neighbors,
        *,
        series=None,
        lag: int = 1,
        ball: bool = False,
        squared: bool = False,
    ) -> None:
        """``series``: the scalar series ``pts`` is the delay embedding of at ``lag``
        (``pts[t, c] = series[t + c · lag]``), or None; ``ball``: Euclidean
        neighbourhoods; ``squared``: S is ln of the RMS distance."""
        self.pts, self.ref, self.w, self.eps, self.ks = pts, ref, w, eps, ks
        self.series = _NO_SERIES if series is None else np.ascontiguousarray(series)
        self.lag = int(lag)
        self.max_neighbors, self.ball, self.squared = max_neighbors, ball, squared
        self.cols = np.ascontiguousarray(pts.T)
        self.head = head
        self.grid = radius_grid(head, float(eps[-1]))
        self.grids = {eps.size - 1: self.grid}
        # position of each row in the order of its first coordinate: the neighbours are
        # taken in that order, so the strided subset does not depend on the grid
        rank = np.empty(head.shape[0], dtype=np.int64)
        rank[np.argsort(head[:, 0], kind="stable")] = np.arange(head.shape[0])
        self.rank = rank
        n = head.shape[0]
        self.work = (np.empty(n, dtype=np.int64), np.empty(n), np.empty(n, dtype=np.int64))
        #: horizons ``ks[q0 : q0 + w]`` of the smallest radius kept by the neighbourhood
        #: pass (None: not kept), and per distance the kept rows (see ``first_curves``)
        self.keep: tuple[int, int] | None = None
        self.first: dict[bool, np.ndarray] = {}

    def log_distances(self, transverse: bool, upto: int | None = None, ks=None):
        """The neighbours used per reference and radius, and the sum and count of the
        finite ``S(k, ε)`` per radius and horizon; with ``upto``, also the per-reference
        ``S`` (reference, radius, horizon) of the radii ``0 … upto`` at the horizons
        ``ks``, else None (it would hold references × radii × horizons values)."""
        ref = self.ref
        eps = self.eps if upto is None else self.eps[: upto + 1]
        if eps.size - 1 not in self.grids:
            # cells as wide as the largest radius asked for: a pass over the small radii
            # reads far fewer candidates than on the grid of the largest, unless the grid
            # is too large for a direct cell table and every cell is found by bisection
            # (measured on Hénon 5·10⁴, 2 coordinates: 95 against 177 ms; on Lorenz, 3
            # coordinates, the finer grid had no table and took 125 against 85 ms)
            fine = radius_grid(self.head, float(eps[-1]))
            self.grids[eps.size - 1] = fine if fine[4].size else self.grid
        ks = self.ks if ks is None else ks
        n_e, nk = eps.size, ks.size
        logd = np.empty((ref.size, n_e, nk) if upto is not None else (0, 0, 0))
        used = np.empty((ref.size, n_e), dtype=np.int64)
        total = np.zeros((n_e, nk))
        count = np.zeros((n_e, nk), dtype=np.int64)
        # Σ ln of the mean distances as exponents and mantissa products (see the kernel)
        expo = np.zeros((n_e, nk), dtype=np.int64)
        prod = np.ones((n_e, nk))
        run = np.zeros(1, dtype=np.int64)
        members, spts, keys, starts, slot, grid = self.grids[eps.size - 1]
        # the neighbourhood pass keeps the smallest radius's per-reference S (rows of the
        # reference points that have a neighbour within it; pages never written cost no
        # memory): the interval's pass is then not needed when that radius is chosen
        q0, width = self.keep if upto is None and self.keep is not None else (0, 0)
        first = np.empty((ref.size if width else 0, width))
        n_first = np.zeros(1, dtype=np.int64)
        chunk = max(REF_CHUNK, -(-ref.size // REF_CALLS))
        for r0 in range(0, ref.size, chunk):
            part = slice(r0, min(r0 + chunk, ref.size))
            used[part] = _kk.kantz_log_distances(
                self.pts,
                self.cols,
                spts,
                members,
                self.rank,
                slot,
                keys,
                starts,
                grid,
                ref[part],
                self.w,
                eps,
                ks,
                self.max_neighbors,
                transverse,
                self.series,
                self.lag,
                self.ball,
                self.squared,
                logd[part] if upto is not None else logd,
                total,
                count,
                *self.work,
                expo,
                prod,
                run,
                first,
                n_first,
                q0,
            )
        if width:
            self.first[transverse] = first[: n_first[0]]
        total += np.log(prod) + expo * np.log(2.0)
        if self.squared:  # the sums hold ln of mean squares: S is half of it
            total *= 0.5
        return (logd if upto is not None else None), used, total, count

    def first_curves(self, transverse: bool, a: int, b: int) -> np.ndarray | None:
        """The kept per-reference ``S`` of the smallest radius at ``ks[a : b + 1]`` (rows:
        the reference points with a neighbour within it, in order), or None when the
        neighbourhood pass did not keep those horizons."""
        if self.keep is None or transverse not in self.first:
            return None
        q0, width = self.keep
        if a < q0 or b >= q0 + width:
            return None
        return np.ascontiguousarray(self.first[transverse][:, a - q0 : b - q0 + 1])


def _kept_horizons(ks: np.ndarray, fixed, n_ref: int) -> tuple[int, int] | None:
    """Horizons ``ks[q0 : q0 + w]`` as ``(q0, w)`` that the neighbourhood pass keeps for
    the interval: the fit range when it is given, else every horizon; None when that is
    more than ``KEEP_VALUES`` values."""
    if fixed:
        a = int(np.searchsorted(ks, fixed[0]))
        b = int(np.searchsorted(ks, fixed[1], side="right")) - 1
        q0, width = a, b - a + 1
    else:
        q0, width = 0, ks.size
    return (q0, width) if 0 < width and n_ref * width <= KEEP_VALUES else None


def _with_distance(run, distance: str, prep) -> tuple[dict, str, str]:
    """Fit with the given distance, or (``"auto"``) Euclidean, refitted transverse for a
    weakly chaotic flow; returns the fit, the distance used and the rule."""
    if distance != "auto":
        return run(distance == "transverse"), distance, "given"
    res = run(False)
    growth = res["slope"] * prep.period
    if prep.lag > 1 and growth < WEAK_CHAOS:
        return (
            run(True),
            "transverse",
            f"auto: euclidean exponent × mean period = {growth:.3g} nats < {WEAK_CHAOS}, "
            "so the neutral along-flow separation dominates; refitted transverse",
        )
    return res, "euclidean", "auto: maps and strongly chaotic flows"


def _interval(prep, res, search, ks, fixed, min_span) -> tuple[tuple[float, float], str, dict]:
    """95 % interval of the exponent, its wording, and its half-widths (per unit of dt)."""
    fit, e_star, pick = res["fits"][res["e_star"]], res["e_star"], res["pick"]
    a, b, slope = fit["a"], fit["b"], fit["slope"]
    # each reference point's own curve of the chosen radius over the fit range: kept by
    # the neighbourhood pass for the smallest radius, else computed again rather than
    # kept for every radius and horizon (a cheap pass: the small radii have the fewest
    # neighbours). The kept rows leave out the reference points without a neighbour,
    # whose slopes are NaN and dropped either way.
    kept = search.first_curves(res["transverse"], a, b) if e_star == 0 else None
    if kept is None:
        kept = search.log_distances(res["transverse"], e_star, ks[a : b + 1])[0][:, e_star, :]
    per_ref = _ref_slopes(kept, ks[a : b + 1], 0, b - a)
    _, half, n_batches = batch_means_ci(per_ref)
    fit_below = fit_above = 0.0
    if not fixed and fit["found"]:
        end = max(b, saturation_index(fit["curve"], res["plateau"]))
        fit_below, fit_above = window_spread(ks, fit["curve"], a, b, end, slope, min_span)
    eps_half = 0.5 * float(np.ptp(pick)) if pick.size > 1 else 0.0
    ci, sys_half, sys_note = with_systematic(
        slope / prep.dt,
        (half + fit_below + eps_half) / prep.dt,
        (half + fit_above + eps_half) / prep.dt,
        method="kantz",
        flow=prep.lag > 1,
    )
    ci_method = (
        f"Student-t 95 % interval over {n_batches} contiguous batches of per-reference "
        f"slopes ({per_ref.size} reference points) in the fit range, widened by the fit-range "
        f"sensitivity and by half the spread of the slopes over the radii{sys_note}"
    )
    if not res["any_found"]:
        ci = (-np.inf, np.inf)
        ci_method = "no straight scaling region found for any radius: interval left unbounded"
    halves = {
        "ci_sampling_half_width": half / prep.dt,
        "ci_fit_range_half_width": max(fit_below, fit_above) / prep.dt,
        "ci_epsilon_half_width": eps_half / prep.dt,
        "ci_systematic_half_width": sys_half,
    }
    return ci, ci_method, halves


def _result(prep, res, search, ks, fixed, min_span, sigma, subsampled, params) -> KantzResult:
    fits, e_star, used = res["fits"], res["e_star"], res["used"]
    fit = fits[e_star]
    ci, ci_method, halves = _interval(prep, res, search, ks, fixed, min_span)
    slopes = np.array([f["slope"] if f and f["found"] else np.nan for f in fits])
    curves = np.vstack([f["curve"] if f is not None else np.full(ks.size, np.nan) for f in fits])
    taken = used[:, e_star]
    return KantzResult(
        method="kantz",
        mle=fit["slope"] / prep.dt,
        mle_bits_per_sample=fit["slope"] / _LN2,
        ci=ci,
        ci_method=ci_method,
        **result_fields(prep),
        fit_range=(int(ks[fit["a"]]), int(ks[fit["b"]])),
        fit_found=bool(fit["found"]),
        r2=float(fit["r2"]),
        horizon=ks,
        curve=fit["curve"],
        n_points=int(res["have"][e_star]),
        subsampled=bool(subsampled),
        params=params | {"mean_neighbors": float(taken[taken > 0].mean())} | halves,
        epsilon=search.eps * prep.scale,
        curves=curves,
        slopes=slopes / prep.dt,
        epsilon_index=e_star,
        noise_level=sigma * prep.scale,
    )


def lyapunov_kantz(
    x: Any,
    *,
    embedding_dim: int | None = None,
    lag: int | None = None,
    dt: float = 1.0,
    theiler_window: int | None = None,
    epsilon: Any = None,
    max_horizon: int | None = None,
    fit_range: Literal["auto"] | tuple[int, int] = "auto",
    max_points: int = DEFAULT_MAX_POINTS,
    max_neighbors: int = DEFAULT_MAX_NEIGHBORS,
    distance: Literal["auto", "euclidean", "transverse"] = "auto",
    definition: Literal["mean", "rms"] = "mean",
) -> KantzResult:
    r"""Largest Lyapunov exponent by Kantz's method (averaged over ε-neighbourhoods).

    For each reference point :math:`\mathbf y_i` of the delay embedding, every point
    :math:`\mathbf y_j` within radius ε (maximum norm unless ``definition="rms"``,
    :math:`|i-j| >` ``theiler_window``)
    is a neighbour, and

    .. math:: S(k, \varepsilon) = \Big\langle \ln \frac{1}{|U_i|} \sum_{j \in U_i}
              \|\mathbf y_{i+k} - \mathbf y_{j+k}\| \Big\rangle_i
              \approx S(0, \varepsilon) + \lambda_1 \, k \, \Delta t

    in the scaling region. Averaging the distance over the whole neighbourhood *before* the
    logarithm makes the curve robust to noise: a neighbour that is close only by chance
    (noise) weighs no more than its distance. For radii above the noise level the curves of
    different ε are parallel in the scaling region; the exponent is their common slope.

    Defaults (only ``dt`` given): lag, dimension, Theiler window and horizon as in
    :func:`~chaoskit.lyapunov_rosenstein`;

    * ``epsilon``: five radii in ratio √2 from ``ε₀ = max(2 d_nn, 4 σ)``, with ``d_nn`` the
      median nearest-neighbour distance (in the neighbourhoods' norm) of the reference
      points and σ the noise level (see below), so that most reference points have
      neighbours and every radius lies above the noise;
    * noise level σ: ``std(Δ⁴x)/√70`` for finely sampled flows (``lag > 1``; the fourth
      difference of white noise has variance 70 σ², that of the smooth signal is
      negligible); not resolved (NaN) for maps or when above 5 % of the standard deviation;
    * fit range: for each radius the automatic scaling region, by the rule Rosenstein
      uses (:func:`chaoskit.lyapunov_rosenstein`); the exponent is the
      slope of the smallest radius with a scaling region (``epsilon_index``): larger
      neighbourhoods bend the curve upwards (Lorenz x, N = 10⁵: +0 % at ε₀, +20 % at 4 ε₀);
    * ``distance="auto"``: Euclidean, except for flows (``lag > 1``) whose Euclidean
      exponent × mean period is below 0.7 nats, which are refitted with the transverse
      distance (the rule of :func:`~chaoskit.lyapunov_rosenstein`; Rössler x sampled at 0.1:
      −23 % Euclidean, −3 % transverse);
    * ``max_points`` = 2,000 evenly spaced reference points, each averaged over at most
      ``max_neighbors`` = 64 neighbours (an evenly strided subset when more qualify).

    The 95 % interval ``ci`` is the sum of three half-widths (in ``params``): sampling
    (per-reference slopes over the fit range, Student-t over 20 contiguous batches),
    fit range (slope change when either end of the window moves by a fifth of its length)
    and radius (half the range of the slopes over the radii with a scaling region); their
    sum is combined in quadrature with the method's systematic error measured against
    tangent-space exponents on a public corpus (``benchmarks/estimator_corpus.py``): 5 % of
    the estimate for maps, 90 % for flows (``params["ci_systematic_half_width"]``).

    Neighbours are found box-assisted (TISEAN's search): on a grid of cells as wide as the
    largest radius over up to three delay coordinates, only the cells around a reference
    point are read; memory stays O(N), time is O(``max_points`` × points in 3^g cells +
    neighbours × horizons). When more than ``max_neighbors`` qualify, the subset is taken
    in the order of the first coordinate, so it does not depend on the grid.

    Parameters
    ----------
    x
        Scalar series (≥ 100 samples), finite and not constant.
    embedding_dim, lag
        Embedding dimension and delay (samples); estimated when ``None``.
    dt
        Sampling interval (> 0). ``mle`` is per unit of ``dt``.
    theiler_window
        Exclude neighbours with ``|i − j| <= theiler_window`` (samples).
    epsilon
        Neighbourhood radii in units of ``x`` (positive; sorted ascending); automatic when
        ``None``.
    max_horizon
        Largest horizon k (samples); automatic when ``None``.
    fit_range
        ``"auto"`` or ``(first, last)`` horizon in samples (used for every radius).
    max_points
        Largest number of reference points (≥ 10).
    max_neighbors
        Largest number of neighbours averaged per reference point and radius (≥ 1).
    distance
        Distance of the separations after ``k`` samples: ``"euclidean"``, ``"transverse"``
        (the part perpendicular to the local flow direction) or ``"auto"`` (above).
    definition
        ``"mean"`` (the default): neighbourhoods are cubes of half-width ε (maximum
        norm) and S is ln of the mean distance, the definition above. ``"rms"``:
        neighbourhoods are Euclidean balls of radius ε and S is ln of the RMS distance,
        the quantity of TISEAN's ``lyap_k`` (except that neighbours at distance exactly ε
        are excluded and zero distances are kept in the mean); it skips a square root per
        neighbour and horizon. The automatic radii follow the norm (nearest-neighbour
        distances in the same norm). The two differ by the spread of the distances within
        a neighbourhood, nearly constant in the scaling region, so the slopes agree within
        a few per cent (0.5–2.5 % on Hénon and Lorenz; docs/performance.md).

    Returns
    -------
    KantzResult
        A :class:`LyapunovResult` (``curve`` is ``S(k, ε)`` of the chosen radius) with
        ``epsilon``, ``curves``, ``slopes``, ``epsilon_index`` and ``noise_level``.

    Raises
    ------
    ValueError
        For invalid input or options (message names the parameter), or when no radius has
        any neighbour.

    References
    ----------
    H. Kantz, "A robust method to estimate the maximal Lyapunov exponent of a time series",
    Phys. Lett. A 185 (1994) 77–87. R. Hegger, H. Kantz, T. Schreiber, "Practical
    implementation of nonlinear time series methods: The TISEAN package", Chaos 9 (1999)
    413–435.

    Examples
    --------
    >>> from chaoskit import lyapunov_kantz, systems
    >>> res = lyapunov_kantz(systems.henon(10_000)[:, 0])
    >>> bool(abs(res.mle - 0.419) < 0.02)
    True
    """
    max_points = check_int(max_points, name="max_points", minimum=10)
    max_neighbors = check_int(max_neighbors, name="max_neighbors", minimum=1)
    check_choice(distance, name="distance", choices=("auto", "euclidean", "transverse"))
    check_choice(definition, name="definition", choices=("mean", "rms"))
    norm, average = ("euclidean", "rms") if definition == "rms" else ("maximum", "distance")
    eps_given = _check_epsilon(epsilon)
    prep, fixed, max_horizon, min_future = prepare_curve(
        x, embedding_dim, lag, dt, theiler_window, max_horizon, fit_range
    )
    pts, w = prep.pts, prep.theiler_window
    rng = np.random.default_rng(12345)
    plateau_log = plateau_level(pts, w, rng, False) if max_horizon is None else np.nan
    horizon_max = horizon_for(prep, plateau_log, min_future, max_horizon, fixed)
    usable = pts.shape[0] - horizon_max
    ks = _grid(horizon_max)
    if fixed:
        ks = np.union1d(ks, np.arange(fixed[0], fixed[1] + 1))
    ref = references(usable, max_points)
    head = np.ascontiguousarray(pts[:usable])
    sigma = noise_level(prep.arr, prep.lag)
    eps, eps_rule = _radii(eps_given, head, ref, w, sigma, prep.scale, norm == "euclidean")
    ball, squared = norm == "euclidean", average == "rms"
    search = _Search(
        pts,
        head,
        ref,
        w,
        eps,
        ks,
        max_neighbors,
        series=prep.arr,
        lag=prep.lag,
        ball=ball,
        squared=squared,
    )
    search.keep = _kept_horizons(ks, fixed, ref.size)
    pairs = rng.integers(0, pts.shape[0], (2, _PLATEAU_PAIRS))
    pairs = pairs[:, np.abs(pairs[0] - pairs[1]) > w]
    min_span = max(3.0, SPAN_PERIODS * prep.period)

    def run(transverse: bool) -> dict:
        _, used, total, count = search.log_distances(transverse)
        plateau = _log_mean_distance(pts, pairs, transverse, squared)
        fit = _fit_all(total, count, used, ks, fixed, plateau, min_span)
        return {"transverse": transverse, "used": used, "plateau": plateau} | fit

    res, used_distance, distance_rule = _with_distance(run, distance, prep)
    params = {
        "max_horizon": int(horizon_max),
        "fit_tolerances": str(TOLERANCES),
        "plateau": res["plateau"],
        "mean_period": prep.period,
        "max_points": max_points,
        "max_neighbors": max_neighbors,
        "epsilon_rule": eps_rule,
        "distance": used_distance,
        "distance_rule": distance_rule,
        "definition": definition,
        "norm": norm,
        "average": average,
    }
    return _result(prep, res, search, ks, fixed, min_span, sigma, ref.size < usable, params)
