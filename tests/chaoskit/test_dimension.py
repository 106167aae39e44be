"""False nearest neighbours and Cao's method on systems of known dimension."""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import (
    cao,
    estimate_delay,
    estimate_embedding_dim,
    false_nearest_neighbors,
    systems,
)


@pytest.fixture(scope="module")
def lorenz_x() -> tuple[np.ndarray, int]:
    x = systems.lorenz(10_000, dt=0.01)[:, 0]
    return x, estimate_delay(x).lag


@pytest.mark.parametrize("method", ["fnn", "cao"])
def test_maps(method: str) -> None:
    assert estimate_embedding_dim(systems.logistic(10_000), lag=1, method=method).embedding_dim == 1
    henon = systems.henon(10_000)[:, 0]
    assert estimate_embedding_dim(henon, lag=1, method=method).embedding_dim == 2


@pytest.mark.parametrize("method", ["fnn", "cao"])
def test_lorenz_x_needs_three(lorenz_x, method: str) -> None:
    x, lag = lorenz_x
    res = estimate_embedding_dim(x, lag=lag, method=method, max_dim=6)
    assert res.embedding_dim == 3 and res.found


def test_fnn_fraction_is_about_zero_at_three_for_lorenz(lorenz_x) -> None:
    x, lag = lorenz_x
    res = false_nearest_neighbors(x, lag=lag, max_dim=5)
    assert res.curve[0] > 0.5 and res.curve[1] > 0.01  # 1 and 2 dimensions are not enough
    assert np.all(res.curve[2:] < 0.005)


def test_cao_e2_flags_noise() -> None:
    noise = np.random.default_rng(0).standard_normal(5000)
    res = cao(noise, lag=1, max_dim=6)
    assert np.all(np.abs(res.e2 - 1.0) < 0.1)  # Cao: E2 = 1 at every d for random data
    henon = cao(systems.henon(5000)[:, 0], lag=1, max_dim=4)
    assert henon.e2[0] < 0.5  # deterministic: E2 differs from 1


def test_periodic_signal_with_exact_repeats() -> None:
    x = np.sin(2 * np.pi * np.arange(4000) / 20.0)
    assert false_nearest_neighbors(x, lag=5, max_dim=5).embedding_dim == 2


def test_theiler_window_without_neighbours_raises() -> None:
    with pytest.raises(ValueError, match="no admissible neighbour"):
        false_nearest_neighbors(systems.logistic(500), lag=1, max_dim=3, theiler_window=300)


def test_to_dataset() -> None:
    ds = cao(systems.henon(2000)[:, 0], lag=1, max_dim=4).to_dataset()
    assert set(ds.data_vars) == {"e1", "e2"}
    for name in ds.variables:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert ds.attrs["embedding_dim"] == 2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"lag": 0}, "lag"),
        ({"lag": 1, "max_dim": 0}, "max_dim"),
        ({"lag": 1, "rtol": -1.0}, "rtol"),
        ({"lag": 200}, "minimum here"),
    ],
)
def test_bad_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        false_nearest_neighbors(systems.logistic(1000), **kwargs)


def test_unknown_method() -> None:
    with pytest.raises(ValueError, match="method must be one of"):
        estimate_embedding_dim(systems.logistic(1000), lag=1, method="svd")
