"""One neighbour grid for the automatic dimension, the horizon's pilot and Rosenstein's
search: the same answers as separate grids, with fewer grids built."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_array_equal

import chaoskit._neighbors_kernels as nk
from chaoskit import lyapunov_rosenstein, systems
from chaoskit._neighbors import GridSearch, grid_nearest_neighbors


@pytest.mark.parametrize("p", [2.0, np.inf])
@pytest.mark.parametrize("m", [1, 3, 5])
def test_limit_gives_the_neighbours_of_the_leading_points(m: int, p: float) -> None:
    """Candidates limited to the first rows: the answers of a grid over those rows."""
    pts = np.random.default_rng(m).standard_normal((1500, m))
    search = GridSearch(pts, theiler_window=7, p=p)
    for limit in (200, 1111, 1500):
        ref = np.arange(0, limit, 3)
        idx, dist = search.query(ref, limit=limit)
        want_idx, want_dist = grid_nearest_neighbors(pts[:limit], theiler_window=7, query=ref, p=p)
        assert_array_equal(idx, want_idx)
        assert_array_equal(dist, want_dist)


def test_known_neighbours_are_kept_and_new_ones_recorded() -> None:
    """A row with a known neighbour is answered with it unsearched (here a deliberately
    admissible but not nearest one); the answers found are written into ``known``."""
    pts = np.random.default_rng(4).standard_normal((800, 2))
    search = GridSearch(pts, theiler_window=5)
    known = np.full(800, -1, dtype=np.int64)
    known[10] = 700
    idx, dist = search.query(np.arange(8, 14), known=known)
    assert idx[2] == 700
    assert dist[2] == np.sqrt(((pts[10] - pts[700]) ** 2).sum())
    fresh, _ = grid_nearest_neighbors(pts, theiler_window=5, query=np.arange(8, 14))
    assert_array_equal(np.delete(idx, 2), np.delete(fresh, 2))
    assert_array_equal(known[[8, 9, 11, 12, 13]], np.delete(fresh, 2))
    with pytest.raises(ValueError, match=r"limit must be in 1 … 800; got 0\."):
        search.query(limit=0)
    with pytest.raises(ValueError, match="known must be an int64 array of 800 entries"):
        search.query(known=np.zeros(5, dtype=np.int64))


def test_defaults_reuse_the_dimension_grid(monkeypatch: pytest.MonkeyPatch) -> None:
    """With the dimension estimated (three grids: d = 1, 2, 3), the pilot and the search
    build no grid of their own (five before), and the estimate is bit for bit the one
    with the same parameters given, which builds its own grid."""
    x = systems.lorenz(10_000)[:, 0]
    builds = []
    bucket = nk.bucket

    def counting(*args):
        builds.append(args[0].shape)
        return bucket(*args)

    monkeypatch.setattr(nk, "bucket", counting)
    auto = lyapunov_rosenstein(x, dt=0.01)
    assert auto.embedding_dim == 3
    assert len(builds) == auto.embedding_dim
    builds.clear()
    given = lyapunov_rosenstein(
        x,
        dt=0.01,
        embedding_dim=auto.embedding_dim,
        lag=auto.lag,
        theiler_window=auto.theiler_window,
    )
    assert len(builds) == 1
    assert given.mle == auto.mle
    assert given.ci == auto.ci
    assert given.fit_range == auto.fit_range
    assert_array_equal(given.curve, auto.curve)
