"""Compiled kernels of the 2-D gradient-deficient ANCF beam (Berzeri–Shabana interpolation).

Every kernel works on one beam of ``n_elements`` equal elements of length ``element_length``
whose nodal vector ``e`` holds ``[r_1, r_1,x, r_2, r_2,x, ...]`` (4 DOFs per node, node ``j``
at ``e[4 j : 4 j + 4]``, element ``i`` at ``e[4 i : 4 i + 8]``). Forces and matrices are
*added*, multiplied by ``scale``, into ``out`` starting at row (and
column) ``offset``, so the multibody core can assemble several beams into its global arrays
once per right-hand-side evaluation.

Constitutive choices are integer codes (see ``docs/ancf.md``):

* ``axial_law``: ``AXIAL_GREEN`` ε = ½(r,ₓᵀr,ₓ − 1), the Berzeri–Shabana form of the paper;
  ``AXIAL_BIOT`` ε = |r,ₓ| − 1, the form of Gerstmayr & Irschik (2008).
* ``bending_law``: ``BENDING_LINEAR`` ½EI|r,ₓₓ|² (constant K_t, the paper's form);
  ``BENDING_MATERIAL`` κ = (r,ₓ × r,ₓₓ)/|r,ₓ|² (Gerstmayr & Irschik 2008, Exudyn's
  ``ANCFCable2D``); ``BENDING_GEOMETRIC`` κ = (r,ₓ × r,ₓₓ)/|r,ₓ|³ (curvature of the deformed
  centre line).

The elastic force is F_e = ∂U/∂e with U = ∫ ½EA ε² + ½EI κ² dx, integrated with
``n_gauss_axial`` and ``n_gauss_bending`` Gauss–Legendre points per element (1…5);
``beam_strain_energy`` returns U by the same quadrature. F_e, the costliest kernel of a
flexible run, takes every element of a Gauss point in one vectorised pass (the elements'
DOFs copied into eight contiguous rows of a caller's scratch, :func:`beam_work`, so that no
kernel here allocates) and adds each point's terms to ``out`` afterwards in the
element-by-element order, so F_e equals that quadrature's to the last bit; the damping
force (``_strain_rate_force``), ∂F_e/∂e and the damping matrix (``_strain_stiffness``) go
element by element and read their Gauss-point quantities from ``_axial_point``,
``_bending_point`` and ``_curvature_point``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

AXIAL_GREEN = 0
AXIAL_BIOT = 1
BENDING_LINEAR = 0
BENDING_MATERIAL = 1
BENDING_GEOMETRIC = 2
MAX_GAUSS = 5

# four shape-function values (or derivatives); the eight DOFs of one element
Shape = tuple[float, float, float, float]
Element = tuple[float, float, float, float, float, float, float, float]


def _gauss_table() -> tuple[np.ndarray, np.ndarray]:
    # Gauss–Legendre points and weights mapped to [0, 1], row n-1 holds the n-point rule.
    xs = np.zeros((MAX_GAUSS, MAX_GAUSS))
    ws = np.zeros((MAX_GAUSS, MAX_GAUSS))
    for n in range(1, MAX_GAUSS + 1):
        x, w = np.polynomial.legendre.leggauss(n)
        xs[n - 1, :n] = 0.5 * (x + 1.0)
        ws[n - 1, :n] = 0.5 * w
    return xs, ws


# numba freezes module-level arrays into the compiled code as constants
_GAUSS_X, _GAUSS_W = _gauss_table()


@njit(cache=True, inline="always")
def _d1(xi: float, l: float) -> Shape:
    # ∂s_k/∂x of the cubic Hermite shape functions at ξ = x/l
    return (
        6.0 * xi * (xi - 1.0) / l,
        1.0 - 4.0 * xi + 3.0 * xi * xi,
        6.0 * xi * (1.0 - xi) / l,
        xi * (3.0 * xi - 2.0),
    )


@njit(cache=True, inline="always")
def _d2(xi: float, l: float) -> Shape:
    # ∂²s_k/∂x²
    return (
        (12.0 * xi - 6.0) / (l * l),
        (6.0 * xi - 4.0) / l,
        (6.0 - 12.0 * xi) / (l * l),
        (6.0 * xi - 2.0) / l,
    )


@njit(cache=True, error_model="numpy")
def shape_functions(xi: float, l: float) -> Shape:
    """Cubic Hermite shape functions s_1…s_4 at ξ = x/l (the slope ones carry the factor l)."""
    xi2 = xi * xi
    xi3 = xi2 * xi
    return (
        1.0 - 3.0 * xi2 + 2.0 * xi3,
        l * (xi - 2.0 * xi2 + xi3),
        3.0 * xi2 - 2.0 * xi3,
        l * (xi3 - xi2),
    )


@njit(cache=True, inline="always")
def _element(e: np.ndarray, b: int) -> Element:
    # the 8 DOFs of the element starting at e[b], as values: helpers that take them instead
    # of the array keep numba from wrapping every inlined call in a refcount pair
    return (e[b], e[b + 1], e[b + 2], e[b + 3], e[b + 4], e[b + 5], e[b + 6], e[b + 7])


@njit(cache=True, inline="always")
def _interpolate(q: Element, d: Shape) -> tuple[float, float]:
    # Σ_k d_k r_k over the element's four vector DOFs, i.e. S e, S,ₓ e or S,ₓₓ e
    x = d[0] * q[0] + d[1] * q[2] + d[2] * q[4] + d[3] * q[6]
    y = d[0] * q[1] + d[1] * q[3] + d[2] * q[5] + d[3] * q[7]
    return x, y


@njit(cache=True, inline="always")
def _axial(rx: float, ry: float, axial_law: int) -> tuple[float, float]:
    """Strain ε and the factor c with ∂ε/∂r,ₓ = c r,ₓ."""
    w2 = rx * rx + ry * ry
    if axial_law == AXIAL_GREEN:
        return 0.5 * (w2 - 1.0), 1.0
    lam = math.sqrt(w2)
    return lam - 1.0, 1.0 / lam


@njit(cache=True, inline="always")
def _curvature(
    rx: float, ry: float, sx: float, sy: float, bending_law: int
) -> tuple[float, float, float, float, float, float]:
    """κ, ∂κ/∂r,ₓ and ∂κ/∂r,ₓₓ (r,ₓₓ = (sx, sy)) for the nonlinear curvature laws."""
    c = rx * sy - ry * sx
    w2 = rx * rx + ry * ry
    # |r,ₓ|^(−2q) without a call to pow (the force kernel's costliest operation otherwise)
    if bending_law == BENDING_MATERIAL:
        q = 1.0
        wq = 1.0 / w2
    else:
        q = 1.5
        wq = 1.0 / (w2 * math.sqrt(w2))
    kappa = c * wq
    f = 2.0 * q * c / w2
    return kappa, wq * (sy - f * rx), wq * (-sx - f * ry), -wq * ry, wq * rx, wq


@njit(cache=True, inline="always")
def _axial_point(
    q: Element, g: int, n_gauss: int, l: float, axial_law: int
) -> tuple[float, Shape, float, float, float, float]:
    """Axial quantities at Gauss point ``g`` of ``n_gauss`` of the element with DOFs ``q``.

    Returns the weight w_g l, S,ₓ (shape derivatives), r,ₓ = (rx, ry), ε and c with
    ∂ε/∂r,ₓ = c r,ₓ.
    """
    d1 = _d1(_GAUSS_X[n_gauss - 1, g], l)
    rx, ry = _interpolate(q, d1)
    eps, c = _axial(rx, ry, axial_law)
    return _GAUSS_W[n_gauss - 1, g] * l, d1, rx, ry, eps, c


@njit(cache=True, inline="always")
def _bending_point(
    q: Element, g: int, n_gauss: int, l: float
) -> tuple[float, Shape, Shape, float, float]:
    """Weight w_g l, S,ₓ, S,ₓₓ and r,ₓₓ = (sx, sy) at Gauss point ``g`` of ``n_gauss`` of the
    element with DOFs ``q`` (all that ``BENDING_LINEAR`` needs).
    """
    xi = _GAUSS_X[n_gauss - 1, g]
    d2 = _d2(xi, l)
    sx, sy = _interpolate(q, d2)
    return _GAUSS_W[n_gauss - 1, g] * l, _d1(xi, l), d2, sx, sy


@njit(cache=True, inline="always")
def _curvature_point(
    q: Element, d1: Shape, sx: float, sy: float, bending_law: int
) -> tuple[float, float, float, float, float, float, float, float]:
    """r,ₓ = (rx, ry) and, from :func:`_curvature`, κ, ∂κ/∂r,ₓ, ∂κ/∂r,ₓₓ and |r,ₓ|^(−2q)
    for the nonlinear bending laws, at the point of :func:`_bending_point`.
    """
    rx, ry = _interpolate(q, d1)
    kap, k1x, k1y, k2x, k2y, wq = _curvature(rx, ry, sx, sy, bending_law)
    return rx, ry, kap, k1x, k1y, k2x, k2y, wq


@njit(cache=True, inline="always")
def _curvature_hessian(
    rx: float, ry: float, sx: float, sy: float, kap: float, wq: float, bending_law: int
) -> tuple[float, float, float, float, float, float, float]:
    """(H11xx, H11xy, H11yy, H12xx, H12xy, H12yx, H12yy): H11 = ∂²κ/∂r,ₓ², H12 = ∂²κ/∂r,ₓ∂r,ₓₓ
    (∂²κ/∂r,ₓₓ² = 0) of κ = (r,ₓ × r,ₓₓ)|r,ₓ|^(−2q); ``wq`` = |r,ₓ|^(−2q).
    """
    q = 1.0 if bending_law == BENDING_MATERIAL else 1.5
    w2 = rx * rx + ry * ry
    c = kap / wq
    ax, ay = sy, -sx
    h = 2.0 * q * wq / w2
    g2 = 4.0 * q * (q + 1.0) * c * wq / (w2 * w2)
    bx, by = -ry, rx
    return (
        -h * 2.0 * ax * rx + g2 * rx * rx - h * c,
        -h * (ax * ry + rx * ay) + g2 * rx * ry,
        -h * 2.0 * ay * ry + g2 * ry * ry - h * c,
        -h * rx * bx,
        wq - h * rx * by,
        -wq - h * ry * bx,
        -h * ry * by,
    )


# The two element-by-element quadratures below are inlined into the public kernels, so the
# ``geometric`` flag is a constant there and costs nothing.
@njit(cache=True, inline="always")
def _strain_rate_force(
    e: np.ndarray,
    e_dot: np.ndarray,
    n_elements: int,
    l: float,
    ea: float,
    ei: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """out += scale ∫ ea ε̇ ∂ε/∂e + ei κ̇ ∂κ/∂e dx with (ε̇, κ̇) = (∂ε/∂e ė, ∂κ/∂e ė) and
    ė = ``e_dot``. ``BENDING_LINEAR`` takes ṙ,ₓₓ with ∂/∂e = S,ₓₓ in place of κ̇.
    """
    for i in range(n_elements):
        o = offset + 4 * i
        q = _element(e, 4 * i)
        q_dot = _element(e_dot, 4 * i)
        for g in range(n_gauss_axial):
            w, d1, rx, ry, _, c = _axial_point(q, g, n_gauss_axial, l, axial_law)
            vx, vy = _interpolate(q_dot, d1)
            f = w * scale * ea * c * c * (rx * vx + ry * vy)
            for k in range(4):
                out[o + 2 * k] += f * d1[k] * rx
                out[o + 2 * k + 1] += f * d1[k] * ry
        for g in range(n_gauss_bending):
            w, d1, d2, sx, sy = _bending_point(q, g, n_gauss_bending, l)
            f = w * scale * ei
            if bending_law == BENDING_LINEAR:
                sx, sy = _interpolate(q_dot, d2)
                for k in range(4):
                    out[o + 2 * k] += f * d2[k] * sx
                    out[o + 2 * k + 1] += f * d2[k] * sy
                continue
            _, _, _, k1x, k1y, k2x, k2y, _ = _curvature_point(q, d1, sx, sy, bending_law)
            vx, vy = _interpolate(q_dot, d1)
            wx, wy = _interpolate(q_dot, d2)
            f = f * (k1x * vx + k1y * vy + k2x * wx + k2y * wy)
            for k in range(4):
                out[o + 2 * k] += f * (d1[k] * k1x + d2[k] * k2x)
                out[o + 2 * k + 1] += f * (d1[k] * k1y + d2[k] * k2y)


@njit(cache=True, inline="always")
def _strain_stiffness(
    e: np.ndarray,
    geometric: bool,
    n_elements: int,
    l: float,
    ea: float,
    ei: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """out += scale K with K = ∫ ea ∂ε/∂e ∂ε/∂eᵀ + ei ∂κ/∂e ∂κ/∂eᵀ dx (the material part K_m),
    plus ∫ ea ε ∂²ε/∂e² + ei κ ∂²κ/∂e² dx if ``geometric`` (then K = ∂F_e/∂e).
    """
    for i in range(n_elements):
        o = offset + 4 * i
        q = _element(e, 4 * i)
        for g in range(n_gauss_axial):
            w, d1, rx, ry, eps, c = _axial_point(q, g, n_gauss_axial, l, axial_law)
            wt = w * scale * ea
            if geometric:
                # Green: S'ᵀ(r' r'ᵀ + ε I)S'; Biot: S'ᵀ(r' r'ᵀ/λ³ + (1 − 1/λ) I)S'
                diag = eps * c
                c3 = c * c * c
                axx = wt * (c3 * rx * rx + diag)
                axy = wt * c3 * rx * ry
                ayy = wt * (c3 * ry * ry + diag)
            else:
                wt = wt * c * c
                axx = wt * rx * rx
                axy = wt * rx * ry
                ayy = wt * ry * ry
            for k in range(4):
                for m in range(4):
                    s = d1[k] * d1[m]
                    out[o + 2 * k, o + 2 * m] += s * axx
                    out[o + 2 * k, o + 2 * m + 1] += s * axy
                    out[o + 2 * k + 1, o + 2 * m] += s * axy
                    out[o + 2 * k + 1, o + 2 * m + 1] += s * ayy
        if bending_law == BENDING_LINEAR:
            # constant K_t; a loop of its own because LLVM does not unswitch this one
            for g in range(n_gauss_bending):
                w, _, d2, _, _ = _bending_point(q, g, n_gauss_bending, l)
                wt = w * scale * ei
                for k in range(4):
                    for m in range(4):
                        s = wt * d2[k] * d2[m]
                        out[o + 2 * k, o + 2 * m] += s
                        out[o + 2 * k + 1, o + 2 * m + 1] += s
            continue
        for g in range(n_gauss_bending):
            w, d1, d2, sx, sy = _bending_point(q, g, n_gauss_bending, l)
            wt = w * scale * ei
            rx, ry, kap, k1x, k1y, k2x, k2y, wq = _curvature_point(q, d1, sx, sy, bending_law)
            h11xx, h11xy, h11yy, h12xx, h12xy, h12yx, h12yy = (
                _curvature_hessian(rx, ry, sx, sy, kap, wq, bending_law)
                if geometric
                else (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            )
            for k in range(4):
                gkx = d1[k] * k1x + d2[k] * k2x
                gky = d1[k] * k1y + d2[k] * k2y
                for m in range(4):
                    gmx = d1[m] * k1x + d2[m] * k2x
                    gmy = d1[m] * k1y + d2[m] * k2y
                    if not geometric:
                        out[o + 2 * k, o + 2 * m] += wt * gkx * gmx
                        out[o + 2 * k, o + 2 * m + 1] += wt * gkx * gmy
                        out[o + 2 * k + 1, o + 2 * m] += wt * gky * gmx
                        out[o + 2 * k + 1, o + 2 * m + 1] += wt * gky * gmy
                        continue
                    p11 = d1[k] * d1[m]
                    p12 = d1[k] * d2[m]
                    p21 = d2[k] * d1[m]
                    hxx = p11 * h11xx + p12 * h12xx + p21 * h12xx
                    hxy = p11 * h11xy + p12 * h12xy + p21 * h12yx
                    hyx = p11 * h11xy + p12 * h12yx + p21 * h12xy
                    hyy = p11 * h11yy + p12 * h12yy + p21 * h12yy
                    out[o + 2 * k, o + 2 * m] += wt * (gkx * gmx + kap * hxx)
                    out[o + 2 * k, o + 2 * m + 1] += wt * (gkx * gmy + kap * hxy)
                    out[o + 2 * k + 1, o + 2 * m] += wt * (gky * gmx + kap * hyx)
                    out[o + 2 * k + 1, o + 2 * m + 1] += wt * (gky * gmy + kap * hyy)


@njit(cache=True, error_model="numpy")
def beam_elastic_force(
    e: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_stiffness: float,
    bending_stiffness: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    scale: float,
    out: np.ndarray,
    offset: int,
    work: np.ndarray,
) -> None:
    """Add ``scale`` · F_e(e) into ``out[offset : offset + 4 (n_elements + 1)]``.

    ``work`` is scratch of at least (8 (1 + 2 ``MAX_GAUSS``), ``n_elements``)
    (:func:`beam_work`). Gauss point by Gauss point over all elements at once: the
    elements' DOFs are copied into eight contiguous rows, so each point's loop over the
    elements is vectorised, and each point's eight terms per element are kept in eight
    more; they are then added to ``out`` element after element and point after point,
    the order and products of the element-by-element quadrature, so the force is the
    same to the last bit.
    """
    ne = n_elements
    l = element_length
    x = work[:8]
    for c in range(8):
        for i in range(ne):
            x[c, i] = e[4 * i + c]
    for g in range(n_gauss_axial):
        d = _d1(_GAUSS_X[n_gauss_axial - 1, g], l)
        wg = _GAUSS_W[n_gauss_axial - 1, g] * l * scale * axial_stiffness
        t = work[8 * (1 + g) : 8 * (2 + g)]
        for i in range(ne):
            rx = d[0] * x[0, i] + d[1] * x[2, i] + d[2] * x[4, i] + d[3] * x[6, i]
            ry = d[0] * x[1, i] + d[1] * x[3, i] + d[2] * x[5, i] + d[3] * x[7, i]
            eps, c = _axial(rx, ry, axial_law)
            f = wg * eps * c
            for k in range(4):
                t[2 * k, i] = f * d[k] * rx
                t[2 * k + 1, i] = f * d[k] * ry
    for g in range(n_gauss_bending):
        xi = _GAUSS_X[n_gauss_bending - 1, g]
        d1 = _d1(xi, l)
        d2 = _d2(xi, l)
        wg = _GAUSS_W[n_gauss_bending - 1, g] * l * scale * bending_stiffness
        t = work[8 * (1 + n_gauss_axial + g) : 8 * (2 + n_gauss_axial + g)]
        for i in range(ne):
            sx = d2[0] * x[0, i] + d2[1] * x[2, i] + d2[2] * x[4, i] + d2[3] * x[6, i]
            sy = d2[0] * x[1, i] + d2[1] * x[3, i] + d2[2] * x[5, i] + d2[3] * x[7, i]
            if bending_law == BENDING_LINEAR:
                for k in range(4):
                    t[2 * k, i] = wg * d2[k] * sx
                    t[2 * k + 1, i] = wg * d2[k] * sy
                continue
            rx = d1[0] * x[0, i] + d1[1] * x[2, i] + d1[2] * x[4, i] + d1[3] * x[6, i]
            ry = d1[0] * x[1, i] + d1[1] * x[3, i] + d1[2] * x[5, i] + d1[3] * x[7, i]
            kap, k1x, k1y, k2x, k2y, _ = _curvature(rx, ry, sx, sy, bending_law)
            f = wg * kap
            for k in range(4):
                t[2 * k, i] = f * (d1[k] * k1x + d2[k] * k2x)
                t[2 * k + 1, i] = f * (d1[k] * k1y + d2[k] * k2y)
    points = n_gauss_axial + n_gauss_bending
    for i in range(ne):
        o = offset + 4 * i
        for g in range(points):
            for c in range(8):
                out[o + c] += work[8 * (1 + g) + c, i]


@njit(cache=True, error_model="numpy")
def beam_elastic_jacobian(
    e: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_stiffness: float,
    bending_stiffness: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · ∂F_e/∂e into the square block of ``out`` starting at (offset, offset)."""
    _strain_stiffness(
        e,
        True,
        n_elements,
        element_length,
        axial_stiffness,
        bending_stiffness,
        axial_law,
        bending_law,
        n_gauss_axial,
        n_gauss_bending,
        scale,
        out,
        offset,
    )


