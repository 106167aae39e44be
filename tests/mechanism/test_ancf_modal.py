"""S5: linearised eigenfrequencies of ANCF beams, and the stiff modes of the paper's rods.

Clamped–free beam of S4 (validation-targets.md S5): Euler–Bernoulli 20.8045, 130.3798,
365.0673 Hz; first axial mode 643.94 Hz; relative errors ≈ 2e-6 / 8e-5 / 6e-4 at 8 elements
and ≈ 1e-7 / 5e-6 / 4e-5 at 16 (h⁴). Rods 3 and 4 of the paper (paper-model.md §2.2),
pinned–pinned: first bending ≈ 137 / 231 Hz, first axial ≈ 4.4 / 5.7 kHz.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from mechanism.core import AncfMesh, beam_modes, euler_bernoulli_frequencies

BENDING = np.array([20.8045, 130.3798, 365.0673])  # Hz
AXIAL = 643.94  # Hz
TABLE_ERRORS = {8: np.array([2e-6, 8e-5, 6e-4]), 16: np.array([1e-7, 5e-6, 4e-5])}
CLAMP = [0, 1, 3]  # position and slope direction; root stretch free


def _cantilever(n_elements: int, **kw) -> AncfMesh:
    return AncfMesh(
        length=2.0,
        n_elements=n_elements,
        area=0.01,
        second_moment=0.1**4 / 12,
        youngs_modulus=2.07e11,
        density=7800.0,
        **kw,
    )


def _rod(length: float, n_elements: int, **kw) -> AncfMesh:
    return AncfMesh(
        length=length,
        n_elements=n_elements,
        area=1e-3,
        second_moment=3.33e-8,
        youngs_modulus=207e9,
        density=7800.0,
        **kw,
    )


def test_analytic_reference_reproduces_the_table() -> None:
    bending, axial = euler_bernoulli_frequencies(_cantilever(1), support="clamped-free")
    assert_allclose(bending, BENDING, rtol=3e-6)
    assert axial[0] == pytest.approx(AXIAL, rel=1e-5)


@pytest.mark.parametrize("n_elements", [8, 16])
def test_clamped_free_bending_errors_follow_the_table(n_elements: int) -> None:
    mesh = _cantilever(n_elements)
    exact, _ = euler_bernoulli_frequencies(mesh, support="clamped-free")
    modes = beam_modes(mesh, fixed_dofs=CLAMP)
    rel = modes.bending_frequencies()[:3] / exact - 1.0
    assert (rel > 0).all()  # consistent mass and conforming shapes: upper bounds
    assert_allclose(rel, TABLE_ERRORS[n_elements], rtol=0.35)
    # against the table's frequencies, printed to 1e-4 Hz
    diff = np.abs(modes.bending_frequencies()[:3] - BENDING)
    assert (diff < 1.5 * TABLE_ERRORS[n_elements] * BENDING + 5e-5).all(), diff


def test_bending_errors_fall_as_h4() -> None:
    errors = []
    for n in (4, 8, 16):
        mesh = _cantilever(n)
        exact, _ = euler_bernoulli_frequencies(mesh, support="clamped-free")
        errors.append(beam_modes(mesh, fixed_dofs=CLAMP).bending_frequencies()[:3] / exact - 1)
    orders = np.log2(np.asarray(errors[:-1]) / np.asarray(errors[1:]))
    assert (orders > 3.6).all() and (orders < 4.2).all(), orders
    assert (orders[-1] > 3.9).all(), orders  # 8 → 16 elements: asymptotic


def test_first_axial_mode_of_the_cantilever() -> None:
    for n in (8, 16):
        modes = beam_modes(_cantilever(n), fixed_dofs=CLAMP)
        assert modes.axial_frequencies()[0] == pytest.approx(AXIAL, rel=1e-5)
        kinds = modes.kind
        assert set(kinds) == {"axial", "bending"}
        assert_allclose(modes.axial_fraction, np.round(modes.axial_fraction), atol=1e-9)


def test_full_slope_clamp_stiffens_the_axial_mode_by_first_order() -> None:
    # r_x,ₓ = 1 at the root forbids the root strain of the axial mode: error ∝ h
    err = [
        beam_modes(_cantilever(n), fixed_dofs=[0, 1, 2, 3]).axial_frequencies()[0] / AXIAL - 1
        for n in (8, 16)
    ]
    assert 0.01 < err[0] < 0.02 and err[0] / err[1] == pytest.approx(2.0, rel=0.05)


def test_linear_bending_law_shifts_the_axial_mode() -> None:
    # K_t also acts along the axis: the constant-K_t element is stiffer axially by ~EI/EA terms
    modes = beam_modes(_cantilever(16, curvature="linear"), fixed_dofs=CLAMP)
    assert modes.axial_frequencies()[0] / AXIAL - 1 == pytest.approx(2.5e-4, rel=0.05)
    assert_allclose(modes.bending_frequencies()[:3], BENDING, rtol=5e-5)


@pytest.mark.parametrize(
    ("length", "bending", "axial"),
    [(0.584, 136.916, 4410.57), (0.45, 230.598, 5723.94)],  # rods 3 and 4
)
def test_pinned_pinned_rods_of_the_paper(length: float, bending: float, axial: float) -> None:
    exact_b, exact_a = euler_bernoulli_frequencies(_rod(length, 1), support="pinned-pinned")
    assert exact_b[0] == pytest.approx(bending, rel=1e-5)
    assert exact_a[0] == pytest.approx(axial, rel=1e-5)
    for n, tol_b in ((4, 3e-4), (8, 2e-5), (16, 1.5e-6), (24, 3e-7)):
        mesh = _rod(length, n)
        ends = [0, 1, mesh.n_dofs - 4, mesh.n_dofs - 3]
        modes = beam_modes(mesh, fixed_dofs=ends)
        assert modes.bending_frequencies()[0] == pytest.approx(exact_b[0], rel=tol_b)
        assert modes.axial_frequencies()[0] == pytest.approx(exact_a[0], rel=1e-5)


def test_highest_mesh_frequencies_grow_as_h2_bending_and_h1_axial() -> None:
    # they set the explicit step limit 2/ω_max; docs/ancf.md tabulates them
    top_b, top_a = [], []
    for n in (8, 16):
        mesh = _rod(0.584, n)
        modes = beam_modes(mesh, fixed_dofs=[0, 1, mesh.n_dofs - 4, mesh.n_dofs - 3])
        top_b.append(modes.bending_frequencies().max())
        top_a.append(modes.axial_frequencies().max())
    assert 1.0e5 < max(top_b[1], top_a[1]) < 2.0e5  # Hz at 16 elements
    assert top_b[1] / top_b[0] == pytest.approx(4.0, rel=0.02)
    assert top_a[1] / top_a[0] == pytest.approx(2.0, rel=0.02)


def test_modal_result_dataset_and_mass_normalisation() -> None:
    mesh = _cantilever(4)
    modes = beam_modes(mesh, fixed_dofs=CLAMP, n_modes=5)
    phi = modes.mode_shape
    assert_allclose(phi.T @ mesh.mass_matrix() @ phi, np.eye(5), atol=1e-10)
    ds = modes.to_dataset()
    assert ds.sizes["mode"] == 5
    for name in ("frequency", "axial_fraction", "kind", "mode_shape"):
        assert {"units", "long_name"} <= set(ds[name].attrs)
    omega2 = (2 * math.pi * modes.frequency) ** 2
    k = mesh.elastic_jacobian(mesh.straight_coordinates())
    assert_allclose(np.diag(phi.T @ k @ phi), omega2, rtol=1e-9)
