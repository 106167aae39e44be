"""Linear algebra and contact Newton solve of the implicit steps: LU factorisation, the
hybrid Jacobian of the accelerations (analytic contact columns, projected differences), the
contact derivatives and their re-linearisation test, and the reduced Newton solve on the
contact unknowns. Used by the generalized-α loop (``_genalpha_kernels.py``) and by the
perturbed copy of the flexible tangent integration (``_tangent_kernels.py``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import (
    njit,
)

from mechanism.core._jit import (
    njit_noalloc,
)
from mechanism.core.bodies import (
    BEAM_F_DAMPING,
    beams_jacobian_add,
)
from mechanism.core.contact import (
    FRICTION_NONE,
    film_engaged,
    film_moved,
    friction_force_derivatives,
    normal_force_derivatives,
)
from mechanism.core.joints import (
    ANGLE_SLOPE,
    PC_VX,
    PC_VY,
    PC_X,
    PC_Y,
    POINT_RIGID,
    apply_point_force,
    update_point_rows,
)
from mechanism.core.model import (
    CF_FILM,
    CF_V0,
    CF_V1,
    CF_VISC,
    CJ_DELTA,
    CJ_DELTA_DOT,
    CJ_PHI_B,
    CJ_VT,
    CNT_COLUMNS,
    CNT_JAC,
    CW_WORN,
    accelerations,
    clearance_forces,
)
from mechanism.core.model import kernels as model_kernels

__all__: list[str] = []


# --------------------------------------------------------------------------- generalized-α


@njit(cache=True, error_model="numpy")
def lu_factor(a, piv):
    """In-place LU factorisation with partial pivoting; False if singular.

    On return ``a`` holds the factors *transposed* (row j of ``a`` is column j of L below
    the diagonal and of U above it), the layout :func:`lu_solve` reads along rows.

    The elimination indexes ``a`` directly (an array view per row and pivot would cost a
    reference count each). Above ``_LU_BUFFERED`` rows the pivot row is copied to a
    buffer, so that the update loop reads and writes different arrays and the compiler
    vectorises it; small matrices skip the buffer's allocation. Both orders of the
    operations are the same, so the factors are too, to the last bit.
    """
    n = a.shape[0]
    if n > _LU_BUFFERED:
        row = np.empty(n)
        for k in range(n):
            if not _lu_pivot(a, piv, k):
                return False
            m = n - k - 1
            k1 = k + 1
            for j in range(m):
                row[j] = a[k, k1 + j]
            for i in range(k1, n):
                f = a[i, k]
                if f != 0.0:
                    for j in range(m):
                        a[i, k1 + j] -= f * row[j]
    else:
        for k in range(n):
            if not _lu_pivot(a, piv, k):
                return False
            for i in range(k + 1, n):
                f = a[i, k]
                if f != 0.0:
                    for j in range(k + 1, n):
                        a[i, j] -= f * a[k, j]
    for i in range(n):
        for j in range(i + 1, n):
            tmp = a[i, j]
            a[i, j] = a[j, i]
            a[j, i] = tmp
    return True


# rows above which lu_factor copies the pivot row to a vectorisable buffer
_LU_BUFFERED = 16


@njit(cache=True, error_model="numpy", inline="always")
def _lu_pivot(a, piv, k):
    """Step k of :func:`lu_factor` before the update: choose and swap the pivot row, scale
    column k below it into the multipliers; False if the column is zero."""
    n = a.shape[0]
    p = k
    big = abs(a[k, k])
    for i in range(k + 1, n):
        if abs(a[i, k]) > big:
            big = abs(a[i, k])
            p = i
    if not big > 0.0:
        return False
    piv[k] = p
    if p != k:
        for j in range(n):
            tmp = a[k, j]
            a[k, j] = a[p, j]
            a[p, j] = tmp
    inv = 1.0 / a[k, k]
    for i in range(k + 1, n):
        a[i, k] *= inv
    return True


@njit_noalloc(error_model="numpy")
def lu_solve(lt, piv, b):
    """Solve A x = b in place from :func:`lu_factor`'s transposed factors.

    Both substitutions take the columns four at a time: each entry of ``b`` below (above)
    a block receives the block's four updates in one pass, in the order of the column
    by column substitution, so the result is the same to the last bit while ``b`` is
    swept a quarter as often. The passes run over contiguous row slices of ``lt``, which
    the compiler vectorises.
    """
    n = lt.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    # forward, unit L: column j of L below the diagonal is lt[j, j + 1 :]
    j0 = 0
    while j0 < n:
        j1 = min(j0 + 4, n)
        for jj in range(j0, j1):
            bj = b[jj]
            for i in range(jj + 1, j1):
                b[i] -= lt[jj, i] * bj
        if j1 - j0 == 4:
            b0, b1, b2, b3 = b[j0], b[j0 + 1], b[j0 + 2], b[j0 + 3]
            c0, c1, c2, c3 = lt[j0, j1:], lt[j0 + 1, j1:], lt[j0 + 2, j1:], lt[j0 + 3, j1:]
            rest = b[j1:]
            for i in range(n - j1):
                rest[i] = (((rest[i] - c0[i] * b0) - c1[i] * b1) - c2[i] * b2) - c3[i] * b3
        else:
            for jj in range(j0, j1):
                bj = b[jj]
                for i in range(j1, n):
                    b[i] -= lt[jj, i] * bj
        j0 = j1
    # backward: column j of U above the diagonal is lt[j, :j], its diagonal lt[j, j]
    j1 = n
    while j1 > 0:
        j0 = max(j1 - 4, 0)
        for jj in range(j1 - 1, j0 - 1, -1):
            bj = b[jj] / lt[jj, jj]
            b[jj] = bj
            for i in range(j0, jj):
                b[i] -= lt[jj, i] * bj
        if j1 - j0 == 4:
            b3, b2, b1, b0 = b[j1 - 1], b[j1 - 2], b[j1 - 3], b[j0]
            c3, c2, c1, c0 = lt[j1 - 1, :j0], lt[j1 - 2, :j0], lt[j1 - 3, :j0], lt[j0, :j0]
            rest = b[:j0]
            for i in range(j0):
                rest[i] = (((rest[i] - c3[i] * b3) - c2[i] * b2) - c1[i] * b1) - c0[i] * b0
        else:
            for jj in range(j1 - 1, j0 - 1, -1):
                bj = b[jj]
                for i in range(j0):
                    b[i] -= lt[jj, i] * bj
        j1 = j0


@njit(cache=True)
def _fd_jacobian(model, ws, t, q, v, vimp, kq, cv, counters):
    """Forward-difference ∂q̈/∂q and ∂q̈/∂q̇ (2n + 1 evaluations).

    The base value is evaluated here: the integrator's q̈ is a Newton iterate, accurate only
    to the tolerance, and its error divided by the tiny increments would swamp the
    Jacobian.
    """
    n = q.shape[0]
    qp = q.copy()
    vp = v.copy()
    f0 = np.empty(n)
    f1 = np.empty(n)
    accelerations(model, ws, t, q, v, vimp, f0, counters)
    for j in range(n):
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        accelerations(model, ws, t, qp, v, vimp, f1, counters)
        qp[j] = q[j]
        for i in range(n):
            kq[i, j] = (f1[i] - f0[i]) / eps
    for j in range(n):
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        accelerations(model, ws, t, q, vp, vimp, f1, counters)
        vp[j] = v[j]
        for i in range(n):
            cv[i, j] = (f1[i] - f0[i]) / eps
    counters[CNT_JAC] += 1


@njit(cache=True, error_model="numpy")
def _project(model, ws, x, out, y, u):
    """out = P M⁻¹ x, P = I − W S⁻¹Φq (the constrained response to a generalized force).

    Reads W = M⁻¹Φqᵀ, Φq and the Cholesky factor of S = Φq M⁻¹Φqᵀ (lower triangle) left in
    ``ws`` by the last :func:`accelerations` call; ``y`` (n) and ``u`` (m) are scratch.
    """
    n = out.shape[0]
    m = model.n_rows
    for i in range(n):
        acc = 0.0
        for l in range(model.blk_lo[i], model.blk_hi[i]):
            acc += model.minv[i, l] * x[l]
        y[i] = acc
    for k in range(m):
        acc = 0.0
        for i in range(n):
            acc += ws.phiq[k, i] * y[i]
        u[k] = acc
    for i in range(m):
        acc = u[i]
        for k in range(i):
            acc -= ws.s[i, k] * u[k]
        u[i] = acc / ws.s[i, i]
    for i in range(m - 1, -1, -1):
        acc = u[i]
        for k in range(i + 1, m):
            acc -= ws.s[k, i] * u[k]
        u[i] = acc / ws.s[i, i]
    for i in range(n):
        acc = y[i]
        for k in range(m):
            acc -= ws.w[i, k] * u[k]
        out[i] = acc


@njit(cache=True, error_model="numpy")
def _projected_columns(model, ws, kbuf, cols, out):
    """out[:, j] = −P M⁻¹ kbuf[:, j] for j in ``cols`` (see :func:`_project`), column by
    column over the sparsity of each factor.

    ``kbuf`` holds element Jacobians, which couple a coordinate only with the other
    coordinates of its mass block, and within a beam only over one or two elements: a
    column's product with M⁻¹ runs over the column's nonzeros (a band of about 12 rows)
    as sums of the contiguous rows of the exactly symmetric M⁻¹, and its product with Φq
    over each constraint row's nonzero columns (``ws.nz_j``). Every sum is taken over the
    same nonzero terms in the same order as the dense products, so the columns are those
    of the dense products bit for bit, at about a sixth of their cost on an ANCF rod.
    Plain loops, not BLAS: a threaded BLAS would spin its threads on the other cores
    between calls and change the sums' order with the machine's core count.

    Reads the Φq, W, S and nonzero lists of the last :func:`accelerations` call."""
    n = out.shape[0]
    m = model.n_rows
    nk = cols.shape[0]
    yt = np.zeros((nk, n))  # yt[c] = −M⁻¹ kbuf[:, cols[c]]
    for c in range(nk):
        j = cols[c]
        lo = model.blk_lo[j]
        hi = model.blk_hi[j]
        yc = yt[c, lo:hi]
        for l in range(lo, hi):
            a = kbuf[l, j]
            if a != 0.0:
                ml = model.minv[l, lo:hi]
                for r in range(hi - lo):
                    yc[r] -= ml[r] * a
    if m == 0:
        for c in range(nk):
            j = cols[c]
            for i in range(n):
                out[i, j] = yt[c, i]
        return
    wt = np.empty((m, n))
    for i in range(n):
        for r in range(m):
            wt[r, i] = ws.w[i, r]
    u = np.empty(m)
    oc = np.empty(n)
    for c in range(nk):
        yc = yt[c]
        for r in range(m):
            acc = 0.0
            for e in range(ws.nz_n[r]):
                i = ws.nz_j[r, e]
                acc += ws.phiq[r, i] * yc[i]
            u[r] = acc
        for r in range(m):
            acc = u[r]
            for k in range(r):
                acc -= ws.s[r, k] * u[k]
            u[r] = acc / ws.s[r, r]
        for r in range(m - 1, -1, -1):
            acc = u[r]
            for k in range(r + 1, m):
                acc -= ws.s[k, r] * u[k]
            u[r] = acc / ws.s[r, r]
        for i in range(n):
            oc[i] = yc[i]
        for r in range(m):
            ur = u[r]
            wr = wt[r]
            for i in range(n):
                oc[i] -= wr[i] * ur
        j = cols[c]
        for i in range(n):
            out[i, j] = oc[i]


@njit_noalloc(error_model="numpy")
def _contact_force(model, q, v, vimp, rows, pci, pcf, gen, cj, scratch_counters):
    """Generalized forces of the clearance joints alone at (q, q̇) into ``gen``; only the
    bearing and journal points ``rows`` of the point cache are refreshed (the clearance
    forces read no other point)."""
    gen[:] = 0.0
    update_point_rows(q, v, model.pt_i, model.pt_f, pci, pcf, rows)
    clearance_forces(model, pci, pcf, vimp, gen, cj, scratch_counters)


@njit(cache=True)
def _contact_rows(model):
    """The point-table rows of the clearance joints' bearings and journals."""
    n_cj = model.cj_i.shape[0]
    rows = np.empty(2 * n_cj, dtype=np.int64)
    for j in range(n_cj):
        rows[2 * j] = model.cj_i[j, 0]
        rows[2 * j + 1] = model.cj_i[j, 1]
    return rows


