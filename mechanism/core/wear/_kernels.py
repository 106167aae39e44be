"""Compiled worn-surface geometry and Archard wear increments.

A worn surface (bearing or journal) is a ring of ``n`` equal angular regions; region ``i``
covers body-frame angles [i Δ, (i+1) Δ), Δ = 2π/n, and holds a wear depth h_i ≥ 0 (m).
The bearing grows outward (local radius R_b + h), the journal shrinks inward (R_j − h).
An empty depth array means an unworn surface.

Wear is *accumulated* per region (Archard, below), but the surface the contact sees is
continuous: :func:`surface_value` interpolates the region values as a periodic monotone
cubic Hermite curve through the region centres (Fritsch–Butland slopes, the equal-spacing
case of PCHIP), which is C1 in the angle, passes through every region value and never
leaves the range of its two neighbouring values (so a depth never dips below zero). The
local clearance, its angular rate (:func:`surface_slope`) and the smoothed curvature of the
contact law all use that one curve.

The volume of material a region has lost is the annular sector between the nominal and
the worn radius, V_i = L Δ h_i (R ± h_i/2); the Archard kernels distribute a worn volume
over regions and invert this formula, so the summed volume is conserved to round-off
whatever the pressure distribution.

Kernels do not validate: ``_profile.py`` and ``_archard.py`` check arrays and parameters
where data enters. They never raise and never return NaN for finite inputs.
"""

from __future__ import annotations

import math

import numpy as np

from mechanism.core._jit import njit_noalloc
from mechanism.core._status import STATUS_OK, STATUS_REDUCED, STATUS_REJECTED
from mechanism.core.contact import effective_curvature, hertz_half_width

TWO_PI = 2.0 * math.pi

# A journal region may lose at most this fraction of its radius (worn-through guard).
MAX_INWARD_DEPTH_FRACTION = 1.0 - 1e-6


@njit_noalloc()
def wrap_angle(angle: float) -> float:
    """Angle in [0, 2π)."""
    a = angle % TWO_PI
    if a >= TWO_PI:  # -tiny % 2π rounds to 2π
        a = 0.0
    return a


@njit_noalloc()
def region_index(angle: float, regions: int) -> int:
    """Index of the region containing ``angle`` (rad); 0 for a non-finite angle."""
    if not math.isfinite(angle) or regions <= 0:
        return 0
    i = math.floor(wrap_angle(angle) * regions / TWO_PI)
    return i % regions


@njit_noalloc(inline="always")
def _between_centres(angle: float, regions: int) -> tuple[int, float]:
    """Region ``i0`` whose centre precedes the finite ``angle`` and the weight of ``i0 + 1``.

    ``i0`` is not wrapped (it may be −1); callers take it modulo the region count.
    """
    u = wrap_angle(angle) * regions / TWO_PI - 0.5
    i0 = math.floor(u)
    return i0, u - i0


@njit_noalloc(inline="always")
def _node_slope(before: float, here: float, after: float) -> float:
    """Fritsch–Butland slope (per region width) at a node from its two neighbours.

    The harmonic mean of the two secants where they have the same sign, else 0: an
    extremum of the data stays an extremum of the curve and the curve is monotone between
    nodes (the harmonic mean is at most twice the smaller secant).
    """
    d0 = here - before
    d1 = after - here
    if not d0 * d1 > 0.0:
        return 0.0
    return 2.0 * d0 * d1 / (d0 + d1)


@njit_noalloc(inline="always")
def _hermite(a: float, b: float, c: float, d: float, w: float) -> float:
    """Monotone cubic between nodes b (w = 0) and c (w = 1); a, d their outer neighbours."""
    m0 = _node_slope(a, b, c)
    m1 = _node_slope(b, c, d)
    w2 = w * w
    w3 = w2 * w
    return (
        (2.0 * w3 - 3.0 * w2 + 1.0) * b
        + (w3 - 2.0 * w2 + w) * m0
        + (3.0 * w2 - 2.0 * w3) * c
        + (w3 - w2) * m1
    )


@njit_noalloc(inline="always")
def _hermite_rate(a: float, b: float, c: float, d: float, w: float) -> float:
    """d/dw of :func:`_hermite` (per region width)."""
    m0 = _node_slope(a, b, c)
    m1 = _node_slope(b, c, d)
    w2 = w * w
    return 6.0 * (w2 - w) * (b - c) + (3.0 * w2 - 4.0 * w + 1.0) * m0 + (3.0 * w2 - 2.0 * w) * m1


