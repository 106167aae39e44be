"""ANCF strain energy: the kernel, analytic states, F_e = ∂U/∂e and the recorded energy."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import mechanism
import mechanism.core._simulate as simulate_module
from mechanism.core import AncfMesh
from mechanism.core.bodies import _ancf_kernels as kernels
from mechanism.core.integrate import GeneralizedAlpha
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state
from mechanism.core.scene import AncfBeam, Effects, RevoluteJoint, Scene, SolverSettings
from tests.mechanism.ancf_meshes import LAWS, central_difference
from tests.mechanism.ancf_meshes import ancf_mesh as _mesh
from tests.mechanism.ancf_meshes import deformed as _deformed


def _reference_strain_energy(mesh: AncfMesh, e: np.ndarray) -> float:
    # U = Σ_elements Σ_points w l (½EA ε² + ½EI κ²) written with numpy, independently of the
    # kernels: Hermite derivatives, Gauss rules from numpy.polynomial.legendre
    l = mesh.element_length
    xa, wa = np.polynomial.legendre.leggauss(mesh.gauss_axial)
    xb, wb = np.polynomial.legendre.leggauss(mesh.gauss_bending)

    def d1(x: float) -> np.ndarray:
        return np.array(
            [6 * x * (x - 1) / l, 1 - 4 * x + 3 * x * x, 6 * x * (1 - x) / l, x * (3 * x - 2)]
        )

    def d2(x: float) -> np.ndarray:
        return np.array(
            [(12 * x - 6) / l**2, (6 * x - 4) / l, (6 - 12 * x) / l**2, (6 * x - 2) / l]
        )

    energy = 0.0
    for i in range(mesh.n_elements):
        q = e[4 * i : 4 * i + 8].reshape(4, 2)
        for x, w in zip(0.5 * (xa + 1.0), 0.5 * wa, strict=True):
            rx = d1(x) @ q
            stretch = math.sqrt(rx @ rx)
            strain = 0.5 * (stretch**2 - 1.0) if mesh.axial_strain == "green" else stretch - 1.0
            energy += 0.5 * mesh.axial_stiffness * strain**2 * w * l
        for x, w in zip(0.5 * (xb + 1.0), 0.5 * wb, strict=True):
            rx = d1(x) @ q
            rxx = d2(x) @ q
            if mesh.curvature == "linear":
                k2 = rxx @ rxx
            else:
                power = 1.0 if mesh.curvature == "material" else 1.5
                k2 = ((rx[0] * rxx[1] - rx[1] * rxx[0]) / (rx @ rx) ** power) ** 2
            energy += 0.5 * mesh.bending_stiffness * k2 * w * l
    return energy


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
@pytest.mark.parametrize(("gauss_axial", "gauss_bending"), [(5, 3), (2, 4)])
def test_kernel_matches_an_independent_quadrature(
    axial: str, curvature: str, gauss_axial: int, gauss_bending: int
) -> None:
    mesh = _mesh(
        3,
        axial_strain=axial,
        curvature=curvature,
        gauss_axial=gauss_axial,
        gauss_bending=gauss_bending,
    )
    e = _deformed(mesh, seed=11)
    expected = _reference_strain_energy(mesh, e)
    assert expected > 0.0
    assert mesh.strain_energy(e) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_uniform_stretch_stores_half_ea_strain_squared_length(axial: str, curvature: str) -> None:
    # straight beam stretched by 1 + s: r,ₓ = (1 + s) t everywhere, r,ₓₓ = 0, so ε is the
    # same at every point and U = ½ EA ε² L exactly (ε = s for Biot, s + s²/2 for Green)
    stretch = 2e-3
    mesh = _mesh(4, axial_strain=axial, curvature=curvature)
    e = mesh.straight_coordinates((0.3, 0.1), angle=-0.8)
    e[0::4] = 0.3 + (e[0::4] - 0.3) * (1.0 + stretch)
    e[1::4] = 0.1 + (e[1::4] - 0.1) * (1.0 + stretch)
    e[2::4] *= 1.0 + stretch
    e[3::4] *= 1.0 + stretch
    strain = stretch if axial == "biot" else stretch + 0.5 * stretch**2
    expected = 0.5 * mesh.axial_stiffness * strain**2 * mesh.length
    assert mesh.strain_energy(e) == pytest.approx(expected, rel=1e-9)


def _arc(mesh: AncfMesh, curvature: float) -> np.ndarray:
    # nodes on a circle of radius 1/κ₀ at arc length s_j, unit tangent slopes: the centre
    # line is unstretched at the nodes and the beam is bent with κ = κ₀
    s = mesh.node_positions()
    radius = 1.0 / curvature
    nodes = np.empty((mesh.n_nodes, 4))
    nodes[:, 0] = radius * np.sin(s / radius)
    nodes[:, 1] = radius * (1.0 - np.cos(s / radius))
    nodes[:, 2] = np.cos(s / radius)
    nodes[:, 3] = np.sin(s / radius)
    return nodes.reshape(-1)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_circular_arc_stores_half_ei_curvature_squared_length(axial: str, curvature: str) -> None:
    # κ₀ L = 1.8 rad of arc. The cubic interpolation is not exactly circular between the
    # nodes; the relative error falls as h⁴: ≤ 1.1e-5 at 8 elements, ≤ 6.7e-7 at 16 (measured)
    kappa0 = 2.0
    errors = []
    for n_elements in (8, 16):
        mesh = _mesh(n_elements, axial_strain=axial, curvature=curvature)
        expected = 0.5 * mesh.bending_stiffness * kappa0**2 * mesh.length
        errors.append(abs(mesh.strain_energy(_arc(mesh, kappa0)) / expected - 1.0))
    assert errors[1] < 1e-6
    assert errors[0] / errors[1] > 10.0  # fourth-order convergence (16 in theory)


@pytest.mark.parametrize(("axial", "curvature"), LAWS)
def test_elastic_force_is_the_gradient_of_the_kernel_energy(axial: str, curvature: str) -> None:
    mesh = _mesh(4, axial_strain=axial, curvature=curvature)
    e = _deformed(mesh, seed=12, amplitude=0.05)
    force = mesh.elastic_force(e)
    numeric = central_difference(mesh.strain_energy, e, 1e-6)
    assert np.linalg.norm(force - numeric) < 1e-6 * np.linalg.norm(force)


# --- the energy of the multibody model ---------------------------------------------------------
def _beam(**kw) -> AncfBeam:
    base = dict(
        length=1.0,
        elements=4,
        area=1e-4,
        second_moment=1e-9,
        youngs_modulus=2e9,
        density=1000.0,
        start=(0.0, 0.0),
        end=(1.0, 0.0),
    )
    base.update(kw)
    return AncfBeam(**base)


def test_mechanical_energy_adds_every_beams_strain_energy() -> None:
    # two beams pinned end to end under gravity, in a stressed state: the kernel total must
    # be ½vᵀMv − Q_gᵀq + U₁ + U₂ with U from each beam's mesh
    scene = Scene(
        name="two-beams",
        ground_points={"O": (0.0, 0.0)},
        bodies={
            "a": _beam(),
            "b": _beam(elements=3, length=0.6, start=(1.0, 0.0), end=(1.6, 0.0)),
        },
        joints={
            "O": RevoluteJoint(bodies=("ground", "a"), points=("O", "start")),
            "A": RevoluteJoint(bodies=("a", "b"), points=("end", "start")),
        },
        effects=Effects(flexibility=True, clearance=False),
    )
    model = assemble(scene)
    q, v = initial_state(model)
    rng = np.random.default_rng(13)
    q = q + 1e-3 * rng.standard_normal(q.size)
    v = v + rng.standard_normal(v.size)
    strain = 0.0
    for name, layout in model.beams.items():
        o = model.body_offsets[model.body_names.index(name)]
        strain += layout.mesh.strain_energy(q[o : o + layout.n_dof])
    expected = 0.5 * v @ model.kernel.mass @ v - model.kernel.gravity_force @ q + strain
    assert strain > 1.0  # J: the strain term is not negligible in this check
    y = np.concatenate([q, v])
    energy = k.mechanical_energy(model.kernel, model.workspace(), y)
    assert energy == pytest.approx(expected, rel=1e-12)
    assert kernels.beams_strain_energy(
        model.kernel.beam_i, model.kernel.beam_f, q
    ) == pytest.approx(strain, rel=1e-14)
    series = np.empty(2)
    k.energy_series(model.kernel, model.workspace(), np.stack([q, q]), np.stack([v, v]), series)
    assert_allclose(series, energy, rtol=1e-14)


def test_free_beam_released_bent_conserves_the_recorded_energy(monkeypatch) -> None:
    # a free, undamped beam (no joints, no gravity) released at rest from a bent shape:
    # the recorded energy starts as pure strain energy and must stay constant while it
    # turns into kinetic energy and back. Generalized-α with ρ∞ = 1 (no numerical damping)
    # and h = 2e-5 s (ω_max h ≈ 0.4 for the highest axial mode of the mesh, ≈ 3 kHz)
    # held it to 1.6e-5 relative over 0.1 s (measured); tolerance 1e-4 over those 0.1 s,
    # 1.6 periods of the first free–free bending mode (15.9 Hz).
    scene = Scene(
        name="free-beam",
        bodies={"rod": _beam()},
        joints={},
        effects=Effects(flexibility=True, clearance=False, gravity=False),
        solver=SolverSettings(rtol=1e-8, atol=1e-10),
    )
    bent = (0.03, 0.01)  # m, amplitudes of sin(πs/L) and sin(2πs/L)
    straight_state = simulate_module.initial_state

    def released_bent(model, **kw):
        # scenes start beams straight; bend this one, at rest
        q, v = straight_state(model, **kw)
        layout = model.beams["rod"]
        o = model.body_offsets[model.body_names.index("rod")]
        q = q.copy()
        q[o : o + layout.n_dof] += layout.mesh.sine_modes(bent)
        return q, v

    monkeypatch.setattr(simulate_module, "initial_state", released_bent)
    ds = mechanism.simulate(
        scene, t_end=0.1, output_step=1e-3, method=GeneralizedAlpha(rho_inf=1.0, step=2e-5)
    )
    assert ds.attrs["solver_status"] == 0 and ds.attrs["solver_rejected_steps"] == 0
    energy = ds.mechanical_energy.values
    mesh = AncfMesh.from_scene(scene.bodies["rod"])
    u0 = mesh.strain_energy(mesh.straight_coordinates() + mesh.sine_modes(bent))
    assert energy[0] == pytest.approx(u0, rel=1e-12)
    assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-4
    # the beam really vibrates: its mid-span deflection changes sign
    w = ds.midspan_deflection.values[:, 0]
    assert w.max() > 0.01 and w.min() < -0.01
