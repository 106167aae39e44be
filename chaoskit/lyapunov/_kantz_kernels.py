"""Compiled kernel of Kantz's neighbourhood-averaged divergence (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._kernels import sq_distance


@njit(cache=True)
def kantz_log_distances(
    pts: np.ndarray,
    order: np.ndarray,
    key: np.ndarray,
    ref: np.ndarray,
    w: int,
    eps: np.ndarray,
    ks: np.ndarray,
    max_neighbors: int,
    transverse: bool,
    out: np.ndarray,
) -> np.ndarray:
    """Per reference point, ln of the mean distance to its ε-neighbours after k samples.

    Candidates are the rows ``order`` (sorted by their first coordinate, ``key`` holds that
    coordinate in the same order): only the slab ``|y_j0 − y_i0| < max(eps)`` is scanned, so
    the memory is O(N). A neighbour ``j`` of reference ``i`` has ``|i − j| > w`` and a
    maximum-norm distance below ``eps[e]``; when more than ``max_neighbors`` qualify an
    evenly strided subset of them (in slab order) is used. Fills
    ``out[r, e, q] = ln mean_j ‖y_{i+k_q} − y_{j+k_q}‖`` (Euclidean; NaN without
    neighbours or at a zero mean distance) and returns the neighbours used per (r, e).
    With ``transverse`` the distance is the part of the separation perpendicular to the
    local flow direction at ``y_{i+k}`` (see ``_kernels.sq_distance``).
    """
    m = pts.shape[1]
    n_e = eps.size
    nk = ks.size
    e_max = eps[n_e - 1]
    cand = np.empty(order.size, dtype=np.int64)
    cdist = np.empty(order.size)
    used = np.zeros((ref.size, n_e), dtype=np.int64)
    acc = np.zeros(nk)
    for r in range(ref.size):
        i = ref[r]
        x0 = pts[i, 0]
        lo = np.searchsorted(key, x0 - e_max)
        hi = np.searchsorted(key, x0 + e_max)
        nc = 0
        for p in range(lo, hi):
            j = order[p]
            if abs(i - j) <= w:
                continue
            d = 0.0
            for c in range(m):
                diff = abs(pts[i, c] - pts[j, c])
                if diff > d:
                    d = diff
                    if d >= e_max:
                        break
            if d < e_max:
                cand[nc] = j
                cdist[nc] = d
                nc += 1
        for e in range(n_e):
            count = 0
            for t in range(nc):
                if cdist[t] < eps[e]:
                    count += 1
            if count == 0:
                for q in range(nk):
                    out[r, e, q] = np.nan
                continue
            stride = (count + max_neighbors - 1) // max_neighbors
            acc[:] = 0.0
            seen = 0
            taken = 0
            for t in range(nc):
                if cdist[t] >= eps[e]:
                    continue
                if seen % stride == 0:
                    j = cand[t]
                    for q in range(nk):
                        acc[q] += np.sqrt(sq_distance(pts, i + ks[q], j + ks[q], transverse))
                    taken += 1
                seen += 1
            used[r, e] = taken
            for q in range(nk):
                out[r, e, q] = np.log(acc[q] / taken) if acc[q] > 0.0 else np.nan
    return used
