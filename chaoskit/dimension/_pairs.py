"""Pair counting for correlation sums: a hashed box grid, a Theiler window, adaptive sampling.

Points are linked into a grid of boxes of side ``r_max`` over their first two delay
coordinates (the first coordinate alone for dimension 1), hashed modulo 512 boxes per axis,
so memory is O(N) whatever the spread of the data; a pair closer than ``r_max`` in any
embedding dimension ≥ 2 lies in neighbouring boxes (the box-assisted search of Grassberger
1990 and of TISEAN). Distances in every dimension ``1 … m_max`` are accumulated along the
delay coordinates of one candidate pair, so all dimensions cost little more than the largest.

Points enter the grid one at a time in a random order and each is compared with those
already in, so every pair is met once. Large radii do not need every pair: as in TISEAN's
``d2`` (Hegger, Kantz & Schreiber 1999) a radius stops collecting once it holds
``pairs_per_radius`` pairs in every dimension, and its correlation sum is its count over
the admissible pairs examined until then. Whenever the largest radius still collecting
drops, the grid is rebuilt with the smaller box, which keeps the candidates few.
"""

from __future__ import annotations

import numpy as np

from . import _kernels as _k

_BLOCK = 256  # points inserted between checks of the stopping rule
#: points inserted per call of the compiled counter when every pair is used: Python runs
#: between calls, so Ctrl-C stops an exact count over 10^5 points promptly (the counts are
#: integers summed in order: the result does not depend on it)
EXACT_BLOCK = 2048


def _count_part(
    x: np.ndarray,
    lag: int,
    dims: tuple[int, int],
    radii: np.ndarray,
    w: int,
    maximum_norm: bool,
    pairs_per_radius: int | None,
    order: np.ndarray,
    rank: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Cumulative counts ``(dims[1], n_r)`` (rows below ``dims[0]`` unused) and totals."""
    lo_dim, max_dim = dims
    two_d = lo_dim >= 2
    n_points, nr = order.size, radii.size
    count = np.zeros((max_dim, nr), dtype=np.int64)
    total = np.zeros(nr, dtype=np.int64)
    head = np.full((_k.GRID, _k.GRID if two_d else 1), -1, dtype=np.int64)
    nxt = np.empty(n_points, dtype=np.int64)
    active, start = nr, 0
    block = EXACT_BLOCK if pairs_per_radius is None else _BLOCK
    while start < n_points and active > 0:
        stop = min(start + block, n_points)
        r = np.ascontiguousarray(radii[:active])
        hist = np.zeros((max_dim, active), dtype=np.int64)
        total[:active] += _k.count_progressive(
            x, lag, max_dim, order, rank, start, stop, r, w, maximum_norm, two_d, head, nxt, hist
        )
        count[:, :active] += np.cumsum(hist, axis=1)
        start = stop
        if pairs_per_radius is not None:
            before = active
            while active > 0 and count[lo_dim - 1 :, active - 1].min() >= pairs_per_radius:
                active -= 1
            if 0 < active < before:
                _k.fill_grid(x, lag, order[:start], float(radii[active - 1]), two_d, head, nxt)
    return count, total


def count_pairs(
    x: np.ndarray,
    *,
    lag: int,
    n_points: int,
    max_dim: int,
    radii: np.ndarray,
    theiler_window: int,
    maximum_norm: bool,
    pairs_per_radius: int | None,
    rng: np.random.Generator,
) -> tuple[np.ndarray, np.ndarray]:
    """Pair counts ``(max_dim, n_r)`` and admissible-pair totals ``(max_dim, n_r)``.

    ``count[m − 1, k] / total[m − 1, k]`` is the correlation sum of dimension ``m`` at
    ``radii[k]`` (ascending). ``pairs_per_radius=None`` uses every pair (exact).
    """
    order = rng.permutation(n_points).astype(np.int64)
    rank = np.empty(n_points, dtype=np.int64)
    rank[order] = np.arange(n_points)
    count = np.zeros((max_dim, radii.size), dtype=np.int64)
    total = np.zeros((max_dim, radii.size), dtype=np.int64)
    args = (radii, theiler_window, maximum_norm, pairs_per_radius, order, rank)
    c1, t1 = _count_part(x, lag, (1, 1), *args)
    count[0], total[0] = c1[0], t1
    if max_dim >= 2:
        c, t = _count_part(x, lag, (2, max_dim), *args)
        count[1:], total[1:] = c[1:], t
    return count, total
