"""The public entry point of the local projective noise reduction and its input handling."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from scipy.spatial import cKDTree

from .._progress import stage
from .._tables import has_time_index
from .._validate import as_series, check_int, check_positive
from ..embedding import estimate_delay, estimate_embedding_dim
from ._projective import MIN_NEIGHBORS, correction_pass, embed, local_spectrum
from ._result import DenoiseResult

__all__ = ["local_projective_denoise"]

MIN_SAMPLES = 100
MAX_ITERATIONS = 100
#: Neighbourhood radius in units of the noise level times √m: the radius must exceed the
#: noise in delay space (norm σ√m), or the neighbourhood is the noise around the point.
RADIUS_NOISE_FACTOR = 2.0
#: Smallest automatic radius, as a fraction of the attractor size (√m · std): clean data
#: have no noise floor to scale with.
RADIUS_SIZE_FRACTION = 0.01
#: A local direction belongs to the manifold when its spread exceeds this many times the
#: smallest one (the noise floor).
SPREAD_RATIO = 2.0
#: The neighbours of a delay vector may be at most 1/LOCAL_FRACTION of all delay vectors
#: (this sets the minimum length): more would average over much of the attractor.
LOCAL_FRACTION = 10
_SPECTRUM_POINTS = 1000  # neighbourhoods sampled for the local spectrum
_SPECTRUM_NEIGHBORS = 50
_UNIFORM_RTOL = 1e-6


def _index_seconds(index: pd.Index) -> np.ndarray:
    """Seconds of a pandas time index (datetime, timedelta or float seconds)."""
    if isinstance(index, pd.DatetimeIndex):
        return np.asarray((index - index[0]) / pd.Timedelta(seconds=1), dtype=np.float64)
    if isinstance(index, pd.TimedeltaIndex):
        return np.asarray(index / pd.Timedelta(seconds=1), dtype=np.float64)
    return index.to_numpy(dtype=np.float64)


def _axis(x: Any, dt: Any) -> tuple[float, dict[str, Any]]:
    """Sampling interval and the description of the input (name, units, axis).

    The interval comes from the time axis of a DataArray or the time index of a pandas
    Series when there is one (a ``dt`` that contradicts it is refused), else from ``dt``,
    else it is 1 (a series indexed by sample).
    """
    meta: dict[str, Any] = {"name": "x", "units": "unknown", "long_name": "x", "dim": "step"}
    t = None
    if isinstance(x, xr.DataArray) and x.ndim == 1:
        meta["name"] = str(x.name) if x.name is not None else "x"
        meta["units"] = str(x.attrs.get("units", "unknown"))
        meta["long_name"] = str(x.attrs.get("long_name", meta["name"]))
        dim = meta["dim"] = str(x.dims[0])
        if dim in x.coords and x[dim].dtype.kind in "fiu":
            t = np.asarray(x[dim].values, dtype=np.float64)
            meta["coord"], meta["coord_attrs"] = t, dict(x[dim].attrs)
    elif has_time_index(x):
        if getattr(x, "name", None) is not None:
            meta["name"] = meta["long_name"] = str(x.name)
        t = _index_seconds(x.index)
        meta["dim"], meta["coord"] = "time", t
        meta["coord_attrs"] = {"units": "s", "long_name": "time"}
    if dt is not None:
        dt = check_positive(dt, name="dt")
    if t is not None and t.size >= 2 and meta["dim"] != "step":
        step = np.diff(t)
        mid = float(np.median(step))
        if mid <= 0 or np.max(np.abs(step - mid)) > _UNIFORM_RTOL * abs(mid):
            raise ValueError(
                f"the {meta['dim']} axis of x is not uniformly sampled; resample it first "
                "(the delay vectors assume equal intervals)."
            )
        if dt is not None and abs(dt - mid) > _UNIFORM_RTOL * mid:
            raise ValueError(
                f"dt={dt:g} contradicts the {meta['dim']} axis of x (sampling interval "
                f"{mid:.6g}); leave dt out, the interval is known."
            )
        return mid, meta
    if dt is None:
        return 1.0, meta
    if "coord" not in meta:
        meta["dim"] = "time"
    return dt, meta


def _manifold_dim(spread: np.ndarray) -> tuple[int, str]:
    """Local directions above the noise floor, plus one (at most m − 1)."""
    m = spread.size
    floor = float(spread[-1])
    above = int(np.sum(spread > SPREAD_RATIO * floor)) if floor > 0 else m
    q = int(min(max(above + 1, 1), m - 1))
    return q, (
        f"estimated: {above} local direction(s) spread more than {SPREAD_RATIO:g}× the "
        "smallest (the noise floor), plus one for the direction across the attractor's "
        f"layers, at most embedding_dim − 1 = {m - 1}"
    )


def _spectrum(z: np.ndarray, m: int, lag: int, w: int) -> np.ndarray:
    """Local spreads (standard deviations along the principal directions, largest first)
    of up to 1000 evenly spaced neighbourhoods of the delay vectors of ``z``."""
    pts = embed(z, m, lag)
    tree = cKDTree(pts, leafsize=16, balanced_tree=False, compact_nodes=False)
    rows = np.unique(np.linspace(0, pts.shape[0] - 1, _SPECTRUM_POINTS).astype(np.int64))
    ev = local_spectrum(pts, tree, rows, min_neighbors=_SPECTRUM_NEIGHBORS, theiler_window=w)
    return np.maximum(ev, 0.0)


def _noise(ev: np.ndarray, q: int) -> float:
    """Noise level: RMS local spread off the ``q`` leading directions (median over points)."""
    return float(np.sqrt(np.median(ev[:, q:].mean(axis=1))))


def _embedding(arr: np.ndarray, embedding_dim: Any, lag: Any) -> tuple[int, int, str, str]:
    """Validated or estimated ``(embedding_dim, lag)`` and how each was obtained."""
    if embedding_dim is not None:
        embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=3, maximum=64)
    if lag is None:
        delay = estimate_delay(arr, method="auto")
        lag, lag_rule = int(delay.lag), f"estimated: estimate_delay(method='auto'), {delay.rule}"
    else:
        lag, lag_rule = check_int(lag, name="lag", minimum=1, maximum=arr.size // 4), "given"
    if embedding_dim is None:
        dim = estimate_embedding_dim(arr, lag=lag)
        m = max(3, dim.embedding_dim + 1)
        rule = (
            f"estimated: false nearest neighbours give {dim.embedding_dim} ({dim.rule}); one "
            "more (at least 3), so that the middle coordinates are over-determined"
        )
        return m, lag, rule, lag_rule
    return embedding_dim, lag, "given", lag_rule


def _check_length(n: int, m: int, lag: int, w: int) -> None:
    """Refuse a series whose neighbourhoods could not be local: every delay vector needs
    ``MIN_NEIGHBORS`` neighbours outside its window, and they may be at most a tenth of all
    delay vectors (more would average over a large part of the attractor)."""
    n_pts = n - (m - 1) * lag
    extra = 2 * w + 2 + LOCAL_FRACTION * MIN_NEIGHBORS
    if n_pts < extra:
        raise ValueError(
            f"x is too short: {n} samples, but embedding_dim={m}, lag={lag} and "
            f"theiler_window={w} need at least {(m - 1) * lag + extra} (the "
            f"{MIN_NEIGHBORS} neighbours of a delay vector, outside its window, must be at "
            f"most 1/{LOCAL_FRACTION} of all delay vectors)."
        )


def _passes(
    z: np.ndarray,
    m: int,
    lag: int,
    q: int,
    w: int,
    iterations: int,
    noise0: float,
    radius: float | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run the correction passes on the standardised series ``z``; return the cleaned
    series, the radius and the RMS correction of each pass (standardised units)."""
    floor = RADIUS_SIZE_FRACTION * np.sqrt(m)
    radii, rms = [], []
    for i in range(iterations):
        r = radius
        if r is None:
            noise = noise0 if i == 0 else _noise(_spectrum(z, m, lag, w), q)
            r = max(RADIUS_NOISE_FACTOR * noise * np.sqrt(m), floor)
        corr = correction_pass(
            z, m=m, lag=lag, q=q, radius=r, min_neighbors=MIN_NEIGHBORS, theiler_window=w
        )
        z = z + corr
        radii.append(r)
        rms.append(float(np.sqrt(np.mean(corr**2))))
    return z, np.asarray(radii), np.asarray(rms)


