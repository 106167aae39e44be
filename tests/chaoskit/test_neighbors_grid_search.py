"""The box-assisted grid built once and queried in parts."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from chaoskit._neighbors import GridSearch, grid_nearest_neighbors, nearest_neighbors


@pytest.mark.parametrize("p", [2.0, np.inf])
@pytest.mark.parametrize("m", [1, 2, 3, 5])
def test_parts_give_the_neighbours_of_one_query(m: int, p: float) -> None:
    """Each part's answers are those of one query over all points and of the k-d tree."""
    pts = np.random.default_rng(m).standard_normal((1500, m))
    ref = np.arange(0, 1500, 3)
    whole_idx, whole_dist = grid_nearest_neighbors(pts, theiler_window=7, query=ref, p=p)
    search = GridSearch(pts, theiler_window=7, p=p)
    parts = [search.query(ref[a : a + b]) for a, b in ((0, 64), (64, 128), (192, 400))]
    assert_array_equal(np.concatenate([idx for idx, _ in parts]), whole_idx)
    assert_array_equal(np.concatenate([d for _, d in parts]), whole_dist)
    tree_idx, _ = nearest_neighbors(pts, theiler_window=7, query=ref, p=p)
    assert_array_equal(whole_idx, tree_idx)
    all_idx, _ = search.query()
    assert_array_equal(all_idx[ref], whole_idx)


def test_bad_norm_and_window() -> None:
    pts = np.zeros((20, 2))
    with pytest.raises(ValueError, match="p must be 2 or inf"):
        GridSearch(pts, theiler_window=1, p=1.0)
    with pytest.raises(ValueError, match="theiler_window"):
        GridSearch(pts, theiler_window=19)
