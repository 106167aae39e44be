"""Compiled kinematics and forces of a slider corner against a guide surface (translational
clearance joint, ``docs/contact-and-wear.md``, "Translational clearance joints").

A guide surface is a straight line fixed to the guide body: the points r with
n·(r − r_g) = h, where r_g is the guide point (on the guide's centre line), n = A(θ_g) n̄
the surface's outward unit normal (from the channel into the guide's material, n̄ in the
guide body's frame) and h the distance of the surface from the centre line. A corner of
the slider is a point r_k fixed to the slider body. With e = r_k − r_g:

* penetration δ = n·e − h (> 0: the corner is inside the guide's material);
* its rate δ̇ = n·(ṙ_k − ṙ_G), ṙ_G = ṙ_g + ω_g k × e the velocity of the guide's material
  point at the corner, which is exactly dδ/dt (ṅ·e = −n·(ω_g k × e));
* sliding velocity v_t = t·(ṙ_k − ṙ_G) along t = k × n.

The contact force on the corner is f = −Fₙ n + F_t t; the guide body takes −f at the same
place (the guide point's force plus the moment e × (−f)), so the contact's power is
−Fₙ δ̇ + F_t v_t: the elastic part is the rate of the contact potential and friction only
dissipates. The functions return and take the same quantities as the revolute clearance
joint's kernels, so the model treats each corner as one row of its clearance table.
"""

from __future__ import annotations

import math

from mechanism.core._jit import njit_inner

from ._kernels import (
    PC_ANG,
    PC_RATE,
    PC_VX,
    PC_VY,
    PC_X,
    PC_Y,
    angle_acceleration,
    apply_point_force,
    point_acceleration,
)

__all__ = ["guide_acceleration", "guide_force_add", "guide_kinematics"]


@njit_inner()
def _wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


@njit_inner()
def guide_kinematics(pcf, guide, corner, normal_x, normal_y, offset):
    """Kinematics of one slider corner against one guide surface from the point cache.

    ``guide`` and ``corner`` are rows of the point cache; (``normal_x``, ``normal_y``) is
    the surface's outward unit normal n̄ in the guide body's frame and ``offset`` its
    distance h from the guide point. Returns ``(ex, ey, nx, ny, delta, delta_dot, v_t,
    phi_b, phi_j)`` like ``clearance_kinematics``: e = r_k − r_g (m), the global normal n,
    δ = n·e − h, δ̇, v_t (module docstring), the direction of n in the guide's frame and
    in the slider's frame (rad; the latter follows the slider's tilt).
    """
    th = pcf[guide, PC_ANG]
    w = pcf[guide, PC_RATE]
    c = math.cos(th)
    s = math.sin(th)
    nx = c * normal_x - s * normal_y
    ny = s * normal_x + c * normal_y
    ex = pcf[corner, PC_X] - pcf[guide, PC_X]
    ey = pcf[corner, PC_Y] - pcf[guide, PC_Y]
    # relative to the guide's material point at the corner: ṙ_g + ω k × e
    dvx = pcf[corner, PC_VX] - pcf[guide, PC_VX] + w * ey
    dvy = pcf[corner, PC_VY] - pcf[guide, PC_VY] - w * ex
    delta = nx * ex + ny * ey - offset
    delta_dot = nx * dvx + ny * dvy
    v_t = -ny * dvx + nx * dvy
    phi_b = math.atan2(normal_y, normal_x)
    phi_j = _wrap(math.atan2(ny, nx) - pcf[corner, PC_ANG])
    return ex, ey, nx, ny, delta, delta_dot, v_t, phi_b, phi_j


@njit_inner()
def guide_force_add(gen, pci, pcf, guide, corner, ex, ey, nx, ny, f_n, f_t):
    """Apply f = −Fₙ n + F_t t to the corner and −f, at the corner's place, to the guide
    body (its guide point's force plus the moment e × (−f))."""
    fx = -f_n * nx - f_t * ny
    fy = -f_n * ny + f_t * nx
    apply_point_force(gen, fx, fy, 0.0, pci, pcf, corner)
    apply_point_force(gen, -fx, -fy, ey * fx - ex * fy, pci, pcf, guide)


@njit_inner()
def guide_acceleration(acc, pci, pcf, guide, corner, ex, ey, nx, ny):
    """δ̈ (m/s²) of a corner against a guide surface for generalised accelerations ``acc``.

    δ̈ = n·(r̈_k − r̈_g) + 2ω t·(ṙ_k − ṙ_g) + α t·e − ω² n·e, with ω, α the guide's
    rotation rate and acceleration and t = k × n (exact for a moving guide).
    """
    akx, aky = point_acceleration(acc, pci, pcf, corner)
    agx, agy = point_acceleration(acc, pci, pcf, guide)
    alpha = angle_acceleration(acc, pci, pcf, guide)
    w = pcf[guide, PC_RATE]
    tx = -ny
    ty = nx
    vx = pcf[corner, PC_VX] - pcf[guide, PC_VX]
    vy = pcf[corner, PC_VY] - pcf[guide, PC_VY]
    return (
        nx * (akx - agx)
        + ny * (aky - agy)
        + 2.0 * w * (tx * vx + ty * vy)
        + alpha * (tx * ex + ty * ey)
        - w * w * (nx * ex + ny * ey)
    )
