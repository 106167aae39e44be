"""Recurrence quantification: analytic cases and pyunicorn's numbers on the same matrix."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest
from scipy.signal import find_peaks

from chaoskit import plot, recurrence_analysis, systems

PERIOD = 50


def test_sine_is_deterministic_with_diagonals_one_period_apart() -> None:
    x = np.sin(2 * np.pi * np.arange(2000) / PERIOD)
    res = recurrence_analysis(x, embedding_dim=2, lag=PERIOD // 4, threshold=0.1)
    assert res.determinism == pytest.approx(1.0, abs=1e-12)
    peaks, _ = find_peaks(res.tau_recurrence, height=0.5 * res.tau_recurrence.max())
    np.testing.assert_array_equal(np.diff(peaks), PERIOD)  # one spacing, the period
    assert peaks[0] == PERIOD
    assert res.max_diagonal == res.n_points - PERIOD  # the first off-diagonal line is whole


def test_white_noise_determinism_follows_from_its_recurrence_rate() -> None:
    # iid samples, m = 1: a recurrence's diagonal neighbours recur independently with
    # probability RR, so the share of points on lines of length ≥ 2 is 1 − (1 − RR)²
    x = np.random.default_rng(5).standard_normal(6000)
    res = recurrence_analysis(x, recurrence_rate=0.05, rng=1)
    np.testing.assert_allclose(res.recurrence_rate, 0.05, rtol=0.02)
    expected = 1.0 - (1.0 - res.recurrence_rate) ** 2
    np.testing.assert_allclose(res.determinism, expected, rtol=0.03)


def test_theiler_window_and_recurrence_rate_count_admissible_pairs() -> None:
    x = systems.lorenz(800, dt=0.02)[:, 0]
    w, eps = 5, 2.0
    res = recurrence_analysis(x, embedding_dim=3, lag=4, threshold=eps, theiler_window=w)
    y = res.matrix.toarray()
    pts = np.column_stack([x[k * 4 : k * 4 + res.n_points] for k in range(3)])
    d = np.linalg.norm(pts[:, None, :] - pts[None, :, :], axis=2)
    i, j = np.indices(d.shape)
    brute = (d <= eps) & (np.abs(i - j) > w)
    np.testing.assert_array_equal(y, brute)
    np.testing.assert_allclose(res.recurrence_rate, brute.sum() / (np.abs(i - j) > w).sum())
    assert np.all(res.tau_recurrence[: w + 1] == 0.0)


def _series():
    rng = np.random.default_rng(11)
    return {
        "sine": (np.sin(2 * np.pi * np.arange(1500) / PERIOD), 2, PERIOD // 4, 0.1),
        "henon": (systems.henon(1500)[:, 0], 2, 1, 0.2),
        "noise": (rng.standard_normal(1500), 1, 1, 0.1),
    }


@pytest.mark.parametrize("name", ["sine", "henon", "noise"])
def test_same_measures_as_pyunicorn(name) -> None:
    timeseries = pytest.importorskip("pyunicorn.timeseries")
    x, m, lag, eps = _series()[name]
    ours = recurrence_analysis(x, embedding_dim=m, lag=lag, threshold=eps, norm="chebyshev")
    rp = timeseries.RecurrencePlot(
        x, metric="supremum", threshold=eps, dim=m, tau=lag, silence_level=3
    )
    n = rp.N
    assert n == ours.n_points
    rmat = rp.recurrence_matrix()
    # pyunicorn keeps the main diagonal in R (and in RR and vertical lines); remove it so
    # both count the same recurrences (its diagonal-line measures already skip it)
    np.testing.assert_allclose(ours.recurrence_rate, (rmat.sum() - n) / (n * n - n), rtol=1e-12)
    theirs = {
        "DET": rp.determinism(),
        "L": rp.average_diaglength(),
        "L_max": rp.max_diaglength(),
        "ENTR": rp.diag_entropy(),
    }
    rmat[np.diag_indices(n)] = 0
    theirs |= {"LAM": rp.laminarity(), "TT": rp.trapping_time(), "V_max": rp.max_vertlength()}
    got = ours.measures()
    for key, value in theirs.items():
        np.testing.assert_allclose(got[key], value, rtol=1e-9, err_msg=key)


def test_dataset_and_plot() -> None:
    res = recurrence_analysis(systems.henon(1000)[:, 0], recurrence_rate=0.05)
    ds = res.to_dataset()
    for var in ds.variables:
        assert "units" in ds[var].attrs and "long_name" in ds[var].attrs, var
    assert ds["diagonal_lines"].values @ ds["line_length"].values == res.matrix.nnz
    ax = plot.recurrence_plot(res)
    ax.figure.canvas.draw()
    assert ax.images
    plt.close(ax.figure)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"threshold": 0.1, "recurrence_rate": 0.1}, "not both"),
        ({"threshold": -1.0}, "threshold"),
        ({"recurrence_rate": 1.5}, "recurrence_rate"),
        ({"min_line": 0}, "min_line"),
        ({"theiler_window": -2}, "theiler_window"),
        ({"norm": "cosine"}, "norm"),
        ({"embedding_dim": 0}, "embedding_dim"),
    ],
)
def test_bad_input(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        recurrence_analysis(np.sin(np.arange(300.0)), **kwargs)
