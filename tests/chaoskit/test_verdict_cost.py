"""What the verdict's cheaper steps must keep: the same least squares, forecasts and Kantz
interval as the direct computations they replace."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial import cKDTree

from chaoskit import lyapunov_kantz, systems
from chaoskit.lyapunov import _kantz
from chaoskit.verdict import _line_spectrum, _surrogates, prediction_error
from chaoskit.verdict._line_spectrum import _basis, _lstsq, line_spectrum


def _lines(n: int = 4096) -> np.ndarray:
    t = np.arange(n, dtype=np.float64)
    return (
        np.cos(2 * np.pi * 0.0123 * t)
        + 0.4 * np.sin(2 * np.pi * 0.0123 * (1 + 5**0.5) / 2 * t + 0.3)
        + 0.01 * np.random.default_rng(3).standard_normal(n)
    )


def test_line_least_squares_match_the_svd_solver() -> None:
    """A well-conditioned basis of 16 lines: the QR solution equals numpy's SVD one."""
    x = _lines()
    freqs = np.random.default_rng(0).uniform(0.01, 0.45, 16)
    basis = _basis(freqs, x.size)
    expected = np.linalg.lstsq(basis, x, rcond=None)[0]
    assert_allclose(_lstsq(basis, x), expected, rtol=1e-10, atol=1e-13)


def test_rank_deficient_line_basis_gets_the_minimum_norm_answer() -> None:
    """Two equal frequencies (two identical column pairs): the SVD solver's minimum-norm
    solution, which splits the amplitude evenly, not an arbitrary one."""
    x = _lines()
    basis = _basis(np.array([0.0123, 0.0123, 0.2]), x.size)
    coef = _lstsq(basis, x)
    assert_allclose(coef, np.linalg.lstsq(basis, x, rcond=None)[0], rtol=1e-9, atol=1e-12)
    assert coef[1] == pytest.approx(coef[2], rel=1e-9)


def test_more_lines_than_samples_get_the_minimum_norm_answer() -> None:
    """A basis wider than it is tall (a short series): the SVD solver's answer."""
    x = _lines(20)
    basis = _basis(np.linspace(0.02, 0.48, 12), x.size)
    assert basis.shape == (20, 25)
    assert_allclose(_lstsq(basis, x), np.linalg.lstsq(basis, x, rcond=None)[0], rtol=1e-12)


def test_line_spectrum_needs_no_svd_solver(monkeypatch: pytest.MonkeyPatch) -> None:
    """A two-frequency torus is resolved without the threaded SVD solver (its worker
    threads cost more CPU than the fit on busy cores): the same kind and bases."""
    x = _lines()
    expected = line_spectrum(x)

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("numpy.linalg.lstsq called")

    monkeypatch.setattr(_line_spectrum.np.linalg, "lstsq", refuse)
    got = line_spectrum(x)
    assert got.kind == expected.kind == "quasi-periodic"
    assert_allclose(got.base_frequencies, expected.base_frequencies, rtol=1e-9)


def _forecast_error(x: np.ndarray, m: int, lag: int, h: int, w: int, k: int) -> float:
    """The statistic with every candidate the window could hide asked for at once."""
    first, last = (m - 1) * lag, x.size - 1 - h
    idx = np.arange(first, last + 1)
    points = np.stack([x[idx - c * lag] for c in range(m)], axis=1)
    ref = np.unique(np.linspace(0, idx.size - 1, min(500, idx.size)).astype(np.int64))
    _, cand = cKDTree(points).query(points[ref], k=k + 2 * w + 1)
    admissible = np.abs(cand - ref[:, None]) > w
    keep = admissible & (np.cumsum(admissible, axis=1) <= k)
    forecast = np.sum(np.where(keep, x[idx[cand] + h], 0.0), axis=1) / k
    return float(np.sqrt(np.mean((forecast - x[idx[ref] + h]) ** 2)) / np.std(x))


@pytest.mark.parametrize(("series", "w"), [("lorenz", 60), ("noise", 60), ("lorenz", 0)])
def test_prediction_error_asks_few_candidates_first(
    monkeypatch: pytest.MonkeyPatch, series: str, w: int
) -> None:
    """The forecast of a smooth series (whose nearest points are its own neighbours in
    time) and of noise equals the one from all 2w + 1 + k candidates, yet the first query
    asks for 4k + 4 of them."""
    if series == "lorenz":
        x = systems.lorenz(3000, dt=0.01)[:, 0]
    else:
        x = np.random.default_rng(1).standard_normal(3000)
    asked: list[int] = []
    tree_class = _surrogates.cKDTree

    class Counting(tree_class):  # type: ignore[misc, valid-type]
        def query(self, *args, k=1, **kwargs):  # type: ignore[no-untyped-def]
            asked.append(int(k))
            return super().query(*args, k=k, **kwargs)

    monkeypatch.setattr(_surrogates, "cKDTree", Counting)
    got = prediction_error(x, embedding_dim=3, lag=5, horizon=5, theiler_window=w)
    assert got == pytest.approx(_forecast_error(x, 3, 5, 5, w, 5), rel=1e-12)
    assert asked[0] == min(24, 5 + 2 * w + 1)


def _lorenz_kantz(**kw: object):  # type: ignore[no-untyped-def]
    x = systems.lorenz(6000, dt=0.01)[:, 0]
    return lyapunov_kantz(
        x, dt=0.01, embedding_dim=3, lag=10, theiler_window=100, max_horizon=150, **kw
    )


@pytest.mark.parametrize("definition", ["mean", "rms"])
@pytest.mark.parametrize("fit_range", [(20, 120), "auto"])
def test_kantz_interval_without_a_pass_of_its_own(
    monkeypatch: pytest.MonkeyPatch, definition: str, fit_range: tuple[int, int] | str
) -> None:
    """When the smallest radius is chosen (always, on this series, with a given fit range),
    the neighbourhood pass keeps the per-reference curves the interval needs: no second
    pass, and the same exponent and interval bit for bit as with that pass."""
    calls: list[object] = []
    log_distances = _kantz._Search.log_distances

    def counting(self, transverse, upto=None, ks=None):  # type: ignore[no-untyped-def]
        calls.append(upto)
        return log_distances(self, transverse, upto, ks)

    monkeypatch.setattr(_kantz._Search, "log_distances", counting)
    kw = {"definition": definition, "fit_range": fit_range, "distance": "euclidean"}
    got = _lorenz_kantz(**kw)
    if fit_range != "auto":  # the first radius with a finite curve over the given range
        assert got.epsilon_index == 0
    # a larger radius chosen by the scaling region still has the interval's own pass
    assert calls == ([None] if got.epsilon_index == 0 else [None, got.epsilon_index])
    monkeypatch.setattr(_kantz, "KEEP_VALUES", 0)  # nothing kept: the interval's own pass
    calls.clear()
    again = _lorenz_kantz(**kw)
    assert calls == [None, again.epsilon_index]
    assert got.mle == again.mle
    assert got.ci == again.ci
    assert got.params == again.params
