"""Statistics of the wear per cycle averaged over revolutions: the batch-means interval,
its largest relative half-width and the revolution windows of a run."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr
from scipy.stats import t as student_t

from mechanism.core.record import window_start

from ._wear_settings import MAX_BATCHES, RELATIVE_HALFWIDTH_FLOOR


def batch_halfwidth(samples: np.ndarray, batches: int = MAX_BATCHES) -> np.ndarray:
    """95 % half-width of the mean of ``samples`` along axis 0, from batch means.

    The samples (one per revolution) are split into at most ``batches`` groups of
    consecutive samples; t(0.975, B − 1) s_B / √B with s_B the standard deviation of the
    B group means. NaN for fewer than two samples.
    """
    n = samples.shape[0]
    b = min(n, batches)
    if b < 2:
        return np.full(samples.shape[1:], math.nan)
    means = np.stack([g.mean(axis=0) for g in np.array_split(samples, b, axis=0)])
    return float(student_t.ppf(0.975, b - 1)) * means.std(axis=0, ddof=1) / math.sqrt(b)


def relative_halfwidth(mean: np.ndarray, halfwidth: np.ndarray) -> float:
    """Largest half-width / mean over the regions whose mean is at least
    :data:`RELATIVE_HALFWIDTH_FLOOR` of their surface's largest (NaN when nothing wears)."""
    worst = math.nan
    for m, h in zip(mean, halfwidth, strict=True):
        top = float(m.max())
        if top <= 0.0 or not np.isfinite(h).all():
            continue
        worn = m >= RELATIVE_HALFWIDTH_FLOOR * top
        value = float((h[worn] / m[worn]).max())
        worst = value if math.isnan(worst) else max(worst, value)
    return worst


def nanmax(a: float, b: float) -> float:
    """The larger of two values, ignoring NaN (NaN only when both are)."""
    if math.isnan(a):
        return b
    return a if math.isnan(b) else max(a, b)


def revolution_bounds(traj: xr.Dataset, settle: float, revolutions: int) -> list[int]:
    """Sample indices that start the ``revolutions`` revolutions after ``settle`` and end
    the last one (its last sample)."""
    bounds = [window_start(traj, settle + k) for k in range(revolutions)]
    return [*bounds, int(traj.sizes["time"]) - 1]


def contact_modes(
    traj: xr.Dataset, joint: str, *, start: int, continuous_time: float
) -> tuple[float, float, float]:
    """Time shares of free flight, impacts and continuous contact of one joint.

    A sample is in contact when its contact force is positive. Consecutive samples in
    contact form one contact episode; an episode lasting less than ``continuous_time`` (s)
    is an impact, a longer one continuous contact. Each sample carries its trapezoidal
    time weight over the window ``traj.time[start:]``, so the three shares add up to 1.
    """
    t = np.asarray(traj["time"].values, dtype=np.float64)[start:]
    force = np.asarray(traj["contact_force"].sel(joint=joint).values, dtype=np.float64)[start:]
    w = np.zeros(t.size)
    if t.size > 1:
        dt = np.diff(t)
        w[:-1] += 0.5 * dt
        w[1:] += 0.5 * dt
    total = float(w.sum())
    if total <= 0.0:
        return (math.nan, math.nan, math.nan)
    on = np.nan_to_num(force) > 0.0
    edges = np.diff(np.concatenate([[0], on.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    impact = continuous = 0.0
    for a, b in zip(starts, ends, strict=True):
        duration = float(w[a:b].sum())
        if duration < continuous_time:
            impact += duration
        else:
            continuous += duration
    return (1.0 - (impact + continuous) / total, impact / total, continuous / total)
