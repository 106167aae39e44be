"""Compiled kernels for the classify package (0–1 test)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def zero_one_k(phi: np.ndarray, c_values: np.ndarray, ncut: int) -> np.ndarray:
    """Correlation-method K of the 0–1 test for each frequency c (Gottwald & Melbourne 2009).

    p(j) = Σ_{i<=j} φ(i) cos(ic), q(j) = Σ_{i<=j} φ(i) sin(ic);
    M(n) = mean over j < N - ncut of (p(j+n) - p(j))² + (q(j+n) - q(j))²;
    D(n) = M(n) - (mean φ)² (1 - cos nc) / (1 - cos c);  K = corr(n, D(n)), n = 1..ncut.
    """
    n_total = phi.size
    n_avg = n_total - ncut
    mean_phi = 0.0
    for i in range(n_total):
        mean_phi += phi[i]
    mean_phi /= n_total
    p = np.empty(n_total)
    q = np.empty(n_total)
    d = np.empty(ncut)
    out = np.empty(c_values.size)
    # The regressor n = 1..ncut has a closed-form mean and spread.
    xi_mean = 0.5 * (ncut + 1.0)
    xi_var = 0.0
    for n in range(1, ncut + 1):
        xi_var += (n - xi_mean) ** 2
    for ic in range(c_values.size):
        c = c_values[ic]
        sp = 0.0
        sq = 0.0
        for j in range(n_total):
            sp += phi[j] * np.cos((j + 1) * c)
            sq += phi[j] * np.sin((j + 1) * c)
            p[j] = sp
            q[j] = sq
        for n in range(1, ncut + 1):
            acc = 0.0
            for j in range(n_avg):
                dp = p[j + n] - p[j]
                dq = q[j + n] - q[j]
                acc += dp * dp + dq * dq
            v_osc = mean_phi * mean_phi * (1.0 - np.cos(n * c)) / (1.0 - np.cos(c))
            d[n - 1] = acc / n_avg - v_osc
        d_mean = 0.0
        for n in range(ncut):
            d_mean += d[n]
        d_mean /= ncut
        cov = 0.0
        d_var = 0.0
        for n in range(ncut):
            cov += (n + 1 - xi_mean) * (d[n] - d_mean)
            d_var += (d[n] - d_mean) ** 2
        if d_var <= 0.0:
            out[ic] = 0.0
        else:
            out[ic] = cov / np.sqrt(xi_var * d_var)
    return out