@njit(cache=True, error_model="numpy")
def beam_damping_force(
    e: np.ndarray,
    e_dot: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_stiffness: float,
    bending_stiffness: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    damping: float,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · F_d, the stiffness-proportional structural damping force.

    F_d = β ∫ (EA ε̇ ∂ε/∂e + EI κ̇ ∂κ/∂e) dx = β K_m(e) ė with β = ``damping`` (s) and K_m the
    material (non-geometric) part of the tangent stiffness; it vanishes for rigid motion.
    """
    _strain_rate_force(
        e,
        e_dot,
        n_elements,
        element_length,
        axial_stiffness * damping,
        bending_stiffness * damping,
        axial_law,
        bending_law,
        n_gauss_axial,
        n_gauss_bending,
        scale,
        out,
        offset,
    )


@njit(cache=True, error_model="numpy")
def beam_damping_jacobian(
    e: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_stiffness: float,
    bending_stiffness: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
    damping: float,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · ∂F_d/∂ė = ``scale`` · β K_m(e) into the block at (offset, offset)."""
    _strain_stiffness(
        e,
        False,
        n_elements,
        element_length,
        axial_stiffness * damping,
        bending_stiffness * damping,
        axial_law,
        bending_law,
        n_gauss_axial,
        n_gauss_bending,
        scale,
        out,
        offset,
    )


@njit(cache=True, error_model="numpy")
def beam_strain_energy(
    e: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_stiffness: float,
    bending_stiffness: float,
    axial_law: int,
    bending_law: int,
    n_gauss_axial: int,
    n_gauss_bending: int,
) -> float:
    """Strain energy U(e) = ∫ ½EA ε² + ½EI κ² dx (J) by the quadrature of the forces.

    Same strain measures and Gauss points as :func:`beam_elastic_force`, so F_e = ∂U/∂e
    holds to round-off; ``BENDING_LINEAR`` takes κ² = |r,ₓₓ|².
    """
    l = element_length
    axial = 0.0
    bending = 0.0
    for i in range(n_elements):
        q = _element(e, 4 * i)
        for g in range(n_gauss_axial):
            w, _, _, _, eps, _ = _axial_point(q, g, n_gauss_axial, l, axial_law)
            axial += w * eps * eps
        for g in range(n_gauss_bending):
            w, d1, _, sx, sy = _bending_point(q, g, n_gauss_bending, l)
            if bending_law == BENDING_LINEAR:
                bending += w * (sx * sx + sy * sy)
            else:
                kap = _curvature_point(q, d1, sx, sy, bending_law)[2]
                bending += w * kap * kap
    return 0.5 * (axial_stiffness * axial + bending_stiffness * bending)


@njit(cache=True, error_model="numpy")
def beam_mass_matrix(
    n_elements: int,
    element_length: float,
    mass_per_length: float,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · M, the constant consistent mass matrix ρA l · m̄ ⊗ I₂ per element."""
    l = element_length
    f = scale * mass_per_length * l
    for i in range(n_elements):
        o = offset + 4 * i
        for k in range(4):
            for m in range(4):
                v = f * _mbar(k, m, l)
                out[o + 2 * k, o + 2 * m] += v
                out[o + 2 * k + 1, o + 2 * m + 1] += v


@njit(cache=True, inline="always")
def _mbar(k: int, m: int, l: float) -> float:
    # m̄ of the Hermite cubic (symmetric); entries with a slope index carry l or l²
    if k > m:
        k, m = m, k
    if k == 0:
        return (13.0 / 35.0, 11.0 * l / 210.0, 9.0 / 70.0, -13.0 * l / 420.0)[m]
    if k == 1:
        return (0.0, l * l / 105.0, 13.0 * l / 420.0, -l * l / 140.0)[m]
    if k == 2:
        return (0.0, 0.0, 13.0 / 35.0, -11.0 * l / 210.0)[m]
    return l * l / 105.0


@njit(cache=True, error_model="numpy")
def beam_distributed_force(
    n_elements: int,
    element_length: float,
    force_per_length_x: float,
    force_per_length_y: float,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · ∫Sᵀ f dx for a constant force per length f (gravity: f = ρA g)."""
    l = element_length
    w = (0.5 * l, l * l / 12.0, 0.5 * l, -l * l / 12.0)
    for i in range(n_elements):
        o = offset + 4 * i
        for k in range(4):
            out[o + 2 * k] += scale * w[k] * force_per_length_x
            out[o + 2 * k + 1] += scale * w[k] * force_per_length_y


@njit(cache=True, error_model="numpy")
def beam_locate(n_elements: int, element_length: float, s: float) -> tuple[int, float]:
    """Element index and local ξ ∈ [0, 1] of arc length ``s`` (clipped to the beam)."""
    i = math.floor(s / element_length)
    if i < 0:
        i = 0
    if i > n_elements - 1:
        i = n_elements - 1
    xi = s / element_length - i
    return i, min(max(xi, 0.0), 1.0)


@njit(cache=True, error_model="numpy")
def beam_position(
    e: np.ndarray, n_elements: int, element_length: float, s: float
) -> tuple[float, float]:
    """Position r(s) = S(ξ) e of the centre line at reference arc length ``s``."""
    i, xi = beam_locate(n_elements, element_length, s)
    return _interpolate(_element(e, 4 * i), shape_functions(xi, element_length))


@njit(cache=True, error_model="numpy")
def beam_slope(
    e: np.ndarray, n_elements: int, element_length: float, s: float
) -> tuple[float, float]:
    """Slope r,ₓ(s) = S,ₓ(ξ) e at reference arc length ``s``."""
    i, xi = beam_locate(n_elements, element_length, s)
    return _interpolate(_element(e, 4 * i), _d1(xi, element_length))


@njit(cache=True, error_model="numpy")
def beam_point_force(
    n_elements: int,
    element_length: float,
    s: float,
    fx: float,
    fy: float,
    scale: float,
    out: np.ndarray,
    offset: int,
) -> None:
    """Add ``scale`` · S(ξ)ᵀ f, the generalised force of a point force f at arc length ``s``."""
    i, xi = beam_locate(n_elements, element_length, s)
    sh = shape_functions(xi, element_length)
    o = offset + 4 * i
    for k in range(4):
        out[o + 2 * k] += scale * sh[k] * fx
        out[o + 2 * k + 1] += scale * sh[k] * fy


@njit(cache=True, error_model="numpy")
def beam_axial_strain(
    e: np.ndarray,
    n_elements: int,
    element_length: float,
    axial_law: int,
    stations: np.ndarray,
    out: np.ndarray,
) -> None:
    """Write the axial strain ε(s) at the reference arc lengths ``stations`` into ``out``."""
    for j in range(stations.size):
        rx, ry = beam_slope(e, n_elements, element_length, stations[j])
        out[j] = _axial(rx, ry, axial_law)[0]


@njit(cache=True, error_model="numpy")
def beam_axial_strain_history(
    coordinates: np.ndarray,
    offset: int,
    n_elements: int,
    element_length: float,
    axial_law: int,
    stations: np.ndarray,
    out: np.ndarray,
) -> None:
    """out[t, j] = ε at ``stations[j]`` of the beam at ``coordinates[t, offset:]``."""
    n = 4 * (n_elements + 1)
    for t in range(coordinates.shape[0]):
        beam_axial_strain(
            coordinates[t, offset : offset + n],
            n_elements,
            element_length,
            axial_law,
            stations,
            out[t],
        )


@njit(cache=True, error_model="numpy")
def beam_midspan_deflection_history(
    coordinates: np.ndarray,
    offset: int,
    n_elements: int,
    element_length: float,
    out: np.ndarray,
) -> None:
    """out[t] = signed distance of r(L/2) from the end-node chord (positive to its left)."""
    n = 4 * (n_elements + 1)
    half = 0.5 * n_elements * element_length
    for t in range(coordinates.shape[0]):
        e = coordinates[t, offset : offset + n]
        ax, ay = e[0], e[1]
        cx, cy = e[n - 4] - ax, e[n - 3] - ay
        mx, my = beam_position(e, n_elements, element_length, half)
        out[t] = (cx * (my - ay) - cy * (mx - ax)) / math.sqrt(cx * cx + cy * cy)


# --- beam tables for the multibody core ---------------------------------------------------
# One row per flexible body: beam_i = [offset, n_elements, axial_law, bending_law,
# gauss_axial, gauss_bending] (int64), beam_f = [element_length, EA, EI, damping] (float64).
BEAM_I_COLUMNS = 6
BEAM_F_COLUMNS = 4
BEAM_F_DAMPING = 3  # column of the damping β in beam_f


@njit(cache=True, inline="always")
def _beam_row(
    beam_i: np.ndarray, beam_f: np.ndarray, b: int
) -> tuple[int, int, tuple[int, float, float, float, int, int, int, int], float]:
    """Offset, DOF count, the kernel parameters (as ``AncfMesh.kernel_parameters``) and the
    damping β of row ``b`` of the beam tables."""
    ne = beam_i[b, 1]
    params = (
        ne,
        beam_f[b, 0],
        beam_f[b, 1],
        beam_f[b, 2],
        beam_i[b, 2],
        beam_i[b, 3],
        beam_i[b, 4],
        beam_i[b, 5],
    )
    return beam_i[b, 0], 4 * (ne + 1), params, beam_f[b, 3]


def beam_work(beam_i: np.ndarray | int) -> np.ndarray:
    """Scratch for :func:`beams_force_add` (and :func:`beam_elastic_force`) of the beams
    in ``beam_i`` (or of one beam, given its element count as an int)."""
    if isinstance(beam_i, (int, np.integer)):
        most = int(beam_i)
    else:
        most = int(beam_i[:, 1].max()) if beam_i.shape[0] > 0 else 0
    return np.zeros((8 * (1 + 2 * MAX_GAUSS), max(most, 1)))


@njit(cache=True, error_model="numpy")
def beams_force_add(
    beam_i: np.ndarray,
    beam_f: np.ndarray,
    q: np.ndarray,
    v: np.ndarray,
    scale: float,
    out: np.ndarray,
    work: np.ndarray,
) -> None:
    """out += scale · (F_e(q) + F_d(q, q̇)) of every beam in the tables (q, v: global).

    Call with ``scale = -1`` to add the elastic and damping forces to Q. ``work`` is the
    scratch of :func:`beam_work` for these tables.
    """
    for b in range(beam_i.shape[0]):
        o, n, params, damping = _beam_row(beam_i, beam_f, b)
        e = q[o : o + n]
        beam_elastic_force(e, *params, scale, out, o, work)
        if damping > 0.0:
            beam_damping_force(e, v[o : o + n], *params, damping, scale, out, o)


@njit(cache=True, error_model="numpy")
def beams_jacobian_add(
    beam_i: np.ndarray,
    beam_f: np.ndarray,
    q: np.ndarray,
    stiffness_scale: float,
    damping_scale: float,
    out: np.ndarray,
) -> None:
    """out += stiffness_scale · ∂F_e/∂q + damping_scale · ∂F_d/∂q̇ for every beam.

    E.g. the Newton matrix of an implicit step M + γh C + βh² K takes
    ``stiffness_scale = βh²`` and ``damping_scale = γh``.
    """
    for b in range(beam_i.shape[0]):
        o, n, params, damping = _beam_row(beam_i, beam_f, b)
        e = q[o : o + n]
        beam_elastic_jacobian(e, *params, stiffness_scale, out, o)
        if damping > 0.0 and damping_scale != 0.0:
            beam_damping_jacobian(e, *params, damping, damping_scale, out, o)


@njit(cache=True, error_model="numpy")
def beams_strain_energy(beam_i: np.ndarray, beam_f: np.ndarray, q: np.ndarray) -> float:
    """Σ U(q) over every beam in the tables (J), see :func:`beam_strain_energy`."""
    energy = 0.0
    for b in range(beam_i.shape[0]):
        o, n, params, _ = _beam_row(beam_i, beam_f, b)
        energy += beam_strain_energy(q[o : o + n], *params)
    return energy
