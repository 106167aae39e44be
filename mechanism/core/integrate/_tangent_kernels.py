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

With ``directional`` the two parts are taken as one difference along the whole deviation,
f(t, y + c d) − f(t, y), one evaluation per stage instead of two: c scales the smaller
part to ``size`` as long as the larger one stays within ``DIRECTIONAL_REACH`` × ``size``
(inside the linear regime measured in docs/mechanism-lyapunov.md §3), so both parts move
the coordinates far above round-off, and the deviation's rate at the start of a step is
the last stage's of the step before (first same as last) unless a renormalisation or a
projection moved it.

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

Flexible models (generalized-α): a perturbed copy (:class:`Deviation`) takes every
accepted step of the reference again from y + d with its own implicit solve
(:func:`deviation_step`, the LU and contact Newton solve of ``_newton_kernels.py``),
its ANCF elastic and damping forces the reference's plus their central difference along
d (:func:`copy_accelerations`); ``genalpha_advance`` calls it, and
:func:`deviation_renormalize` rescales d every ``every`` accepted steps.
"""

from __future__ import annotations

import math
from typing import (
    Any,
    NamedTuple,
)

import numpy as np
from numba import (
    njit,
)

from mechanism.core._jit import (
    njit_noalloc,
)
from mechanism.core._status import (
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.bodies import (
    beams_force_add,
)
from mechanism.core.contact import (
    APPROACH_BOUNDED,
    APPROACH_RATIO,
    FRICTION_AMBROSIO,
)
from mechanism.core.forces import (
    force_elements_add,
)
from mechanism.core.joints import (
    constraint_rows,
    update_point_rows,
    update_points,
)
from mechanism.core.model import (
    CF_FLOOR,
    CF_V0,
    CF_V1,
    CJ_DELTA,
    CJ_DELTA_DOT,
    CJ_FN,
    CJ_VT,
    CNT_COLUMNS,
    CNT_CONTACT_EVENTS,
    CNT_FEV,
    CNT_REJECTED,
    CNT_STEPS,
    CW_WORN,
    approach_step,
    cholesky_solve,
    clearance_forces,
    clearance_state,
    evaluate_constraints,
    project,
    rhs,
    schur,
    solve,
)

from ._dopri_kernels import (
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
    wrms,
)
from ._newton_kernels import (
    contact_derivatives,
    contact_newton_solve,
    lu_factor,
    lu_solve,
)
from ._step_kernels import (
    chunk_end,
    next_step_size,
)

_EPS = 2.220446049250313e-16
# largest coordinate change (m or rad) of the finite difference of Φq q̇ + Φt along δq
_G_STEP = 1e-7

#: directional difference (``directional``): the larger of the deviation's two parts (position,
#: velocity; mass-weighted sizes) is shifted by at most this multiple of ``size``, so that
#: the smaller one still moves the coordinates far above their round-off
DIRECTIONAL_REACH = 10.0

# ``growth`` (float64[GROWTH_COLUMNS]) accumulated by :func:`tangent_advance`
GROWTH_LOG = 0  # Σ ln(|d| / size) over the renormalisations
GROWTH_COUNT = 1  # renormalisations done
GROWTH_LAST_T = 2  # time of the last renormalisation
GROWTH_COLUMNS = 3


@njit_noalloc()
def _next_time(schedule, t):
    """The first time of the increasing ``schedule`` after ``t`` (+inf past its end)."""
    lo = 0
    hi = schedule.shape[0]
    while lo < hi:
        mid = (lo + hi) // 2
        if schedule[mid] > t:
            hi = mid
        else:
            lo = mid + 1
    return schedule[lo] if lo < schedule.shape[0] else np.inf


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
    schur(model, ws)
    for k in range(m):
        s = 0.0
        for j in range(n):
            s += ws.phiq[k, j] * d[j]
        ws.lam[k] = s
    if not cholesky_solve(ws.s, ws.lam, m):
        return False
    big = 0.0
    for i in range(n):
        s = 0.0
        for k in range(m):
            s += ws.w[i, k] * ws.lam[k]
        d[i] -= s
        big = max(big, abs(d[i]))
    schur(model, ws)
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
    if not cholesky_solve(ws.s, ws.lam, m):
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
    deviations ``dvimp`` of the latched impact velocity, one row per deviation (row c
    of ``d``, ``dvimp`` and ``size``).

    Like :func:`mechanism.core.model._kernels.update_latch`: a joint the reference sees
    penetrating is in contact (latch and its deviations frozen; an event counted on
    entry); one it sees separated tracks the approach speed δ̇, floored at
    ``impact_velocity_floor``. A latch deviation is the derivative of that value along
    its deviation on the reference's branch: (∂δ̇/∂y)·d by finite differences (the
    position and the velocity part of d each scaled to ``size``, as in
    :func:`_deviation_rate`), 0 when the reference is held at the floor.
    """
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return
    n = model.n_dof
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    tracking = False
    for j in range(ncj):
        delta, ddot, _ = clearance_state(model, ws, y, j)
        if delta > 0.0:
            if contact[j] == 0:
                contact[j] = 1
                counters[CNT_CONTACT_EVENTS] += 1
        else:
            contact[j] = 0
            floor = model.cj_f[j, CF_FLOOR]
            for c in range(d.shape[0]):
                dvimp[c, j] = 0.0
            if ddot > floor:
                vimp[j] = ddot
                tracking = True
            else:
                vimp[j] = floor
    if not tracking:
        return
    for c in range(d.shape[0]):
        _latch_deviation(model, ws, ws2, y, d[c], vimp, dvimp[c], contact, yp, size[c], tau,
                         inv_mass)  # fmt: skip