# clearance-table layout, bound here for the compiled kernels below
_CF_RB = model_kernels.CF_RB
_CF_RJ = model_kernels.CF_RJ
_CF_K = model_kernels.CF_K
_CF_EXP = model_kernels.CF_EXP
_CF_CE = model_kernels.CF_CE
_CF_MU = model_kernels.CF_MU
_CI_KIND = model_kernels.CI_KIND
_CONTACT_JOURNAL = model_kernels.CONTACT_JOURNAL
_CJ_EX = model_kernels.CJ_EX
_CJ_EY = model_kernels.CJ_EY
# rows of the analytic-derivative scratch (``contact_scratch``), each over the columns cc
_W_EX = 0  # ∂e_x/∂q_cc of e = r_j − r_b (= ∂ė_x/∂q̇_cc)
_W_EY = 1
_W_DX = 2  # ∂ė_x/∂q_cc (a rigid point's velocity turns with its angle)
_W_DY = 3
_W_TH = 4  # R_j ∂θ_j/∂q_cc − R_b ∂θ_b/∂q_cc (= ∂(R_j ω_j − R_b ω_b)/∂q̇_cc)
_W_OM = 5  # ∂(R_j ω_j − R_b ω_b)/∂q_cc
_W_ROWS = 6


@njit(cache=True)
def analytic_contact_supported(model):
    """Whether :func:`contact_derivatives` takes the analytic path for this model: every
    clearance joint is a dry, unworn journal in a bearing. Translational clearance
    corners, worn profiles and oil films keep the forward differences."""
    for j in range(model.cj_i.shape[0]):
        if model.cj_i[j, _CI_KIND] != _CONTACT_JOURNAL:
            return False
        if model.cw_i[j, CW_WORN] != 0 or model.cj_f[j, CF_VISC] > 0.0:
            return False
    return True


