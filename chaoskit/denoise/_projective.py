"""Local projective noise reduction (Grassberger, Hegger, Kantz, Schaffrath & Schreiber 1993)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["END_WEIGHT", "MIN_NEIGHBORS", "correction_pass", "embed", "local_spectrum"]

#: Weight of the first and last delay coordinates in the correction (TISEAN ghkss): they
#: are the least constrained by the dynamics (no past before the first, no future after the
#: last), so the correction is put on the middle coordinates.
END_WEIGHT = 1e-3
#: Every neighbourhood holds at least this many points (TISEAN ghkss ``-k``): fewer make
#: the local covariance, and so the projection, a fit to the noise.
MIN_NEIGHBORS = 30
#: At most this many neighbours per neighbourhood: bounds the cost when the radius is large.
MAX_NEIGHBORS = 200
_CHUNK = 4096  # reference points per block (block arrays of a few MB)


def embed(x: np.ndarray, m: int, lag: int) -> np.ndarray:
    """Delay vectors ``(x_i, x_{i+lag}, …, x_{i+(m-1)lag})`` as a contiguous (M, m) array."""
    span = (m - 1) * lag
    n = x.size - span
    return np.ascontiguousarray(np.stack([x[j * lag : j * lag + n] for j in range(m)], axis=1))


def _neighbourhoods(
    pts: np.ndarray,
    tree: cKDTree,
    rows: np.ndarray,
    *,
    radius: float,
    min_neighbors: int,
    theiler_window: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Neighbours of ``pts[rows]``: those within ``radius`` (at most :data:`MAX_NEIGHBORS`),
    at least the ``min_neighbors`` nearest; pairs with ``|i - j| <= theiler_window`` are
    excluded. Returns an index array (len(rows), K) padded with -1 and the count per row."""
    k_query = min(pts.shape[0], MAX_NEIGHBORS + 2 * theiler_window + 1)
    dist, idx = tree.query(pts[rows], k=k_query)
    ok = np.abs(idx - rows[:, None]) > theiler_window
    rank = np.cumsum(ok, axis=1)
    keep = ok & ((dist <= radius) | (rank <= min_neighbors)) & (rank <= MAX_NEIGHBORS)
    count = keep.sum(axis=1)
    width = int(count.max()) if count.size else 0
    order = np.argsort(~keep, axis=1, kind="stable")[:, :width]
    nbr = np.take_along_axis(idx, order, axis=1)
    nbr[np.take_along_axis(~keep, order, axis=1)] = -1
    return nbr, count


def _local_covariance(pts: np.ndarray, nbr: np.ndarray, count: np.ndarray):
    """Centre of mass and covariance of each neighbourhood (padding ``-1`` ignored)."""
    mask = (nbr >= 0)[:, :, None]
    block = np.where(mask, pts[np.maximum(nbr, 0)], 0.0)
    centre = block.sum(axis=1) / count[:, None]
    dev = np.where(mask, block - centre[:, None, :], 0.0)
    cov = np.einsum("kni,knj->kij", dev, dev) / count[:, None, None]
    return centre, cov


def local_spectrum(
    pts: np.ndarray, tree: cKDTree, rows: np.ndarray, *, min_neighbors: int, theiler_window: int
) -> np.ndarray:
    """Eigenvalues (descending) of the local covariance of the ``min_neighbors`` nearest
    neighbours of each of ``pts[rows]``: the local singular-value spectrum squared."""
    nbr, count = _neighbourhoods(
        pts, tree, rows, radius=0.0, min_neighbors=min_neighbors, theiler_window=theiler_window
    )
    _, cov = _local_covariance(pts, nbr, count)
    return np.linalg.eigvalsh(cov)[:, ::-1]


def correction_pass(
    x: np.ndarray,
    *,
    m: int,
    lag: int,
    q: int,
    radius: float,
    min_neighbors: int,
    theiler_window: int,
    curvature: bool = True,
) -> np.ndarray:
    """One GHKSS pass: the correction to add to each sample of ``x``.

    Each delay vector is moved towards the ``q``-dimensional subspace spanned by the
    leading directions of its neighbourhood's weighted covariance (through the
    neighbourhood's centre of mass); with ``curvature`` the mean correction of the
    neighbours is subtracted (the centre of mass lies on the concave side of a curved
    manifold). The correction of a sample is the mean of the corrections it receives in the
    delay vectors where it is a middle coordinate.
    """
    pts = embed(x, m, lag)
    n_pts = pts.shape[0]
    tree = cKDTree(pts, leafsize=16, balanced_tree=False, compact_nodes=False)
    weight = np.ones(m)
    weight[0] = weight[-1] = 1.0 / END_WEIGHT
    theta = np.zeros_like(pts)
    blocks = []
    for start in range(0, n_pts, _CHUNK):
        rows = np.arange(start, min(start + _CHUNK, n_pts), dtype=np.int64)
        nbr, count = _neighbourhoods(
            pts,
            tree,
            rows,
            radius=radius,
            min_neighbors=min_neighbors,
            theiler_window=theiler_window,
        )
        centre, cov = _local_covariance(pts, nbr, count)
        gamma = cov * weight[None, :, None] * weight[None, None, :]
        _, vec = np.linalg.eigh(gamma)  # ascending: the first m - q span the normal space
        normal = vec[:, :, : m - q]
        dev = (pts[rows] - centre) * weight
        proj = np.einsum("kiq,kq->ki", normal, np.einsum("kiq,ki->kq", normal, dev))
        theta[rows] = -proj / weight
        blocks.append((rows, nbr.astype(np.int32), count))  # kept for the curvature step
    if curvature:
        # the centre of mass lies off the manifold, on its concave side; the neighbours'
        # mean correction measures that offset, so it is taken out
        shift = np.zeros_like(theta)
        for rows, nbr, count in blocks:
            mask = (nbr >= 0)[:, :, None]
            shift[rows] = (
                np.where(mask, theta[np.maximum(nbr, 0)], 0.0).sum(axis=1) / count[:, None]
            )
        theta = theta - shift
    total = np.zeros(x.size)
    hits = np.zeros(x.size)
    for j in range(1, m - 1):  # middle coordinates only
        total[j * lag : j * lag + n_pts] += theta[:, j]
        hits[j * lag : j * lag + n_pts] += 1.0
    return np.where(hits > 0, total / np.maximum(hits, 1.0), 0.0)
