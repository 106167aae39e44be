"""ANCF beam kernels per right-hand-side evaluation.

The multibody core calls ``beams_force_add`` once per RHS and ``beams_jacobian_add`` once per
Newton matrix; these numbers bound the flexible-body share of the S6 (1 s simulated in ≤ 1 s)
and paper-scene (≤ 3 s per revolution) budgets. Run with
``python -m pytest benchmarks/test_ancf_kernels.py --benchmark-only``.
"""

from __future__ import annotations

import numpy as np
import pytest

from mechanism.core.bodies import AncfMesh, beam_modes, solve_beam_static
from mechanism.core.bodies import _ancf_kernels as kernels


def _rod(n_elements: int, **kw) -> AncfMesh:
    return AncfMesh(
        length=0.584,
        n_elements=n_elements,
        area=1e-3,
        second_moment=3.33e-8,
        youngs_modulus=207e9,
        density=7800.0,
        **kw,
    )


def _state(mesh: AncfMesh) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    e = mesh.straight_coordinates(angle=0.7) + 1e-4 * rng.standard_normal(mesh.n_dofs)
    return e, rng.standard_normal(mesh.n_dofs)


@pytest.mark.parametrize("curvature", ["material", "linear"])
@pytest.mark.parametrize("n_elements", [16])
def test_elastic_force(benchmark, n_elements: int, curvature: str) -> None:
    mesh = _rod(n_elements, curvature=curvature)
    e, _ = _state(mesh)
    out = np.zeros(mesh.n_dofs)
    args = (e, *mesh.kernel_parameters, 1.0, out, 0, kernels.beam_work(n_elements))
    kernels.beam_elastic_force(*args)  # JIT warm-up
    benchmark(kernels.beam_elastic_force, *args)


@pytest.mark.parametrize("n_elements", [16])
def test_elastic_jacobian(benchmark, n_elements: int) -> None:
    mesh = _rod(n_elements)
    e, _ = _state(mesh)
    out = np.zeros((mesh.n_dofs, mesh.n_dofs))
    args = (e, *mesh.kernel_parameters, 1.0, out, 0)
    kernels.beam_elastic_jacobian(*args)
    benchmark(kernels.beam_elastic_jacobian, *args)


@pytest.mark.parametrize("curvature", ["material", "linear"])
def test_damping_force(benchmark, curvature: str) -> None:
    mesh = _rod(16, curvature=curvature, damping=1e-6)
    e, e_dot = _state(mesh)
    out = np.zeros(mesh.n_dofs)
    args = (e, e_dot, *mesh.kernel_parameters, mesh.damping, 1.0, out, 0)
    kernels.beam_damping_force(*args)
    benchmark(kernels.beam_damping_force, *args)


def test_damping_jacobian(benchmark) -> None:
    mesh = _rod(16, damping=1e-6)
    e, _ = _state(mesh)
    out = np.zeros((mesh.n_dofs, mesh.n_dofs))
    args = (e, *mesh.kernel_parameters, mesh.damping, 1.0, out, 0)
    kernels.beam_damping_jacobian(*args)
    benchmark(kernels.beam_damping_jacobian, *args)


def test_strain_energy(benchmark) -> None:
    # evaluated once per output sample for the recorded mechanical energy
    mesh = _rod(16)
    e, _ = _state(mesh)
    args = (e, *mesh.kernel_parameters)
    kernels.beam_strain_energy(*args)
    benchmark(kernels.beam_strain_energy, *args)


def test_two_rods_force_with_damping(benchmark) -> None:
    # the paper scene: rods 3 and 4, 16 elements each, through the beam tables
    meshes = [_rod(16, damping=1e-6), _rod(16, damping=1e-6)]
    beam_i = np.array(
        [[o, 16, kernels.AXIAL_BIOT, kernels.BENDING_MATERIAL, 5, 3] for o in (9, 77)],
        dtype=np.int64,
    )
    beam_f = np.array(
        [[m.element_length, m.axial_stiffness, m.bending_stiffness, m.damping] for m in meshes]
    )
    q = np.zeros(145)
    v = np.zeros(145)
    for m, o in zip(meshes, (9, 77), strict=True):
        q[o : o + 68], v[o : o + 68] = _state(m)
    gen = np.zeros(145)
    work = kernels.beam_work(beam_i)
    kernels.beams_force_add(beam_i, beam_f, q, v, -1.0, gen, work)
    benchmark(kernels.beams_force_add, beam_i, beam_f, q, v, -1.0, gen, work)


def test_s4_static_cantilever_32_elements(benchmark) -> None:
    mesh = AncfMesh(
        length=2.0,
        n_elements=32,
        area=0.01,
        second_moment=0.1**4 / 12,
        youngs_modulus=2.07e11,
        density=7800.0,
    )
    load = mesh.point_force(2.0, (0.0, -3.0 * mesh.bending_stiffness / 4.0))
    solve_beam_static(mesh, load, fixed_dofs=[0, 1, 3])
    sol = benchmark(solve_beam_static, mesh, load, fixed_dofs=[0, 1, 3])
    assert sol.success


def test_s5_modes_16_elements(benchmark) -> None:
    mesh = _rod(16)
    beam_modes(mesh, fixed_dofs=[0, 1, 3])
    benchmark(beam_modes, mesh, fixed_dofs=[0, 1, 3])
