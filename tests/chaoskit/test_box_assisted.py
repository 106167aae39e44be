"""Box-assisted neighbour searches of the estimators: the same neighbours as before."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.signal import lfilter

from chaoskit import lyapunov_kantz, systems
from chaoskit._neighbors import build_tree, nearest_neighbors, radius_grid
from chaoskit.embedding import embed, standardize
from chaoskit.embedding._dimension import _neighbours
from chaoskit.lyapunov import _kernels as _k
from chaoskit.lyapunov._kantz import _Search


def _lorenz_points(n: int, m: int, lag: int) -> np.ndarray:
    return np.ascontiguousarray(embed(standardize(systems.lorenz(n)[:, 0]), m, lag))


def test_radius_grid_cells_are_as_wide_as_the_radius() -> None:
    pts = _lorenz_points(3000, 3, 10)
    members, spts, keys, starts, slot, grid = radius_grid(pts, 0.2)
    cell = grid[2]
    assert cell >= 0.2
    assert sorted(members.tolist()) == list(range(pts.shape[0]))
    assert_allclose(spts, pts[members], rtol=0, atol=0)
    assert starts[0] == 0 and starts[-1] == pts.shape[0] and starts.size == keys.size + 1
    assert (np.diff(keys) > 0).all()
    assert (slot[keys] == np.arange(keys.size)).all()


@pytest.mark.parametrize("m", [1, 2, 5])
def test_kantz_neighbourhoods_match_brute_force_in_any_dimension(m: int) -> None:
    """Every point within the radius is found, whatever the number of grid coordinates."""
    pts = _lorenz_points(2500, m, 7)
    ks = np.arange(0, 6, dtype=np.int64)
    usable = pts.shape[0] - ks[-1]
    ref = np.arange(0, usable, 37, dtype=np.int64)
    eps = np.array([0.1, 0.2, 0.35])
    logd, used, _, _ = _Search(pts, pts[:usable], ref, 20, eps, ks, 10**9).log_distances(
        False, eps.size - 1
    )
    far = np.abs(np.arange(usable)[None, :] - ref[:, None]) > 20
    d0 = np.abs(pts[:usable][None, :, :] - pts[ref][:, None, :]).max(axis=2)
    for e, radius in enumerate(eps):
        assert (used[:, e] == (far & (d0 < radius)).sum(axis=1)).all()
    r = int(np.argmax(used[:, 0]))
    nb = np.flatnonzero(far[r] & (d0[r] < eps[0]))
    expect = [np.log(np.linalg.norm(pts[nb + k] - pts[ref[r] + k], axis=1).mean()) for k in ks]
    assert_allclose(logd[r, 0], expect, rtol=1e-12)


def test_kantz_neighbourhoods_on_a_grid_too_large_for_a_cell_table() -> None:
    """Small radii in three coordinates: the occupied cells are found by bisection."""
    pts = _lorenz_points(3000, 3, 10)
    eps = np.array([0.01, 0.03])
    assert radius_grid(pts, eps[-1])[4].size == 0
    ks = np.arange(0, 3, dtype=np.int64)
    usable = pts.shape[0] - 2
    ref = np.arange(0, usable, 7, dtype=np.int64)
    used = _Search(pts, pts[:usable], ref, 5, eps, ks, 10**9).log_distances(False)[1]
    far = np.abs(np.arange(usable)[None, :] - ref[:, None]) > 5
    d0 = np.abs(pts[:usable][None, :, :] - pts[ref][:, None, :]).max(axis=2)
    for e, radius in enumerate(eps):
        assert (used[:, e] == (far & (d0 < radius)).sum(axis=1)).all()
    assert used[:, -1].sum() > 100


def test_capped_neighbourhoods_take_the_strided_subset_in_first_coordinate_order() -> None:
    pts = _lorenz_points(4000, 3, 10)
    ks = np.array([0, 1, 2], dtype=np.int64)
    usable = pts.shape[0] - 2
    ref = np.array([500, 1700, 3100], dtype=np.int64)
    eps = np.array([0.6])
    cap = 5
    logd, used, _, _ = _Search(pts, pts[:usable], ref, 10, eps, ks, cap).log_distances(
        False, eps.size - 1
    )
    order = np.argsort(pts[:usable, 0], kind="stable")
    for r, i in enumerate(ref):
        d0 = np.abs(pts[order] - pts[i]).max(axis=1)
        nb = order[(np.abs(order - i) > 10) & (d0 < eps[0])]
        assert nb.size > cap
        take = nb[:: -(-nb.size // cap)]
        assert used[r, 0] == take.size
        expect = np.log(np.linalg.norm(pts[take + 2] - pts[i + 2], axis=1).mean())
        assert_allclose(logd[r, 0, 2], expect, rtol=1e-13)


# S(k, ε) at k = 0, 3, 8 for ε = 0.1, 0.3, 0.6 of the AR(1) series below, computed by the
# slab search the grid search replaced: with the default cap of 64 neighbours (the two
# larger radii take strided subsets) and without a cap
_SLAB_CAPPED = [
    [-3.4356436253344595, -0.0258765355124296, 0.31979584559488894],
    [-2.324718597111, 0.01838146087630733, 0.3548047142714402],
    [-1.632532494911408, 0.02986107010094501, 0.3573672787434098],
]
_SLAB_UNCAPPED = [
    [-3.4356436253344595, -0.0258765355124296, 0.31979584559488894],
    [-2.32561139703191, 0.02054621450190505, 0.3567791963611819],
    [-1.634704446383783, 0.03202275742948048, 0.3588456186244328],
]


@pytest.mark.parametrize(("cap", "expect"), [(64, _SLAB_CAPPED), (10**9, _SLAB_UNCAPPED)])
def test_kantz_curves_are_those_of_the_slab_search(cap: int, expect) -> None:
    """The same neighbours and subsets as before; uncapped sums over a neighbourhood are
    taken in another order, so agreement is to rounding (1e-15 measured)."""
    x = lfilter([1.0], [1.0, -0.9], np.random.default_rng(7).standard_normal(4000))
    res = lyapunov_kantz(
        x,
        embedding_dim=2,
        lag=1,
        theiler_window=5,
        epsilon=[0.1, 0.3, 0.6],
        max_horizon=8,
        fit_range=(1, 6),
        max_neighbors=cap,
    )
    assert_allclose(res.curves[:, [0, 3, 8]], expect, rtol=1e-12)
    assert res.params["mean_neighbors"] == pytest.approx(5.891506849315069, rel=1e-15)
    assert res.mle == pytest.approx(0.19358277251485267, rel=1e-12)


@pytest.mark.parametrize(("dim", "p"), [(1, 2.0), (2, 2.0), (4, 2.0), (3, np.inf)])
def test_fnn_neighbours_are_those_of_the_tree(dim: int, p: float) -> None:
    arr = standardize(systems.lorenz(6000)[:, 0])
    lag, w = 10, 60
    n_points = arr.size - dim * lag
    ref, nbr, dist = _neighbours(arr, dim, lag, n_points, w, 1500, p)
    pts = embed(arr[: n_points + (dim - 1) * lag], dim, lag)
    t_nbr, t_dist = nearest_neighbors(pts, theiler_window=w, query=ref, tree=build_tree(pts), p=p)
    assert (nbr == t_nbr).all()
    assert_allclose(dist, t_dist, rtol=1e-15, atol=0)


def test_sample_orbit_pair_slopes_match_the_definition() -> None:
    pts = _lorenz_points(3000, 3, 10)
    ref = np.arange(5, 2500, 13, dtype=np.int64)
    far = np.abs(np.arange(2500)[None, :] - ref[:, None]) > 50
    d = np.linalg.norm(pts[:2500][None, :, :] - pts[ref][:, None, :], axis=2)
    nbr = np.where(far, d, np.inf).argmin(axis=1).astype(np.int64)
    shift = _k.orbit_shifts(pts, ref, nbr)
    ks = np.array([0, 4, 9, 20, 33], dtype=np.int64)
    slope, valid = _k.pair_slopes(pts, ref, nbr, ks, _k.SAMPLE_ORBIT, shift)
    assert valid.all()
    for p in (0, 7, ref.size - 1):
        i, j, s = ref[p], nbr[p], shift[p]
        y = []
        for k in ks:
            d_sample = ((pts[j + k] - pts[i + k]) ** 2).sum()
            vel = 0.5 * (pts[j + k + 1] - pts[j + k - 1])
            acc = pts[j + k + 1] - 2.0 * pts[j + k] + pts[j + k - 1]
            orbit = pts[j + k] + s * vel + 0.5 * s * s * acc
            d_orbit = ((orbit - pts[i + k]) ** 2).sum()
            y.append(0.25 * np.log(d_sample * d_orbit))
        assert_allclose(slope[p], np.polyfit(ks, y, 1)[0], rtol=1e-10)
