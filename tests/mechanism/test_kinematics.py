"""Constraint rows, point kinematics and clearance-joint kinematics against finite
differences of the positions (an independent check of every analytic derivative)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import mechanism
from mechanism.core.joints import _kernels as jk
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state
from tests.mechanism.scenes import rigid_paper, rotating_guide


def _phi(model, ws, t, q, v=None):
    k.evaluate_constraints(model.kernel, ws, t, q, np.zeros_like(q) if v is None else v)
    return ws.phi.copy(), ws.phiq.copy(), ws.phit.copy(), ws.gam.copy()


def _models():
    return {
        "rotating-guide": assemble(rotating_guide(clearance=False)),
        "paper": assemble(rigid_paper()),
        "slider-crank": assemble(mechanism.load_scene("slider-crank")),
    }


MODELS = _models()


@pytest.fixture(params=sorted(MODELS))
def model(request):
    return MODELS[request.param]


def _random_state(model, seed):
    rng = np.random.default_rng(seed)
    q = model.q_guess + rng.normal(scale=0.05, size=model.n_dof)
    v = rng.normal(scale=2.0, size=model.n_dof)
    a = rng.normal(scale=50.0, size=model.n_dof)
    return q, v, a


def test_jacobian_matches_central_differences(model) -> None:
    ws = model.workspace()
    q, _, _ = _random_state(model, 1)
    t = 0.137
    _, phiq, _, _ = _phi(model, ws, t, q)
    h = 1e-6
    fd = np.empty_like(phiq)
    for j in range(model.n_dof):
        dq = np.zeros_like(q)
        dq[j] = h
        fd[:, j] = (_phi(model, ws, t, q + dq)[0] - _phi(model, ws, t, q - dq)[0]) / (2 * h)
    assert_allclose(phiq, fd, rtol=1e-7, atol=1e-8)


def test_time_derivative_matches_central_differences(model) -> None:
    ws = model.workspace()
    q, _, _ = _random_state(model, 2)
    t = 0.211
    h = 1e-6
    _, _, phit, _ = _phi(model, ws, t, q)
    fd = (_phi(model, ws, t + h, q)[0] - _phi(model, ws, t - h, q)[0]) / (2 * h)
    assert_allclose(phit, fd, rtol=1e-6, atol=1e-6)


def test_gamma_is_the_velocity_dependent_part_of_the_second_derivative(model) -> None:
    """Along q(t) = q + v t + a t²/2: d²Φ/dt² = Φq a − γ (paper-model §2.3)."""
    ws = model.workspace()
    q, v, a = _random_state(model, 3)
    t0 = 0.05
    _, phiq, _, gam = _phi(model, ws, t0, q, v)
    h = 1e-4

    def phi_at(s):
        return _phi(model, ws, t0 + s, q + v * s + 0.5 * a * s * s)[0]

    second = (phi_at(h) - 2 * phi_at(0.0) + phi_at(-h)) / (h * h)
    assert_allclose(phiq @ a - gam, second, rtol=1e-5, atol=1e-3)


def test_initial_state_is_consistent(model) -> None:
    q0, v0 = initial_state(model)
    ws = model.workspace()
    phi, phiq, phit, _ = _phi(model, ws, 0.0, q0, v0)
    assert np.abs(phi).max() < 1e-10
    assert np.abs(phiq @ v0 + phit).max() < 1e-9 * max(1.0, np.abs(v0).max())


def test_profile_drive_reproduces_its_samples() -> None:
    scene = rotating_guide(clearance=False)
    model = assemble(scene)
    km = model.kernel
    drive = scene.drive
    for t, angle in zip(drive.time, drive.angle, strict=True):
        for turns in (0, 3):
            f, _, _ = jk.drive_angle(
                t + turns * drive.period, km.drive_i, km.drive_f, km.spline_x, km.spline_c
            )
            assert f == pytest.approx(angle + 2 * math.pi * turns, abs=1e-12)
    # derivatives of the spline against finite differences
    h = 1e-6
    for t in (0.013, 0.2, 0.49):
        _f0, df, ddf = jk.drive_angle(t, km.drive_i, km.drive_f, km.spline_x, km.spline_c)
        fp = jk.drive_angle(t + h, km.drive_i, km.drive_f, km.spline_x, km.spline_c)
        fm = jk.drive_angle(t - h, km.drive_i, km.drive_f, km.spline_x, km.spline_c)
        assert df == pytest.approx((fp[0] - fm[0]) / (2 * h), rel=1e-7)
        assert ddf == pytest.approx((fp[1] - fm[1]) / (2 * h), rel=1e-6, abs=1e-6)


# --- clearance joint -------------------------------------------------------------------


def _clearance_setup(seed):
    model = assemble(rotating_guide(clearance=True))
    km = model.kernel
    ws = model.workspace()
    q0, _v0 = initial_state(model)
    rng = np.random.default_rng(seed)
    # push the journal off-centre by more than the clearance and move every body
    q = q0 + rng.normal(scale=3e-4, size=q0.size)
    v = rng.normal(scale=0.5, size=q0.size)
    return model, km, ws, q, v


def _kin(km, ws, q, v):
    jk.update_points(q, v, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    b, j = km.cj_i[0, 0], km.cj_i[0, 1]
    rb, rj, c = km.cj_f[0, k.CF_RB], km.cj_f[0, k.CF_RJ], km.cj_f[0, k.CF_C]
    return jk.clearance_kinematics(ws.pcf, b, j, rb, rj, c), (b, j, rb, rj)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_clearance_rates_match_finite_differences(seed) -> None:
    model, km, ws, q, v = _clearance_setup(seed)
    (ex, ey, nx, ny, delta, ddot, vt, phib, phij), (b, j, rb, rj) = _kin(km, ws, q, v)
    assert delta == pytest.approx(math.hypot(ex, ey) - km.cj_f[0, k.CF_C], abs=1e-15)
    # material points of journal and bearing that sit at the contact point at t = 0
    jk.update_points(q, v, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    pj = ws.pcf[j, : jk.PC_Y + 1] + rj * np.array([nx, ny])
    pb = ws.pcf[b, : jk.PC_Y + 1] + rb * np.array([nx, ny])
    offs = model.body_offsets
    names = model.body_names
    link = offs[names.index("link")]
    tag = offs[names.index("tag")]

    def material(qq, p, base):
        th0 = q[base + 2]
        rel = p - q[base : base + 2]
        c, s = math.cos(qq[base + 2] - th0), math.sin(qq[base + 2] - th0)
        return qq[base : base + 2] + np.array([c * rel[0] - s * rel[1], s * rel[0] + c * rel[1]])

    h = 1e-7
    qp, qm = q + h * v, q - h * v
    rel_vel = (
        material(qp, pj, link)
        - material(qm, pj, link)
        - material(qp, pb, tag)
        + material(qm, pb, tag)
    ) / (2 * h)
    assert vt == pytest.approx(rel_vel @ np.array([-ny, nx]), rel=1e-6, abs=1e-9)
    assert ddot == pytest.approx(rel_vel @ np.array([nx, ny]), rel=1e-6, abs=1e-9)
    dp = _kin(km, ws, qp, v)[0][4]
    dm = _kin(km, ws, qm, v)[0][4]
    assert ddot == pytest.approx((dp - dm) / (2 * h), rel=1e-6, abs=1e-9)
    # contact angles in the frames of the bearing (tag) and journal (link) bodies
    phi = math.atan2(ny, nx)
    wrap = lambda a: math.atan2(math.sin(a), math.cos(a))  # noqa: E731
    assert phib == pytest.approx(wrap(phi - q[tag + 2]), abs=1e-12)
    assert phij == pytest.approx(wrap(phi - q[link + 2]), abs=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_contact_forces_do_the_work_of_the_contact_pair(seed) -> None:
    """Virtual power: Qᵀq̇ = f_j·(ṙ_j^Q − ṙ_b^Q) = −Fₙ δ̇ + F_t v_t, and the pair carries
    no net force (action = reaction)."""
    model, km, ws, q, v = _clearance_setup(seed)
    (_ex, _ey, nx, ny, _delta, ddot, vt, _, _), (b, j, rb, rj) = _kin(km, ws, q, v)
    fn, ft = 1234.5, -321.0
    gen = np.zeros(model.n_dof)
    jk.clearance_force_add(gen, ws.pci, ws.pcf, b, j, rb, rj, nx, ny, fn, ft)
    assert gen @ v == pytest.approx(-fn * ddot + ft * vt, rel=1e-12, abs=1e-9)
    offs = dict(zip(model.body_names, model.body_offsets, strict=True))
    fx = gen[offs["link"]] + gen[offs["tag"]]
    fy = gen[offs["link"] + 1] + gen[offs["tag"] + 1]
    assert abs(fx) < 1e-9 and abs(fy) < 1e-9


def test_slope_angle_points_have_consistent_derivatives() -> None:
    """The ANGLE_SLOPE branch (ANCF node frames): rate, Jacobian and quadratic term."""
    pt_i = np.array([[jk.POINT_LINEAR, -1, jk.ANGLE_SLOPE, 2, 0, -1, -1, -1]], dtype=np.int64)
    pt_f = np.array([[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]])
    pci = np.zeros((1, jk.PCI_COLUMNS), dtype=np.int64)
    pcf = np.zeros((1, jk.PCF_COLUMNS))
    q = np.array([0.3, -0.2, 0.8, 0.5])
    v = np.array([0.1, 0.4, -1.3, 2.2])
    a = np.array([1.0, -2.0, 3.0, 0.5])

    def angle(s):
        qq = q + v * s + 0.5 * a * s * s
        jk.update_points(qq, v + a * s, pt_i, pt_f, pci, pcf)
        return pcf[0, jk.PC_ANG]

    jk.update_points(q, v, pt_i, pt_f, pci, pcf)
    rate = pcf[0, jk.PC_RATE]
    acc = jk.angle_acceleration(a, pci, pcf, 0)
    h = 1e-5
    assert rate == pytest.approx((angle(h) - angle(-h)) / (2 * h), rel=1e-8)
    assert acc == pytest.approx((angle(h) - 2 * angle(0) + angle(-h)) / h**2, rel=1e-5)
    jk.update_points(q, v, pt_i, pt_f, pci, pcf)
    assert (pcf[0, jk.PC_X], pcf[0, jk.PC_Y]) == (0.3, -0.2)
    gen = np.zeros(4)
    jk.apply_point_force(gen, 2.0, 3.0, 0.7, pci, pcf, 0)
    # power of a force and a moment: f·ṙ + M θ̇
    assert gen @ v == pytest.approx(2.0 * 0.1 + 3.0 * 0.4 + 0.7 * rate, rel=1e-12)
