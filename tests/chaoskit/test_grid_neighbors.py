"""Box-assisted nearest neighbours and the vectorised divergence kernels, against
brute force and the general kernels."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

import chaoskit._neighbors as neighbors_module
from chaoskit import lyapunov_kantz, lyapunov_rosenstein, systems
from chaoskit._neighbors import grid_nearest_neighbors, nearest_neighbors
from chaoskit.lyapunov import _kernels
from chaoskit.lyapunov._common import batch_means_ci
from chaoskit.lyapunov._rosenstein import slope_spread


def _brute(points: np.ndarray, w: int, p: float) -> tuple[np.ndarray, np.ndarray]:
    n = points.shape[0]
    diff = points[:, None, :] - points[None, :, :]
    d = np.abs(diff).max(axis=2) if np.isinf(p) else np.sqrt((diff**2).sum(axis=2))
    idx = np.arange(n)
    d[np.abs(idx[:, None] - idx[None, :]) <= w] = np.inf
    return d.argmin(axis=1), d.min(axis=1)  # argmin: ties to the smaller index


@pytest.mark.parametrize("dim", [1, 2, 3, 5])
@pytest.mark.parametrize("w", [0, 1, 40, 149])
@pytest.mark.parametrize("p", [2.0, np.inf])
def test_grid_matches_brute_force(dim: int, w: int, p: float) -> None:
    rng = np.random.default_rng(10 * dim + w)
    pts = rng.standard_normal((300, dim))
    idx, dist = grid_nearest_neighbors(pts, theiler_window=w, p=p)
    ref_idx, ref_dist = _brute(pts, w, p)
    assert_array_equal(idx, ref_idx)
    assert_allclose(dist, ref_dist, rtol=1e-12)


def test_grid_ties_go_to_the_smaller_index() -> None:
    # integer lattice points: many neighbours at exactly the same distance
    pts = np.array([[i % 7, (3 * i) % 5] for i in range(200)], dtype=np.float64)
    for p in (2.0, np.inf):
        idx, dist = grid_nearest_neighbors(pts, theiler_window=2, p=p)
        ref_idx, ref_dist = _brute(pts, 2, p)
        assert_array_equal(idx, ref_idx)
        assert_allclose(dist, ref_dist, rtol=0, atol=0)


def test_grid_slow_trajectory_and_query_subset() -> None:
    t = np.linspace(0, 4 * np.pi, 2000)
    pts = np.column_stack([np.cos(t), np.sin(t)])
    q = np.array([0, 5, 999, 1999, 3])  # not increasing: the seed must not be trusted
    idx, dist = grid_nearest_neighbors(pts, theiler_window=300, query=q)
    _, ref_dist = _brute(pts, 300, 2.0)
    assert_allclose(dist, ref_dist[q], rtol=1e-12)
    assert np.all(np.abs(idx - q) > 300)


def test_grid_agrees_with_the_tree_on_an_attractor() -> None:
    x = systems.lorenz(8000, dt=0.01)[:, 0]
    pts = np.ascontiguousarray(np.column_stack([x[:-20], x[10:-10], x[20:]]))
    for p in (2.0, np.inf):
        a_idx, a_dist = nearest_neighbors(pts, theiler_window=100, p=p)
        b_idx, b_dist = grid_nearest_neighbors(pts, theiler_window=100, p=p)
        assert_allclose(b_dist, a_dist, rtol=1e-12)
        assert np.mean(a_idx == b_idx) > 0.999  # differ only at exact distance ties


def test_grid_bad_input() -> None:
    pts = np.random.default_rng(2).standard_normal((100, 2))
    with pytest.raises(ValueError, match="no admissible neighbour"):
        grid_nearest_neighbors(pts, theiler_window=50)
    with pytest.raises(ValueError, match="p must be 2 or inf"):
        grid_nearest_neighbors(pts, theiler_window=1, p=1.0)


@pytest.mark.parametrize("p", [2.0, np.inf])
def test_grid_on_a_map_both_bucketings_match_brute_force(p: float, monkeypatch) -> None:
    # Hénon: a clustered two-coordinate set, where most queries end in their own cell;
    # the points are bucketed by counting sort (few cells per point) or by argsort
    x = systems.henon(1500)[:, 0]
    pts = np.ascontiguousarray(np.column_stack([x[:-1], x[1:]]))
    ref_idx, ref_dist = _brute(pts, 1, p)
    idx, dist = grid_nearest_neighbors(pts, theiler_window=1, p=p)
    monkeypatch.setattr(neighbors_module, "_COUNTING_CELLS", 0)
    a_idx, a_dist = grid_nearest_neighbors(pts, theiler_window=1, p=p)
    for i, d in ((idx, dist), (a_idx, a_dist)):
        assert_array_equal(i, ref_idx)
        assert_allclose(d, ref_dist, rtol=1e-12)


def test_grid_sparse_middle_coordinate_matches_brute_force() -> None:
    # a grid coordinate with a single cell: rings grow over the other two only
    pts = np.random.default_rng(8).standard_normal((400, 3))
    pts[:, 1] = 0.25
    for p in (2.0, np.inf):
        idx, dist = grid_nearest_neighbors(pts, theiler_window=3, p=p)
        ref_idx, ref_dist = _brute(pts, 3, p)
        assert_array_equal(idx, ref_idx)
        assert_allclose(dist, ref_dist, rtol=1e-12)


@pytest.mark.parametrize("step", [1, 2, 3, 5])
def test_euclidean_divergence_matches_the_general_kernel(step: int) -> None:
    # the general SAMPLE_ORBIT kernel with zero shifts is sqrt(d2 · d2) = d2 per pair
    x = systems.lorenz(6000, dt=0.01)[:, 0]
    pts = np.ascontiguousarray(np.column_stack([x[:-20], x[10:-10], x[20:]]) / x.std())
    ref = np.arange(0, 5000, 2)
    nbr, _ = grid_nearest_neighbors(pts[:5000], theiler_window=100, query=ref)
    ks = np.append(np.arange(0, 301, step), 302)  # a last horizon off the step
    zero = np.zeros(ref.size)
    total, count = _kernels.log_divergence(pts, ref, nbr, ks, _kernels.EUCLIDEAN, zero)
    gen, gcount = _kernels.log_divergence(pts, ref, nbr, ks, _kernels.SAMPLE_ORBIT, zero)
    assert_array_equal(count, gcount)
    assert_allclose(total, gen, rtol=1e-12, atol=1e-9)
    kw = ks[5:60]
    s, v = _kernels.pair_slopes(pts, ref, nbr, kw, _kernels.EUCLIDEAN, zero)
    gs, gv = _kernels.pair_slopes(pts, ref, nbr, kw, _kernels.SAMPLE_ORBIT, zero)
    assert_array_equal(v, gv)
    assert_allclose(s, gs, rtol=1e-12, atol=1e-15)


def test_estimates_on_henon_are_unchanged() -> None:
    # the tree search and the per-radius Kantz pass gave 0.418178 and 0.425756 here; the
    # Hénon series is chaotic, so only what survives a change of rounding is asserted
    x = systems.henon(10_000)[:, 0]
    assert_allclose(lyapunov_rosenstein(x).mle, 0.418178, atol=2e-3)
    assert_allclose(lyapunov_kantz(x).mle, 0.425756, atol=2e-3)


@pytest.mark.parametrize("step", [1, 2, 4])
def test_orbit_divergence_matches_numpy(step: int) -> None:
    x = systems.lorenz(3000, dt=0.01)[:, 0]
    pts = np.ascontiguousarray(np.column_stack([x[:-20], x[10:-10], x[20:]]) / x.std())
    ref = np.arange(0, 2500, 5)
    nbr, _ = grid_nearest_neighbors(pts[:2500], theiler_window=100, query=ref)
    shift = _kernels.orbit_shifts(pts, ref, nbr)
    ks = np.arange(0, 200, step)
    total, count = _kernels.log_divergence(pts, ref, nbr, ks, _kernels.ORBIT, shift)
    s = shift[:, None]
    jk = nbr[:, None] + ks[None, :]
    ik = ref[:, None] + ks[None, :]
    ok = (ik < pts.shape[0]) & (jk + 1 < pts.shape[0])
    jk, ik = np.where(ok, jk, 1), np.where(ok, ik, 0)
    y = (
        (0.5 * s * (s - 1.0))[..., None] * pts[np.maximum(jk - 1, 0)]
        + (1.0 - s * s)[..., None] * pts[jk]
        + (0.5 * s * (s + 1.0))[..., None] * pts[jk + 1]
    )
    d2 = ((y - pts[ik]) ** 2).sum(axis=2)
    ok &= d2 > 0
    expected = np.where(ok, 0.5 * np.log(np.where(ok, d2, 1.0)), 0.0).sum(axis=0)
    assert_array_equal(count, ok.sum(axis=0))
    assert_allclose(total, expected, rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("mode", [_kernels.EUCLIDEAN, _kernels.SAMPLE_ORBIT])
def test_batch_slope_sums_match_the_per_pair_slopes(mode: int) -> None:
    # the interval's spread from batch sums of log distances equals the batch means of the
    # per-pair slopes; a pair at zero distance sends it back to the per-pair path
    x = systems.lorenz(5000, dt=0.01)[:, 0]
    pts = np.ascontiguousarray(np.column_stack([x[:-20], x[10:-10], x[20:]]) / x.std())
    ref = np.arange(0, 4600, 3)
    nbr, _ = grid_nearest_neighbors(pts[:4600], theiler_window=100, query=ref)
    shift = _kernels.orbit_shifts(pts, ref, nbr)
    ks = np.unique(np.linspace(20, 300, 32).astype(np.int64))
    slopes, valid = _kernels.pair_slopes(pts, ref, nbr, ks, mode, shift)
    _, half, n_batches = batch_means_ci(slopes[valid])
    got = slope_spread(pts, ref, nbr, ks, mode, shift)
    assert got[1:] == (n_batches, int(valid.sum())) == (20, 1534)
    assert_allclose(got[0], half, rtol=1e-12)
    pts[nbr[7] + ks[2]] = pts[ref[7] + ks[2]]
    slopes, valid = _kernels.pair_slopes(pts, ref, nbr, ks, mode, shift)
    _, half, n_batches = batch_means_ci(slopes[valid])
    assert slope_spread(pts, ref, nbr, ks, mode, shift) == (half, n_batches, int(valid.sum()))
