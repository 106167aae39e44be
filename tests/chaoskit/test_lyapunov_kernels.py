"""Rosenstein's divergence-curve kernels against a brute-force numpy reference."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from chaoskit import systems
from chaoskit.embedding import embed, standardize
from chaoskit.lyapunov import _kernels as _k


def _brute_curve(pts, ref, nbr, ks, shift, orbit):
    """Σ ln d_k and the number of terms per horizon, straight from the definition."""
    n = pts.shape[0]
    total = np.zeros(ks.size)
    count = np.zeros(ks.size, dtype=np.int64)
    for i, j, s in zip(ref, nbr, shift, strict=True):
        for q, k in enumerate(ks):
            if i + k >= n or j + k + (1 if orbit else 0) >= n:
                continue
            y = pts[j + k]
            if orbit:
                # the orbit point y(j + k + s), quadratic through the three samples around it
                prev = pts[max(j + k - 1, 0)]
                y = 0.5 * s * (s - 1.0) * prev + (1.0 - s * s) * y
                y = y + 0.5 * s * (s + 1.0) * pts[j + k + 1]
            d2 = float(((y - pts[i + k]) ** 2).sum())
            if d2 > 0.0:
                total[q] += 0.5 * np.log(d2)
                count[q] += 1
    return total, count


def _pairs():
    """Lorenz pairs (a reference and a nearby sample) plus pairs at the data's edges."""
    x = standardize(systems.lorenz(2000, dt=0.01)[:, 0])
    pts = embed(x, 3, 7)
    n = pts.shape[0]
    rng = np.random.default_rng(5)
    ref = rng.integers(0, n, 150)
    nbr = np.clip(ref + rng.integers(-400, 400, ref.size), 1, n - 1)
    shift = rng.uniform(-1.0, 1.0, ref.size)
    # a neighbour at the first sample (no sample before it: no shift), pairs near the end
    ref = np.r_[ref, 10, n - 3, n - 60, 4]
    nbr = np.r_[nbr, 0, 20, n - 1, n - 2]
    shift = np.r_[shift, 0.0, 0.4, -0.3, 0.2]
    return pts, ref.astype(np.int64), nbr.astype(np.int64), shift


GRIDS = {
    "step 1": np.arange(0, 120),
    "step 2": np.r_[np.arange(0, 161, 2), 161],
    "step 3 from 3": np.arange(3, 200, 3),
    "step 5": np.arange(0, 250, 5),
    "uneven tail": np.r_[np.arange(0, 60, 2), np.arange(61, 90)],
    "two": np.array([0, 1]),
}


@pytest.mark.parametrize("orbit", [False, True])
@pytest.mark.parametrize("grid", list(GRIDS))
def test_log_divergence_matches_brute_force(grid: str, orbit: bool) -> None:
    """Sample and orbit curves on uniform steps (the phase-split path) and uneven grids
    (gathered) against the definition, within 1e-12; the counts exactly."""
    pts, ref, nbr, shift = _pairs()
    ks = GRIDS[grid].astype(np.int64)
    total, count = _k.log_divergence(pts, ref, nbr, ks, _k.ORBIT if orbit else _k.EUCLIDEAN, shift)
    expect, expect_count = _brute_curve(pts, ref, nbr, ks, shift, orbit)
    assert (count == expect_count).all()
    assert count[0] > 100
    assert_allclose(total, expect, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("grid", list(GRIDS))
def test_both_curves_in_one_pass_are_those_of_their_own_passes(grid: str) -> None:
    """The fused sample-and-orbit pass gives each curve bit for bit."""
    pts, ref, nbr, shift = _pairs()
    ks = GRIDS[grid].astype(np.int64)
    total, count = _k.sample_orbit_log_divergence(pts, ref, nbr, ks, shift)
    for row, mode in enumerate((_k.EUCLIDEAN, _k.ORBIT)):
        alone, alone_count = _k.log_divergence(pts, ref, nbr, ks, mode, shift)
        assert np.array_equal(total[row], alone)
        assert np.array_equal(count[row], alone_count)


def test_phase_columns_split_the_samples_by_phase() -> None:
    pts = np.arange(14.0).reshape(7, 2)
    out = _k.phase_columns(pts, 3)
    assert out.shape == (3, 2, 3)
    assert out[1, 0].tolist() == [2.0, 8.0, 0.0]  # rows 1 and 4; past the end: zero
    assert out[0, 1].tolist() == [1.0, 7.0, 13.0]  # rows 0, 3 and 6
