"""System-level compiled kernels: constraints, forces and the equations of motion.

The model tables come from :func:`mechanism.core.model._assemble.assemble` as a ``KernelModel``
named tuple (contiguous int64/float64 arrays and scalars); scratch arrays come in a
``Workspace`` named tuple allocated once per run, so nothing here allocates.

Equations of motion (docs/paper-model.md §7), with the constant mass matrix M::

    [ M   Φqᵀ ] [ q̈ ]   [ Q                  ]
    [ Φq  0   ] [ λ  ] = [ γ − 2αΦ̇ − β²Φ ]

solved by the Schur complement with the constant M⁻¹ (assembled once)::

    a₀ = M⁻¹Q,  W = M⁻¹Φqᵀ,  (Φq W) λ = Φq a₀ − (γ − 2αΦ̇ − β²Φ),  q̈ = a₀ − W λ.

Φq is sparse (a row touches the coordinates of at most two points), so W and Φq W are
built from each row's nonzero columns.

Kernels that allocate nothing are compiled without numba's reference counting
(:func:`mechanism.core._jit.njit_noalloc`; here and in the joint, contact, wear and
integrator kernels they call), which halves the cost of a right-hand side. Those the
compiled loops call and a run never calls from Python are also compiled without the
wrappers for calls from Python (:func:`mechanism.core._jit.njit_inner`; a call from
Python runs a twin that has them).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mechanism.core._jit import njit_inner, njit_noalloc
from mechanism.core._status import STATUS_NONFINITE, STATUS_OK, STATUS_SINGULAR
from mechanism.core.bodies import beams_force_add, beams_strain_energy
from mechanism.core.contact import (
    APPROACH_RATIO,
    FRICTION_NONE,
    contact_potential,
    film_factor,
    friction_force,
    normal_force,
    positive_film_force,
    short_bearing_force,
)
from mechanism.core.forces import force_elements_add, force_elements_potential
from mechanism.core.joints import (
    PC_ANG,
    PC_RATE,
    PC_VX,
    PC_VY,
    PC_X,
    PC_Y,
    angle_acceleration,
    apply_point_force,
    clearance_force_add,
    clearance_kinematics,
    constraint_columns,
    constraint_rows,
    guide_acceleration,
    guide_force_add,
    guide_kinematics,
    point_acceleration,
    update_point_rows,
    update_points,
)
from mechanism.core.wear import local_clearance, local_stiffness_tabulated, surface_slope

# a worn joint in contact: in one step its contact direction slides over at most
# SLIDE_REGIONS regions of a worn surface, and its local clearance changes by at most
# SLIDE_CLEARANCE × c₀ (``_slide_step_if``)
SLIDE_REGIONS = 1
SLIDE_CLEARANCE = 0.05

# light samples: crank angle, slider s, ṡ, then e_x, e_y of each clearance joint
LIGHT_COLUMNS = 3
# columns of the per-clearance-joint table ``ws.cj`` filled by every force evaluation
CJ_EX = 0
CJ_EY = 1
CJ_DELTA = 2
CJ_DELTA_DOT = 3
CJ_VT = 4
CJ_FN = 5
CJ_FT = 6
CJ_PHI_B = 7
CJ_PHI_J = 8
CJ_K = 9  # contact stiffness used (the local K_n on a worn profile)
CJ_COLUMNS = 10

# columns of the clearance parameter table ``model.cj_f``
CF_RB = 0
CF_RJ = 1
CF_C = 2
CF_K = 3
CF_EXP = 4
CF_CE = 5
CF_MU = 6
CF_V0 = 7
CF_V1 = 8
CF_FLOOR = 9
# a corner of a translational clearance joint (CI_KIND = CONTACT_GUIDE) holds the distance
# h of its guide surface from the guide point in CF_RB (CF_RJ = 0) and the surface's
# outward normal in the guide body's frame here
CF_NX = 10
CF_NY = 11
# oil film of a lubricated revolute clearance joint (CF_VISC = 0: a dry joint): viscosity
# (Pa s), bearing length (m), film breakdown thickness (m) and the cavitation condition
# (0: the Pinkus–Sternlicht π-film, 1: the positive-pressure film)
CF_VISC = 12
CF_LUB_L = 13
CF_FILM = 14
CF_CAV = 15
CF_COLUMNS = 16

# columns of the clearance index table ``model.cj_i``: [bearing point, journal point, law
# code, friction code, kind]; a corner row has the guide point and the corner point
CI_KIND = 4
CI_COLUMNS = 5
CONTACT_JOURNAL = 0  # a journal in a bearing (revolute clearance joint)
CONTACT_GUIDE = 1  # a slider corner against a guide surface (translational clearance joint)

# counters (int64 array shared by the kernels and the integrators)
CNT_STEPS = 0
CNT_REJECTED = 1
CNT_FEV = 2
CNT_CONTACT_EVENTS = 3
CNT_CONTACT_EVALS = 4
CNT_JAC = 5
CNT_NEWTON = 6
CNT_WORN_EVALS = 7  # contact evaluations that read a worn profile (0 for unworn scenes)
CNT_COLUMNS = 8

# worn-profile table ``model.cw_i`` (n_cj, CW_COLUMNS) of every clearance joint: depths and
# tabulated curvatures of both surfaces are slices of the flat ``cw_h`` / ``cw_k``
CW_WORN = 0  # 1 when a profile is non-empty (else the unworn path runs)
CW_B_OFF = 1
CW_B_N = 2
CW_J_OFF = 3
CW_J_N = 4
CW_FORM = 5  # stiffness form code for the local stiffness, −1: K is a given number
CW_COLUMNS = 6
# ``model.cw_f`` (n_cj, 2) = [E*, radius ratio limit]


# columns of the derived output table written with every output sample
OUT_CRANK = 0
OUT_S = 1
OUT_SD = 2
OUT_SDD = 3
OUT_ENERGY = 4
OUT_VIOLATION = 5
OUT_COLUMNS = 6

# ideal-joint reaction table ``model.jt_i`` = [kind, first row, guide point]
JOINT_PIN = 0
JOINT_PRISMATIC = 1


@njit_noalloc()
def evaluate_constraints(model, ws, t, q, v):
    """Update the point cache and fill ``ws.phi``, ``ws.phiq``, ``ws.phit``, ``ws.gam``."""
    update_points(q, v, model.pt_i, model.pt_f, ws.pci, ws.pcf)
    ws.phiq[:, :] = 0.0
    constraint_rows(
        t,
        model.con_i,
        model.con_f,
        model.drive_i,
        model.drive_f,
        model.spline_x,
        model.spline_c,
        ws.pci,
        ws.pcf,
        ws.phi,
        ws.phiq,
        ws.phit,
        ws.gam,
    )


# ------------------------------------------------------------- effects a scene may lack
# Each ``*_if`` kernel calls the kernel of one effect unless its switch (a field of the
# model: ``beams_on``, ``forces_on``, ``worn_on``, ``film_on``) is None. numba removes a
# branch on an argument that is None before type inference, so a model whose switch is
# None compiles a no-op here and never compiles the effect's kernels. A switch is None
# only where the effect is absent (``with_effect_switches``), so the pruned call is one
# the kernels would have skipped at run time: results are unchanged.


@njit_inner()
def beams_force_if(on, beam_i, beam_f, q, v, scale, gen, work):
    """:func:`~mechanism.core.bodies.beams_force_add` unless ``on`` is None."""
    if on is None:
        return
    beams_force_add(beam_i, beam_f, q, v, scale, gen, work)


@njit_inner()
def beams_energy_if(on, beam_i, beam_f, q):
    """:func:`~mechanism.core.bodies.beams_strain_energy` (J), 0 when ``on`` is None."""
    if on is None:
        return 0.0
    return beams_strain_energy(beam_i, beam_f, q)


@njit_inner()
def forces_add_if(on, fe_i, fe_f, fe_t, t, pci, pcf, gen, fe):
    """:func:`~mechanism.core.forces.force_elements_add` unless ``on`` is None."""
    if on is None:
        return
    force_elements_add(fe_i, fe_f, fe_t, t, pci, pcf, gen, fe)


@njit_inner()
def forces_energy_if(on, fe_i, fe_f, fe_t, pcf):
    """:func:`~mechanism.core.forces.force_elements_potential` (J), 0 when ``on`` is None."""
    if on is None:
        return 0.0
    return force_elements_potential(fe_i, fe_f, fe_t, pcf)


@njit_inner()
def worn_contact_if(on, cw_i, cw_f, cw_h, cw_k, j, r_bearing, r_journal, clearance,
                    stiffness, phi_b, phi_j):  # fmt: skip
    """:func:`worn_contact`, or the unworn (c₀, K) when ``on`` is None."""
    if on is None:
        return clearance, stiffness
    return worn_contact(cw_i, cw_f, cw_h, cw_k, j, r_bearing, r_journal, clearance, stiffness,
                        phi_b, phi_j)  # fmt: skip


@njit_inner()
def worn_clearance_rate_if(on, cw_i, cw_h, j, pcf, bearing, journal, ex, ey, phi_b, phi_j):
    """:func:`worn_clearance_rate`, or 0 (an unworn joint's) when ``on`` is None."""
    if on is None:
        return 0.0
    return worn_clearance_rate(cw_i, cw_h, j, pcf, bearing, journal, ex, ey, phi_b, phi_j)


@njit_inner()
def guide_force_if(on, gen, pci, pcf, guide, corner, ex, ey, nx, ny, f_n, f_t):
    """:func:`~mechanism.core.joints.guide_force_add` unless ``on`` is None."""
    if on is None:
        return
    guide_force_add(gen, pci, pcf, guide, corner, ex, ey, nx, ny, f_n, f_t)


@njit_inner()
def guide_acceleration_if(on, acc, pci, pcf, guide, corner, ex, ey, nx, ny):
    """:func:`~mechanism.core.joints.guide_acceleration`, 0 when ``on`` is None."""
    if on is None:
        return 0.0
    return guide_acceleration(acc, pci, pcf, guide, corner, ex, ey, nx, ny)


@njit_inner()
def worn_contact(cw_i, cw_f, cw_h, cw_k, j, r_bearing, r_journal, clearance, stiffness,
                 phi_b, phi_j):  # fmt: skip
    """Local clearance c(φ_b, φ_j) (m) and stiffness K_n of clearance joint ``j``.

    Unworn joints return (c₀, K). A worn one reads the local clearance
    c₀ + h_b(φ_b) + h_j(φ_j) of the continuous worn surfaces (the monotone cubic through the
    region depths, ``mechanism.core.wear._kernels.surface_value``) and K_n = (4/3)E*√R*_n
    from the curvatures tabulated once per profile and interpolated by the same cubic
    (docs/paper-model.md §6); the damping of the force laws scales with K, so it follows.
    """
    if cw_i[j, CW_WORN] == 0:
        return clearance, stiffness
    bo = cw_i[j, CW_B_OFF]
    bn = cw_i[j, CW_B_N]
    jo = cw_i[j, CW_J_OFF]
    jn = cw_i[j, CW_J_N]
    c = local_clearance(clearance, cw_h[bo : bo + bn], cw_h[jo : jo + jn], phi_b, phi_j)
    if cw_i[j, CW_FORM] < 0:
        return c, stiffness
    kn = local_stiffness_tabulated(
        cw_f[j, 0], cw_i[j, CW_FORM], r_bearing, r_journal, cw_k[bo : bo + bn],
        cw_k[jo : jo + jn], phi_b, phi_j, cw_f[j, 1],
    )  # fmt: skip
    return c, kn


@njit_inner()
def worn_clearance_rate(cw_i, cw_h, j, pcf, bearing, journal, ex, ey, phi_b, phi_j):
    """dc/dt = h_b'(φ_b) φ̇_b + h_j'(φ_j) φ̇_j (m/s) of a worn joint (0 when unworn).

    The local clearance changes while the contact direction moves over a worn flank, so the
    penetration rate is δ̇ = d|e|/dt − dc/dt; h' is the exact angular derivative of the
    continuous surface that gives c (``surface_slope``), so δ̇ is the time derivative of δ,
    and φ̇ = (e × ė)/|e|² minus each part's rotation rate.
    """
    if cw_i[j, CW_WORN] == 0:
        return 0.0
    e2 = ex * ex + ey * ey
    if not e2 > 0.0:
        return 0.0
    dvx = pcf[journal, PC_VX] - pcf[bearing, PC_VX]
    dvy = pcf[journal, PC_VY] - pcf[bearing, PC_VY]
    rate = (ex * dvy - ey * dvx) / e2
    bo = cw_i[j, CW_B_OFF]
    bn = cw_i[j, CW_B_N]
    jo = cw_i[j, CW_J_OFF]
    jn = cw_i[j, CW_J_N]
    out = 0.0
    if bn > 0:
        out += surface_slope(cw_h[bo : bo + bn], phi_b) * (rate - pcf[bearing, PC_RATE])
    if jn > 0:
        out += surface_slope(cw_h[jo : jo + jn], phi_j) * (rate - pcf[journal, PC_RATE])
    return out


@njit_inner()
def contact_kinematics(cj_i, cj_f, pcf, j, guide_on=True):
    """``clearance_kinematics`` of row ``j`` of the clearance table: a journal in its
    bearing, or a slider corner against its guide surface (``guide_kinematics``).

    ``guide_on`` is the model's switch of slider corners (``KernelModel.guide_on``): with
    None the table has no corner row and the corner's kernels are not compiled."""
    if guide_on is not None:
        if cj_i[j, CI_KIND] == CONTACT_GUIDE:
            return guide_kinematics(
                pcf, cj_i[j, 0], cj_i[j, 1], cj_f[j, CF_NX], cj_f[j, CF_NY], cj_f[j, CF_RB]
            )
    return clearance_kinematics(
        pcf, cj_i[j, 0], cj_i[j, 1], cj_f[j, CF_RB], cj_f[j, CF_RJ], cj_f[j, CF_C]
    )


@njit_inner()
def film_force_add(cj_f, j, pci, pcf, b, jn, ex, ey, nx, ny, e_dot, gen):
    """gen += the oil-film force of lubricated clearance joint ``j``: the short-bearing
    force (``mechanism.core.contact._lubrication``) on the journal centre, its opposite on
    the bearing centre, faded out as the film thins to its breakdown thickness. ``e_dot``
    is d|e|/dt of the nominal geometry."""
    c = cj_f[j, CF_C]
    ne = math.sqrt(ex * ex + ey * ey)
    eps = ne / c
    w = film_factor(c, cj_f[j, CF_FILM], eps)
    if w == 0.0:
        return
    # ε W = ε (ω_j + ω_b) − 2 ε γ̇ with ε γ̇ = (e × ė)/(c |e|), finite at e = 0
    eps_w = eps * (pcf[jn, PC_RATE] + pcf[b, PC_RATE])
    if ne > 0.0:
        dvx = pcf[jn, PC_VX] - pcf[b, PC_VX]
        dvy = pcf[jn, PC_VY] - pcf[b, PC_VY]
        eps_w -= 2.0 * (ex * dvy - ey * dvx) / (c * ne)
    mu = cj_f[j, CF_VISC]
    length = cj_f[j, CF_LUB_L]
    if cj_f[j, CF_CAV] > 0.0:
        f_r, f_t = positive_film_force(mu, cj_f[j, CF_RJ], length, c, eps, e_dot / c, eps_w)
    else:
        f_r, f_t = short_bearing_force(mu, cj_f[j, CF_RJ], length, c, eps, e_dot / c, eps_w)
    fx = w * (f_r * nx - f_t * ny)
    fy = w * (f_r * ny + f_t * nx)
    apply_point_force(gen, fx, fy, 0.0, pci, pcf, jn)
    apply_point_force(gen, -fx, -fy, 0.0, pci, pcf, b)


@njit_inner()
def film_force_if(on, cj_f, j, pci, pcf, b, jn, ex, ey, nx, ny, e_dot, gen):
    """:func:`film_force_add` unless ``on`` is None (no lubricated joint)."""
    if on is None:
        return
    film_force_add(cj_f, j, pci, pcf, b, jn, ex, ey, nx, ny, e_dot, gen)


@njit_inner()
def clearance_forces(model, pci, pcf, vimp, gen, cj, counters):
    cj_i = model.cj_i
    cj_f = model.cj_f
    cw_i = model.cw_i
    for j in range(cj_i.shape[0]):
        b = cj_i[j, 0]
        jn = cj_i[j, 1]
        rb = cj_f[j, CF_RB]
        rj = cj_f[j, CF_RJ]
        c0 = cj_f[j, CF_C]
        ex, ey, nx, ny, delta, ddot, vt, phib, phij = contact_kinematics(
            cj_i, cj_f, pcf, j, model.guide_on
        )
        if cj_f[j, CF_VISC] > 0.0:
            film_force_if(model.film_on, cj_f, j, pci, pcf, b, jn, ex, ey, nx, ny, ddot, gen)
        kn = cj_f[j, CF_K]
        if cw_i[j, CW_WORN] != 0:
            counters[CNT_WORN_EVALS] += 1
            c, kn = worn_contact_if(
                model.worn_on, cw_i, model.cw_f, model.cw_h, model.cw_k, j, rb, rj, c0, kn,
                phib, phij,
            )  # fmt: skip
            delta += c0 - c
            ddot -= worn_clearance_rate_if(
                model.worn_on, cw_i, model.cw_h, j, pcf, b, jn, ex, ey, phib, phij
            )
        fn = 0.0
        ft = 0.0
        if delta > 0.0:
            counters[CNT_CONTACT_EVALS] += 1
            fn = normal_force(cj_i[j, 2], kn, cj_f[j, CF_EXP], cj_f[j, CF_CE], delta, ddot, vimp[j])
            if cj_i[j, 3] != FRICTION_NONE:
                ft = friction_force(
                    cj_i[j, 3], cj_f[j, CF_MU], cj_f[j, CF_V0], cj_f[j, CF_V1], fn, vt
                )
            if cj_i[j, CI_KIND] == CONTACT_GUIDE:
                guide_force_if(model.guide_on, gen, pci, pcf, b, jn, ex, ey, nx, ny, fn, ft)
            else:
                clearance_force_add(gen, pci, pcf, b, jn, rb, rj, nx, ny, fn, ft)
        cj[j, CJ_EX] = ex
        cj[j, CJ_EY] = ey
        cj[j, CJ_DELTA] = delta
        cj[j, CJ_DELTA_DOT] = ddot
        cj[j, CJ_VT] = vt
        cj[j, CJ_FN] = fn
        cj[j, CJ_FT] = ft
        cj[j, CJ_PHI_B] = phib
        cj[j, CJ_PHI_J] = phij
        cj[j, CJ_K] = kn


@njit_inner()
def cholesky_solve(s, b, m):
    """Solve S x = b in place (S symmetric positive definite, overwritten by its factor).

    Returns False if S is not numerically positive definite (redundant or singular
    constraints).
    """
    for j in range(m):
        d = s[j, j]
        for k in range(j):
            d -= s[j, k] * s[j, k]
        if not d > 1e-300:
            return False
        d = math.sqrt(d)
        s[j, j] = d
        for i in range(j + 1, m):
            x = s[i, j]
            for k in range(j):
                x -= s[i, k] * s[j, k]
            s[i, j] = x / d
    for i in range(m):
        x = b[i]
        for k in range(i):
            x -= s[i, k] * b[k]
        b[i] = x / s[i, i]
    for i in range(m - 1, -1, -1):
        x = b[i]
        for k in range(i + 1, m):
            x -= s[k, i] * b[k]
        b[i] = x / s[i, i]
    return True


@njit_inner()
def _schur_arrays(phiq, minv, minv_h, blk_lo, blk_hi, blk_st, con_i, pci, nzn, nzj, w, s):
    m, n = phiq.shape
    if minv_h is not None:
        # rods: a row's few nonzero columns among many coordinates, listed from the
        # columns of its primitive's points
        constraint_columns(con_i, pci, phiq, nzn, nzj)
    else:
        # rigid bodies: a scan of the few coordinates is cheaper than the lists
        for k in range(m):
            # branch-free compaction of the nonzero columns (the row of nzj has room for n)
            cnt = 0
            row = phiq[k]
            idx = nzj[k]
            for j in range(n):
                idx[cnt] = j
                cnt += row[j] != 0.0
            nzn[k] = cnt
    w[:, :] = 0.0
    for k in range(m):
        for e in range(nzn[k]):
            j = nzj[k, e]
            pj = phiq[k, j]
            lo = blk_lo[j]
            # (a model without such blocks has minv_h None and compiles no branch here)
            if minv_h is not None:
                if blk_st[j] == 2:
                    # only the rows of j's plane: the others are exact zeros of M⁻¹
                    mh = minv_h[j]
                    lo += (j - lo) % 2
                    for a in range((blk_hi[j] - blk_lo[j]) // 2):
                        w[lo + 2 * a, k] += mh[a] * pj
                    continue
            mj = minv[j]  # column j of the symmetric M⁻¹, read as its contiguous row
            for i in range(lo, blk_hi[j]):
                w[i, k] += mj[i] * pj
    for k in range(m):
        for ll in range(k + 1):
            acc = 0.0
            for e in range(nzn[k]):
                j = nzj[k, e]
                acc += phiq[k, j] * w[j, ll]
            s[k, ll] = acc
            s[ll, k] = acc


@njit_noalloc(inline="always")
def schur(model, ws):
    """W = M⁻¹Φqᵀ and S = Φq W from the current Φq, using each row's nonzero columns."""
    _schur_arrays(ws.phiq, model.minv, model.minv_h, model.blk_lo, model.blk_hi, model.blk_st,
                  model.con_i, ws.pci, ws.nz_n, ws.nz_j, ws.w, ws.s)  # fmt: skip


@njit_noalloc()
def accelerations(model, ws, t, q, v, vimp, acc, counters):
    """Solve the equations of motion for q̈ (into ``acc``) and λ (into ``ws.lam``).

    Returns a status code (0 success, 2 singular constraint Jacobian, 3 non-finite).
    """
    counters[CNT_FEV] += 1
    # array-level calls: passing the model/workspace tuples costs more than the arithmetic
    pci = ws.pci
    pcf = ws.pcf
    phi = ws.phi
    phiq = ws.phiq
    phit = ws.phit
    gam = ws.gam
    gen = ws.gen
    update_points(q, v, model.pt_i, model.pt_f, pci, pcf)
    phiq[:, :] = 0.0
    constraint_rows(
        t, model.con_i, model.con_f, model.drive_i, model.drive_f, model.spline_x,
        model.spline_c, pci, pcf, phi, phiq, phit, gam,
    )  # fmt: skip
    # Q = gravity − elastic/damping forces of the ANCF beams + contact/friction + force
    # elements (each term only when the scene has it, so an absent effect costs nothing)
    gravity = model.gravity_force
    for i in range(gen.shape[0]):
        gen[i] = gravity[i]
    if model.beam_i.shape[0] > 0:
        beams_force_if(model.beams_on, model.beam_i, model.beam_f, q, v, -1.0, gen, ws.beam)
    if model.cj_i.shape[0] > 0:
        clearance_forces(model, pci, pcf, vimp, gen, ws.cj, counters)
    if model.fe_i.shape[0] > 0:
        forces_add_if(model.forces_on, model.fe_i, model.fe_f, model.fe_t, t, pci, pcf, gen, ws.fe)
    return solve(
        model.minv, model.minv_h, model.blk_lo, model.blk_hi, model.blk_st, model.con_i, pci,
        model.alpha, model.beta, phi, phiq, phit, gam, gen, v, ws.a0, ws.w, ws.s, ws.lam,
        ws.nz_n, ws.nz_j, acc,
    )  # fmt: skip


@njit_inner()
def _block_solve(minv, minv_h, blk_lo, blk_hi, blk_st, x, out):
    """out = M⁻¹x block by block, as a sum of the columns of the symmetric M⁻¹ (read as
    its contiguous rows) over slices: no reduction and no bounds read per element, so the
    compiler vectorises it (5× faster than row dot products on a 68 × 68 ANCF block). A
    block of two planes (``blk_st`` 2) sums each plane's columns over its own rows only
    (``minv_h``, None in a model without such blocks): the same nonzero terms in the same
    order, at half the arithmetic."""
    n = x.shape[0]
    out[:] = 0.0
    j = 0
    while j < n:
        lo = blk_lo[j]
        hi = blk_hi[j]
        o = out[lo:hi]
        if minv_h is not None:
            if blk_st[j] == 2:
                half = (hi - lo) // 2
                for b in range(half):
                    xe = x[lo + 2 * b]
                    xo = x[lo + 2 * b + 1]
                    me = minv_h[lo + 2 * b]
                    mo = minv_h[lo + 2 * b + 1]
                    for a in range(half):
                        o[2 * a] += me[a] * xe
                        o[2 * a + 1] += mo[a] * xo
                j = hi
                continue
        for jj in range(lo, hi):
            xj = x[jj]
            mj = minv[jj, lo:hi]
            for i in range(hi - lo):
                o[i] += mj[i] * xj
        j = hi


@njit_inner()
def solve(minv, minv_h, blk_lo, blk_hi, blk_st, con_i, pci, alpha, beta, phi, phiq, phit, gam,
          gen, v, a0, w, s, lam, nzn, nzj, acc):  # fmt: skip
    n = a0.shape[0]
    m = phi.shape[0]
    _block_solve(minv, minv_h, blk_lo, blk_hi, blk_st, gen, a0)
    if m == 0:
        for i in range(n):
            acc[i] = a0[i]
        return STATUS_OK
    _schur_arrays(phiq, minv, minv_h, blk_lo, blk_hi, blk_st, con_i, pci, nzn, nzj, w, s)
    two_alpha = 2.0 * alpha
    beta2 = beta * beta
    for k in range(m):
        pv = phit[k]
        pa = 0.0
        for e in range(nzn[k]):
            j = nzj[k, e]
            pj = phiq[k, j]
            pv += pj * v[j]
            pa += pj * a0[j]
        lam[k] = pa - (gam[k] - two_alpha * pv - beta2 * phi[k])
    if not cholesky_solve(s, lam, m):
        return STATUS_SINGULAR
    # q̈ = a₀ − Wλ, each column of W only over the mass blocks of its row's nonzero
    # columns (W is zero elsewhere; per entry the same subtractions in the same order)
    for i in range(n):
        acc[i] = a0[i]
    for k in range(m):
        lk = lam[k]
        last = -1
        for e in range(nzn[k]):
            lo = blk_lo[nzj[k, e]]
            if lo == last:
                continue
            last = lo
            for i in range(lo, blk_hi[nzj[k, e]]):
                acc[i] -= w[i, k] * lk
    ok = True
    for i in range(n):
        if not math.isfinite(acc[i]):
            ok = False
    return STATUS_OK if ok else STATUS_NONFINITE


@njit_noalloc()
def rhs(model, ws, t, y, vimp, dydt, counters):
    """First-order form y = [q; q̇], ẏ = [q̇; q̈]. Returns the status of :func:`accelerations`."""
    n = model.n_dof
    for i in range(n):
        dydt[i] = y[n + i]
    return accelerations(model, ws, t, y[:n], y[n:], vimp, dydt[n:], counters)


@njit_inner()
def clearance_state(model, ws, y, j):
    """(δ, δ̇, K) of clearance joint ``j`` at state ``y`` (point cache must be current);
    δ and K from the local clearance and stiffness on a worn profile."""
    rb = model.cj_f[j, CF_RB]
    rj = model.cj_f[j, CF_RJ]
    c0 = model.cj_f[j, CF_C]
    res = contact_kinematics(model.cj_i, model.cj_f, ws.pcf, j, model.guide_on)
    c, kn = worn_contact_if(
        model.worn_on, model.cw_i, model.cw_f, model.cw_h, model.cw_k, j, rb, rj, c0,
        model.cj_f[j, CF_K], res[7], res[8],
    )  # fmt: skip
    rate = worn_clearance_rate_if(
        model.worn_on, model.cw_i, model.cw_h, j, ws.pcf, model.cj_i[j, 0], model.cj_i[j, 1],
        res[0], res[1], res[7], res[8],
    )  # fmt: skip
    return res[4] + c0 - c, res[5] - rate, kn


@njit_noalloc()
def update_latch(model, ws, y, vimp, contact, counters, carry_worn):
    """Discrete contact state after an accepted step (the impact-velocity latch).

    While a joint is separated (δ ≤ 0) its impact velocity tracks the approach speed δ̇
    of the latest accepted state, floored at ``impact_velocity_floor``; when an accepted
    state penetrates, the value is frozen until separation and a contact event is
    counted. Separated states feel no contact force, so updating the latch never changes
    the right-hand side at the current state.

    With ``carry_worn`` (the fixed-step generalized-α), a worn joint in contact whose
    accepted state is driven in faster than ``APPROACH_RATIO`` times its latched speed
    latches δ̇/``APPROACH_RATIO`` instead: on a worn flank a sliding journal separates and
    re-enters at a grazing δ̇ (the latch holds the floor) and is then carried in at its
    sliding speed, and the damping χ̂Kδⁿ/δ̇⁻ of such a latch is a damper far stiffer than a
    fixed step can follow (docs/simulator.md, "Fixed-step generalized-α on worn
    profiles").
    """
    if model.cj_i.shape[0] == 0:
        return
    n = model.n_dof
    for j in range(model.cj_i.shape[0]):
        # the clearance state reads the joint's bearing and journal points only
        update_point_rows(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf, model.cj_i[j, :2])
        delta, ddot, _ = clearance_state(model, ws, y, j)
        if delta > 0.0:
            if contact[j] == 0:
                contact[j] = 1
                counters[CNT_CONTACT_EVENTS] += 1
            if carry_worn and model.cw_i[j, CW_WORN] != 0 and ddot > APPROACH_RATIO * vimp[j]:
                vimp[j] = ddot / APPROACH_RATIO
        else:
            contact[j] = 0
            floor = model.cj_f[j, CF_FLOOR]
            vimp[j] = ddot if ddot > floor else floor


@njit_inner()
def entry_depth_ratio(model, ws, y, contact):
    """Largest δ/c at state ``y`` over the clearance joints that were separated
    (``contact`` = 0) at the last accepted state, or −inf; the implicit integrator rejects
    steps that enter contact too deep."""
    worst = -np.inf
    separated = False
    for j in range(model.cj_i.shape[0]):
        separated = separated or contact[j] == 0
    if not separated:
        return worst
    n = model.n_dof
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    for j in range(model.cj_i.shape[0]):
        if contact[j] != 0:
            continue
        delta, _, _ = clearance_state(model, ws, y, j)
        r = delta / model.cj_f[j, CF_C]
        if r > worst:
            worst = r
    return worst


@njit_inner()
def approach_step(model, ws, y, acc, fraction):
    """Longest step (s) in which no separated clearance joint's journal can travel more
    than ``fraction`` of its gap to the bearing wall, at state ``y`` with accelerations
    ``acc`` (q̈); inf when every joint is in contact (local δ > 0) on an unworn profile:
    the step is then the error control's, which sees the contact force in its stages. A
    worn joint in contact is bounded only by the slide of its contact direction over its
    worn surfaces (:func:`_slide_step_if`).

    The gap g is a lower bound on the distance from the journal centre to the wall. With
    the relative speed v = |ė| and acceleration a = |ë| of the journal centre,
    v h + ½ a h² = f g (f = ``fraction``) gives h = 2 f g / (v + √(v² + 2 a f g)). On an
    unworn joint g = c₀ − |e|. On a worn one the wall is the local clearance
    c = c₀ + h_b + h_j, and g is the larger of c₀ − |e| (wear only deepens) and
    :func:`_worn_gap`, the smallest local clearance the journal can face during the step
    minus |e|, positive for a journal in a worn groove beyond c₀.
    A grazing joint (g = 0) returns 0: the caller's floor applies.
    """
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return np.inf
    n = model.n_dof
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    pcf = ws.pcf
    limit = np.inf
    for j in range(ncj):
        delta, _, _ = clearance_state(model, ws, y, j)
        if delta > 0.0:
            limit = min(limit, _slide_step_if(model.worn_on, model, ws, j))
            continue
        b = model.cj_i[j, 0]
        jn = model.cj_i[j, 1]
        if model.cj_i[j, CI_KIND] == CONTACT_GUIDE:
            limit = min(limit, _corner_approach(model, ws, acc, j, delta, fraction))
            continue
        ex = pcf[jn, PC_X] - pcf[b, PC_X]
        ey = pcf[jn, PC_Y] - pcf[b, PC_Y]
        ne = math.sqrt(ex * ex + ey * ey)
        vx = pcf[jn, PC_VX] - pcf[b, PC_VX]
        vy = pcf[jn, PC_VY] - pcf[b, PC_VY]
        ajx, ajy = point_acceleration(acc, ws.pci, pcf, jn)
        abx, aby = point_acceleration(acc, ws.pci, pcf, b)
        speed = math.sqrt(vx * vx + vy * vy)
        accel = math.sqrt((ajx - abx) ** 2 + (ajy - aby) ** 2)
        gap = model.cj_f[j, CF_C] - ne
        gap = _worn_gap_if(model.worn_on, model, ws, acc, j, -delta, ne, gap, speed, accel,
                           fraction)  # fmt: skip
        gap = fraction * gap
        if not gap > 0.0:
            return 0.0
        limit = min(limit, _reach(gap, speed, accel))
    return limit


@njit_noalloc(inline="always")
def _reach(gap, speed, accel):
    """Time (s) to travel ``gap`` from ``speed`` at ``accel``: v h + ½ a h² = g."""
    denom = speed + math.sqrt(speed * speed + 2.0 * accel * gap)
    return 2.0 * gap / denom if denom > 0.0 else np.inf


@njit_inner()
def _slide_step_if(on, model, ws, j):
    """Step (s) in which the depth of each worn surface of joint ``j`` in contact changes
    by at most ``SLIDE_CLEARANCE`` × c₀ as its contact direction slides (inf when unworn or
    when ``on`` is None).

    The surface is C1, but a flank may be as deep as the clearance and one region wide; a
    step that slid across it in one go would reach the far side with the error control
    seeing the force change only there. Between region centres the surface is monotone,
    so over one region it changes by at most D, the largest difference of neighbouring
    region depths within ``SLIDE_REGIONS`` + 1 regions of the direction; the direction
    moves over a surface at φ̇ = (e × ė)/|e|² minus the part's rate, so
    h = min(SLIDE_CLEARANCE c₀ / D, ``SLIDE_REGIONS``) regions / |φ̇|.
    """
    if on is None:
        return np.inf
    cw_i = model.cw_i
    if cw_i[j, CW_WORN] == 0:
        return np.inf
    pcf = ws.pcf
    b = model.cj_i[j, 0]
    jn = model.cj_i[j, 1]
    ex = pcf[jn, PC_X] - pcf[b, PC_X]
    ey = pcf[jn, PC_Y] - pcf[b, PC_Y]
    e2 = ex * ex + ey * ey
    if not e2 > 0.0:
        return np.inf
    vx = pcf[jn, PC_VX] - pcf[b, PC_VX]
    vy = pcf[jn, PC_VY] - pcf[b, PC_VY]
    turn = (ex * vy - ey * vx) / e2
    phi = math.atan2(ey, ex)
    allowed = SLIDE_CLEARANCE * model.cj_f[j, CF_C]
    out = np.inf
    for part, off, regions in (
        (b, cw_i[j, CW_B_OFF], cw_i[j, CW_B_N]), (jn, cw_i[j, CW_J_OFF], cw_i[j, CW_J_N])
    ):  # fmt: skip
        rate = abs(turn - pcf[part, PC_RATE])
        if regions == 0 or not rate > 0.0:
            continue
        values = model.cw_h[off : off + regions]
        here = math.floor((phi - pcf[part, PC_ANG]) * regions / (2.0 * math.pi))
        jump = 0.0
        for k in range(here - SLIDE_REGIONS - 1, here + SLIDE_REGIONS + 2):
            k0 = (k % regions + regions) % regions
            jump = max(jump, abs(values[(k0 + 1) % regions] - values[k0]))
        cells = SLIDE_REGIONS if not jump * SLIDE_REGIONS > allowed else allowed / jump
        out = min(out, cells * 2.0 * math.pi / regions / rate)
    return out


@njit_inner()
def _worn_gap_if(on, model, ws, acc, j, radial, ne, gap, speed, accel, fraction):
    """:func:`_worn_gap` of a worn joint ``j``, else ``gap`` (also when ``on`` is None)."""
    if on is None:
        return gap
    if model.cw_i[j, CW_WORN] == 0:
        return gap
    return max(gap, _worn_gap(model, ws, acc, j, radial, ne, speed, accel, fraction))


@njit_inner()
def _worn_gap(model, ws, acc, j, radial, ne, speed, accel, fraction):
    """Lower bound (m) on the distance from a separated worn journal's centre to its wall
    during the step of :func:`approach_step`.

    ``radial`` = c(φ) − |e| > 0 is the radial gap at the current contact direction φ. A
    wall point at an angle Δ from φ is at least |e| sin Δ away (beyond 90°: at least c₀),
    so the walls outside ±W, sin W = ``radial``/|e|, are farther than ``radial``; inside,
    the wall is at least min c − |e| away, with min c = c₀ + min h_b + min h_j over the
    window in each part's frame, widened by the part's rotation |θ̇| h + ½ |θ̈| h² over the
    step h. The step depends on the gap, so the rotation is taken over the step of the
    narrower window first: the wider window gives a smaller gap, hence a shorter step
    than the one its rotation was taken over.
    """
    if not radial > 0.0:
        return 0.0
    c0 = model.cj_f[j, CF_C]
    half = 0.5 * math.pi if not radial < ne else math.asin(radial / ne)
    pcf = ws.pcf
    b = model.cj_i[j, 0]
    jn = model.cj_i[j, 1]
    phi = math.atan2(pcf[jn, PC_Y] - pcf[b, PC_Y], pcf[jn, PC_X] - pcf[b, PC_X])
    phi_b = phi - pcf[b, PC_ANG]
    phi_j = phi - pcf[jn, PC_ANG]
    first = min(_window_clearance(model, j, c0, phi_b, half, phi_j, half) - ne, c0)
    if not first > 0.0:
        return first
    h = _reach(fraction * first, speed, accel)
    turn_b = abs(pcf[b, PC_RATE]) * h + 0.5 * abs(angle_acceleration(acc, ws.pci, pcf, b)) * h * h
    turn_j = abs(pcf[jn, PC_RATE]) * h + 0.5 * abs(angle_acceleration(acc, ws.pci, pcf, jn)) * h * h
    wall = _window_clearance(model, j, c0, phi_b, half + turn_b, phi_j, half + turn_j)
    return min(wall - ne, c0)


@njit_inner()
def _window_clearance(model, j, c0, phi_b, half_b, phi_j, half_j):
    """c₀ + min h_b over φ_b ± ``half_b`` + min h_j over φ_j ± ``half_j`` (m) of joint ``j``."""
    cw_i = model.cw_i
    cw_h = model.cw_h
    bo = cw_i[j, CW_B_OFF]
    jo = cw_i[j, CW_J_OFF]
    none = cw_h[0:0]
    return (
        c0
        + _surface_min(cw_h[bo : bo + cw_i[j, CW_B_N]], none, phi_b, half_b)
        + _surface_min(cw_h[jo : jo + cw_i[j, CW_J_N]], none, phi_j, half_j)
    )


@njit_inner()
def _surface_min(values, none, angle, half):
    """Smallest value over angle ± ``half`` of the continuous surface through per-region
    ``values`` (0 when empty; ``none`` is an empty array).

    The surface is monotone between neighbouring region centres, so its minimum over an
    arc is at an end of the arc or at a region centre inside it.
    """
    n = values.size
    if n == 0:
        return 0.0
    low = np.inf
    if not half < math.pi:
        for k in range(n):
            low = min(low, values[k])
        return low
    # local_clearance with c₀ = 0 and no second surface is the value of one surface
    low = min(
        local_clearance(0.0, values, none, angle - half, 0.0),
        local_clearance(0.0, values, none, angle + half, 0.0),
    )
    scale = n / (2.0 * math.pi)
    first = math.ceil((angle - half) * scale - 0.5)
    last = math.floor((angle + half) * scale - 0.5)
    for k in range(first, last + 1):
        low = min(low, values[((k % n) + n) % n])
    return low


@njit_noalloc(inline="always")
def _corner_approach(model, ws, acc, j, delta, fraction):
    """The step of :func:`approach_step` for a separated slider corner (row ``j``, at
    penetration ``delta`` ≤ 0): the gap is its distance −δ to the guide surface, the speed
    and acceleration those of δ (normal to the surface; sliding along it closes no gap)."""
    gap = -fraction * delta
    if not gap > 0.0:
        return 0.0
    ex, ey, nx, ny, _, ddot, _, _, _ = contact_kinematics(
        model.cj_i, model.cj_f, ws.pcf, j, model.guide_on
    )
    speed = abs(ddot)
    accel = abs(
        guide_acceleration_if(
            model.guide_on, acc, ws.pci, ws.pcf, model.cj_i[j, 0], model.cj_i[j, 1], ex, ey,
            nx, ny,
        )
    )  # fmt: skip
    denom = speed + math.sqrt(speed * speed + 2.0 * accel * gap)
    return 2.0 * gap / denom if denom > 0.0 else np.inf


@njit_inner()
def journal_travel_ratio(model, ws, y0, y1):
    """Largest |e(y1) − e(y0)|/c₀ over the clearance joints: how far, in nominal radial
    clearances, a journal centre moved relative to its bearing between two states (0
    without clearance joints). Overwrites the joints' rows of the point cache."""
    n = model.n_dof
    worst = 0.0
    pcf = ws.pcf
    for j in range(model.cj_i.shape[0]):
        b = model.cj_i[j, 0]
        jn = model.cj_i[j, 1]
        rows = model.cj_i[j, :2]
        update_point_rows(y0[:n], y0[n:], model.pt_i, model.pt_f, ws.pci, pcf, rows)
        if model.cj_i[j, CI_KIND] == CONTACT_GUIDE:
            # a corner's travel towards or away from its surface: sliding along it is free
            d0 = contact_kinematics(model.cj_i, model.cj_f, pcf, j, model.guide_on)[4]
            update_point_rows(y1[:n], y1[n:], model.pt_i, model.pt_f, ws.pci, pcf, rows)
            d1 = contact_kinematics(model.cj_i, model.cj_f, pcf, j, model.guide_on)[4]
            r = abs(d1 - d0) / model.cj_f[j, CF_C]
            if r > worst:
                worst = r
            continue
        ex = pcf[jn, PC_X] - pcf[b, PC_X]
        ey = pcf[jn, PC_Y] - pcf[b, PC_Y]
        update_point_rows(y1[:n], y1[n:], model.pt_i, model.pt_f, ws.pci, pcf, rows)
        dx = pcf[jn, PC_X] - pcf[b, PC_X] - ex
        dy = pcf[jn, PC_Y] - pcf[b, PC_Y] - ey
        r = math.sqrt(dx * dx + dy * dy) / model.cj_f[j, CF_C]
        if r > worst:
            worst = r
    return worst


@njit_noalloc()
def project(model, ws, t, y, tol, max_iter):
    """Project positions onto Φ(q, t) = 0 and velocities onto Φq q̇ + Φt = 0.

    Minimum-mass-norm corrections Δq = −M⁻¹Φqᵀ(ΦqM⁻¹Φqᵀ)⁻¹Φ (Newton) and the same for
    q̇; returns False when the constraint matrix is singular.
    """
    n = model.n_dof
    m = model.n_rows
    if m == 0:
        return True
    q = y[:n]
    v = y[n:]
    for _ in range(max_iter):
        evaluate_constraints(model, ws, t, q, v)
        err = 0.0
        for k in range(m):
            err = max(err, abs(ws.phi[k]))
        if err < tol:
            break
        schur(model, ws)
        for k in range(m):
            ws.lam[k] = ws.phi[k]
        if not cholesky_solve(ws.s, ws.lam, m):
            return False
        for i in range(n):
            s = 0.0
            for k in range(m):
                s += ws.w[i, k] * ws.lam[k]
            q[i] -= s
    evaluate_constraints(model, ws, t, q, v)
    schur(model, ws)
    for k in range(m):
        s = ws.phit[k]
        for j in range(n):
            s += ws.phiq[k, j] * v[j]
        ws.lam[k] = s
    if not cholesky_solve(ws.s, ws.lam, m):
        return False
    for i in range(n):
        s = 0.0
        for k in range(m):
            s += ws.w[i, k] * ws.lam[k]
        v[i] -= s
    return True


@njit_inner()
def mechanical_energy(model, ws, y):
    """Kinetic + gravity + contact potential + beam strain energy + the potential of the
    force elements (J) of state ``y``.

    T = ½ q̇ᵀMq̇, V_g = −Q_gᵀq (Q_g constant), V_c = Σ K δ^(n+1)/(n+1), for flexible
    bodies U = Σ ∫ ½EA ε² + ½EI κ² dx by the quadrature of their elastic forces
    (:func:`~mechanism.core.bodies._ancf_kernels.beams_strain_energy`), and the energy
    stored by springs and actuators
    (:func:`~mechanism.core.forces._kernels.force_elements_potential`; dampers and
    applied loads store none).
    """
    n = model.n_dof
    q = y[:n]
    v = y[n:]
    kin = 0.0
    for i in range(n):
        s = 0.0
        for j in range(model.blk_lo[i], model.blk_hi[i]):
            s += model.mass[i, j] * v[j]
        kin += 0.5 * v[i] * s
    pot = 0.0
    for i in range(n):
        pot -= model.gravity_force[i] * q[i]
    if model.cj_i.shape[0] > 0:
        update_points(q, v, model.pt_i, model.pt_f, ws.pci, ws.pcf)
        for j in range(model.cj_i.shape[0]):
            delta, _, kn = clearance_state(model, ws, y, j)
            pot += contact_potential(kn, model.cj_f[j, CF_EXP], delta)
    if model.beam_i.shape[0] > 0:
        pot += beams_energy_if(model.beams_on, model.beam_i, model.beam_f, q)
    if model.fe_i.shape[0] > 0:
        update_points(q, v, model.pt_i, model.pt_f, ws.pci, ws.pcf)
        pot += forces_energy_if(model.forces_on, model.fe_i, model.fe_f, model.fe_t, ws.pcf)
    return kin + pot


# --------------------------------------------------------------------------- output series


@njit(cache=True)
def energy_series(model, ws, q, v, out):
    """:func:`mechanical_energy` for every sample (J)."""
    n = model.n_dof
    y = np.empty(2 * n)
    for i in range(q.shape[0]):
        for j in range(n):
            y[j] = q[i, j]
            y[n + j] = v[i, j]
        out[i] = mechanical_energy(model, ws, y)


@njit_noalloc()
def violation_series(model, ws, t, q, v, out):
    """max_k |Φ_k(q, t)| for every sample (m for point rows, rad for angle rows)."""
    for i in range(q.shape[0]):
        evaluate_constraints(model, ws, t[i], q[i], v[i])
        worst = 0.0
        for k in range(model.n_rows):
            worst = max(worst, abs(ws.phi[k]))
        out[i] = worst


@njit_inner()
def crank_angle(model, pcf):
    """Crank angle (rad, unwrapped) from the point cache; 0 without a crank joint."""
    pa = model.out_i[0]
    pb = model.out_i[1]
    return pcf[pb, PC_ANG] - pcf[pa, PC_ANG] if pa >= 0 else 0.0


@njit_inner()
def _slider_kinematics(model, pcf):
    """Slider position s and velocity ṡ along its guide from the point cache, with the
    guide direction (gx, gy), its rate ω and the relative position and velocity (d, ḋ)."""
    ga = model.out_i[2]
    gb = model.out_i[3]
    th = pcf[ga, PC_ANG]
    w = pcf[ga, PC_RATE]
    c = math.cos(th)
    sn = math.sin(th)
    ux = model.out_f[0]
    uy = model.out_f[1]
    gx = c * ux - sn * uy
    gy = sn * ux + c * uy
    kx = -gy
    ky = gx
    dx = pcf[gb, PC_X] - pcf[ga, PC_X]
    dy = pcf[gb, PC_Y] - pcf[ga, PC_Y]
    ddx = pcf[gb, PC_VX] - pcf[ga, PC_VX]
    ddy = pcf[gb, PC_VY] - pcf[ga, PC_VY]
    # s = u·d, u = A(θ_a) ū: ṡ = u̇·d + u·ḋ, s̈ = ü·d + 2u̇·ḋ + u·d̈
    s = gx * dx + gy * dy
    sd = w * (kx * dx + ky * dy) + gx * ddx + gy * ddy
    return s, sd, gx, gy, w, dx, dy, ddx, ddy


@njit_noalloc()
def light_outputs(model, ws, y, out):
    """Crank angle, slider s and ṡ of state ``y`` from positions and velocities alone
    (no right-hand-side evaluation): ``out`` = [crank angle, s, ṡ] (0 where absent),
    followed, when ``out`` has room, by the eccentricity e_x, e_y of each clearance joint
    (journal centre minus bearing centre, m; columns ``LIGHT_COLUMNS + 2j``, ``+ 1``)."""
    n = model.n_dof
    pcf = ws.pcf
    update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, pcf)
    out[0] = crank_angle(model, pcf)
    if model.out_i[2] >= 0:
        s, sd, _, _, _, _, _, _, _ = _slider_kinematics(model, pcf)
        out[1] = s
        out[2] = sd
    else:
        out[1] = 0.0
        out[2] = 0.0
    cj_i = model.cj_i
    if out.shape[0] >= LIGHT_COLUMNS + 2 * cj_i.shape[0]:
        for j in range(cj_i.shape[0]):
            out[LIGHT_COLUMNS + 2 * j] = pcf[cj_i[j, 1], PC_X] - pcf[cj_i[j, 0], PC_X]
            out[LIGHT_COLUMNS + 2 * j + 1] = pcf[cj_i[j, 1], PC_Y] - pcf[cj_i[j, 0], PC_Y]


@njit_inner()
def derived_outputs(model, ws, q, v, a, out, jf):
    """Output quantities of the state whose right-hand side was just evaluated.

    Reads the point cache, λ, Φ and the clearance table left in ``ws`` by
    :func:`accelerations` at (q, q̇) with accelerations ``a``, and writes ``out``
    (crank angle, slider s, ṡ, s̈, mechanical energy, max|Φ|) and ``jf`` (reaction force
    on ``bodies[1]`` of every ideal joint, N).
    """
    pci = ws.pci
    pcf = ws.pcf
    out[OUT_CRANK] = crank_angle(model, pcf)
    ga = model.out_i[2]
    gb = model.out_i[3]
    if ga >= 0:
        s, sd, gx, gy, w, dx, dy, ddx, ddy = _slider_kinematics(model, pcf)
        kx = -gy
        ky = gx
        al = angle_acceleration(a, pci, pcf, ga)
        aax, aay = point_acceleration(a, pci, pcf, ga)
        abx, aby = point_acceleration(a, pci, pcf, gb)
        out[OUT_S] = s
        out[OUT_SD] = sd
        out[OUT_SDD] = (
            al * (kx * dx + ky * dy)
            - w * w * (gx * dx + gy * dy)
            + 2.0 * w * (kx * ddx + ky * ddy)
            + gx * (abx - aax)
            + gy * (aby - aay)
        )
    else:
        out[OUT_S] = 0.0
        out[OUT_SD] = 0.0
        out[OUT_SDD] = 0.0
    n = model.n_dof
    energy = 0.0
    for i in range(n):
        x = 0.0
        for j in range(model.blk_lo[i], model.blk_hi[i]):
            x += model.mass[i, j] * v[j]
        energy += 0.5 * v[i] * x - model.gravity_force[i] * q[i]
    for j in range(model.cj_i.shape[0]):
        energy += contact_potential(ws.cj[j, CJ_K], model.cj_f[j, CF_EXP], ws.cj[j, CJ_DELTA])
    if model.beam_i.shape[0] > 0:
        energy += beams_energy_if(model.beams_on, model.beam_i, model.beam_f, q)
    if model.fe_i.shape[0] > 0:
        energy += forces_energy_if(model.forces_on, model.fe_i, model.fe_f, model.fe_t, pcf)
    out[OUT_ENERGY] = energy
    worst = 0.0
    for k in range(model.n_rows):
        worst = max(worst, abs(ws.phi[k]))
    out[OUT_VIOLATION] = worst
    for j in range(model.jt_i.shape[0]):
        r = model.jt_i[j, 1]
        if model.jt_i[j, 0] == JOINT_PIN:
            jf[j, 0] = ws.lam[r]
            jf[j, 1] = ws.lam[r + 1]
        else:
            # Φ = n·(r_b − r_a): the force on b is −n λ
            th = pcf[model.jt_i[j, 2], PC_ANG]
            c = math.cos(th)
            sn = math.sin(th)
            nx = c * model.jt_f[j, 0] - sn * model.jt_f[j, 1]
            ny = sn * model.jt_f[j, 0] + c * model.jt_f[j, 1]
            jf[j, 0] = -nx * ws.lam[r + 1]
            jf[j, 1] = -ny * ws.lam[r + 1]
