"""Hard inputs for the estimators: each case asserts what happens, not only that it runs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from chaoskit import (
    cao,
    estimate_delay,
    false_nearest_neighbors,
    lyapunov_rosenstein,
    lyapunov_wolf,
    mutual_information,
    systems,
)

METHODS = [lyapunov_rosenstein, lyapunov_wolf]


@pytest.mark.parametrize("method", METHODS)
def test_minimum_accepted_length(method) -> None:
    res = method(systems.logistic(100))  # the documented minimum
    assert np.isfinite(res.mle) and res.n_samples == 100
    assert abs(res.mle - math.log(2.0)) < 0.1
    with pytest.raises(ValueError, match="minimum here is 100"):
        method(systems.logistic(99))


@pytest.mark.parametrize("method", METHODS)
def test_constant_series(method) -> None:
    with pytest.raises(ValueError, match="constant"):
        method(np.full(500, 3.0))
    with pytest.raises(ValueError, match="constant"):
        estimate_delay(np.full(500, 3.0))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("method", METHODS)
def test_non_finite_values(method, bad) -> None:
    x = systems.logistic(500)
    x[123] = bad
    with pytest.raises(ValueError, match="index 123"):
        method(x)


def test_object_and_string_dtypes() -> None:
    with pytest.raises(ValueError, match="numeric"):
        lyapunov_rosenstein(np.array(["1.0"] * 200))
    with pytest.raises(ValueError, match="numeric"):
        lyapunov_wolf(np.array([1.0] * 200, dtype=object))


@pytest.mark.parametrize("method", METHODS)
def test_integer_dtype_gives_the_float_result(method) -> None:
    x = np.round(systems.logistic(5000) * 1e6).astype(np.int64)
    assert method(x).mle == method(x.astype(np.float64)).mle


@pytest.mark.parametrize("amplitude", [1e150, 1e-150])
@pytest.mark.parametrize("method", METHODS)
def test_huge_and_tiny_amplitudes(method, amplitude) -> None:
    x = systems.henon(5000)[:, 0]
    ref = method(x)
    res = method(x * amplitude + 2.0 * amplitude)
    assert_allclose(res.mle, ref.mle, rtol=1e-9)
    assert (res.lag, res.embedding_dim) == (ref.lag, ref.embedding_dim)


def test_huge_amplitude_in_delay_and_dimension() -> None:
    x = systems.henon(3000)[:, 0]
    assert_allclose(
        mutual_information(x * 1e200, max_lag=5).curve, mutual_information(x, max_lag=5).curve
    )
    assert false_nearest_neighbors(x * 1e200, lag=1, max_dim=3).embedding_dim == 2
    assert_allclose(cao(x * 1e-200, lag=1, max_dim=3).curve, cao(x, lag=1, max_dim=3).curve)


def test_white_noise_is_not_reported_as_a_confident_exponent() -> None:
    noise = np.random.default_rng(0).standard_normal(5000)
    res = lyapunov_rosenstein(noise)
    # the divergence jumps to its plateau in one step: no scaling region, no precision
    assert not res.fit_found
    assert res.ci == (-np.inf, np.inf)
    wolf = lyapunov_wolf(noise)
    assert abs(wolf.mle) < 0.05  # renormalised separations of noise do not grow on average


def test_heavy_noise_on_the_logistic_map() -> None:
    rng = np.random.default_rng(1)
    x = systems.logistic(10_000)
    noisy = x + 0.5 * x.std() * rng.standard_normal(x.size)
    res = lyapunov_rosenstein(noisy)
    # noise of half the signal's spread hides the scaling region; the estimate is flagged
    # and is far below ln 2 rather than spuriously high
    assert not res.fit_found
    assert res.mle < 0.5 * math.log(2.0)
    mild = lyapunov_rosenstein(x + 0.01 * x.std() * rng.standard_normal(x.size))
    assert mild.fit_found and abs(mild.mle - math.log(2.0)) < 0.1


def test_theiler_window_that_leaves_no_neighbours_raises_fast() -> None:
    x = systems.lorenz(3000)[:, 0]
    with pytest.raises(ValueError, match="needs at least"):
        lyapunov_rosenstein(x, dt=0.01, embedding_dim=3, lag=17, theiler_window=1490)
    with pytest.raises(ValueError, match="no admissible neighbour"):
        false_nearest_neighbors(x, lag=17, max_dim=3, theiler_window=1480)


def test_exactly_repeating_series() -> None:
    x = np.tile([0.1, 0.7, 0.3, 0.9, 0.5], 100)  # period 5, exact repeats
    # every neighbour coincides with its reference point: Rosenstein's curve is undefined
    with pytest.raises(ValueError, match="repeats exactly"):
        lyapunov_rosenstein(x)
    res_w = lyapunov_wolf(x)
    assert abs(res_w.mle) < 0.01
