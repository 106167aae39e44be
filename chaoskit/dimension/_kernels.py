"""Compiled pair-counting kernels for the correlation sum (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit

GRID = 512  # boxes per axis of the hashed grid (a power of two: the index is masked)


@njit(cache=True, inline="always")
def _box(value: float, inv: float) -> np.int64:
    return np.int64(np.floor(value * inv)) & (GRID - 1)


@njit(cache=True)
def fill_grid(
    x: np.ndarray,
    lag: int,
    points: np.ndarray,
    eps: float,
    two_d: bool,
    head: np.ndarray,
    nxt: np.ndarray,
) -> None:
    """Link ``points`` into boxes of side ``eps`` over (x_i, x_{i+lag}) or x_i alone."""
    head[:] = -1
    inv = 1.0 / eps
    for q in range(points.size):
        i = points[q]
        bx = _box(x[i], inv)
        by = _box(x[i + lag], inv) if two_d else 0
        nxt[i] = head[bx, by]
        head[bx, by] = i


@njit(cache=True)
def count_progressive(
    x: np.ndarray,
    lag: int,
    max_dim: int,
    order: np.ndarray,
    rank: np.ndarray,
    start: int,
    stop: int,
    radii: np.ndarray,
    theiler_window: int,
    maximum_norm: bool,
    two_d: bool,
    head: np.ndarray,
    nxt: np.ndarray,
    hist: np.ndarray,
) -> int:
    """Count the pairs of ``order[start:stop]`` with every point inserted before it.

    Each point ``i = order[n]`` is compared with the points already in the grid (those of
    rank < n), then inserted, so every unordered pair is met once. ``hist[m − 1, k]`` gains
    the pairs with ``|i − j| > w`` and ``radii[k − 1] < ‖y_i − y_j‖_m ≤ radii[k]``. Returns
    the number of admissible pairs examined (the normalisation). ``two_d``: the grid holds
    (x_i, x_{i+lag}) boxes, valid for dimensions ≥ 2 only; else x_i boxes (dimension 1).
    The box side is ``radii[-1]``.
    """
    r_max = radii[-1]
    r_max2 = r_max * r_max
    inv = 1.0 / r_max
    nr = radii.size
    n_points = rank.size
    admissible = 0
    for n in range(start, stop):
        i = order[n]
        admissible += n
        for j in range(max(0, i - theiler_window), min(n_points, i + theiler_window + 1)):
            if rank[j] < n:
                admissible -= 1
        bx = np.int64(np.floor(x[i] * inv))
        by = np.int64(np.floor(x[i + lag] * inv)) if two_d else np.int64(0)
        for ox in range(-1, 2):
            for oy in range(-1, 2):
                if not two_d and oy != 0:
                    continue
                j = head[(bx + ox) & (GRID - 1), (by + oy) & (GRID - 1)]
                while j != -1:
                    if abs(j - i) > theiler_window:
                        d = 0.0
                        for m in range(max_dim):
                            diff = abs(x[i + m * lag] - x[j + m * lag])
                            if maximum_norm:
                                if diff > d:
                                    d = diff
                                if d > r_max:
                                    break
                                dist = d
                            else:
                                d += diff * diff
                                if d > r_max2:
                                    break
                                dist = np.sqrt(d)
                            lo = 0  # first radius ≥ dist (binary search)
                            hi = nr
                            while lo < hi:
                                mid = (lo + hi) // 2
                                if radii[mid] < dist:
                                    lo = mid + 1
                                else:
                                    hi = mid
                            hist[m, lo] += 1
                    j = nxt[j]
        bx &= GRID - 1
        by &= GRID - 1
        nxt[i] = head[bx, by]
        head[bx, by] = i
    return admissible
