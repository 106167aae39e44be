"""Analytic partials of the contact laws, and the clearance-force derivatives the
generalized-α Newton loop builds from them, against central differences: over a grid of
states away from the laws' kinks (relative agreement ≤ 1e-6), and the one-sided value
each kink takes."""

from __future__ import annotations

import numpy as np
import pytest

import mechanism
from mechanism.core.contact import (
    APPROACH_BOUNDED,
    APPROACH_RATIO,
    CONTACT_LAWS,
    FRICTION_LAWS,
    friction_force,
    friction_force_derivatives,
    normal_force,
    normal_force_derivatives,
)
from mechanism.core.integrate import _newton_kernels as nk
from mechanism.core.integrate._driver import initial_latch
from mechanism.core.integrate._methods import _contact_columns
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state

K = 1.31e10  # N m^-1.5, the paper scene's joint C
EXPONENT = 1.5
RESTITUTION = 0.9
MU, V0, V1 = 0.15, 1e-4, 2e-4


def _central(f, x, h):
    """Fourth-order central difference of the scalar function f at x with step h."""
    return (8.0 * (f(x + h) - f(x - h)) - (f(x + 2.0 * h) - f(x - 2.0 * h))) / (12.0 * h)


def _vary(fn, args, i):
    """fn of its argument ``i`` alone, the others held at ``args``."""

    def f(x):
        return fn(*args[:i], x, *args[i + 1 :])

    return f


def _close(a, b, rel=1e-6):
    assert abs(a - b) <= rel * max(abs(a), abs(b)), (a, b)


@pytest.mark.parametrize("bounded", [0, APPROACH_BOUNDED])
@pytest.mark.parametrize("law", sorted(CONTACT_LAWS))
def test_normal_force_partials_match_central_differences(law, bounded) -> None:
    code = CONTACT_LAWS[law] | bounded
    vimp = 0.05
    for delta in (1e-8, 3e-7, 2e-6, 1.5e-5):
        # compressing and restituting, inside and beyond the bounded rule's switch at 2·vimp
        for ddot in (-0.04, -1e-3, 0.0, 2e-3, 0.03, 0.08, 0.3):
            args = (code, K, EXPONENT, RESTITUTION)
            force, d_delta, d_ddot = normal_force_derivatives(*args, delta, ddot, vimp)
            assert force == normal_force(*args, delta, ddot, vimp)
            if force == 0.0:  # clamped: a contact does not pull
                assert (d_delta, d_ddot) == (0.0, 0.0)
                continue
            state = (*args, delta, ddot, vimp)
            _close(d_delta, _central(_vary(normal_force, state, 4), delta, 1e-4 * delta))
            if abs(abs(ddot) - APPROACH_RATIO * vimp) < 1e-3:
                continue  # next to the bounded rule's kink
            expected = _central(_vary(normal_force, state, 5), ddot, 1e-5)
            assert abs(d_ddot - expected) <= 1e-6 * max(abs(d_ddot), force / 0.3), (law, ddot)


def test_normal_force_partials_at_the_kinks() -> None:
    """The one-sided values: δ ≤ 0 gives zeros, and with n = 1.5 the right-hand limit of
    ∂F/∂δ = nKδ^0.5 goes to 0 as well; where the force is clamped at 0 the partials are
    0; the bounded approach speed switches at δ̇ = 2·vimp, where the latched branch
    (∂F/∂δ̇ = χ̂Kδⁿ/vimp) holds and just above it ∂F/∂δ̇ = 0."""
    law = CONTACT_LAWS["lankarani-nikravesh"]
    args = (law, K, EXPONENT, RESTITUTION)
    assert normal_force_derivatives(*args, 0.0, 0.1, 0.05) == (0.0, 0.0, 0.0)
    assert normal_force_derivatives(*args, -1e-6, 0.1, 0.05) == (0.0, 0.0, 0.0)
    _, d_delta, _ = normal_force_derivatives(*args, 1e-16, 0.0, 0.05)
    assert d_delta == pytest.approx(1.5 * K * 1e-8, rel=1e-12)  # → 0 with δ
    chi = 0.75 * (1.0 - RESTITUTION**2)
    clamp = -0.05 / chi  # F = Kδⁿ(1 + χ̂δ̇/vimp) = 0 here; clamped just beyond
    assert normal_force_derivatives(*args, 1e-6, clamp * (1 + 1e-9), 0.05) == (0.0, 0.0, 0.0)
    bounded = (law | APPROACH_BOUNDED, K, EXPONENT, RESTITUTION)
    edge = APPROACH_RATIO * 0.05
    force, _, d_ddot = normal_force_derivatives(*bounded, 1e-6, edge, 0.05)
    assert d_ddot == pytest.approx(chi * K * 1e-9 / 0.05, rel=1e-12)
    assert force == pytest.approx(K * 1e-9 * (1.0 + 2.0 * chi), rel=1e-12)
    assert normal_force_derivatives(*bounded, 1e-6, edge * (1 + 1e-12), 0.05)[2] == 0.0


