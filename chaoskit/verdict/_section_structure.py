"""Structure of a section: a few distinct clusters, a closed curve, or a scattered set."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from scipy.cluster.hierarchy import fcluster, linkage
from scipy.sparse.csgraph import dijkstra, minimum_spanning_tree
from scipy.spatial.distance import pdist, squareform

from .._validate import check_int, check_positive

__all__ = ["SectionStructure", "section_structure"]

StructureKind = Literal["clusters", "closed-curve", "scattered", "too-few-points"]


@dataclass(frozen=True, kw_only=True)
class SectionStructure:
    """What the points of a Poincaré or stroboscopic set look like.

    Attributes
    ----------
    kind
        ``"clusters"`` (a period-``n_clusters`` orbit), ``"closed-curve"`` (points filling
        a closed curve: quasi-periodic), ``"scattered"`` (neither) or ``"too-few-points"``.
    n_clusters
        Number of distinct clusters (0 unless ``kind == "clusters"``).
    labels
        Cluster label of each point, in time order (all 0 unless ``kind == "clusters"``).
    cluster_radius
        Largest RMS radius of a cluster, in units of ``scale`` (NaN unless clusters).
    cyclic_fraction
        Fraction of points whose label equals the label ``n_clusters`` points later.
    curve_closure
        Distance between the two ends of the longest path of the minimum spanning tree,
        over the 95th percentile of its edge lengths (small for a closed curve; NaN if not
        computed).
    curve_coverage
        Fraction of points on that longest path.
    curve_thickness
        95th percentile of the distance of the other points to the path, over the path
        length divided by 2π.
    n_points
        Points analysed.
    scale
        Length scale of the motion used to judge tightness (e.g. the standard deviation of
        the signal).
    """

    kind: StructureKind
    n_clusters: int
    labels: np.ndarray
    cluster_radius: float
    cyclic_fraction: float
    curve_closure: float
    curve_coverage: float
    curve_thickness: float
    n_points: int
    scale: float


def _cluster_radius(points: np.ndarray, labels: np.ndarray) -> float:
    radius = 0.0
    for lab in np.unique(labels):
        members = points[labels == lab]
        r = float(np.sqrt(np.mean(np.sum((members - members.mean(axis=0)) ** 2, axis=1))))
        radius = max(radius, r)
    return radius


def _periodic_clusters(
    points: np.ndarray, *, max_clusters: int, tol: float, min_cyclic: float
) -> tuple[int, np.ndarray, float, float] | None:
    """Smallest k whose clusters are all tight and visited in a fixed cyclic order."""
    n = points.shape[0]
    tree = linkage(points, method="ward")
    for k in range(1, min(max_clusters, n // 3) + 1):
        labels = fcluster(tree, t=k, criterion="maxclust") - 1
        if np.unique(labels).size != k:
            continue
        radius = _cluster_radius(points, labels)
        if radius > tol:
            continue
        cyclic = 1.0 if k == 1 else float(np.mean(labels[k:] == labels[:-k]))
        if cyclic >= min_cyclic:
            return k, labels, radius, cyclic
    return None


def _closed_curve(points: np.ndarray) -> tuple[float, float, float]:
    """Closure, coverage and thickness of the longest path through the spanning tree."""
    dist = squareform(pdist(points))
    tree = minimum_spanning_tree(dist)
    tree = tree + tree.T
    # The longest path of a tree: farthest node from any node, then farthest from that one.
    d0 = dijkstra(tree, indices=0)
    a = int(np.argmax(np.where(np.isfinite(d0), d0, -1.0)))
    da, pred = dijkstra(tree, indices=a, return_predecessors=True)
    b = int(np.argmax(np.where(np.isfinite(da), da, -1.0)))
    path = [b]
    while path[-1] != a:
        path.append(int(pred[path[-1]]))
    path_arr = np.array(path)
    edges = dist[path_arr[:-1], path_arr[1:]]
    if edges.size == 0:
        return np.inf, 0.0, np.inf
    closure = float(dist[a, b] / max(np.percentile(edges, 95), np.finfo(float).tiny))
    length = float(edges.sum())
    off = np.setdiff1d(np.arange(points.shape[0]), path_arr)
    if off.size:
        gap = np.min(dist[np.ix_(off, path_arr)], axis=1)
        thickness = float(np.percentile(gap, 95) / (length / (2.0 * np.pi)))
    else:
        thickness = 0.0
    return closure, path_arr.size / points.shape[0], thickness


def section_structure(
    points: Any,
    *,
    scale: float | None = None,
    max_clusters: int = 32,
    cluster_tol: float = 0.1,
    min_cyclic: float = 0.9,
    max_closure: float = 3.0,
    min_coverage: float = 0.5,
    max_thickness: float = 0.1,
    max_points: int = 1000,
    min_points: int = 20,
) -> SectionStructure:
    r"""Classify a set of section points (rows, in time order) by its geometry.

    **Clusters.** Ward's hierarchical clustering is cut into :math:`k = 1, 2, \ldots`
    clusters; the first :math:`k` for which every cluster's RMS radius is at most
    ``cluster_tol * scale`` *and* the labels repeat with period :math:`k`
    (:math:`L_{n+k} = L_n` for at least ``min_cyclic`` of the points) is a period-:math:`k`
    orbit. The cyclic-order condition is what a periodic orbit does and a chaotic band
    split into small pieces does not.

    **Closed curve.** Otherwise the longest path :math:`P` of the Euclidean minimum spanning
    tree is taken as the backbone of the set. Points filling a closed curve give a path that
    runs once around the curve, so its two ends are neighbours (``curve_closure``, the end
    gap over the 95th-percentile path edge, at most ``max_closure``), it holds most points
    (``curve_coverage >= min_coverage``) and the rest lie close to it (``curve_thickness``,
    the 95th-percentile distance to the path over its length / 2π, at most
    ``max_thickness``). An arc (the section of a Rössler band), a fractal set or a cloud fails
    one of these.

    Parameters
    ----------
    points
        ``(n, d)`` array of points in time order (a 1-D array is one coordinate).
    scale
        Length scale of the motion; cluster radii are compared with ``cluster_tol * scale``.
        Default: the RMS distance of the points from their centroid (give the signal's
        standard deviation when the set may be a single point).
    max_clusters
        Largest period looked for.
    max_points
        Only the last ``max_points`` points are analysed (the cost is quadratic).
    min_points
        Fewer points give ``kind="too-few-points"``.

    Returns
    -------
    SectionStructure

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import section_structure, systems
    >>> x = systems.logistic(400, r=3.5)
    >>> s = section_structure(np.column_stack([x[:-1], x[1:]]))
    >>> s.kind, s.n_clusters
    ('clusters', 4)
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2:
        raise ValueError(f"points must be an (n, d) array; got shape {pts.shape}.")
    if not np.all(np.isfinite(pts)):
        raise ValueError("points contain NaN or inf values.")
    max_clusters = check_int(max_clusters, name="max_clusters", minimum=1)
    max_points = check_int(max_points, name="max_points", minimum=3)
    min_points = check_int(min_points, name="min_points", minimum=3)
    pts = pts[-max_points:]
    n = pts.shape[0]
    spread = float(np.sqrt(np.mean(np.sum((pts - pts.mean(axis=0)) ** 2, axis=1)))) if n else 0.0
    scale = spread if scale is None else check_positive(scale, name="scale")
    nan = float("nan")
    empty = np.zeros(n, dtype=np.int64)
    if n < min_points:
        return SectionStructure(
            kind="too-few-points", n_clusters=0, labels=empty, cluster_radius=nan,
            cyclic_fraction=nan, curve_closure=nan, curve_coverage=nan, curve_thickness=nan,
            n_points=n, scale=scale,
        )  # fmt: skip
    if scale == 0.0:  # every point identical: one cluster
        return SectionStructure(
            kind="clusters", n_clusters=1, labels=empty, cluster_radius=0.0,
            cyclic_fraction=1.0, curve_closure=nan, curve_coverage=nan, curve_thickness=nan,
            n_points=n, scale=scale,
        )  # fmt: skip
    unit = pts / scale
    found = _periodic_clusters(
        unit, max_clusters=max_clusters, tol=cluster_tol, min_cyclic=min_cyclic
    )
    if found is not None:
        k, labels, radius, cyclic = found
        return SectionStructure(
            kind="clusters", n_clusters=k, labels=labels.astype(np.int64),
            cluster_radius=radius, cyclic_fraction=cyclic, curve_closure=nan,
            curve_coverage=nan, curve_thickness=nan, n_points=n, scale=scale,
        )  # fmt: skip
    closure, coverage, thickness = _closed_curve(unit)
    closed = closure <= max_closure and coverage >= min_coverage and thickness <= max_thickness
    return SectionStructure(
        kind="closed-curve" if closed else "scattered", n_clusters=0, labels=empty,
        cluster_radius=nan, cyclic_fraction=nan, curve_closure=closure,
        curve_coverage=coverage, curve_thickness=thickness, n_points=n, scale=scale,
    )  # fmt: skip
