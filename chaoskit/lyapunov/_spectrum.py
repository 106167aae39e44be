"""Lyapunov spectrum from a scalar series: local linear maps and QR (Sano & Sawada 1985;
Eckmann, Kamphorst, Ruelle & Ciliberto 1986), with a check for spurious exponents."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import xarray as xr
from scipy.spatial import cKDTree

from .._neighbors import default_theiler_window
from .._tables import check_index_interval
from .._validate import as_series, check_choice, check_int, check_positive
from ..embedding import embed, lag_or_estimate, standardize
from . import _spectrum_kernels as _k

__all__ = ["LyapunovSpectrumResult", "lyapunov_spectrum"]

_CHUNK_ENTRIES = 4_000_000
SPURIOUS_TOL = 0.075  # no counterpart within 7.5 % of max(|λ_k|, λ_1): spurious
SpuriousCheck = Literal["embedding", "reversal", "none"]
_CHECKS: tuple[str, ...] = ("embedding", "reversal", "none")


@dataclass(frozen=True, kw_only=True)
class LyapunovSpectrumResult:
    """Lyapunov exponents from the local linear maps of an embedded series.

    Attributes
    ----------
    exponents
        λ_1 ≥ … ≥ λ_m, natural log per unit of ``dt`` (per second when ``dt`` is in seconds,
        per iteration for maps with ``dt = 1``).
    spurious
        For each exponent, whether it lacks a counterpart in ``check_exponents`` within
        7.5 % of ``max(|λ_k|, λ_1)``. All ``False`` when ``check`` is ``"none"``.
    check
        ``"embedding"``: the counterparts are the spectrum at ``embedding_dim + 1`` (true
        exponents persist, spurious ones move); ``"reversal"``: the negated spectrum of the
        time-reversed series (true exponents flip sign, Parlitz 1992); ``"none"``.
    check_exponents
        The spectrum the exponents were checked against (negated for ``"reversal"``;
        empty for ``"none"``).
    sum_exponents
        λ_1 + … + λ_m (the mean log contraction of phase-space volume per unit time).
    kaplan_yorke_dimension
        ``D_KY = j + (λ_1 + … + λ_j) / |λ_{j+1}|`` with j the largest index with a
        non-negative partial sum.
    running
        Running estimate of every exponent against the reference index (convergence).
    dt, embedding_dim, lag, step, n_neighbors, theiler_window
        Sampling interval, embedding, evolution time (samples), neighbours per map and
        Theiler window (samples) used.
    lag_rule
        ``"given"`` or how the delay was estimated.
    n_references, n_samples
        Maps evaluated and the length of the input series.
    """

    exponents: np.ndarray
    spurious: np.ndarray
    check: str
    check_exponents: np.ndarray
    sum_exponents: float
    kaplan_yorke_dimension: float
    running: np.ndarray
    dt: float
    embedding_dim: int
    lag: int
    step: int
    n_neighbors: int
    theiler_window: int
    lag_rule: str
    n_references: int
    n_samples: int

    def to_dataset(self) -> xr.Dataset:
        """Exponents over ``exponent`` and their running estimates over ``reference``."""
        idx = np.arange(1, self.embedding_dim + 1)
        return xr.Dataset(
            {
                "exponent_value": (
                    "exponent",
                    self.exponents,
                    {"units": "per unit of dt", "long_name": "Lyapunov exponent (natural log)"},
                ),
                "spurious": (
                    "exponent",
                    self.spurious.astype(np.int8),
                    {"units": "1", "long_name": "1 where the check flags the exponent"},
                ),
                "running": (
                    ("reference", "exponent"),
                    self.running,
                    {"units": "per unit of dt", "long_name": "running exponent estimate"},
                ),
            },
            coords={
                "exponent": ("exponent", idx, {"units": "1", "long_name": "exponent index"}),
                "reference": (
                    "reference",
                    np.arange(self.running.shape[0]),
                    {"units": "1", "long_name": "local maps accumulated"},
                ),
            },
            attrs={
                "sum_exponents": self.sum_exponents,
                "check": self.check,
                "check_exponents": self.check_exponents,
                "kaplan_yorke_dimension": self.kaplan_yorke_dimension,
                "dt": self.dt,
                "embedding_dim": self.embedding_dim,
                "lag": self.lag,
                "step": self.step,
                "n_neighbors": self.n_neighbors,
                "theiler_window": self.theiler_window,
                "lag_rule": self.lag_rule,
                "n_references": self.n_references,
                "n_samples": self.n_samples,
            },
        )


def _neighbours(pts: np.ndarray, refs: np.ndarray, k: int, w: int, last: int) -> np.ndarray:
    """``k`` nearest points ``j ≤ last`` of each reference with ``|i − j| > w``."""
    n = pts.shape[0]
    tree = cKDTree(pts[: last + 1], leafsize=16, balanced_tree=False, compact_nodes=False)
    want = min(last + 1, k + 2 * w + 1)
    out = np.empty((refs.size, k), dtype=np.int64)
    chunk = max(1, _CHUNK_ENTRIES // want)
    for start in range(0, refs.size, chunk):
        q = refs[start : start + chunk]
        _, idx = tree.query(pts[q], k=want)
        idx = np.atleast_2d(idx)
        ok = np.abs(idx - q[:, None]) > w
        if np.any(ok.sum(axis=1) < k):
            raise ValueError(
                f"too few admissible neighbours: the series is too short for n_neighbors={k} "
                f"and theiler_window={w}."
            )
        rank = np.cumsum(ok, axis=1)
        sel = ok & (rank <= k)
        out[start : start + q.size] = idx[sel].reshape(q.size, k)
    del n
    return out


def _kaplan_yorke(lam: np.ndarray) -> float:
    partial = np.cumsum(lam)
    if partial[0] < 0:
        return 0.0
    j = int(np.flatnonzero(partial >= 0)[-1])
    if j + 1 >= lam.size:
        return float(lam.size)
    return float(j + 1 + partial[j] / abs(lam[j + 1]))


def _run(arr: np.ndarray, m: int, lag: int, step: int, k: int, w: int, dt: float):
    pts = embed(arr, m, lag)
    last = pts.shape[0] - 1 - step
    refs = np.arange(0, last + 1, step, dtype=np.int64)
    nb = _neighbours(pts, refs, k, w, last)
    running = np.empty((refs.size, m))
    total = _k.spectrum(pts, refs, nb, step, running)
    scale = 1.0 / (step * dt)
    return total / refs.size * scale, running * scale, refs.size


def lyapunov_spectrum(
    x: Any,
    *,
    embedding_dim: int,
    lag: int | None = None,
    dt: float = 1.0,
    step: int | None = None,
    n_neighbors: int | None = None,
    theiler_window: int | None = None,
    spurious_check: SpuriousCheck = "embedding",
) -> LyapunovSpectrumResult:
    r"""All ``embedding_dim`` Lyapunov exponents of a scalar series.

    At each reference point :math:`\mathbf y_i` of the delay embedding the tangent map over
    ``step`` samples is fitted by least squares to the evolution of its nearest neighbours,
    :math:`\mathbf y_{j+s} - \bar{\mathbf y}_{+s} \approx J_i (\mathbf y_j - \bar{\mathbf y})`;
    the product of the maps is re-orthonormalised by QR and

    .. math:: \lambda_k = \frac{1}{K s\,\Delta t} \sum_{i=1}^{K} \ln |R^{(i)}_{kk}|.

    An embedding larger than the attractor needs adds spurious exponents. The default
    check computes the spectrum again at ``embedding_dim + 1``: exponents of the dynamics
    persist, spurious ones move or vanish. ``"reversal"`` uses the time-reversed series
    instead (true exponents flip sign; Parlitz 1992); from data it works for maps but not
    for strongly dissipative flows, whose reversed contraction rates the local fits miss.

    Parameters
    ----------
    x
        Scalar series sampled every ``dt``.
    embedding_dim
        Embedding dimension m (2 … 12): the number of exponents.
    lag
        Delay in samples (default: estimated, the ``"auto"`` rule of
        :func:`chaoskit.estimate_delay`).
    dt
        Sampling interval (units of the caller; 1 for maps).
    step
        Evolution time of each local map, samples (≥ 1; default: the lag). Maps need 1; for
        flows one-sample maps are nearly the identity and their fits noisy.
    n_neighbors
        Neighbours per fit (default ``2·m + 4``, at least ``m + 1``).
    theiler_window
        Neighbours closer in time than this are excluded (default: one mean period,
        capped at N/10).
    spurious_check
        ``"embedding"`` (default), ``"reversal"`` or ``"none"`` (half the cost).

    Returns
    -------
    LyapunovSpectrumResult

    Raises
    ------
    ValueError
        On bad parameters or a series too short for the embedding and the neighbours.

    References
    ----------
    M. Sano and Y. Sawada, "Measurement of the Lyapunov spectrum from a chaotic time
    series", Phys. Rev. Lett. 55 (1985) 1082. J.-P. Eckmann, S. O. Kamphorst, D. Ruelle
    and S. Ciliberto, "Liapunov exponents from time series", Phys. Rev. A 34 (1986) 4971.
    U. Parlitz, "Identification of true and spurious Lyapunov exponents from time
    series", Int. J. Bifurcation Chaos 2 (1992) 155.

    Examples
    --------
    >>> from chaoskit import lyapunov_spectrum, systems
    >>> res = lyapunov_spectrum(systems.henon(5000)[:, 0], embedding_dim=2, lag=1)
    >>> [round(float(v), 1) for v in res.exponents]
    [0.4, -1.6]
    """
    m = check_int(embedding_dim, name="embedding_dim", minimum=2, maximum=12)
    dt = check_positive(dt, name="dt")
    check_index_interval(x, dt)
    k = 2 * m + 4 if n_neighbors is None else n_neighbors
    k = check_int(k, name="n_neighbors", minimum=m + 1, maximum=200)
    arr = standardize(as_series(x, min_length=100))
    n = arr.size
    lag_used, lag_rule = lag_or_estimate(arr, lag)
    step = lag_used if step is None else check_int(step, name="step", minimum=1)
    n_points = n - (m - 1) * lag_used
    if theiler_window is None:
        w = default_theiler_window(arr, max(n_points, 1))
    else:
        w = check_int(theiler_window, name="theiler_window", minimum=0)
    need = (m - 1) * lag_used + step + k + 2 * w + 2
    if n < need:
        raise ValueError(
            f"x is too short: {n} samples, but embedding_dim={m}, lag={lag_used}, step={step}, "
            f"n_neighbors={k} and theiler_window={w} need at least {need}."
        )
    spurious_check = check_choice(spurious_check, name="spurious_check", choices=_CHECKS)  # type: ignore[assignment]
    lam, running, n_refs = _run(arr, m, lag_used, step, k, w, dt)
    if spurious_check == "embedding":
        if m + 1 > 12 or n < need + lag_used:
            raise ValueError(
                f"spurious_check='embedding' needs embedding_dim + 1 = {m + 1} ≤ 12 and "
                f"{need + lag_used} samples; use spurious_check='none'."
            )
        k_up = max(k, 2 * (m + 1) + 4) if n_neighbors is None else k
        other = _run(arr, m + 1, lag_used, step, k_up, w, dt)[0]
    elif spurious_check == "reversal":
        other = -_run(np.ascontiguousarray(arr[::-1]), m, lag_used, step, k, w, dt)[0]
    else:
        other = np.empty(0)
    if other.size:
        scale = max(float(lam[0]), 0.0)
        spurious = np.array(
            [np.min(np.abs(other - v)) > SPURIOUS_TOL * max(abs(v), scale) for v in lam]
        )
    else:
        spurious = np.zeros(m, dtype=bool)
    return LyapunovSpectrumResult(
        exponents=lam,
        spurious=spurious,
        check=spurious_check,
        check_exponents=np.sort(other)[::-1].copy(),
        sum_exponents=float(lam.sum()),
        kaplan_yorke_dimension=_kaplan_yorke(lam),
        running=running,
        dt=dt,
        embedding_dim=m,
        lag=lag_used,
        step=step,
        n_neighbors=k,
        theiler_window=w,
        lag_rule=lag_rule,
        n_references=n_refs,
        n_samples=n,
    )
