"""Compiled force elements: spring–damper–actuators, torsional spring–dampers and
applied loads, added to the generalized forces of a right-hand side.

Tables (built by ``mechanism.core.forces._tables.force_tables``):

``fe_i`` int64 (n_elements, FI_COLUMNS)
    kind (``FE_SPRING``, ``FE_TORSION``, ``FE_LOAD``); the point-table rows ``FI_A`` and
    ``FI_B`` (spring ends, the joint's two points of a torsional spring, the load point in
    ``FI_A``); the offsets and lengths in ``fe_t`` of the force–deflection
    (``FI_TK_*``) and force–velocity (``FI_TC_*``) tables of a spring, and at ``FI_TC_*``
    the torque–speed table (rad/s, N m) of a motor's torsional element; the time profile
    of a load (``FI_TIME``: ``PROFILE_NONE``, ``PROFILE_FOURIER``, ``PROFILE_TABLE``, its
    data at ``FI_TT_*``); its joint-coordinate profile (``FI_COORD``: ``COORD_NONE``,
    ``COORD_SLIDE``, ``COORD_ANGLE``; the joint's points ``FI_CA``, ``FI_CB``; its table at
    ``FI_CT_*``; ``FI_ACTIVE``: ``ACTIVE_ALWAYS``, ``ACTIVE_INCREASING``,
    ``ACTIVE_DECREASING``); ``FI_FRAME`` 1 for a follower load.
``fe_f`` float64 (n_elements, FF_COLUMNS)
    stiffness, damping, free length or reference angle, actuator force or torque, load
    force (x, y) and torque, the time profile's period, a prismatic joint's axis.
``fe_t`` float64, flat
    a table of n samples at offset o holds x = fe_t[o:o+n], y = fe_t[o+n:o+2n]; a Fourier
    profile of n harmonics holds a₀, a₁..aₙ, b₁..bₙ from o.

Every value comes from the point cache of the evaluation (positions, velocities, angles
and their rates), so the elements cost one pass over their rows and nothing when the
scene has none (the caller skips the call on an empty table).
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_noalloc
from mechanism.core.joints import PC_ANG, PC_RATE, PC_VX, PC_VY, PC_X, PC_Y, apply_point_force

FE_SPRING = 0
FE_TORSION = 1
FE_LOAD = 2

PROFILE_NONE = 0
PROFILE_FOURIER = 1
PROFILE_TABLE = 2

COORD_NONE = 0
COORD_SLIDE = 1
COORD_ANGLE = 2

ACTIVE_ALWAYS = 0
ACTIVE_INCREASING = 1
ACTIVE_DECREASING = 2

FI_KIND = 0
FI_A = 1
FI_B = 2
FI_TK_OFF = 3
FI_TK_N = 4
FI_TC_OFF = 5
FI_TC_N = 6
FI_TIME = 7
FI_TT_OFF = 8
FI_TT_N = 9
FI_COORD = 10
FI_CA = 11
FI_CB = 12
FI_CT_OFF = 13
FI_CT_N = 14
FI_ACTIVE = 15
FI_FRAME = 16
FI_COLUMNS = 17

FF_K = 0
FF_C = 1
FF_REF = 2  # free length (m) or reference angle (rad)
FF_ACT = 3  # actuator force (N) or torque (N m)
FF_FX = 4
FF_FY = 5
FF_TORQUE = 6
FF_PERIOD = 7
FF_UX = 8  # prismatic axis of a coordinate profile, in the guide body's frame
FF_UY = 9
FF_COLUMNS = 10

# what one evaluation reports per element (``out``): the element's force (spring tension,
# N; torsional moment on the second body, N m; load factor, 1), its coordinate
# (deflection L − L₀, m; angle φ − φ₀, rad; profile coordinate) and that coordinate's rate
FO_FORCE = 0
FO_COORD = 1
FO_RATE = 2
FO_COLUMNS = 3


@njit_noalloc()
def table_value(fe_t, o, n, x):
    """Linear interpolation through the table at ``o`` (n samples), end values held."""
    if x <= fe_t[o]:
        return fe_t[o + n]
    if x >= fe_t[o + n - 1]:
        return fe_t[o + 2 * n - 1]
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if fe_t[o + mid] <= x:
            lo = mid
        else:
            hi = mid
    x0 = fe_t[o + lo]
    x1 = fe_t[o + hi]
    y0 = fe_t[o + n + lo]
    y1 = fe_t[o + n + hi]
    return y0 + (y1 - y0) * (x - x0) / (x1 - x0)


@njit_noalloc()
def _antiderivative(fe_t, o, n, x):
    """∫ from the first sample to x of the clamped interpolant of the table at ``o``."""
    x0 = fe_t[o]
    if x <= x0:
        return fe_t[o + n] * (x - x0)
    acc = 0.0
    for i in range(n - 1):
        xa = fe_t[o + i]
        xb = fe_t[o + i + 1]
        ya = fe_t[o + n + i]
        yb = fe_t[o + n + i + 1]
        if x <= xb:
            yx = ya + (yb - ya) * (x - xa) / (xb - xa)
            return acc + 0.5 * (ya + yx) * (x - xa)
        acc += 0.5 * (ya + yb) * (xb - xa)
    return acc + fe_t[o + 2 * n - 1] * (x - fe_t[o + n - 1])


@njit_noalloc()
def table_integral(fe_t, o, n, x):
    """∫₀ˣ f(s) ds of the clamped piecewise-linear f of the table at ``o`` (exact)."""
    return _antiderivative(fe_t, o, n, x) - _antiderivative(fe_t, o, n, 0.0)


@njit_noalloc()
def periodic_table_value(fe_t, o, n, period, t):
    """The table at ``o`` read periodically: samples over [x₀, x₀ + period), linear between
    them and from the last sample back to the first at x₀ + period."""
    x0 = fe_t[o]
    u = x0 + (t - x0) - period * math.floor((t - x0) / period)
    last = fe_t[o + n - 1]
    if u >= last:
        y0 = fe_t[o + 2 * n - 1]
        y1 = fe_t[o + n]
        return y0 + (y1 - y0) * (u - last) / (x0 + period - last)
    return table_value(fe_t, o, n, u)


@njit_noalloc()
def fourier_value(fe_t, o, n, period, t):
    """a₀ + Σₖ aₖ cos(2πkt/P) + bₖ sin(2πkt/P) of the n harmonics stored at ``o``."""
    w = 2.0 * math.pi / period
    value = fe_t[o]
    for k in range(1, n + 1):
        arg = w * k * t
        value += fe_t[o + k] * math.cos(arg) + fe_t[o + n + k] * math.sin(arg)
    return value


@njit_noalloc()
def joint_coordinate(fe_i, fe_f, pcf, e):
    """(s, ṡ) of the joint coordinate of element ``e``'s profile: the slide along a
    prismatic joint's axis (m) or the relative angle of a revolute joint (rad)."""
    a = fe_i[e, FI_CA]
    b = fe_i[e, FI_CB]
    if fe_i[e, FI_COORD] == COORD_ANGLE:
        return pcf[b, PC_ANG] - pcf[a, PC_ANG], pcf[b, PC_RATE] - pcf[a, PC_RATE]
    th = pcf[a, PC_ANG]
    w = pcf[a, PC_RATE]
    c = math.cos(th)
    sn = math.sin(th)
    gx = c * fe_f[e, FF_UX] - sn * fe_f[e, FF_UY]
    gy = sn * fe_f[e, FF_UX] + c * fe_f[e, FF_UY]
    dx = pcf[b, PC_X] - pcf[a, PC_X]
    dy = pcf[b, PC_Y] - pcf[a, PC_Y]
    ddx = pcf[b, PC_VX] - pcf[a, PC_VX]
    ddy = pcf[b, PC_VY] - pcf[a, PC_VY]
    # s = u·d with u = A(θ_a) ū: ṡ = u̇·d + u·ḋ, u̇ = ω k × u
    return gx * dx + gy * dy, w * (gx * dy - gy * dx) + gx * ddx + gy * ddy