@njit_noalloc()
def _latch_deviation(model, ws, ws2, y, d, vimp, dvimp, contact, yp, size, tau, inv_mass):
    """Add (∂δ̇/∂y)·d to ``dvimp`` of every tracking joint (separated, above the floor);
    ``ws`` holds the points of the reference ``y``."""
    ncj = model.cj_i.shape[0]
    n = model.n_dof
    n2 = y.shape[0]
    pq, pv = part_norms(model, d, inv_mass)
    for half in range(2):
        if half == 0:
            if not pq > 0.0:
                continue
            c = size / pq
            _shift(y, d, np.int64(0), n, c, yp)  # not a literal: one specialisation
        else:
            if not pv > 0.0:
                continue
            c = size / (tau * pv)
            _shift(y, d, n, n2, c, yp)
        update_points(yp[:n], yp[n:], model.pt_i, model.pt_f, ws2.pci, ws2.pcf)
        for j in range(ncj):
            if contact[j] != 0 or not vimp[j] > model.cj_f[j, CF_FLOOR]:
                continue
            _, ddot, _ = clearance_state(model, ws, y, j)
            _, ddot_p, _ = clearance_state(model, ws2, yp, j)
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
def _directional_scale(a, b, size):
    """c such that c·d has the mass-weighted size ``size`` in its smaller part (sizes a and
    b of the position and the velocity part, m), the larger part capped at
    ``DIRECTIONAL_REACH`` × size; 0 for a zero deviation."""
    big = max(a, b)
    small = min(a, b)
    if not big > 0.0:
        return 0.0
    if not small > 0.0:
        return size / big
    return size / max(small, big / DIRECTIONAL_REACH)


