"""Nearest-neighbour search in delay space with an exact Theiler window.

A KD-tree (:class:`scipy.spatial.cKDTree`) gives the ``k`` nearest candidates of each query
point in O(log N); candidates closer in time than the Theiler window are dropped and the
first remaining one is the neighbour. Points whose ``k`` candidates are all excluded are
queried again with a larger ``k`` (×4 each round). ``k = 2w + 2`` always contains an admissible
point, because at most ``2w + 1`` points (the point itself included) lie inside the window,
so the loop ends after a few rounds. Time O(N log N), memory O(N·m) plus a bounded
``chunk × k`` candidate block.

:func:`grid_nearest_neighbors` finds the same neighbours box-assisted (TISEAN's search):
faster when the Theiler window is wide, since an excluded point costs one comparison there
instead of a tree candidate. :func:`radius_grid` buckets the points for the fixed-radius
neighbourhoods of Kantz's estimator (cells as wide as the radius).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from . import _neighbors_kernels as _nk

__all__ = [
    "GridSearch",
    "build_tree",
    "check_theiler_window",
    "default_theiler_window",
    "grid_nearest_neighbors",
    "mean_period",
    "nearest_neighbors",
    "radius_grid",
]

_CHUNK_ENTRIES = 2_000_000  # candidates held at once (≈ 32 MB of index + distance)
#: query points per tree query: one query is a fraction of a second, and Python runs
#: between queries, so Ctrl-C stops a search over 10^6 points promptly (each point's
#: neighbour is found on its own: the result does not depend on it)
CHUNK_POINTS = 20_000
_FIRST_K = 8
#: mean number of points per grid cell the box-assisted search aims at, and the number of
#: points the cell size is tuned on
_GRID_OCCUPANCY = 16.0
_GRID_PILOT = 4096
_GRID_MAX_CELLS = 1 << 20  # per coordinate, so that three of them fit a 64-bit cell id
_GRID_TABLE = 1 << 20  # cells up to which a direct cell → members table is kept (4 MB)
#: cells per point up to which the points are counting-sorted by cell (measured, 5·10⁴
#: points: 4 cells per point 4.3 ms against 5.8 ms with a comparison sort, 8 about even)
_COUNTING_CELLS = 6
_NO_ORDER = np.empty(0, dtype=np.int64)


def check_theiler_window(theiler_window: int, n_points: int) -> None:
    """Raise a ValueError if ``theiler_window`` leaves some point without a neighbour.

    Point ``i`` has an admissible neighbour iff some ``j`` in ``[0, n_points)`` has
    ``|i - j| > theiler_window``; this holds for every ``i`` iff ``n_points >= 2w + 2``.
    """
    if n_points < 2 * theiler_window + 2:
        raise ValueError(
            f"theiler_window={theiler_window} leaves no admissible neighbour: excluding pairs "
            f"with |i - j| <= {theiler_window} needs at least {2 * theiler_window + 2} "
            f"embedded points, but only {n_points} are available. Use a smaller "
            "theiler_window or a longer series."
        )


def build_tree(points: np.ndarray) -> cKDTree:
    """Build the KD-tree used by :func:`nearest_neighbors` (reuse it across queries)."""
    return cKDTree(points, leafsize=16, balanced_tree=False, compact_nodes=False)


def nearest_neighbors(
    points: np.ndarray,
    *,
    theiler_window: int,
    query: np.ndarray | None = None,
    tree: cKDTree | None = None,
    p: float = 2.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Nearest neighbour of each query point with ``|i - j| > theiler_window``.

    Parameters
    ----------
    points
        ``(M, m)`` contiguous float64 array; row ``i`` is the state at sample ``i``.
    theiler_window
        Pairs with ``|i - j| <= theiler_window`` are excluded (``0`` excludes only the point
        itself).
    query
        Row indices to find neighbours for (default: all rows).
    tree
        A tree from :func:`build_tree` over ``points``, to avoid rebuilding it.
    p
        Minkowski norm (2 Euclidean, ``np.inf`` maximum norm).

    Returns
    -------
    index, distance
        ``int64`` and ``float64`` arrays of the length of ``query``.

    Raises
    ------
    ValueError
        If the window leaves some point without an admissible neighbour (see
        :func:`check_theiler_window`).
    """
    n_points = points.shape[0]
    check_theiler_window(theiler_window, n_points)
    if tree is None:
        tree = build_tree(points)
    q = np.arange(n_points, dtype=np.int64) if query is None else np.asarray(query, np.int64)
    out_idx = np.full(q.size, -1, dtype=np.int64)
    out_dist = np.full(q.size, np.inf)
    k_max = min(n_points, 2 * theiler_window + 2)
    k = min(_FIRST_K, k_max)
    pending = np.arange(q.size)
    while pending.size:
        chunk = max(1, min(CHUNK_POINTS, _CHUNK_ENTRIES // k))
        unresolved = []
        for start in range(0, pending.size, chunk):
            sel = pending[start : start + chunk]
            qi = q[sel]
            dist, idx = tree.query(points[qi], k=k, p=p)
            if k == 1:
                dist, idx = dist[:, None], idx[:, None]
            ok = np.abs(idx - qi[:, None]) > theiler_window
            ok &= idx < n_points
            has = ok.any(axis=1)
            first = ok.argmax(axis=1)
            rows = np.flatnonzero(has)
            out_idx[sel[rows]] = idx[rows, first[rows]]
            out_dist[sel[rows]] = dist[rows, first[rows]]
            unresolved.append(sel[~has])
        pending = np.concatenate(unresolved)
        if pending.size and k >= k_max:  # cannot happen when check_theiler_window passed
            raise RuntimeError("neighbour search failed to resolve all points")
        k = min(4 * k, k_max)
    return out_idx, out_dist


def _grid_columns(m: int) -> np.ndarray:
    """Coordinates the grid is laid over: first, last and (m > 3) middle delay coordinate."""
    if m <= 3:
        return np.arange(m, dtype=np.int64)
    return np.array([0, m // 2, m - 1], dtype=np.int64)


def _grid(points: np.ndarray, cols: np.ndarray, cell: float):
    lo = points[:, cols].min(axis=0)
    span = points[:, cols].max(axis=0) - lo
    ncell = np.minimum(np.floor(span / cell).astype(np.int64) + 1, _GRID_MAX_CELLS)
    stride = np.ones(cols.size, dtype=np.int64)
    for d in range(1, cols.size):
        stride[d] = stride[d - 1] * ncell[d - 1]
    return lo, ncell, stride


def _cell_size(points: np.ndarray, cols: np.ndarray) -> float:
    """Cell edge giving about ``_GRID_OCCUPANCY`` points per cell, tuned on a strided pilot.

    The expected number of other points in a point's cell grows linearly with the number
    of points, so the occupancy of the pilot predicts that of the whole set.
    """
    n = points.shape[0]
    pilot = np.ascontiguousarray(points[:: max(1, n // _GRID_PILOT)])
    scale = n / pilot.shape[0]
    span = float(np.ptp(points[:, cols], axis=0).max())
    if span <= 0.0:
        return 1.0
    cell = span / max(1.0, n ** (1.0 / cols.size))
    for _ in range(40):
        lo, ncell, stride = _grid(pilot, cols, cell)
        keys = np.sort(_nk.cell_keys(pilot, cols, lo, cell, ncell, stride))
        occ = 1.0 + (_nk.occupancy(keys) - 1.0) * scale
        if occ > 2.0 * _GRID_OCCUPANCY and cell > span * 1e-9:
            cell *= 0.5
        elif occ < 0.5 * _GRID_OCCUPANCY and cell < span:
            cell *= 2.0
        else:
            break
    return cell


def grid_nearest_neighbors(
    points: np.ndarray,
    *,
    theiler_window: int,
    query: np.ndarray | None = None,
    p: float = 2.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Nearest neighbour of each query point with ``|i - j| > theiler_window``, box-assisted.

    The same neighbours as :func:`nearest_neighbors` (ties go to the smaller index), found
    on a uniform grid over up to three coordinates (TISEAN's box-assisted search, with
    rings of cells visited until no closer point can remain): the Theiler window costs
    one index comparison per excluded point, where the tree must return and discard them.

    Parameters
    ----------
    points
        ``(M, m)`` float64 array; row ``i`` is the state at sample ``i``.
    theiler_window
        Pairs with ``|i - j| <= theiler_window`` are excluded.
    query
        Row indices to find neighbours for (default: all rows).
    p
        ``2`` (Euclidean) or ``np.inf`` (maximum norm).

    Returns
    -------
    index, distance
        ``int64`` and ``float64`` arrays of the length of ``query``.

    Raises
    ------
    ValueError
        If the window leaves some point without an admissible neighbour, or ``p`` is
        neither 2 nor inf.
    """
    return GridSearch(points, theiler_window=theiler_window, p=p).query(query)


class GridSearch:
    """The grid of :func:`grid_nearest_neighbors`, built once and queried in parts.

    A caller that may stop early (a decision reached on part of the query points) asks
    for the neighbours of a few query points at a time; each answer is the one
    :func:`grid_nearest_neighbors` gives for that point.

    Parameters
    ----------
    points, theiler_window, p
        As for :func:`grid_nearest_neighbors`.
    """

    def __init__(self, points: np.ndarray, *, theiler_window: int, p: float = 2.0) -> None:
        if p not in (2, 2.0, np.inf):
            raise ValueError(f"p must be 2 or inf for the grid search; got {p!r}.")
        points = np.ascontiguousarray(points, dtype=np.float64)
        n_points = points.shape[0]
        check_theiler_window(theiler_window, n_points)
        cols = _grid_columns(points.shape[1])
        cell = _cell_size(points, cols)
        lo, ncell, stride = _grid(points, cols, cell)
        keys = _nk.cell_keys(points, cols, lo, cell, ncell, stride)
        total = int(np.prod(ncell))
        dense = total <= max(_GRID_TABLE, 8 * n_points)
        # the order inside a cell does not matter (ties go to the smaller index)
        order = _NO_ORDER if total <= _COUNTING_CELLS * n_points else np.argsort(keys)
        members, spts, unique, starts, slot = _nk.bucket(points, keys, order, total, dense)
        self.points = points
        self.theiler_window = int(theiler_window)
        self._grid = (cols, lo, float(cell), ncell, stride, unique, slot, starts, members)
        self._spts = spts
        self._maxnorm = p == np.inf

    def query(
        self,
        query: np.ndarray | None = None,
        *,
        limit: int | None = None,
        known: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Indices and distances of the nearest admissible neighbours of the rows ``query``
        (default: every row).

        Parameters
        ----------
        query
            Row indices (default: every row).
        limit
            Only rows ``j < limit`` are candidates (default: every row): the answers are
            those of a grid built over ``points[:limit]``, so one grid serves searches over
            leading parts of the same points.
        known
            ``int64`` array, one entry per row: a neighbour already found for this
            ``limit`` (−1: none). Those rows are answered without a search and seed the
            others; every answer found is written into it, so that a later call over
            more rows reuses them.
        """
        n_points = self.points.shape[0]
        q = np.arange(n_points, dtype=np.int64) if query is None else np.asarray(query, np.int64)
        limit = n_points if limit is None else int(limit)
        if not 0 < limit <= n_points:
            raise ValueError(f"limit must be in 1 … {n_points}; got {limit}.")
        if known is None:
            known = np.full(n_points, -1, dtype=np.int64)
        elif known.shape != (n_points,) or known.dtype != np.int64:
            raise ValueError(f"known must be an int64 array of {n_points} entries.")
        cols, lo, cell, ncell, stride, unique, slot, starts, members = self._grid
        return _nk.grid_query(
            self.points,
            self._spts,
            q,
            self.theiler_window,
            limit,
            known,
            cols,
            lo,
            cell,
            ncell,
            stride,
            unique,
            slot,
            starts,
            members,
            self._maxnorm,
        )


def radius_grid(points: np.ndarray, radius: float) -> tuple:
    """Points bucketed for a search of every point within ``radius`` (maximum norm).

    Cells at least ``radius`` wide over up to three coordinates (first, last and middle
    delay coordinate), so that a point's neighbours within ``radius`` lie in the 3^g cells
    around its own: TISEAN's box-assisted search for fixed-radius neighbourhoods.

    Returns
    -------
    members, spts, keys, starts, slot, grid
        The rows sorted by cell (inside a cell by the first coordinate) and their
        coordinates in that order, each occupied cell id
        and the offset of its first member (``starts`` has one more entry), the position of
        every cell id in ``keys`` (−1: empty; an empty array when the grid is too large for
        such a table), and ``(coordinates, lower corner, cell edge, cells per coordinate,
        strides)``: the arguments of the compiled kernels that read it.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    n_points = points.shape[0]
    cols = _grid_columns(points.shape[1])
    span = float(np.ptp(points[:, cols], axis=0).max()) if n_points else 0.0
    # never more cells than the ids hold: a coarser grid only adds candidates
    # (a hair wider than the radius, so that rounding of the cell index cannot lose one)
    cell = max(float(radius) * (1.0 + 1e-9), span / (_GRID_MAX_CELLS - 1), np.finfo(float).tiny)
    lo, ncell, stride = _grid(points, cols, cell)
    keys = _nk.cell_keys(points, cols, lo, cell, ncell, stride)
    # by cell, and inside a cell by the first coordinate: a search reads only the slab of
    # that coordinate within the radius (ties by index: lexsort is stable)
    members = np.lexsort((points[:, 0], keys)).astype(np.int64)
    sorted_keys = keys[members]
    first = np.flatnonzero(np.r_[True, sorted_keys[1:] != sorted_keys[:-1]])
    starts = np.append(first, n_points).astype(np.int64)
    unique = np.ascontiguousarray(sorted_keys[first])
    total = int(np.prod(ncell.astype(np.float64)))
    dense = total <= max(_GRID_TABLE, 8 * n_points)
    slot = _nk.slot_table(unique, total) if dense else np.empty(0, dtype=np.int32)
    grid = (cols, lo, float(cell), ncell, stride)
    return members, np.ascontiguousarray(points[members]), unique, starts, slot, grid


def mean_period(x: np.ndarray) -> float:
    """Mean period in samples, 1 / (power-weighted mean frequency) of the periodogram.

    Used as the default Theiler window (Rosenstein et al. 1993): neighbours closer in time
    than about one mean period lie on the same stretch of trajectory.
    """
    y = x - x.mean()
    power = np.abs(np.fft.rfft(y)) ** 2
    freq = np.fft.rfftfreq(y.size)
    total = power[1:].sum()
    if total <= 0.0:
        return 1.0
    return float(total / (freq[1:] * power[1:]).sum())


def default_theiler_window(x: np.ndarray, n_points: int) -> int:
    """``ceil(mean_period(x))`` capped at ``n_points // 10`` so that neighbours remain."""
    w = int(np.ceil(mean_period(x)))
    return int(max(1, min(w, n_points // 10)))
