"""Kernels of the generalized-α step on the flexible paper scene: the vectorised mass and LU
solves against numpy, the partial point-cache refresh against the full one, and the rule
that reuses the clearance-force derivatives."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechanism
from mechanism.core.bodies import beams_jacobian_add
from mechanism.core.integrate import GeneralizedAlpha, StepSettings
from mechanism.core.integrate import _newton_kernels as nk
from mechanism.core.integrate._driver import initial_latch
from mechanism.core.integrate._methods import _contact_columns
from mechanism.core.joints import CON_ROWS, constraint_columns, constraint_rows
from mechanism.core.joints._kernels import update_point_rows, update_points
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state


@pytest.fixture(scope="module")
def flexible():
    model = assemble(mechanism.load_scene("paper"))
    q, v = initial_state(model)
    return model, q, v


def test_mass_inverse_is_exactly_symmetric_and_block_solve_matches_numpy(flexible) -> None:
    model, q, _ = flexible
    km = model.kernel
    np.testing.assert_array_equal(km.minv, km.minv.T)
    x = np.random.default_rng(0).normal(size=q.size)
    out = np.empty_like(x)
    k._block_solve(km.minv, km.minv_h, km.blk_lo, km.blk_hi, km.blk_st, x, out)
    np.testing.assert_allclose(out, np.linalg.solve(km.mass, x), rtol=1e-9, atol=0.0)


def test_the_rods_planes_apart_give_the_same_accelerations_bit_for_bit(flexible) -> None:
    """Each rod's x and y coordinates are mass blocks of their own (the rods' 136
    coordinates; the 9 rigid ones are not), and M⁻¹Q, W = M⁻¹Φqᵀ and the accelerations
    taken plane by plane equal those of the whole blocks to the last bit."""
    model, q, v = flexible
    km = model.kernel
    assert np.bincount(km.blk_st).tolist() == [0, 9, 136]
    whole = km._replace(blk_st=np.ones_like(km.blk_st))
    rng = np.random.default_rng(3)
    vimp = np.zeros(km.cj_i.shape[0])
    for _ in range(20):
        q1 = q + 1e-5 * rng.normal(size=q.size)
        v1 = v + 1e-2 * rng.normal(size=v.size)
        got = []
        for km_ in (km, whole):
            ws = model.workspace()
            acc = np.zeros(q.size)
            counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
            assert k.accelerations(km_, ws, 0.01, q1, v1, vimp, acc, counters) == 0
            got.append((acc, ws.lam, ws.w, ws.a0))
        for split, full in zip(*got, strict=True):
            np.testing.assert_array_equal(split, full)


@pytest.mark.parametrize("name", mechanism.list_scenes())
def test_the_primitives_columns_are_the_nonzero_columns_of_the_constraint_jacobian(name) -> None:
    """The Schur complement's nonzero columns of each row of Φq, listed from the columns
    of each primitive's two points, are those a scan of the row finds, in every shipped
    scene at perturbed states (and every row belongs to a primitive)."""
    model = assemble(mechanism.load_scene(name))
    km = model.kernel
    rows = sum(CON_ROWS[typ] for typ in km.con_i[:, 0])
    assert rows == km.n_rows
    ws = model.workspace()
    q, v = initial_state(model)
    rng = np.random.default_rng(4)
    for _ in range(5):
        q1 = q + 1e-3 * rng.normal(size=q.size)
        v1 = v + 1e-1 * rng.normal(size=v.size)
        update_points(q1, v1, km.pt_i, km.pt_f, ws.pci, ws.pcf)
        ws.phiq[:, :] = 0.0
        constraint_rows(0.01, km.con_i, km.con_f, km.drive_i, km.drive_f, km.spline_x,
                        km.spline_c, ws.pci, ws.pcf, ws.phi, ws.phiq, ws.phit, ws.gam)  # fmt: skip
        constraint_columns(km.con_i, ws.pci, ws.phiq, ws.nz_n, ws.nz_j)
        for r in range(km.n_rows):
            expected = np.flatnonzero(ws.phiq[r])
            assert expected.size > 0
            np.testing.assert_array_equal(ws.nz_j[r, : ws.nz_n[r]], expected)


def test_lu_solve_matches_numpy() -> None:
    rng = np.random.default_rng(1)
    a = rng.normal(size=(145, 145)) + 20.0 * np.eye(145)
    b = rng.normal(size=145)
    lt = a.copy()
    piv = np.empty(145, dtype=np.int64)
    assert nk.lu_factor(lt, piv)
    x = b.copy()
    nk.lu_solve(lt, piv, x)
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-12, atol=1e-14)


def test_point_rows_refresh_equals_the_full_refresh(flexible) -> None:
    model, q, v = flexible
    km = model.kernel
    ws = model.workspace()
    rng = np.random.default_rng(2)
    q1 = q + 1e-4 * rng.normal(size=q.size)
    v1 = v + 1e-2 * rng.normal(size=v.size)
    update_points(q, v, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    pci, pcf = ws.pci.copy(), ws.pcf.copy()
    rows = np.ascontiguousarray(km.cj_i[:, :2].ravel())
    update_point_rows(q1, v1, km.pt_i, km.pt_f, pci, pcf, rows)
    update_points(q1, v1, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    np.testing.assert_array_equal(pcf[rows], ws.pcf[rows])
    np.testing.assert_array_equal(pci[rows], ws.pci[rows])
    others = np.setdiff1d(np.arange(km.pt_i.shape[0]), rows)
    assert not np.array_equal(pcf[others], ws.pcf[others])  # left at the old state


def _in_contact(model, q, v):
    """(ws, vimp) with the journal of joint C pushed 20 µm into its bearing and sliding."""
    km = model.kernel
    ws = model.workspace()
    q = q.copy()
    q[_contact_columns(model)[0]] += km.cj_f[0, k.CF_C] + 2e-5
    vimp, _ = initial_latch(model, np.concatenate([q, v]))
    acc = np.empty_like(q)
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    assert k.accelerations(km, ws, 0.0, q, v, vimp, acc, counters) == 0
    assert ws.cj[0, k.CJ_DELTA] > 0.0
    return ws, vimp


def test_contact_derivatives_are_reused_only_while_the_state_holds(flexible) -> None:
    model, q, v = flexible
    km = model.kernel
    ws, vimp = _in_contact(model, q, v)
    lin = np.full((km.cj_i.shape[0], nk.LIN_COLUMNS), np.nan)
    assert not nk.linearisation_holds(km, ws.cj, vimp, lin)  # nothing recorded yet
    nk.record_linearisation(ws.cj, vimp, lin)
    assert nk.linearisation_holds(km, ws.cj, vimp, lin)
    rel = nk.RELINEARISE
    for column, scale in (
        (k.CJ_DELTA, ws.cj[0, k.CJ_DELTA]),
        (k.CJ_PHI_B, 1.0),
        (k.CJ_DELTA_DOT, abs(ws.cj[0, k.CJ_DELTA_DOT]) + vimp[0]),
    ):
        cj = ws.cj.copy()
        cj[0, column] += 0.5 * rel * scale
        assert nk.linearisation_holds(km, cj, vimp, lin), column
        cj[0, column] += rel * scale
        assert not nk.linearisation_holds(km, cj, vimp, lin), column
    cj = ws.cj.copy()
    cj[0, k.CJ_DELTA] = -1e-6  # separated: the contact forces' derivatives vanish
    assert not nk.linearisation_holds(km, cj, vimp, lin)
    other = vimp.copy()
    other[0] *= 2.0  # a new impact latches a new approach speed
    assert not nk.linearisation_holds(km, ws.cj, other, lin)
    # friction: sliding on one side of the ramp keeps its (flat) linearisation, crossing
    # into the ramp does not
    v0, v1 = km.cj_f[0, k.CF_V0], km.cj_f[0, k.CF_V1]
    cj = ws.cj.copy()
    cj[0, k.CJ_VT] = 10.0 * v1
    nk.record_linearisation(cj, vimp, lin)
    cj[0, k.CJ_VT] = 3.0 * v1
    assert nk.linearisation_holds(km, cj, vimp, lin)
    cj[0, k.CJ_VT] = 0.5 * (v0 + v1)
    assert not nk.linearisation_holds(km, cj, vimp, lin)


def test_chunked_integration_follows_the_same_path(flexible) -> None:
    """An integration split into progress chunks keeps the Jacobian, the clearance-force
    linearisations and the refresh flags across the chunks: bit-identical to one call."""
    model, q, v = flexible
    y0 = np.concatenate([q, v])
    period = 60.0 / 150.0
    t_out = np.linspace(0.0, 0.3 * period, 31)
    method = GeneralizedAlpha(step="max_step")
    runs = [
        method.integrate(
            model,
            y0,
            t_out,
            steps=StepSettings(rtol=1e-5, atol=1e-5, max_step=period / 10_000),
            progress=progress,
        )
        for progress in (False, True)
    ]
    one, chunked = (dataclasses.replace(r.stats, wall_time=0.0) for r in runs)
    assert one.contact_events > 4 and one.jacobian_evaluations > 1
    assert one == chunked
    np.testing.assert_array_equal(runs[0].final_state, runs[1].final_state)


def test_newton_accepts_one_iteration_when_the_last_contraction_bounds_the_error() -> None:
    """The ideal flexible paper mechanism at T/10 000: with the contraction rate the same
    Newton matrix showed in the previous step, about half of the steps stop after one
    iteration (before: at least two per step), and the result stays within the Newton
    tolerance of a run converged 10⁴× tighter."""
    model = assemble(mechanism.load_scene("paper"), ideal=True)
    q, v = initial_state(model, eccentricity=False)
    y0 = np.concatenate([q, v])
    period = 60.0 / 150.0
    t_out = np.linspace(0.0, 0.1 * period, 11)
    runs = [
        GeneralizedAlpha(step="max_step").integrate(
            model, y0, t_out, steps=StepSettings(rtol=tol, atol=tol, max_step=period / 10_000)
        )
        for tol in (1e-5, 1e-9)
    ]
    coarse, tight = runs
    assert coarse.stats.steps == 1000
    assert coarse.stats.newton_iterations < 1.7 * coarse.stats.steps
    n = model.n_dof
    scale = 1e-5 * (1.0 + np.abs(tight.final_state[:n]))
    assert np.max(np.abs(coarse.final_state[:n] - tight.final_state[:n]) / scale) < 1.0


def test_projected_element_columns_equal_the_dense_product(flexible) -> None:
    """−P M⁻¹ K over the interior ANCF columns, computed over the sparsity of K and Φq,
    equals the dense product P = I − M⁻¹Φqᵀ(Φq M⁻¹Φqᵀ)⁻¹Φq to round-off."""
    model, q, v = flexible
    km = model.kernel
    ws = model.workspace()
    n = model.n_dof
    rng = np.random.default_rng(3)
    q = q + 1e-5 * rng.standard_normal(n)  # a stressed state
    vimp, _ = initial_latch(model, np.concatenate([q, v]))
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    acc = np.zeros(n)
    k.accelerations(km, ws, 0.0, q, v, vimp, acc, counters)
    kbuf = np.zeros((n, n))
    beams_jacobian_add(km.beam_i, km.beam_f, q, 1.0, 0.0, kbuf)
    cols = np.flatnonzero(np.any(kbuf != 0.0, axis=0)).astype(np.int64)
    out = np.zeros((n, n))
    nk._projected_columns(km, ws, kbuf, cols, out)
    minv = km.minv
    phiq = ws.phiq
    w = minv @ phiq.T
    proj = np.eye(n) - w @ np.linalg.solve(phiq @ w, phiq)
    dense = -proj @ minv @ kbuf[:, cols]
    scale = np.max(np.abs(dense))
    np.testing.assert_allclose(out[:, cols], dense, rtol=0, atol=1e-10 * scale)
