"""Compiled box-assisted nearest-neighbour search with a Theiler window (no validation here).

The points are bucketed on a uniform grid over ``g`` of their coordinates (``cols``): the
cells are numbered ``Σ c_d · stride_d``, the points sorted by cell (``members``), and
``keys``/``starts`` hold each occupied cell and the offset of its first member; inside
a cell the members are sorted by the first coordinate, so that a scan starts at the
query's place and stops where that coordinate alone is farther than the best. A query
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
def bucket(points, keys, order, total, dense):
    """The points sorted by cell: ``members`` (row indices), ``spts`` (their coordinates),
    each occupied cell id (``unique``), the offset of its first member (``starts``, one
    more entry) and, if ``dense``, the position of every cell id ``0 … total − 1`` in
    ``unique`` (``slot``, −1: empty; else an empty array).

    ``order`` sorts ``keys``; an empty ``order`` asks for a counting sort here (stable,
    O(N + total): for grids of at most a few cells per point it costs less than a
    comparison sort and the passes that follow one). Inside each cell the members are
    sorted by the first coordinate (:func:`_scan_sorted`).
    """
    n, m = points.shape
    if order.size == n:
        members = order.astype(np.int64)
    else:
        cursor = np.zeros(total + 1, dtype=np.int64)
        for i in range(n):
            cursor[keys[i] + 1] += 1
        for c in range(total):
            cursor[c + 1] += cursor[c]
        members = np.empty(n, dtype=np.int64)
        for i in range(n):
            members[cursor[keys[i]]] = i
            cursor[keys[i]] += 1
    n_unique = 0
    for q in range(n):
        if q == 0 or keys[members[q]] != keys[members[q - 1]]:
            n_unique += 1
    unique = np.empty(n_unique, dtype=np.int64)
    starts = np.empty(n_unique + 1, dtype=np.int64)
    u = 0
    for q in range(n):
        key = keys[members[q]]
        if q == 0 or key != unique[u - 1]:
            unique[u] = key
            starts[u] = q
            u += 1
    starts[n_unique] = n
    slot = np.full(total if dense else 0, -1, dtype=np.int32)
    if dense:
        for u in range(n_unique):
            slot[unique[u]] = u
    # each cell's members by their first coordinate (insertion sort: a few per cell)
    for u in range(n_unique):
        for q in range(starts[u] + 1, starts[u + 1]):
            v = members[q]
            x = points[v, 0]
            r = q - 1
            while r >= starts[u] and points[members[r], 0] > x:
                members[r + 1] = members[r]
                r -= 1
            members[r + 1] = v
    spts = np.empty((n, m))
    for q in range(n):
        for c in range(m):
            spts[q, c] = points[members[q], c]
    return members, spts, unique, starts, slot


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
def _point_distance(points, i, j, maxnorm):
    """Squared Euclidean (or maximum-norm) distance of rows ``i`` and ``j``."""
    d = 0.0
    for c in range(points.shape[1]):
        diff = points[i, c] - points[j, c]
        if maxnorm:
            d = max(d, abs(diff))
        else:
            d += diff * diff
    return d


@njit(cache=True, inline="always")
def _scan_cell(points, spts, i, w, limit, lo_m, hi_m, members, best, best_j, maxnorm):
    """Members ``lo_m … hi_m − 1`` (rows of ``spts``, the points in cell order) against row
    ``i`` of ``points``: the best admissible one (``|i − j| > w`` and ``j < limit``) so far
    (each distance abandoned once it exceeds ``best``; ties to the smaller index)."""
    m = points.shape[1]
    for q in range(lo_m, hi_m):
        j = members[q]
        if abs(i - j) <= w or j >= limit:
            continue
        d = 0.0
        for c in range(m):
            diff = spts[q, c] - points[i, c]
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


@njit(cache=True, inline="always")
def _scan_sorted(points, spts, i, w, limit, lo_m, hi_m, members, best, best_j, maxnorm):
    """:func:`_scan_cell` over a cell whose members are sorted by the first coordinate:
    from the query's place in that order outwards, each way until the first-coordinate
    gap alone exceeds ``best`` (the distance's first term is that gap, and adding the
    others never makes the rounded sum smaller, so no closer or tied point is skipped)."""
    m = points.shape[1]
    xq = points[i, 0]
    # first member whose first coordinate is >= the query's
    a = lo_m
    b = hi_m
    while a < b:
        mid = (a + b) >> 1
        if spts[mid, 0] < xq:
            a = mid + 1
        else:
            b = mid
    for step in (1, -1):
        q = a if step == 1 else a - 1
        while lo_m <= q < hi_m:
            dx = spts[q, 0] - xq
            gap = dx if step == 1 else -dx
            if (gap if maxnorm else dx * dx) > best:
                break
            j = members[q]
            if abs(i - j) > w and j < limit:
                d = 0.0
                for c in range(m):
                    diff = spts[q, c] - points[i, c]
                    if maxnorm:
                        d = max(d, abs(diff))
                    else:
                        d += diff * diff
                    if d > best:
                        break
                if d < best or (d == best and j < best_j):
                    best = d
                    best_j = j
            q += step
    return best, best_j


@njit(cache=True)
def _scan_all(points, spts, i, w, limit, members, best, best_j, maxnorm):
    """Every point against row ``i`` (a query whose rings would cover more cells than
    there are points)."""
    return _scan_cell(points, spts, i, w, limit, 0, members.size, members, best, best_j, maxnorm)


@njit(cache=True, inline="always")
def _gap(off, frac, cell):
    """Distance (in the grid coordinate) from the query to a cell ``off`` cells away."""
    if off > 0:
        return (off - frac) * cell
    if off < 0:
        return (frac - off - 1.0) * cell
    return 0.0


@njit(cache=True, inline="always")
def _grid_cell(value, lo, cell, n):
    """Cell of ``value`` on ``n`` cells from ``lo`` (clipped) and the position in it."""
    u = (value - lo) / cell
    c = min(max(int(np.floor(u)), 0), n - 1)
    return c, u - c


@njit(cache=True, inline="always")
def _seeded(points, i, w, limit, answer, prev_j, maxnorm):
    """The better of two exact candidates, so that most cells are skipped unseen: the
    successor of the neighbour of the point before (neighbouring trajectories stay close)
    and the neighbour of the query answered just before (same or next cell)."""
    best = np.inf
    best_j = -1
    for k in range(2):
        if k == 0:
            seed = answer[i - 1] + 1 if i > 0 and answer[i - 1] >= 0 else -1
        else:
            seed = prev_j
        if 0 <= seed < limit and abs(i - seed) > w:
            d = _point_distance(points, i, seed, maxnorm)
            if d < best or (d == best and seed < best_j):
                best = d
                best_j = seed
    return best, best_j


@njit(cache=True)
def grid_query(
    points,
    spts,
    query,
    w,
    limit,
    answer,
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
    """Nearest admissible neighbour (``|i − j| > w`` and ``j < limit``) of each row in
    ``query``.

    ``answer`` holds, per row of ``points``, a neighbour already known for this ``w`` and
    ``limit`` (−1: none): such a row is not searched again, and the known neighbours seed
    the search of the rows after them; the answers found are written into it.

    ``spts`` holds the points in cell order (``points[members]``), so that a cell's
    members are read from contiguous memory; ``slot`` maps every cell id to its position in
    ``keys`` (−1: empty), or is empty when the grid is too large for such a table and the
    cells are found by bisection of ``keys``. Returns the indices and the distances
    (Euclidean, or maximum norm with ``maxnorm``). A query whose search would visit more
    cells than there are points is answered by a scan of every point. The rings are
    written out here and the helpers inlined, with the grid's shape in scalars: calls and
    array reads per ring were a third of the time on a two-coordinate map.
    """
    g = cols.size
    nq = query.size
    out_j = np.full(nq, -1, dtype=np.int64)
    out_d = np.full(nq, np.inf)
    # the grid's shape as scalars (kept in registers); unused coordinates have one cell
    ca, cb, cz = cols[0], cols[1 % g], cols[2 % g]
    n0 = ncell[0]
    n1 = ncell[1] if g > 1 else 1
    n2 = ncell[2] if g > 2 else 1
    s0 = stride[0]
    s1 = stride[1] if g > 1 else 0
    s2 = stride[2] if g > 2 else 0
    max_ring = max(n0, max(n1, n2))
    use_slot = slot.size > 0
    prev_j = -1
    for t in range(nq):
        i = query[t]
        if answer[i] >= 0:  # known (exact, so the search would return it)
            d = _point_distance(points, i, answer[i], maxnorm)
            out_j[t] = answer[i]
            out_d[t] = d if maxnorm else np.sqrt(d)
            prev_j = answer[i]
            continue
        c0, f0 = _grid_cell(points[i, ca], lo[0], cell, n0)
        c1, f1, c2, f2 = 0, 0.5, 0, 0.5
        if g > 1:
            c1, f1 = _grid_cell(points[i, cb], lo[1], cell, n1)
        if g > 2:
            c2, f2 = _grid_cell(points[i, cz], lo[2], cell, n2)
        fmin = min(min(f0, 1.0 - f0), min(min(f1, 1.0 - f1), min(f2, 1.0 - f2)))
        fmin = min(0.5, max(0.0, fmin))
        best, best_j = _seeded(points, i, w, limit, answer, prev_j, maxnorm)
        r = 0
        visited = 0
        while True:
            side = 2 * r + 1
            visited += side if g == 1 else (side * side if g == 2 else side * side * side)
            if visited > members.size:
                # best_j typed, not the literal −1 of a query without a seed (a literal
                # argument compiles the kernel once more)
                best, best_j = _scan_all(
                    points, spts, i, w, limit, members, best, np.int64(best_j), maxnorm
                )
                break
            # the cells at Chebyshev distance r from the query's, skipping those farther
            # than the best candidate; off the ring's faces only the cells at ±r of the
            # last coordinate belong to it
            r1 = r if n1 > 1 else 0
            r2 = r if n2 > 1 else 0
            for o0 in range(-r, r + 1):
                edge0 = o0 == -r or o0 == r
                if not edge0 and r1 == 0 and r2 == 0:
                    continue
                a0 = c0 + o0
                if a0 < 0 or a0 >= n0:
                    continue
                e0 = _gap(o0, f0, cell)
                g0 = e0 if maxnorm else e0 * e0
                if g0 > best:
                    continue
                inner1 = not edge0 and r2 == 0
                for o1 in range(-r1, r1 + 1, 2 * r1 if inner1 else 1):
                    a1 = c1 + o1
                    if a1 < 0 or a1 >= n1:
                        continue
                    e1 = _gap(o1, f1, cell)
                    g1 = max(g0, e1) if maxnorm else g0 + e1 * e1
                    if g1 > best:
                        continue
                    inner2 = not edge0 and abs(o1) != r and r2 > 0
                    for o2 in range(-r2, r2 + 1, 2 * r2 if inner2 else 1):
                        a2 = c2 + o2
                        if a2 < 0 or a2 >= n2:
                            continue
                        e2 = _gap(o2, f2, cell)
                        if (max(g1, e2) if maxnorm else g1 + e2 * e2) > best:
                            continue
                        key = a0 * s0 + a1 * s1 + a2 * s2
                        pos = slot[key] if use_slot else find_key(keys, key)
                        if pos >= 0:
                            best, best_j = _scan_sorted(
                                points,
                                spts,
                                i,
                                w,
                                limit,
                                starts[pos],
                                starts[pos + 1],
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
