"""Compiled generalized-α loop (implicit, for stiff contact and flexible models).

:func:`genalpha_advance` advances a chunk of steps, with the Jacobian buffers of
:class:`Jacobian` (:func:`jacobian_buffers`) and, for the largest Lyapunov exponent of a
flexible model, a perturbed copy (:class:`~mechanism.core.integrate._tangent_kernels.Deviation`)
taking the same steps. The typed tuples shared with Dormand–Prince and the recording after
every accepted step are in ``_step_kernels.py``; the LU and contact Newton solve in
``_newton_kernels.py``.
"""

from __future__ import annotations

import math
from typing import (
    NamedTuple,
)

import numpy as np
from numba import (
    njit,
)

from mechanism.core._jit import (
    njit_inner,
)
from mechanism.core._status import (
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.contact import (
    FRICTION_NONE,
)
from mechanism.core.model import (
    CF_V0,
    CF_V1,
    CJ_DELTA,
    CJ_VT,
    CNT_NEWTON,
    CNT_REJECTED,
    CNT_STEPS,
    accelerations,
    approach_step,
    entry_depth_ratio,
    journal_travel_ratio,
    project,
    update_latch,
)

from ._newton_kernels import (
    LIN_COLUMNS,
    contact_derivatives,
    contact_newton_solve,
    contact_scratch,
    hybrid_jacobian,
    linearisation_holds,
    lu_factor,
    lu_solve,
    record_linearisation,
    response_basis,
)
from ._step_kernels import (
    DENSE_HERMITE,
    EPS,
    after_step,
    chunk_end,
    entry_fraction,
)
from ._tangent_kernels import (
    DEV_SINCE,
    deviation_latch,
    deviation_renormalize,
    deviation_step,
)

__all__ = ["Jacobian"]


class Jacobian(NamedTuple):
    """Generalized-α Jacobian buffers: ∂q̈/∂q, ∂q̈/∂q̇, the column sets (differenced,
    analytic ANCF, clearance-contact) and the clearance-force linearisations that go
    with them. Everything a step reads from earlier steps lives here (or in
    ``LoopState``), so an integration split into pieces follows the same path as one
    call (:func:`jacobian_buffers`)."""

    kq: np.ndarray
    cv: np.ndarray
    fd_cols: np.ndarray
    an_cols: np.ndarray
    contact_cols: np.ndarray
    dq0: np.ndarray  # (nc, nc) clearance-force derivatives at the Jacobian's state
    dv0: np.ndarray
    basis: np.ndarray  # (nc, n) constrained response P M⁻¹ e_cc at the Jacobian's state
    dqi: np.ndarray  # (nc, nc) derivatives at the last re-linearised Newton iterate
    dvi: np.ndarray
    gt: np.ndarray  # (n_cj, nc) ∂v_t/∂q̇_cc of the last linearisation
    lin: np.ndarray  # (n_cj, LIN_COLUMNS) state of the last re-linearisation
    flags: np.ndarray  # int64[JF_COLUMNS]


JF_BASE_CONTACT = 0  # a joint touches at the Jacobian's state
JF_LIN_TOUCHING = 1  # a joint touches at the last re-linearisation
JF_FRESH = 2  # the Jacobian was refreshed whole for the current step
JF_STALE = 3  # the next refresh may keep the differenced ∂q̈/∂q̇ columns
JF_COLUMNS = 4


def jacobian_buffers(
    n: int, n_cj: int, fd_cols: np.ndarray, an_cols: np.ndarray, contact_cols: np.ndarray
) -> Jacobian:
    """Empty :class:`Jacobian` (not yet valid) for ``n`` coordinates and ``n_cj``
    clearance joints."""
    nc = contact_cols.shape[0]
    return Jacobian(
        kq=np.zeros((n, n)), cv=np.zeros((n, n)), fd_cols=fd_cols, an_cols=an_cols,
        contact_cols=contact_cols, dq0=np.zeros((nc, nc)), dv0=np.zeros((nc, nc)),
        basis=np.zeros((nc, n)), dqi=np.zeros((nc, nc)), dvi=np.zeros((nc, nc)),
        gt=np.zeros((n_cj, nc)), lin=np.full((n_cj, LIN_COLUMNS), np.nan),
        flags=np.zeros(JF_COLUMNS, dtype=np.int64),
    )  # fmt: skip


REFRESH_AFTER = 10


@njit_inner()
def _record_step(model, ws, out, dense, told, t, h, vimp, contact, scratch, yout, counters):
    """:func:`after_step` on the step's Hermite dense output, as a kernel of its own
    compiled without reference counts (inlined into the loop, which allocates and so
    counts references, its reads of the recording tuples would each be counted)."""
    after_step(model, ws, out, DENSE_HERMITE, dense, told, t, h, vimp, contact, scratch,
               yout, counters)  # fmt: skip


# Newton stops once the estimated remaining error θ/(1 − θ)·‖Δx‖ is below this fraction
# of the tolerance
NEWTON_BOUND = 0.03


# Largest relative journal travel per accepted generalized-α step, in nominal radial
# clearances (docs/simulator.md, "Fixed-step generalized-α on worn profiles")
TRAVEL_LIMIT = 0.5


@njit(cache=True, error_model="numpy", nogil=True)
def genalpha_advance(model, ws, loop, out, ctl, jac, t_stop, dev):
    """Advance a variable-step generalized-α integration (Chung & Hulbert 1993) of
    q̈ = a(t, q, q̇) until ``t ≥ t_stop`` (or ``t_end``).

    Parameters αm = (2ρ∞ − 1)/(ρ∞ + 1), αf = ρ∞/(ρ∞ + 1), γ = ½ + αf − αm,
    β = ¼(γ + ½)² (Arnold & Brüls 2007 form with pseudo-accelerations ``apse``). Each step
    solves R(x) = x − a(t + h, q(x), q̇(x)) for x = q̈ₙ₊₁ by modified Newton on
    J = I − c_q ∂a/∂q − c_v ∂a/∂q̇ (:func:`hybrid_jacobian`, taken at the step's predicted
    end q̈ₙ₊₁ = q̈ₙ in models without clearance joints and at its start otherwise;
    refreshed when Newton stalls,
    when the Newton iterations beyond two per step since the last refresh exceed
    ``REFRESH_AFTER``, and — in models
    without contact columns — when a clearance joint changes between contact and
    separation; convergence from the observed contraction rate: after two iterations,
    or after one when the rate the same matrix showed in the previous step bounds the
    remaining error). The step is rejected when Newton fails,
    when the local error estimate e_q = h²|β − 1/6| Δq̈, e_v = h(|γ − ½| + 1/12) Δq̈
    exceeds the tolerance, or when a
    separated clearance joint would enter contact deeper than ``entry_depth`` × clearance
    (so that every impact starts with a short step and a well-defined approach speed; the
    retry interpolates the entry time, and steps below 1e-6 × ``max_step`` are accepted).

    With ``fixed_step`` > 0 the error test is skipped and every step after an accepted
    one is ``fixed_step`` (pass ``max_step`` ≤ ``fixed_step``): the fixed-step scheme of
    structural dynamics, whose numerical damping (ρ∞ < 1) removes unresolved stiff modes
    that would otherwise hold an error-controlled step at their period (ANCF axial
    modes, docs/ancf.md §8).

    Clearance-joint forces are stiff and only piecewise smooth (contact onset, the
    stick–slip ramp of regularised friction acting on a light journal), so a Jacobian
    taken at the start of the step can be useless at its end. The columns ``cc`` that
    those forces read (the bearing and journal coordinates) are therefore re-linearised
    at every Newton iterate that touches (:func:`contact_derivatives`: one evaluation of
    the contact law and its partials for dry journals, a few differenced evaluations
    otherwise; kept while the contact state moved by less than ``RELINEARISE`` since,
    :func:`linearisation_holds`), and the change, mapped by the constrained response
    P M⁻¹ frozen at the Jacobian's state, enters the factorised matrix as a rank-len(cc)
    Sherman–Morrison–Woodbury correction (:func:`contact_newton_solve`): a semi-smooth
    Newton iteration at O(n·len(cc)) extra work per iterate.

    ``state`` = [t, h, Jacobian valid, Newton iterations beyond two per step since the
    last refresh, last Newton iterate left the admissible configurations, contraction
    rate θ last measured with the current Jacobian (−1: none), the step it was measured
    at]; the contact
    linearisations and refresh flags live in ``jac``, so calls that stop at successive
    ``t_stop``, or after ``ctl.chunk_steps`` attempted steps, follow the path of one call
    bit for bit. Returns 1 (``t_stop`` reached, or the step budget spent with
    ``state[0]`` < ``t_stop``), 0 (done) or a negative failure status.

    ``dev`` is None, or a :class:`Deviation` that follows the run: after every accepted
    step the perturbed copy takes the same step (:func:`deviation_step`), its latch
    follows the reference's contact state, and it is renormalised every ``dev.every``
    accepted steps and at the step that reaches ``t_stop`` or ``t_end``. The reference's
    steps, counters and state do not depend on it (with None the deviation's code is
    compiled out).
    """
    y = loop.y
    acc = loop.f
    apse = loop.apse
    state = loop.step
    vimp = loop.vimp
    contact = loop.contact
    counters = loop.counters
    kq = jac.kq
    cv = jac.cv
    fd_cols = jac.fd_cols
    an_cols = jac.an_cols
    cc = jac.contact_cols
    t_end = ctl.t_end
    rtol = ctl.rtol
    atol = ctl.atol
    max_step = ctl.max_step
    rho_inf = ctl.rho_inf
    max_newton = ctl.max_newton
    entry_depth = ctl.entry_depth
    projection = ctl.projection
    fixed_step = ctl.fixed_step
    n = model.n_dof
    n2 = 2 * n
    q = y[:n]
    v = y[n:]
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gm = 0.5 + af - am
    bt = 0.25 * (gm + 0.5) ** 2
    x = np.empty(n)
    f = np.empty(n)
    dx = np.empty(n)
    anew = np.empty(n)
    qn = np.empty(n)
    vn = np.empty(n)
    jm = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    yout = np.empty(n2)
    scratch = np.empty(n2)
    dense = np.empty((4, n2))
    out_counters = np.zeros(counters.shape[0], dtype=np.int64)
    was = np.zeros(contact.shape[0], dtype=contact.dtype)
    nc = cc.shape[0]
    dq0 = jac.dq0
    dv0 = jac.dv0
    dqi = jac.dqi
    dvi = jac.dvi
    basis = jac.basis
    gt = jac.gt
    lin = jac.lin
    flags = jac.flags
    delta = np.zeros((nc, nc))
    zb = np.zeros((nc, n))
    sm = np.zeros((nc, nc))
    spiv = np.empty(nc, dtype=np.int64)
    wv = np.empty(nc)
    cs = contact_scratch(model, ws)
    # the clearance tables read inside the Newton loop, taken out of their tuples once
    cj_state = ws.cj
    cj_f = model.cj_f
    cj_i = model.cj_i
    lin_touching = flags[JF_LIN_TOUCHING] != 0
    base_contact = flags[JF_BASE_CONTACT] != 0
    t = state[0]
    h = state[1]
    jac_valid = state[2] > 0.0
    # the LU factors are rebuilt from kq, cv and h, bit for bit
    h_lu = -1.0
    fresh = flags[JF_FRESH] != 0
    excess = int(state[3])
    stale = flags[JF_STALE] != 0
    singular_iterate = state[4] > 0.0
    theta_carry = state[5]
    theta_h = state[6]
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while True:
        stop, status = chunk_end(
            t, t_end, t_stop, counters, ctl.max_steps, ctl.chunk_steps, attempted
        )
        if stop:
            break
        h = min(h, max_step)
        if ctl.approach_floor > 0.0:
            near = approach_step(model, ws, y, acc, ctl.approach_fraction)
            h = min(h, max(ctl.approach_floor, near))
        if t + 1.01 * h >= t_end:
            h = t_end - t
        if h < 10.0 * EPS * max(abs(t), 1e-300) or h <= 0.0:
            status = STATUS_SINGULAR if singular_iterate else STATUS_STEP_TOO_SMALL
            break
        if not jac_valid:
            if nc == 0:
                # Taken at the step's predicted end (x = q̈ₙ), where Newton converges, not at
                # its start: a rotating beam's axial stiffness turns with it, and its leak
                # into the far softer bending directions over one step made the start's
                # Jacobian contract only by θ ≈ 0.01–0.09 per iteration, against
                # θ ≈ 0.002 at the predicted end (S6, h = 1e-4 s; docs/ancf.md §8)
                for i in range(n):
                    anew[i] = (acc[i] - am * apse[i]) / (1.0 - am)
                    qn[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * apse[i] + bt * anew[i])
                    vn[i] = v[i] + h * ((1.0 - gm) * apse[i] + gm * anew[i])
                hybrid_jacobian(model, ws, t + h, qn, vn, vimp, kq, cv, fd_cols, an_cols, counters,
                                not stale)  # fmt: skip
            else:
                hybrid_jacobian(model, ws, t, q, v, vimp, kq, cv, fd_cols, an_cols, counters,
                                not stale)  # fmt: skip
            if nc > 0:
                accelerations(model, ws, t, q, v, vimp, f, counters)
                base_contact = contact_derivatives(model, ws, q, v, vimp, cc, dq0, dv0, gt, cs)
                response_basis(model, ws, cc, basis)
            jac_valid = True
            # only a complete refresh makes a Newton failure a reason to shorten the step
            fresh = not stale
            stale = False
            excess = 0
            h_lu = -1.0
            # a new matrix: its contraction rate is not known yet
            theta_carry = -1.0
        cq = h * h * bt * (1.0 - af) / (1.0 - am)
        cvv = h * gm * (1.0 - af) / (1.0 - am)
        if h != h_lu:
            for i in range(n):
                for j in range(n):
                    jm[i, j] = -cq * kq[i, j] - cvv * cv[i, j]
                jm[i, i] += 1.0
            if not lu_factor(jm, piv):
                status = STATUS_SINGULAR
                break
            for c in range(nc):
                for i in range(n):
                    zb[c, i] = basis[c, i]
                lu_solve(jm, piv, zb[c])
            h_lu = h
        for i in range(n):
            x[i] = acc[i]
        last_theta = -1.0
        converged = False
        iters = 0
        prev = np.inf
        st = STATUS_OK
        for it in range(max_newton):
            for i in range(n):
                anew[i] = ((1.0 - af) * x[i] + af * acc[i] - am * apse[i]) / (1.0 - am)
                qn[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * apse[i] + bt * anew[i])
                vn[i] = v[i] + h * ((1.0 - gm) * apse[i] + gm * anew[i])
            st = accelerations(model, ws, t + h, qn, vn, vimp, f, counters)
            counters[CNT_NEWTON] += 1
            if st != STATUS_OK:
                break
            for i in range(n):
                dx[i] = f[i] - x[i]
            touching = False
            if nc > 0:
                # cj_state (ws.cj) holds the clearance state at this iterate (the evaluation
                # above)
                if linearisation_holds(model, cj_state, vimp, lin):
                    touching = lin_touching
                else:
                    touching = contact_derivatives(model, ws, qn, vn, vimp, cc, dqi, dvi, gt, cs)
                    record_linearisation(cj_state, vimp, lin)
                    lin_touching = touching
            if touching or base_contact:
                for a in range(nc):
                    for b in range(nc):
                        delta[a, b] = -cq * (dqi[a, b] - dq0[a, b]) - cvv * (dvi[a, b] - dv0[a, b])
                if not contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, wv, dx):
                    break
            else:
                lu_solve(jm, piv, dx)
            scale = 1.0
            if touching:
                # Regularised friction is flat while sliding and in its dead zone and steep
                # in the narrow ramp between: a full update from a flat piece overshoots (to
                # the opposite sliding direction, or out of the dead zone) and Newton
                # oscillates. Such an update is shortened to land in the middle of the ramp,
                # whose own tangent the contact derivatives capture; convergence is still
                # judged on the full update.
                for j in range(contact.shape[0]):
                    v0 = cj_f[j, CF_V0]
                    v1 = cj_f[j, CF_V1]
                    vt = cj_state[j, CJ_VT]
                    if cj_state[j, CJ_DELTA] <= 0.0 or cj_i[j, 3] == FRICTION_NONE:
                        continue
                    dvt = 0.0
                    for c in range(nc):
                        dvt += gt[j, c] * cvv * dx[cc[c]]
                    vnew = vt + dvt
                    target = np.nan
                    leaves = vt * vnew < 0.0 or abs(vnew) < v0  # into or across the dead zone
                    if abs(vt) > v1 and leaves:
                        target = 0.5 * (v0 + v1) * (1.0 if vt > 0.0 else -1.0)
                    elif abs(vt) >= v0 and leaves:
                        target = 0.5 * v0 * (1.0 if vt > 0.0 else -1.0)
                    elif abs(vt) < v0 and abs(vnew) > v1:
                        target = 0.5 * (v0 + v1) * (1.0 if vnew > 0.0 else -1.0)
                    if math.isfinite(target) and dvt != 0.0:
                        r = (target - vt) / dvt
                        if 0.0 < r < scale:
                            scale = r
            # the size of the full Newton update measures convergence, damped or not
            sq = 0.0
            for i in range(n):
                sk_q = atol + rtol * abs(q[i])
                sk_v = atol + rtol * abs(v[i])
                sq += (cq * dx[i] / sk_q) ** 2 + (cvv * dx[i] / sk_v) ** 2
            conv = math.sqrt(sq / n2)
            iters = it + 1
            for i in range(n):
                x[i] += scale * dx[i]
            if not math.isfinite(conv):
                break
            # Convergence from the observed contraction rate θ (Hairer & Wanner IV.8): a
            # stale Jacobian can make the first update small while the residual is not,
            # so a single iteration is accepted only on the rate the same matrix showed
            # in the previous step (below), otherwise two are taken.
            if scale < 1.0:
                # a shortened update says nothing about the contraction: start afresh
                prev = np.inf
                continue
            if it == 0 and theta_carry >= 0.0 and h == theta_h:
                # One iteration suffices when the contraction rate θ of the same matrix in
                # the previous step says the remaining error, ≈ θ/(1 − θ) times this
                # update, is already below the bound (Hairer & Wanner IV.8, η from the
                # previous step raised to 0.8 to stay on the safe side)
                eta = max(theta_carry / (1.0 - theta_carry), 1e-16) ** 0.8
                if eta * conv < NEWTON_BOUND:
                    converged = True
                    break
            if it >= 1:
                if conv <= 1e-12 * (1.0 + prev) or prev <= 0.0:
                    converged = True
                    break
                theta = conv / prev
                last_theta = theta
                if theta >= 0.9:
                    break
                if theta / (1.0 - theta) * conv < NEWTON_BOUND:
                    converged = True
                    break
            prev = conv
        # A Newton iterate may leave the admissible configurations (a wild first update
        # on a stiff contact): that is a failed iteration, handled like any other — the
        # step is retried smaller, and only a step that shrinks to nothing reports it.
        singular_iterate = st == STATUS_SINGULAR
        if not converged:
            theta_carry = -1.0
            if not fresh:
                jac_valid = False
                continue
            counters[CNT_REJECTED] += 1
            h *= 0.25
            continue
        for i in range(n):
            anew[i] = ((1.0 - af) * x[i] + af * acc[i] - am * apse[i]) / (1.0 - am)
            qn[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * apse[i] + bt * anew[i])
            vn[i] = v[i] + h * ((1.0 - gm) * apse[i] + gm * anew[i])
        # local error estimate from the change of acceleration over the step
        ce_q = h * h * abs(bt - 1.0 / 6.0)
        ce_v = h * (abs(gm - 0.5) + 1.0 / 12.0)
        sq = 0.0
        for i in range(n):
            da = x[i] - acc[i]
            sk_q = atol + rtol * max(abs(q[i]), abs(qn[i]))
            sk_v = atol + rtol * max(abs(v[i]), abs(vn[i]))
            sq += (ce_q * da / sk_q) ** 2 + (ce_v * da / sk_v) ** 2
        e = math.sqrt(sq / n2)
        for i in range(n):
            yout[i] = qn[i]
            yout[n + i] = vn[i]
        if entry_depth > 0.0:
            r_end = entry_depth_ratio(model, ws, yout, contact)
            # A penetration that does not vanish with the step is a jump of the surface
            # (a worn profile between regions), not an impact to resolve: below
            # ``ctl.entry_min_step`` (1e-6 × max_step) the entry is accepted rather than
            # retried forever.
            if r_end > entry_depth and h > ctl.entry_min_step:
                counters[CNT_REJECTED] += 1
                h *= entry_fraction(model, ws, y, contact, entry_depth, r_end)
                continue
        if nc > 0 and h > ctl.entry_min_step:
            # A journal that moves more than TRAVEL_LIMIT clearances in one step has jumped
            # over its impacts (thrown off a worn flank it can cross the whole bearing and
            # end inside the opposite wall while the contact latch still says "touching",
            # which the entry test does not see): retried with a step that moves it a
            # quarter of that.
            travel = journal_travel_ratio(model, ws, y, yout)
            if travel > TRAVEL_LIMIT:
                counters[CNT_REJECTED] += 1
                h *= max(0.01, 0.25 * TRAVEL_LIMIT / travel)
                continue
        if fixed_step <= 0.0 and not e <= 1.0:
            counters[CNT_REJECTED] += 1
            h *= max(0.2, 0.9 * e ** (-1.0 / 3.0)) if math.isfinite(e) else 0.2
            continue
        # A stale Jacobian shows as Newton iterations beyond the two every step takes
        # (the rods turn, and their axial stiffness turns with them): refresh it once
        # those extra iterations since the last refresh exceed REFRESH_AFTER, which
        # amortises a refresh over the steps it speeds up (docs/ancf.md §8).
        if iters > 2:
            excess += iters - 2
        if excess > REFRESH_AFTER and not fresh:
            jac_valid = False
            # Staleness is the rotation of the stiffness, i.e. of ∂q̈/∂q; the differenced
            # ∂q̈/∂q̇ columns (constraint stabilisation, ∝ h·2α in J) barely change and are
            # kept, which halves the refresh. Clearance joints' velocity derivatives
            # enter the contact correction against the Jacobian's state: refreshed whole.
            stale = nc == 0
        fresh = False
        told = t
        t = t + h
        if t_end - t < 4.0 * EPS * max(abs(t_end), 1.0):
            t = t_end
        for i in range(n):
            dense[0, i] = q[i]
            dense[0, n + i] = v[i]
            dense[1, i] = qn[i]
            dense[1, n + i] = vn[i]
            dense[2, i] = v[i]
            dense[2, n + i] = acc[i]
            dense[3, i] = vn[i]
            dense[3, n + i] = x[i]
        _record_step(model, ws, out, dense, told, t, h, vimp, contact, scratch, yout,
                     out_counters)  # fmt: skip
        if dev is not None:
            dst = deviation_step(model, dev, t, h, qn, vn, vimp, am, af, gm, bt, cq, cvv, jm,
                                  piv, cc, zb, dq0, dv0, base_contact, cs, sm, spiv,
                                  wv)  # fmt: skip
        for i in range(n):
            q[i] = qn[i]
            v[i] = vn[i]
            apse[i] = anew[i]
            acc[i] = x[i]
        counters[CNT_STEPS] += 1
        if last_theta >= 0.0:
            theta_carry = min(last_theta, 0.5)
            theta_h = h
        changed = False
        for j in range(contact.shape[0]):
            was[j] = contact[j]
        update_latch(model, ws, y, vimp, contact, counters, fixed_step > 0.0)
        for j in range(contact.shape[0]):
            if was[j] != contact[j]:
                changed = True
        if changed and nc == 0:
            # contact stiffness appears or vanishes: the Jacobian is no longer useful
            jac_valid = False
        if projection:
            if not project(model, ws, t, y, 1e-12, 5):
                status = STATUS_SINGULAR
                break
            accelerations(model, ws, t, q, v, vimp, acc, counters)
        if dev is not None:
            if dst != STATUS_OK:
                status = STATUS_SINGULAR if dst == STATUS_SINGULAR else STATUS_NONFINITE
                break
            deviation_latch(model, dev, y, contact, fixed_step > 0.0)
            dev.growth[DEV_SINCE] += 1.0
            if dev.growth[DEV_SINCE] >= dev.every or t >= t_stop or t >= t_end:
                dst = deviation_renormalize(model, dev, t, vimp)
                if dst != STATUS_OK:
                    status = STATUS_NONFINITE
                    break
        if fixed_step > 0.0:
            h = fixed_step
        else:
            grow = 2.0 if e < 1e-10 else min(2.0, max(0.2, 0.9 * e ** (-1.0 / 3.0)))
            h *= grow
    state[0] = t
    state[1] = h
    state[2] = 1.0 if jac_valid else 0.0
    state[3] = float(excess)
    state[4] = 1.0 if singular_iterate else 0.0
    state[5] = theta_carry
    state[6] = theta_h
    flags[JF_BASE_CONTACT] = 1 if base_contact else 0
    flags[JF_LIN_TOUCHING] = 1 if lin_touching else 0
    flags[JF_FRESH] = 1 if fresh else 0
    flags[JF_STALE] = 1 if stale else 0
    return status