@njit_noalloc()
def _cc_index(cc, d):
    """Position of coordinate ``d`` in the sorted contact columns ``cc`` (−1 if absent)."""
    lo = 0
    hi = cc.shape[0] - 1
    while lo <= hi:
        mid = (lo + hi) // 2
        if cc[mid] < d:
            lo = mid + 1
        elif cc[mid] > d:
            hi = mid - 1
        else:
            return mid
    return -1


@njit_noalloc(error_model="numpy")
def _point_maps(model, q, v, cc, pci, pcf, k, sign, radius, g, wk, dq, f_x, f_y, f_t):
    """Add point ``k``'s maps to the rows of ``wk`` (``sign`` +1 journal, −1 bearing;
    ``radius`` its contact radius) and the parts of ∂Q/∂q that come from the point's
    configuration-dependent maps (a rigid point's lever arm, a slope angle's ∂θ/∂q) under
    the force (f_x, f_y) and friction force f_t on the journal. ``g`` (length n, zero on
    entry and on return) is scratch; the maps are read off :func:`apply_point_force`, the
    same kernel that applies the force."""
    nc = cc.shape[0]
    for r in range(3):
        apply_point_force(g, 1.0 if r == 0 else 0.0, 1.0 if r == 1 else 0.0,
                          1.0 if r == 2 else 0.0, pci, pcf, k)  # fmt: skip
        row = _W_EX if r == 0 else (_W_EY if r == 1 else _W_TH)
        scale = sign if r < 2 else sign * radius
        for a in range(nc):
            wk[row, a] += scale * g[cc[a]]
            g[cc[a]] = 0.0
    kind = model.pt_i[k, 0]
    base = model.pt_i[k, 1]
    if kind == POINT_RIGID:
        # r = R + A(θ)s̄: ∂r/∂θ = (−u_y, u_x) turns with θ, ∂²r/∂θ² = −u, ∂ṙ/∂θ = −ω u
        a = _cc_index(cc, base + 2)
        ux = pcf[k, PC_X] - q[base]
        uy = pcf[k, PC_Y] - q[base + 1]
        w = v[base + 2]
        wk[_W_DX, a] -= sign * w * ux
        wk[_W_DY, a] -= sign * w * uy
        dq[a, a] -= sign * (ux * f_x + uy * f_y)
    if model.pt_i[k, 2] == ANGLE_SLOPE:
        # θ = atan2(g_y, g_x): ∂θ/∂g = (−g_y, g_x)/|g|² with the symmetric Hessian
        # [[2g_xg_y, g_y² − g_x²], [g_y² − g_x², −2g_xg_y]]/|g|⁴, and ω = ∂θ/∂g · ġ
        sl = model.pt_i[k, 3]
        a0 = _cc_index(cc, sl)
        a1 = _cc_index(cc, sl + 1)
        gx = q[sl]
        gy = q[sl + 1]
        g4 = (gx * gx + gy * gy) ** 2
        h00 = 2.0 * gx * gy / g4
        h01 = (gy * gy - gx * gx) / g4
        sr = sign * radius
        wk[_W_OM, a0] += sr * (h00 * v[sl] + h01 * v[sl + 1])
        wk[_W_OM, a1] += sr * (h01 * v[sl] - h00 * v[sl + 1])
        m = sr * f_t
        dq[a0, a0] += m * h00
        dq[a0, a1] += m * h01
        dq[a1, a0] += m * h01
        dq[a1, a1] -= m * h00


