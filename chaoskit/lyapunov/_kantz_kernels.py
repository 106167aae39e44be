"""Compiled kernel of Kantz's neighbourhood-averaged divergence (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit

from .._neighbors_kernels import find_key
from ._kernels import LOG_RUN, MANTISSA, ONE_BITS, TINY, sq_distance


@njit(cache=True, inline="always")
def _cell_of(v, lo, cell, ncell):
    return min(max(int(np.floor((v - lo) / cell)), 0), ncell - 1)


@njit(cache=True)
def _gather(pts, spts, members, slot, keys, starts, grid, i, w, e_max, cand, cdist, crank, rank):
    """Admissible points within ``e_max`` (maximum norm) of row ``i``: the members of the
    3 × 3 × 3 cells around its cell (cells are at least ``e_max`` wide, so no neighbour lies
    farther), in grid order, with each one's distance and ``rank``. Returns how many."""
    gcols, lo, cell, ncell, stride = grid
    m = pts.shape[1]
    g = gcols.size
    cen = np.zeros(3, dtype=np.int64)
    ncl = np.ones(3, dtype=np.int64)
    strd = np.zeros(3, dtype=np.int64)
    for d in range(g):
        cen[d] = _cell_of(pts[i, gcols[d]], lo[d], cell, ncell[d])
        ncl[d] = ncell[d]
        strd[d] = stride[d]
    nc = 0
    for c0 in range(max(cen[0] - 1, 0), min(cen[0] + 2, ncl[0])):
        for c1 in range(max(cen[1] - 1, 0), min(cen[1] + 2, ncl[1])):
            for c2 in range(max(cen[2] - 1, 0), min(cen[2] + 2, ncl[2])):
                key = c0 * strd[0] + c1 * strd[1] + c2 * strd[2]
                pos = slot[key] if slot.size else find_key(keys, key)
                if pos < 0:
                    continue
                for p in range(starts[pos], starts[pos + 1]):
                    j = members[p]
                    if abs(i - j) <= w:
                        continue
                    d = 0.0
                    for c in range(m):
                        diff = abs(spts[p, c] - pts[i, c])
                        if diff > d:
                            d = diff
                            if d >= e_max:
                                break
                    if d < e_max:
                        cand[nc] = j
                        cdist[nc] = d
                        crank[nc] = rank[j]
                        nc += 1
    return nc


@njit(cache=True)
def kantz_log_distances(
    pts: np.ndarray,
    cols: np.ndarray,
    spts: np.ndarray,
    members: np.ndarray,
    rank: np.ndarray,
    slot: np.ndarray,
    keys: np.ndarray,
    starts: np.ndarray,
    grid: tuple,
    ref: np.ndarray,
    w: int,
    eps: np.ndarray,
    ks: np.ndarray,
    max_neighbors: int,
    transverse: bool,
    out: np.ndarray,
    total: np.ndarray,
    count: np.ndarray,
    cand: np.ndarray,
    cdist: np.ndarray,
    crank: np.ndarray,
    expo: np.ndarray,
    prod: np.ndarray,
    run: np.ndarray,
) -> np.ndarray:
    """Per reference point, ln of the mean distance to its ε-neighbours after k samples.

    Neighbours are found box-assisted (TISEAN's search): the candidate rows are bucketed on
    a grid of cells at least ``max(eps)`` wide over up to three coordinates (``grid`` =
    ``(coordinates, lower corner, cell edge, cells per coordinate, strides)``; ``members``
    the rows sorted by cell, ``spts`` their coordinates in that order, ``keys``/``starts``
    each occupied cell and the offset of its first member, ``slot`` the position of every
    cell id in ``keys`` or empty to bisect ``keys``), and only the 3^g cells around a
    reference point's cell are read. A neighbour ``j`` of reference ``i`` has
    ``|i − j| > w`` and a maximum-norm distance below ``eps[e]``; when more than
    ``max_neighbors`` qualify, an evenly strided subset of them in slab order (``rank``:
    position of each row when sorted by its first coordinate) is used.

    Adds the finite ``S = ln mean_j ‖y_{i+k_q} − y_{j+k_q}‖`` (Euclidean; NaN without
    neighbours or at a zero mean distance) to ``total[e, q]`` and counts them in
    ``count[e, q]`` (in reference order), stores every one in ``out[r, e, q]`` unless
    ``out`` is empty, and returns the neighbours used per (r, e). With ``transverse`` the
    distance is the part of the separation perpendicular to the local flow direction at
    ``y_{i+k}`` (see ``_kernels.sq_distance``). ``cols`` is ``pts.T`` made contiguous
    (a neighbour's distances at consecutive horizons are read from contiguous memory);
    ``cand``, ``cdist`` and ``crank`` are work buffers of ``members.size`` entries (int64,
    float64, int64), allocated once by the caller.

    The sum over references is taken without a log per term (the terms are ln of a mean
    distance): each mean is split into its binary exponent, summed in ``expo[e, q]``
    (int64), and a mantissa in [1, 2), multiplied into ``prod[e, q]``, whose log is added
    to ``total`` every 512 references (``run[0]`` counts them). The state lives in the
    caller's arrays, so the sums do not depend on how the references are split into
    calls; the caller adds ``ln prod + expo · ln 2`` once after the last call.
    """
    n_e = eps.size
    nk = ks.size
    e_max = eps[n_e - 1]
    store = out.size > 0
    used = np.zeros((ref.size, n_e), dtype=np.int64)
    acc = np.zeros((n_e, nk))
    row = np.empty(nk)
    bits = row.view(np.int64)
    for r in range(ref.size):
        i = ref[r]
        nc = _gather(
            pts, spts, members, slot, keys, starts, grid, i, w, e_max, cand, cdist, crank, rank
        )
        capped = nc > max_neighbors
        if capped:
            # a strided subset: taken in slab order, so that it does not depend on the grid
            idx = np.argsort(crank[:nc])
            cand[:nc] = cand[:nc][idx]
            cdist[:nc] = cdist[:nc][idx]
        taken_e = _accumulate(
            pts, cols, i, cand, cdist, nc, eps, ks, max_neighbors, capped, transverse, acc, row
        )
        for e in range(n_e):
            taken = taken_e[e]
            used[r, e] = taken
            for q in range(nk):
                v = np.nan
                if taken > 0 and acc[e, q] > 0.0:
                    mean = acc[e, q] / taken
                    if mean >= TINY:
                        row[0] = mean
                        word = bits[0]
                        expo[e, q] += (word >> 52) - 1023
                        bits[0] = (word & MANTISSA) | ONE_BITS
                        prod[e, q] *= row[0]
                    else:  # subnormal: its own log
                        total[e, q] += np.log(mean)
                    count[e, q] += 1
                    if store:
                        v = np.log(mean)
                if store:
                    out[r, e, q] = v
        run[0] += 1
        if run[0] == LOG_RUN:
            for e in range(n_e):
                for q in range(nk):
                    total[e, q] += np.log(prod[e, q])
                    prod[e, q] = 1.0
            run[0] = 0
    return used