@njit_noalloc()
def surface_value(values: np.ndarray, angle: float) -> float:
    """Value at ``angle`` of the continuous curve through per-region ``values``.

    The periodic monotone cubic through the region centres (module docstring): equal to
    ``values[i]`` at the centre of region i, C1 everywhere, within the range of the two
    nearest region values. 0 for an empty array; ``values[0]`` for a non-finite angle
    (memory safety; the state is already NaN then).
    """
    n = values.size
    if n == 0:
        return 0.0
    if not math.isfinite(angle):
        return values[0]
    i0, w = _between_centres(angle, n)
    return _hermite(
        values[(i0 - 1) % n], values[i0 % n], values[(i0 + 1) % n], values[(i0 + 2) % n], w
    )


@njit_noalloc()
def surface_slope(values: np.ndarray, angle: float) -> float:
    """Derivative d/dφ (per rad) at ``angle`` of the curve of :func:`surface_value`.

    0 for an empty array or a non-finite angle.
    """
    n = values.size
    if n == 0 or not math.isfinite(angle):
        return 0.0
    i0, w = _between_centres(angle, n)
    rate = _hermite_rate(
        values[(i0 - 1) % n], values[i0 % n], values[(i0 + 1) % n], values[(i0 + 2) % n], w
    )
    return rate * n / TWO_PI


@njit_noalloc()
def local_clearance(
    clearance: float,
    bearing_depth: np.ndarray,
    journal_depth: np.ndarray,
    bearing_angle: float,
    journal_angle: float,
) -> float:
    """Local radial clearance c = c₀ + h_b(φ_b) + h_j(φ_j) (m) on the continuous surfaces.

    ``bearing_angle`` and ``journal_angle`` are the contact direction in each body's frame.
    """
    return (
        clearance
        + surface_value(bearing_depth, bearing_angle)
        + surface_value(journal_depth, journal_angle)
    )


@njit_noalloc()
def smoothed_depth(depth: np.ndarray, i: int, smoothing: int) -> float:
    """Centred moving average of width ``smoothing`` regions at region ``i`` (circular).

    An even width w averages w + 1 regions with half weight on the two end ones, so the
    window stays centred and a symmetric profile stays symmetric.
    """
    n = depth.size
    if smoothing <= 1:
        return depth[i % n]
    h = smoothing // 2
    total = 0.0
    for m in range(-h, h + 1):
        total += depth[(i + m) % n]
    if smoothing % 2 == 0:
        total -= 0.5 * (depth[(i - h) % n] + depth[(i + h) % n])
    return total / smoothing


@njit_noalloc()
def surface_curvature(
    radius: float, depth: np.ndarray, i: int, smoothing: int, outward: bool
) -> float:
    """Signed curvature (1/m) at the centre of region ``i`` of a smoothed worn circle.

    From the circle through the smoothed profile points of regions i−1, i, i+1;
    positive when the centre of curvature lies on the side of the ring's centre (1/R for
    an unworn surface), negative where wear has made the surface locally bulge inward.
    Computed from depth differences in the frame of point i, which keeps the unworn value
    1/R to round-off.
    """
    n = depth.size
    if n < 3:
        return 1.0 / radius
    sign = 1.0 if outward else -1.0
    h0 = smoothed_depth(depth, i, smoothing)
    hm = smoothed_depth(depth, i - 1, smoothing)
    hp = smoothed_depth(depth, i + 1, smoothing)
    rm = radius + sign * hm
    rp = radius + sign * hp
    step = TWO_PI / n
    c2 = 2.0 * math.sin(0.5 * step) ** 2  # 1 − cos Δ without cancellation
    sn = math.sin(step)
    # Points in the frame of point i (x radial, y tangential): P∓ − P₀.
    dmx = sign * (hm - h0) - rm * c2
    dmy = -rm * sn
    dpx = sign * (hp - h0) - rp * c2
    dpy = rp * sn
    # Turning of A = P−, B = P₀, C = P+ (counter-clockwise on an unworn ring).
    cross = (-dmx) * dpy - (-dmy) * dpx
    la = math.hypot(dmx, dmy)
    lb = math.hypot(dpx, dpy)
    lc = math.hypot(dpx - dmx, dpy - dmy)
    denom = la * lb * lc
    if not denom > 0.0:
        return 1.0 / radius
    return 2.0 * cross / denom