@njit_noalloc(error_model="numpy")
def _analytic_derivatives(model, q, v, vimp, cc, pci, pcf, cj0, dq, dv, gt, g, wk):
    """∂Q_cc/∂q_cc, ∂Q_cc/∂q̇_cc and ∂v_t/∂q̇_cc of the dry, unworn journal joints from
    one evaluation (``cj0``, the point cache at (q, q̇)): the contact law's own partials
    (:func:`~mechanism.core.contact.normal_force_derivatives`,
    :func:`~mechanism.core.contact.friction_force_derivatives`) chained with the exact
    derivatives of δ, δ̇, v_t and of the force's direction and point maps."""
    nc = cc.shape[0]
    dq[:, :] = 0.0
    dv[:, :] = 0.0
    for j in range(model.cj_i.shape[0]):
        b = model.cj_i[j, 0]
        jn = model.cj_i[j, 1]
        rb = model.cj_f[j, _CF_RB]
        rj = model.cj_f[j, _CF_RJ]
        ex = cj0[j, _CJ_EX]
        ey = cj0[j, _CJ_EY]
        delta = cj0[j, CJ_DELTA]
        ddot = cj0[j, CJ_DELTA_DOT]
        vt = cj0[j, CJ_VT]
        fn = 0.0
        n_d = 0.0
        n_dd = 0.0
        ft = 0.0
        t_fn = 0.0
        t_vt = 0.0
        if delta > 0.0:
            fn, n_d, n_dd = normal_force_derivatives(
                model.cj_i[j, 2], model.cj_f[j, _CF_K], model.cj_f[j, _CF_EXP],
                model.cj_f[j, _CF_CE], delta, ddot, vimp[j],
            )  # fmt: skip
            if model.cj_i[j, 3] != FRICTION_NONE:
                ft, t_fn, t_vt = friction_force_derivatives(
                    model.cj_i[j, 3], model.cj_f[j, _CF_MU], model.cj_f[j, CF_V0],
                    model.cj_f[j, CF_V1], fn, vt,
                )  # fmt: skip
        ne = math.sqrt(ex * ex + ey * ey)
        if ne > 0.0:
            nx = ex / ne
            ny = ey / ne
        else:
            nx = 1.0
            ny = 0.0
        tx = -ny
        ty = nx
        # force on the journal f = −Fₙ n + F_t t (clearance_force_add)
        f_x = -fn * nx + ft * tx
        f_y = -fn * ny + ft * ty
        for r in range(_W_ROWS):
            for c in range(nc):
                wk[r, c] = 0.0
        _point_maps(model, q, v, cc, pci, pcf, jn, 1.0, rj, g, wk, dq, f_x, f_y, ft)
        _point_maps(model, q, v, cc, pci, pcf, b, -1.0, rb, g, wk, dq, f_x, f_y, ft)
        dvx = pcf[jn, PC_VX] - pcf[b, PC_VX]
        dvy = pcf[jn, PC_VY] - pcf[b, PC_VY]
        slip = dvx * tx + dvy * ty  # ė·t
        for c in range(nc):
            gt[j, c] = tx * wk[_W_EX, c] + ty * wk[_W_EY, c] + wk[_W_TH, c]
        if not (fn > 0.0 or ft != 0.0):
            continue
        for c in range(nc):
            t_e = tx * wk[_W_EX, c] + ty * wk[_W_EY, c]
            n_e = nx * wk[_W_EX, c] + ny * wk[_W_EY, c]
            t_ed = tx * wk[_W_DX, c] + ty * wk[_W_DY, c]
            n_ed = nx * wk[_W_DX, c] + ny * wk[_W_DY, c]
            turn = t_e / ne  # ∂n/∂q_c = t·turn, ∂t/∂q_c = −n·turn
            # position column: δ, δ̇, v_t and the direction move
            dfn = n_d * n_e + n_dd * (n_ed + slip * turn)
            dft = t_fn * dfn + t_vt * (t_ed - ddot * turn + wk[_W_OM, c])
            dfx = -nx * dfn - fn * tx * turn + tx * dft - ft * nx * turn
            dfy = -ny * dfn - fn * ty * turn + ty * dft - ft * ny * turn
            for a in range(nc):
                dq[a, c] += wk[_W_EX, a] * dfx + wk[_W_EY, a] * dfy + wk[_W_TH, a] * dft
            # velocity column: δ̇ and v_t move
            dfn = n_dd * n_e
            dft = t_fn * dfn + t_vt * gt[j, c]
            dfx = -nx * dfn + tx * dft
            dfy = -ny * dfn + ty * dft
            for a in range(nc):
                dv[a, c] += wk[_W_EX, a] * dfx + wk[_W_EY, a] * dfy + wk[_W_TH, a] * dft


