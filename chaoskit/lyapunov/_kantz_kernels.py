"""Compiled kernel of Kantz's neighbourhood-averaged divergence (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._kernels import sq_distance


@njit(cache=True)
def kantz_log_distances(pts, order, key, ref, w, eps, ks, max_neighbors, transverse, out):
    """:func:`kantz_log_distances_cols` with the transposed coordinates built here."""
    cols = np.ascontiguousarray(pts.T)
    return kantz_log_distances_cols(
        pts, order, key, ref, w, eps, ks, max_neighbors, transverse, out, cols
    )


@njit(cache=True)
def kantz_log_distances_cols(
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
    cols: np.ndarray,
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
    local flow direction at ``y_{i+k}`` (see ``_kernels.sq_distance``). ``cols`` is
    ``pts.T`` made contiguous (each coordinate a row, so that a neighbour's distances at
    consecutive horizons are read from contiguous memory).
    """
    m = pts.shape[1]
    n_e = eps.size
    nk = ks.size
    e_max = eps[n_e - 1]
    cand = np.empty(order.size, dtype=np.int64)
    cdist = np.empty(order.size)
    used = np.zeros((ref.size, n_e), dtype=np.int64)
    acc = np.zeros((n_e, nk))
    row = np.empty(nk)
    total_e = np.zeros(n_e, dtype=np.int64)
    stride_e = np.ones(n_e, dtype=np.int64)
    seen_e = np.zeros(n_e, dtype=np.int64)
    taken_e = np.zeros(n_e, dtype=np.int64)
    take_e = np.zeros(n_e, dtype=np.bool_)
    unit = True
    for q in range(1, nk):
        if ks[q] != ks[q - 1] + 1:
            unit = False
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
        # one pass over the candidates for every radius: a neighbour's distance curve is
        # computed once and added to each radius that takes it (the radii nest), in the
        # same candidate order as a pass per radius, so the sums are the same
        for e in range(n_e):
            count = 0
            for t in range(nc):
                if cdist[t] < eps[e]:
                    count += 1
            total_e[e] = count
            stride_e[e] = (count + max_neighbors - 1) // max_neighbors if count else 1
            seen_e[e] = 0
            taken_e[e] = 0
        acc[:, :] = 0.0
        for t in range(nc):
            any_ = False
            for e in range(n_e):
                take_e[e] = False
                if cdist[t] < eps[e]:
                    take_e[e] = seen_e[e] % stride_e[e] == 0
                    seen_e[e] += 1
                    any_ = any_ or take_e[e]
            if not any_:
                continue
            j = cand[t]
            if transverse:
                for q in range(nk):
                    row[q] = np.sqrt(sq_distance(pts, i + ks[q], j + ks[q], True))
            else:
                row[:] = 0.0
                for c in range(m):
                    col = cols[c]
                    if unit:  # consecutive horizons: contiguous slices, vectorised
                        a = col[i + ks[0] : i + ks[0] + nk]
                        b = col[j + ks[0] : j + ks[0] + nk]
                        for q in range(nk):
                            diff = b[q] - a[q]
                            row[q] += diff * diff
                    else:
                        for q in range(nk):
                            diff = col[j + ks[q]] - col[i + ks[q]]
                            row[q] += diff * diff
                for q in range(nk):
                    row[q] = np.sqrt(row[q])
            for e in range(n_e):
                if take_e[e]:
                    taken_e[e] += 1
                    for q in range(nk):
                        acc[e, q] += row[q]
        for e in range(n_e):
            taken = taken_e[e]
            used[r, e] = taken
            for q in range(nk):
                if taken == 0:
                    out[r, e, q] = np.nan
                else:
                    out[r, e, q] = np.log(acc[e, q] / taken) if acc[e, q] > 0.0 else np.nan
    return used
