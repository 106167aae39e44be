"""The size of a state deviation and its projection onto the constraints' tangent space.

Shared by the two tangent integrations: Dormand–Prince on a rigid model
(``_tangent_kernels``) and generalized-α on a flexible one (the deviation of
:func:`mechanism.core.integrate._kernels.genalpha_advance`).
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_noalloc
from mechanism.core.model._kernels import _cholesky_solve, _schur, evaluate_constraints

__all__ = ["deviation_norm", "project_tangent"]

# largest coordinate change (m or rad) of the finite difference of Φq q̇ + Φt along δq
_G_STEP = 1e-7


@njit_noalloc()
def deviation_norm(model, d, tau2, inv_mass):
    """√((δqᵀMδq + τ² δq̇ᵀMδq̇)/m): the mass-weighted size (m) of a deviation.

    With m the total mass, a rigid translation of the whole mechanism by δ has size δ and
    a velocity deviation counts as the displacement it makes in the time τ.
    """
    n = model.n_dof
    s = 0.0
    for i in range(n):
        xq = 0.0
        xv = 0.0
        for j in range(model.blk_lo[i], model.blk_hi[i]):
            xq += model.mass[i, j] * d[j]
            xv += model.mass[i, j] * d[n + j]
        s += d[i] * xq + tau2 * d[n + i] * xv
    return math.sqrt(max(s, 0.0) * inv_mass)


@njit_noalloc()
def project_tangent(model, ws, ws2, t, y, d, scratch):
    """Project the deviation ``d`` onto the tangent space of the constraint manifold at y.

    Position level Φq δq = 0 and velocity level Φq δq̇ + (∂(Φq q̇ + Φt)/∂q) δq = 0, each by
    the mass-orthogonal correction −M⁻¹Φqᵀ(ΦqM⁻¹Φqᵀ)⁻¹r; the velocity-level Jacobian
    product is a finite difference of Φq q̇ + Φt along δq. Returns False when the
    constraint matrix is singular.
    """
    n = model.n_dof
    m = model.n_rows
    if m == 0:
        return True
    q = y[:n]
    v = y[n:]
    evaluate_constraints(model, ws, t, q, v)
    _schur(model, ws)
    for k in range(m):
        s = 0.0
        for j in range(n):
            s += ws.phiq[k, j] * d[j]
        ws.lam[k] = s
    if not _cholesky_solve(ws.s, ws.lam, m):
        return False
    big = 0.0
    for i in range(n):
        s = 0.0
        for k in range(m):
            s += ws.w[i, k] * ws.lam[k]
        d[i] -= s
        big = max(big, abs(d[i]))
    _schur(model, ws)
    for k in range(m):
        s = 0.0
        for j in range(n):
            s += ws.phiq[k, j] * d[n + j]
        ws.lam[k] = s
    if big > 0.0:
        step = _G_STEP / big
        for i in range(n):
            scratch[i] = q[i] + step * d[i]
        evaluate_constraints(model, ws2, t, scratch[:n], v)
        for k in range(m):
            g = ws2.phit[k] - ws.phit[k]
            for j in range(n):
                g += (ws2.phiq[k, j] - ws.phiq[k, j]) * v[j]
            ws.lam[k] += g / step
    if not _cholesky_solve(ws.s, ws.lam, m):
        return False
    for i in range(n):
        s = 0.0
        for k in range(m):
            s += ws.w[i, k] * ws.lam[k]
        d[n + i] -= s
    return True
