"""Compiled Dormand–Prince 5(4) of a state and its deviation (largest Lyapunov exponent).

A reference state y and a small deviation d are advanced by the *same* Runge–Kutta steps:
every stage evaluates the compiled right-hand side f at the reference stage value y_s and at
y_s + d_s, and the deviation's stage derivative is their difference,

    d' ≈ f(t, y + d) − f(t, y)       (a directional finite difference of f along d),

so d follows the variational equation d' = (∂f/∂y) d to first order in |d|. Step size and
accept/reject are decided from the reference's error estimate alone, and the contact
state (the impact-velocity latch and the in-contact flags) is advanced from the reference
at the same accepted steps: the two states never differ by their step sequence or by when
an impact is counted, only by the dynamics (Benettin et al. 1980; the tangent map computed
by finite differences, Parker & Chua 1989, §3.4). Each copy keeps its own latched impact
velocity (its own approach speed at the accepted step the reference last saw separated),
so the dependence of the damping on the approach speed is part of the deviation.

Every ``every`` accepted steps (and at each chunk end) the deviation is projected onto
the tangent space of the constraint manifold and rescaled to its initial size; the log of
the growth factor is accumulated.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mechanism.core._jit import njit_noalloc
from mechanism.core.joints._kernels import update_points
from mechanism.core.model._kernels import (
    CF_FLOOR,
    CJ_PHI_B,
    CJ_PHI_J,
    CNT_CONTACT_EVENTS,
    CNT_REJECTED,
    CNT_STEPS,
    CW_B_N,
    CW_J_N,
    CW_WORN,
    STATUS_OK,
    _cholesky_solve,
    _clearance_state,
    _schur,
    approach_step,
    evaluate_constraints,
    project,
    rhs,
)
from mechanism.core.wear._kernels import region_index

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


@njit_noalloc()
def latch_pair(model, ws, ws2, y, yp, vimp, vimp_p, contact, counters):
    """Contact state after an accepted step, decided by the reference ``y``.

    Like :func:`mechanism.core.model._kernels.update_latch`: a joint the reference sees penetrating
    is in contact (both latches frozen; an event counted on entry); one it sees separated
    tracks the approach speed, each copy its own (``vimp`` from y, ``vimp_p`` from the
    perturbed state ``yp``), floored at ``impact_velocity_floor``.
    """
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return
    n = model.n_dof
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    update_points(yp[:n], yp[n:], model.pt_i, model.pt_f, ws2.pci, ws2.pcf)
    for j in range(ncj):
        delta, ddot, _ = _clearance_state(model, ws, y, j)
        if delta > 0.0:
            if contact[j] == 0:
                contact[j] = 1
                counters[CNT_CONTACT_EVENTS] += 1
        else:
            contact[j] = 0
            floor = model.cj_f[j, CF_FLOOR]
            vimp[j] = ddot if ddot > floor else floor
            _, ddot_p, _ = _clearance_state(model, ws2, yp, j)
            vimp_p[j] = ddot_p if ddot_p > floor else floor


@njit_noalloc()
def has_worn(model):
    """Whether any clearance joint of the model carries a worn profile."""
    for j in range(model.cw_i.shape[0]):
        if model.cw_i[j, CW_WORN] != 0:
            return True
    return False


@njit_noalloc()
def _same_regions(model, ws, phi):
    """Whether the contact directions in ``ws.cj`` fall in the same worn-profile regions as
    ``phi`` (n_cj, 2) on every worn surface."""
    cw_i = model.cw_i
    for j in range(cw_i.shape[0]):
        if cw_i[j, CW_WORN] == 0:
            continue
        nb = cw_i[j, CW_B_N]
        if nb > 0 and region_index(ws.cj[j, CJ_PHI_B], nb) != region_index(phi[j, 0], nb):
            return False
        nj = cw_i[j, CW_J_N]
        if nj > 0 and region_index(ws.cj[j, CJ_PHI_J], nj) != region_index(phi[j, 1], nj):
            return False
    return True


@njit_noalloc()
def _deviation_rate(model, ws, t, ys, ds, f_ref, vimp, vimp_p, vimp_m, yp, fp, kd, phi, worn,
                    fresh, counters_p):  # fmt: skip
    """kd = f(t, ys + ds) − f_ref, f_ref = f(t, ys).

    With ``fresh`` the last evaluation in ``ws`` was f(t, ys) and its contact directions are
    copied to ``phi``; otherwise ``phi`` already holds them.

    On a worn profile (``worn``) the depths are tabulated per region, so the clearance jumps
    where the contact direction crosses a region boundary. When the perturbed state lies in
    another region than the reference, the difference is taken on the reference's side,
    kd = f_ref − f(t, ys − ds): the deviation sees the profile's slope, never the jump of
    its tabulation.
    """
    n2 = ys.shape[0]
    if worn and fresh:
        for j in range(phi.shape[0]):
            phi[j, 0] = ws.cj[j, CJ_PHI_B]
            phi[j, 1] = ws.cj[j, CJ_PHI_J]
    for i in range(n2):
        yp[i] = ys[i] + ds[i]
    st = rhs(model, ws, t, yp, vimp_p, fp, counters_p)
    if worn and not _same_regions(model, ws, phi):
        for i in range(n2):
            yp[i] = ys[i] - ds[i]
        # the mirrored copy's latch: the perturbed one reflected through the reference's
        for j in range(vimp.shape[0]):
            vimp_m[j] = 2.0 * vimp[j] - vimp_p[j]
        st = rhs(model, ws, t, yp, vimp_m, fp, counters_p)
        for i in range(n2):
            kd[i] = f_ref[i] - fp[i]
        return st
    for i in range(n2):
        kd[i] = fp[i] - f_ref[i]
    return st


@njit(cache=True)
def tangent_start(model, ws, t, y, d, k1, kd1, vimp, vimp_p, counters, counters_p):
    """k1 = f(t, y) and kd1 = f(t, y + d) − k1; returns a status."""
    st = rhs(model, ws, t, y, vimp, k1, counters)
    if st != STATUS_OK:
        return st
    yp = np.empty_like(y)
    fp = np.empty_like(y)
    phi = np.empty((model.cj_i.shape[0], 2))
    vimp_m = np.empty_like(vimp)
    st = _deviation_rate(
        model, ws, t, y, d, k1, vimp, vimp_p, vimp_m, yp, fp, kd1, phi, has_worn(model), True,
        counters_p,
    )  # fmt: skip
    return STATUS_RUNNING if st == STATUS_OK else st


@njit_noalloc()
def renormalize(model, ws, ws2, t, y, d, scratch, size, tau2, inv_mass, growth):
    """Project ``d`` onto the constraint tangent, add ln(|d|/size) to ``growth`` and
    rescale d to ``size``. Returns False on a singular constraint matrix or a zero or
    non-finite deviation."""
    if not project_tangent(model, ws, ws2, t, y, d, scratch):
        return False
    r = deviation_norm(model, d, tau2, inv_mass)
    if not (r > 0.0 and math.isfinite(r)):
        return False
    growth[GROWTH_LOG] += math.log(r / size)
    growth[GROWTH_COUNT] += 1.0
    growth[GROWTH_LAST_T] = t
    f = size / r
    for i in range(d.shape[0]):
        d[i] *= f
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
    vimp_p,
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
):
    """Advance reference and deviation to ``t_stop`` (≤ ``t_end``), landing on it, and
    renormalise there.

    The reference is stepped exactly as :func:`mechanism.core.integrate._kernels.dopri5_advance`
    steps it (same controller, error norm, maximum step, approach bound of the clearance
    joints, latch and optional projection);
    the deviation rides along. Every ``every`` accepted steps, and at the end, the
    deviation is renormalised (:func:`renormalize`). ``state`` = [t, h, facold, last step
    rejected, accepted steps since the last renormalisation]. Returns ``STATUS_RUNNING``
    when ``t_stop`` < ``t_end`` was reached, 0 at ``t_end``, or a negative failure status.
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
    phi = np.empty((model.cj_i.shape[0], 2))
    vimp_m = np.empty_like(vimp)
    worn = has_worn(model)
    beta = 0.04
    expo1 = 0.2 - beta * 0.75
    t = state[0]
    h = state[1]
    facold = state[2]
    last_rejected = state[3] > 0.0
    since = int(state[4])
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
            model, ws, t + C2 * h, ytmp, dtmp, k2, vimp, vimp_p, vimp_m, yp, fp, kd2, phi,
            worn, True, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i])
            dtmp[i] = d[i] + h * (A31 * kd1[i] + A32 * kd2[i])
        st |= rhs(model, ws, t + C3 * h, ytmp, vimp, k3, counters)
        st |= _deviation_rate(
            model, ws, t + C3 * h, ytmp, dtmp, k3, vimp, vimp_p, vimp_m, yp, fp, kd3, phi,
            worn, True, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
            dtmp[i] = d[i] + h * (A41 * kd1[i] + A42 * kd2[i] + A43 * kd3[i])
        st |= rhs(model, ws, t + C4 * h, ytmp, vimp, k4, counters)
        st |= _deviation_rate(
            model, ws, t + C4 * h, ytmp, dtmp, k4, vimp, vimp_p, vimp_m, yp, fp, kd4, phi,
            worn, True, counters_p,
        )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
            dtmp[i] = d[i] + h * (A51 * kd1[i] + A52 * kd2[i] + A53 * kd3[i] + A54 * kd4[i])
        st |= rhs(model, ws, t + C5 * h, ytmp, vimp, k5, counters)
        st |= _deviation_rate(
            model, ws, t + C5 * h, ytmp, dtmp, k5, vimp, vimp_p, vimp_m, yp, fp, kd5, phi,
            worn, True, counters_p,
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
            model, ws, t + h, ytmp, dtmp, k6, vimp, vimp_p, vimp_m, yp, fp, kd6, phi,
            worn, True, counters_p,
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
            model, ws, t + h, ynew, dnew, k7, vimp, vimp_p, vimp_m, yp, fp, kd7, phi,
            worn, True, counters_p,
        )  # fmt: skip
        if st != STATUS_OK:
            status = STATUS_SINGULAR
            break
        for i in range(n2):
            err[i] = h * (
                E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]
            )
        e = _wrms(err, y, ynew, rtol, atol)
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
            for i in range(n2):
                yp[i] = y[i] + d[i]
            latch_pair(model, ws, ws2, y, yp, vimp, vimp_p, contact, counters)
            if projection:
                if not project(model, ws, t, y, 1e-12, 5):
                    status = STATUS_SINGULAR
                    break
                rhs(model, ws, t, y, vimp, k1, counters)
            since += 1
            if since >= every or t >= t_stop or t >= t_end:
                if not renormalize(model, ws, ws2, t, y, d, scratch, size, tau2, inv_mass,
                                   growth):  # fmt: skip
                    status = STATUS_NONFINITE
                    break
                since = 0
            # the perturbed copy's latch (or the rescaling) may have changed its rate
            # phi holds the reference's contact directions at y from the last stage (or
            # from the evaluation after a projection)
            st = _deviation_rate(
                model, ws, t, y, d, k1, vimp, vimp_p, vimp_m, yp, fp, kd1, phi, worn, projection,
                counters_p,
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
