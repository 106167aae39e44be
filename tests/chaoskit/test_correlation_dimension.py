"""Correlation dimension: known D2 of standard attractors and nolds' correlation sums."""

from __future__ import annotations

import matplotlib.pyplot as plt
import nolds
import numpy as np
import pytest

import chaoskit
from chaoskit import correlation_dimension, plot, systems

N = 20_000


@pytest.mark.parametrize(
    ("name", "series", "lag", "expected"),
    [
        # Grassberger & Procaccia (1983): Hénon 1.21 ± 0.01, logistic (r = 4) 1.0,
        # Lorenz 2.05 ± 0.01; a two-frequency torus is a smooth 2-surface
        ("henon", lambda: systems.henon(N)[:, 0], 1, 1.21),
        ("logistic", lambda: systems.logistic(N), 1, 1.0),
        ("lorenz", lambda: systems.lorenz(N, dt=0.01)[:, 0], None, 2.05),
        ("torus", lambda: systems.torus(N, dt=0.37), None, 2.0),
    ],
)
def test_known_correlation_dimensions_within_5_percent(name, series, lag, expected) -> None:
    res = correlation_dimension(series(), lag=lag)
    assert res.scaling_found, name
    assert res.saturated, name
    np.testing.assert_allclose(res.d2, expected, rtol=0.05, err_msg=name)
    assert res.interval[0] <= res.d2 <= res.interval[1]


def test_white_noise_does_not_saturate() -> None:
    x = np.random.default_rng(3).standard_normal(5000)
    res = correlation_dimension(x, embedding_dims=[1, 2, 3, 4, 5], lag=1)
    assert not res.saturated
    # the slope follows the embedding dimension: noise fills every dimension offered
    np.testing.assert_allclose(res.dimension_by_dim, [1, 2, 3, 4, 5], rtol=0.15)


@pytest.mark.parametrize("system", ["henon", "lorenz"])
def test_same_correlation_sums_as_nolds(system) -> None:
    n = 2000
    x = systems.henon(n)[:, 0] if system == "henon" else systems.lorenz(n, dt=0.02)[:, 0]
    lag, m = (1, 3) if system == "henon" else (5, 4)
    sd = np.std(x, ddof=1)
    rvals = nolds.logarithmic_r(0.1 * sd, 0.5 * sd, 1.03)
    _, (_, log_c, _) = nolds.corr_dim(x, m, lag=lag, rvals=rvals, fit="poly", debug_data=True)
    res = correlation_dimension(
        x,
        embedding_dims=[m],
        lag=lag,
        theiler_window=0,
        radii=rvals,
        norm="euclidean",
        pairs_per_radius=None,
    )
    # nolds counts the N zero self-distances too and divides by N(N-1) ordered pairs
    pts = n - (m - 1) * lag
    theirs = np.exp(log_c)
    ours = (2 * res.pairs[0] + pts) / (pts * (pts - 1))
    np.testing.assert_allclose(ours, theirs, rtol=1e-12)
    np.testing.assert_allclose(res.correlation_sum[0], 2 * res.pairs[0] / (pts * (pts - 1)))


def test_sampled_sums_agree_with_exact_ones() -> None:
    x = systems.henon(4000)[:, 0]
    kw = {"embedding_dims": [1, 2, 3], "lag": 1, "theiler_window": 2}
    exact = correlation_dimension(x, pairs_per_radius=None, **kw)
    sampled = correlation_dimension(x, pairs_per_radius=2000, rng=1, **kw)
    enough = exact.pairs >= 2000
    # a radius that stopped early holds ≥ 2000 pairs: ~2-3 % statistical error, 4σ bound
    np.testing.assert_allclose(
        sampled.correlation_sum[enough], exact.correlation_sum[enough], rtol=0.12
    )
    np.testing.assert_array_equal(sampled.pairs[~enough], exact.pairs[~enough])


def test_theiler_window_removes_exactly_the_close_pairs() -> None:
    x = systems.lorenz(600, dt=0.02)[:, 0]
    w, m, lag = 7, 3, 4
    res = correlation_dimension(
        x, embedding_dims=[m], lag=lag, theiler_window=w, norm="chebyshev", pairs_per_radius=None
    )
    y = chaoskit.delay_embed(x, embedding_dim=m, lag=lag)
    d = np.max(np.abs(y[:, None, :] - y[None, :, :]), axis=2)
    i, j = np.triu_indices(y.shape[0], k=w + 1)
    brute = np.array([(d[i, j] <= r).sum() for r in res.radius])
    np.testing.assert_array_equal(res.pairs[0], brute)
    np.testing.assert_allclose(res.correlation_sum[0][brute > 0], brute[brute > 0] / i.size)


def test_user_scaling_range_and_dataset() -> None:
    x = systems.henon(5000)[:, 0]
    res = correlation_dimension(x, embedding_dims=[1, 2], lag=1, scaling_range=(0.01, 0.2))
    assert 0.01 <= res.scaling_range[0] < res.scaling_range[1] <= 0.2
    ds = res.to_dataset()
    assert ds["correlation_sum"].dims == ("embedding_dim", "radius")
    for name in ds.variables:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    assert ds.attrs["d2"] == res.d2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"embedding_dims": [3, 2]}, "embedding_dims"),
        ({"embedding_dims": []}, "embedding_dims"),
        ({"lag": 0}, "lag"),
        ({"theiler_window": -1}, "theiler_window"),
        ({"norm": "manhattan"}, "norm"),
        ({"pairs_per_radius": 10}, "pairs_per_radius"),
        ({"radii": [0.1, 0.05, 0.2]}, "radii"),
        ({"scaling_range": (0.2, 0.1)}, "scaling_range"),
        ({"theiler_window": 400}, "too short"),
    ],
)
def test_bad_input_is_a_clear_value_error(kwargs, match) -> None:
    x = systems.henon(500)[:, 0]
    with pytest.raises(ValueError, match=match):
        correlation_dimension(x, **{"lag": 1, **kwargs})


def test_local_slopes_plot() -> None:
    res = correlation_dimension(systems.henon(3000)[:, 0], embedding_dims=[1, 2, 3], lag=1)
    ax = plot.local_slopes(res)
    assert len(ax.lines) >= 3
    ax.figure.canvas.draw()
    plt.close(ax.figure)
