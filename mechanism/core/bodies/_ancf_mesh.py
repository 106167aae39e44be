"""2-D gradient-deficient ANCF beams: the mesh (geometry, section, material, formulation).

A beam of reference length L is cut into ``n_elements`` equal two-node elements; each node
carries its position r and slope r,ₓ (4 DOFs), consecutive elements share nodes, so the beam's
nodal vector has 4 (n_elements + 1) entries ``[r_1, r_1,x, r_2, r_2,x, ...]``. Inside an
element r(x) = S(ξ) e with cubic Hermite shape functions (Berzeri & Shabana 2000; Jia et al.
2025, §3). The elastic energy is

    U = ∫₀ᴸ ½ EA ε² + ½ EI κ² dx,

with the axial strain ε and the bending measure κ chosen by :class:`AncfMesh`
(``axial_strain``, ``curvature``). The default (Biot strain ``|r,ₓ| − 1`` and the material
curvature ``(r,ₓ × r,ₓₓ)/|r,ₓ|²`` of Gerstmayr & Irschik 2008) reproduces the large-deflection
cantilever benchmark to 1e-7 m; the constant-stiffness form ``½EI|r,ₓₓ|²`` of the paper
(``curvature="linear"``) is kept as an option and is off by 7.5e-4 m there (see
``docs/ancf.md``).

The compiled kernels live in :mod:`mechanism.core.bodies._ancf_kernels`; this module wraps them
for single beams (mass, gravity, point, elastic and damping forces, strains). The Newton static
solver and the linearised modal analysis of one beam are in ``_ancf_analysis``, the assembly
layout of a beam body in the multibody model in ``_ancf_layout``.

References
----------
D. Berzeri, A. A. Shabana, "Development of simple models for the elastic forces in the
absolute nodal co-ordinate formulation", J. Sound Vib. 235 (2000) 539–565.
J. Gerstmayr, H. Irschik, "On the correct representation of bending and axial deformation in
the absolute nodal coordinate formulation with an elastic line approach", J. Sound Vib. 318
(2008) 461–487.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from chaoskit.contract import check_choice, check_int, check_positive

from . import _ancf_kernels as _k

if TYPE_CHECKING:
    from mechanism.core.scene import AncfBeam

__all__ = ["AncfMesh"]

AxialStrain = Literal["biot", "green"]
Curvature = Literal["material", "geometric", "linear"]

#: kernel codes of the axial strain and the curvature (also read by the assembly layout)
AXIAL_CODES = {"green": _k.AXIAL_GREEN, "biot": _k.AXIAL_BIOT}
CURVATURE_CODES = {
    "linear": _k.BENDING_LINEAR,
    "material": _k.BENDING_MATERIAL,
    "geometric": _k.BENDING_GEOMETRIC,
}


def vector2(value: Any, *, name: str) -> np.ndarray:
    arr = np.asarray(value, dtype=np.float64).reshape(-1)
    if arr.size != 2 or not np.isfinite(arr).all():
        raise ValueError(f"{name} must be two finite numbers (x, y); got {value!r}.")
    return arr


@dataclass(frozen=True, kw_only=True)
class AncfMesh:
    """A straight-reference 2-D ANCF beam: geometry, section, material and formulation.

    Parameters
    ----------
    length : float
        Reference (unstressed) length L, m.
    n_elements : int
        Number of equal elements, 1…10000.
    area, second_moment : float
        Cross-section area A (m²) and second moment of area I (m⁴) about the bending axis.
    youngs_modulus, density : float
        E (Pa) and ρ (kg m⁻³).
    damping : float
        Stiffness-proportional structural damping coefficient β (s), ≥ 0:
        F_d = β ∫(EA ε̇ ∂ε/∂e + EI κ̇ ∂κ/∂e) dx, which vanishes under rigid motion.
    axial_strain : {"biot", "green"}
        ``ε = |r,ₓ| − 1`` (default) or the Green strain ½(r,ₓᵀr,ₓ − 1) of the paper; the two
        differ by ε²/2, i.e. by < 1e-6 relative at the strains of the paper's rods.
    curvature : {"material", "geometric", "linear"}
        ``κ = (r,ₓ × r,ₓₓ)/|r,ₓ|²`` (default), ``(r,ₓ × r,ₓₓ)/|r,ₓ|³``, or the paper's constant
        bending stiffness K_t = EI∫S,ₓₓᵀS,ₓₓ dx (energy ``½EI|r,ₓₓ|²``, ``κ ≈ |r,ₓₓ|``).
    gauss_axial, gauss_bending : int
        Gauss–Legendre points per element for the axial and the bending energy, 1…5
        (defaults 5 and 3; 5 points integrate the Green-strain energy exactly).

    Attributes
    ----------
    element_length : float
        l = L / n_elements, m.
    axial_stiffness, bending_stiffness : float
        EA (N) and EI (N m²).
    mass_per_length, mass : float
        ρA (kg m⁻¹) and ρAL (kg).

    Examples
    --------
    >>> mesh = AncfMesh(length=2.0, n_elements=8, area=0.01, second_moment=0.1**4 / 12,
    ...                 youngs_modulus=2.07e11, density=7800.0)
    >>> mesh.n_dofs, round(mesh.mass, 6)
    (36, 156.0)
    """

    length: float
    n_elements: int
    area: float
    second_moment: float
    youngs_modulus: float
    density: float
    damping: float = 0.0
    axial_strain: AxialStrain = "biot"
    curvature: Curvature = "material"
    gauss_axial: int = 5
    gauss_bending: int = 3
    # derived in __post_init__ (see Attributes)
    element_length: float = field(init=False, repr=False, compare=False)
    axial_stiffness: float = field(init=False, repr=False, compare=False)
    bending_stiffness: float = field(init=False, repr=False, compare=False)
    mass_per_length: float = field(init=False, repr=False, compare=False)
    mass: float = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        for name in ("length", "area", "second_moment", "youngs_modulus", "density"):
            object.__setattr__(self, name, check_positive(getattr(self, name), name=name))
        object.__setattr__(
            self, "damping", check_positive(self.damping, name="damping", allow_zero=True)
        )
        object.__setattr__(
            self,
            "n_elements",
            check_int(self.n_elements, name="n_elements", minimum=1, maximum=10000),
        )
        check_choice(self.axial_strain, name="axial_strain", choices=tuple(AXIAL_CODES))
        check_choice(self.curvature, name="curvature", choices=tuple(CURVATURE_CODES))
        for name in ("gauss_axial", "gauss_bending"):
            check_int(getattr(self, name), name=name, minimum=1, maximum=_k.MAX_GAUSS)
        mass_per_length = self.density * self.area
        derived = {
            "element_length": self.length / self.n_elements,
            "axial_stiffness": self.youngs_modulus * self.area,
            "bending_stiffness": self.youngs_modulus * self.second_moment,
            "mass_per_length": mass_per_length,
            "mass": mass_per_length * self.length,
        }
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    @classmethod
    def from_scene(cls, beam: AncfBeam, **formulation: Any) -> AncfMesh:
        """Build the mesh of a scene's :class:`~mechanism.scene.AncfBeam` body.

        ``formulation`` passes ``axial_strain``, ``curvature``, ``gauss_axial`` or
        ``gauss_bending`` through; a ``mass`` override sets ρ = m / (A L).
        """
        # a mass override is honoured through the density, which the stiffness ignores
        density = beam.density if beam.mass is None else beam.mass / (beam.area * beam.length)
        return cls(
            length=beam.length,
            n_elements=beam.elements,
            area=beam.area,
            second_moment=beam.second_moment,
            youngs_modulus=beam.youngs_modulus,
            density=density,
            damping=beam.damping,
            **formulation,
        )

    # --- derived sizes -------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return self.n_elements + 1

    @property
    def n_dofs(self) -> int:
        """4 (n_elements + 1): position and slope (x, y) of every node."""
        return 4 * self.n_nodes

    @property
    def kernel_parameters(self) -> tuple[int, float, float, float, int, int, int, int]:
        """The arguments that follow ``e`` in every elastic kernel of ``_ancf_kernels``.

        ``(n_elements, element_length, EA, EI, axial_law, bending_law, gauss_axial,
        gauss_bending)``; the damping kernels take ``damping`` after them.
        """
        return (
            self.n_elements,
            self.element_length,
            self.axial_stiffness,
            self.bending_stiffness,
            AXIAL_CODES[self.axial_strain],
            CURVATURE_CODES[self.curvature],
            self.gauss_axial,
            self.gauss_bending,
        )

    def node_dofs(self, node: int) -> np.ndarray:
        """Indices ``[x, y, x,ₓ, y,ₓ]`` of node ``node`` (negative counts from the end)."""
        n = self.n_nodes
        j = check_int(node, name="node", minimum=-n, maximum=n - 1) % n
        return np.arange(4 * j, 4 * j + 4)

    def node_positions(self) -> np.ndarray:
        """Reference arc length of every node, m."""
        return np.linspace(0.0, self.length, self.n_nodes)

    # --- states --------------------------------------------------------------------------
    def straight_coordinates(self, start: ArrayLike = (0.0, 0.0), angle: float = 0.0) -> np.ndarray:
        """Nodal vector of the unstressed straight beam from ``start`` at ``angle`` (rad).

        Positions r_j = start + s_j t, slopes r_j,ₓ = t = (cos angle, sin angle).
        """
        p0 = vector2(start, name="start")
        t = np.array([math.cos(angle), math.sin(angle)])
        e = np.empty(self.n_dofs)
        nodes = e.reshape(-1, 4)
        nodes[:, 0:2] = p0 + self.node_positions()[:, None] * t
        nodes[:, 2:4] = t
        return e

    def rigid_velocities(
        self, e: Any, *, velocity: ArrayLike = (0.0, 0.0), angular_velocity: float = 0.0
    ) -> np.ndarray:
        """ė of a rigid motion: node 1 moves with ``velocity``, the beam spins at ω (rad/s).

        ṙ_j = v + ω k × (r_j − r_1), ṙ_j,ₓ = ω k × r_j,ₓ.
        """
        nodes = self._coordinates(e).reshape(-1, 4)
        v = vector2(velocity, name="velocity")
        w = float(angular_velocity)
        out = np.empty((self.n_nodes, 4))
        rel = nodes[:, 0:2] - nodes[0, 0:2]
        out[:, 0] = v[0] - w * rel[:, 1]
        out[:, 1] = v[1] + w * rel[:, 0]
        out[:, 2] = -w * nodes[:, 3]
        out[:, 3] = w * nodes[:, 2]
        return out.reshape(-1)

    def sine_modes(self, amplitudes: ArrayLike, *, angle: float = 0.0) -> np.ndarray:
        """Nodal vector of the transverse field w(s) = Σ_k a_k sin(kπ s/L) along n.

        n = (−sin angle, cos angle) is the left normal of a beam at ``angle``; nodal
        positions get w(s_j) n and slopes w'(s_j) n. Being linear, this serves for
        displacements (m) and for velocities (m/s), e.g. Simeon's elastic initial
        velocities of the flexible slider-crank (docs/ancf.md).
        """
        a = np.asarray(amplitudes, dtype=np.float64).reshape(-1)
        s = self.node_positions()
        k = np.arange(1, a.size + 1)[:, None] * (math.pi / self.length)
        w = a @ np.sin(k * s)
        dw = a @ (k * np.cos(k * s))
        normal = np.array([-math.sin(angle), math.cos(angle)])
        out = np.empty((self.n_nodes, 4))
        out[:, 0:2] = w[:, None] * normal
        out[:, 2:4] = dw[:, None] * normal
        return out.reshape(-1)

    def _coordinates(self, e: Any, name: str = "e") -> np.ndarray:
        arr = np.ascontiguousarray(e, dtype=np.float64)
        if arr.shape != (self.n_dofs,):
            raise ValueError(
                f"{name} must be a nodal vector of length {self.n_dofs} "
                f"(4 × {self.n_nodes} nodes); got shape {arr.shape}."
            )
        if not np.isfinite(arr).all():
            raise ValueError(f"{name} contains non-finite values.")
        return arr

    # --- matrices and forces -------------------------------------------------------------
    def mass_matrix(self) -> np.ndarray:
        """Constant consistent mass matrix M = Σ ρA l m̄ ⊗ I₂ (kg, kg m, kg m²)."""
        out = np.zeros((self.n_dofs, self.n_dofs))
        _k.beam_mass_matrix(self.n_elements, self.element_length, self.mass_per_length, 1.0, out, 0)
        return out

    def gravity_force(self, gravity: ArrayLike = (0.0, -9.81)) -> np.ndarray:
        """Generalised gravity force Q_g = ρA ∫Sᵀg dx (N, N m) for g in m s⁻²."""
        g = vector2(gravity, name="gravity")
        out = np.zeros(self.n_dofs)
        rho_a = self.mass_per_length
        _k.beam_distributed_force(
            self.n_elements, self.element_length, rho_a * g[0], rho_a * g[1], 1.0, out, 0
        )
        return out

    def point_force(self, s: float, force: ArrayLike) -> np.ndarray:
        """Generalised force S(ξ)ᵀf of a point force f (N) at reference arc length s (m)."""
        s = self._arc_length(s)
        f = vector2(force, name="force")
        out = np.zeros(self.n_dofs)
        _k.beam_point_force(self.n_elements, self.element_length, s, f[0], f[1], 1.0, out, 0)
        return out

    def elastic_force(self, e: Any) -> np.ndarray:
        """Elastic force F_e(e) = ∂U/∂e (enters the equations of motion as −F_e)."""
        out = np.zeros(self.n_dofs)
        work = _k.beam_work(self.n_elements)
        _k.beam_elastic_force(self._coordinates(e), *self.kernel_parameters, 1.0, out, 0, work)
        return out

    def elastic_jacobian(self, e: Any) -> np.ndarray:
        """Tangent stiffness ∂F_e/∂e (analytic, symmetric)."""
        out = np.zeros((self.n_dofs, self.n_dofs))
        _k.beam_elastic_jacobian(self._coordinates(e), *self.kernel_parameters, 1.0, out, 0)
        return out

    def damping_force(self, e: Any, e_dot: Any) -> np.ndarray:
        """Structural damping force F_d = β K_m(e) ė (zero when ``damping`` is 0)."""
        out = np.zeros(self.n_dofs)
        _k.beam_damping_force(
            self._coordinates(e),
            self._coordinates(e_dot, "e_dot"),
            *self.kernel_parameters,
            self.damping,
            1.0,
            out,
            0,
        )
        return out

    def damping_jacobian(self, e: Any) -> np.ndarray:
        """∂F_d/∂ė = β K_m(e), the damping matrix (∂F_d/∂e is not provided)."""
        out = np.zeros((self.n_dofs, self.n_dofs))
        _k.beam_damping_jacobian(
            self._coordinates(e), *self.kernel_parameters, self.damping, 1.0, out, 0
        )
        return out

    def strain_energy(self, e: Any) -> float:
        """Strain energy U(e) = ∫ ½EA ε² + ½EI κ² dx (J) by the quadrature of the forces,
        so that F_e = ∂U/∂e (``curvature="linear"``: ``κ² = |r,ₓₓ|²``).
        """
        return float(_k.beam_strain_energy(self._coordinates(e), *self.kernel_parameters))

    # --- outputs -------------------------------------------------------------------------
    def _arc_length(self, s: Any) -> float:
        s = float(s)
        if not 0.0 <= s <= self.length:
            raise ValueError(f"s must be in [0, {self.length}] m; got {s}.")
        return s

    def position(self, e: Any, s: float) -> np.ndarray:
        """Centre-line position r(s) at reference arc length s (m)."""
        return np.array(
            _k.beam_position(
                self._coordinates(e), self.n_elements, self.element_length, self._arc_length(s)
            )
        )

    def axial_strain_at(self, e: Any, stations: Any = None) -> np.ndarray:
        """Axial strain ε at reference arc lengths ``stations`` (m; default: nodes and
        element mid-points, where the cubic interpolation gives its most accurate strain).
        """
        return self.axial_strain_history(self._coordinates(e)[None, :], stations)[0]

    def _stations(self, stations: Any) -> np.ndarray:
        # default: nodes and element mid-points
        if stations is None:
            return np.linspace(0.0, self.length, 2 * self.n_elements + 1)
        st = np.ascontiguousarray(stations, dtype=np.float64).reshape(-1)
        if st.size == 0 or st.min() < 0.0 or st.max() > self.length:
            raise ValueError(f"stations must lie in [0, {self.length}] m.")
        return st

    def _history(self, coordinates: Any, offset: int) -> np.ndarray:
        arr = np.ascontiguousarray(coordinates, dtype=np.float64)
        if arr.ndim != 2:
            raise ValueError(f"coordinates must be 2-D (time, dof); got shape {arr.shape}.")
        offset = check_int(offset, name="offset", minimum=0, maximum=arr.shape[1] - self.n_dofs)
        return arr

    def axial_strain_history(
        self, coordinates: Any, stations: Any = None, *, offset: int = 0
    ) -> np.ndarray:
        """ε (time, station) of the beam whose DOFs start at column ``offset`` of
        ``coordinates`` (time, dof); stations as in :meth:`axial_strain_at`.
        """
        arr = self._history(coordinates, offset)
        st = self._stations(stations)
        out = np.empty((arr.shape[0], st.size))
        _k.beam_axial_strain_history(
            arr,
            offset,
            self.n_elements,
            self.element_length,
            AXIAL_CODES[self.axial_strain],
            st,
            out,
        )
        return out

    def midspan_deflection_history(self, coordinates: Any, *, offset: int = 0) -> np.ndarray:
        """:meth:`midspan_deflection` (m) for every row of ``coordinates`` (time, dof)."""
        arr = self._history(coordinates, offset)
        out = np.empty(arr.shape[0])
        _k.beam_midspan_deflection_history(arr, offset, self.n_elements, self.element_length, out)
        return out

    def midspan_deflection(self, e: Any) -> float:
        """Signed distance (m) of r(L/2) from the chord r_1 → r_N, positive to its left."""
        e = self._coordinates(e)
        a = e[0:2]
        b = e[-4:-2]
        chord = b - a
        norm = math.hypot(chord[0], chord[1])
        if norm == 0.0:
            raise ValueError("the end nodes coincide; the chord direction is undefined.")
        mid = self.position(e, 0.5 * self.length) - a
        return float((chord[0] * mid[1] - chord[1] * mid[0]) / norm)
