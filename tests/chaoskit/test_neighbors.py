"""Nearest neighbours with an exact Theiler window, against brute force."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from chaoskit._neighbors import mean_period, nearest_neighbors


def _brute(points: np.ndarray, w: int, p: float) -> tuple[np.ndarray, np.ndarray]:
    n = points.shape[0]
    diff = points[:, None, :] - points[None, :, :]
    d = np.abs(diff).max(axis=2) if np.isinf(p) else np.sqrt((diff**2).sum(axis=2))
    idx = np.arange(n)
    d[np.abs(idx[:, None] - idx[None, :]) <= w] = np.inf
    return d.argmin(axis=1), d.min(axis=1)


@pytest.mark.parametrize("w", [0, 1, 5, 40, 149])
@pytest.mark.parametrize("p", [2.0, np.inf])
def test_matches_brute_force(w: int, p: float) -> None:
    rng = np.random.default_rng(w)
    pts = rng.standard_normal((300, 3))
    idx, dist = nearest_neighbors(pts, theiler_window=w, p=p)
    ref_idx, ref_dist = _brute(pts, w, p)
    assert_allclose(dist, ref_dist, rtol=1e-12)
    assert_array_equal(idx, ref_idx)
    assert np.all(np.abs(idx - np.arange(300)) > w)


def test_slow_trajectory_needs_the_large_k_fallback() -> None:
    # on a slowly drawn circle the nearest candidates are all inside the window
    t = np.linspace(0, 4 * np.pi, 2000)
    pts = np.column_stack([np.cos(t), np.sin(t)])
    idx, dist = nearest_neighbors(pts, theiler_window=300)
    _, ref_dist = _brute(pts, 300, 2.0)
    assert_allclose(dist, ref_dist, rtol=1e-12)
    assert np.all(np.abs(idx - np.arange(2000)) > 300)


def test_query_subset() -> None:
    pts = np.random.default_rng(1).standard_normal((200, 2))
    q = np.array([0, 17, 199])
    idx, _ = nearest_neighbors(pts, theiler_window=3, query=q)
    assert_array_equal(idx, _brute(pts, 3, 2.0)[0][q])


def test_window_without_neighbours_raises_at_once() -> None:
    pts = np.random.default_rng(2).standard_normal((100, 2))
    nearest_neighbors(pts, theiler_window=49)  # 2w + 2 = 100 points: still possible
    with pytest.raises(ValueError, match="no admissible neighbour"):
        nearest_neighbors(pts, theiler_window=50)


def test_mean_period_of_a_sine() -> None:
    x = np.sin(2 * np.pi * np.arange(4000) / 25.0)
    assert_allclose(mean_period(x), 25.0, rtol=1e-3)