@njit_noalloc(error_model="numpy")
def contact_derivatives(model, ws, q, v, vimp, cc, dq, dv, gt, cs):
    """Derivatives of the clearance-joint forces with respect to the coordinates ``cc``
    they read (bearing and journal points): ``dq[a, c] = ∂Q_cc[a]/∂q_cc[c]``,
    ``dv[a, c] = ∂Q_cc[a]/∂q̇_cc[c]`` and ``gt[j, c] = ∂v_t/∂q̇_cc[c]`` of joint j (the
    generalized contact force is nonzero only on ``cc``). When every clearance joint is a
    dry, unworn journal (:func:`analytic_contact_supported`) they are exact, from one
    evaluation of the contact law and its partials (:func:`_analytic_derivatives`);
    otherwise forward differences of the contact forces alone (2·len(cc) + 1
    evaluations). Returns whether any clearance joint is in contact, or floats on an
    engaged oil film, at (q, q̇) (the forces include the film's); zeros when none is.
    ``cs`` holds the scratch (:func:`contact_scratch`), so the call allocates nothing.
    """
    rows, pci, pcf, cj0, cj, cnt, g0, g1, qp, vp, wk, analytic = cs
    nc = cc.shape[0]
    n_cj = ws.cj.shape[0]
    _contact_force(model, q, v, vimp, rows, pci, pcf, g0, cj0, cnt)
    touching = False
    for j in range(n_cj):
        # an engaged oil film is re-linearised like a dry contact (stiff near the wall)
        film = film_engaged(model.cj_f[j, CF_VISC], model.cj_f[j, CF_FILM], cj0[j, CJ_DELTA])
        if cj0[j, CJ_DELTA] > 0.0 or film:
            touching = True
    if not touching:
        dq[:, :] = 0.0
        dv[:, :] = 0.0
        return False
    if analytic:
        g1[:] = 0.0
        _analytic_derivatives(model, q, v, vimp, cc, pci, pcf, cj0, dq, dv, gt, g1, wk)
        return True
    for i in range(q.shape[0]):
        qp[i] = q[i]
        vp[i] = v[i]
    for c in range(nc):
        j = cc[c]
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        _contact_force(model, qp, v, vimp, rows, pci, pcf, g1, cj, cnt)
        qp[j] = q[j]
        for a in range(nc):
            dq[a, c] = (g1[cc[a]] - g0[cc[a]]) / eps
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        _contact_force(model, q, vp, vimp, rows, pci, pcf, g1, cj, cnt)
        vp[j] = v[j]
        for a in range(nc):
            dv[a, c] = (g1[cc[a]] - g0[cc[a]]) / eps
        for jj in range(n_cj):
            gt[jj, c] = (cj[jj, CJ_VT] - cj0[jj, CJ_VT]) / eps
    return True


