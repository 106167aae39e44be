"""Compiled kernel of the Lyapunov spectrum from data (no validation here)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def spectrum(
    pts: np.ndarray, refs: np.ndarray, neighbours: np.ndarray, step: int, running: np.ndarray
) -> np.ndarray:
    """QR-accumulated log stretches of the local linear maps along the reference points.

    For reference ``i = refs[r]`` with neighbours ``j = neighbours[r]`` the map ``J`` solves
    the centred least-squares problem ``(y_{j+s} − ȳ_{+s}) ≈ J (y_j − ȳ)``. ``Q ← qr(J Q)``
    and ``ln |R_kk|`` is summed; ``running[r]`` holds the running mean per reference.
    Returns the sum of ``ln |R_kk|`` over all references.
    """
    m = pts.shape[1]
    k = neighbours.shape[1]
    q = np.eye(m)
    total = np.zeros(m)
    a = np.empty((k, m))
    b = np.empty((k, m))
    for r in range(refs.size):
        mean_a = np.zeros(m)
        mean_b = np.zeros(m)
        for n in range(k):
            j = neighbours[r, n]
            for c in range(m):
                a[n, c] = pts[j, c]
                b[n, c] = pts[j + step, c]
                mean_a[c] += pts[j, c]
                mean_b[c] += pts[j + step, c]
        for n in range(k):
            for c in range(m):
                a[n, c] -= mean_a[c] / k
                b[n, c] -= mean_b[c] / k
        jt = np.linalg.lstsq(a, b)[0]  # a @ jt ≈ b, so J = jt.T
        z = np.ascontiguousarray(jt.T) @ q
        q, rr = np.linalg.qr(z)
        q = np.ascontiguousarray(q)
        for c in range(m):
            d = rr[c, c]
            if d < 0.0:  # keep R's diagonal positive: flip the matching column of Q
                for row in range(m):
                    q[row, c] = -q[row, c]
                d = -d
            total[c] += np.log(d) if d > 0.0 else -np.inf
        for c in range(m):
            running[r, c] = total[c] / (r + 1)
    return total
