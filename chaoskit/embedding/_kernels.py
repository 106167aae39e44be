"""Compiled kernels for delay and dimension estimation (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def bin_indices(x: np.ndarray, bins: int) -> np.ndarray:
    """Equal-width bin index in ``[0, bins)`` of every sample (range = data range).

    Safe for every finite x: differences are taken of halves (``hi - lo`` overflows near the
    float64 limit; halving is exact, so normal-range codes are unchanged), and the float
    position is clipped before the integer conversion (a NaN or huge float converted to an
    integer would index outside the histogram).
    """
    lo = 0.5 * x.min()
    hi = 0.5 * x.max()
    out = np.zeros(x.size, dtype=np.int64)
    if not hi > lo:  # constant, or a span of a few subnormals that halving rounds away
        return out
    scale = 0.5 * bins / (hi - lo)
    for i in range(x.size):
        f = (0.5 * x[i] - lo) * scale * 2.0
        if f >= bins:
            out[i] = bins - 1
        elif f >= 0.0:
            out[i] = int(f)
        else:  # NaN (an infinite scale at a subnormal range) or rounding below zero
            out[i] = 0
    return out


@njit(cache=True)
def mutual_information_curve(codes: np.ndarray, bins: int, lag0: int, lag1: int) -> np.ndarray:
    """Histogram mutual information I(x_t; x_{t+τ}) in nats for τ = lag0 … lag1 − 1."""
    n = codes.size
    out = np.empty(lag1 - lag0)
    joint = np.empty((bins, bins), dtype=np.int64)
    pa = np.empty(bins, dtype=np.int64)
    pb = np.empty(bins, dtype=np.int64)
    flat = joint.reshape(bins * bins)
    for lag in range(lag0, lag1):
        flat[:] = 0
        m = n - lag
        for i in range(m):
            flat[codes[i] * bins + codes[i + lag]] += 1
        # the marginal counts as the joint's row and column sums (integers: the same
        # counts as incrementing them per pair, at a third of the increments)
        for a in range(bins):
            t = 0
            for b in range(bins):
                t += joint[a, b]
            pa[a] = t
        for b in range(bins):
            t = 0
            for a in range(bins):
                t += joint[a, b]
            pb[b] = t
        # I = Σ p_ab ln(p_ab / (p_a p_b)) with p = count / m
        s = 0.0
        for a in range(bins):
            if pa[a] == 0:
                continue
            for b in range(bins):
                c = joint[a, b]
                if c > 0:
                    s += c * np.log(c * m / (pa[a] * pb[b]))
        out[lag - lag0] = s / m
    return out


@njit(cache=True)
def fnn_counts(
    x: np.ndarray,
    ref: np.ndarray,
    nbr: np.ndarray,
    dist: np.ndarray,
    dim: int,
    lag: int,
    rtol: float,
    atol: float,
    attractor_size: float,
) -> tuple[int, int]:
    """Kennel's two tests for pairs (ref, nbr) at dimension ``dim``; returns (false, used)."""
    # distances below eps are rounding noise (e.g. exact repeats of a periodic signal)
    eps = 1e-9 * attractor_size
    false = 0
    used = 0
    for p in range(ref.size):
        i = ref[p]
        j = nbr[p]
        r = dist[p]
        extra = abs(x[i + dim * lag] - x[j + dim * lag])
        r1 = np.sqrt(r * r + extra * extra)
        used += 1
        if r1 / attractor_size > atol:
            false += 1
        elif r > eps:
            if extra / r > rtol:
                false += 1
        elif extra > rtol * eps:  # coincident points that separate in the next coordinate
            false += 1
    return false, used


@njit(cache=True)
def cao_sums(
    x: np.ndarray,
    ref: np.ndarray,
    nbr: np.ndarray,
    dist: np.ndarray,
    dim: int,
    lag: int,
    eps: float,
) -> tuple[float, float, int]:
    """Σ a(i, d) and Σ |x_{i+dτ} − x_{n+dτ}| over pairs farther apart than eps (max norm)."""
    sa = 0.0
    se = 0.0
    used = 0
    for p in range(ref.size):
        r = dist[p]
        if r <= eps:
            continue
        extra = abs(x[ref[p] + dim * lag] - x[nbr[p] + dim * lag])
        sa += max(r, extra) / r
        se += extra
        used += 1
    return sa, se, used