# A linearisation of the clearance forces is reused while every quantity that sets it
# has moved by less than this fraction of its scale (docs/ancf.md §8)
RELINEARISE = 0.01
LIN_DELTA = 0  # δ, δ̇, v_t, φ_b and the latched impact speed at the last linearisation
LIN_DELTA_DOT = 1
LIN_VT = 2
LIN_PHI = 3
LIN_VIMP = 4
LIN_COLUMNS = 5


@njit_noalloc()
def linearisation_holds(model, cj, vimp, lin):
    """Whether the clearance-force derivatives taken at the state ``lin`` recorded still
    hold at the state of ``cj`` (the last evaluation) to about ``RELINEARISE``: the same
    joints touch with the same latched impact speed, and per touching joint δ, the
    contact angle and δ̇ moved by less than that fraction of δ, of a radian and of
    |δ̇| + the impact speed, and v_t stayed on the same flat side of a regularised friction
    law (|v_t| ≥ v1, one sign) or moved by less than the fraction of v0; a floating
    journal's engaged film thickness and direction by less than that fraction
    (``film_moved``). Worn joints, whose
    stiffness jumps between profile regions, are always re-linearised."""
    for j in range(cj.shape[0]):
        d = cj[j, CJ_DELTA]
        dr = lin[j, LIN_DELTA]
        if not (d > 0.0) == (dr > 0.0) or not vimp[j] == lin[j, LIN_VIMP]:
            return False
        if not d > 0.0:
            if film_moved(
                model.cj_f[j, CF_VISC], model.cj_f[j, CF_FILM], d, dr, cj[j, CJ_PHI_B],
                lin[j, LIN_PHI], RELINEARISE,
            ):  # fmt: skip
                return False
            continue
        if model.cw_i[j, CW_WORN] != 0:
            return False
        if abs(d - dr) > RELINEARISE * dr:
            return False
        if abs(cj[j, CJ_PHI_B] - lin[j, LIN_PHI]) > RELINEARISE:
            return False
        dd = cj[j, CJ_DELTA_DOT]
        ddr = lin[j, LIN_DELTA_DOT]
        if abs(dd - ddr) > RELINEARISE * (abs(ddr) + vimp[j]):
            return False
        if model.cj_i[j, 3] != FRICTION_NONE:
            vt = cj[j, CJ_VT]
            vtr = lin[j, LIN_VT]
            v0 = model.cj_f[j, CF_V0]
            v1 = model.cj_f[j, CF_V1]
            sliding = min(abs(vt), abs(vtr)) >= v1 and vt * vtr > 0.0
            if not sliding and abs(vt - vtr) > RELINEARISE * v0:
                return False
    return True


