"""Analyses of one ANCF beam: static equilibrium by Newton's method, the linearised
eigenmodes and the Euler–Bernoulli reference frequencies they are checked against."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import scipy.linalg
import xarray as xr

from chaoskit.contract import check_choice, check_int, check_positive

from . import _ancf_kernels as _k
from ._ancf_mesh import AncfMesh

__all__ = [
    "BeamModes",
    "BeamStaticSolution",
    "beam_modes",
    "euler_bernoulli_frequencies",
    "solve_beam_static",
]

Support = Literal["clamped-free", "pinned-pinned"]


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
    work = _k.beam_work(mesh.n_elements)
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
            _k.beam_elastic_force(e, *params, 1.0, force, 0, work)
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