@njit_noalloc()
def curvature_at(
    radius: float,
    depth: np.ndarray,
    angle: float,
    smoothing: int,
    outward: bool,
) -> float:
    """Signed curvature (1/m) of a worn surface at ``angle``; 1/R for an unworn one.

    The region-centre curvatures of :func:`surface_curvature`, interpolated by the same
    monotone cubic as the depth (:func:`surface_value` of :func:`curvature_profile`).
    """
    n = depth.size
    if n < 3:
        return 1.0 / radius
    if not math.isfinite(angle):
        return surface_curvature(radius, depth, 0, smoothing, outward)
    i0, w = _between_centres(angle, n)
    return _hermite(
        surface_curvature(radius, depth, (i0 - 1) % n, smoothing, outward),
        surface_curvature(radius, depth, i0 % n, smoothing, outward),
        surface_curvature(radius, depth, (i0 + 1) % n, smoothing, outward),
        surface_curvature(radius, depth, (i0 + 2) % n, smoothing, outward),
        w,
    )


@njit_noalloc()
def curvature_profile(
    radius: float, depth: np.ndarray, smoothing: int, outward: bool, out: np.ndarray
) -> None:
    """Fill ``out`` with the signed curvature (1/m) at every region centre."""
    for i in range(out.size):
        out[i] = surface_curvature(radius, depth, i, smoothing, outward)


@njit_noalloc()
def local_effective_radius(
    form: int,
    bearing_radius: float,
    journal_radius: float,
    bearing_depth: np.ndarray,
    journal_depth: np.ndarray,
    bearing_angle: float,
    journal_angle: float,
    smoothing: int,
    radius_ratio_limit: float,
) -> float:
    """Local effective radius R* (m) from the smoothed local curvatures of both surfaces.

    1/R* = κ_j − κ_b (conformal) or κ_j + κ_b (sum of radii), bounded to within a factor
    ``radius_ratio_limit`` (≥ 1) of the unworn R*: a locally flat or bulging worn patch
    would otherwise give an infinite or negative R*, where the Hertz model does not apply.
    """
    kb = curvature_at(bearing_radius, bearing_depth, bearing_angle, smoothing, True)
    kj = curvature_at(journal_radius, journal_depth, journal_angle, smoothing, False)
    return _bounded_effective_radius(
        form, bearing_radius, journal_radius, kb, kj, radius_ratio_limit
    )


@njit_noalloc()
def local_stiffness(
    effective_modulus: float,
    form: int,
    bearing_radius: float,
    journal_radius: float,
    bearing_depth: np.ndarray,
    journal_depth: np.ndarray,
    bearing_angle: float,
    journal_angle: float,
    smoothing: int,
    radius_ratio_limit: float,
) -> float:
    """Local contact stiffness K_n = (4/3) E* √R*_n (N m^-1.5) of a worn joint."""
    r_star = local_effective_radius(
        form,
        bearing_radius,
        journal_radius,
        bearing_depth,
        journal_depth,
        bearing_angle,
        journal_angle,
        smoothing,
        radius_ratio_limit,
    )
    return _hertz_stiffness(effective_modulus, r_star)


@njit_noalloc(inline="always")
def _hertz_stiffness(effective_modulus: float, effective_radius: float) -> float:
    """K_n = (4/3) E* √R* (N m^-1.5)."""
    return 4.0 / 3.0 * effective_modulus * math.sqrt(effective_radius)


@njit_noalloc()
def _bounded_effective_radius(
    form: int,
    bearing_radius: float,
    journal_radius: float,
    bearing_curvature: float,
    journal_curvature: float,
    radius_ratio_limit: float,
) -> float:
    nominal = effective_curvature(form, 1.0 / bearing_radius, 1.0 / journal_radius)
    kappa = effective_curvature(form, bearing_curvature, journal_curvature)
    low = nominal / radius_ratio_limit
    high = nominal * radius_ratio_limit
    if not kappa >= low:  # also catches NaN
        kappa = low
    elif kappa > high:
        kappa = high
    return 1.0 / kappa