@njit_noalloc()
def record_linearisation(cj, vimp, lin):
    for j in range(cj.shape[0]):
        lin[j, LIN_DELTA] = cj[j, CJ_DELTA]
        lin[j, LIN_DELTA_DOT] = cj[j, CJ_DELTA_DOT]
        lin[j, LIN_VT] = cj[j, CJ_VT]
        lin[j, LIN_PHI] = cj[j, CJ_PHI_B]
        lin[j, LIN_VIMP] = vimp[j]


@njit(cache=True)
def contact_scratch(model, ws):
    """Scratch of :func:`contact_derivatives`, allocated once per integration call, and
    whether it takes the analytic path (:func:`analytic_contact_supported`)."""
    n = model.n_dof
    return (
        _contact_rows(model), ws.pci.copy(), ws.pcf.copy(), ws.cj.copy(), ws.cj.copy(),
        np.zeros(CNT_COLUMNS, dtype=np.int64), np.empty(n), np.empty(n), np.empty(n),
        np.empty(n), np.zeros((_W_ROWS, n)), analytic_contact_supported(model),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def response_basis(model, ws, cc, basis):
    """``basis[a] = P M⁻¹ e_cc[a]``: the constrained acceleration response to a unit
    generalized force on coordinate cc[a] (factors of the last :func:`accelerations`)."""
    n = basis.shape[1]
    e = np.zeros(n)
    y = np.empty(n)
    u = np.empty(model.n_rows)
    for a in range(cc.shape[0]):
        e[cc[a]] = 1.0
        _project(model, ws, e, basis[a], y, u)
        e[cc[a]] = 0.0


@njit_noalloc(error_model="numpy")
def contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, w, dx):
    """Solve (J₀ + Y Δ Eᵀ) dx = r in place (``dx`` holds r) by Sherman–Morrison–Woodbury:
    J₀ = LU(``jm``, ``piv``), ``zb`` = rows of J₀⁻¹Y, Δ (``delta``, nc × nc) the change of
    the contact-force derivatives and E the selection of the columns ``cc``. Returns False
    if the small capacitance matrix is singular."""
    n = dx.shape[0]
    nc = cc.shape[0]
    lu_solve(jm, piv, dx)
    # (I + Eᵀ Z Δ) w = Eᵀ y, Z = J₀⁻¹Y; then dx = y − Z Δ w
    for a in range(nc):
        for b in range(nc):
            acc = 0.0
            for c in range(nc):
                acc += zb[c, cc[a]] * delta[c, b]
            sm[a, b] = acc
        sm[a, a] += 1.0
        w[a] = dx[cc[a]]
    if not lu_factor(sm, spiv):
        return False
    lu_solve(sm, spiv, w)
    for c in range(nc):
        acc = 0.0
        for b in range(nc):
            acc += delta[c, b] * w[b]
        for i in range(n):
            dx[i] -= zb[c, i] * acc
    return True