@njit_noalloc()
def _spring_add(fe_i, fe_f, fe_t, e, pci, pcf, gen, out):
    a = fe_i[e, FI_A]
    b = fe_i[e, FI_B]
    dx = pcf[b, PC_X] - pcf[a, PC_X]
    dy = pcf[b, PC_Y] - pcf[a, PC_Y]
    length = math.sqrt(dx * dx + dy * dy)
    ux = 0.0
    uy = 0.0
    rate = 0.0
    if length > 0.0:
        # along a line of zero length the direction is undefined: no force
        ux = dx / length
        uy = dy / length
        rate = ux * (pcf[b, PC_VX] - pcf[a, PC_VX]) + uy * (pcf[b, PC_VY] - pcf[a, PC_VY])
    deflection = length - fe_f[e, FF_REF]
    tension = fe_f[e, FF_K] * deflection + fe_f[e, FF_C] * rate + fe_f[e, FF_ACT]
    if fe_i[e, FI_TK_N] > 0:
        tension += table_value(fe_t, fe_i[e, FI_TK_OFF], fe_i[e, FI_TK_N], deflection)
    if fe_i[e, FI_TC_N] > 0:
        tension += table_value(fe_t, fe_i[e, FI_TC_OFF], fe_i[e, FI_TC_N], rate)
    if length > 0.0:
        apply_point_force(gen, tension * ux, tension * uy, 0.0, pci, pcf, a)
        apply_point_force(gen, -tension * ux, -tension * uy, 0.0, pci, pcf, b)
    if out.shape[0] > 0:
        out[e, FO_FORCE] = tension
        out[e, FO_COORD] = deflection
        out[e, FO_RATE] = rate