@pytest.mark.parametrize("law", ["coulomb", "ambrosio"])
def test_friction_partials_match_central_differences(law) -> None:
    code = FRICTION_LAWS[law]
    fn = 250.0
    speeds = (3e-5, 1.2e-4, 1.5e-4, 1.9e-4, 5e-4, 0.02)
    for vt in (*speeds, *(-s for s in speeds)):
        if law == "ambrosio" and abs(vt) < V0:
            continue  # the dead zone: checked at the kinks
        ft, d_fn, d_vt = friction_force_derivatives(code, MU, V0, V1, fn, vt)
        assert ft == friction_force(code, MU, V0, V1, fn, vt)
        state = (code, MU, V0, V1, fn, vt)
        _close(d_fn, _central(_vary(friction_force, state, 4), fn, 1e-3))
        expected = _central(_vary(friction_force, state, 5), vt, 1e-9)
        assert abs(d_vt - expected) <= 1e-6 * MU * fn / V0, (law, vt)


def test_friction_partials_at_the_kinks() -> None:
    """Ambrósio's ramp has its slope −μFₙ/(v1 − v0) only strictly inside (v0, v1): at
    |v_t| = v0, |v_t| = v1 and in the dead zone ∂F_t/∂v_t = 0, and at v_t = 0 every partial
    is 0; no normal force, no friction (zeros); Coulomb at v_t = 0 has the slope −μFₙ/v0."""
    amb = FRICTION_LAWS["ambrosio"]
    fn = 250.0
    for vt in (V0, -V0, V1, -V1, 0.5 * V0, 0.0):
        assert friction_force_derivatives(amb, MU, V0, V1, fn, vt)[2] == 0.0
    assert friction_force_derivatives(amb, MU, V0, V1, fn, 0.0) == (0.0, 0.0, 0.0)
    _, d_fn, d_vt = friction_force_derivatives(amb, MU, V0, V1, fn, V0 * (1.0 + 1e-9))
    assert d_vt == pytest.approx(-MU * fn / (V1 - V0), rel=1e-12)
    assert d_fn == pytest.approx(-MU * 1e-9, rel=1e-6)  # c_d = 1e-9 just inside
    assert friction_force_derivatives(amb, MU, V0, V1, 0.0, 1.5e-4) == (0.0, 0.0, 0.0)
    coul = FRICTION_LAWS["coulomb"]
    assert friction_force_derivatives(coul, MU, V0, V1, fn, 0.0) == (
        0.0, 0.0, pytest.approx(-MU * fn / V0, rel=1e-15)
    )  # fmt: skip


def _model(flexible: bool):
    scene = mechanism.load_scene("paper")
    if not flexible:
        scene = scene.replace({"effects.flexibility": False})
    model = assemble(scene)
    q, v = initial_state(model)
    return model, q, v


@pytest.fixture(scope="module", params=[True, False], ids=["ancf-journal", "rigid-journal"])
def paper(request):
    return _model(request.param)


