"""Sample entropy, DFA and Hurst through chaoskit: analytic values, nolds' numbers, limits."""

from __future__ import annotations

import nolds
import numpy as np
import pytest
from scipy.special import erf

from chaoskit import detrended_fluctuation, hurst_exponent, sample_entropy
from chaoskit.complexity import MAX_SAMPLES


@pytest.fixture(scope="module")
def noise() -> np.ndarray:
    return np.random.default_rng(7).standard_normal(4000)


def test_sample_entropy_of_white_noise_is_analytic(noise) -> None:
    # iid Gaussian: a template pair matches at length m+1 given length m with probability
    # P(|X − Y| ≤ r) = erf(r / (2σ)), so SampEn = −ln erf(r / 2σ)
    r = 0.2
    res = sample_entropy(noise, embedding_dim=2, tolerance=r * noise.std())
    expected = -np.log(erf(r / 2.0))
    np.testing.assert_allclose(res.value, expected, rtol=0.05)
    assert res.units == "nat"
    assert res.params["tolerance"] == pytest.approx(r * noise.std())


def test_sample_entropy_is_nolds_value(noise) -> None:
    x = noise[:1500]
    assert sample_entropy(x).value == nolds.sampen(x, emb_dim=2)
    res = sample_entropy(np.sin(0.3 * np.arange(1500)), embedding_dim=3)
    assert res.value < 0.2  # a sine is predictable


def test_dfa_white_noise_and_random_walk(noise) -> None:
    white = detrended_fluctuation(noise)
    walk = detrended_fluctuation(np.cumsum(noise))
    np.testing.assert_allclose(white.value, 0.5, atol=0.06)
    np.testing.assert_allclose(walk.value, 1.5, atol=0.08)
    assert white.value == nolds.dfa(noise, fit_exp="poly")
    slope = np.polyfit(np.log(white.scale), np.log(white.curve), 1)[0]
    np.testing.assert_allclose(slope, white.value, rtol=1e-6)  # the curve is the fitted one


def test_hurst_of_white_noise_and_of_persistent_noise() -> None:
    rng = np.random.default_rng(1)
    white = rng.standard_normal(20_000)
    res = hurst_exponent(white)
    np.testing.assert_allclose(res.value, 0.5, atol=0.05)
    assert res.value == nolds.hurst_rs(white, fit="poly")
    # AR(1) with φ = 0.9 is persistent over short windows: H well above 0.5
    ar = np.empty_like(white)
    ar[0] = 0.0
    for k in range(1, ar.size):
        ar[k] = 0.9 * ar[k - 1] + white[k]
    assert hurst_exponent(ar).value > 0.7


def test_results_to_dataset(noise) -> None:
    for res in (sample_entropy(noise[:800]), detrended_fluctuation(noise)):
        ds = res.to_dataset()
        assert ds.attrs["value"] == res.value
        for name in ds.variables:
            assert "units" in ds[name].attrs and "long_name" in ds[name].attrs


@pytest.mark.parametrize(
    ("func", "measure"),
    [
        (sample_entropy, "sample_entropy"),
        (detrended_fluctuation, "dfa"),
        (hurst_exponent, "hurst_rs"),
    ],
)
def test_the_length_limit_is_checked_before_calling_nolds(func, measure, monkeypatch) -> None:
    called = []
    monkeypatch.setattr(nolds, {"sample_entropy": "sampen"}.get(measure, measure), called.append)
    assert MAX_SAMPLES[measure] >= 20_000  # the limits in the docs
    monkeypatch.setitem(MAX_SAMPLES, measure, 1000)  # the same check, on a short series
    x = np.random.default_rng(0).standard_normal(1001)
    with pytest.raises(ValueError, match="limited here to 1000 samples"):
        func(x)
    assert not called


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda x: sample_entropy(x, embedding_dim=0), "embedding_dim"),
        (lambda x: sample_entropy(x, tolerance=-1.0), "tolerance"),
        (lambda x: sample_entropy(x, tolerance=1e-9), "undefined"),
        (lambda x: detrended_fluctuation(x, windows=[2, 8]), "windows"),
        (lambda x: detrended_fluctuation(x, order=0), "order"),
        (lambda x: hurst_exponent(x, windows=[8]), "windows"),
        (lambda x: hurst_exponent(x[:20]), "too short"),
    ],
)
def test_bad_input(call, match, noise) -> None:
    with pytest.raises(ValueError, match=match):
        call(noise[:600])
