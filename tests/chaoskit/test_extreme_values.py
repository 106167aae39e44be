"""Extreme but finite values: every estimator gives a result or a clear ValueError.

Near the float64 limits, differences and squares of samples over- or underflow; before the
fix a series of amplitude 1e308 gave NaN histogram codes that indexed outside their arrays.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numpy.testing import assert_array_equal

from chaoskit import (
    VerdictRule,
    analyze,
    classify,
    classify_variables,
    iaaft_surrogates,
    load_trajectory,
    lyapunov_rosenstein,
    mutual_information,
    surrogate_test,
    systems,
    zero_one_test,
)
from chaoskit.embedding import _kernels

T = np.arange(2000) * 0.01
QUASI = np.sin(T) + 0.5 * np.sin(2.3 * T)
UNIT = QUASI / np.max(np.abs(QUASI)) * 0.75  # peak 0.75: in [0.5, 1)
HENON = systems.henon(1200)[:, 0]
_REF_MI = mutual_information(UNIT, max_lag=60).curve
_REF_LABEL = classify(UNIT, dt=0.01, rng=0).label

CHEAP = VerdictRule(alpha=0.25)  # 3 surrogates can reach it: the fuzz test is about crashes


def test_the_reported_1e308_series_is_classified_like_the_unit_one() -> None:
    x = (np.sin(T) + 0.5 * np.sin(2.3 * T)) * 1e308
    verdicts = classify_variables(load_trajectory(x, dt=0.01), rng=0)
    assert verdicts["x"].label == _REF_LABEL
    assert "2**-1024" in verdicts["x"].reason  # the exact rescaling is stated


@settings(max_examples=40, deadline=None)
@given(exponent=st.integers(min_value=-1070, max_value=1023))
def test_mutual_information_is_exact_or_refused_over_the_whole_float64_range(
    exponent: int,
) -> None:
    """x · 2**k is the same information; accepted amplitudes give the identical curve."""
    x = np.ldexp(UNIT, exponent)
    peak = float(np.max(np.abs(x)))
    if peak == 0.0:
        return  # underflowed completely: constant, refused elsewhere
    try:
        curve = mutual_information(x, max_lag=60).curve
    except ValueError as err:
        assert "peak magnitude" in str(err) or "constant" in str(err)
        assert not 1e-300 <= peak <= 1e300
    else:
        assert 1e-300 <= peak <= 1e300
        assert_array_equal(curve, _REF_MI)


def test_histogram_codes_stay_in_range_for_every_finite_span() -> None:
    for x in (
        np.array([-1.7e308, 1.7e308, 0.0, 1e308]),
        np.array([1e-300, np.nextafter(1e-300, 1.0), 1e-300]),  # subnormal span: inf scale
        np.array([5e-324, 0.0, 1e-323]),
        np.array([5e-324, 0.0]),  # halving rounds the span away
    ):
        codes = _kernels.bin_indices(x, 16)
        assert codes.min() >= 0 and codes.max() < 16


@functools.cache
def _unit_verdict():
    return classify(UNIT[:1000], dt=0.01, rng=0, n_surrogates=3, rule=CHEAP)


@pytest.mark.parametrize("exponent", [-1014, -700, 700, 1023])
def test_classify_is_scale_invariant_up_to_the_float64_limit(exponent: int) -> None:
    ref = _unit_verdict()
    got = classify(np.ldexp(UNIT[:1000], exponent), dt=0.01, rng=0, n_surrogates=3, rule=CHEAP)
    assert (got.label, got.lag, got.embedding_dim) == (ref.label, ref.lag, ref.embedding_dim)
    assert got.votes == ref.votes


@pytest.mark.parametrize("scale", [1.7e308, 1e-310])
def test_estimators_refuse_amplitudes_beyond_the_accepted_range(scale: float) -> None:
    x = HENON / np.max(np.abs(HENON)) * scale
    with pytest.raises(ValueError, match=r"peak magnitude .* outside the accepted range"):
        zero_one_test(x, rng=0)
    with pytest.raises(ValueError, match="peak magnitude"):
        iaaft_surrogates(x, n_surrogates=1, rng=0)


@pytest.mark.parametrize("exponent", [990, -990])
def test_surrogate_test_at_extreme_amplitudes_matches_unit_scale(exponent: int) -> None:
    kwargs = {"embedding_dim": 2, "lag": 1, "n_surrogates": 9, "alpha": 0.1, "rng": 0}
    ref = surrogate_test(HENON, **kwargs)
    res = surrogate_test(np.ldexp(HENON, exponent), **kwargs)  # peaks 1.3e±298
    assert res.p_value == ref.p_value
    assert res.rejected == ref.rejected
    assert np.isclose(res.effect, ref.effect, rtol=1e-12)


def _series(draw: st.DrawFn) -> np.ndarray:
    n = draw(st.integers(min_value=0, max_value=500))
    x = draw(
        arrays(
            np.float64,
            n,
            elements=st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False, width=64),
        )
    )
    scale = 10.0 ** draw(st.floats(min_value=-300.0, max_value=300.0))
    x = x * scale
    if n > 10 and draw(st.booleans()):  # a constant stretch
        a = draw(st.integers(0, n - 2))
        b = draw(st.integers(a + 1, n))
        x[a:b] = x[a]
    return x


@st.composite
def finite_series(draw: st.DrawFn) -> np.ndarray:
    return _series(draw)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(x=finite_series())
def test_fuzz_load_analyze_classify_never_crash(x: np.ndarray) -> None:
    """Random finite arrays: a result or a clear one-line ValueError, never another error."""
    try:
        ds = load_trajectory(x, dt=0.01)
    except ValueError as err:
        assert str(err) and "\n" not in str(err)
        return
    table = analyze(ds, rng=0, n_surrogates=3, rule=CHEAP)
    assert table.sizes["variable"] == 1
    try:
        # analyze gives each variable its own stream spawned from rng: the same one here
        stream = np.random.default_rng(0).spawn(1)[0]
        verdict = classify(x, dt=0.01, rng=stream, n_surrogates=3, rule=CHEAP)
    except ValueError as err:
        assert str(err) and "\n" not in str(err)
    else:
        assert verdict.label == str(table["label"].item())


@pytest.mark.parametrize(
    "spikes", [{0: 1.0, 1: 6.44986434e-195}, {0: 0.0, 132: -1.0}], ids=["zero", "level"]
)
def test_a_constant_series_with_isolated_spikes_is_analysed_alike_both_ways(spikes) -> None:
    """Two cases the fuzz test found: a series constant but for one or two samples (its
    trimmed part has no spread: the surrogate statistic is 0, not 0/0), through
    ``analyze`` and through ``classify`` with the stream ``analyze`` gives it."""
    x = np.full(200, 0.0 if 1 in spikes else -0.125)
    for i, value in spikes.items():
        x[i] = value
    table = analyze(load_trajectory(x, dt=0.01), rng=0, n_surrogates=3, rule=CHEAP)
    stream = np.random.default_rng(0).spawn(1)[0]
    verdict = classify(x, dt=0.01, rng=stream, n_surrogates=3, rule=CHEAP)
    assert verdict.label == str(table["label"].item())


def test_a_numpy_number_is_shown_plainly_in_the_message() -> None:
    """A bad value that arrives as a numpy scalar reads as a number, not as
    ``np.float64(...)``."""
    x = np.sin(np.arange(2000) * 0.1)
    with pytest.raises(ValueError) as info:
        lyapunov_rosenstein(x, dt=np.float64(-29.990000000000002))
    assert str(info.value) == "dt must be finite and > 0; got -29.990000000000002."


def test_a_time_index_that_contradicts_dt_is_refused() -> None:
    """A Series indexed by time stamps 10 ms apart, given to an estimator that takes
    ``dt``: the default dt = 1 would measure the exponent per sample, not per second, so
    the call is refused naming the interval; with dt = 0.01 it runs."""
    pd = pytest.importorskip("pandas")
    x = systems.lorenz(3000, dt=0.01)[:, 0]
    series = pd.Series(x, index=pd.date_range("2020", periods=x.size, freq="10ms"))
    with pytest.raises(ValueError, match=r"dt=1 contradicts the time index of x .*dt=0\.01"):
        lyapunov_rosenstein(series)
    assert lyapunov_rosenstein(series, dt=0.01).mle > 0.0
