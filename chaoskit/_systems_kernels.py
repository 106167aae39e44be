"""Compiled right-hand sides and a fixed-step RK4 for the reference systems."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _rhs(kind: int, t: float, s: np.ndarray, p: np.ndarray, out: np.ndarray) -> None:
    if kind == 0:  # Lorenz: sigma, rho, beta
        out[0] = p[0] * (s[1] - s[0])
        out[1] = s[0] * (p[1] - s[2]) - s[1]
        out[2] = s[0] * s[1] - p[2] * s[2]
    elif kind == 1:  # Rössler: a, b, c
        out[0] = -s[1] - s[2]
        out[1] = s[0] + p[0] * s[1]
        out[2] = p[1] + s[2] * (s[0] - p[2])
    elif kind == 2:  # forced Duffing x'' + d x' + alpha x + beta x^3 = gamma cos(omega t)
        out[0] = s[1]
        out[1] = -p[0] * s[1] - p[1] * s[0] - p[2] * s[0] ** 3 + p[3] * np.cos(p[4] * t)
    else:  # van der Pol x'' - mu (1 - x^2) x' + x = 0
        out[0] = s[1]
        out[1] = p[0] * (1.0 - s[0] * s[0]) * s[1] - s[0]


@njit(cache=True)
def rk4_sample(
    kind: int, p: np.ndarray, s0: np.ndarray, t0: float, dt: float, substeps: int, n: int
) -> np.ndarray:
    """Integrate with classical RK4 at step dt/substeps and return n samples at spacing dt."""
    d = s0.size
    out = np.empty((n, d))
    s = s0.copy()
    k1 = np.empty(d)
    k2 = np.empty(d)
    k3 = np.empty(d)
    k4 = np.empty(d)
    tmp = np.empty(d)
    h = dt / substeps
    t = t0
    for i in range(n):
        out[i] = s
        for _ in range(substeps):
            _rhs(kind, t, s, p, k1)
            for j in range(d):
                tmp[j] = s[j] + 0.5 * h * k1[j]
            _rhs(kind, t + 0.5 * h, tmp, p, k2)
            for j in range(d):
                tmp[j] = s[j] + 0.5 * h * k2[j]
            _rhs(kind, t + 0.5 * h, tmp, p, k3)
            for j in range(d):
                tmp[j] = s[j] + h * k3[j]
            _rhs(kind, t + h, tmp, p, k4)
            for j in range(d):
                s[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j])
            t += h
    return out


@njit(cache=True)
def logistic(n: int, r: float, x0: float, discard: int) -> np.ndarray:
    x = x0
    for _ in range(discard):
        x = r * x * (1.0 - x)
    out = np.empty(n)
    for i in range(n):
        out[i] = x
        x = r * x * (1.0 - x)
    return out


@njit(cache=True)
def henon(n: int, a: float, b: float, x0: float, y0: float, discard: int) -> np.ndarray:
    x, y = x0, y0
    for _ in range(discard):
        x, y = 1.0 - a * x * x + y, b * x
    out = np.empty((n, 2))
    for i in range(n):
        out[i, 0] = x
        out[i, 1] = y
        x, y = 1.0 - a * x * x + y, b * x
    return out
