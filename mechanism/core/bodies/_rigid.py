"""Rigid bodies: reference-point coordinates (x, y, θ) at the centre of mass.

docs/paper-model.md §3: a point P of body i is r_P = R_i + A(θ_i) s̄_P with
A(θ) = [[cos θ, −sin θ], [sin θ, cos θ]]; with the reference point at the centre of mass the
mass matrix is diag(m, m, J) and there is no velocity-quadratic inertia term in 2-D;
gravity gives Q_g = [m g_x, m g_y, 0].

A body *layout* tells assembly how many coordinates a body has, its constant mass block,
its constant generalised gravity, its initial coordinates and how to express its named
points in the flat point table of ``mechanism.core.joints._kernels``. Flexible bodies (ANCF
beams) provide the same five things.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechanism.core.joints import ANGLE_RIGID, POINT_RIGID
from mechanism.core.scene import AncfBeam, RigidBody

__all__ = ["RigidLayout", "rigid_bar_from_beam"]


def rigid_bar_from_beam(beam: AncfBeam) -> RigidBody:
    """The rigid bar that replaces an ANCF beam when ``effects.flexibility`` is off.

    Same mass (``beam.mass`` or ρ A L), centroidal inertia ``beam.rigid_inertia`` or
    m L²/12, centre of mass at the midpoint of ``start``–``end``, angle of that chord, and
    points ``"start"``/``"end"`` at ∓L/2 on the bar axis.

    Examples
    --------
    >>> from mechanism.core.scene import AncfBeam
    >>> bar = rigid_bar_from_beam(AncfBeam(length=2.0, area=1e-3, second_moment=1e-8,
    ...     youngs_modulus=2e11, density=7800.0, start=(0.0, 0.0), end=(0.0, 2.0)))
    >>> round(bar.mass, 6), round(bar.inertia, 6), bar.points["end"]
    (15.6, 5.2, (1.0, 0.0))
    """
    length = float(beam.length)
    mass = float(beam.total_mass)
    inertia = float(beam.centroidal_inertia)
    sx, sy = beam.start
    ex, ey = beam.end
    return RigidBody(
        mass=mass,
        inertia=inertia,
        position=(0.5 * (sx + ex), 0.5 * (sy + ey)),
        angle=math.atan2(ey - sy, ex - sx),
        points={"start": (-0.5 * length, 0.0), "end": (0.5 * length, 0.0)},
    )


@dataclass(frozen=True, kw_only=True)
class RigidLayout:
    """Assembly layout of a rigid body: coordinates (x, y, θ) of its centre of mass."""

    name: str
    body: RigidBody

    n_dof = 3
    coordinate_names = ("x", "y", "theta")

    def mass_block(self) -> np.ndarray:
        """Constant mass block diag(m, m, J) (kg, kg, kg m²)."""
        return np.diag([self.body.mass, self.body.mass, self.body.inertia]).astype(np.float64)

    def gravity_block(self, gravity: tuple[float, float]) -> np.ndarray:
        """Generalised gravity force [m g_x, m g_y, 0] (N, N, N m)."""
        m = self.body.mass
        return np.array([m * gravity[0], m * gravity[1], 0.0])

    def initial_coordinates(self) -> np.ndarray:
        """The scene's pose guess [x, y, θ] (refined by assembly)."""
        x, y = self.body.position
        return np.array([x, y, self.body.angle], dtype=np.float64)

    @property
    def point_names(self) -> tuple[str, ...]:
        return tuple(self.body.points)

    def point_row(self, point: str, offset: int) -> tuple[list[int], list[float]]:
        """Rows of the point table for ``point`` with the body's coordinates at ``offset``."""
        if point not in self.body.points:
            raise KeyError(point)
        sx, sy = self.body.points[point]
        return (
            [POINT_RIGID, offset, ANGLE_RIGID, -1, -1, -1, -1, -1],
            [float(sx), float(sy), 0.0, 0.0, 0.0, 0.0],
        )