@njit_noalloc()
def _torsion_add(fe_i, fe_f, fe_t, e, pci, pcf, gen, out):
    a = fe_i[e, FI_A]
    b = fe_i[e, FI_B]
    angle = pcf[b, PC_ANG] - pcf[a, PC_ANG] - fe_f[e, FF_REF]
    rate = pcf[b, PC_RATE] - pcf[a, PC_RATE]
    moment = -fe_f[e, FF_K] * angle - fe_f[e, FF_C] * rate + fe_f[e, FF_ACT]
    if fe_i[e, FI_TC_N] > 0:
        # a motor's tabulated torque–speed curve (the rate in rad/s)
        moment += table_value(fe_t, fe_i[e, FI_TC_OFF], fe_i[e, FI_TC_N], rate)
    apply_point_force(gen, 0.0, 0.0, moment, pci, pcf, b)
    apply_point_force(gen, 0.0, 0.0, -moment, pci, pcf, a)
    if out.shape[0] > 0:
        out[e, FO_FORCE] = moment
        out[e, FO_COORD] = angle
        out[e, FO_RATE] = rate


@njit_noalloc()
def _load_add(fe_i, fe_f, fe_t, e, t, pci, pcf, gen, out):
    factor = 1.0
    kind = fe_i[e, FI_TIME]
    if kind == PROFILE_FOURIER:
        factor = fourier_value(fe_t, fe_i[e, FI_TT_OFF], fe_i[e, FI_TT_N], fe_f[e, FF_PERIOD], t)
    elif kind == PROFILE_TABLE:
        factor = periodic_table_value(
            fe_t, fe_i[e, FI_TT_OFF], fe_i[e, FI_TT_N], fe_f[e, FF_PERIOD], t
        )
    s = 0.0
    sd = 0.0
    if fe_i[e, FI_COORD] != COORD_NONE:
        s, sd = joint_coordinate(fe_i, fe_f, pcf, e)
        active = fe_i[e, FI_ACTIVE]
        if (active == ACTIVE_INCREASING and not sd > 0.0) or (
            active == ACTIVE_DECREASING and not sd < 0.0
        ):
            factor = 0.0
        else:
            factor *= table_value(fe_t, fe_i[e, FI_CT_OFF], fe_i[e, FI_CT_N], s)
    p = fe_i[e, FI_A]
    fx = factor * fe_f[e, FF_FX]
    fy = factor * fe_f[e, FF_FY]
    if fe_i[e, FI_FRAME] != 0:
        th = pcf[p, PC_ANG]
        c = math.cos(th)
        sn = math.sin(th)
        fx, fy = c * fx - sn * fy, sn * fx + c * fy
    apply_point_force(gen, fx, fy, factor * fe_f[e, FF_TORQUE], pci, pcf, p)
    if out.shape[0] > 0:
        out[e, FO_FORCE] = factor
        out[e, FO_COORD] = s
        out[e, FO_RATE] = sd


@njit_noalloc()
def force_elements_add(fe_i, fe_f, fe_t, t, pci, pcf, gen, out):
    """gen += the generalized forces of every force element at time ``t`` (point cache
    current). ``out`` (n_elements, FO_COLUMNS) receives each element's force, coordinate
    and rate; pass an array with no rows to skip that."""
    for e in range(fe_i.shape[0]):
        kind = fe_i[e, FI_KIND]
        if kind == FE_SPRING:
            _spring_add(fe_i, fe_f, fe_t, e, pci, pcf, gen, out)
        elif kind == FE_TORSION:
            _torsion_add(fe_i, fe_f, fe_t, e, pci, pcf, gen, out)
        else:
            _load_add(fe_i, fe_f, fe_t, e, t, pci, pcf, gen, out)


@njit_noalloc()
def force_elements_potential(fe_i, fe_f, fe_t, pcf):
    """Potential energy (J) stored by the springs and actuators (point cache current):
    ½k(L − L₀)² + ∫₀^(L−L₀) f_k + F_act L per translational element, ½k(φ − φ₀)² − τ_act φ
    per torsional one. Dampers and applied loads store none."""
    energy = 0.0
    for e in range(fe_i.shape[0]):
        kind = fe_i[e, FI_KIND]
        a = fe_i[e, FI_A]
        b = fe_i[e, FI_B]
        if kind == FE_SPRING:
            dx = pcf[b, PC_X] - pcf[a, PC_X]
            dy = pcf[b, PC_Y] - pcf[a, PC_Y]
            length = math.sqrt(dx * dx + dy * dy)
            deflection = length - fe_f[e, FF_REF]
            energy += 0.5 * fe_f[e, FF_K] * deflection * deflection + fe_f[e, FF_ACT] * length
            if fe_i[e, FI_TK_N] > 0:
                energy += table_integral(fe_t, fe_i[e, FI_TK_OFF], fe_i[e, FI_TK_N], deflection)
        elif kind == FE_TORSION:
            phi = pcf[b, PC_ANG] - pcf[a, PC_ANG]
            angle = phi - fe_f[e, FF_REF]
            energy += 0.5 * fe_f[e, FF_K] * angle * angle - fe_f[e, FF_ACT] * phi
    return energy