@njit_noalloc()
def _deviation_rate(model, ws, t, ys, ds, f_ref, vimp, dvimp, vimp_p, yp, fp, kd, ref,
                    fresh, size, tau, inv_mass, counters_p, directional):  # fmt: skip
    """kd = (∂f/∂y)(t, ys)·ds + (∂f/∂δ̇⁻)·dvimp, f_ref = f(t, ys), by finite differences.

    With ``directional`` one difference along the whole of ``ds`` (and ``dvimp``): one
    evaluation instead of two, the shift scaled so that the smaller part moves by
    ``size`` unless the larger one would then move by more than ``DIRECTIONAL_REACH`` ×
    ``size`` (:func:`_directional_scale`). Otherwise the two parts separately:

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
    if directional:
        c = _directional_scale(pq, tau * pv, size)
        if c > 0.0:
            st |= _half_rate(
                model, ws, t, ys, ds, np.int64(0), n2, c, f_ref, vimp, dvimp, np.bool_(True),
                vimp_p, yp, fp, kd, ref, counters_p,
            )  # fmt: skip
        return st
    if pq > 0.0:
        st |= _half_rate(
            model, ws, t, ys, ds, np.int64(0), n, size / pq, f_ref, vimp, dvimp, np.bool_(False),
            vimp_p, yp, fp, kd, ref, counters_p,
        )  # fmt: skip
    if pv > 0.0:
        st |= _half_rate(
            model, ws, t, ys, ds, n, n2, size / (tau * pv), f_ref, vimp, dvimp, np.bool_(True),
            vimp_p, yp, fp, kd, ref, counters_p,
        )  # fmt: skip
    return st


@njit(cache=True)
def tangent_start(model, ws, t, y, d, k1, kd1, vimp, dvimp, counters, counters_p, size, tau,
                  inv_mass, directional):  # fmt: skip
    """k1 = f(t, y) and, for every row c of the block ``d`` (with ``dvimp[c]`` and
    ``size[c]``), kd1[c] = its rate (:func:`_deviation_rate`); returns a status."""
    st = rhs(model, ws, t, y, vimp, k1, counters)
    if st != STATUS_OK:
        return st
    yp = np.empty_like(y)
    fp = np.empty_like(y)
    ref = np.empty(model.cj_i.shape[0])
    vimp_p = np.empty_like(vimp)
    for c in range(d.shape[0]):
        # the first column reads the reference's branches from ws, the others reuse them
        st |= _deviation_rate(
            model, ws, t, y, d[c], k1, vimp, dvimp[c], vimp_p, yp, fp, kd1[c], ref, c == 0,
            size[c], tau, inv_mass, counters_p, directional,
        )  # fmt: skip
    return STATUS_RUNNING if st == STATUS_OK else st


@njit_noalloc()
def renormalize(model, ws, ws2, t, y, d, dvimp, scratch, size, tau2, inv_mass, growth):
    """Project ``d`` onto the constraint tangent, add ln(|d|/size) to ``growth`` and
    rescale d and the latch deviation ``dvimp`` (part of the linearised state) to
    ``size``. Returns False on a singular constraint matrix or a zero or non-finite
    deviation, except that a zero deviation of size 0 (a run of the reference alone) is
    left as it is."""
    if not project_tangent(model, ws, ws2, t, y, d, scratch):
        return False
    r = deviation_size(model, d, tau2, inv_mass)
    if size == 0.0 and r == 0.0:
        return True  # a reference-only run: no deviation to measure
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
    schedule,
    directional,
):
    """Advance the reference and a block of deviations to ``t_stop`` (≤ ``t_end``),
    landing on it, and renormalise there.

    The block: row c of ``d`` (k, 2n), ``kd1``, ``dvimp`` (k, joints), ``growth``
    (k, ``GROWTH_COLUMNS``) and ``size`` (k,) is one deviation, carried in lock-step with
    the one reference on its steps, each by the arithmetic of a lone deviation (k = 1 is
    the single-deviation integration bit for bit). With ``deviation_rtol`` = 0 the
    reference is stepped exactly as
    :func:`mechanism.core.integrate._dopri_kernels.dopri5_advance` steps it (same controller,
    error norm, maximum step, approach bound of the clearance joints, latch and optional
    projection) and the deviations ride along; with ``deviation_rtol`` > 0 the error
    passed to the controller is the largest of the reference's and the deviations' (each
    one's embedded error estimate in the mass-weighted norm over ``deviation_rtol`` × its
    size). Every ``every`` accepted steps, and at the end, every deviation is renormalised
    (:func:`renormalize`). ``state`` = [t, h, facold, last step rejected, accepted steps
    since the last renormalisation]. Returns ``STATUS_RUNNING`` when ``t_stop`` <
    ``t_end`` was reached, or after ``chunk_steps`` (> 0) attempted steps with
    ``state[0]`` < ``t_stop`` (the next call continues bit for bit), 0 at ``t_end``, or a
    negative failure status.

    A non-empty ``schedule`` (increasing times holding the stops) fixes the steps: each
    goes from ``t`` to the next schedule time and is accepted whatever its error
    estimate, so the end state is a smooth function of the start, with no adaptive
    choice to jump.
    """
    n2 = y.shape[0]
    nc = d.shape[0]
    k2 = np.empty(n2)
    k3 = np.empty(n2)
    k4 = np.empty(n2)
    k5 = np.empty(n2)
    k6 = np.empty(n2)
    k7 = np.empty(n2)
    kd2 = np.empty((nc, n2))
    kd3 = np.empty((nc, n2))
    kd4 = np.empty((nc, n2))
    kd5 = np.empty((nc, n2))
    kd6 = np.empty((nc, n2))
    kd7 = np.empty((nc, n2))
    ytmp = np.empty(n2)
    dtmp = np.empty(n2)
    ynew = np.empty(n2)
    dnew = np.empty((nc, n2))
    yp = np.empty(n2)
    fp = np.empty(n2)
    err = np.empty(n2)
    scratch = np.empty(n2)
    ref = np.empty(model.cj_i.shape[0])
    vimp_p = np.empty_like(vimp)
    tau = math.sqrt(tau2)
    fixed_steps = schedule.shape[0] > 0
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
        stop, status = chunk_end(t, t_end, t_stop, counters, max_steps, chunk_steps, attempted)
        if stop:
            break
        h = min(h, max_step)
        if approach_floor > 0.0:
            near = approach_step(model, ws, y, k1[n2 // 2 :], approach_fraction)
            h = min(h, max(approach_floor, near))
        # land on the stop time, so segments are exact (e.g. drive periods)
        if t + 1.01 * h >= t_stop:
            h = t_stop - t
        target = t_stop
        if fixed_steps:
            target = min(_next_time(schedule, t), t_stop)
            h = target - t
        if h < 10.0 * _EPS * max(abs(t), 1e-300) or h <= 0.0:
            status = STATUS_STEP_TOO_SMALL
            break
        # the stages: the reference's, then every deviation's at the reference's stage
        # state (the first column reads the reference's contact branches from ws)
        st = STATUS_OK
        for i in range(n2):
            ytmp[i] = y[i] + h * A21 * k1[i]
        st |= rhs(model, ws, t + C2 * h, ytmp, vimp, k2, counters)
        for c in range(nc):
            for i in range(n2):
                dtmp[i] = d[c, i] + h * A21 * kd1[c, i]
            st |= _deviation_rate(
                model, ws, t + C2 * h, ytmp, dtmp, k2, vimp, dvimp[c], vimp_p, yp, fp, kd2[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i])
        st |= rhs(model, ws, t + C3 * h, ytmp, vimp, k3, counters)
        for c in range(nc):
            for i in range(n2):
                dtmp[i] = d[c, i] + h * (A31 * kd1[c, i] + A32 * kd2[c, i])
            st |= _deviation_rate(
                model, ws, t + C3 * h, ytmp, dtmp, k3, vimp, dvimp[c], vimp_p, yp, fp, kd3[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
        st |= rhs(model, ws, t + C4 * h, ytmp, vimp, k4, counters)
        for c in range(nc):
            for i in range(n2):
                dtmp[i] = d[c, i] + h * (A41 * kd1[c, i] + A42 * kd2[c, i] + A43 * kd3[c, i])
            st |= _deviation_rate(
                model, ws, t + C4 * h, ytmp, dtmp, k4, vimp, dvimp[c], vimp_p, yp, fp, kd4[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
        st |= rhs(model, ws, t + C5 * h, ytmp, vimp, k5, counters)
        for c in range(nc):
            for i in range(n2):
                dtmp[i] = d[c, i] + h * (
                    A51 * kd1[c, i] + A52 * kd2[c, i] + A53 * kd3[c, i] + A54 * kd4[c, i]
                )
            st |= _deviation_rate(
                model, ws, t + C5 * h, ytmp, dtmp, k5, vimp, dvimp[c], vimp_p, yp, fp, kd5[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        for i in range(n2):
            ytmp[i] = y[i] + h * (
                A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]
            )
        st |= rhs(model, ws, t + h, ytmp, vimp, k6, counters)
        for c in range(nc):
            for i in range(n2):
                dtmp[i] = d[c, i] + h * (
                    A61 * kd1[c, i] + A62 * kd2[c, i] + A63 * kd3[c, i] + A64 * kd4[c, i]
                    + A65 * kd5[c, i]
                )  # fmt: skip
            st |= _deviation_rate(
                model, ws, t + h, ytmp, dtmp, k6, vimp, dvimp[c], vimp_p, yp, fp, kd6[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        for i in range(n2):
            ynew[i] = y[i] + h * (
                A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]
            )
        st |= rhs(model, ws, t + h, ynew, vimp, k7, counters)
        for c in range(nc):
            for i in range(n2):
                dnew[c, i] = d[c, i] + h * (
                    A71 * kd1[c, i] + A73 * kd3[c, i] + A74 * kd4[c, i] + A75 * kd5[c, i]
                    + A76 * kd6[c, i]
                )  # fmt: skip
            st |= _deviation_rate(
                model, ws, t + h, ynew, dnew[c], k7, vimp, dvimp[c], vimp_p, yp, fp, kd7[c],
                ref, c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
        if st != STATUS_OK:
            status = STATUS_SINGULAR
            break
        for i in range(n2):
            err[i] = h * (
                E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]
            )
        e = wrms(err, y, ynew, rtol, atol)
        if deviation_rtol > 0.0:
            # every deviation's own error estimate, relative to its size
            for c in range(nc):
                for i in range(n2):
                    err[i] = h * (
                        E1 * kd1[c, i]
                        + E3 * kd3[c, i]
                        + E4 * kd4[c, i]
                        + E5 * kd5[c, i]
                        + E6 * kd6[c, i]
                        + E7 * kd7[c, i]
                    )
                scale = max(deviation_size(model, d[c], tau2, inv_mass),
                            deviation_size(model, dnew[c], tau2, inv_mass))  # fmt: skip
                e = max(
                    e,
                    deviation_size(model, err, tau2, inv_mass) / (deviation_rtol * scale),
                )
        if fixed_steps and not math.isfinite(e):
            status = STATUS_NONFINITE
            break
        if not math.isfinite(e):
            counters[CNT_REJECTED] += 1
            h *= 0.1
            last_rejected = True
            continue
        fac11 = e**expo1
        if e <= 1.0 or fixed_steps:
            t = t + h
            if abs(t_stop - t) < 4.0 * _EPS * max(abs(t_stop), 1.0):
                t = t_stop
            if fixed_steps:
                t = target
            for i in range(n2):
                y[i] = ynew[i]
                k1[i] = k7[i]
            for c in range(nc):
                for i in range(n2):
                    d[c, i] = dnew[c, i]
            counters[CNT_STEPS] += 1
            latch_pair(model, ws, ws2, y, d, vimp, dvimp, contact, counters, yp, size, tau,
                       inv_mass)  # fmt: skip
            if projection:
                if not project(model, ws, t, y, 1e-12, 5):
                    status = STATUS_SINGULAR
                    break
                rhs(model, ws, t, y, vimp, k1, counters)
            since += 1
            status = _after_step(
                model, ws, ws2, t, y, d, k1, kd1, kd7, vimp, dvimp, vimp_p, yp, fp, ref,
                scratch, size, tau, tau2, inv_mass, growth, counters_p, projection,
                directional, since >= every or t >= t_stop or t >= t_end,
            )  # fmt: skip
            if status != STATUS_RUNNING:
                break
            if since >= every or t >= t_stop or t >= t_end:
                since = 0
            h, facold, last_rejected = next_step_size(
                True, e, h, fac11, facold, beta, last_rejected
            )
        else:
            counters[CNT_REJECTED] += 1
            h, facold, last_rejected = next_step_size(
                False, e, h, fac11, facold, beta, last_rejected
            )
    state[0] = t
    state[1] = h
    state[2] = facold
    state[3] = 1.0 if last_rejected else 0.0
    state[4] = float(since)
    return status


@njit(cache=True, nogil=True)
def tangent_stops(
    model, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters, counters_p, growth,
    stops, t_end, rtol, atol, max_step, projection, max_steps, every, size, tau2, inv_mass,
    approach_floor, approach_fraction, deviation_rtol, chunk_steps, schedule, directional,
    cursor, out_t, out_log, out_y, out_contact, out_events, out_latch,
):  # fmt: skip
    """:func:`tangent_advance` over the stops ``stops[cursor[0]:]`` in one call, writing
    at every stop reached row ``cursor[1]`` of the outputs (time, the log growth of each
    deviation, the state, the contact flags, the count of contact entries, the latches)
    and advancing both cursors. Returns after ``chunk_steps`` attempted steps
    (``STATUS_RUNNING``; called again it continues bit for bit), at the end
    (``STATUS_OK``) or on a failure: the numbers of one :func:`tangent_advance` call per
    stop, without a return to Python at each (a run recorded at every step)."""
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while cursor[0] < stops.shape[0]:
        left = chunk_steps - (counters[CNT_STEPS] + counters[CNT_REJECTED] - attempted)
        if left <= 0:
            return STATUS_RUNNING
        t_stop = stops[cursor[0]]
        status = tangent_advance(
            model, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters,
            counters_p, growth, t_stop, t_end, rtol, atol, max_step, projection, max_steps,
            every, size, tau2, inv_mass, approach_floor, approach_fraction, deviation_rtol,
            left, schedule, directional,
        )  # fmt: skip
        if status != STATUS_RUNNING and status != STATUS_OK:
            return status
        if status == STATUS_RUNNING and state[0] < t_stop:
            continue  # the budget is spent: checked above
        row = cursor[1]
        out_t[row] = state[0]
        for c in range(d.shape[0]):
            out_log[row, c] = growth[c, GROWTH_LOG]
        for i in range(y.shape[0]):
            out_y[row, i] = y[i]
        for j in range(contact.shape[0]):
            out_contact[row, j] = contact[j]
            out_latch[row, j] = vimp[j]
        out_events[row] = counters[CNT_CONTACT_EVENTS]
        cursor[0] += 1
        cursor[1] += 1
        if status == STATUS_OK:
            return status
    return status


@njit(cache=True, nogil=True)
def tangent_steps(
    model, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters, counters_p, growth,
    t_stop, t_end, rtol, atol, max_step, projection, max_steps, every, size, tau2, inv_mass,
    approach_floor, approach_fraction, deviation_rtol, chunk_steps, schedule, directional,
    times, count,
):  # fmt: skip
    """:func:`tangent_advance` towards ``t_stop`` one attempted step per call, writing the
    time of every accepted step to ``times[count[0]]`` and counting it: the numbers of
    one Python call per step (``chunk_steps`` = 1) without the return to Python. Returns
    after ``chunk_steps`` attempted steps, when ``times`` is full (``STATUS_RUNNING``) or
    as :func:`tangent_advance` does at the stop, the end or a failure."""
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while count[0] < times.shape[0]:
        if counters[CNT_STEPS] + counters[CNT_REJECTED] - attempted >= chunk_steps:
            return STATUS_RUNNING
        t = state[0]
        status = tangent_advance(
            model, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters,
            counters_p, growth, t_stop, t_end, rtol, atol, max_step, projection, max_steps,
            every, size, tau2, inv_mass, approach_floor, approach_fraction, deviation_rtol,
            1, schedule, directional,
        )  # fmt: skip
        if state[0] > t:
            times[count[0]] = state[0]
            count[0] += 1
        if status != STATUS_RUNNING or state[0] >= t_stop:
            return status
    return status


@njit(cache=True)
def clearance_rows(model, ws, times, states, latch, columns, out):
    """``out[i, j, c]`` = column ``columns[c]`` of clearance joint j's state (``ws.cj``)
    at ``states[i]`` (time ``times[i]``, latches ``latch[i]``)."""
    f = np.zeros(states.shape[1])
    counters = np.zeros(CNT_COLUMNS, dtype=np.int64)
    for i in range(states.shape[0]):
        rhs(model, ws, times[i], states[i], latch[i], f, counters)
        for j in range(out.shape[1]):
            for c in range(columns.shape[0]):
                out[i, j, c] = ws.cj[j, columns[c]]


@njit_noalloc()
def _after_step(model, ws, ws2, t, y, d, k1, kd1, kd7, vimp, dvimp, vimp_p, yp, fp, ref,
                scratch, size, tau, tau2, inv_mass, growth, counters_p, projection,
                directional, due):  # fmt: skip
    """After an accepted step: renormalise every deviation when ``due``, then the rate at
    the new point of each (anew, or first same as last). Returns ``STATUS_RUNNING``, or
    the failure status."""
    n2 = y.shape[0]
    # the split difference recomputes the rate after every step (as it always has: the
    # periodic orbits' monodromy matrices are those numbers)
    changed = projection or not directional
    if due:
        for c in range(d.shape[0]):
            if not renormalize(model, ws, ws2, t, y, d[c], dvimp[c], scratch, size[c], tau2,
                               inv_mass, growth[c]):  # fmt: skip
                return STATUS_NONFINITE
        changed = True
    for c in range(d.shape[0]):
        if changed:
            # the projection moved d (or y): its rate anew; ref holds the reference's
            # branches at y from the last stage (or, for the first column, from the
            # evaluation after a projection)
            st = _deviation_rate(
                model, ws, t, y, d[c], k1, vimp, dvimp[c], vimp_p, yp, fp, kd1[c], ref,
                projection and c == 0, size[c], tau, inv_mass, counters_p, directional,
            )  # fmt: skip
            if st != STATUS_OK:
                return STATUS_SINGULAR
        else:
            # first same as last: the rate at the new point is the last stage's (the
            # latch the step may have changed acts only in contact, where it is frozen)
            for i in range(n2):
                kd1[c, i] = kd7[c, i]
    return STATUS_RUNNING


class Deviation(NamedTuple):
    """A perturbed copy of a generalized-α integration, kept as its deviation from the
    reference (the largest Lyapunov exponent of a flexible model, docs/mechanism-lyapunov.md).

    After each step the reference accepts, the copy takes the same step h from its own
    state, solving its own implicit equation with the reference's Newton matrix
    (:func:`deviation_step`); the contact state is the reference's, each copy keeps its
    own impact-velocity latch (:func:`deviation_latch`); every ``every`` accepted steps
    and at the end of every chunk the deviation is measured and rescaled
    (:func:`deviation_renormalize`)."""

    d: np.ndarray  # (2n,) [δq; δq̇]
    dacc: np.ndarray  # (n,) δq̈, the deviation of the integrator's acceleration
    dapse: np.ndarray  # (n,) deviation of the pseudo-accelerations
    vimp: np.ndarray  # impact-velocity latch of the perturbed copy
    growth: np.ndarray  # float64[DEV_COLUMNS]
    counters: np.ndarray  # int64[CNT_COLUMNS]: the deviation's evaluations
    ws: Any  # workspace of the deviation's evaluations (the reference's is left alone)
    f0: np.ndarray  # (n,) q̈ at the reference's accepted state (scratch from here on)
    f1: np.ndarray  # (n,)
    fel: np.ndarray  # (n,) −(elastic + damping forces) of the beams at the reference state
    dx: np.ndarray  # (n,)
    res: np.ndarray  # (n,)
    dqn: np.ndarray  # (n,)
    dvn: np.ndarray  # (n,)
    yp: np.ndarray  # (2n,)
    scratch: np.ndarray  # (2n,)
    hx: np.ndarray  # (DEV_DEPTH, n) differences of the copy's last Newton iterates
    hf: np.ndarray  # (DEV_DEPTH, n) differences of their updates
    xprev: np.ndarray  # (n,) the last iterate
    fprev: np.ndarray  # (n,) its update
    size: float  # size (m) the deviation is rescaled to
    tau2: float  # τ² (s²) of the deviation norm
    inv_mass: float  # 1 / total mass (1/kg)
    every: int  # accepted steps between renormalisations
    tol: float  # Newton test of the copy, relative to the deviation's size
    max_newton: int  # Newton iterations of the copy per step


DEV_LOG = 0  # Σ ln(|d| / size) over the renormalisations
DEV_COUNT = 1  # renormalisations done
DEV_LAST_T = 2  # time of the last renormalisation
DEV_SINCE = 3  # accepted steps since the last renormalisation
DEV_NEWTON = 4  # Newton iterations of the copy
DEV_UNCONVERGED = 5  # steps whose copy ended max_newton iterations above DEV_FLOOR
DEV_COLUMNS = 6
DEV_DEPTH = 5  # iterates the copy's Newton mixes (Anderson acceleration)
#: the beams' forces of the perturbed copy are differenced along its deviation at this
#: largest coordinate change (m): the axial stiffness turns an ulp of a slope into a force
#: far above the deviation's own (docs/mechanism-lyapunov.md §1)
DEV_REACH = 1e-7
#: a copy's Newton iteration that stops converging (at the round-off of its
#: coordinates) below this share of the deviation's size has converged; one that ends
#: its iterations above it counts as unconverged
DEV_FLOOR = 1e-3


@njit_noalloc()
def copy_accelerations(model, dev, t, q, v, dq, dv, vimp, acc):
    """q̈ of the state (q + δq, q̇ + δq̇) into ``acc``, as :func:`accelerations` solves it,
    except that the beams' elastic and damping forces are the reference's (``dev.fel``, at
    (q, q̇)) plus their central difference along (δq, δq̇) at a change of ``DEV_REACH``.

    Evaluated directly at a deviation of 1e-13 m, the rods' axial stiffness (1e9–1e10 N/m
    per element) turns the round-off of the perturbed slopes (an ulp, 2e-16) into forces
    larger than the deviation's own; the forces are smooth, so their increment is taken
    at a larger scale instead. Everything else (constraints, contact, friction, force
    elements) is evaluated at the perturbed state. With δq = δq̇ = 0 it is the
    reference's q̈ by the same arithmetic. Returns a status."""
    ws = dev.ws
    n = q.shape[0]
    yp = dev.yp
    sc = dev.scratch
    big = 0.0
    for i in range(n):
        yp[i] = q[i] + dq[i]
        yp[n + i] = v[i] + dv[i]
        big = max(big, abs(dq[i]), abs(dv[i]))
    dev.counters[CNT_FEV] += 1
    update_points(yp[:n], yp[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    ws.phiq[:, :] = 0.0
    constraint_rows(
        t, model.con_i, model.con_f, model.drive_i, model.drive_f, model.spline_x,
        model.spline_c, ws.pci, ws.pcf, ws.phi, ws.phiq, ws.phit, ws.gam,
    )  # fmt: skip
    gen = ws.gen
    for i in range(n):
        gen[i] = model.gravity_force[i] + dev.fel[i]
    if model.beam_i.shape[0] > 0 and big > 0.0:
        step = DEV_REACH / big
        for i in range(n):
            sc[i] = q[i] + step * dq[i]
            sc[n + i] = v[i] + step * dv[i]
        beams_force_add(model.beam_i, model.beam_f, sc[:n], sc[n:], -0.5 / step, gen, ws.beam)
        for i in range(n):
            sc[i] = q[i] - step * dq[i]
            sc[n + i] = v[i] - step * dv[i]
        beams_force_add(model.beam_i, model.beam_f, sc[:n], sc[n:], 0.5 / step, gen, ws.beam)
    if model.cj_i.shape[0] > 0:
        clearance_forces(model, ws.pci, ws.pcf, vimp, gen, ws.cj, dev.counters)
    if model.fe_i.shape[0] > 0:
        # the force elements are soft (springs, dampers, loads): evaluated at the
        # perturbed state like the contact, as the reference's accelerations add them
        force_elements_add(model.fe_i, model.fe_f, model.fe_t, t, ws.pci, ws.pcf, gen, ws.fe)
    return solve(
        model.minv, model.minv_h, model.blk_lo, model.blk_hi, model.blk_st, model.con_i, ws.pci,
        model.alpha, model.beta, ws.phi, ws.phiq, ws.phit, ws.gam, gen, yp[n:], ws.a0, ws.w,
        ws.s, ws.lam, ws.nz_n, ws.nz_j, acc,
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def deviation_step(model, dev, t, h, qn, vn, vimp, am, af, gm, bt, cq, cvv, jm, piv, cc, zb,
                    dq0, dv0, base_contact, cs, sm, spiv, wv):  # fmt: skip
    """Advance the deviation ``dev`` over the step of size ``h`` the reference just
    accepted, ending at time ``t`` in the state (``qn``, ``vn``).

    The perturbed copy takes the same generalized-α step from its own state: its
    acceleration x + δx solves its implicit equation, written as one for δx,

        δx = a(t, qn + δqn(δx), vn + δvn(δx); copy's latch) − a(t, qn, vn; reference's latch),

    with δqn, δvn the predictor and corrector of the method applied to δq, δq̇, δq̈ and
    the pseudo-accelerations' deviation. The difference form shares the reference's own
    Newton residual (its iterate solves its equation only to the tolerance, far more than
    the deviation's size) with the copy. Newton with the reference's iteration matrix
    (the LU factors ``jm`` at h, frozen at the Jacobian's state) whose clearance-contact
    columns are re-linearised at the accepted state (the Sherman–Morrison–Woodbury
    correction of the reference's loop; the reference's own last linearisation may lie
    before its last update, on the other side of a friction ramp whose slope is a
    damper of 1e8 1/s), from the last step's δq̈, until the update is below ``dev.tol``
    of the deviation's size. Returns a status.
    """
    n = qn.shape[0]
    d = dev.d
    dacc = dev.dacc
    dapse = dev.dapse
    f0 = dev.f0
    f1 = dev.f1
    dx = dev.dx
    r = dev.res
    dqn = dev.dqn
    dvn = dev.dvn
    growth = dev.growth
    tau2 = dev.tau2
    c0 = (1.0 - af) / (1.0 - am)
    c1 = af / (1.0 - am)
    c2 = -am / (1.0 - am)
    fel = dev.fel
    for i in range(n):
        fel[i] = 0.0
        dqn[i] = 0.0
    if model.beam_i.shape[0] > 0:
        beams_force_add(model.beam_i, model.beam_f, qn, vn, -1.0, fel, dev.ws.beam)
    st = copy_accelerations(model, dev, t, qn, vn, dqn, dqn, vimp, f0)
    if st != STATUS_OK:
        return st
    nc = cc.shape[0]
    smw = False
    delta = np.zeros((nc, nc))
    if nc > 0:
        dqc = np.zeros((nc, nc))
        dvc = np.zeros((nc, nc))
        gtc = np.zeros((dev.vimp.shape[0], nc))
        touching = contact_derivatives(model, dev.ws, qn, vn, vimp, cc, dqc, dvc, gtc, cs)
        smw = touching or base_contact
        if smw:
            for a in range(nc):
                for b in range(nc):
                    delta[a, b] = -cq * (dqc[a, b] - dq0[a, b]) - cvv * (dvc[a, b] - dv0[a, b])
    for i in range(n):
        dx[i] = dacc[i]
    converged = False
    prev = np.inf
    conv = np.inf
    # Anderson mixing of the last DEV_DEPTH iterates: the frozen matrix contracts some
    # directions slowly (the reference tolerates a contraction up to 0.9), which the
    # copy, held to 1e-6 of its size, cannot; mixing removes a few such directions
    hx = dev.hx
    hf = dev.hf
    xprev = dev.xprev
    fprev = dev.fprev
    stored = 0
    for it in range(dev.max_newton):
        for i in range(n):
            da = c0 * dx[i] + c1 * dacc[i] + c2 * dapse[i]
            dqn[i] = d[i] + h * d[n + i] + h * h * ((0.5 - bt) * dapse[i] + bt * da)
            dvn[i] = d[n + i] + h * ((1.0 - gm) * dapse[i] + gm * da)
        st = copy_accelerations(model, dev, t, qn, vn, dqn, dvn, dev.vimp, f1)
        if st != STATUS_OK:
            return st
        for i in range(n):
            r[i] = f1[i] - f0[i] - dx[i]
        if smw:
            if not contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, wv, r):
                return STATUS_SINGULAR
        else:
            lu_solve(jm, piv, r)
        num = 0.0
        den = 0.0
        for i in range(n):
            num += (cq * r[i]) ** 2 + tau2 * (cvv * r[i]) ** 2
            den += dqn[i] ** 2 + tau2 * dvn[i] ** 2
        growth[DEV_NEWTON] += 1.0
        if not math.isfinite(num):
            return STATUS_NONFINITE
        conv = math.sqrt(num / den) if den > 0.0 else 0.0
        # the copy's coordinates carry the round-off of the reference's, so its updates
        # stall at a floor (about 1e-3 of the deviation on the paper scene, 2.5e-5 on a
        # stiff-rod pendulum; docs/performance.md, The exponent's cost): an update below
        # DEV_FLOOR that no longer halves has reached it
        if conv <= dev.tol or (conv <= DEV_FLOOR and conv >= 0.5 * prev):
            for i in range(n):
                dx[i] += r[i]
            converged = True
            break
        prev = conv
        if it > 0:
            slot = (it - 1) % DEV_DEPTH
            for i in range(n):
                hx[slot, i] = dx[i] - xprev[i]
                hf[slot, i] = r[i] - fprev[i]
            stored = min(stored + 1, DEV_DEPTH)
        for i in range(n):
            xprev[i] = dx[i]
            fprev[i] = r[i]
        mixed = False
        if stored > 0:
            a = np.zeros((stored, stored))
            g = np.zeros(stored)
            apiv = np.zeros(stored, dtype=np.int64)
            trace = 0.0
            for u in range(stored):
                for w in range(stored):
                    acc = 0.0
                    for i in range(n):
                        acc += hf[u, i] * hf[w, i]
                    a[u, w] = acc
                acc = 0.0
                for i in range(n):
                    acc += hf[u, i] * r[i]
                g[u] = acc
                trace += a[u, u]
            for u in range(stored):
                a[u, u] += 1e-12 * trace
            if trace > 0.0 and lu_factor(a, apiv):
                lu_solve(a, apiv, g)
                for i in range(n):
                    acc = dx[i] + r[i]
                    for u in range(stored):
                        acc -= g[u] * (hx[u, i] + hf[u, i])
                    dx[i] = acc
                mixed = True
        if not mixed:
            for i in range(n):
                dx[i] += r[i]
    if not converged and conv > DEV_FLOOR:
        growth[DEV_UNCONVERGED] += 1.0
    for i in range(n):
        da = c0 * dx[i] + c1 * dacc[i] + c2 * dapse[i]
        dq_new = d[i] + h * d[n + i] + h * h * ((0.5 - bt) * dapse[i] + bt * da)
        dv_new = d[n + i] + h * ((1.0 - gm) * dapse[i] + gm * da)
        d[i] = dq_new
        d[n + i] = dv_new
        dapse[i] = da
        dacc[i] = dx[i]
    return STATUS_OK


@njit_noalloc()
def deviation_latch(model, dev, y, contact, carry_worn):
    """The perturbed copy's impact-velocity latch after an accepted step: the reference
    decides contact (``contact``, already updated); a joint it sees separated tracks the
    copy's own approach speed at y + d, floored as :func:`update_latch` does; one in
    contact keeps the copy's latched value, raised from the copy's own δ̇ as
    :func:`update_latch` raises it with ``carry_worn`` on a worn joint."""
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return
    n = model.n_dof
    yp = dev.yp
    for i in range(2 * n):
        yp[i] = y[i] + dev.d[i]
    ws = dev.ws
    for j in range(ncj):
        carry = carry_worn and model.cw_i[j, CW_WORN] != 0
        if contact[j] != 0 and not carry:
            continue
        update_point_rows(yp[:n], yp[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf, model.cj_i[j, :2])
        _, ddot, _ = clearance_state(model, ws, yp, j)
        if contact[j] != 0:
            if ddot > APPROACH_RATIO * dev.vimp[j]:
                dev.vimp[j] = ddot / APPROACH_RATIO
            continue
        floor = model.cj_f[j, CF_FLOOR]
        dev.vimp[j] = ddot if ddot > floor else floor


@njit_noalloc()
def deviation_size(model, d, tau2, inv_mass):
    """√((δqᵀMδq + τ² δq̇ᵀMδq̇)/m): the mass-weighted size (m) of a deviation, in the
    rigid and the generalized-α tangent integrations alike.

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
def deviation_renormalize(model, dev, t, vimp):
    """Add ln(|d|/size) to the growth and rescale the deviation — (δq, δq̇), and with them
    δq̈, the pseudo-accelerations' deviation and the difference of the copy's latched
    impact velocities from the reference's ``vimp``, so the copy stays a consistent
    generalized-α state — to ``dev.size``. Unlike the rigid case the deviation is not
    projected onto the constraints' tangent space: a mass-orthogonal correction moves
    the rods' end nodes against their interior nodes and excites the stiff axial modes
    (docs/mechanism-lyapunov.md §1). Returns a status."""
    n = model.n_dof
    d = dev.d
    growth = dev.growth
    size = deviation_size(model, d, dev.tau2, dev.inv_mass)
    if not (size > 0.0 and math.isfinite(size)):
        return STATUS_NONFINITE
    growth[DEV_LOG] += math.log(size / dev.size)
    growth[DEV_COUNT] += 1.0
    growth[DEV_LAST_T] = t
    growth[DEV_SINCE] = 0.0
    f = dev.size / size
    for i in range(2 * n):
        d[i] *= f
    for i in range(n):
        dev.dacc[i] *= f
        dev.dapse[i] *= f
    # the copy's latched impact velocities are part of its state: their difference from
    # the reference's is rescaled with the rest
    for j in range(vimp.shape[0]):
        dev.vimp[j] = vimp[j] + f * (dev.vimp[j] - vimp[j])
    return STATUS_OK
