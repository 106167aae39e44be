"""Compiled kinematics of points, angles, ideal-constraint rows and clearance joints.

Everything here works on the flat tables built by ``mechanism/core/model/_assemble.py``.

Points (``pt_i``: int64 (n_points, 8), ``pt_f``: float64 (n_points, 6))
    ``pt_i[k] = [kind, base, angle_kind, slope, d0, d1, d2, d3]`` and
    ``pt_f[k] = [sx, sy, w0, w1, w2, w3]``.

    * ``kind = POINT_GROUND``: a fixed global point (sx, sy).
    * ``kind = POINT_RIGID``: r = R + A(θ) s̄ on a rigid body whose (x, y, θ) are
      q[base], q[base + 1], q[base + 2] (docs/paper-model.md §3); nonlinear in θ.
    * ``kind = POINT_LINEAR``: r = Σᵢ wᵢ (q[dᵢ], q[dᵢ + 1]) over the dᵢ ≥ 0, e.g. an ANCF
      node (one entry, weight 1) or a point inside an ANCF element (shape-function
      weights); linear in q, so it has no velocity-quadratic acceleration term.

    The angle attached to a point (used by prismatic, fixed and drive rows, contact angles
    and the friction moment) is 0 for ``ANGLE_NONE``, θ = q[base + 2] for ``ANGLE_RIGID``
    and atan2(r,ₓ,y, r,ₓ,x) of the slope (q[slope], q[slope + 1]) for ``ANGLE_SLOPE``.

Point cache (``pci``: int64 (n_points, PCI_COLUMNS), ``pcf``: float64 (n_points,
PCF_COLUMNS)), filled once per evaluation by :func:`update_points`
    position, velocity, the velocity-quadratic acceleration term (r̈ = J q̈ + that), the
    angle, its rate and quadratic term, and the sparse Jacobians ∂r/∂q (up to 8 entries
    (dof, ∂x/∂q_dof, ∂y/∂q_dof)) and ∂θ/∂q (up to 2 entries). Every constraint row, force
    and output reads the cache, so each point's trigonometry is evaluated once.

Constraint primitives (``con_i``: int64 (n_con, 4) = [type, a, b, row], ``con_f``: (n_con, 4))
    * ``CON_COINCIDE`` (2 rows): Φ = r_a − r_b − c, c = (con_f[0], con_f[1]).
    * ``CON_ANGLE`` (1 row): Φ = θ_b − θ_a − con_f[0].
    * ``CON_NORMAL`` (1 row): Φ = n_a · (r_b − r_a) − con_f[2], n_a = A(θ_a) n̄ with
      n̄ = (con_f[0], con_f[1]) the guide normal in a's frame (prismatic joint).
    * ``CON_DRIVE`` (1 row): Φ = θ_b − θ_a − con_f[0] − f(t), f from the drive tables.

Rows follow the acceleration equation Φq q̈ = γ, γ = −(Φq q̇)_q q̇ − 2Φqt q̇ − Φtt
(docs/paper-model.md §4); each point and angle contributes its velocity-quadratic term.
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_inner, njit_noalloc

POINT_GROUND = 0
POINT_RIGID = 1
POINT_LINEAR = 2

ANGLE_NONE = 0
ANGLE_RIGID = 1
ANGLE_SLOPE = 2

CON_COINCIDE = 0
CON_ANGLE = 1
CON_NORMAL = 2
CON_DRIVE = 3

#: rows used by each constraint primitive, indexed by its type code
CON_ROWS = (2, 1, 1, 1)

DRIVE_NONE = 0
DRIVE_CONSTANT_SPEED = 1
DRIVE_PROFILE = 2

# point cache columns
PC_X = 0
PC_Y = 1
PC_VX = 2
PC_VY = 3
PC_QX = 4
PC_QY = 5
PC_ANG = 6
PC_RATE = 7
PC_AQUAD = 8
PC_JX = 9  # 8 entries
PC_JY = 17  # 8 entries
PC_AC = 25  # 2 entries
PCF_COLUMNS = 27
PCI_JN = 0
PCI_JDOF = 1  # 8 entries
PCI_AN = 9
PCI_ADOF = 10  # 2 entries
PCI_COLUMNS = 12


@njit_noalloc()
def update_points(q, v, pt_i, pt_f, pci, pcf):
    """Fill the point cache at (q, q̇) (see the module docstring)."""
    _fill_points(q, v, pt_i, pt_f, pci, pcf, None)


@njit_inner()
def update_point_rows(q, v, pt_i, pt_f, pci, pcf, rows):
    """Refresh only the cached points ``rows`` at (q, q̇) (the others keep their values)."""
    _fill_points(q, v, pt_i, pt_f, pci, pcf, rows)


@njit_inner()
def _fill_points(q, v, pt_i, pt_f, pci, pcf, rows):
    # one loop for both callers: numba compiles ``rows = None`` as its own specialisation
    # with the test pruned (a call per point would cost a reference-count pair each)
    count = pt_i.shape[0] if rows is None else rows.shape[0]
    for r in range(count):
        k = r if rows is None else rows[r]
        kind = pt_i[k, 0]
        ci = pci[k]
        cf = pcf[k]
        if kind == POINT_GROUND:
            cf[PC_X] = pt_f[k, 0]
            cf[PC_Y] = pt_f[k, 1]
            cf[PC_VX] = 0.0
            cf[PC_VY] = 0.0
            cf[PC_QX] = 0.0
            cf[PC_QY] = 0.0
            ci[PCI_JN] = 0
        elif kind == POINT_RIGID:
            base = pt_i[k, 1]
            th = q[base + 2]
            w = v[base + 2]
            c = math.cos(th)
            s = math.sin(th)
            sx = pt_f[k, 0]
            sy = pt_f[k, 1]
            ux = c * sx - s * sy
            uy = s * sx + c * sy
            cf[PC_X] = q[base] + ux
            cf[PC_Y] = q[base + 1] + uy
            cf[PC_VX] = v[base] - w * uy
            cf[PC_VY] = v[base + 1] + w * ux
            cf[PC_QX] = -w * w * ux
            cf[PC_QY] = -w * w * uy
            ci[PCI_JN] = 3
            ci[PCI_JDOF] = base
            ci[PCI_JDOF + 1] = base + 1
            ci[PCI_JDOF + 2] = base + 2
            cf[PC_JX] = 1.0
            cf[PC_JY] = 0.0
            cf[PC_JX + 1] = 0.0
            cf[PC_JY + 1] = 1.0
            # ∂(A s̄)/∂θ = k × A s̄ = (−uy, ux)
            cf[PC_JX + 2] = -uy
            cf[PC_JY + 2] = ux
        else:
            x = 0.0
            y = 0.0
            vx = 0.0
            vy = 0.0
            jn = 0
            for j in range(4):
                d = pt_i[k, 4 + j]
                if d >= 0:
                    wt = pt_f[k, 2 + j]
                    x += wt * q[d]
                    y += wt * q[d + 1]
                    vx += wt * v[d]
                    vy += wt * v[d + 1]
                    ci[PCI_JDOF + jn] = d
                    cf[PC_JX + jn] = wt
                    cf[PC_JY + jn] = 0.0
                    ci[PCI_JDOF + jn + 1] = d + 1
                    cf[PC_JX + jn + 1] = 0.0
                    cf[PC_JY + jn + 1] = wt
                    jn += 2
            ci[PCI_JN] = jn
            cf[PC_X] = x
            cf[PC_Y] = y
            cf[PC_VX] = vx
            cf[PC_VY] = vy
            cf[PC_QX] = 0.0
            cf[PC_QY] = 0.0
        ak = pt_i[k, 2]
        if ak == ANGLE_RIGID:
            base = pt_i[k, 1]
            cf[PC_ANG] = q[base + 2]
            cf[PC_RATE] = v[base + 2]
            cf[PC_AQUAD] = 0.0
            ci[PCI_AN] = 1
            ci[PCI_ADOF] = base + 2
            cf[PC_AC] = 1.0
        elif ak == ANGLE_SLOPE:
            sl = pt_i[k, 3]
            gx = q[sl]
            gy = q[sl + 1]
            g2 = gx * gx + gy * gy
            cross = gx * v[sl + 1] - gy * v[sl]
            dot = gx * v[sl] + gy * v[sl + 1]
            cf[PC_ANG] = math.atan2(gy, gx)
            cf[PC_RATE] = cross / g2
            # θ̈ = (r,ₓ × r̈,ₓ)/|r,ₓ|² − 2 (r,ₓ·ṙ,ₓ)(r,ₓ × ṙ,ₓ)/|r,ₓ|⁴
            cf[PC_AQUAD] = -2.0 * dot * cross / (g2 * g2)
            ci[PCI_AN] = 2
            ci[PCI_ADOF] = sl
            ci[PCI_ADOF + 1] = sl + 1
            cf[PC_AC] = -gy / g2
            cf[PC_AC + 1] = gx / g2
        else:
            cf[PC_ANG] = 0.0
            cf[PC_RATE] = 0.0
            cf[PC_AQUAD] = 0.0
            ci[PCI_AN] = 0


@njit_inner()
def point_acceleration(a, pci, pcf, k):
    """r̈ of cached point ``k`` for generalised accelerations ``a``."""
    ax = pcf[k, PC_QX]
    ay = pcf[k, PC_QY]
    for e in range(pci[k, PCI_JN]):
        d = pci[k, PCI_JDOF + e]
        ax += pcf[k, PC_JX + e] * a[d]
        ay += pcf[k, PC_JY + e] * a[d]
    return ax, ay


@njit_inner()
def angle_acceleration(a, pci, pcf, k):
    """θ̈ of the frame at cached point ``k`` for generalised accelerations ``a``."""
    al = pcf[k, PC_AQUAD]
    for e in range(pci[k, PCI_AN]):
        al += pcf[k, PC_AC + e] * a[pci[k, PCI_ADOF + e]]
    return al


@njit_inner()
def apply_point_force(gen, fx, fy, moment, pci, pcf, k):
    """gen += J_pᵀ f + moment ∂θ_p/∂q for a force f at cached point ``k``.

    For a rigid body J_pᵀ f puts f on (x, y) and the moment (A s̄) × f of f about the
    reference point on θ (docs/paper-model.md §5); for a slope angle the moment is mapped by
    ∂θ/∂r,ₓ = [−r,ₓ,y, r,ₓ,x]/|r,ₓ|² (docs/paper-model.md §5).
    """
    for e in range(pci[k, PCI_JN]):
        d = pci[k, PCI_JDOF + e]
        gen[d] += pcf[k, PC_JX + e] * fx + pcf[k, PC_JY + e] * fy
    if moment != 0.0:
        for e in range(pci[k, PCI_AN]):
            gen[pci[k, PCI_ADOF + e]] += pcf[k, PC_AC + e] * moment


@njit_inner()
def drive_angle(t, drive_i, drive_f, spline_x, spline_c):
    """Prescribed relative angle f(t) and its first two derivatives (rad, rad/s, rad/s²).

    Constant speed: f = ωt. Profile: f(t) = ramp·t/P + s((t − t₀) mod P) with s a periodic
    cubic spline (coefficients ``spline_c[4, k]`` on breakpoints ``spline_x``, local powers).
    """
    kind = drive_i[0]
    if kind == DRIVE_CONSTANT_SPEED:
        w = drive_f[1]
        return w * t, w, 0.0
    if kind == DRIVE_PROFILE:
        period = drive_f[2]
        ramp = drive_f[3]
        t0 = spline_x[0]
        tau = (t - t0) % period
        lo = 0
        hi = spline_c.shape[1] - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if spline_x[mid] - t0 <= tau:
                lo = mid
            else:
                hi = mid - 1
        x = tau - (spline_x[lo] - t0)
        c0 = spline_c[0, lo]
        c1 = spline_c[1, lo]
        c2 = spline_c[2, lo]
        c3 = spline_c[3, lo]
        f = ((c0 * x + c1) * x + c2) * x + c3
        df = (3.0 * c0 * x + 2.0 * c1) * x + c2
        ddf = 6.0 * c0 * x + 2.0 * c1
        return f + ramp * t / period, df + ramp / period, ddf
    return 0.0, 0.0, 0.0


@njit_inner(inline="always")
def _insert_column(cols, count, j):
    """Insert column ``j`` into the ascending list ``cols[:count]`` unless it is there;
    returns the new count."""
    i = count
    while i > 0 and cols[i - 1] > j:
        i -= 1
    if i > 0 and cols[i - 1] == j:
        return count
    for k in range(count, i, -1):
        cols[k] = cols[k - 1]
    cols[i] = j
    return count + 1


@njit_inner()
def constraint_columns(con_i, pci, phiq, nzn, nzj):
    """The nonzero columns of every row of Φq, ascending (row r: ``nzj[r, :nzn[r]]``).

    A primitive's rows are nonzero only at the Jacobian and angle columns of its two
    points (those :func:`constraint_rows` writes from the point cache), so each row is
    filtered over that short list instead of scanned over all coordinates: the same
    lists. ``nzj`` has a row of room for every row of Φq.
    """
    for c in range(con_i.shape[0]):
        typ = con_i[c, 0]
        r = con_i[c, 3]
        last = r + CON_ROWS[typ] - 1
        # the candidates, ascending and unique, in the primitive's last row of nzj
        cand = nzj[last]
        cnt = 0
        for side in range(2):
            p = con_i[c, 1 + side]
            for e in range(pci[p, PCI_JN]):
                cnt = _insert_column(cand, cnt, pci[p, PCI_JDOF + e])
            for e in range(pci[p, PCI_AN]):
                cnt = _insert_column(cand, cnt, pci[p, PCI_ADOF + e])
        # the other rows first; the last row is filtered in place (it writes at or
        # before the entry it reads)
        for rr in range(r, last + 1):
            out = nzj[rr]
            k = 0
            for e in range(cnt):
                j = cand[e]
                out[k] = j
                k += phiq[rr, j] != 0.0
            nzn[rr] = k


@njit_inner()
def constraint_rows(
    t, con_i, con_f, drive_i, drive_f, spline_x, spline_c, pci, pcf, phi, phiq, phit, gam
):
    """Fill Φ, Φq (zeroed by the caller), Φt and γ of every primitive from the point cache."""
    for c in range(con_i.shape[0]):
        typ = con_i[c, 0]
        a = con_i[c, 1]
        b = con_i[c, 2]
        r = con_i[c, 3]
        if typ == CON_COINCIDE:
            phi[r] = pcf[a, PC_X] - pcf[b, PC_X] - con_f[c, 0]
            phi[r + 1] = pcf[a, PC_Y] - pcf[b, PC_Y] - con_f[c, 1]
            for e in range(pci[a, PCI_JN]):
                d = pci[a, PCI_JDOF + e]
                phiq[r, d] += pcf[a, PC_JX + e]
                phiq[r + 1, d] += pcf[a, PC_JY + e]
            for e in range(pci[b, PCI_JN]):
                d = pci[b, PCI_JDOF + e]
                phiq[r, d] -= pcf[b, PC_JX + e]
                phiq[r + 1, d] -= pcf[b, PC_JY + e]
            phit[r] = 0.0
            phit[r + 1] = 0.0
            gam[r] = pcf[b, PC_QX] - pcf[a, PC_QX]
            gam[r + 1] = pcf[b, PC_QY] - pcf[a, PC_QY]
        elif typ == CON_ANGLE or typ == CON_DRIVE:
            f = con_f[c, 0]
            df = 0.0
            ddf = 0.0
            if typ == CON_DRIVE:
                f1, df, ddf = drive_angle(t, drive_i, drive_f, spline_x, spline_c)
                f += f1
            phi[r] = pcf[b, PC_ANG] - pcf[a, PC_ANG] - f
            for e in range(pci[b, PCI_AN]):
                phiq[r, pci[b, PCI_ADOF + e]] += pcf[b, PC_AC + e]
            for e in range(pci[a, PCI_AN]):
                phiq[r, pci[a, PCI_ADOF + e]] -= pcf[a, PC_AC + e]
            phit[r] = -df
            gam[r] = ddf - (pcf[b, PC_AQUAD] - pcf[a, PC_AQUAD])
        elif typ == CON_NORMAL:
            th = pcf[a, PC_ANG]
            w = pcf[a, PC_RATE]
            ct = math.cos(th)
            st = math.sin(th)
            nbx = con_f[c, 0]
            nby = con_f[c, 1]
            nx = ct * nbx - st * nby
            ny = st * nbx + ct * nby
            # dn/dθ = k × n
            mx = -ny
            my = nx
            dx = pcf[b, PC_X] - pcf[a, PC_X]
            dy = pcf[b, PC_Y] - pcf[a, PC_Y]
            ddx = pcf[b, PC_VX] - pcf[a, PC_VX]
            ddy = pcf[b, PC_VY] - pcf[a, PC_VY]
            phi[r] = nx * dx + ny * dy - con_f[c, 2]
            for e in range(pci[b, PCI_JN]):
                phiq[r, pci[b, PCI_JDOF + e]] += nx * pcf[b, PC_JX + e] + ny * pcf[b, PC_JY + e]
            for e in range(pci[a, PCI_JN]):
                phiq[r, pci[a, PCI_JDOF + e]] -= nx * pcf[a, PC_JX + e] + ny * pcf[a, PC_JY + e]
            md = mx * dx + my * dy
            for e in range(pci[a, PCI_AN]):
                phiq[r, pci[a, PCI_ADOF + e]] += md * pcf[a, PC_AC + e]
            # Φ̈ = n̈·d + 2ṅ·ḋ + n·d̈ with n̈ = θ̈ k×n − θ̇² n
            quad = (
                md * pcf[a, PC_AQUAD]
                - w * w * (nx * dx + ny * dy)
                + 2.0 * w * (mx * ddx + my * ddy)
                + nx * (pcf[b, PC_QX] - pcf[a, PC_QX])
                + ny * (pcf[b, PC_QY] - pcf[a, PC_QY])
            )
            phit[r] = 0.0
            gam[r] = -quad


@njit_inner()
def _wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


@njit_inner()
def clearance_kinematics(pcf, bearing, journal, r_bearing, r_journal, clearance):
    """Kinematics of a journal in a bearing from the point cache (docs/paper-model.md §5).

    Returns ``(ex, ey, nx, ny, delta, delta_dot, v_t, phi_b, phi_j)``: the eccentricity
    e = r_j − r_b (m), the unit normal n = e/|e| (x axis when e = 0), the penetration
    δ = |e| − c, its rate δ̇ = (ṙ_j^Q − ṙ_b^Q)·n (> 0 while penetration grows), the
    sliding velocity v_t = (ṙ_j^Q − ṙ_b^Q)·t of the contact points along t = k × n, and the
    contact angle in the bearing and journal frames (rad, in (−π, π]).
    """
    ex = pcf[journal, PC_X] - pcf[bearing, PC_X]
    ey = pcf[journal, PC_Y] - pcf[bearing, PC_Y]
    ne = math.sqrt(ex * ex + ey * ey)
    if ne > 0.0:
        nx = ex / ne
        ny = ey / ne
    else:
        nx = 1.0
        ny = 0.0
    dvx = pcf[journal, PC_VX] - pcf[bearing, PC_VX]
    dvy = pcf[journal, PC_VY] - pcf[bearing, PC_VY]
    delta = ne - clearance
    delta_dot = dvx * nx + dvy * ny
    # the contact points r + R n move with their bodies: ω k × (R n) = ω R t, t = (−ny, nx)
    v_t = (
        -dvx * ny + dvy * nx + pcf[journal, PC_RATE] * r_journal - pcf[bearing, PC_RATE] * r_bearing
    )
    phi = math.atan2(ny, nx)
    phi_b = _wrap(phi - pcf[bearing, PC_ANG])
    phi_j = _wrap(phi - pcf[journal, PC_ANG])
    return ex, ey, nx, ny, delta, delta_dot, v_t, phi_b, phi_j


@njit_inner()
def clearance_force_add(gen, pci, pcf, bearing, journal, r_bearing, r_journal, nx, ny, f_n, f_t):
    """Apply the contact pair to both bodies (docs/paper-model.md §5).

    On the journal f_j = −Fₙ n + F_t t at its contact point r_j + R_j n, i.e. f_j at the
    journal point plus the friction moment R_j F_t (n × t = 1); on the bearing −f_j at
    r_b + R_b n, i.e. −f_j at the bearing point plus the moment −R_b F_t.
    """
    fx = -f_n * nx - f_t * ny
    fy = -f_n * ny + f_t * nx
    apply_point_force(gen, fx, fy, r_journal * f_t, pci, pcf, journal)
    apply_point_force(gen, -fx, -fy, -r_bearing * f_t, pci, pcf, bearing)
