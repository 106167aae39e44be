"""Wolf's compiled replacement search against a brute-force reference of the same rule."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from numpy.testing import assert_allclose

from chaoskit import lyapunov_wolf, systems
from chaoskit.lyapunov import _kernels as _k
from chaoskit.lyapunov import _wolf


def _reference(pts, members, fid, old, w, lower, upper, dlt, widen, cos_max, stop):
    """The selection rule written out in numpy over every candidate."""
    cand = members[(np.abs(members - fid) > w) & (members + 1 < stop)]
    vec = pts[cand] - pts[fid]
    dist = np.sqrt((vec**2).sum(axis=1))
    norm_old = np.sqrt(old @ old)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = (vec @ old) / (dist * norm_old) if norm_old > 0 else np.ones(cand.size)
    ok = (dist >= lower) & (dist <= upper + widen * dlt) & (cos >= cos_max)
    if norm_old > 0:
        ok &= dist > 0
    if not ok.any():
        return -1
    level = np.where(dist > upper, np.ceil((dist - upper) / dlt), 0.0)[ok]
    # lowest level, then largest cosine, then nearest, then earliest
    order = np.lexsort((cand[ok], dist[ok] ** 2, -cos[ok], level))
    return int(cand[ok][order[0]])


@pytest.mark.parametrize("m", [1, 2, 3, 5])
@pytest.mark.parametrize("cell_factor", [0.1, 1 / 3, 1.0, 10.0])
def test_band_search_matches_brute_force(m: int, cell_factor: float) -> None:
    rng = np.random.default_rng(m)
    n = 3000
    pts = np.ascontiguousarray(rng.standard_normal((n, m)) * np.linspace(1.0, 0.3, m))
    if m == 1:  # ties in the cosine (all ±1): the distance and index must break them
        pts = np.round(pts, 2)
    lower, upper, dlt, widen = 0.05, 0.2, 0.1, 5
    grid = _wolf._pool_grid(pts, cell_factor * upper, 2000)
    members = np.sort(grid[6])
    for trial in range(200):
        fid = int(rng.integers(0, n))
        old = rng.standard_normal(m) if trial % 10 else np.zeros(m)
        cos_max = np.cos(rng.uniform(0.2, 1.2))
        norm_old = float(np.sqrt(old @ old))
        wide = upper + widen * dlt
        got, _, _ = _k._band_scan(
            pts, fid, old, norm_old, 7, lower, wide, upper, dlt, cos_max, n - 5, grid, True
        )
        want = _reference(pts, members, fid, old, 7, lower, upper, dlt, widen, cos_max, n - 5)
        assert got == want, (trial, fid)


def test_nearest_beyond_matches_brute_force() -> None:
    rng = np.random.default_rng(3)
    pts = np.ascontiguousarray(rng.standard_normal((500, 2)))
    members = np.arange(0, 500, 2, dtype=np.int64)
    for fid in range(0, 500, 37):
        got = _k._nearest_beyond(pts, fid, 4, 0.3, 490, members)
        cand = members[(np.abs(members - fid) > 4) & (members + 1 < 490)]
        dist = np.linalg.norm(pts[cand] - pts[fid], axis=1)
        assert got == cand[dist >= 0.3][np.argmin(dist[dist >= 0.3])]


@pytest.mark.parametrize(
    ("x", "dt"),
    [(systems.henon(4000)[:, 0], 1.0), (systems.lorenz(8000)[:, 0], 0.01)],
    ids=["henon", "lorenz"],
)
def test_estimate_does_not_depend_on_the_grid(monkeypatch, x, dt) -> None:
    """The grid only prefilters candidates: any cell size gives the same replacements."""
    base = lyapunov_wolf(x, dt=dt)
    for factor in (0.1, 3.0):
        monkeypatch.setattr(_wolf, "_CELL_FACTOR", factor)
        res = lyapunov_wolf(x, dt=dt)
        assert res.n_points == base.n_points
        assert_allclose(res.mle, base.mle, rtol=1e-12)


def test_wolf_compiles_its_search_kernels_once(tmp_path) -> None:
    """The replacement search is called with typed indices and flags: a constant argument
    would be typed as its literal and compile the kernel once more per constant. Counted
    in a child process with an empty cache (kernels loaded from a cache by their caller
    list no signatures)."""
    child = (
        "import json\n"
        "from chaoskit import lyapunov_wolf, systems\n"
        "from chaoskit.lyapunov import _kernels as k\n"
        "lyapunov_wolf(systems.henon(3000)[:, 0])\n"
        "lyapunov_wolf(systems.lorenz(3000)[:, 0], dt=0.01)\n"
        "names = ('_band_scan', '_nearest_beyond', 'evolve_pair')\n"
        "print(json.dumps({n: len(getattr(k, n).signatures) for n in names}))\n"
    )
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_NUM_THREADS": "1"}
    run = subprocess.run(
        [sys.executable, "-c", child], env=env, capture_output=True, text=True, check=True
    )
    counts = json.loads(run.stdout.strip().splitlines()[-1])
    assert counts == {"_band_scan": 1, "_nearest_beyond": 1, "evolve_pair": 1}