@njit_noalloc()
def local_stiffness_tabulated(
    effective_modulus: float,
    form: int,
    bearing_radius: float,
    journal_radius: float,
    bearing_curvature: np.ndarray,
    journal_curvature: np.ndarray,
    bearing_angle: float,
    journal_angle: float,
    radius_ratio_limit: float,
) -> float:
    """:func:`local_stiffness` from curvatures tabulated once per profile, O(1) per call.

    ``bearing_curvature`` / ``journal_curvature`` come from :func:`curvature_profile` (an
    empty array means an unworn surface, curvature 1/R). Use it while the profile is
    constant (between wear updates); it gives the same value as :func:`local_stiffness`.
    """
    if bearing_curvature.size == 0:
        kb = 1.0 / bearing_radius
    else:
        kb = surface_value(bearing_curvature, bearing_angle)
    if journal_curvature.size == 0:
        kj = 1.0 / journal_radius
    else:
        kj = surface_value(journal_curvature, journal_angle)
    r_star = _bounded_effective_radius(
        form, bearing_radius, journal_radius, kb, kj, radius_ratio_limit
    )
    return _hertz_stiffness(effective_modulus, r_star)


@njit_noalloc()
def _elliptic_cdf(s: float) -> float:
    """Fraction of a semi-elliptical (Hertz) load on [−1, s] of its support [−1, 1]."""
    if s <= -1.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    return 0.5 + (s * math.sqrt(1.0 - s * s) + math.asin(s)) / math.pi


@njit_noalloc()
def sector_volume(
    radius: float, length: float, step: float, h1: float, h2: float, outward: bool
) -> float:
    """Volume (m³) between depths h1 ≤ h2 of one region of angular width ``step``."""
    if outward:
        return length * step * (h2 - h1) * (radius + 0.5 * (h1 + h2))
    return length * step * (h2 - h1) * (radius - 0.5 * (h1 + h2))


@njit_noalloc()
def _depth_for_volume(
    radius: float, length: float, step: float, h: float, volume: float, outward: bool
) -> float:
    """Depth increment that removes ``volume`` from a region at depth ``h`` (stable form)."""
    q = 2.0 * volume / (length * step)
    if outward:
        r = radius + h
        return q / (r + math.sqrt(r * r + q))
    r = radius - h
    disc = r * r - q
    if disc < 0.0:
        disc = 0.0
    return q / (r + math.sqrt(disc))


@njit_noalloc()
def _touched_span(angle: float, half_angle: float, n: int) -> tuple[float, int, int]:
    step = TWO_PI / n
    centre = wrap_angle(angle)
    if half_angle > 0.0:
        lo = math.floor((centre - half_angle) / step)
        hi = math.floor((centre + half_angle) / step)
    else:
        lo = region_index(centre, n)
        hi = lo
    return centre, lo, hi


@njit_noalloc()
def _share(m: int, centre: float, half_angle: float, step: float, lo: int, hi: int) -> float:
    if lo == hi:
        return 1.0
    s_lo = (m * step - centre) / half_angle
    s_hi = ((m + 1) * step - centre) / half_angle
    if m == lo:
        s_lo = -1.0
    if m == hi:
        s_hi = 1.0
    return _elliptic_cdf(s_hi) - _elliptic_cdf(s_lo)


@njit_noalloc()
def archard_increment(
    depth: np.ndarray,
    angle: float,
    normal_force: float,
    slip: float,
    coefficient: float,
    radius: float,
    length: float,
    half_width: float,
    outward: bool,
    max_increment: float,
) -> tuple[int, float]:
    """Add one Archard wear increment to a surface profile, in place.

    ΔV = k Fₙ Δs (m³) is removed around ``angle`` (rad, in the surface's frame): all in the
    touched region when ``half_width`` ≤ 0, else spread over the regions covered by
    ±``half_width``/``radius`` with the semi-elliptical Hertz pressure profile. Each region's
    depth grows by the amount that removes its share of ΔV, so Σ V_i grows by ΔV exactly.

    ``max_increment`` (m, ≤ 0 for none) caps the depth any region may gain in this call;
    an inward (journal) region may never lose its whole radius. When a cap binds, the whole
    increment is scaled down (its shape kept) and ``STATUS_REDUCED`` is returned.

    Returns
    -------
    status : int
        ``STATUS_OK``, ``STATUS_REDUCED`` or ``STATUS_REJECTED`` (non-finite input, nothing
        applied).
    applied_volume : float
        Volume actually removed (m³).
    """
    n = depth.size
    if not (
        math.isfinite(angle)
        and math.isfinite(normal_force)
        and math.isfinite(slip)
        and math.isfinite(coefficient)
        and math.isfinite(half_width)
    ):
        return STATUS_REJECTED, 0.0
    if n == 0 or not (normal_force > 0.0 and slip > 0.0 and coefficient > 0.0):
        return STATUS_OK, 0.0
    volume = coefficient * normal_force * slip
    step = TWO_PI / n
    half_angle = half_width / radius if half_width > 0.0 else 0.0
    if half_angle > math.pi - step:  # cover each region at most once
        half_angle = math.pi - step
    centre, lo, hi = _touched_span(angle, half_angle, n)
    # Pass 1: the largest fraction of ΔV every touched region can take within its limits.
    scale = 1.0
    for m in range(lo, hi + 1):
        share = _share(m, centre, half_angle, step, lo, hi)
        if share <= 0.0:
            continue
        i = m % n
        h = depth[i]
        limit = max_increment if max_increment > 0.0 else math.inf
        if not outward:
            room = MAX_INWARD_DEPTH_FRACTION * radius - h
            if room < limit:
                limit = room if room > 0.0 else 0.0
        if limit < math.inf:
            allowed = sector_volume(radius, length, step, h, h + limit, outward)
            if allowed < share * volume * scale:
                scale = allowed / (share * volume)
    # Pass 2: apply.
    applied = 0.0
    for m in range(lo, hi + 1):
        share = _share(m, centre, half_angle, step, lo, hi)
        if share <= 0.0:
            continue
        i = m % n
        dv = share * volume * scale
        depth[i] += _depth_for_volume(radius, length, step, depth[i], dv, outward)
        applied += dv
    return (STATUS_REDUCED if scale < 1.0 else STATUS_OK), applied