def local_projective_denoise(
    x: Any,
    *,
    embedding_dim: int | None = None,
    lag: int | None = None,
    manifold_dim: int | None = None,
    radius: float | None = None,
    iterations: int = 3,
    dt: float | None = None,
    theiler_window: int | None = None,
) -> DenoiseResult:
    r"""Reduce measurement noise by local projections onto the attractor (GHKSS).

    The series is embedded in delay vectors
    :math:`\mathbf y_i = (x_i, x_{i+\tau}, \dots, x_{i+(m-1)\tau})`. Deterministic dynamics
    put them close to a smooth ``manifold_dim``-dimensional surface; additive noise spreads
    them in all :math:`m` directions. For each :math:`\mathbf y_i`, the covariance of its
    neighbourhood (the points within ``radius``, at least 30) is weighted with
    :math:`R = \mathrm{diag}(10^3, 1, \dots, 1, 10^3)`, the :math:`m - q` directions of
    least weighted variance are taken as normal to the surface, and the component of
    :math:`\mathbf y_i` minus the neighbourhood's centre of mass along them is removed;
    the mean correction of the neighbours is subtracted (the centre of mass lies on the
    concave side of a curved surface). The end weights leave the first and last coordinates
    almost untouched: a sample is corrected by the mean of its corrections as a middle
    coordinate. The pass is repeated ``iterations`` times, each with the radius scaled to
    the noise still present.

    Defaults chosen from the data (each recorded in the result's ``*_rule``):

    * ``lag``: :func:`~chaoskit.estimate_delay` with ``method="auto"``;
    * ``embedding_dim``: one more than :func:`~chaoskit.estimate_embedding_dim` (false
      nearest neighbours), at least 3;
    * ``manifold_dim``: from the local singular-value spectrum: the number of local
      directions whose spread exceeds twice the smallest (the noise floor), plus one for the
      direction across the layers of a fractal attractor, which is thinner than the noise,
      at most ``embedding_dim − 1``;
    * ``radius``: twice the estimated noise level times :math:`\sqrt m` (the noise's extent
      in delay space), at least 1 % of the attractor size :math:`\sqrt m\,\mathrm{std}(x)`;
      the noise level is the RMS spread of the neighbourhoods off their ``manifold_dim``
      leading directions, re-estimated before each pass;
    * ``theiler_window``: :math:`(m-1)\tau`, so that no neighbour shares a sample (and so
      its noise) with the delay vector it corrects.

    Nothing in chaoskit applies this step silently: pass ``result.cleaned`` to the
    estimators yourself, and report that you did.

    Parameters
    ----------
    x
        Scalar series: numpy array, pandas Series, or a 1-D xarray DataArray (a variable of
        a trajectory Dataset, ``ds["x"]``); finite, not constant, and at least
        :math:`(m-1)\tau + 2w + 302` samples (``w`` the Theiler window), so that the 30
        neighbours of a delay vector are at most a tenth of all of them.
    embedding_dim
        Dimension :math:`m` of the delay vectors, 3 … 64.
    lag
        Delay :math:`\tau` in samples, 1 … N/4.
    manifold_dim
        Dimension :math:`q` of the local surface, 1 … ``embedding_dim`` − 1.
    radius
        Neighbourhood radius in the units of ``x`` (> 0), used in every pass.
    iterations
        Number of passes, 1 … 100 (default 3).
    dt
        Sampling interval (> 0); by default taken from a DataArray's time axis or a pandas
        time index (a ``dt`` that contradicts them is refused), else 1 (a series indexed by
        sample). It only labels the time axis of the output.
    theiler_window
        Delay vectors with ``|i − j| <=`` ``theiler_window`` are not neighbours (samples,
        >= 0).

    Returns
    -------
    DenoiseResult
        ``cleaned`` series, ``correction_rms`` per pass, the parameters used with their
        rules, and :meth:`~chaoskit.DenoiseResult.to_dataset` /
        :meth:`~chaoskit.DenoiseResult.to_dataarray`.

    Raises
    ------
    ValueError
        For non-numeric, non-finite, constant or too short input, or a parameter outside
        its range (the message names it).

    References
    ----------
    P. Grassberger, R. Hegger, H. Kantz, C. Schaffrath, T. Schreiber, "On noise reduction
    methods for chaotic data", Chaos 3 (1993) 127–141; H. Kantz, T. Schreiber, *Nonlinear
    Time Series Analysis*, 2nd ed., Cambridge University Press (2004), §10.3.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import local_projective_denoise, systems
    >>> x = systems.henon(5000)[:, 0]
    >>> noisy = x + 0.05 * x.std() * np.random.default_rng(0).standard_normal(x.size)
    >>> res = local_projective_denoise(noisy)
    >>> bool(np.std(res.cleaned - x) < 0.5 * np.std(noisy - x))
    True
    """
    stage("denoise")
    if isinstance(x, xr.Dataset):
        raise ValueError(
            "x is a Dataset; pass one of its variables, e.g. ds['x'] "
            "(chaoskit.select_series picks one series of a multi-dimensional variable)."
        )
    iterations = check_int(iterations, name="iterations", minimum=1, maximum=MAX_ITERATIONS)
    arr = as_series(x, min_length=MIN_SAMPLES)
    dt, meta = _axis(x, dt)
    if radius is not None:
        radius = check_positive(radius, name="radius")
    if theiler_window is not None:
        theiler_window = check_int(theiler_window, name="theiler_window", minimum=0)
    # work in units of the standard deviation: scale-free rules, no overflow of squares
    mean, scale = float(arr.mean()), float(arr.std())
    z = (arr - mean) / scale
    m, lag, dim_rule, lag_rule = _embedding(z, embedding_dim, lag)
    if manifold_dim is not None:
        manifold_dim = check_int(manifold_dim, name="manifold_dim", minimum=1, maximum=m - 1)
    w = (m - 1) * lag if theiler_window is None else theiler_window
    _check_length(z.size, m, lag, w)
    ev = _spectrum(z, m, lag, w)
    spread = np.sqrt(np.median(ev, axis=0))
    q, q_rule = _manifold_dim(spread) if manifold_dim is None else (manifold_dim, "given")
    noise0 = _noise(ev, q)
    z, radii, rms = _passes(
        z, m, lag, q, w, iterations, noise0, None if radius is None else radius / scale
    )
    radius_rule = (
        "given"
        if radius is not None
        else (
            f"estimated: {RADIUS_NOISE_FACTOR:g} × noise level × √embedding_dim, at least "
            f"{RADIUS_SIZE_FRACTION:g} × √embedding_dim × std(x); re-estimated each pass"
        )
    )
    return DenoiseResult(
        cleaned=z * scale + mean,
        original=arr.copy(),
        method="local_projective",
        embedding_dim=m,
        lag=lag,
        manifold_dim=q,
        radius=radii * scale,
        min_neighbors=MIN_NEIGHBORS,
        theiler_window=w,
        iterations=iterations,
        noise_level=noise0 * scale,
        correction_rms=rms * scale,
        local_spread=spread * scale,
        embedding_dim_rule=dim_rule,
        lag_rule=lag_rule,
        manifold_dim_rule=q_rule,
        radius_rule=radius_rule,
        dt=dt,
        **meta,
    )
