"""ANCF beam element: mass, loads, elastic forces and their analytic Jacobian."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from mechanism.core.bodies import _ancf_kernels as kernels
from tests.mechanism.ancf_meshes import LAWS, central_difference
from tests.mechanism.ancf_meshes import ancf_mesh as _mesh
from tests.mechanism.ancf_meshes import deformed as _deformed


def _hermite_mass(l: float) -> np.ndarray:
    # paper-model §2.2, m̄ written out independently of the kernel
    return np.array(
        [
            [13 / 35, 11 * l / 210, 9 / 70, -13 * l / 420],
            [11 * l / 210, l**2 / 105, 13 * l / 420, -(l**2) / 140],
            [9 / 70, 13 * l / 420, 13 / 35, -11 * l / 210],
            [-13 * l / 420, -(l**2) / 140, -11 * l / 210, l**2 / 105],
        ]
    )


def test_element_mass_matrix_is_rho_a_l_mbar_kron_identity() -> None:
    mesh = _mesh(1)
    l = mesh.element_length
    expected = mesh.mass_per_length * l * np.kron(_hermite_mass(l), np.eye(2))
    assert_allclose(mesh.mass_matrix(), expected, rtol=1e-14, atol=0.0)


def test_assembled_mass_carries_the_beam_mass_and_is_positive_definite() -> None:
    mesh = _mesh(5)
    mass = mesh.mass_matrix()
    # a rigid translation of 1 m/s along x has momentum m: uᵀ M u with u = unit positions
    u = np.zeros(mesh.n_dofs)
    u[0::4] = 1.0
    assert u @ mass @ u == pytest.approx(mesh.mass, rel=1e-13)
    assert_allclose(mass, mass.T, rtol=0, atol=0)
    assert np.linalg.eigvalsh(mass).min() > 0.0


def test_gravity_force_matches_quadrature_and_total_weight() -> None:
    mesh = _mesh(4)
    g = (0.3, -9.81)
    q = mesh.gravity_force(g)
    u = np.zeros(mesh.n_dofs)
    u[1::4] = 1.0
    assert u @ q == pytest.approx(mesh.mass * g[1], rel=1e-13)
    # element vector ρA l [½, l/12, ½, −l/12] ⊗ g from paper-model §2.2
    l = mesh.element_length
    single = _mesh(1, length=l)
    expected = mesh.mass_per_length * l * np.kron([0.5, l / 12, 0.5, -l / 12], g)
    assert_allclose(single.gravity_force(g), expected, rtol=1e-14)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_no_elastic_force_in_rigid_placements(axial: str, curvature: str) -> None:
    mesh = _mesh(4, axial_strain=axial, curvature=curvature)
    for angle in (0.0, 1.1, -2.5):
        e = mesh.straight_coordinates((0.4, -1.0), angle=angle)
        force = mesh.elastic_force(e)
        assert np.abs(force).max() < 1e-6  # N, against EA = 2e8 N
        assert mesh.strain_energy(e) == pytest.approx(0.0, abs=1e-20)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_elastic_force_is_the_gradient_of_the_strain_energy(axial: str, curvature: str) -> None:
    mesh = _mesh(3, axial_strain=axial, curvature=curvature)
    e = _deformed(mesh, seed=1)
    force = mesh.elastic_force(e)
    numeric = central_difference(mesh.strain_energy, e, 1e-6)
    assert_allclose(force, numeric, rtol=0, atol=1e-7 * np.abs(force).max())


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_analytic_jacobian_matches_finite_differences(axial: str, curvature: str) -> None:
    mesh = _mesh(3, axial_strain=axial, curvature=curvature)
    e = _deformed(mesh, seed=2)
    jac = mesh.elastic_jacobian(e)
    numeric = central_difference(mesh.elastic_force, e, 1e-7)
    assert_allclose(jac, numeric, rtol=0, atol=1e-7 * np.abs(jac).max())
    assert_allclose(jac, jac.T, rtol=0, atol=1e-12 * np.abs(jac).max())


@pytest.mark.parametrize("curvature", ["material", "linear"])
@pytest.mark.parametrize(("gauss_axial", "gauss_bending"), [(1, 1), (2, 4), (4, 5)])
def test_jacobian_matches_finite_differences_for_every_gauss_rule(
    curvature: str, gauss_axial: int, gauss_bending: int
) -> None:
    # the quadrature loops index the Gauss table by rule and point; other rules than the
    # defaults and more elements than one shared node pattern exercise that indexing
    mesh = _mesh(5, curvature=curvature, gauss_axial=gauss_axial, gauss_bending=gauss_bending)
    e = _deformed(mesh, seed=14)
    jac = mesh.elastic_jacobian(e)
    numeric = central_difference(mesh.elastic_force, e, 1e-7)
    assert_allclose(jac, numeric, rtol=0, atol=1e-7 * np.abs(jac).max())


def test_linear_bending_stiffness_is_the_papers_constant_kt() -> None:
    mesh = _mesh(1, curvature="linear", area=1e-300)  # EA → 0 leaves only K_t
    l = mesh.element_length
    kt = (mesh.bending_stiffness / l**3) * np.array(
        [
            [12, 6 * l, -12, 6 * l],
            [6 * l, 4 * l**2, -6 * l, 2 * l**2],
            [-12, -6 * l, 12, -6 * l],
            [6 * l, 2 * l**2, -6 * l, 4 * l**2],
        ]
    )
    for e in (mesh.straight_coordinates(), _deformed(mesh, seed=3)):
        expected = np.kron(kt, np.eye(2))
        assert_allclose(mesh.elastic_jacobian(e), expected, rtol=0, atol=1e-13 * kt.max())


@pytest.mark.parametrize("curvature", ["material", "geometric"])
def test_reference_tangent_is_bar_plus_euler_bernoulli_stiffness(curvature: str) -> None:
    # at the straight unstressed state along x: axial bar stiffness on x, K_t on y
    mesh = _mesh(1, curvature=curvature)
    l = mesh.element_length
    bar = (mesh.axial_stiffness / (30 * l)) * np.array(
        [
            [36, 3 * l, -36, 3 * l],
            [3 * l, 4 * l**2, -3 * l, -(l**2)],
            [-36, -3 * l, 36, -3 * l],
            [3 * l, -(l**2), -3 * l, 4 * l**2],
        ]
    )
    kt = (mesh.bending_stiffness / l**3) * np.array(
        [
            [12, 6 * l, -12, 6 * l],
            [6 * l, 4 * l**2, -6 * l, 2 * l**2],
            [-12, -6 * l, 12, -6 * l],
            [6 * l, 2 * l**2, -6 * l, 4 * l**2],
        ]
    )
    expected = np.kron(bar, np.diag([1.0, 0.0])) + np.kron(kt, np.diag([0.0, 1.0]))
    jac = mesh.elastic_jacobian(mesh.straight_coordinates())
    assert_allclose(jac, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_uniform_stretch_gives_the_chosen_axial_strain_and_force() -> None:
    stretch = 1e-3
    for axial, strain in (("biot", stretch), ("green", stretch + 0.5 * stretch**2)):
        mesh = _mesh(4, axial_strain=axial)
        e = mesh.straight_coordinates() * (1.0 + stretch)
        assert_allclose(mesh.axial_strain_at(e), strain, rtol=1e-10)
        # end-node axial force = EA ε ∂ε/∂λ: N for Biot, N λ for Green (∂ε/∂λ = λ)
        factor = 1.0 if axial == "biot" else 1.0 + stretch
        force = mesh.elastic_force(e)
        assert force[-4] == pytest.approx(mesh.axial_stiffness * strain * factor, rel=1e-9)
        assert force[0] == pytest.approx(-mesh.axial_stiffness * strain * factor, rel=1e-9)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_structural_damping_force_and_its_velocity_jacobian(axial: str, curvature: str) -> None:
    mesh = _mesh(3, axial_strain=axial, curvature=curvature, damping=2e-5)
    e = _deformed(mesh, seed=4)
    e_dot = np.random.default_rng(5).standard_normal(mesh.n_dofs)
    cd = mesh.damping_jacobian(e)
    assert_allclose(mesh.damping_force(e, e_dot), cd @ e_dot, rtol=1e-12, atol=0)
    assert_allclose(cd, cd.T, rtol=0, atol=1e-12 * np.abs(cd).max())
    assert np.linalg.eigvalsh(cd).min() > -1e-9 * np.abs(cd).max()
    # at the unstressed state β K_m equals β times the tangent stiffness
    e0 = mesh.straight_coordinates(angle=0.7)
    assert_allclose(
        mesh.damping_jacobian(e0),
        mesh.damping * mesh.elastic_jacobian(e0),
        rtol=0,
        atol=1e-9 * mesh.damping * np.abs(mesh.elastic_jacobian(e0)).max(),
    )


@pytest.mark.parametrize("curvature", ["material", "geometric"])
def test_structural_damping_vanishes_under_rigid_motion(curvature: str) -> None:
    mesh = _mesh(4, curvature=curvature, damping=1e-4)
    e = _deformed(mesh, seed=6)
    e_dot = mesh.rigid_velocities(e, velocity=(0.3, -2.0), angular_velocity=15.7)
    force = mesh.damping_force(e, e_dot)
    scale = np.abs(mesh.damping_force(e, np.ones(mesh.n_dofs))).max()
    assert np.abs(force).max() < 1e-10 * scale


def test_kernels_add_scaled_into_an_offset_block() -> None:
    mesh = _mesh(2)
    e = _deformed(mesh, seed=7)
    params = mesh.kernel_parameters
    n, offset, scale = mesh.n_dofs, 5, -2.5
    vec = np.ones(n + 9)
    mat = np.ones((n + 9, n + 9))
    kernels.beam_elastic_force(e, *params, scale, vec, offset, kernels.beam_work(params[0]))
    kernels.beam_elastic_jacobian(e, *params, scale, mat, offset)
    assert_allclose(vec[offset : offset + n], 1.0 + scale * mesh.elastic_force(e), rtol=1e-14)
    assert_allclose(
        mat[offset : offset + n, offset : offset + n],
        1.0 + scale * mesh.elastic_jacobian(e),
        rtol=1e-14,
    )
    untouched = np.ones(n + 9, bool)
    untouched[offset : offset + n] = False
    assert (vec[untouched] == 1.0).all()
    assert (mat[untouched] == 1.0).all() and (mat[:, untouched] == 1.0).all()


def test_damping_kernels_add_scaled_into_an_offset_block() -> None:
    mesh = _mesh(2, damping=3e-5)
    e = _deformed(mesh, seed=15)
    e_dot = np.random.default_rng(16).standard_normal(mesh.n_dofs)
    params = mesh.kernel_parameters
    n, offset, scale = mesh.n_dofs, 4, 0.75
    vec = np.full(n + 6, 2.0)
    mat = np.full((n + 6, n + 6), 2.0)
    kernels.beam_damping_force(e, e_dot, *params, mesh.damping, scale, vec, offset)
    kernels.beam_damping_jacobian(e, *params, mesh.damping, scale, mat, offset)
    block = slice(offset, offset + n)
    assert_allclose(vec[block], 2.0 + scale * mesh.damping_force(e, e_dot), rtol=1e-14)
    assert_allclose(mat[block, block], 2.0 + scale * mesh.damping_jacobian(e), rtol=1e-14)
    untouched = np.ones(n + 6, bool)
    untouched[block] = False
    assert (vec[untouched] == 2.0).all()
    assert (mat[untouched] == 2.0).all() and (mat[:, untouched] == 2.0).all()
    # the energy kernel reads the same parameters and returns a number
    assert kernels.beam_strain_energy(e, *params) == pytest.approx(mesh.strain_energy(e))


def test_position_point_force_and_midspan_deflection() -> None:
    mesh = _mesh(4, length=2.0)
    e = mesh.straight_coordinates((1.0, 2.0), angle=math.pi / 2)
    assert_allclose(mesh.position(e, 1.3), [1.0, 3.3], atol=1e-15)
    # a point force at a node loads only that node's position DOFs
    q = mesh.point_force(1.0, (3.0, -4.0))
    expected = np.zeros(mesh.n_dofs)
    expected[mesh.node_dofs(2)[:2]] = (3.0, -4.0)
    assert_allclose(q, expected, atol=1e-14)
    # virtual work of a point force between nodes equals f · δr(s)
    s = 0.37
    q = mesh.point_force(s, (1.5, 0.5))
    d = np.random.default_rng(8).standard_normal(mesh.n_dofs)
    assert q @ d == pytest.approx(np.dot((1.5, 0.5), mesh.position(d, s)), rel=1e-12)
    # beam along +y: moving the middle node to −x is a deflection to the chord's left
    e[mesh.node_dofs(2)[0]] -= 0.01
    assert mesh.midspan_deflection(e) == pytest.approx(0.01, rel=1e-12)


def test_rigid_velocities_are_a_rigid_motion() -> None:
    mesh = _mesh(3)
    e = mesh.straight_coordinates((0.2, 0.1), angle=0.3)
    e_dot = mesh.rigid_velocities(e, velocity=(1.0, 2.0), angular_velocity=3.0)
    dt = 1e-7
    # a rotation about node 1 plus translation keeps every strain zero to first order
    assert np.abs(mesh.axial_strain_at(e + dt * e_dot)).max() < 1e-12
    assert_allclose(e_dot[0:2], (1.0, 2.0))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"n_elements": 0}, "n_elements"),
        ({"length": -1.0}, "length"),
        ({"damping": -1.0}, "damping"),
        ({"curvature": "cubic"}, "curvature"),
        ({"axial_strain": "log"}, "axial_strain"),
        ({"gauss_axial": 6}, "gauss_axial"),
    ],
)
def test_invalid_parameters_are_named(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        _mesh(**kwargs)


def test_wrong_vector_length_is_reported() -> None:
    mesh = _mesh(2)
    with pytest.raises(ValueError, match="length 12"):
        mesh.elastic_force(np.zeros(8))
    with pytest.raises(ValueError, match="s must be in"):
        mesh.position(mesh.straight_coordinates(), 2.0)


# --- helpers for the multibody core -----------------------------------------------------------
def _scene_beam(**kw):
    from mechanism.core.scene import AncfBeam

    base = dict(
        length=0.584,
        elements=4,
        area=1e-3,
        second_moment=3.33e-8,
        youngs_modulus=207e9,
        density=7800.0,
        start=(0.35, 0.06),
        end=(0.35 - 0.584 * math.cos(1.0), 0.06 + 0.584 * math.sin(1.0)),
    )
    base.update(kw)
    return AncfBeam(**base)


def test_beam_tables_add_elastic_and_damping_forces_of_several_beams() -> None:
    from mechanism.core.bodies import AncfLayout

    layouts = [
        AncfLayout(name="rod3", beam=_scene_beam(damping=1e-5)),
        AncfLayout(name="rod4", beam=_scene_beam(elements=3, length=0.45), curvature="linear"),
    ]
    offsets = [3, 3 + layouts[0].n_dof]
    n = offsets[1] + layouts[1].n_dof + 2
    rows = [lay.beam_row(o) for lay, o in zip(layouts, offsets, strict=True)]
    beam_i = np.array([r[0] for r in rows], dtype=np.int64)
    beam_f = np.array([r[1] for r in rows], dtype=np.float64)
    assert beam_i.shape[1] == kernels.BEAM_I_COLUMNS and beam_f.shape[1] == kernels.BEAM_F_COLUMNS
    rng = np.random.default_rng(9)
    q = rng.standard_normal(n)
    v = rng.standard_normal(n)
    for lay, o in zip(layouts, offsets, strict=True):
        q[o : o + lay.n_dof] = _deformed(lay.mesh, seed=o)
    gen = np.zeros(n)
    kernels.beams_force_add(beam_i, beam_f, q, v, -1.0, gen, kernels.beam_work(beam_i))
    jac = np.zeros((n, n))
    kernels.beams_jacobian_add(beam_i, beam_f, q, 0.25, 0.5, jac)
    expected = np.zeros(n)
    expected_jac = np.zeros((n, n))
    for lay, o in zip(layouts, offsets, strict=True):
        sl = slice(o, o + lay.n_dof)
        m = lay.mesh
        expected[sl] = -(m.elastic_force(q[sl]) + m.damping_force(q[sl], v[sl]))
        expected_jac[sl, sl] = 0.25 * m.elastic_jacobian(q[sl]) + 0.5 * m.damping_jacobian(q[sl])
    assert_allclose(gen, expected, rtol=1e-13, atol=0)
    assert_allclose(jac, expected_jac, rtol=1e-13, atol=0)


def test_layout_points_and_rigid_state_match_the_rigid_bar() -> None:
    from mechanism.core.bodies import AncfLayout, rigid_bar_from_beam
    from mechanism.core.joints import ANGLE_SLOPE, POINT_LINEAR

    def point_position(q, pt_i, pt_f, k):
        # the documented POINT_LINEAR rule: r = Σ w_j (q[d_j], q[d_j + 1]) over d_j ≥ 0
        assert pt_i[k, 0] == POINT_LINEAR
        d = [(pt_i[k, 4 + j], pt_f[k, 2 + j]) for j in range(4) if pt_i[k, 4 + j] >= 0]
        return sum(w * q[i : i + 2] for i, w in d)

    def point_angle(q, pt_i, k):
        assert pt_i[k, 2] == ANGLE_SLOPE
        s = pt_i[k, 3]
        return math.atan2(q[s + 1], q[s])

    def point_angle_rate(q, v, pt_i, k):
        s = pt_i[k, 3]
        return (q[s] * v[s + 1] - q[s + 1] * v[s]) / (q[s] ** 2 + q[s + 1] ** 2)

    beam = _scene_beam(mass=5.0)
    lay = AncfLayout(name="rod3", beam=beam)
    assert lay.mesh.mass == pytest.approx(5.0, rel=1e-14)
    assert len(lay.coordinate_names) == lay.n_dof == 20
    e0 = lay.initial_coordinates()
    assert_allclose(e0[0:2], beam.start, atol=1e-15)
    assert_allclose(e0[-4:-2], beam.end, atol=1e-12)
    bar = rigid_bar_from_beam(beam)
    e, e_dot = lay.from_rigid_state(bar.position, bar.angle, (0.3, -0.2), 4.0)
    assert_allclose(e, e0, atol=1e-12)
    assert np.abs(lay.mesh.elastic_force(e)).max() < 1e-6
    offset = 7
    q = np.zeros(offset + lay.n_dof + 1)
    v = np.zeros_like(q)
    q[offset : offset + lay.n_dof] = e
    v[offset : offset + lay.n_dof] = e_dot
    rows = [lay.point_row(p, offset) for p in ("start", "end")]
    pt_i = np.array([r[0] for r in rows], dtype=np.int64)
    pt_f = np.array([r[1] for r in rows], dtype=np.float64)
    half = 0.5 * beam.length * np.array([math.cos(bar.angle), math.sin(bar.angle)])
    for k, sign in ((0, -1.0), (1, 1.0)):
        assert_allclose(point_position(q, pt_i, pt_f, k), bar.position + sign * half, atol=1e-12)
        assert point_angle(q, pt_i, k) == pytest.approx(bar.angle, abs=1e-14)
        assert point_angle_rate(q, v, pt_i, k) == pytest.approx(4.0, rel=1e-14)
    # the centre moves with the prescribed velocity
    mid = lay.mesh.position(e_dot, 0.5 * beam.length)
    assert_allclose(mid, (0.3, -0.2), atol=1e-14)
    with pytest.raises(KeyError):
        lay.point_row("middle", 0)


def test_histories_sine_modes_and_midspan_deflection() -> None:
    mesh = _mesh(8, length=0.3)
    straight = mesh.straight_coordinates((0.1, 0.2), angle=0.5)
    a = 1e-3
    bent = straight + mesh.sine_modes([a, 2e-4], angle=0.5)
    # sin(πs/L) = 1 at mid-span, sin(2πs/L) = 0: deflection a to the left of the chord
    assert mesh.midspan_deflection(bent) == pytest.approx(a, rel=1e-12)
    history = np.stack([straight, bent, straight + mesh.sine_modes([-a], angle=0.5)])
    padded = np.hstack([np.zeros((3, 2)), history, np.zeros((3, 1))])
    assert_allclose(mesh.midspan_deflection_history(padded, offset=2), [0.0, a, -a], atol=1e-15)
    strains = mesh.axial_strain_history(padded, [0.0, 0.15, 0.3], offset=2)
    assert strains.shape == (3, 3)
    assert_allclose(strains[0], 0.0, atol=1e-15)
    assert_allclose(strains[1], mesh.axial_strain_at(bent, [0.0, 0.15, 0.3]), rtol=1e-14)
    # the interpolated transverse field matches the sine between nodes to cubic accuracy
    s = 0.37 * mesh.length
    normal = np.array([-math.sin(0.5), math.cos(0.5)])
    w = (mesh.position(bent, s) - mesh.position(straight, s)) @ normal
    exact = a * math.sin(math.pi * s / mesh.length) + 2e-4 * math.sin(2 * math.pi * s / mesh.length)
    assert w == pytest.approx(exact, rel=1e-4)
