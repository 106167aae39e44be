"""Compiled box-assisted nearest-neighbour search with a Theiler window (no validation here).

The points are bucketed on a uniform grid over ``g`` of their coordinates (``cols``): the
cells are numbered ``Σ c_d · stride_d``, the points sorted by cell (``members``), and
``keys``/``starts`` hold each occupied cell and the offset of its first member. A query
visits the cells around its own in rings of growing Chebyshev radius, skips a cell whose
box is farther (in the ``g`` coordinates) than the best candidate so far, and stops once
every unvisited cell lies farther than that candidate: the projected distance bounds the
full distance from below in both norms, so the grid only prefilters and the neighbour is
the exact one. Ties go to the smaller index, so the result does not depend on the grid.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def cell_keys(points, cols, lo, cell, ncell, stride):
    """Linear cell id of every point on the grid of ``cols`` (cells clipped to the grid)."""
    n = points.shape[0]
    keys = np.empty(n, dtype=np.int64)
    for i in range(n):
        key = 0
        for d in range(cols.size):
            c = int(np.floor((points[i, cols[d]] - lo[d]) / cell))
            c = min(max(c, 0), ncell[d] - 1)
            key += c * stride[d]
        keys[i] = key
    return keys


@njit(cache=True)
def occupancy(sorted_keys):
    """Mean number of points in the cell of a point: Σ count² / N over the occupied cells."""
    n = sorted_keys.size
    total = 0.0
    run = 1
    for i in range(1, n + 1):
        if i < n and sorted_keys[i] == sorted_keys[i - 1]:
            run += 1
        else:
            total += run * run
            run = 1
    return total / n


@njit(cache=True)
def slot_table(keys, total):
    """Position of every cell id ``0 … total − 1`` in the sorted ``keys`` (−1: empty)."""
    slot = np.full(total, -1, dtype=np.int32)
    for p in range(keys.size):
        slot[keys[p]] = p
    return slot


@njit(cache=True, inline="always")
def find_key(keys, key):
    """Position of ``key`` in the sorted ``keys``, or −1 (binary search)."""
    lo = 0
    hi = keys.size
    while lo < hi:
        mid = (lo + hi) >> 1
        if keys[mid] < key:
            lo = mid + 1
        else:
            hi = mid
    if lo < keys.size and keys[lo] == key:
        return lo
    return -1


@njit(cache=True, inline="always")
def _distance(points, i, j, best, maxnorm):
    """Squared Euclidean (or maximum-norm) distance, abandoned above ``best`` (returns inf)."""
    d = 0.0
    for c in range(points.shape[1]):
        diff = points[i, c] - points[j, c]
        if maxnorm:
            diff = abs(diff)
            if diff > d:
                d = diff
        else:
            d += diff * diff
        if d > best:
            return np.inf
    return d


@njit(cache=True)
def _scan_cell(spts, qv, i, w, lo_m, hi_m, members, best, best_j, maxnorm):
    """Members ``lo_m … hi_m − 1`` (rows of ``spts``, the points in cell order) against the
    query ``qv`` (row ``i``): the best admissible one so far."""
    for q in range(lo_m, hi_m):
        j = members[q]
        if abs(i - j) <= w:
            continue
        d = 0.0
        for c in range(qv.size):
            diff = spts[q, c] - qv[c]
            if maxnorm:
                d = max(d, abs(diff))
            else:
                d += diff * diff
            if d > best:
                break
        if d < best or (d == best and j < best_j):
            best = d
            best_j = j
    return best, best_j


@njit(cache=True)
def _brute(spts, qv, i, w, members, maxnorm):
    return _scan_cell(spts, qv, i, w, 0, members.size, members, np.inf, -1, maxnorm)


@njit(cache=True, inline="always")
def _gap(off, frac, cell):
    """Distance (in the grid coordinate) from the query to a cell ``off`` cells away."""
    if off > 0:
        return (off - frac) * cell
    if off < 0:
        return (frac - off - 1.0) * cell
    return 0.0


@njit(cache=True, inline="always")
def _join(a, b, maxnorm):
    return max(a, b) if maxnorm else a + b


@njit(cache=True)
def _ring(
    spts, qv, i, w, r, cen, frc, ncl, strd, cell, keys, slot, starts, members, best, best_j, mx
):
    """Scan the cells at Chebyshev distance ``r`` from the query's cell (three coordinates,
    unused ones have one cell), skipping those farther than ``best``."""
    for o0 in range(-r, r + 1):
        c0 = cen[0] + o0
        if c0 < 0 or c0 >= ncl[0]:
            continue
        e0 = _gap(o0, frc[0], cell)
        g0 = e0 if mx else e0 * e0
        if g0 > best:
            continue
        r1 = r if ncl[1] > 1 else 0
        for o1 in range(-r1, r1 + 1):
            c1 = cen[1] + o1
            if c1 < 0 or c1 >= ncl[1]:
                continue
            e1 = _gap(o1, frc[1], cell)
            g1 = _join(g0, e1 if mx else e1 * e1, mx)
            if g1 > best:
                continue
            r2 = r if ncl[2] > 1 else 0
            edge = abs(o0) == r or abs(o1) == r
            for o2 in range(-r2, r2 + 1):
                if not edge and abs(o2) != r:
                    continue
                c2 = cen[2] + o2
                if c2 < 0 or c2 >= ncl[2]:
                    continue
                e2 = _gap(o2, frc[2], cell)
                if _join(g1, e2 if mx else e2 * e2, mx) > best:
                    continue
                key = c0 * strd[0] + c1 * strd[1] + c2 * strd[2]
                pos = slot[key] if slot.size else find_key(keys, key)
                if pos < 0:
                    continue
                best, best_j = _scan_cell(
                    spts, qv, i, w, starts[pos], starts[pos + 1], members, best, best_j, mx
                )
    return best, best_j


@njit(cache=True)
def grid_query(
    points,
    spts,
    query,
    proc,
    w,
    cols,
    lo,
    cell,
    ncell,
    stride,
    keys,
    slot,
    starts,
    members,
    maxnorm,
):
    """Nearest admissible neighbour (``|i − j| > w``) of each row in ``query``.

    ``spts`` holds the points in cell order (``points[members]``), so that a cell's
    members are read from contiguous memory; ``slot`` maps every cell id to its position in
    ``keys`` (−1: empty), or is empty when the grid is too large for such a table and the
    cells are found by bisection of ``keys``. The queries are answered in the order
    ``proc`` (by cell, so that consecutive queries read the same cells from cache).
    Returns the indices and the distances
    (Euclidean, or maximum norm with ``maxnorm``). A query whose search would visit more
    cells than there are points is answered by a scan of every point.
    """
    g = cols.size
    nq = query.size
    out_j = np.full(nq, -1, dtype=np.int64)
    out_d = np.full(nq, np.inf)
    cen = np.zeros(3, dtype=np.int64)
    frc = np.full(3, 0.5)
    ncl = np.ones(3, dtype=np.int64)
    strd = np.zeros(3, dtype=np.int64)
    max_ring = 0
    for d in range(g):
        ncl[d] = ncell[d]
        strd[d] = stride[d]
        max_ring = max(max_ring, ncell[d])
    qv = np.empty(points.shape[1])
    n_points = points.shape[0]
    answer = np.full(n_points, -1, dtype=np.int64)  # neighbour of each point answered
    prev_j = -1
    for tt in range(nq):
        t = proc[tt]
        i = query[t]
        qv[:] = points[i]
        fmin = 0.5
        for d in range(g):
            u = (points[i, cols[d]] - lo[d]) / cell
            c = min(max(int(np.floor(u)), 0), ncell[d] - 1)
            cen[d] = c
            frc[d] = u - c
            fmin = min(fmin, max(0.0, min(frc[d], 1.0 - frc[d])))
        best = np.inf  # squared for the Euclidean norm
        best_j = -1
        # two exact candidates bound the search from the start, so that most cells are
        # skipped unseen: the successor of the neighbour of the point before (neighbouring
        # trajectories stay close) and the neighbour of the query answered just before
        # (it lies in the same or the next cell)
        for seed in (answer[i - 1] + 1 if i > 0 and answer[i - 1] >= 0 else -1, prev_j):
            if 0 <= seed < n_points and abs(i - seed) > w:
                d = _distance(points, i, seed, np.inf, maxnorm)
                if d < best or (d == best and seed < best_j):
                    best = d
                    best_j = seed
        visited = 0
        r = 0
        while True:
            side = 2 * r + 1
            visited += side**g
            if visited > members.size:
                best, best_j = _brute(spts, qv, i, w, members, maxnorm)
                break
            best, best_j = _ring(
                spts,
                qv,
                i,
                w,
                r,
                cen,
                frc,
                ncl,
                strd,
                cell,
                keys,
                slot,
                starts,
                members,
                best,
                best_j,
                maxnorm,
            )
            # every unvisited cell lies at least (r + fmin) cells away in the grid coordinates
            reach = (r + fmin) * cell
            if best_j >= 0 and best <= (reach if maxnorm else reach * reach):
                break
            if r >= max_ring:
                break
            r += 1
        out_j[t] = best_j
        out_d[t] = best if maxnorm else np.sqrt(best)
        answer[i] = best_j
        prev_j = best_j
    return out_j, out_d