@njit(cache=True, error_model="numpy")
def hybrid_jacobian(
    model, ws, t, q, v, vimp, kq, cv, fd_cols, an_cols, counters, velocity_columns=True
):
    """∂q̈/∂q and ∂q̈/∂q̇: forward differences for the columns ``fd_cols`` and, for the
    interior ANCF coordinates ``an_cols`` (no joint or contact point reads them, so they
    enter q̈ only through Q = −F_e − F_d), the exact −P M⁻¹ ∂F/∂q from the analytic
    element Jacobian (docs/ancf.md §8): 2·len(fd_cols) + 1 evaluations instead of 2n + 1.
    With ``velocity_columns`` False the differenced columns of ∂q̈/∂q̇ are left as they
    are (len(fd_cols) + 1 evaluations).
    """
    n = q.shape[0]
    f0 = np.empty(n)
    f1 = np.empty(n)
    accelerations(model, ws, t, q, v, vimp, f0, counters)
    if an_cols.shape[0] > 0:
        kbuf = np.zeros((n, n))
        beams_jacobian_add(model.beam_i, model.beam_f, q, 1.0, 0.0, kbuf)
        _projected_columns(model, ws, kbuf, an_cols, kq)
        damped = False
        for b in range(model.beam_f.shape[0]):
            if model.beam_f[b, BEAM_F_DAMPING] > 0.0:
                damped = True
        if damped:
            kbuf[:, :] = 0.0
            beams_jacobian_add(model.beam_i, model.beam_f, q, 0.0, 1.0, kbuf)
            _projected_columns(model, ws, kbuf, an_cols, cv)
        else:
            # undamped beams: interior velocities do not enter q̈ at all
            for i in range(n):
                for c in range(an_cols.shape[0]):
                    cv[i, an_cols[c]] = 0.0
    qp = q.copy()
    vp = v.copy()
    for c in range(fd_cols.shape[0]):
        j = fd_cols[c]
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        accelerations(model, ws, t, qp, v, vimp, f1, counters)
        qp[j] = q[j]
        for i in range(n):
            kq[i, j] = (f1[i] - f0[i]) / eps
    if not velocity_columns:
        counters[CNT_JAC] += 1
        return
    for c in range(fd_cols.shape[0]):
        j = fd_cols[c]
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        accelerations(model, ws, t, q, vp, vimp, f1, counters)
        vp[j] = v[j]
        for i in range(n):
            cv[i, j] = (f1[i] - f0[i]) / eps
    counters[CNT_JAC] += 1
