"""Compiled kernels for sections: local Lagrange interpolation and bracketed root finding.

The interpolant through ``order + 1`` samples around a bracket ``[t[i], t[i + 1]]`` is
evaluated in the Lagrange product form with times taken relative to ``t[i]``, so that large
absolute times lose no digits. Inputs are contiguous float64 arrays checked by the caller.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _first_node(i: int, n: int, npts: int) -> int:
    # Nodes centred on the bracket (i, i + 1); shifted inwards at the ends of the series.
    start = i - (npts - 2) // 2
    if start < 0:
        start = 0
    if start > n - npts:
        start = n - npts
    return start


@njit(cache=True)
def _weights(t: np.ndarray, start: int, npts: int, origin: float, s: float, w: np.ndarray) -> None:
    for j in range(npts):
        tj = t[start + j] - origin
        num = 1.0
        den = 1.0
        for k in range(npts):
            if k != j:
                tk = t[start + k] - origin
                num *= s - tk
                den *= tj - tk
        w[j] = num / den


@njit(cache=True)
def _eval(
    t: np.ndarray, x: np.ndarray, start: int, npts: int, origin: float, s: float, w: np.ndarray
) -> float:
    _weights(t, start, npts, origin, s, w)
    acc = 0.0
    for j in range(npts):
        acc += w[j] * x[start + j]
    return acc


@njit(cache=True)
def find_roots(
    t: np.ndarray, x: np.ndarray, brackets: np.ndarray, targets: np.ndarray, order: int
) -> np.ndarray:
    """Solve p_i(t) = target_i in each bracket [t[i], t[i + 1]] (Illinois regula falsi).

    ``p_i`` interpolates ``x`` through ``order + 1`` samples around the bracket. The data
    change sign across each bracket, and ``p_i`` matches the data at its nodes, so a root
    exists and stays bracketed; the Illinois update keeps superlinear convergence.
    """
    n = t.size
    npts = min(order + 1, n)
    w = np.empty(npts)
    out = np.empty(brackets.size)
    for b in range(brackets.size):
        i = brackets[b]
        level = targets[b]
        start = _first_node(i, n, npts)
        origin = t[i]
        a = 0.0
        c = t[i + 1] - origin
        fa = x[i] - level
        fc = x[i + 1] - level
        if fa == 0.0:
            out[b] = origin
            continue
        if fc == 0.0:
            out[b] = t[i + 1]
            continue
        side = 0
        s = a
        tol = 1e-15 * c + 1e-300
        for _ in range(200):
            s = (a * fc - c * fa) / (fc - fa)
            fs = _eval(t, x, start, npts, origin, s, w) - level
            if fs == 0.0 or c - a <= tol:
                break
            if (fs > 0.0) == (fc > 0.0):
                c = s
                fc = fs
                if side == 1:
                    fa *= 0.5
                side = 1
            else:
                a = s
                fa = fs
                if side == -1:
                    fc *= 0.5
                side = -1
            if abs(fs) <= 1e-15 * (abs(level) + abs(x[i]) + abs(x[i + 1])):
                break
        out[b] = origin + s
    return out


@njit(cache=True)
def interpolate_at(
    t: np.ndarray, y: np.ndarray, brackets: np.ndarray, times: np.ndarray, order: int
) -> np.ndarray:
    """Evaluate the local Lagrange interpolant of each column of ``y`` at ``times``.

    ``times[b]`` lies in ``[t[brackets[b]], t[brackets[b] + 1]]``.
    """
    n = t.size
    npts = min(order + 1, n)
    w = np.empty(npts)
    out = np.empty((times.size, y.shape[1]))
    for b in range(times.size):
        i = brackets[b]
        start = _first_node(i, n, npts)
        origin = t[i]
        _weights(t, start, npts, origin, times[b] - origin, w)
        for col in range(y.shape[1]):
            acc = 0.0
            for j in range(npts):
                acc += w[j] * y[start + j, col]
            out[b, col] = acc
    return out