@njit_noalloc()
def worn_volume(depth: np.ndarray, radius: float, length: float, outward: bool) -> float:
    """Total volume (m³) a surface has lost, Σ L Δ h_i (R ± h_i/2)."""
    n = depth.size
    if n == 0:
        return 0.0
    step = TWO_PI / n
    total = 0.0
    for i in range(n):
        total += sector_volume(radius, length, step, 0.0, depth[i], outward)
    return total


@njit_noalloc(inline="always")
def _tally(
    status: int, applied: float, slot: int, counters: np.ndarray, volumes: np.ndarray
) -> None:
    """Book one :func:`archard_increment` as :func:`archard_history` reports it."""
    volumes[slot] += applied
    if status == STATUS_REDUCED:
        counters[1] += 1
    elif status == STATUS_REJECTED:
        counters[2] += 1


@njit_noalloc()
def archard_history(
    bearing_depth: np.ndarray,
    journal_depth: np.ndarray,
    bearing_angle: np.ndarray,
    journal_angle: np.ndarray,
    normal_force: np.ndarray,
    slip: np.ndarray,
    coefficient: float,
    bearing_radius: float,
    journal_radius: float,
    length: float,
    effective_modulus: float,
    form: int,
    smoothing: int,
    radius_ratio_limit: float,
    spread: bool,
    wear_journal: bool,
    max_increment: float,
    counters: np.ndarray,
    volumes: np.ndarray,
) -> None:
    """Apply a history of contact samples to both profiles in place.

    Per sample: local R* from the current profile, Hertz half-width, then one
    :func:`archard_increment` per worn surface. ``counters`` (int64[3]) accumulates
    applied samples, reduced and rejected increments; ``volumes`` (float64[3]) the
    requested volume Σ k Fₙ Δs and the volumes applied to the bearing and the journal.
    """
    for s in range(normal_force.size):
        force = normal_force[s]
        if not (force > 0.0 and slip[s] > 0.0):
            if not (math.isfinite(force) and math.isfinite(slip[s])):
                counters[2] += 1
            continue
        half_width = 0.0
        if spread:
            r_star = local_effective_radius(
                form,
                bearing_radius,
                journal_radius,
                bearing_depth,
                journal_depth,
                bearing_angle[s],
                journal_angle[s],
                smoothing,
                radius_ratio_limit,
            )
            half_width = hertz_half_width(force, r_star, length, effective_modulus)
        volumes[0] += coefficient * force * slip[s]
        counters[0] += 1
        status, applied = archard_increment(
            bearing_depth,
            bearing_angle[s],
            force,
            slip[s],
            coefficient,
            bearing_radius,
            length,
            half_width,
            True,
            max_increment,
        )
        _tally(status, applied, 1, counters, volumes)
        if wear_journal:
            status, applied = archard_increment(
                journal_depth,
                journal_angle[s],
                force,
                slip[s],
                coefficient,
                journal_radius,
                length,
                half_width,
                False,
                max_increment,
            )
            _tally(status, applied, 2, counters, volumes)
