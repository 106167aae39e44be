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
def _gather(
    pts, spts, members, slot, keys, starts, grid, i, w, e_max, ball, cand, cdist, crank, rank
):
    """Admissible points within ``e_max`` of row ``i`` (maximum norm, or Euclidean with
    ``ball``): the members of the 3 × 3 × 3 cells around its cell (cells are at least
    ``e_max`` wide, so no neighbour lies farther), in grid order, with each one's distance
    and ``rank``. The members of a cell are in the order of their first coordinate, so
    only the slab within ``e_max`` of row ``i`` in that coordinate is read. Returns how
    many."""
    gcols, lo, cell, ncell, stride = grid
    m = pts.shape[1]
    g = gcols.size
    # the cell of row i and the grid's shape in scalars (small arrays here were allocated
    # once per reference point)
    x0 = _cell_of(pts[i, gcols[0]], lo[0], cell, ncell[0])
    n0, s0 = ncell[0], stride[0]
    x1, n1, s1 = 0, 1, 0
    x2, n2, s2 = 0, 1, 0
    if g > 1:
        x1 = _cell_of(pts[i, gcols[1]], lo[1], cell, ncell[1])
        n1, s1 = ncell[1], stride[1]
    if g > 2:
        x2 = _cell_of(pts[i, gcols[2]], lo[2], cell, ncell[2])
        n2, s2 = ncell[2], stride[2]
    # a squared distance above this has a root above e_max whatever the rounding
    e2_stop = e_max * e_max * (1.0 + 1e-9)
    # the slab of the first coordinate that can hold a neighbour, padded so that rounding
    # cannot drop one (points in the pad are tested exactly)
    xi = pts[i, 0]
    pad = e_max * (1.0 + 1e-6) + 1e-15 * abs(xi)
    x_lo = xi - pad
    x_hi = xi + pad
    nc = 0
    for c0 in range(max(x0 - 1, 0), min(x0 + 2, n0)):
        for c1 in range(max(x1 - 1, 0), min(x1 + 2, n1)):
            for c2 in range(max(x2 - 1, 0), min(x2 + 2, n2)):
                key = c0 * s0 + c1 * s1 + c2 * s2
                pos = slot[key] if slot.size else find_key(keys, key)
                if pos < 0:
                    continue
                # members are sorted by the first coordinate inside a cell: start at the
                # first one that can lie within e_max of row i, stop past the last one
                first = starts[pos]
                end = starts[pos + 1]
                hi = end
                while first < hi:
                    mid = (first + hi) >> 1
                    if spts[mid, 0] <= x_lo:
                        first = mid + 1
                    else:
                        hi = mid
                for p in range(first, end):
                    if spts[p, 0] >= x_hi:
                        break
                    j = members[p]
                    if abs(i - j) <= w:
                        continue
                    d = 0.0
                    if ball:
                        for c in range(m):
                            diff = spts[p, c] - pts[i, c]
                            d += diff * diff
                            if d > e2_stop:
                                break
                        d = np.sqrt(d)
                    else:
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
    series: np.ndarray,
    lag: int,
    ball: bool,
    squared: bool,
    out: np.ndarray,
    total: np.ndarray,
    count: np.ndarray,
    cand: np.ndarray,
    cdist: np.ndarray,
    crank: np.ndarray,
    expo: np.ndarray,
    prod: np.ndarray,
    run: np.ndarray,
    first: np.ndarray,
    n_first: np.ndarray,
    q0: int,
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
    position of each row when sorted by its first coordinate) is used. With ``ball`` the
    neighbourhood is the Euclidean ball instead of the maximum-norm cube.

    Adds the finite ``S = ln mean_j ‖y_{i+k_q} − y_{j+k_q}‖`` (Euclidean; NaN without
    neighbours or at a zero mean distance) to ``total[e, q]`` and counts them in
    ``count[e, q]`` (in reference order), stores every one in ``out[r, e, q]`` unless
    ``out`` is empty, and returns the neighbours used per (r, e). With ``squared`` the mean
    is that of the squared distances (no root per horizon), and ``S`` is half its log (ln
    of the RMS distance, TISEAN's ``lyap_k``); the sums in ``total`` then hold the logs of
    the means of squares, which the caller halves. With ``transverse`` the
    distance is the part of the separation perpendicular to the local flow direction at
    ``y_{i+k}`` (see ``_kernels.sq_distance``). ``cols`` is ``pts.T`` made contiguous
    (a neighbour's distances at consecutive horizons are read from contiguous memory);
    ``cand``, ``cdist`` and ``crank`` are work buffers of ``members.size`` entries (int64,
    float64, int64), allocated once by the caller. ``series`` is the scalar series the rows
    of ``pts`` are delay vectors of (``pts[t, c] = series[t + c · lag]``), or empty: with
    it the squared difference of each sample pair is computed once and shared by the
    coordinates and horizons it enters (the same sums in the same order).

    The sum over references is taken without a log per term (the terms are ln of a mean
    distance): each mean is split into its binary exponent, summed in ``expo[e, q]``
    (int64), and a mantissa in [1, 2), multiplied into ``prod[e, q]``, whose log is added
    to ``total`` every 512 references (``run[0]`` counts them). The state lives in the
    caller's arrays, so the sums do not depend on how the references are split into
    calls; the caller adds ``ln prod + expo · ln 2`` once after the last call.

    ``first`` (references × w, or 0 × 0 for none) receives, for every reference point with
    a neighbour within the smallest radius, its ``S`` of that radius at the horizons
    ``ks[q0 : q0 + w]``, one row per such point in reference order from row
    ``n_first[0]`` on (which counts them): the values ``out[r, 0, q0 : q0 + w]`` would
    hold, without a pass of their own.
    """
    n_e = eps.size
    nk = ks.size
    e_max = eps[n_e - 1]
    store = out.size > 0
    used = np.zeros((ref.size, n_e), dtype=np.int64)
    acc = np.zeros((n_e, nk))
    row = np.empty(nk)
    sq = np.empty(nk + (pts.shape[1] - 1) * lag)
    sacc = np.empty((n_e, sq.size))
    counts = (
        np.empty(n_e, dtype=np.int64),
        np.empty(n_e, dtype=np.int64),
        np.empty(n_e, dtype=np.int64),
        np.empty(n_e, dtype=np.bool_),
    )
    bits = row.view(np.int64)
    for r in range(ref.size):
        i = ref[r]
        nc = _gather(
            pts,
            spts,
            members,
            slot,
            keys,
            starts,
            grid,
            i,
            w,
            e_max,
            ball,
            cand,
            cdist,
            crank,
            rank,
        )
        capped = nc > max_neighbors
        if capped:
            # a strided subset: taken in slab order, so that it does not depend on the grid
            idx = np.argsort(crank[:nc])
            cand[:nc] = cand[:nc][idx]
            cdist[:nc] = cdist[:nc][idx]
        taken_e = _accumulate(
            pts,
            cols,
            series,
            lag,
            squared,
            i,
            cand,
            cdist,
            nc,
            eps,
            ks,
            max_neighbors,
            capped,
            transverse,
            acc,
            row,
            sq,
            sacc,
            counts,
        )
        for e in range(n_e):
            taken = taken_e[e]
            used[r, e] = taken
            if not store and _add_means(acc[e], taken, row, bits, expo[e], prod[e], count[e]):
                continue
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
                        v = 0.5 * np.log(mean) if squared else np.log(mean)
                if store:
                    out[r, e, q] = v
        if first.shape[0] > 0 and taken_e[0] > 0:
            _keep_first(acc[0], taken_e[0], squared, q0, first[n_first[0]])
            n_first[0] += 1
        run[0] += 1
        if run[0] == LOG_RUN:
            for e in range(n_e):
                for q in range(nk):
                    total[e, q] += np.log(prod[e, q])
                    prod[e, q] = 1.0
            run[0] = 0
    return used


@njit(cache=True)
def _keep_first(acc, taken, squared, q0, dst):
    """``dst[q] = S`` from the sum ``acc[q0 + q]`` over ``taken`` neighbours, as the
    stored ``out`` of :func:`kantz_log_distances` (NaN at a zero sum)."""
    for q in range(dst.size):
        v = np.nan
        if acc[q0 + q] > 0.0:
            mean = acc[q0 + q] / taken
            v = 0.5 * np.log(mean) if squared else np.log(mean)
        dst[q] = v


@njit(cache=True, inline="always")
def _add_means(acc, taken, row, bits, expo, prod, count):
    """The per-reference step of :func:`kantz_log_distances` for one radius when every
    mean distance ``acc / taken`` is a normal number (or no neighbour was taken): each
    mean's binary exponent added to ``expo``, its mantissa multiplied into ``prod``, one
    count more per horizon. The same operations as the general loop, in loops without
    branches that vectorise (the general loop's store and reload of one word per horizon
    kept it scalar: 2.4× the time). Returns False, having changed nothing but ``row``,
    when some mean is zero, subnormal or not finite: the general loop then runs."""
    if taken == 0:
        return True
    nk = row.size
    normal = True
    for q in range(nk):
        mean = acc[q] / taken
        row[q] = mean
        normal &= mean >= TINY
    if not normal:
        return False
    for q in range(nk):
        word = bits[q]
        expo[q] += (word >> 52) - 1023
        bits[q] = (word & MANTISSA) | ONE_BITS
    for q in range(nk):
        prod[q] *= row[q]
        count[q] += 1
    return True


_FUSED_HORIZONS = 64  # consecutive horizons from which the fused distance pass is used


@njit(cache=True, inline="always")
def _add_root_distances(cols, i, j, k0, squared, dst):
    """``dst[q] += ‖y_{i+k0+q} − y_{j+k0+q}‖`` (or its square with ``squared``) for up to
    three coordinates: the squared distance, its root and the addition in one vectorised
    pass (the same arithmetic, in the same order, as building the row of squared distances
    first)."""
    m = cols.shape[0]
    nk = dst.size
    a0 = cols[0][i + k0 : i + k0 + nk]
    b0 = cols[0][j + k0 : j + k0 + nk]
    if m == 1:
        for q in range(nk):
            diff = b0[q] - a0[q]
            dst[q] += diff * diff if squared else np.sqrt(diff * diff)
        return
    a1 = cols[1][i + k0 : i + k0 + nk]
    b1 = cols[1][j + k0 : j + k0 + nk]
    if m == 2:
        if squared:
            for q in range(nk):
                d0 = b0[q] - a0[q]
                d1 = b1[q] - a1[q]
                dst[q] += d0 * d0 + d1 * d1
        else:
            for q in range(nk):
                d0 = b0[q] - a0[q]
                d1 = b1[q] - a1[q]
                dst[q] += np.sqrt(d0 * d0 + d1 * d1)
        return
    a2 = cols[2][i + k0 : i + k0 + nk]
    b2 = cols[2][j + k0 : j + k0 + nk]
    if squared:
        for q in range(nk):
            d0 = b0[q] - a0[q]
            d1 = b1[q] - a1[q]
            d2 = b2[q] - a2[q]
            dst[q] += d0 * d0 + d1 * d1 + d2 * d2
    else:
        for q in range(nk):
            d0 = b0[q] - a0[q]
            d1 = b1[q] - a1[q]
            d2 = b2[q] - a2[q]
            dst[q] += np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)


@njit(cache=True, inline="always")
def _delay_squares(series, lag, m, a0, b0, nk, sq):
    """``sq[t] = (series[b0 + t] − series[a0 + t])²`` for every sample the coordinates of
    ``nk`` consecutive delay vectors read (``nk + (m − 1) · lag``)."""
    span = nk + (m - 1) * lag
    a = series[a0 : a0 + span]
    b = series[b0 : b0 + span]
    for t in range(span):
        diff = b[t] - a[t]
        sq[t] = diff * diff


@njit(cache=True, inline="always")
def _add_delay_distances(sq, lag, m, squared, dst):
    """``dst[q] += ‖·‖`` (or ``‖·‖²`` with ``squared``) of the delay vectors whose squared
    coordinate differences ``sq`` holds: coordinate ``c`` of horizon ``q`` is
    ``sq[q + c · lag]``, summed in coordinate order as the row-wise pass does."""
    nk = dst.size
    # one loop per case, the branches outside: a select inside the loop kept it scalar
    if m == 2:
        if squared:
            for q in range(nk):
                dst[q] += sq[q] + sq[q + lag]
        else:
            for q in range(nk):
                dst[q] += np.sqrt(sq[q] + sq[q + lag])
    elif m == 3:
        if squared:
            for q in range(nk):
                dst[q] += sq[q] + sq[q + lag] + sq[q + 2 * lag]
        else:
            for q in range(nk):
                dst[q] += np.sqrt(sq[q] + sq[q + lag] + sq[q + 2 * lag])
    else:
        for q in range(nk):
            v = sq[q]
            for c in range(1, m):
                v += sq[q + c * lag]
            dst[q] += v if squared else np.sqrt(v)


@njit(cache=True)
def _linear_shells(series, i0, cand, cdist, nc, eps, k0, sacc, taken_e):
    """The squared sample differences of each neighbour added to its shell's row of
    ``sacc`` (uncapped RMS pass of :func:`_accumulate` on a delay embedding), in
    candidate order, and counted per shell."""
    span = sacc.shape[1]
    a = series[i0 : i0 + span]
    for t in range(nc):
        shell = 0
        while cdist[t] >= eps[shell]:
            shell += 1
        b0 = cand[t] + k0
        b = series[b0 : b0 + span]
        dst = sacc[shell]
        for u in range(span):
            diff = b[u] - a[u]
            dst[u] += diff * diff
        taken_e[shell] += 1


@njit(cache=True)
def _fused_shells(cols, i, cand, cdist, nc, eps, k0, squared, acc, taken_e):
    """Each neighbour's curve (:func:`_add_root_distances`) added to its shell's row of
    ``acc``, in candidate order, and counted per shell (uncapped fused pass)."""
    for t in range(nc):
        shell = 0
        while cdist[t] >= eps[shell]:
            shell += 1
        _add_root_distances(cols, i, cand[t], k0, squared, acc[shell])
        taken_e[shell] += 1


@njit(cache=True)
def _delay_shells(series, lag, m, squared, i0, cand, cdist, nc, eps, k0, acc, taken_e, sq):
    """The uncapped delay pass of :func:`_accumulate` on its own: each neighbour's curve
    (from the squared sample differences, :func:`_delay_squares`) added to the row of its
    shell, in candidate order, and counted per shell. A kernel of its own: inside
    :func:`_accumulate` the same loop cost about 20 ns more per neighbour (Hénon)."""
    nk = acc.shape[1]
    for t in range(nc):
        shell = 0
        while cdist[t] >= eps[shell]:
            shell += 1
        _delay_squares(series, lag, m, i0, cand[t] + k0, nk, sq)
        _add_delay_distances(sq, lag, m, squared, acc[shell])
        taken_e[shell] += 1


@njit(cache=True)
def _accumulate(
    pts,
    cols,
    series,
    lag,
    squared,
    i,
    cand,
    cdist,
    nc,
    eps,
    ks,
    max_neighbors,
    capped,
    transverse,
    acc,
    row,
    sq,
    sacc,
    counts,
):
    """Sum of the distance curves (or squared-distance curves with ``squared``) of the
    neighbours of ``i`` taken for each radius (``acc[e, q]``); returns how many were taken
    per radius.

    Each neighbour's curve is computed once. Without a cap it is added to the shell
    ``eps[e−1] <= d < eps[e]`` it lies in, and the sums of the nested radii are the running
    sums over the shells. With a cap (``capped``: more than ``max_neighbors`` candidates,
    given in slab order) every radius takes an evenly strided subset of its own neighbours
    and the curve is added to each radius that takes it. ``counts``: four work arrays of
    one entry per radius (int64 × 3, bool), allocated once per call of the kernel; the
    third (neighbours taken per radius) is returned.

    Squared distances of a delay embedding without a cap are linear in the squared sample
    differences: those are summed per shell (``sacc``, one row of ``nk + (m − 1) · lag``
    per radius) and combined over the coordinates once per reference point, not per
    neighbour (the same sums in another order).
    """
    n_e = eps.size
    nk = ks.size
    m = pts.shape[1]
    unit = True
    for q in range(1, nk):
        if ks[q] != ks[q - 1] + 1:
            unit = False
    # consecutive horizons of a delay embedding: each squared sample difference once
    delay = unit and not transverse and series.size > 0
    linear = delay and squared and not capped
    if linear:
        sacc[:, :] = 0.0
    # long curves of at most three coordinates: the squared distance, its root and the
    # addition in one pass over the coordinates (measured: Lorenz, 201 horizons, 20 % less
    # time than the row-wise pass, 30 % less than the delay pass; on Hénon's 21 horizons
    # the delay pass is the fastest)
    fused = unit and not transverse and m <= 3 and nk >= _FUSED_HORIZONS
    stride_e, seen_e, taken_e, take_e = counts
    stride_e[:] = 1
    seen_e[:] = 0
    taken_e[:] = 0
    take_e[:] = False
    if capped:
        for e in range(n_e):
            cnt = 0
            for t in range(nc):
                if cdist[t] < eps[e]:
                    cnt += 1
            stride_e[e] = (cnt + max_neighbors - 1) // max_neighbors if cnt else 1
    acc[:, :] = 0.0
    # uncapped passes of consecutive horizons: each neighbour to its shell, in a kernel of
    # its own (inside this one the same loops cost about 20 ns more per neighbour)
    if linear:
        _linear_shells(series, i + ks[0], cand, cdist, nc, eps, ks[0], sacc, taken_e)
        nc = 0  # every neighbour is in: the shells' running sums below
    elif fused and not capped:
        _fused_shells(cols, i, cand, cdist, nc, eps, ks[0], squared, acc, taken_e)
        nc = 0
    elif delay and not capped:
        _delay_shells(
            series, lag, m, squared, i + ks[0], cand, cdist, nc, eps, ks[0], acc, taken_e, sq
        )
        nc = 0
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
        if delay:  # capped: the uncapped delay pass is _delay_shells
            _delay_squares(series, lag, m, i + ks[0], j + ks[0], nk, sq)
            row[:] = 0.0
            _add_delay_distances(sq, lag, m, squared, row)
        elif transverse:
            # (written out here: as a separate function it compiles to slower code)
            for q in range(nk):
                v = sq_distance(pts, i + ks[q], j + ks[q], True)
                row[q] = v if squared else np.sqrt(v)
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
            if not squared:
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
    if linear:
        for e in range(n_e):
            if e > 0:
                taken_e[e] += taken_e[e - 1]
                for u in range(sacc.shape[1]):
                    sacc[e, u] += sacc[e - 1, u]
            _add_delay_distances(sacc[e], lag, m, True, acc[e])
    elif not capped:
        for e in range(1, n_e):
            taken_e[e] += taken_e[e - 1]
            for q in range(nk):
                acc[e, q] += acc[e - 1, q]
    return taken_e
