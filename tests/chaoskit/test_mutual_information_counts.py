"""The compiled mutual-information curve against a NumPy histogram estimate."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from chaoskit import mutual_information, systems


def _numpy_mi(x: np.ndarray, max_lag: int, bins: int) -> np.ndarray:
    """I(τ) = Σ p_ab ln(p_ab / (p_a p_b)) from NumPy's histograms on the same bins."""
    lo, hi = x.min(), x.max()
    codes = np.minimum(((x - lo) / (hi - lo) * bins).astype(int), bins - 1)
    out = []
    for lag in range(max_lag + 1):
        a, b = codes[: x.size - lag], codes[lag:]
        joint = np.bincount(a * bins + b, minlength=bins * bins).reshape(bins, bins)
        p = joint / a.size
        pa, pb = p.sum(axis=1), p.sum(axis=0)
        nz = p > 0
        out.append(float((p[nz] * np.log(p[nz] / np.outer(pa, pb)[nz])).sum()))
    return np.array(out)


@pytest.mark.parametrize("bins", [2, 16, 37])
@pytest.mark.parametrize(
    "x",
    [
        systems.henon(3000)[:, 0],
        np.sin(0.07 * np.arange(2500)) + 0.1 * np.random.default_rng(1).standard_normal(2500),
        np.random.default_rng(2).standard_normal(2000),
    ],
    ids=["henon", "noisy-sine", "noise"],
)
def test_curve_matches_numpy_histograms(x: np.ndarray, bins: int) -> None:
    """Marginals taken as the joint's row and column sums: the same counts as per pair."""
    got = mutual_information(x, max_lag=40, bins=bins).curve
    assert_allclose(got, _numpy_mi(x, 40, bins), rtol=1e-12, atol=1e-15)
