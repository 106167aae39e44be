"""Assembly layout of a flexible ANCF beam body in the multibody model."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from mechanism.core.joints import ANGLE_SLOPE, POINT_LINEAR

from ._ancf_mesh import AXIAL_CODES, CURVATURE_CODES, AncfMesh, AxialStrain, Curvature, vector2

if TYPE_CHECKING:
    from mechanism.core.scene import AncfBeam

__all__ = ["AncfLayout"]


@dataclass(frozen=True, kw_only=True)
class AncfLayout:
    """Assembly layout of a flexible :class:`~mechanism.scene.AncfBeam` body .

    Provides what :class:`~mechanism.core.bodies.RigidLayout` provides (``n_dof``,
    ``coordinate_names``, ``mass_block``, ``gravity_block``, ``initial_coordinates``,
    ``point_names``, ``point_row``) plus ``beam_row`` (one row of the beam tables read by
    :func:`~mechanism.core.bodies._ancf_kernels.beams_force_add`) and :meth:`from_rigid_state`
    (straight, unstressed coordinates and rigid-motion velocities). The points ``"start"``
    and ``"end"`` are the first and last node: linear points whose frame angle is that of
    the nodal slope (``ANGLE_SLOPE``), so a revolute pin is a linear constraint on the
    node's position DOFs and a moment acts through the slope DOFs.
    """

    name: str
    beam: AncfBeam
    axial_strain: AxialStrain = "biot"
    curvature: Curvature = "material"
    gauss_axial: int = 5
    gauss_bending: int = 3
    mesh: AncfMesh = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "mesh",
            AncfMesh.from_scene(
                self.beam,
                axial_strain=self.axial_strain,
                curvature=self.curvature,
                gauss_axial=self.gauss_axial,
                gauss_bending=self.gauss_bending,
            ),
        )

    @property
    def n_dof(self) -> int:
        return self.mesh.n_dofs

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """``node{j}.x``, ``node{j}.y``, ``node{j}.slope_x``, ``node{j}.slope_y``."""
        return tuple(
            f"node{j}.{c}"
            for j in range(self.mesh.n_nodes)
            for c in ("x", "y", "slope_x", "slope_y")
        )

    def mass_block(self) -> np.ndarray:
        """Constant consistent mass matrix of the beam."""
        return self.mesh.mass_matrix()

    def gravity_block(self, gravity: tuple[float, float]) -> np.ndarray:
        """Generalised gravity force ρA∫Sᵀg dx."""
        return self.mesh.gravity_force(gravity)

    def _chord(self) -> tuple[np.ndarray, float]:
        start = np.asarray(self.beam.start, dtype=np.float64)
        end = np.asarray(self.beam.end, dtype=np.float64)
        d = end - start
        return start, math.atan2(d[1], d[0])

    @property
    def chord_angle(self) -> float:
        """Angle (rad) of the initial chord ``start`` → ``end``."""
        return self._chord()[1]

    def initial_coordinates(self) -> np.ndarray:
        """Straight, unstressed beam from ``start`` towards ``end`` with its own length."""
        start, angle = self._chord()
        return self.mesh.straight_coordinates(start, angle)

    @property
    def point_names(self) -> tuple[str, ...]:
        return ("start", "end")

    def point_row(self, point: str, offset: int) -> tuple[list[int], list[float]]:
        """Point-table rows of ``"start"`` (node 1) or ``"end"`` (last node)."""
        if point not in self.point_names:
            raise KeyError(point)
        node = offset + (0 if point == "start" else 4 * self.mesh.n_elements)
        return (
            [POINT_LINEAR, offset, ANGLE_SLOPE, node + 2, node, -1, -1, -1],
            [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        )

    def beam_row(self, offset: int) -> tuple[list[int], list[float]]:
        """Rows ``beam_i``/``beam_f`` of the beam tables (see ``_ancf_kernels``)."""
        m = self.mesh
        return (
            [
                int(offset),
                m.n_elements,
                AXIAL_CODES[m.axial_strain],
                CURVATURE_CODES[m.curvature],
                m.gauss_axial,
                m.gauss_bending,
            ],
            [m.element_length, m.axial_stiffness, m.bending_stiffness, m.damping],
        )

    def from_rigid_state(
        self,
        position: ArrayLike,
        angle: float,
        velocity: ArrayLike = (0.0, 0.0),
        angular_velocity: float = 0.0,
    ) -> tuple[np.ndarray, np.ndarray]:
        """(e, ė) of the beam moving rigidly like the bar of
        :func:`~mechanism.core.bodies.rigid_bar_from_beam` with centre ``position`` (m), ``angle``
        (rad), centre ``velocity`` (m/s) and ``angular_velocity`` (rad/s).

        Solve the ideal mechanism with ``effects.flexibility = False`` and map each bar's
        state through this method: the beam starts straight, unstressed and with zero
        strain rates (a minimum-kinetic-energy velocity projection would not give that).
        """
        centre = vector2(position, name="position")
        v = vector2(velocity, name="velocity")
        w = float(angular_velocity)
        half = 0.5 * self.mesh.length
        t = np.array([math.cos(angle), math.sin(angle)])
        start = centre - half * t
        e = self.mesh.straight_coordinates(start, angle)
        # velocity of the start node: v + ω k × (start − centre)
        v_start = v + w * np.array([half * t[1], -half * t[0]])
        return e, self.mesh.rigid_velocities(e, velocity=v_start, angular_velocity=w)
