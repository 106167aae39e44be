"""IAAFT surrogates keep the values and the spectrum; the surrogate test separates chaos from
linear noise."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from chaoskit import (
    PeriodicOrbitEvidence,
    SurrogateResult,
    cycle_boundaries,
    cycle_shuffled_surrogates,
    cycle_spread,
    cycle_surrogate_test,
    iaaft_surrogates,
    surrogate_test,
    systems,
    twin_surrogates,
)
from chaoskit.verdict import CycleForecast, prediction_error
from chaoskit.verdict._surrogates import match_ends


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


# ----------------------------------------------------------------- the noisy-periodic null

DRIVE = 2 * np.pi / 1.2  # forced Duffing drive period, s


def two_harmonics(noise: float, seed: int, n: int = 8000, dt: float = 0.05) -> np.ndarray:
    """sin t + 0.3 sin(2t + 1) plus white noise of ``noise`` (period 2π: 125.66 samples)."""
    t = np.arange(n) * dt
    rng = np.random.default_rng(seed)
    return np.sin(t) + 0.3 * np.sin(2 * t + 1) + noise * rng.standard_normal(n)


def test_cycle_shuffled_surrogates_keep_every_cycle_exactly() -> None:
    x = two_harmonics(0.1, 0, dt=2 * np.pi / 50)  # 50 samples per cycle
    cuts = cycle_boundaries(x, 2 * np.pi, dt=2 * np.pi / 50)
    assert set(np.diff(cuts)) == {50}
    cycles = x[cuts[0] : cuts[-1]].reshape(-1, 50)
    surrogates = cycle_shuffled_surrogates(x, 2 * np.pi, dt=2 * np.pi / 50, n_surrogates=5, rng=0)
    for s in surrogates:
        pieces = s.reshape(-1, 50)
        # every piece is one of the data's cycles, sample for sample, each used once
        assert np.array_equal(np.unique(pieces, axis=0), np.unique(cycles, axis=0))
        assert not np.array_equal(pieces, cycles)  # and the order is new


def test_cycle_shuffled_surrogates_keep_the_values_at_a_fractional_period() -> None:
    x = two_harmonics(0.1, 1)  # 125.66 samples per cycle: cycles of 125 and 126 samples
    cuts = cycle_boundaries(x, 2 * np.pi, dt=0.05)
    assert set(np.diff(cuts)) <= {125, 126}
    s = cycle_shuffled_surrogates(x, 2 * np.pi, dt=0.05, n_surrogates=3, rng=2)
    for row in s:
        assert np.array_equal(np.sort(row), np.sort(x[cuts[0] : cuts[-1]]))


def test_cycle_boundaries_cut_where_the_cycles_agree() -> None:
    # the noise is confined to the first half of each cycle: the cut falls in the second
    t = np.arange(5000) * (2 * np.pi / 100)
    noise = np.random.default_rng(3).standard_normal(t.size) * (np.sin(t) > 0)
    cuts = cycle_boundaries(np.sin(t) + 0.2 * noise, 2 * np.pi, dt=2 * np.pi / 100)
    assert np.all(np.sin(t[cuts]) <= 0.0)


def mean_cycle(x: np.ndarray, m: int = 50) -> tuple[np.ndarray, float]:
    """The mean of the cycles between upward zero crossings (each resampled to ``m``
    points; a crossing counts after the series fell below -0.5) and the mean cycle length."""
    starts, armed = [], False
    for i in range(1, x.size):
        if x[i] < -0.5:
            armed = True
        elif armed and x[i - 1] < 0.0 <= x[i]:
            starts.append(i)
            armed = False
    grid = np.arange(x.size)
    cycles = [
        np.interp(np.linspace(a, b, m, endpoint=False), grid, x)
        for a, b in itertools.pairwise(starts)
    ]
    return np.mean(cycles, axis=0), float(np.mean(np.diff(starts)))


def test_twin_surrogates_reproduce_the_mean_cycle() -> None:
    x = two_harmonics(0.05, 4, n=3000, dt=2 * np.pi / 50)
    s = twin_surrogates(x, embedding_dim=2, lag=12, n_surrogates=3, rng=0)
    data_mean, data_length = mean_cycle(x)
    for row in s:
        mean, length = mean_cycle(row)
        # measured over seeds 0–5: RMS difference 0.009–0.068 of the spread, cycle length
        # 48.5–50.2 samples (jumping to a twin's successor can skip a sample)
        assert np.sqrt(np.mean((mean - data_mean) ** 2)) < 0.1 * np.std(x)
        assert abs(length - data_length) < 2.5
        assert not np.array_equal(row, x[-row.size :])  # a new trajectory, not the data


def test_twin_surrogates_of_an_exact_orbit_jump_between_its_cycles() -> None:
    t = np.arange(2000) * (2 * np.pi / 40)
    x = np.sin(t) + 0.3 * np.sin(2 * t + 1)
    s = twin_surrogates(x, embedding_dim=2, lag=10, n_surrogates=2, rng=1)
    # every cycle of an exact orbit is a twin of every other: the surrogate is the orbit
    mean = x[:40]
    for row in s:
        err = min(np.max(np.abs(np.roll(row[:40], k) - mean)) for k in range(40))
        assert err < 1e-9


@pytest.mark.parametrize("noise", [0.01, 0.1])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_noisy_periodic_orbit_does_not_reject_the_cycle_null(noise: float, seed: int) -> None:
    x = two_harmonics(noise, seed)
    res = cycle_surrogate_test(x, 2 * np.pi, dt=0.05, forecast=CycleForecast(lag=30), rng=seed)
    # measured over seeds 0–19: never rejected; the largest effect 0.05 at 1 %, 0.04 at 10 %
    assert not res.rejected
    assert res.effect < 0.1
    assert res.null == "noisy periodic orbit"
    # what varies from cycle to cycle is white: measured 0 for seeds 0–9
    assert cycle_spread(x, 2 * np.pi, dt=0.05) == 0.0


@pytest.mark.parametrize("nudge", [0.0, 1e-12])
def test_forced_duffing_chaos_rejects_the_cycle_null(nudge: float) -> None:
    t, s = systems.duffing(4000, gamma=0.5, samples_per_period=50, initial=(1.0 + nudge, 0.0))
    res = cycle_surrogate_test(
        s[:, 0], DRIVE, dt=float(t[1] - t[0]), forecast=CycleForecast(lag=12), rng=0
    )
    # measured: effect 0.84 and every surrogate worse than the data
    assert res.rejected and res.p_value == pytest.approx(0.05, abs=1e-12)
    assert res.effect > 0.5
    assert cycle_spread(s[:, 0], DRIVE, dt=float(t[1] - t[0])) > 0.5  # measured 0.96


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"period": 0.1}, "period must span at least 4 samples"),
        ({"period": 1000.0}, "at least 8"),
        (
            {"forecast": CycleForecast(lag=10, horizon=200)},
            "horizon must be shorter than one cycle",
        ),
        ({"min_gain": 1.0}, r"min_gain must be in \[0, 1\)"),
        ({"n_surrogates": 5}, "n_surrogates = 5 cannot reach alpha"),
    ],
)
def test_cycle_surrogate_test_refuses_bad_input(kwargs: dict, match: str) -> None:
    options = {"period": 2 * np.pi, "dt": 0.05, "forecast": CycleForecast(lag=10), **kwargs}
    with pytest.raises(ValueError, match=match):
        cycle_surrogate_test(two_harmonics(0.1, 0, n=2000), **options)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"embedding_dim": 0}, "embedding_dim"),
        ({"lag": 0}, "lag"),
        ({"horizon": 0}, "horizon"),
        ({"theiler_window": -1}, "theiler_window"),
        ({"n_neighbors": 0}, "n_neighbors"),
        ({"n_reference": 9}, "n_reference"),
    ],
)
def test_cycle_forecast_refuses_bad_settings(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        CycleForecast(**kwargs)


def test_cycle_forecast_defaults_match_the_test_defaults() -> None:
    """The default forecast is three delay coordinates of lag 1, five neighbours."""
    x = two_harmonics(0.1, 0, n=2000)
    default = cycle_surrogate_test(x, 2 * np.pi, dt=0.05, rng=0)
    explicit = cycle_surrogate_test(
        x,
        2 * np.pi,
        dt=0.05,
        forecast=CycleForecast(embedding_dim=3, lag=1, n_neighbors=5, n_reference=1000),
        rng=0,
    )
    assert (default.embedding_dim, default.lag, default.horizon) == (3, 1, 1)
    assert default.statistic == explicit.statistic
    np.testing.assert_array_equal(default.surrogate_statistics, explicit.surrogate_statistics)
    with pytest.raises(TypeError, match="forecast must be a CycleForecast or None; got dict"):
        cycle_surrogate_test(x, 2 * np.pi, dt=0.05, forecast={"lag": 2})
    with pytest.raises(TypeError, match="unexpected keyword argument 'lag'"):
        cycle_surrogate_test(x, 2 * np.pi, dt=0.05, lag=2)  # type: ignore[call-arg]


def test_periodic_orbit_evidence_properties_and_refusals() -> None:
    ev = PeriodicOrbitEvidence(2, np.array([0.5 + 0.5j, -0.2]), np.array([1.0]), 1e-9, 2e-5, 1e-4)
    assert ev.stable and ev.attracting and ev.converged and ev.problem() is None
    assert ev.multipliers.dtype == np.complex128
    assert ev.largest_multiplier == pytest.approx(np.sqrt(0.5), rel=1e-12)
    unstable = PeriodicOrbitEvidence(1, np.array([-1.3]), np.array([]), 1e-9, 1e-3, 1e-4)
    assert not unstable.stable and not unstable.attracting
    assert unstable.problem() == (
        "it is unstable (largest multiplier |μ| = 1.3 ≥ 1); the motion does not approach it "
        "(distance 0.001 > tolerance 0.0001)"
    )
    for args, match in (
        ((0, [0.5], [], 0.0, 0.0, 1e-4), "period must be an integer >= 1"),
        ((1.5, [0.5], [], 0.0, 0.0, 1e-4), "period must be an integer >= 1"),
        ((1, [np.nan], [], 0.0, 0.0, 1e-4), "multipliers must be finite"),
        ((1, [0.5], [], -1.0, 0.0, 1e-4), "residual must be a finite number >= 0"),
        ((1, [0.5], [], 0.0, 0.0, 0.0), "tolerance must be > 0"),
    ):
        with pytest.raises(ValueError, match=match):
            PeriodicOrbitEvidence(*args)
