"""Lyapunov spectrum from data: known spectra, spurious exponents, nolds.lyap_e."""

from __future__ import annotations

import nolds
import numpy as np
import pytest

from chaoskit import lyapunov_spectrum, systems

LN_B = np.log(0.3)  # Hénon: λ1 + λ2 = ln |det J| = ln b


@pytest.fixture(scope="module")
def henon_x() -> np.ndarray:
    return systems.henon(10_000)[:, 0]


def test_henon_spectrum(henon_x) -> None:
    res = lyapunov_spectrum(henon_x, embedding_dim=2, lag=1)
    np.testing.assert_allclose(res.exponents[0], 0.419, rtol=0.05)
    np.testing.assert_allclose(res.exponents.sum(), LN_B, rtol=0.10)
    assert not res.spurious.any()
    # Kaplan–Yorke: 1 + λ1/|λ2| = 1.26 for Hénon
    np.testing.assert_allclose(res.kaplan_yorke_dimension, 1.26, rtol=0.05)


@pytest.mark.parametrize("check", ["embedding", "reversal"])
def test_an_extra_dimension_adds_a_flagged_spurious_exponent(henon_x, check) -> None:
    res = lyapunov_spectrum(henon_x, embedding_dim=3, lag=1, spurious_check=check)
    # the two exponents of the map survive; the third (here a second positive one) is flagged
    assert res.spurious.sum() == 1
    kept = res.exponents[~res.spurious]
    np.testing.assert_allclose(kept, [0.419, LN_B - 0.419], rtol=0.05)


def test_lorenz_spectrum() -> None:
    x = systems.lorenz(50_000, dt=0.01)[:, 0]
    res = lyapunov_spectrum(x, embedding_dim=4, lag=8, dt=0.01, step=10)
    np.testing.assert_allclose(res.exponents[0], 0.906, rtol=0.10)
    assert abs(res.exponents[1]) < 0.1
    assert list(res.spurious) == [False, False, True, False]


def test_lorenz_spectrum_short() -> None:
    x = systems.lorenz(20_000, dt=0.01)[:, 0]
    res = lyapunov_spectrum(x, embedding_dim=3, lag=10, dt=0.01, step=10, spurious_check="none")
    np.testing.assert_allclose(res.exponents[0], 0.906, rtol=0.12)
    assert abs(res.exponents[1]) < 0.1
    assert res.exponents[2] < -5.0


def test_agrees_with_nolds_lyap_e_on_henon(henon_x) -> None:
    x = henon_x[:3000]
    theirs = nolds.lyap_e(x, emb_dim=2, matrix_dim=2, min_tsep=2, tau=1)
    ours = lyapunov_spectrum(x, embedding_dim=2, lag=1, theiler_window=2, spurious_check="none")
    np.testing.assert_allclose(ours.exponents, theirs, rtol=0.05)


def test_result_dataset_and_running_curve(henon_x) -> None:
    res = lyapunov_spectrum(henon_x[:3000], embedding_dim=2, lag=1, spurious_check="none")
    np.testing.assert_allclose(res.running[-1], res.exponents)
    ds = res.to_dataset()
    for name in ds.variables:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs, name
    assert ds.attrs["check"] == "none"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"embedding_dim": 1}, "embedding_dim"),
        ({"embedding_dim": 2, "step": 0}, "step"),
        ({"embedding_dim": 2, "n_neighbors": 2}, "n_neighbors"),
        ({"embedding_dim": 2, "dt": 0.0}, "dt"),
        ({"embedding_dim": 2, "spurious_check": "maybe"}, "spurious_check"),
        ({"embedding_dim": 2, "theiler_window": 5000}, "too short"),
    ],
)
def test_bad_input(kwargs, match, henon_x) -> None:
    with pytest.raises(ValueError, match=match):
        lyapunov_spectrum(henon_x[:2000], **{"lag": 1, **kwargs})
