"""Compiled Dormand–Prince 5(4) of a state and its deviation (largest Lyapunov exponent).

A reference state y and a deviation d are advanced by the *same* Runge–Kutta steps. At
every stage the deviation's rate is the directional derivative of the compiled
right-hand side f along d, by finite differences (the tangent map computed by finite
differences, Parker & Chua 1989, §3.4), taken in two parts so that each is well above
round-off and inside the linear regime:

    d' ≈ [f(t, y + c_q d_q) − f(t, y)]/c_q + [f(t, y + c_v d_v) − f(t, y)]/c_v,

d_q and d_v the position and velocity parts of d, each scaled (c_q, c_v) to the size
``size`` in the mass-weighted norm (the position rows are exact: d_q' = d_v). A
deviation of a stiff contact is mostly velocity; evaluated as it is, its position part
can be a few ulps of the coordinates. Each shifted state is evaluated on the reference's
branch of the contact law (in or out of contact, zone of the friction ramp, clamped
force, bounded approach speed): when it lies on another one, the
difference is taken on the reference's side, f(y) − f(y − c·part), the one-sided
derivative of the reference's piece.

The contact state (the impact-velocity latch and the in-contact flags) is decided by the
reference at the accepted steps; the latched impact velocity has its own deviation
(its derivative along d when latched, frozen in contact), part of the linearised state:
it is rescaled with d at every renormalisation.

Step size and accept/reject follow the reference's error estimate and, with
``deviation_rtol`` > 0, the deviation's own (relative to its size): without it, where
the reference rides a stiff friction ramp at the explicit method's stability limit, the
deviation grows by the integrator's amplification, not the mechanism's (Benettin et al.
1980).

Every ``every`` accepted steps (and at each chunk end) the deviation is projected onto
the tangent space of the constraint manifold and rescaled to its initial size; the log of
the growth factor is accumulated.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mechanism.core._jit import njit_noalloc
from mechanism.core.contact._kernels import APPROACH_BOUNDED, APPROACH_RATIO, FRICTION_AMBROSIO
from mechanism.core.joints._kernels import update_points
from mechanism.core.model._kernels import (
    CF_FLOOR,
    CF_V0,
    CF_V1,
    CJ_DELTA,
    CJ_DELTA_DOT,
    CJ_FN,
    CJ_VT,
    CNT_CONTACT_EVENTS,
    CNT_REJECTED,
    CNT_STEPS,
    STATUS_OK,
    _cholesky_solve,
    _clearance_state,
    _schur,
    approach_step,
    evaluate_constraints,
    project,
    rhs,
)

from ._kernels import (
    A21,
    A31,
    A32,
    A41,
    A42,
    A43,
    A51,
    A52,
    A53,
    A54,
    A61,
    A62,
    A63,
    A64,
    A65,
    A71,
    A73,
    A74,
    A75,
    A76,
    C2,
    C3,
    C4,
    C5,
    E1,
    E3,
    E4,
    E5,
    E6,
    E7,
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
    _wrms,
    deviation_size,
)

_EPS = 2.220446049250313e-16
# largest coordinate change (m or rad) of the finite difference of Φq q̇ + Φt along δq
_G_STEP = 1e-7

# ``growth`` (float64[GROWTH_COLUMNS]) accumulated by :func:`tangent_advance`
GROWTH_LOG = 0  # Σ ln(|d| / size) over the renormalisations
GROWTH_COUNT = 1  # renormalisations done
GROWTH_LAST_T = 2  # time of the last renormalisation
GROWTH_COLUMNS = 3


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


@njit_noalloc()
def part_norms(model, d, inv_mass):
    """(√(δqᵀMδq/m), √(δq̇ᵀMδq̇/m)): the mass-weighted sizes of the position part (m) and
    of the velocity part (m/s) of a deviation."""
    n = model.n_dof
    sq = 0.0
    sv = 0.0
    for i in range(n):
        xq = 0.0
        xv = 0.0
        for j in range(model.blk_lo[i], model.blk_hi[i]):
            xq += model.mass[i, j] * d[j]
            xv += model.mass[i, j] * d[n + j]
        sq += d[i] * xq
        sv += d[n + i] * xv
    return math.sqrt(max(sq, 0.0) * inv_mass), math.sqrt(max(sv, 0.0) * inv_mass)


@njit_noalloc()
def _shift(y, d, lo, hi, c, out):
    """out = y with c·d added to the components lo:hi."""
    for i in range(y.shape[0]):
        out[i] = y[i]
    for i in range(lo, hi):
        out[i] = y[i] + c * d[i]


@njit_noalloc()
def latch_pair(model, ws, ws2, y, d, vimp, dvimp, contact, counters, yp, size, tau, inv_mass):
    """Contact state after an accepted step, decided by the reference ``y``, and the
    deviation ``dvimp`` of the latched impact velocity.

    Like :func:`mechanism.core.model._kernels.update_latch`: a joint the reference sees
    penetrating is in contact (latch and its deviation frozen; an event counted on entry);
    one it sees separated tracks the approach speed δ̇, floored at
    ``impact_velocity_floor``. The latch's deviation is the derivative of that value along
    ``d`` on the reference's branch: (∂δ̇/∂y)·d by finite differences (the position and
    the velocity part of d each scaled to ``size``, as in :func:`_deviation_rate`), 0 when
    the reference is held at the floor.
    """
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return
    n = model.n_dof
    n2 = y.shape[0]
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    tracking = False
    for j in range(ncj):
        delta, ddot, _ = _clearance_state(model, ws, y, j)
        if delta > 0.0:
            if contact[j] == 0:
                contact[j] = 1
                counters[CNT_CONTACT_EVENTS] += 1
        else:
            contact[j] = 0
            floor = model.cj_f[j, CF_FLOOR]
            dvimp[j] = 0.0
            if ddot > floor:
                vimp[j] = ddot
                tracking = True
            else:
                vimp[j] = floor
    if not tracking:
        return
    pq, pv = part_norms(model, d, inv_mass)
    for half in range(2):
        if half == 0:
            if not pq > 0.0:
                continue
            c = size / pq
            _shift(y, d, 0, n, c, yp)
        else:
            if not pv > 0.0:
                continue
            c = size / (tau * pv)
            _shift(y, d, n, n2, c, yp)
        update_points(yp[:n], yp[n:], model.pt_i, model.pt_f, ws2.pci, ws2.pcf)
        for j in range(ncj):
            if contact[j] != 0 or not vimp[j] > model.cj_f[j, CF_FLOOR]:
                continue
            _, ddot, _ = _clearance_state(model, ws, y, j)
            _, ddot_p, _ = _clearance_state(model, ws2, yp, j)
            dvimp[j] += (ddot_p - ddot) / c


@njit_noalloc()
def _branch(model, cj, j, vimp):
    """Which smooth piece of the contact law clearance joint ``j`` is on, from its row of
    ``ws.cj`` after an evaluation with latched impact velocity ``vimp``: 0 separated,
    else 1 + 2 × friction zone of the Ambrósio law (0 below v0, 1 on the ramp, 2 above
    v1) + 8 if the force is clamped at 0 + 16 if the bounded approach speed is active."""
    if not cj[j, CJ_DELTA] > 0.0:
        return 0.0
    code = 1.0
    if model.cj_i[j, 3] == FRICTION_AMBROSIO:
        speed = abs(cj[j, CJ_VT])
        if speed > model.cj_f[j, CF_V0]:
            code += 2.0
        if speed >= model.cj_f[j, CF_V1]:
            code += 2.0
    if cj[j, CJ_FN] == 0.0:
        code += 8.0
    if (model.cj_i[j, 2] & APPROACH_BOUNDED) != 0 and cj[j, CJ_DELTA_DOT] > APPROACH_RATIO * vimp:
        code += 16.0
    return code


@njit_noalloc()
def _same_branch(model, ws, vimp_p, ref):
    """Whether the last evaluation in ``ws`` lies on the reference's branches ``ref``
    (one :func:`_branch` code per clearance joint)."""
    for j in range(ref.shape[0]):
        if _branch(model, ws.cj, j, vimp_p[j]) != ref[j]:
            return False
    return True


@njit_noalloc()
def _half_rate(model, ws, t, ys, ds, lo, hi, c, f_ref, vimp, dvimp, latch, vimp_p, yp, fp, kd,
               ref, counters_p):  # fmt: skip
    """Add (a(ys + c·ds[lo:hi]) − a(ys))/c to the acceleration rows of ``kd``, on the
    reference's branch (mirrored, (a(ys) − a(ys − c·ds[lo:hi]))/c, when the shifted state
    is on another one); with ``latch`` the latched impact velocity is shifted by c·dvimp."""
    n2 = ys.shape[0]
    n = n2 // 2
    sign = 1.0
    while True:
        _shift(ys, ds, lo, hi, sign * c, yp)
        for j in range(vimp.shape[0]):
            vimp_p[j] = vimp[j] + sign * c * dvimp[j] if latch else vimp[j]
        st = rhs(model, ws, t, yp, vimp_p, fp, counters_p)
        if sign < 0.0 or _same_branch(model, ws, vimp_p, ref):
            break
        sign = -1.0
    for i in range(n, n2):
        kd[i] += sign * (fp[i] - f_ref[i]) / c
    return st


@njit_noalloc()
def _deviation_rate(model, ws, t, ys, ds, f_ref, vimp, dvimp, vimp_p, yp, fp, kd, ref,
                    fresh, size, tau, inv_mass, counters_p):  # fmt: skip
    """kd = (∂f/∂y)(t, ys)·ds + (∂f/∂δ̇⁻)·dvimp, f_ref = f(t, ys), by finite differences.

    The position rows are exact (kd_q = ds_q̇). The acceleration rows are the sum of two
    one-sided directional differences, one along the position part of ``ds`` and one
    along its velocity part (with the latch deviation ``dvimp``), each scaled so that its
    mass-weighted size is ``size`` (m; the velocity part's τ|δq̇| = ``size``), and the
    results scaled back. Linear in ds to first order, and each difference is well above
    round-off: the deviation of a stiff contact is mostly velocity, its position part
    can be 1e-5 of its size, a few ulps of the coordinates if it were evaluated as it is.

    Each shifted state is evaluated on the reference's branch of the contact law (contact,
    friction-ramp zone, clamp, approach bound; :func:`_same_branch`):
    when it lies on another one, the difference is taken on the reference's side,
    (f(ys) − f(ys − c·part))/c, so the deviation follows the one-sided derivative of the
    reference's piece, never the kink or the jump between pieces.

    With ``fresh`` the last evaluation in ``ws`` was f(t, ys) and its branches are stored
    in ``ref``; otherwise ``ref`` already holds them.
    """
    n2 = ys.shape[0]
    n = n2 // 2
    if fresh:
        for j in range(ref.shape[0]):
            ref[j] = _branch(model, ws.cj, j, vimp[j])
    for i in range(n):
        kd[i] = ds[n + i]
        kd[n + i] = 0.0
    pq, pv = part_norms(model, ds, inv_mass)
    st = STATUS_OK
    if pq > 0.0:
        st |= _half_rate(
            model, ws, t, ys, ds, 0, n, size / pq, f_ref, vimp, dvimp, False, vimp_p, yp, fp,
            kd, ref, counters_p,
        )  # fmt: skip
    if pv > 0.0:
        st |= _half_rate(
            model, ws, t, ys, ds, n, n2, size / (tau * pv), f_ref, vimp, dvimp, True, vimp_p,
            yp, fp, kd, ref, counters_p,
        )  # fmt: skip
    return st


@njit(cache=True)
def tangent_start(model, ws, t, y, d, k1, kd1, vimp, dvimp, counters, counters_p, size, tau,
                  inv_mass):  # fmt: skip
    """k1 = f(t, y) and kd1 = the deviation's rate (:func:`_deviation_rate`); returns a
    status."""
    st = rhs(model, ws, t, y, vimp, k1, counters)
    if st != STATUS_OK:
        return st
    yp = np.empty_like(y)
    fp = np.empty_like(y)
    ref = np.empty(model.cj_i.shape[0])
    vimp_p = np.empty_like(vimp)
    st = _deviation_rate(
        model, ws, t, y, d, k1, vimp, dvimp, vimp_p, yp, fp, kd1, ref, True,
        size, tau, inv_mass, counters_p,
    )  # fmt: skip
    return STATUS_RUNNING if st == STATUS_OK else st


@njit_noalloc()
def renormalize(model, ws, ws2, t, y, d, dvimp, scratch, size, tau2, inv_mass, growth):
    """Project ``d`` onto the constraint tangent, add ln(|d|/size) to ``growth`` and
    rescale d and the latch deviation ``dvimp`` (part of the linearised state) to
    ``size``. Returns False on a singular constraint matrix or a zero or non-finite
    deviation."""
    if not project_tangent(model, ws, ws2, t, y, d, scratch):
        return False
    r = deviation_size(model, d, tau2, inv_mass)
    if not (r > 0.0 and math.isfinite(r)):
        return False
    growth[GROWTH_LOG] += math.log(r / size)
    growth[GROWTH_COUNT] += 1.0
    growth[GROWTH_LAST_T] = t
    f = size / r
    for i in range(d.shape[0]):
        d[i] *= f
    for j in range(dvimp.shape[0]):
        dvimp[j] *= f
    return True


@njit(cache=True, nogil=True)
def tangent_advance(
    model,
    ws,
    ws2,
    y,
    d,
    k1,
    kd1,
    state,
    vimp,
    dvimp,
    contact,
    counters,
    counters_p,
    growth,
    t_stop,
    t_end,
    rtol,
    atol,
    max_step,
    projection,
    max_steps,
    every,
    size,
    tau2,
    inv_mass,
    approach_floor,
    approach_fraction,
    deviation_rtol,
    chunk_steps,
):
    """Advance reference and deviation to ``t_stop`` (≤ ``t_end``), landing on it, and
    renormalise there.

    With ``deviation_rtol`` = 0 the reference is stepped exactly as
    :func:`mechanism.core.integrate._kernels.dopri5_advance` steps it (same controller,
    error norm, maximum step, approach bound of the clearance joints, latch and optional
    projection) and the deviation rides along; with ``deviation_rtol`` > 0 the error
    passed to the controller is the larger of the reference's and the deviation's
    (its embedded error estimate in the mass-weighted norm over ``deviation_rtol`` × its
    size). Every ``every`` accepted steps, and at the end, the
    deviation is renormalised (:func:`renormalize`). ``state`` = [t, h, facold, last step
    rejected, accepted steps since the last renormalisation]. Returns ``STATUS_RUNNING``
    when ``t_stop`` < ``t_end`` was reached, or after ``chunk_steps`` (> 0) attempted steps
    with ``state[0]`` < ``t_stop`` (the next call continues bit for bit), 0 at ``t_end``,
    or a negative failure status.
    """
    n2 = y.shape[0]
    k2 = np.empty(n2)
    k3 = np.empty(n2)
    k4 = np.empty(n2)
    k5 = np.empty(n2)
    k6 = np.empty(n2)
    k7 = np.empty(n2)
    kd2 = np.empty(n2)
    kd3 = np.empty(n2)
    kd4 = np.empty(n2)
    kd5 = np.empty(n2)
    kd6 = np.empty(n2)
    kd7 = np.empty(n2)
    ytmp = np.empty(n2)
    dtmp = np.empty(n2)
    ynew = np.empty(n2)
    dnew = np.empty(n2)
    yp = np.empty(n2)
    fp = np.empty(n2)
    err = np.empty(n2)
    scratch = np.empty(n2)
    ref = np.empty(model.cj_i.shape[0])
    vimp_p = np.empty_like(vimp)
    tau = math.sqrt(tau2)
    beta = 0.04
    expo1 = 0.2 - beta * 0.75
    t = state[0]
    h = state[1]
    facold = state[2]
    last_rejected = state[3] > 0.0
    since = int(state[4])
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while True:
        if t >= t_end:
            status = STATUS_OK
            break
        if t >= t_stop:
            break
        if counters[CNT_STEPS] + counters[CNT_REJECTED] >= max_steps:
            status = STATUS_MAX_STEPS
            break
        if 0 < chunk_steps <= counters[CNT_STEPS] + counters[CNT_REJECTED] - attempted:
            break  # back to Python, which checks for Ctrl-C and calls again
        h = min(h, max_step)
        if approach_floor > 0.0:
            near = approach_step(model, ws, y, k1[n2 // 2 :], approach_fraction)
            h = min(h, max(approach_floor, near))
        # land on the stop time, so segments are exact (e.g. drive periods)
        if t + 1.01 * h >= t_stop:
            h = t_stop - t
        if h < 10.0 * _EPS * max(abs(t), 1e-300) or h <= 0.0:
            status = STATUS_STEP_TOO_SMALL
            break
        st = STATUS_OK
        for i in range(n2):
            ytmp[i] = y[i] + h * A21 * k1[i]
            dtmp[i] = d[i] + h * A21 * kd1[i]
        st |= rhs(model, ws, t + C2 * h, ytmp, vimp, k2, counters)
        st |= _deviation_rate(
            model, ws, t + C2 * h, ytmp, dtmp, k2, vimp, dvimp, vimp_p, yp, fp, kd2,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i])
            dtmp[i] = d[i] + h * (A31 * kd1[i] + A32 * kd2[i])
        st |= rhs(model, ws, t + C3 * h, ytmp, vimp, k3, counters)
        st |= _deviation_rate(
            model, ws, t + C3 * h, ytmp, dtmp, k3, vimp, dvimp, vimp_p, yp, fp, kd3,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
            dtmp[i] = d[i] + h * (A41 * kd1[i] + A42 * kd2[i] + A43 * kd3[i])
        st |= rhs(model, ws, t + C4 * h, ytmp, vimp, k4, counters)
        st |= _deviation_rate(
            model, ws, t + C4 * h, ytmp, dtmp, k4, vimp, dvimp, vimp_p, yp, fp, kd4,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
            dtmp[i] = d[i] + h * (A51 * kd1[i] + A52 * kd2[i] + A53 * kd3[i] + A54 * kd4[i])
        st |= rhs(model, ws, t + C5 * h, ytmp, vimp, k5, counters)
        st |= _deviation_rate(
            model, ws, t + C5 * h, ytmp, dtmp, k5, vimp, dvimp, vimp_p, yp, fp, kd5,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (
                A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]
            )
            dtmp[i] = d[i] + h * (
                A61 * kd1[i] + A62 * kd2[i] + A63 * kd3[i] + A64 * kd4[i] + A65 * kd5[i]
            )
        st |= rhs(model, ws, t + h, ytmp, vimp, k6, counters)
        st |= _deviation_rate(
            model, ws, t + h, ytmp, dtmp, k6, vimp, dvimp, vimp_p, yp, fp, kd6,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ynew[i] = y[i] + h * (
                A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]
            )
            dnew[i] = d[i] + h * (
                A71 * kd1[i] + A73 * kd3[i] + A74 * kd4[i] + A75 * kd5[i] + A76 * kd6[i]
            )
        st |= rhs(model, ws, t + h, ynew, vimp, k7, counters)
        st |= _deviation_rate(
            model, ws, t + h, ynew, dnew, k7, vimp, dvimp, vimp_p, yp, fp, kd7,
            ref, True, size, tau, inv_mass, counters_p,
        )  # fmt: skip
        if st != STATUS_OK:
            status = STATUS_SINGULAR
            break
        for i in range(n2):
            err[i] = h * (
                E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]
            )
        e = _wrms(err, y, ynew, rtol, atol)
        if deviation_rtol > 0.0:
            # the deviation's own error estimate, relative to its size
            for i in range(n2):
                err[i] = h * (
                    E1 * kd1[i]
                    + E3 * kd3[i]
                    + E4 * kd4[i]
                    + E5 * kd5[i]
                    + E6 * kd6[i]
                    + E7 * kd7[i]
                )
            scale = max(deviation_size(model, d, tau2, inv_mass),
                        deviation_size(model, dnew, tau2, inv_mass))  # fmt: skip
            e = max(e, deviation_size(model, err, tau2, inv_mass) / (deviation_rtol * scale))
        if not math.isfinite(e):
            counters[CNT_REJECTED] += 1
            h *= 0.1
            last_rejected = True
            continue
        fac11 = e**expo1
        if e <= 1.0:
            t = t + h
            if abs(t_stop - t) < 4.0 * _EPS * max(abs(t_stop), 1.0):
                t = t_stop
            for i in range(n2):
                y[i] = ynew[i]
                d[i] = dnew[i]
                k1[i] = k7[i]
            counters[CNT_STEPS] += 1
            latch_pair(model, ws, ws2, y, d, vimp, dvimp, contact, counters, yp, size, tau,
                       inv_mass)  # fmt: skip
            if projection:
                if not project(model, ws, t, y, 1e-12, 5):
                    status = STATUS_SINGULAR
                    break
                rhs(model, ws, t, y, vimp, k1, counters)
            since += 1
            if since >= every or t >= t_stop or t >= t_end:
                if not renormalize(model, ws, ws2, t, y, d, dvimp, scratch, size, tau2,
                                   inv_mass, growth):  # fmt: skip
                    status = STATUS_NONFINITE
                    break
                since = 0
            # the latch's deviation (or the projection) may have changed the rate; ref
            # holds the reference's branches at y from the last stage (or from the
            # evaluation after a projection)
            st = _deviation_rate(
                model, ws, t, y, d, k1, vimp, dvimp, vimp_p, yp, fp, kd1, ref, projection,
                size, tau, inv_mass, counters_p,
            )  # fmt: skip
            if st != STATUS_OK:
                status = STATUS_SINGULAR
                break
            fac = fac11 / facold**beta
            fac = max(0.1, min(5.0, fac / 0.9))
            hnew = h / fac
            facold = max(e, 1e-4)
            if last_rejected:
                hnew = min(hnew, h)
            last_rejected = False
            h = hnew
        else:
            counters[CNT_REJECTED] += 1
            h = h / min(5.0, fac11 / 0.9)
            last_rejected = True
    state[0] = t
    state[1] = h
    state[2] = facold
    state[3] = 1.0 if last_rejected else 0.0
    state[4] = float(since)
    return status