_FUSED_HORIZONS = 64  # consecutive horizons from which the fused distance pass is used


@njit(cache=True, inline="always")
def _add_root_distances(cols, i, j, k0, dst):
    """``dst[q] += ‖y_{i+k0+q} − y_{j+k0+q}‖`` for up to three coordinates: the squared
    distance, its root and the addition in one vectorised pass (the same arithmetic, in
    the same order, as building the row of squared distances first)."""
    m = cols.shape[0]
    nk = dst.size
    a0 = cols[0][i + k0 : i + k0 + nk]
    b0 = cols[0][j + k0 : j + k0 + nk]
    if m == 1:
        for q in range(nk):
            diff = b0[q] - a0[q]
            dst[q] += np.sqrt(diff * diff)
        return
    a1 = cols[1][i + k0 : i + k0 + nk]
    b1 = cols[1][j + k0 : j + k0 + nk]
    if m == 2:
        for q in range(nk):
            d0 = b0[q] - a0[q]
            d1 = b1[q] - a1[q]
            dst[q] += np.sqrt(d0 * d0 + d1 * d1)
        return
    a2 = cols[2][i + k0 : i + k0 + nk]
    b2 = cols[2][j + k0 : j + k0 + nk]
    for q in range(nk):
        d0 = b0[q] - a0[q]
        d1 = b1[q] - a1[q]
        d2 = b2[q] - a2[q]
        dst[q] += np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@njit(cache=True)
def _accumulate(
    pts, cols, i, cand, cdist, nc, eps, ks, max_neighbors, capped, transverse, acc, row
):
    """Sum of the distance curves of the neighbours of ``i`` taken for each radius
    (``acc[e, q]``); returns how many were taken per radius.

    Each neighbour's curve is computed once. Without a cap it is added to the shell
    ``eps[e−1] <= d < eps[e]`` it lies in, and the sums of the nested radii are the running
    sums over the shells. With a cap (``capped``: more than ``max_neighbors`` candidates,
    given in slab order) every radius takes an evenly strided subset of its own neighbours
    and the curve is added to each radius that takes it.
    """
    n_e = eps.size
    nk = ks.size
    m = pts.shape[1]
    unit = True
    for q in range(1, nk):
        if ks[q] != ks[q - 1] + 1:
            unit = False
    # the fused pass pays on long curves only (measured: Lorenz, 201 horizons, 20 % less
    # time; Hénon, 21 horizons, 70 % more)
    fused = unit and not transverse and m <= 3 and nk >= _FUSED_HORIZONS
    stride_e = np.ones(n_e, dtype=np.int64)
    seen_e = np.zeros(n_e, dtype=np.int64)
    taken_e = np.zeros(n_e, dtype=np.int64)
    take_e = np.zeros(n_e, dtype=np.bool_)
    if capped:
        for e in range(n_e):
            cnt = 0
            for t in range(nc):
                if cdist[t] < eps[e]:
                    cnt += 1
            stride_e[e] = (cnt + max_neighbors - 1) // max_neighbors if cnt else 1
    acc[:, :] = 0.0
    for t in range(nc):
        shell = 0
        if capped:
            any_ = False
            for e in range(n_e):
                take_e[e] = False
                if cdist[t] < eps[e]:
                    take_e[e] = seen_e[e] % stride_e[e] == 0
                    seen_e[e] += 1
                    any_ = any_ or take_e[e]
            if not any_:
                continue
        else:
            while cdist[t] >= eps[shell]:
                shell += 1
        j = cand[t]
        if fused and not capped:
            _add_root_distances(cols, i, j, ks[0], acc[shell])
            taken_e[shell] += 1
            continue
        # (written out here: as a separate function it compiles to slower code)
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
        if capped:
            for e in range(n_e):
                if take_e[e]:
                    taken_e[e] += 1
                    for q in range(nk):
                        acc[e, q] += row[q]
        else:
            taken_e[shell] += 1
            for q in range(nk):
                acc[shell, q] += row[q]
    if not capped:
        for e in range(1, n_e):
            taken_e[e] += taken_e[e - 1]
            for q in range(nk):
                acc[e, q] += acc[e - 1, q]
    return taken_e
