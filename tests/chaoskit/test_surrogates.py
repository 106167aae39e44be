"""IAAFT surrogates keep the values and the spectrum; the surrogate test separates chaos from
linear noise."""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import SurrogateResult, iaaft_surrogates, surrogate_test, systems
from chaoskit.verdict._surrogates import match_ends, prediction_error


def ar1(n: int, phi: float, seed: int) -> np.ndarray:
    """AR(1) noise x_i = φ x_{i−1} + e_i: linear, the null hypothesis of the surrogate test."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n)
    x = np.empty(n)
    x[0] = e[0]
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


def test_iaaft_keeps_values_exactly_and_spectrum_closely() -> None:
    x = np.exp(ar1(1024, 0.9, 1) / 3.0)  # a skewed, correlated series
    s = iaaft_surrogates(x, n_surrogates=4, rng=0)
    assert s.shape == (4, 1024)
    for row in s:
        np.testing.assert_array_equal(np.sort(row), np.sort(x))
        assert not np.array_equal(row, x)
    amp = np.abs(np.fft.rfft(x))
    for row in s:
        err = np.linalg.norm(np.abs(np.fft.rfft(row)) - amp) / np.linalg.norm(amp)
        assert err < 0.05
    shuffled = np.random.default_rng(0).permutation(x)  # what the iteration starts from
    assert np.linalg.norm(np.abs(np.fft.rfft(shuffled)) - amp) / np.linalg.norm(amp) > 0.3


def test_iaaft_is_reproducible() -> None:
    x = ar1(256, 0.5, 2)
    np.testing.assert_array_equal(
        iaaft_surrogates(x, n_surrogates=2, rng=5), iaaft_surrogates(x, n_surrogates=2, rng=5)
    )


def test_match_ends_finds_a_matching_segment() -> None:
    t = np.arange(1000) * 0.01
    x = np.sin(2 * np.pi * 0.73 * t)
    seg = x[match_ends(x)]
    assert abs(seg[0] - seg[-1]) < 0.05 and seg.size > 800


def test_prediction_error_of_a_known_case() -> None:
    # A period-2 sequence is predicted perfectly; white noise no better than its mean.
    alt = np.tile([0.0, 1.0], 300)
    alt = alt + 1e-9 * np.arange(600)  # not exactly constant neighbours
    assert prediction_error(alt, embedding_dim=1, lag=1, horizon=1, theiler_window=1) < 1e-3
    noise = np.random.default_rng(0).standard_normal(2000)
    err = prediction_error(noise, embedding_dim=2, lag=1, horizon=1, theiler_window=0)
    assert 0.95 < err < 1.25  # mean of 5 neighbours: sqrt(1 + 1/5) ≈ 1.10


def test_chaotic_map_rejects_linear_noise() -> None:
    res = surrogate_test(systems.henon(1000)[:, 0], embedding_dim=2, lag=1, rng=0)
    assert isinstance(res, SurrogateResult)
    assert res.rejected and res.p_value == pytest.approx(0.05) and res.effect > 0.5
    assert res.surrogate_statistics.shape == (19,)
    assert res.to_dataset()["prediction_error"].attrs["units"] == "1"


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_linear_noise_is_not_rejected(seed: int) -> None:
    red = ar1(2000, 0.9, 10 + seed)
    res = surrogate_test(red, embedding_dim=3, lag=2, rng=seed)
    assert not res.rejected
    white = np.random.default_rng(seed).standard_normal(1000)
    assert not surrogate_test(white, embedding_dim=2, lag=1, rng=seed).rejected


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"alpha": 1.5}, "alpha"),
        ({"min_effect": 1.0}, "min_effect"),
        ({"n_surrogates": 0}, "n_surrogates"),
        ({"lag": 0}, "lag"),
        ({"theiler_window": 400}, "too short"),
    ],
)
def test_bad_input(kwargs: dict, match: str) -> None:
    options = {"embedding_dim": 2, "lag": 1, **kwargs}
    with pytest.raises(ValueError, match=match):
        surrogate_test(systems.henon(500)[:, 0], **options)
