"""Compiled kernels for the Lyapunov estimators (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit

from .._neighbors_kernels import find_key


@njit(cache=True, inline="always")
def _row_sq_distance(a: np.ndarray, i: int, b: np.ndarray, j: int) -> float:
    """‖a_i − b_j‖² over the columns of ``a``."""
    d2 = 0.0
    for c in range(a.shape[1]):
        diff = a[i, c] - b[j, c]
        d2 += diff * diff
    return d2


@njit(cache=True)
def sq_distance(pts: np.ndarray, i: int, j: int, transverse: bool) -> float:
    """‖y_j − y_i‖², or of its part perpendicular to the local flow direction at y_i.

    The flow direction is the central difference y_{i+1} − y_{i−1} (one-sided at the ends).
    """
    n, m = pts.shape
    lo = i - 1 if i > 0 else i
    hi = i + 1 if i + 1 < n else i
    d2 = 0.0
    dv = 0.0
    v2 = 0.0
    for c in range(m):
        diff = pts[j, c] - pts[i, c]
        d2 += diff * diff
        if transverse:
            vel = pts[hi, c] - pts[lo, c]
            dv += diff * vel
            v2 += vel * vel
    if transverse and v2 > 0.0:
        d2 -= dv * dv / v2
    return d2 if d2 > 0.0 else 0.0


# distance modes of the divergence kernels
EUCLIDEAN = 0  # ‖y_{j+k} − y_{i+k}‖ to the neighbour sample
TRANSVERSE = 1  # its part perpendicular to the local flow direction at y_{i+k}
ORBIT = 2  # to the neighbour's orbit point shifted by a fraction of a sample
SAMPLE_ORBIT = 3  # geometric mean of EUCLIDEAN and ORBIT


@njit(cache=True)
def orbit_sq_distance(pts: np.ndarray, i: int, j: int, s: float) -> float:
    """‖y(j + s) − y_i‖² with y(j + s) quadratic through y_{j−1}, y_j, y_{j+1} (|s| ≤ 1)."""
    m = pts.shape[1]
    d2 = 0.0
    for c in range(m):
        yj = pts[j, c]
        if s != 0.0:
            vel = 0.5 * (pts[j + 1, c] - pts[j - 1, c])
            acc = pts[j + 1, c] - 2.0 * yj + pts[j - 1, c]
            yj = yj + s * vel + 0.5 * s * s * acc
        diff = yj - pts[i, c]
        d2 += diff * diff
    return d2


@njit(cache=True)
def _pair_sq(pts: np.ndarray, i: int, j: int, s: float, mode: int) -> float:
    """Squared distance of the pair (i, j) in ``mode``; for SAMPLE_ORBIT the geometric mean
    of the two squared distances, so that ½ ln of it is the mean of the two log distances."""
    if mode == TRANSVERSE:
        return sq_distance(pts, i, j, True)
    if mode == ORBIT:
        return orbit_sq_distance(pts, i, j, s)
    d2 = sq_distance(pts, i, j, False)
    if mode == SAMPLE_ORBIT:
        return np.sqrt(d2 * orbit_sq_distance(pts, i, j, s))
    return d2


@njit(cache=True)
def _log_distance(pts: np.ndarray, i: int, j: int, transverse: bool) -> float:
    """ln of the distance of :func:`sq_distance`; −inf for a zero distance."""
    d2 = sq_distance(pts, i, j, transverse)
    if d2 <= 0.0:
        return -np.inf
    return 0.5 * np.log(d2)


@njit(cache=True)
def orbit_shifts(pts: np.ndarray, ref: np.ndarray, nbr: np.ndarray) -> np.ndarray:
    """Fractional sample shift s of each neighbour to the point of its orbit closest to y_i.

    Minimises ‖y(j + s) − y_i‖ with y(j + s) = y_j + s v + s²/2 a (central differences
    v, a through y_{j−1}, y_j, y_{j+1}) by a few Newton steps from s = 0, clipped to
    [−1, 1]; 0 at the ends of the data. A sampled flow leaves each nearest neighbour up to
    half a sampling step *along* the flow from the closest point of its orbit.
    """
    n, m = pts.shape
    out = np.zeros(ref.size)
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        if j < 1 or j + 1 >= n:
            continue
        s = 0.0
        for _ in range(4):
            grad = 0.0
            curv = 0.0
            for c in range(m):
                vel = 0.5 * (pts[j + 1, c] - pts[j - 1, c])
                acc = pts[j + 1, c] - 2.0 * pts[j, c] + pts[j - 1, c]
                r = pts[j, c] + s * vel + 0.5 * s * s * acc - pts[i, c]
                dr = vel + s * acc
                grad += r * dr
                curv += dr * dr + r * acc
            if curv <= 0.0:
                break
            s = min(1.0, max(-1.0, s - grad / curv))
        out[p] = s
    return out


TINY = 2.2250738585072014e-308  # smallest normal float64
MANTISSA = 0xFFFFFFFFFFFFF
ONE_BITS = 1023 << 52
LOG_RUN = 512  # products of at most this many mantissas in [1, 2) stay below 2^512


@njit(cache=True)
def phase_columns(pts: np.ndarray, step: int) -> np.ndarray:
    """The coordinates split by the phase of the sample index modulo ``step``:
    ``out[r, c, u] = pts[r + step·u, c]`` (zero past the end), so that the samples of a
    horizon grid on that step are contiguous in ``u``."""
    n, m = pts.shape
    size = (n + step - 1) // step
    out = np.zeros((step, m, size))
    for t in range(n):
        r = t % step
        u = t // step
        for c in range(m):
            out[r, c, u] = pts[t, c]
    return out


@njit(cache=True)
def _euclidean_log_divergence(pts, ref, nbr, ks, orbit, shift):
    """:func:`log_divergence` for the EUCLIDEAN and ORBIT modes, vectorised over horizons.

    The leading horizons on one uniform step read the coordinates split by phase
    (:func:`phase_columns`), so a pair's samples at consecutive horizons are contiguous for
    any step (a strided read does not vectorise; building the whole span and keeping every
    step-th costs ``step`` times the arithmetic); the horizons after that run are gathered
    one by one. The squared distances are summed over the coordinates in order, as the
    scalar path does, and each is split into its binary exponent and a mantissa in [1, 2)
    by its bits (exact): the exponents are summed as integers and the mantissas
    multiplied, one log per horizon every 512 pairs. Subnormal distances (below 2.2e-308)
    take the slow path.
    """
    n, m = pts.shape
    cols = np.ascontiguousarray(pts.T)
    nk = ks.size
    step = ks[1] - ks[0] if nk > 1 else 1
    # leading horizons on one uniform step: contiguous in the phase-split coordinates
    uni = 1
    while uni < nk and ks[uni] == ks[0] + uni * step:
        uni += 1
    phases = phase_columns(pts, step)
    total = np.zeros(nk)
    count = np.zeros(nk, dtype=np.int64)
    expo = np.zeros(nk, dtype=np.int64)
    prod = np.ones(nk)
    buf = np.empty(nk)
    bits = buf.view(np.int64)
    run = 0
    edge = 1 if orbit else 0  # the interpolated neighbour needs y_{j+k+1}
    k0 = ks[0]
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        lim = nk
        while lim > 0 and (i + ks[lim - 1] >= n or j + ks[lim - 1] + edge >= n):
            lim -= 1
        # Lagrange weights of y_{j−1}, y_j, y_{j+1} for the orbit point y(j + s)
        s = shift[p] if orbit else 0.0
        w_prev = 0.5 * s * (s - 1.0)
        w_here = 1.0 - s * s
        w_next = 0.5 * s * (s + 1.0)
        head = min(lim, uni) if (j + k0 >= 1 or not orbit) else 0
        buf[:lim] = 0.0
        ra, ua = (i + k0) % step, (i + k0) // step
        rb, ub = (j + k0) % step, (j + k0) // step
        for c in range(m):
            col = cols[c]
            a = phases[ra, c, ua : ua + head]
            if orbit:
                r0, u0 = (j + k0 - 1) % step, (j + k0 - 1) // step
                r2, u2 = (j + k0 + 1) % step, (j + k0 + 1) // step
                b0 = phases[r0, c, u0 : u0 + head]
                b1 = phases[rb, c, ub : ub + head]
                b2 = phases[r2, c, u2 : u2 + head]
                for t in range(head):
                    diff = w_prev * b0[t] + w_here * b1[t] + w_next * b2[t] - a[t]
                    buf[t] += diff * diff
                for q in range(head, lim):
                    jk = j + ks[q]
                    jp = max(jk - 1, 0)  # weight 0 when s = 0
                    diff = w_prev * col[jp] + w_here * col[jk] + w_next * col[jk + 1]
                    diff -= col[i + ks[q]]
                    buf[q] += diff * diff
            else:
                b = phases[rb, c, ub : ub + head]
                for t in range(head):
                    diff = b[t] - a[t]
                    buf[t] += diff * diff
                for q in range(head, lim):
                    diff = col[j + ks[q]] - col[i + ks[q]]
                    buf[q] += diff * diff
        odd = 0
        for q in range(lim):
            d2 = buf[q]
            ok = d2 >= TINY
            odd += 1 if (d2 > 0.0 and not ok) else 0
            word = bits[q]
            expo[q] += ((word >> 52) - 1023) if ok else 0
            count[q] += 1 if ok else 0
            bits[q] = (word & MANTISSA) | ONE_BITS
            prod[q] *= buf[q] if ok else 1.0
        if odd:
            for q in range(lim):
                if orbit:
                    d2 = orbit_sq_distance(pts, i + ks[q], j + ks[q], s)
                else:
                    d2 = _row_sq_distance(pts, j + ks[q], pts, i + ks[q])
                if 0.0 < d2 < TINY:
                    total[q] += 0.5 * np.log(d2)
                    count[q] += 1
        run += 1
        if run == LOG_RUN:
            for q in range(nk):
                total[q] += 0.5 * np.log(prod[q])
                prod[q] = 1.0
            run = 0
    ln2 = np.log(2.0)
    for q in range(nk):
        total[q] += 0.5 * (np.log(prod[q]) + expo[q] * ln2)
    return total, count


@njit(cache=True, inline="always")
def _split(buf, bits, lim, expo, count, prod):
    """Split the squared distances ``buf[:lim]`` into exponents (summed in ``expo``) and
    mantissas (multiplied into ``prod``), counting them; returns how many are subnormal
    (those take the slow path)."""
    odd = 0
    for q in range(lim):
        d2 = buf[q]
        ok = d2 >= TINY
        odd += 1 if (d2 > 0.0 and not ok) else 0
        word = bits[q]
        expo[q] += ((word >> 52) - 1023) if ok else 0
        count[q] += 1 if ok else 0
        bits[q] = (word & MANTISSA) | ONE_BITS
        prod[q] *= buf[q] if ok else 1.0
    return odd


@njit(cache=True)
def sample_orbit_log_divergence(pts, ref, nbr, ks, shift):
    """The EUCLIDEAN and ORBIT results of :func:`log_divergence` in one pass over the pairs
    (rows 0 and 1 of the returned sums and counts): a pair's samples are read once for
    both, and each curve's arithmetic is that of its own pass (the same sums, bit for
    bit)."""
    n, m = pts.shape
    nk = ks.size
    step = ks[1] - ks[0] if nk > 1 else 1
    uni = 1
    while uni < nk and ks[uni] == ks[0] + uni * step:
        uni += 1
    cols = np.ascontiguousarray(pts.T)
    phases = phase_columns(pts, step)
    total = np.zeros((2, nk))
    count = np.zeros((2, nk), dtype=np.int64)
    expo = np.zeros((2, nk), dtype=np.int64)
    prod = np.ones((2, nk))
    tot_s, tot_o = total[0], total[1]
    cnt_s, cnt_o = count[0], count[1]
    exp_s, exp_o = expo[0], expo[1]
    prod_s, prod_o = prod[0], prod[1]
    buf_s = np.empty(nk)
    bits_s = buf_s.view(np.int64)
    buf_o = np.empty(nk)
    bits_o = buf_o.view(np.int64)
    run = 0
    k0 = ks[0]
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        lim_s = nk
        while lim_s > 0 and (i + ks[lim_s - 1] >= n or j + ks[lim_s - 1] >= n):
            lim_s -= 1
        lim_o = lim_s
        while lim_o > 0 and j + ks[lim_o - 1] + 1 >= n:
            lim_o -= 1
        s = shift[p]
        w_prev = 0.5 * s * (s - 1.0)
        w_here = 1.0 - s * s
        w_next = 0.5 * s * (s + 1.0)
        head_s = min(lim_s, uni)
        head_o = min(lim_o, uni) if j + k0 >= 1 else 0
        buf_s[:lim_s] = 0.0
        buf_o[:lim_o] = 0.0
        ra, ua = (i + k0) % step, (i + k0) // step
        rb, ub = (j + k0) % step, (j + k0) // step
        r0, u0 = (j + k0 - 1) % step, (j + k0 - 1) // step
        r2, u2 = (j + k0 + 1) % step, (j + k0 + 1) // step
        both_head = min(head_s, head_o)
        for c in range(m):
            col = cols[c]
            a = phases[ra, c, ua : ua + head_s]
            b1 = phases[rb, c, ub : ub + head_s]
            b0 = phases[r0, c, u0 : u0 + both_head]
            b2 = phases[r2, c, u2 : u2 + both_head]
            for t in range(both_head):
                at = a[t]
                bt = b1[t]
                diff = bt - at
                buf_s[t] += diff * diff
                diff = w_prev * b0[t] + w_here * bt + w_next * b2[t] - at
                buf_o[t] += diff * diff
            for t in range(both_head, head_s):
                diff = b1[t] - a[t]
                buf_s[t] += diff * diff
            for q in range(head_s, lim_s):
                diff = col[j + ks[q]] - col[i + ks[q]]
                buf_s[q] += diff * diff
            for q in range(both_head, lim_o):
                jk = j + ks[q]
                jp = max(jk - 1, 0)
                diff = w_prev * col[jp] + w_here * col[jk] + w_next * col[jk + 1]
                diff -= col[i + ks[q]]
                buf_o[q] += diff * diff
        odd = _split(buf_s, bits_s, lim_s, exp_s, cnt_s, prod_s)
        if odd:
            for q in range(lim_s):
                d2 = _row_sq_distance(pts, j + ks[q], pts, i + ks[q])
                if 0.0 < d2 < TINY:
                    tot_s[q] += 0.5 * np.log(d2)
                    cnt_s[q] += 1
        odd = _split(buf_o, bits_o, lim_o, exp_o, cnt_o, prod_o)
        if odd:
            for q in range(lim_o):
                d2 = orbit_sq_distance(pts, i + ks[q], j + ks[q], s)
                if 0.0 < d2 < TINY:
                    tot_o[q] += 0.5 * np.log(d2)
                    cnt_o[q] += 1
        run += 1
        if run == LOG_RUN:
            for q in range(nk):
                tot_s[q] += 0.5 * np.log(prod_s[q])
                prod_s[q] = 1.0
                tot_o[q] += 0.5 * np.log(prod_o[q])
                prod_o[q] = 1.0
            run = 0
    ln2 = np.log(2.0)
    for q in range(nk):
        tot_s[q] += 0.5 * (np.log(prod_s[q]) + exp_s[q] * ln2)
        tot_o[q] += 0.5 * (np.log(prod_o[q]) + exp_o[q] * ln2)
    return total, count


@njit(cache=True)
def log_divergence(
    pts: np.ndarray,
    ref: np.ndarray,
    nbr: np.ndarray,
    ks: np.ndarray,
    mode: int,
    shift: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Σ ln d_k over pairs and the number of terms, for each k in ``ks`` (distance ``mode``).

    ``ks`` is increasing; ``shift`` holds each neighbour's orbit shift (ORBIT modes). Pairs
    leaving the data or at zero distance are skipped at that k. The logarithm dominates the
    cost, so squared distances are multiplied together until the product would leave
    [1e-200, 1e200], and one log is taken per such run: ln a + ln b = ln ab (each product
    carries a relative rounding error of at most one unit in the last place per factor, so
    a sum over N pairs moves by less than N · 1e-16 in absolute terms).
    """
    if mode == EUCLIDEAN or mode == ORBIT:
        return _euclidean_log_divergence(pts, ref, nbr, ks, mode == ORBIT, shift)
    n, m = pts.shape
    edge = 1 if mode >= ORBIT else 0  # the interpolated neighbour needs y_{j+k+1}
    total = np.zeros(ks.size)
    count = np.zeros(ks.size, dtype=np.int64)
    prod = np.ones(ks.size)
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        # Lagrange weights of y_{j−1}, y_j, y_{j+1} for the orbit point y(j + s)
        s = shift[p]
        w_prev = 0.5 * s * (s - 1.0)
        w_here = 1.0 - s * s
        w_next = 0.5 * s * (s + 1.0)
        for q in range(ks.size):
            k = ks[q]
            if i + k >= n or j + k + edge >= n:
                break
            if mode == EUCLIDEAN:
                d2 = _row_sq_distance(pts, j + k, pts, i + k)
            elif mode == ORBIT:
                d2 = 0.0
                jp = max(j + k - 1, 0)  # weight 0 when s = 0
                for c in range(m):
                    y = w_prev * pts[jp, c] + w_here * pts[j + k, c] + w_next * pts[j + k + 1, c]
                    diff = y - pts[i + k, c]
                    d2 += diff * diff
            else:
                d2 = _pair_sq(pts, i + k, j + k, shift[p], mode)
            if d2 > 0.0:
                pr = prod[q] * d2
                if pr < 1e-200 or pr > 1e200:
                    total[q] += 0.5 * np.log(prod[q])
                    pr = d2
                prod[q] = pr
                count[q] += 1
    for q in range(ks.size):
        total[q] += 0.5 * np.log(prod[q])
    return total, count


