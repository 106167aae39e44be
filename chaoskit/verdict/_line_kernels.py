"""Compiled kernel of the line spectrum: Householder least squares on one thread."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def householder_qr(columns: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """R (m × m, upper triangular) and the first m entries of Qᵀy of the n × m matrix whose
    columns are the rows of ``columns`` (m × n, C order; n ≥ m), by Householder reflections.

    The reflections run on this thread only: a tall, narrow least-squares problem is too
    small for a threaded LAPACK to gain anything, and on busy cores its worker threads
    spend far more CPU waiting for each other than the factorisation takes.
    """
    m, n = columns.shape
    a = columns.copy()
    b = y.copy()
    r = np.zeros((m, m))
    for k in range(m):
        v = a[k, k:]
        norm = np.sqrt(np.dot(v, v))
        if norm == 0.0:
            continue  # a zero column: R[k, k] = 0 leaves the rank check to the caller
        alpha = -norm if v[0] >= 0.0 else norm
        v[0] -= alpha
        scale = 2.0 / np.dot(v, v)
        for j in range(k + 1, m):
            w = a[j, k:]
            s = scale * np.dot(v, w)
            for i in range(n - k):
                w[i] -= s * v[i]
        w = b[k:]
        s = scale * np.dot(v, w)
        for i in range(n - k):
            w[i] -= s * v[i]
        r[k, k] = alpha
        for j in range(k + 1, m):
            r[k, j] = a[j, k]
    return r, b[:m].copy()
