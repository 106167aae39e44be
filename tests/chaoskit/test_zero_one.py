"""The 0–1 test for chaos: targets on the logistic map and an independent implementation."""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import ZeroOneResult, systems, zero_one_test


def _k_c_reference(phi: np.ndarray, c: float, ncut: int) -> float:
    """Plain-numpy K_c (Gottwald & Melbourne 2009, eqs. 2.1–2.5), written independently."""
    j = np.arange(1, phi.size + 1)
    p = np.cumsum(phi * np.cos(j * c))
    q = np.cumsum(phi * np.sin(j * c))
    m_avg = phi.size - ncut
    n = np.arange(1, ncut + 1)
    msd = np.array(
        [np.mean((p[k : k + m_avg] - p[:m_avg]) ** 2 + (q[k : k + m_avg] - q[:m_avg]) ** 2)
         for k in n]
    )  # fmt: skip
    d = msd - np.mean(phi) ** 2 * (1 - np.cos(n * c)) / (1 - np.cos(c))
    return float(np.corrcoef(n, d)[0, 1])


@pytest.mark.parametrize("r", [3.2, 3.5])
def test_periodic_logistic_gives_k_below_0_1(r: float) -> None:
    result = zero_one_test(systems.logistic(2000, r=r), rng=0)
    assert result.k < 0.1


@pytest.mark.parametrize("r", [3.9, 4.0])
def test_chaotic_logistic_gives_k_above_0_9(r: float) -> None:
    result = zero_one_test(systems.logistic(2000, r=r), rng=0)
    assert result.k > 0.9


def test_kernel_matches_an_independent_implementation() -> None:
    phi = systems.logistic(600, r=3.7)
    result = zero_one_test(phi, n_c=5, rng=7)
    expected = [_k_c_reference(phi, c, 60) for c in result.c_values]
    np.testing.assert_allclose(result.k_values, expected, rtol=1e-9, atol=1e-12)
    assert result.k == pytest.approx(float(np.median(expected)), rel=1e-9)


def test_result_fields_and_reproducibility() -> None:
    x = systems.henon(1000)[:, 0]
    a = zero_one_test(x, rng=3)
    b = zero_one_test(x, rng=np.random.default_rng(3))
    assert isinstance(a, ZeroOneResult)
    np.testing.assert_array_equal(a.k_values, b.k_values)
    assert a.ncut == 100 and a.n_samples == 1000 and a.k_values.size == 100
    assert np.all((a.c_values > np.pi / 5) & (a.c_values < 4 * np.pi / 5))
    ds = a.to_dataset()
    assert ds["k_c"].attrs["units"] == "1" and ds.attrs["k_median"] == a.k
    with pytest.raises(AttributeError):
        a.k = 0.0  # type: ignore[misc]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"n_c": 0}, "n_c"), ({"ncut": 5}, "ncut"), ({"ncut": 400}, "ncut"), ({"rng": -1}, "rng")],
)
def test_bad_input(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        zero_one_test(systems.logistic(500), **kwargs)


def test_series_checks() -> None:
    with pytest.raises(ValueError, match="too short"):
        zero_one_test(np.arange(50.0))
    with pytest.raises(ValueError, match="constant"):
        zero_one_test(np.ones(500))