@njit(cache=True)
def _euclidean_pair_slopes(pts, ref, nbr, ks, kbar, sxx):
    """:func:`pair_slopes` for the Euclidean distance, coordinates transposed."""
    n, m = pts.shape
    cols = np.ascontiguousarray(pts.T)
    nk = ks.size
    slope = np.zeros(ref.size)
    valid = np.zeros(ref.size, dtype=np.bool_)
    weight = np.empty(nk)
    for q in range(nk):
        weight[q] = 0.5 * (ks[q] - kbar)
    last = ks[nk - 1]
    buf = np.empty(nk)
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        if i + last >= n or j + last >= n:
            continue
        buf[:] = 0.0
        for c in range(m):
            col = cols[c]
            for q in range(nk):
                diff = col[j + ks[q]] - col[i + ks[q]]
                buf[q] += diff * diff
        ok = True
        for q in range(nk):
            if buf[q] <= 0.0:
                ok = False
        if not ok:
            continue
        sxy = 0.0
        for q in range(nk):
            sxy += weight[q] * np.log(buf[q])
        slope[p] = sxy / sxx
        valid[p] = True
    return slope, valid


@njit(cache=True)
def _sample_orbit_pair_slopes(pts, ref, nbr, ks, shift, kbar, sxx):
    """:func:`pair_slopes` for SAMPLE_ORBIT, coordinates transposed: the sample and orbit
    squared distances of a pair at every horizon are built column by column, with the
    arithmetic of :func:`sq_distance` and :func:`orbit_sq_distance` (same results)."""
    n, m = pts.shape
    cols = np.ascontiguousarray(pts.T)
    nk = ks.size
    slope = np.zeros(ref.size)
    valid = np.zeros(ref.size, dtype=np.bool_)
    weight = np.empty(nk)
    for q in range(nk):
        weight[q] = ks[q] - kbar
    last = ks[nk - 1]
    d_sample = np.empty(nk)
    d_orbit = np.empty(nk)
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        if i + last >= n or j + last + 1 >= n:
            continue
        s = shift[p]
        d_sample[:] = 0.0
        d_orbit[:] = 0.0
        for c in range(m):
            col = cols[c]
            for q in range(nk):
                jk = j + ks[q]
                yi = col[i + ks[q]]
                yj = col[jk]
                diff = yj - yi
                d_sample[q] += diff * diff
                if s != 0.0:
                    vel = 0.5 * (col[jk + 1] - col[jk - 1])
                    acc = col[jk + 1] - 2.0 * yj + col[jk - 1]
                    yj = yj + s * vel + 0.5 * s * s * acc
                diff = yj - yi
                d_orbit[q] += diff * diff
        sxy = 0.0
        ok = True
        for q in range(nk):
            # (sq_distance clips a negative rounding to zero; a sum of squares is not)
            d2 = np.sqrt(d_sample[q] * d_orbit[q])
            if d2 <= 0.0:
                ok = False
                break
            sxy += weight[q] * 0.5 * np.log(d2)
        if ok:
            slope[p] = sxy / sxx
            valid[p] = True
    return slope, valid