def _place(model, q, v, depth, angle, ddot, vt):
    """(q, v, vimp) with joint C's journal ``depth`` into its bearing at ``angle``, moving
    in at ``ddot`` and sliding at ``vt``: the journal point's first two coordinates are its
    position (an ANCF node's, or the rod's reference point)."""
    km = model.kernel
    ws = model.workspace()
    cc = _contact_columns(model)
    q, v = q.copy(), v.copy()
    acc = np.empty_like(q)
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    vimp, _ = initial_latch(model, np.concatenate([q, v]))
    vimp[:] = 0.05
    radius = km.cj_f[0, k.CF_C] + depth
    n = np.array([np.cos(angle), np.sin(angle)])
    for _ in range(3):  # the rod's reference point and angle set the journal's motion
        k.accelerations(km, ws, 0.0, q, v, vimp, acc, counters)
        e = ws.cj[0, [k.CJ_EX, k.CJ_EY]]
        q[cc[:2]] += radius * n - e
        k.accelerations(km, ws, 0.0, q, v, vimp, acc, counters)
        t = np.array([-n[1], n[0]])
        v[cc[:2]] += (ddot - ws.cj[0, k.CJ_DELTA_DOT]) * n + (vt - ws.cj[0, k.CJ_VT]) * t
    k.accelerations(km, ws, 0.0, q, v, vimp, acc, counters)
    assert ws.cj[0, k.CJ_DELTA] == pytest.approx(depth, rel=1e-6)
    assert ws.cj[0, k.CJ_VT] == pytest.approx(vt, rel=1e-6)
    return ws, q, v, vimp


def _force(model, cs, q, v, vimp, cc):
    """(Q_cc, v_t of joint C) of the clearance forces alone at (q, q̇)."""
    g = np.zeros(q.size)
    cj = cs[3].copy()
    nk._contact_force(model.kernel, q, v, vimp, cs[0], cs[1], cs[2], g, cj, cs[5])
    return g[cc], cj[0, k.CJ_VT]


def _force_at(model, cs, q, v, vimp, cc, x, j, value):
    """Q_cc with x[j] (x: q or q̇) set to ``value``."""
    keep = x[j]
    x[j] = value
    out = _force(model, cs, q, v, vimp, cc)[0]
    x[j] = keep
    return out


@pytest.mark.parametrize(
    "vt", [0.5 * V0, 1.5e-4, -1.7e-4, 0.03], ids=["dead-zone", "ramp", "ramp-neg", "sliding"]
)
def test_clearance_force_derivatives_match_central_differences(paper, vt) -> None:
    """The Newton loop's ∂Q/∂q, ∂Q/∂q̇ and ∂v_t/∂q̇ on joint C's columns (an ANCF node
    with its slope angle, or a rigid rod's x, y, θ), from one law evaluation, against
    central differences of the contact forces; relative to each matrix's largest entry."""
    model, q0, v0 = paper
    km = model.kernel
    cc = _contact_columns(model)
    nc = cc.size
    for depth, angle, ddot in ((2e-6, 0.7, 1e-3), (1e-5, -2.4, -4e-3)):
        ws, q, v, vimp = _place(model, q0, v0, depth, angle, ddot, vt)
        cs = nk.contact_scratch(km, ws)
        assert cs[-1]  # a dry, unworn journal: the analytic path
        dq, dv, gt = np.zeros((nc, nc)), np.zeros((nc, nc)), np.zeros((1, nc))
        assert nk.contact_derivatives(km, ws, q, v, vimp, cc, dq, dv, gt, cs)
        cq, cv, cg = np.zeros((nc, nc)), np.zeros((nc, nc)), np.zeros((1, nc))
        for c, j in enumerate(cc):
            for x, out, h in ((q, cq, 1e-3 * depth), (v, cv, 1e-8)):
                out[:, c] = _central(_vary(_force_at, (model, cs, q, v, vimp, cc, x, j), 8),
                                     x[j], h)  # fmt: skip
            keep = v[j]
            for s, sign in ((1e-8, 1.0), (-1e-8, -1.0)):
                v[j] = keep + s
                cg[0, c] += sign * _force(model, cs, q, v, vimp, cc)[1] / 2e-8
            v[j] = keep
        for name, got, ref in (("dq", dq, cq), ("dv", dv, cv), ("gt", gt, cg)):
            err = np.abs(got - ref).max() / np.abs(ref).max()
            assert err <= 1e-6, (name, depth, err)


def test_forward_differences_remain_for_laws_without_the_analytic_path() -> None:
    """A lubricated joint keeps the forward differences (the film force has no analytic
    partials here); the dry paper scene takes the analytic path."""
    dry, _, _ = _model(True)
    assert nk.analytic_contact_supported(dry.kernel)
    scene = mechanism.load_scene("paper").replace({"joints.C.lubrication": {"viscosity": 0.04}})
    assert not nk.analytic_contact_supported(assemble(scene).kernel)
