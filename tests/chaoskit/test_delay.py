"""Mutual information, autocorrelation and delay selection."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from chaoskit import autocorrelation, estimate_delay, mutual_information, systems


def _mi_reference(x: np.ndarray, lag: int, bins: int) -> float:
    """Independent estimate with numpy's histogram2d on the same equal-width bins."""
    edges = np.linspace(x.min(), x.max(), bins + 1)
    a, b = x[: x.size - lag], x[lag:]
    joint, _, _ = np.histogram2d(a, b, bins=[edges, edges])
    p = joint / joint.sum()
    pa, pb = p.sum(axis=1), p.sum(axis=0)
    nz = p > 0
    return float((p[nz] * np.log(p[nz] / np.outer(pa, pb)[nz])).sum())


def test_mi_matches_histogram2d() -> None:
    x = systems.lorenz(3000)[:, 0]
    mi = mutual_information(x, max_lag=30, bins=12)
    ref = [_mi_reference(x, lag, 12) for lag in range(31)]
    assert_allclose(mi.curve, ref, rtol=1e-10, atol=1e-12)
    assert mi.units == "nat" and mi.lags[-1] == 30


def test_mi_of_independent_noise_is_its_small_bias() -> None:
    x = np.random.default_rng(0).random(200_000)
    mi = mutual_information(x, max_lag=5, bins=8)
    # I(0) is the entropy of 8 equally likely bins; for lag >= 1 only the
    # Miller–Madow bias (B - 1)^2 / (2N) remains
    assert_allclose(mi.curve[0], np.log(8), rtol=1e-3)
    assert np.all(mi.curve[1:] < 3 * 49 / (2 * 200_000))


def test_autocorrelation_of_a_sine_is_a_cosine() -> None:
    w = 2 * np.pi / 40
    x = np.sin(w * np.arange(40_000))
    acf = autocorrelation(x, max_lag=60)
    assert_allclose(acf.curve, np.cos(w * acf.lags), atol=2e-3)


def test_mi_first_minimum_of_lorenz_x() -> None:
    # validation target: first MI minimum near 0.15–0.17 time units at dt = 0.01
    for n in (10_000, 50_000):
        res = estimate_delay(systems.lorenz(n, dt=0.01)[:, 0])
        assert 15 <= res.lag <= 19, res.lag
        assert res.found and res.method == "mi_first_minimum"


def test_acf_rules_on_an_ar1_process() -> None:
    phi = 0.9
    rng = np.random.default_rng(3)
    e = rng.standard_normal(200_000)
    x = np.empty_like(e)
    x[0] = e[0]
    for i in range(1, e.size):
        x[i] = phi * x[i - 1] + e[i]
    # rho(tau) = phi^tau drops below 1/e after 1 / -ln(phi) = 9.49 lags
    assert estimate_delay(x, method="acf_1_over_e").lag == 10


def test_acf_first_zero_of_a_sine_is_a_quarter_period() -> None:
    x = np.sin(2 * np.pi * np.arange(5000) / 42.0 + 0.3)
    assert estimate_delay(x, method="acf_first_zero").lag == 11  # cos crosses 0 at 10.5


def test_auto_gives_one_for_maps_and_the_mi_minimum_for_lorenz() -> None:
    assert estimate_delay(systems.logistic(5000), method="auto").lag == 1
    assert estimate_delay(systems.henon(5000)[:, 0], method="auto").lag == 1
    lorenz = systems.lorenz(10_000)[:, 0]
    assert estimate_delay(lorenz, method="auto").lag == estimate_delay(lorenz).lag


def test_fallback_is_reported() -> None:
    x = np.cumsum(np.random.default_rng(5).standard_normal(2000))  # random walk
    res = estimate_delay(x, method="acf_first_zero", max_lag=20)
    assert not res.found and "max_lag" in res.rule


def test_to_dataset_has_units_and_long_names() -> None:
    res = estimate_delay(systems.lorenz(3000)[:, 0], method="auto")
    ds = res.to_dataset()
    for name in ds.variables:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert ds.attrs["lag"] == res.lag
    ds2 = mutual_information(systems.logistic(500), max_lag=5).to_dataset()
    assert ds2["mutual_information"].attrs["units"] == "nat"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"method": "nope"}, "method must be one of"),
        ({"bins": 1}, "bins"),
        ({"max_lag": 10_000}, "max_lag"),
    ],
)
def test_bad_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        estimate_delay(systems.logistic(1000), **kwargs)


def test_too_short() -> None:
    with pytest.raises(ValueError, match="minimum here is 16"):
        mutual_information(np.arange(15.0))