@njit(cache=True)
def pair_slopes(
    pts: np.ndarray,
    ref: np.ndarray,
    nbr: np.ndarray,
    ks: np.ndarray,
    mode: int,
    shift: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares slope (per sample) of each pair's ln d_k over k in ``ks``.

    Returns (slope, valid); a pair is invalid if it leaves the data or touches zero distance.
    """
    n = pts.shape[0]
    edge = 1 if mode >= ORBIT else 0
    slope = np.zeros(ref.size)
    valid = np.zeros(ref.size, dtype=np.bool_)
    kbar = 0.0
    for q in range(ks.size):
        kbar += ks[q]
    kbar /= ks.size
    sxx = 0.0
    for q in range(ks.size):
        sxx += (ks[q] - kbar) ** 2
    if mode == EUCLIDEAN:
        return _euclidean_pair_slopes(pts, ref, nbr, ks, kbar, sxx)
    if mode == SAMPLE_ORBIT:
        return _sample_orbit_pair_slopes(pts, ref, nbr, ks, shift, kbar, sxx)
    last = ks[ks.size - 1]
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        if i + last >= n or j + last + edge >= n:
            continue
        sxy = 0.0
        ok = True
        for q in range(ks.size):
            k = ks[q]
            d2 = _pair_sq(pts, i + k, j + k, shift[p], mode)
            if d2 <= 0.0:
                ok = False
                break
            sxy += (k - kbar) * 0.5 * np.log(d2)
        if ok:
            slope[p] = sxy / sxx
            valid[p] = True
    return slope, valid


@njit(cache=True, inline="always")
def _flush_logs(prod, logs):
    """Add ln of each running mantissa product to ``logs`` and restart the products."""
    for q in range(prod.size):
        logs[q] += np.log(prod[q])
        prod[q] = 1.0


@njit(cache=True)
def batch_slope_sums(pts, ref, nbr, ks, mode, shift, edges):
    """Sum of the per-pair slopes of :func:`pair_slopes` over each batch of pairs
    ``edges[b] … edges[b + 1] − 1`` (EUCLIDEAN or SAMPLE_ORBIT; every pair must stay
    inside the data up to the last horizon).

    A slope is linear in the pair's log distances, so a batch's sum is
    Σ_k w_k Σ_pairs ln d²_k: the squared distances (for SAMPLE_ORBIT the product of the
    sample and orbit ones) are split into binary exponent and mantissa as in
    :func:`log_divergence`, one log per horizon every 512 pairs and at each batch's end,
    instead of one per pair and horizon. Returns (sums, ok); ``ok`` is False when some
    pair has a zero (or subnormal) distance, which :func:`pair_slopes` marks invalid:
    the caller then takes that path.
    """
    m = pts.shape[1]
    cols = np.ascontiguousarray(pts.T)
    nk = ks.size
    kbar = 0.0
    for q in range(nk):
        kbar += ks[q]
    kbar /= nk
    sxx = 0.0
    for q in range(nk):
        sxx += (ks[q] - kbar) ** 2
    # ln d = ½ ln d² (sample); ½ ln √(d²_sample d²_orbit) = ¼ ln of the product
    scale = 0.25 if mode == SAMPLE_ORBIT else 0.5
    n_batches = edges.size - 1
    sums = np.zeros(n_batches)
    d_sample = np.empty(nk)
    d_orbit = np.empty(nk)
    bits = d_sample.view(np.int64)
    expo = np.zeros(nk, dtype=np.int64)
    prod = np.ones(nk)
    logs = np.zeros(nk)
    ln2 = np.log(2.0)
    for b in range(n_batches):
        expo[:] = 0
        logs[:] = 0.0
        run = 0
        for p in range(edges[b], edges[b + 1]):
            i = ref[p]
            j = nbr[p]
            s = shift[p]
            d_sample[:] = 0.0
            d_orbit[:] = 0.0
            for c in range(m):
                col = cols[c]
                for q in range(nk):
                    jk = j + ks[q]
                    yi = col[i + ks[q]]
                    yj = col[jk]
                    diff = yj - yi
                    d_sample[q] += diff * diff
                    if mode == SAMPLE_ORBIT:
                        if s != 0.0:
                            vel = 0.5 * (col[jk + 1] - col[jk - 1])
                            acc = col[jk + 1] - 2.0 * yj + col[jk - 1]
                            yj = yj + s * vel + 0.5 * s * s * acc
                        diff = yj - yi
                        d_orbit[q] += diff * diff
            for q in range(nk):
                d2 = d_sample[q] * d_orbit[q] if mode == SAMPLE_ORBIT else d_sample[q]
                if not d2 >= TINY:
                    return sums, False
                d_sample[q] = d2
                word = bits[q]
                expo[q] += (word >> 52) - 1023
                bits[q] = (word & MANTISSA) | ONE_BITS
                prod[q] *= d_sample[q]
            run += 1
            if run == LOG_RUN:
                _flush_logs(prod, logs)
                run = 0
        _flush_logs(prod, logs)
        total = 0.0
        for q in range(nk):
            total += (ks[q] - kbar) * scale * (logs[q] + expo[q] * ln2)
        sums[b] = total / sxx
    return sums, True


@njit(cache=True)
def mean_log_distance(pts: np.ndarray, i: np.ndarray, j: np.ndarray, transverse: bool) -> float:
    """Mean of ln‖y_i − y_j‖ (or its transverse part) over the pairs; zeros skipped."""
    total = 0.0
    count = 0
    for p in range(i.size):
        ld = _log_distance(pts, i[p], j[p], transverse)
        if ld > -np.inf:
            total += ld
            count += 1
    return total / count if count else 0.0


@njit(cache=True)
def _ls_slope(c1, c2, cy, cky, a, b):
    # prefix sums are exclusive at the left: sums over [a, b] = c[b + 1] - c[a]
    n = b - a + 1
    s1 = c1[b + 1] - c1[a]
    s2 = c2[b + 1] - c2[a]
    sy = cy[b + 1] - cy[a]
    sky = cky[b + 1] - cky[a]
    den = n * s2 - s1 * s1
    if den <= 0.0:
        return 0.0
    return (n * sky - s1 * sy) / den


@njit(cache=True)
def _prefix_sums(k, y):
    # exclusive prefix sums of k, k², y and k·y: any window's least-squares slope in O(1)
    n = k.size
    c1 = np.zeros(n + 1)
    c2 = np.zeros(n + 1)
    cy = np.zeros(n + 1)
    cky = np.zeros(n + 1)
    for i in range(n):
        c1[i + 1] = c1[i] + k[i]
        c2[i + 1] = c2[i] + k[i] * k[i]
        cy[i + 1] = cy[i] + y[i]
        cky[i + 1] = cky[i] + k[i] * y[i]
    return c1, c2, cy, cky


@njit(cache=True)
def _straight(c1, c2, cy, cky, a, b, s, tol):
    # slopes over the first, middle and last fifth (>= 2 points) within tol * s of each other
    m3 = max(2, (b - a + 1) // 5)
    s_first = _ls_slope(c1, c2, cy, cky, a, a + m3 - 1)
    s_last = _ls_slope(c1, c2, cy, cky, b - m3 + 1, b)
    mid = (a + b) // 2
    s_mid = _ls_slope(c1, c2, cy, cky, mid - m3 // 2, mid - m3 // 2 + m3 - 1)
    return max(s_first, s_mid, s_last) - min(s_first, s_mid, s_last) <= tol * s


@njit(cache=True)
def best_linear_window(
    k: np.ndarray, y: np.ndarray, min_len: float, tol: float
) -> tuple[int, int, bool]:
    """Window [a, b] of indices into (k, y) with the largest fitted rise that is straight.

    Straight: positive least-squares slope s, and the slopes fitted to the first, middle
    and last fifth of the window (at least two points each) spread by at most ``tol · s``.
    Windows must span at least ``min_len`` in ``k``. Returns (a, b, found); when none
    qualifies, (0, n - 1, False).
    """
    n = k.size
    c1, c2, cy, cky = _prefix_sums(k, y)
    best = -1.0
    ba = 0
    bb = n - 1
    found = False
    for a in range(n):
        for b in range(a + 3, n):
            span = k[b] - k[a]
            if span < min_len:
                continue
            s = _ls_slope(c1, c2, cy, cky, a, b)
            if s <= 0.0:
                continue
            rise = s * span
            if rise <= best:
                continue
            if _straight(c1, c2, cy, cky, a, b, s, tol):
                best = rise
                ba = a
                bb = b
                found = True
    return ba, bb, found


@njit(cache=True)
def straight_slope_range(
    k: np.ndarray, y: np.ndarray, min_len: float, tol: float, min_rise: float
) -> tuple[float, float, int]:
    """Smallest and largest least-squares slope over the straight windows (the test of
    :func:`best_linear_window`) that span at least ``min_len`` in ``k`` and rise by at least
    ``min_rise``; with their count (0: none, and NaN slopes)."""
    n = k.size
    c1, c2, cy, cky = _prefix_sums(k, y)
    lo = np.inf
    hi = -np.inf
    count = 0
    for a in range(n):
        for b in range(a + 3, n):
            span = k[b] - k[a]
            if span < min_len:
                continue
            s = _ls_slope(c1, c2, cy, cky, a, b)
            if s <= 0.0 or s * span < min_rise:
                continue
            if _straight(c1, c2, cy, cky, a, b, s, tol):
                lo = min(lo, s)
                hi = max(hi, s)
                count += 1
    if count == 0:
        return np.nan, np.nan, 0
    return lo, hi, count


@njit(cache=True)
def evolve_pair(
    pts: np.ndarray, i: int, j: int, steps: int, stop: int, inc: np.ndarray
) -> tuple[int, int, float]:
    """Evolve the pair (i, j) by up to ``steps`` samples, writing ln(d'/d) into ``inc[i]``.

    Stops early when either index reaches ``stop``. Returns the evolved (i, j) and their
    distance.
    """
    d0 = np.sqrt(_row_sq_distance(pts, i, pts, j))
    for _ in range(steps):
        if i + 1 >= stop or j + 1 >= stop:
            break
        d1 = np.sqrt(_row_sq_distance(pts, i + 1, pts, j + 1))
        if d0 > 0.0 and d1 > 0.0:
            inc[i] = np.log(d1 / d0)
        else:
            inc[i] = 0.0  # a coincident pair carries no stretching information
        i += 1
        j += 1
        d0 = d1
    return i, j, d0


# --- Wolf: replacement search on a uniform grid and the evolve/replace loop -------------
#
# The replacement candidates (a strided pool of the embedded points) are bucketed on a
# uniform grid over the first ``g = min(m, 3)`` coordinates: ``keys`` holds the sorted,
# distinct linear cell ids and ``starts`` the offsets of their members in ``members``. A
# search of radius R visits the (2c + 1)^g cells around the query cell, c = ⌊R/h⌋ + 1, and
# checks the full m-dimensional distance, so the grid is only a prefilter and the result
# does not depend on it.


@njit(cache=True, inline="always")
def _is_candidate(c: int, fid: int, w: int, stop: int) -> bool:
    """Outside the Theiler window ``w`` of ``fid``, with a successor before ``stop``."""
    return abs(c - fid) > w and c + 1 < stop


@njit(cache=True)
def _band_scan(
    pts,
    fid,
    old,
    norm_old,
    w,
    lower,
    radius,
    upper,
    dlt,
    cos_max,
    stop,
    grid,
    use_levels,
):
    """Best candidate within ``radius`` of ``pts[fid]``: lowest widening level, then cosine.

    Candidates: ``|c − fid| > w``, ``c + 1 < stop``, distance in [lower, radius] and cosine
    to ``old`` ≥ ``cos_max``. The level is ⌈(d − upper)/dlt⌉ (0 inside the band) when
    ``use_levels``, else 0. ``grid`` is the tuple built by ``_wolf._pool_grid``. Returns
    (index, level, cosine); index −1 if none.
    """
    grid_lo, cell, ncell, stride, keys, starts, members, pool = grid
    m = pts.shape[1]
    g = grid_lo.size
    reach = int(np.floor(radius / cell)) + 1
    side = 2 * reach + 1
    total = 1
    for _ in range(g):
        total *= side
    centre = np.empty(g, dtype=np.int64)
    frac = np.empty(g)  # position of the query inside its cell, in cells
    for d in range(g):
        u = (pts[fid, d] - grid_lo[d]) / cell
        c = min(max(int(np.floor(u)), 0), ncell[d] - 1)
        centre[d] = c
        frac[d] = u - c
    best = -1
    best_level = np.inf
    best_cos = -np.inf
    best_d2 = np.inf
    r2 = radius * radius
    rc2 = (radius / cell) ** 2
    # visiting more cells than there are candidates costs more than scanning them all
    brute = total > members.size // 4
    for t in range(1 if brute else total):
        key = 0
        rest = t
        inside = True
        gap2 = 0.0  # squared distance (in cells) from the query to the cell's box
        for d in range(g):
            off = rest % side - reach
            rest //= side
            c = centre[d] + off
            if c < 0 or c >= ncell[d]:
                inside = False
                break
            if off > 0:
                gap2 += (off - frac[d]) ** 2
            elif off < 0:
                gap2 += (frac[d] - off - 1.0) ** 2
            key += c * stride[d]
        if brute:
            lo, hi = 0, members.size
        else:
            if not inside or gap2 > rc2:
                continue
            pos = find_key(keys, key)
            if pos < 0:
                continue
            lo, hi = starts[pos], starts[pos + 1]
        for q in range(lo, hi):
            c = members[q]
            if not _is_candidate(c, fid, w, stop):
                continue
            d2 = 0.0
            for k in range(m):
                diff = pool[q, k] - pts[fid, k]
                d2 += diff * diff
                if d2 > r2:
                    break
            if d2 > r2:
                continue
            dist = np.sqrt(d2)
            if dist < lower:
                continue
            if norm_old > 0.0:
                if dist <= 0.0:
                    continue
                dot = 0.0
                for k in range(m):
                    dot += (pool[q, k] - pts[fid, k]) * old[k]
                cos = dot / (dist * norm_old)
            else:
                cos = 1.0
            if cos < cos_max:
                continue
            level = 0.0
            if use_levels and dlt > 0.0 and dist > upper:
                level = np.ceil((dist - upper) / dlt)
            # ties (every same-side point has cosine 1 in one dimension) go to the nearer
            # point, then the earlier one, so the result does not depend on the grid
            if (
                level < best_level
                or (level == best_level and cos > best_cos)
                or (level == best_level and cos == best_cos and (d2, c) < (best_d2, best))
            ):
                best = c
                best_level = level
                best_cos = cos
                best_d2 = d2
    return best, best_level, best_cos


@njit(cache=True)
def _nearest_beyond(pts, fid, w, lower, stop, members):
    """Nearest pool point with ``|c − fid| > w``, ``c + 1 < stop`` and distance ≥ lower.

    If none is that far, the nearest admissible point at any distance; −1 if none at all.
    Brute force: only needed when a neighbour ran off the data or hit the fiducial point.
    """
    far = -1
    far_d2 = np.inf
    any_ = -1
    any_d2 = np.inf
    lower2 = lower * lower
    for q in range(members.size):
        c = members[q]
        if not _is_candidate(c, fid, w, stop):
            continue
        d2 = _row_sq_distance(pts, c, pts, fid)
        if d2 < any_d2:
            any_ = c
            any_d2 = d2
        if d2 >= lower2 and d2 < far_d2:
            far = c
            far_d2 = d2
    return far if far >= 0 else any_


@njit(cache=True)
def wolf_loop(pts, w, lower, upper, dlt, widen, cos_max, evolve, always, grid, inc):
    """Wolf's fixed-evolution/replacement loop; ln(L'/L) per sample goes into ``inc``.

    The pair is evolved ``evolve`` samples; then, unless the separation is still inside the
    band [lower, upper] (and ``always`` is false), the neighbour is replaced by the band
    point with the smallest angle to the old separation (cosine ≥ ``cos_max``), widening
    the upper bound by ``dlt`` up to ``widen`` times. With no such point the evolved
    neighbour is kept, unless it ran off the data or coincides with the fiducial point;
    then the nearest point beyond ``lower`` is taken. Returns (replacements, replacements
    meeting the angle condition, intervals kept without replacement, those of them whose
    separation had grown above the band).
    """
    n, m = pts.shape
    cell = grid[1]
    members = grid[6]
    wide = upper + widen * dlt
    one_pass = (2 * (int(np.floor(wide / cell)) + 1) + 1) ** grid[0].size > members.size // 4
    zero = np.zeros(m)
    # typed indices and flags, not literals: a constant argument is typed as its literal
    # and compiles the callee once more per distinct constant
    i = np.int64(0)
    j, _, _ = _band_scan(
        pts, i, zero, 0.0, w, lower, wide, upper, dlt, -1.0, n, grid, np.bool_(True)
    )
    if j < 0:
        j = _nearest_beyond(pts, i, w, lower, n, members)
    if j < 0:
        return 0, 0, 0, 0
    replacements = 0
    angle_ok = 0
    kept = 0
    kept_above = 0
    old = np.empty(m)
    while i + 1 < n:
        i, j, d = evolve_pair(pts, i, j, evolve, n, inc)
        if i + 1 >= n:
            break
        valid = j + 1 < n and d > 0.0
        if valid and not always and lower <= d <= upper:
            continue
        norm2 = 0.0
        for k in range(m):
            old[k] = pts[j, k] - pts[i, k]
            norm2 += old[k] * old[k]
        norm_old = np.sqrt(norm2)
        # inside the band first: if anything qualifies there, no widening is needed (unless
        # the widened search scans every candidate anyway)
        new = -1
        if not one_pass:
            new, _, _ = _band_scan(
                pts,
                i,
                old,
                norm_old,
                w,
                lower,
                upper,
                upper,
                dlt,
                cos_max,
                n,
                grid,
                np.bool_(False),
            )
        if new < 0 and (widen > 0 or one_pass):
            new, _, _ = _band_scan(
                pts, i, old, norm_old, w, lower, wide, upper, dlt, cos_max, n, grid, np.bool_(True)
            )
        if new >= 0:
            angle_ok += 1
        else:
            if valid:  # Wolf: no acceptable replacement, keep the evolved neighbour
                kept += 1
                if d > upper:
                    kept_above += 1
                continue
            new = _nearest_beyond(pts, i, w, lower, n, members)
            if new < 0:
                break
        j = new
        replacements += 1
        if j + 1 >= n:  # no neighbour with a future left anywhere: stop here
            break
    return replacements, angle_ok, kept, kept_above
