"""2-D gradient-deficient ANCF beams: mesh description, static equilibrium and modal analysis.

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
for single beams and adds the Newton static solver and the linearised modal analysis used by
the validation tests S4 and S5.

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
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import scipy.linalg
import xarray as xr
from numpy.typing import ArrayLike

from chaoskit.contract import check_choice, check_int, check_positive
from mechanism.core.joints import ANGLE_SLOPE, POINT_LINEAR

from . import _ancf_kernels as _k

if TYPE_CHECKING:
    from mechanism.core.scene import AncfBeam

__all__ = [
    "AncfLayout",
    "AncfMesh",
    "BeamModes",
    "BeamStaticSolution",
    "beam_modes",
    "euler_bernoulli_frequencies",
    "solve_beam_static",
]

AxialStrain = Literal["biot", "green"]
Curvature = Literal["material", "geometric", "linear"]
Support = Literal["clamped-free", "pinned-pinned"]

_AXIAL_CODES = {"green": _k.AXIAL_GREEN, "biot": _k.AXIAL_BIOT}
_CURVATURE_CODES = {
    "linear": _k.BENDING_LINEAR,
    "material": _k.BENDING_MATERIAL,
    "geometric": _k.BENDING_GEOMETRIC,
}


def _vector2(value: Any, *, name: str) -> np.ndarray:
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
        check_choice(self.axial_strain, name="axial_strain", choices=tuple(_AXIAL_CODES))
        check_choice(self.curvature, name="curvature", choices=tuple(_CURVATURE_CODES))
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
            _AXIAL_CODES[self.axial_strain],
            _CURVATURE_CODES[self.curvature],
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
        p0 = _vector2(start, name="start")
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
        v = _vector2(velocity, name="velocity")
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
        g = _vector2(gravity, name="gravity")
        out = np.zeros(self.n_dofs)
        rho_a = self.mass_per_length
        _k.beam_distributed_force(
            self.n_elements, self.element_length, rho_a * g[0], rho_a * g[1], 1.0, out, 0
        )
        return out

    def point_force(self, s: float, force: ArrayLike) -> np.ndarray:
        """Generalised force S(ξ)ᵀf of a point force f (N) at reference arc length s (m)."""
        s = self._arc_length(s)
        f = _vector2(force, name="force")
        out = np.zeros(self.n_dofs)
        _k.beam_point_force(self.n_elements, self.element_length, s, f[0], f[1], 1.0, out, 0)
        return out

    def elastic_force(self, e: Any) -> np.ndarray:
        """Elastic force F_e(e) = ∂U/∂e (enters the equations of motion as −F_e)."""
        out = np.zeros(self.n_dofs)
        _k.beam_elastic_force(self._coordinates(e), *self.kernel_parameters, 1.0, out, 0)
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
            _AXIAL_CODES[self.axial_strain],
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


# --- static equilibrium ----------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class BeamStaticSolution:
    """Result of :func:`solve_beam_static`.

    ``coordinates`` is the equilibrium nodal vector, ``reference`` the start vector;
    ``iterations`` lists the Newton iterations of each load step.
    """

    mesh: AncfMesh
    coordinates: np.ndarray
    reference: np.ndarray
    load: np.ndarray
    fixed_dofs: tuple[int, ...]
    load_steps: int
    iterations: tuple[int, ...]
    residual_norm: float
    success: bool
    message: str
    wall_time: float = field(default=0.0)

    def node_displacement(self, node: int = -1) -> np.ndarray:
        """Displacement r − r_ref of node ``node`` (default: the last), m."""
        idx = self.mesh.node_dofs(node)[:2]
        return self.coordinates[idx] - self.reference[idx]

    def to_dataset(self) -> xr.Dataset:
        """Nodal positions, slopes and displacements over ``node`` and ``component``."""
        nodes = self.coordinates.reshape(-1, 4)
        ref = self.reference.reshape(-1, 4)
        coords = {
            "node": np.arange(self.mesh.n_nodes),
            "component": ["x", "y"],
            "arc_length": (
                "node",
                self.mesh.node_positions(),
                {"units": "m", "long_name": "reference arc length"},
            ),
        }
        ds = xr.Dataset(
            {
                "position": (
                    ("node", "component"),
                    nodes[:, 0:2],
                    {"units": "m", "long_name": "nodal position"},
                ),
                "slope": (
                    ("node", "component"),
                    nodes[:, 2:4],
                    {"units": "1", "long_name": "nodal slope dr/dx"},
                ),
                "displacement": (
                    ("node", "component"),
                    nodes[:, 0:2] - ref[:, 0:2],
                    {"units": "m", "long_name": "nodal displacement"},
                ),
            },
            coords=coords,
        )
        ds.attrs.update(
            load_steps=self.load_steps,
            success=int(self.success),
            message=self.message,
            residual_norm=self.residual_norm,
            newton_iterations=list(self.iterations),
        )
        return ds


def solve_beam_static(
    mesh: AncfMesh,
    load: Any,
    *,
    fixed_dofs: Sequence[int],
    initial: Any = None,
    load_steps: int = 10,
    rtol: float = 1e-10,
    xtol: float = 1e-13,
    max_iterations: int = 30,
) -> BeamStaticSolution:
    """Static equilibrium F_e(e) = λ_k Q for λ_k = k/``load_steps`` by Newton's method.

    Each load step is solved with the analytic tangent ∂F_e/∂e; the DOFs in ``fixed_dofs``
    keep their initial values (a clamp of a beam along x is ``[0, 1, 3]`` with the root
    stretch free, as in Gerstmayr & Irschik 2008, or ``[0, 1, 2, 3]``). The load Q is a
    fixed-direction generalised force (e.g. from :meth:`AncfMesh.point_force`).

    Parameters
    ----------
    mesh : AncfMesh
    load : array_like, shape (n_dofs,)
        Generalised external force Q (N, N m).
    fixed_dofs : sequence of int
        Constrained DOF indices.
    initial : array_like, optional
        Start vector; default the straight beam along x from the origin.
    load_steps : int
        Number of equal load increments, ≥ 1.
    rtol : float
        Convergence when ``|residual| ≤ rtol · |Q|`` on the free DOFs ...
    xtol : float
        ... or when the largest Newton correction is ``≤ xtol · (1 + max |e|)``.
    max_iterations : int
        Newton iterations allowed per load step.

    Returns
    -------
    BeamStaticSolution
        With ``success=False`` and a message if a step did not converge (no exception).

    Examples
    --------
    >>> mesh = AncfMesh(length=2.0, n_elements=4, area=0.01, second_moment=0.1**4 / 12,
    ...                 youngs_modulus=2.07e11, density=7800.0)
    >>> p = 3 * mesh.bending_stiffness / mesh.length**2
    >>> sol = solve_beam_static(mesh, mesh.point_force(2.0, (0.0, -p)), fixed_dofs=[0, 1, 3])
    >>> bool(sol.success), np.round(sol.node_displacement(), 4).tolist()
    (True, [-0.5074, -1.2055])
    """
    start = time.perf_counter()
    q = mesh._coordinates(load, "load")
    e0 = mesh.straight_coordinates() if initial is None else mesh._coordinates(initial, "initial")
    steps = check_int(load_steps, name="load_steps", minimum=1)
    rtol = check_positive(rtol, name="rtol")
    xtol = check_positive(xtol, name="xtol")
    max_iterations = check_int(max_iterations, name="max_iterations", minimum=1)
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64).reshape(-1))
    if fixed.size and (fixed.min() < 0 or fixed.max() >= mesh.n_dofs):
        raise ValueError(f"fixed_dofs must lie in [0, {mesh.n_dofs - 1}].")
    free = np.setdiff1d(np.arange(mesh.n_dofs), fixed)
    params = mesh.kernel_parameters
    scale = max(float(np.linalg.norm(q[free])), 1e-300)
    e = e0.copy()
    force = np.empty(mesh.n_dofs)
    jac = np.empty((mesh.n_dofs, mesh.n_dofs))
    iterations: list[int] = []
    res_norm = 0.0

    def result(success: bool, message: str) -> BeamStaticSolution:
        return BeamStaticSolution(
            mesh=mesh,
            coordinates=e,
            reference=e0,
            load=q,
            fixed_dofs=tuple(int(i) for i in fixed),
            load_steps=steps,
            iterations=tuple(iterations),
            residual_norm=res_norm,
            success=success,
            message=message,
            wall_time=time.perf_counter() - start,
        )

    for k in range(1, steps + 1):
        target = q * (k / steps)
        step = math.inf
        for it in range(max_iterations + 1):
            force[:] = 0.0
            _k.beam_elastic_force(e, *params, 1.0, force, 0)
            residual = force[free] - target[free]
            res_norm = float(np.linalg.norm(residual))
            # with a very stiff axial law round-off in F_e can exceed rtol·|Q|; a Newton
            # correction at round-off level then means convergence as well
            if res_norm <= rtol * scale or step <= xtol * (1.0 + np.abs(e).max()):
                iterations.append(it)
                break
            if it == max_iterations:
                iterations.append(it)
                return result(
                    False,
                    f"Newton did not converge in load step {k} of {steps} "
                    f"(|residual| = {res_norm:.3e} N).",
                )
            jac[:] = 0.0
            _k.beam_elastic_jacobian(e, *params, 1.0, jac, 0)
            delta = scipy.linalg.solve(jac[np.ix_(free, free)], residual, assume_a="sym")
            e[free] -= delta
            step = float(np.abs(delta).max())
    return result(True, "converged")


# --- modal analysis ------------------------------------------------------------------------
@dataclass(frozen=True, kw_only=True)
class BeamModes:
    """Linearised eigenmodes K φ = ω² M φ of a beam with some DOFs fixed, ascending.

    ``axial_fraction`` is the share of a mode's kinetic energy (φᵀMφ) carried by the
    displacement along the beam's reference direction; ``kind`` is "axial" above 0.5 and
    "bending" otherwise.
    """

    mesh: AncfMesh
    frequency: np.ndarray  # Hz
    mode_shape: np.ndarray  # (n_dofs, n_modes), zero at fixed DOFs, φᵀMφ = 1
    axial_fraction: np.ndarray
    fixed_dofs: tuple[int, ...]

    @property
    def kind(self) -> np.ndarray:
        return np.where(self.axial_fraction > 0.5, "axial", "bending")

    def bending_frequencies(self) -> np.ndarray:
        """Frequencies (Hz) of the bending modes, ascending."""
        return self.frequency[self.axial_fraction <= 0.5]

    def axial_frequencies(self) -> np.ndarray:
        """Frequencies (Hz) of the axial modes, ascending."""
        return self.frequency[self.axial_fraction > 0.5]

    def to_dataset(self) -> xr.Dataset:
        """Frequencies, kinds and mode shapes over ``mode`` (and ``dof``)."""
        n = self.frequency.size
        ds = xr.Dataset(
            {
                "frequency": (
                    "mode",
                    self.frequency,
                    {"units": "Hz", "long_name": "natural frequency"},
                ),
                "axial_fraction": (
                    "mode",
                    self.axial_fraction,
                    {"units": "1", "long_name": "axial share of modal mass"},
                ),
                "kind": (
                    "mode",
                    self.kind.astype(object),
                    {"units": "1", "long_name": "mode kind (axial or bending)"},
                ),
                "mode_shape": (
                    ("dof", "mode"),
                    self.mode_shape,
                    {"units": "1", "long_name": "mass-normalised mode shape"},
                ),
            },
            coords={"mode": np.arange(1, n + 1), "dof": np.arange(self.mesh.n_dofs)},
        )
        ds.attrs.update(fixed_dofs=list(self.fixed_dofs), n_elements=self.mesh.n_elements)
        return ds


def beam_modes(
    mesh: AncfMesh,
    *,
    fixed_dofs: Sequence[int],
    coordinates: Any = None,
    n_modes: int | None = None,
) -> BeamModes:
    """Eigenfrequencies of the beam linearised about ``coordinates``.

    Solves K_r φ = ω² M_r φ with K = ∂F_e/∂e at ``coordinates`` (default: the straight,
    unstressed beam along x) and M the consistent mass matrix, both reduced by removing
    ``fixed_dofs``. Frequencies are f = ω/2π in Hz.

    Examples
    --------
    >>> mesh = AncfMesh(length=2.0, n_elements=8, area=0.01, second_moment=0.1**4 / 12,
    ...                 youngs_modulus=2.07e11, density=7800.0)
    >>> modes = beam_modes(mesh, fixed_dofs=[0, 1, 2, 3])
    >>> np.round(modes.bending_frequencies()[:2], 2).tolist()
    [20.8, 130.39]
    """
    e = (
        mesh.straight_coordinates()
        if coordinates is None
        else mesh._coordinates(coordinates, "coordinates")
    )
    fixed = np.unique(np.asarray(fixed_dofs, dtype=np.int64).reshape(-1))
    if fixed.size and (fixed.min() < 0 or fixed.max() >= mesh.n_dofs):
        raise ValueError(f"fixed_dofs must lie in [0, {mesh.n_dofs - 1}].")
    free = np.setdiff1d(np.arange(mesh.n_dofs), fixed)
    n_free = free.size
    n_modes = (
        n_free if n_modes is None else check_int(n_modes, name="n_modes", minimum=1, maximum=n_free)
    )
    stiffness = mesh.elastic_jacobian(e)[np.ix_(free, free)]
    mass = mesh.mass_matrix()
    lam, vec = scipy.linalg.eigh(
        stiffness, mass[np.ix_(free, free)], subset_by_index=[0, n_modes - 1]
    )
    shapes = np.zeros((mesh.n_dofs, n_modes))
    shapes[free] = vec
    # axial direction: the chord of the linearisation state
    chord = e[-4:-2] - e[0:2]
    t = chord / np.linalg.norm(chord)
    axial = np.zeros_like(shapes)
    axial[0::2] = t[0] * (t[0] * shapes[0::2] + t[1] * shapes[1::2])
    axial[1::2] = t[1] * (t[0] * shapes[0::2] + t[1] * shapes[1::2])
    total = np.einsum("im,ij,jm->m", shapes, mass, shapes)
    frac = np.einsum("im,ij,jm->m", axial, mass, axial) / total
    return BeamModes(
        mesh=mesh,
        frequency=np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * math.pi),
        mode_shape=shapes,
        axial_fraction=frac,
        fixed_dofs=tuple(int(i) for i in fixed),
    )


# Roots of cos β cosh β = −1 (clamped–free Euler–Bernoulli beam)
_CLAMPED_FREE_ROOTS = (
    1.8751040687119611,
    4.694091132974175,
    7.854757438237613,
    10.995540734875467,
    14.13716839104647,
)


def euler_bernoulli_frequencies(
    mesh: AncfMesh, *, support: Support, n_modes: int = 3
) -> tuple[np.ndarray, np.ndarray]:
    """Euler–Bernoulli bending and rod axial frequencies (Hz) of the continuous beam.

    ``support="clamped-free"``: f_n = β_n² √(EI/ρA) / (2π L²) with cos β cosh β = −1, axial
    f_n = (2n − 1) c / (4L); ``"pinned-pinned"`` (ends fixed in position): f_n = n² π
    √(EI/ρA) / (2 L²), axial f_n = n c / (2L); c = √(E/ρ).
    """
    check_choice(support, name="support", choices=("clamped-free", "pinned-pinned"))
    n_modes = check_int(n_modes, name="n_modes", minimum=1, maximum=len(_CLAMPED_FREE_ROOTS))
    length = mesh.length
    reach = math.sqrt(mesh.bending_stiffness / mesh.mass_per_length)
    c = math.sqrt(mesh.youngs_modulus / mesh.density)
    n = np.arange(1, n_modes + 1, dtype=np.float64)
    if support == "clamped-free":
        beta = np.asarray(_CLAMPED_FREE_ROOTS[:n_modes], dtype=np.float64)
        bending = beta**2 * reach / (2.0 * math.pi * length**2)
        axial = (2 * n - 1) * c / (4.0 * length)
    else:
        bending = n**2 * math.pi * reach / (2.0 * length**2)
        axial = n * c / (2.0 * length)
    return bending, axial


# --- assembly layout for the multibody core ------------------------------------------------
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
                _AXIAL_CODES[m.axial_strain],
                _CURVATURE_CODES[m.curvature],
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
        centre = _vector2(position, name="position")
        v = _vector2(velocity, name="velocity")
        w = float(angular_velocity)
        half = 0.5 * self.mesh.length
        t = np.array([math.cos(angle), math.sin(angle)])
        start = centre - half * t
        e = self.mesh.straight_coordinates(start, angle)
        # velocity of the start node: v + ω k × (start − centre)
        v_start = v + w * np.array([half * t[1], -half * t[0]])
        return e, self.mesh.rigid_velocities(e, velocity=v_start, angular_velocity=w)
