"""Largest Lyapunov exponent: known exponents, non-chaotic signals, nolds cross-check."""

from __future__ import annotations

import math

import nolds
import numpy as np
import pandas as pd
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from chaoskit import LyapunovResult, lyapunov_rosenstein, lyapunov_wolf, systems

LOGISTIC = math.log(2.0)
HENON = 0.4192
LORENZ = 0.9056
ROSSLER = 0.0714

METHODS = [lyapunov_rosenstein, lyapunov_wolf]


@pytest.mark.parametrize("method", METHODS)
def test_logistic_map(method) -> None:
    res = method(systems.logistic(10_000))
    assert_allclose(res.mle, LOGISTIC, rtol=0.02)
    assert res.lag == 1 and res.embedding_dim == 1
    assert_allclose(res.mle_bits_per_sample, res.mle / math.log(2.0), rtol=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_henon_map(method) -> None:
    res = method(systems.henon(10_000)[:, 0])
    assert_allclose(res.mle, HENON, rtol=0.02)
    assert res.embedding_dim == 2
    assert res.ci[0] < res.mle < res.ci[1]


# initial conditions for the robustness tests (each run discards 5000 samples of transient)
LORENZ_ICS = [(1.0, 1.0, 1.0), (-5.0, 3.0, 20.0), (2.0, -7.0, 25.0), (10.0, 10.0, 30.0)]
ROSSLER_ICS = [(1.0, 1.0, 0.0), (-3.0, 2.0, 0.1), (4.0, -1.0, 0.3), (-6.0, -2.0, 0.5)]


def _lorenz_x(n: int, ic: int) -> np.ndarray:
    return systems.lorenz(n, dt=0.01, initial=LORENZ_ICS[ic])[:, 0]


def _rossler_x(n: int, ic: int) -> np.ndarray:
    return systems.rossler(n, dt=0.05, initial=ROSSLER_ICS[ic])[:, 0]


def _covers(res, value: float) -> bool:
    return res.ci[0] <= value <= res.ci[1]


@pytest.mark.parametrize("ic", [0, 1, 2])
def test_lorenz_x_rosenstein_50k(ic: int) -> None:
    res = lyapunov_rosenstein(_lorenz_x(50_000, ic), dt=0.01)
    assert_allclose(res.mle, LORENZ, rtol=0.05)
    assert _covers(res, LORENZ), res.ci
    assert res.fit_found and res.embedding_dim == 3 and 15 <= res.lag <= 20
    # a flow: the mean of the nearest-sample and closest-orbit-point curves
    assert res.params["neighbor"] == "mean" and res.params["distance"] == "euclidean"
    # the fit starts after the alignment transient and ends before saturation
    assert 20 <= res.fit_range[0] < res.fit_range[1] <= 500


@pytest.mark.parametrize("ic", [0, 1, 2, 3])
def test_lorenz_x_rosenstein_10k(ic: int) -> None:
    """N = 10⁴ (≈ 60 orbits): −5 … +7 % over these initial conditions, interval covers."""
    res = lyapunov_rosenstein(_lorenz_x(10_000, ic), dt=0.01)
    assert_allclose(res.mle, LORENZ, rtol=0.08)
    assert _covers(res, LORENZ), res.ci
    assert res.fit_found


@pytest.mark.slow
@pytest.mark.parametrize("ic", [0, 1, 2, 3])
def test_lorenz_x_rosenstein_100k(ic: int) -> None:
    res = lyapunov_rosenstein(_lorenz_x(100_000, ic), dt=0.01)
    assert_allclose(res.mle, LORENZ, rtol=0.055)
    assert _covers(res, LORENZ), res.ci


def test_lorenz_x_wolf_10k() -> None:
    res = lyapunov_wolf(_lorenz_x(10_000, 0), dt=0.01)
    assert_allclose(res.mle, LORENZ, rtol=0.10)


def test_wolf_bounds_from_below_only_when_its_separations_run_saturated() -> None:
    """A band no point lies in leaves Wolf no replacement: every interval keeps its evolved
    neighbour from above the band, the separations run near the attractor's size and the
    stretching is biased low, so the interval reaches +inf (and only then)."""
    x = _lorenz_x(10_000, 0)
    ok = lyapunov_wolf(x, dt=0.01)
    assert ok.params["saturated_fraction"] < 0.1 and math.isfinite(ok.ci[1])
    starved = lyapunov_wolf(x, dt=0.01, scale=(1e-6, 2e-6))
    assert starved.params["saturated_fraction"] > 0.9
    assert starved.mle < 0.5 * LORENZ  # the bias the open upper end admits
    assert starved.ci[1] == math.inf and math.isfinite(starved.ci[0])
    assert "upper end +inf" in starved.ci_method


@pytest.mark.parametrize("ic", [0, 1, 2])
def test_lorenz_x_wolf_50k(ic: int) -> None:
    res = lyapunov_wolf(_lorenz_x(50_000, ic), dt=0.01)
    assert_allclose(res.mle, LORENZ, rtol=0.10)
    assert res.params["max_angle_rule"] == "auto: 45°"


@pytest.mark.parametrize("ic", [0, 1, 2, 3])
def test_rossler_x_rosenstein_50k(ic: int) -> None:
    res = lyapunov_rosenstein(_rossler_x(50_000, ic), dt=0.05)
    assert_allclose(res.mle, ROSSLER, rtol=0.10)
    # weak chaos per orbit: the automatic rule switches to the transverse distance
    assert res.params["distance"] == "transverse"


@pytest.mark.parametrize("ic", [0, 1, 2, 3])
def test_rossler_x_wolf_50k(ic: int) -> None:
    res = lyapunov_wolf(_rossler_x(50_000, ic), dt=0.05)
    assert_allclose(res.mle, ROSSLER, rtol=0.10)
    # weak chaos per orbit: the automatic rule tightens the replacement angle
    assert res.params["max_angle"] == pytest.approx(0.2)


@pytest.mark.slow
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("ic", [0, 1, 2, 3])
def test_rossler_x_100k(method, ic: int) -> None:
    res = method(_rossler_x(100_000, ic), dt=0.05)
    assert_allclose(res.mle, ROSSLER, rtol=0.10)


def test_distance_rule_keeps_euclidean_for_lorenz_and_maps() -> None:
    assert (
        lyapunov_rosenstein(systems.lorenz(10_000)[:, 0], dt=0.01).params["distance"] == "euclidean"
    )
    assert lyapunov_rosenstein(systems.henon(5000)[:, 0]).params["distance"] == "euclidean"


def test_explicit_distances_differ_only_in_the_curve() -> None:
    x = systems.rossler(20_000)[:, 0]
    e = lyapunov_rosenstein(x, dt=0.05, distance="euclidean")
    t = lyapunov_rosenstein(x, dt=0.05, distance="transverse")
    assert (e.lag, e.embedding_dim, e.n_points) == (t.lag, t.embedding_dim, t.n_points)
    assert t.mle > e.mle  # removing the neutral along-flow part steepens the curve
    with pytest.raises(ValueError, match="distance must be one of"):
        lyapunov_rosenstein(x, dt=0.05, distance="manhattan")


def test_orbit_shift_finds_the_closest_point_of_a_sampled_orbit() -> None:
    """Two concentric circles sampled coarsely: the orbit distance is the radial gap."""
    from chaoskit.lyapunov import _kernels as _k

    t = np.arange(400) * 0.1
    inner = np.c_[np.cos(t), np.sin(t)]
    outer = 1.01 * np.c_[np.cos(t[:200] + 0.037), np.sin(t[:200] + 0.037)]
    pts = np.ascontiguousarray(np.vstack([inner[:200], outer]))
    ref = np.arange(10, 190, dtype=np.int64)
    nbr = ref + 200  # same sample index on the outer circle, 0.037 rad ahead
    shift = _k.orbit_shifts(pts, ref, nbr)
    assert_allclose(shift, -0.37, atol=0.01)  # −0.037 rad at 0.1 rad per sample
    pairs = zip(ref, nbr, shift, strict=True)
    d_orbit = [np.sqrt(_k.orbit_sq_distance(pts, i, j, s)) for i, j, s in pairs]
    d_sample = np.linalg.norm(pts[nbr] - pts[ref], axis=1)
    assert_allclose(d_orbit, 0.01, rtol=2e-3)
    assert np.all(d_sample > 0.037)


def test_neighbor_options_and_the_mean_curve() -> None:
    x = _lorenz_x(20_000, 0)
    kw = {"dt": 0.01, "max_horizon": 400, "fit_range": (80, 250)}
    sample = lyapunov_rosenstein(x, neighbor="sample", **kw)
    orbit = lyapunov_rosenstein(x, neighbor="orbit", **kw)
    mean = lyapunov_rosenstein(x, neighbor="mean", **kw)
    auto = lyapunov_rosenstein(x, **kw)
    assert (sample.params["neighbor"], orbit.params["neighbor"]) == ("sample", "orbit")
    assert auto.params["neighbor"] == "mean" and auto.mle == mean.mle
    # moving each neighbour to its orbit's closest point removes the along-flow offset
    assert orbit.curve[0] < sample.curve[0] - 0.3
    assert_allclose(mean.curve, 0.5 * (sample.curve + orbit.curve), rtol=1e-12)
    assert sample.mle < mean.mle < orbit.mle
    # the interval is widened by half the sample-vs-orbit slope difference
    assert_allclose(mean.params["ci_neighbor_half_width"], 0.5 * (orbit.mle - sample.mle))
    assert mean.ci[1] - mean.mle >= mean.params["ci_neighbor_half_width"]
    # maps have no flow direction: nearest sample
    assert lyapunov_rosenstein(systems.henon(3000)[:, 0]).params["neighbor"] == "sample"
    with pytest.raises(ValueError, match="neighbor must be one of"):
        lyapunov_rosenstein(x, dt=0.01, neighbor="closest")


def _sine(n: int) -> tuple[np.ndarray, float]:
    dt = 0.05
    return np.sin(2 * np.pi * 0.37 * np.arange(n) * dt), dt


def _vdp(n: int) -> tuple[np.ndarray, float]:
    return systems.van_der_pol(n, dt=0.05)[:, 0], 0.05


def _torus(n: int) -> tuple[np.ndarray, float]:
    return systems.torus(n, dt=0.05), 0.05


@pytest.mark.parametrize("signal", [_sine, _vdp, _torus], ids=["sine", "van_der_pol", "torus"])
@pytest.mark.parametrize("method", METHODS)
def test_never_a_confident_positive_on_regular_signals(signal, method) -> None:
    x, dt = signal(10_000)
    res = method(x, dt=dt)
    # the interval contains 0, or the exponent is below 1 % of the sampling rate
    assert res.ci[0] <= 0.0 <= res.ci[1] or res.mle < 0.01 / dt, (res.mle, res.ci)


@pytest.mark.parametrize(
    ("name", "x", "dt", "m", "lag", "w", "fit"),
    [
        ("henon", systems.henon(3000)[:, 0], 1.0, 2, 1, 10, (1, 10)),
        ("lorenz", systems.lorenz(3000)[:, 0], 0.01, 3, 17, 100, (60, 250)),
    ],
)
def test_rosenstein_agrees_with_nolds(name, x, dt, m, lag, w, fit) -> None:
    """Independent implementation, same embedding, Theiler window and fit range: within 2 %."""
    a, b = fit
    expected = nolds.lyap_r(
        x,
        emb_dim=m,
        lag=lag,
        min_tsep=w,
        tau=dt,
        trajectory_len=b + 1,
        fit="poly",
        fit_offset=a,
    )
    res = lyapunov_rosenstein(
        x,
        embedding_dim=m,
        lag=lag,
        dt=dt,
        theiler_window=w,
        max_horizon=b,
        fit_range=fit,
        max_points=10**6,
        neighbor="sample",
    )
    assert_allclose(res.mle, expected, rtol=0.02)
    assert res.fit_range == fit and not res.subsampled


def test_given_parameters_are_used_and_reported() -> None:
    x = systems.henon(5000)[:, 0]
    res = lyapunov_rosenstein(x, embedding_dim=3, lag=1, theiler_window=7, max_horizon=30)
    assert (res.embedding_dim, res.lag, res.theiler_window) == (3, 1, 7)
    assert res.lag_rule == res.dim_rule == "given"
    assert res.horizon[-1] == 30 and res.curve.shape == res.horizon.shape
    assert res.params["max_horizon"] == 30


def test_long_series_are_subsampled_and_say_so() -> None:
    res = lyapunov_rosenstein(systems.logistic(30_000), max_points=2000)
    assert res.subsampled and res.n_points == 2000
    assert_allclose(res.mle, LOGISTIC, rtol=0.02)


@pytest.mark.parametrize(
    "wrap", [pd.Series, lambda a: xr.DataArray(a, dims="time"), lambda a: list(a)]
)
def test_input_types(wrap) -> None:
    x = systems.henon(3000)[:, 0]
    ref = lyapunov_rosenstein(x).mle
    assert lyapunov_rosenstein(wrap(x)).mle == ref


@pytest.mark.parametrize("method", METHODS)
def test_result_is_frozen_and_converts_to_a_dataset(method, tmp_path) -> None:
    res = method(systems.henon(3000)[:, 0])
    assert isinstance(res, LyapunovResult)
    with pytest.raises(AttributeError):
        res.mle = 0.0  # type: ignore[misc]
    ds = res.to_dataset()
    for name in ds.variables:
        assert "units" in ds[name].attrs and "long_name" in ds[name].attrs
    assert ds.attrs["mle"] == res.mle and ds.attrs["method"] == method.__name__[9:]
    ds.to_netcdf(tmp_path / "res.nc", engine="h5netcdf")  # attrs are netCDF-safe
    with xr.open_dataset(tmp_path / "res.nc", engine="h5netcdf") as back:
        assert back.attrs["mle"] == res.mle


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"dt": 0.0}, "dt must be finite and > 0"),
        ({"dt": -1.0}, "dt"),
        ({"lag": 0}, "lag"),
        ({"embedding_dim": 0}, "embedding_dim"),
        ({"theiler_window": -1}, "theiler_window"),
        ({"theiler_window": 600}, "needs at least"),
    ],
)
def test_bad_options(method, kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        method(systems.henon(1000)[:, 0], **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"fit_range": "manual"}, "fit_range"),
        ({"fit_range": (5, 2)}, "fit_range"),
        ({"max_horizon": 10, "fit_range": (1, 20)}, "beyond max_horizon"),
        ({"max_horizon": 1}, "max_horizon"),
        ({"max_horizon": 5000}, "needs at least"),
    ],
)
def test_bad_rosenstein_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        lyapunov_rosenstein(systems.henon(1000)[:, 0], **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"scale": (1.0, 0.5)}, "scale"),
        ({"scale": "wide"}, "scale"),
        ({"max_angle": 4.0}, "max_angle"),
        ({"evolve": 0}, "evolve"),
        ({"replace": "never"}, "replace"),
    ],
)
def test_bad_wolf_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        lyapunov_wolf(systems.henon(1000)[:, 0], **kwargs)


def test_wolf_paper_variant_runs_and_reports_bits() -> None:
    x = systems.henon(5000)[:, 0]
    res = lyapunov_wolf(x, evolve=1, replace="always")
    assert res.params["replace"] == "always" and res.params["evolve"] == 1
    assert_allclose(res.mle, HENON, rtol=0.05)
    assert_allclose(res.mle_bits_per_sample, res.mle / math.log(2.0), rtol=1e-12)


def _synthetic_curve(noise: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray, float]:
    """Steep transient (k < 30), straight part of slope 0.02, then exponential saturation."""
    k = np.arange(1000)
    y = np.where(k < 30, 0.06 * k, 1.8 + 0.02 * (k - 30))
    bend = k > 300
    y = np.where(bend, 7.8 + 4.0 * (1 - np.exp(-0.02 * (k - 300))), y)
    y = y + noise * np.random.default_rng(seed).standard_normal(k.size)
    return k, y - 5.0, 11.8 - 5.0  # curve and plateau


@pytest.mark.parametrize("noise", [0.0, 0.01])
def test_scaling_region_finds_the_straight_part(noise: float) -> None:
    from chaoskit.lyapunov._scaling import scaling_region

    k, y, plateau = _synthetic_curve(noise)
    a, b, found = scaling_region(k, y, plateau=plateau, min_span=50)
    assert found
    assert 25 <= k[a] <= 60 and 150 <= k[b] <= 305
    slope = np.polyfit(k[a : b + 1], y[a : b + 1], 1)[0]
    assert_allclose(slope, 0.02, rtol=0.02)


def test_scaling_region_reports_missing_straight_part() -> None:
    from chaoskit.lyapunov._scaling import scaling_region

    k = np.arange(200)
    y = np.random.default_rng(1).standard_normal(200)  # no trend at all
    a, b, found = scaling_region(k, y, plateau=5.0, min_span=20)
    assert not found and (a, b) == (0, 199)


def test_fit_window_family_spread() -> None:
    from chaoskit.lyapunov._scaling import family_spread

    k = np.arange(200, dtype=np.float64)
    line = 0.05 * k
    assert family_spread(k, line, 20, 150, 199, min_span=10) == pytest.approx((0, 0), abs=1e-12)
    # two straight stretches of (nearly) equal rise, slopes 0.05 and 0.0415: the largest-rise
    # rule cannot tell them apart, so the spread is their difference
    k = np.arange(220, dtype=np.float64)
    kinked = np.where(k < 100, 0.05 * k, 5.0 + 0.0415 * (k - 100))
    below, above = family_spread(k, kinked, 0, 99, 219, min_span=10)
    assert below == pytest.approx(0.0085, rel=0.05) and above == pytest.approx(0.0, abs=1e-9)


def test_with_systematic_adds_the_relative_term_in_quadrature() -> None:
    from chaoskit.lyapunov._common import SYSTEMATIC, with_systematic

    (low, high), sys_half, note = with_systematic(2.0, 0.3, 0.4, method="rosenstein", flow=True)
    rel = SYSTEMATIC["rosenstein"][1]
    assert_allclose(sys_half, rel * 2.0)
    assert_allclose(
        (low, high), (2.0 - math.hypot(0.3, rel * 2.0), 2.0 + math.hypot(0.4, rel * 2.0))
    )
    assert "flows" in note and f"{rel:.0%}" in note
    # every relative term is below 1: it alone never moves a bound across zero
    assert all(0.0 < r < 1.0 for pair in SYSTEMATIC.values() for r in pair)
    (low, _), _, _ = with_systematic(-1.0, 0.0, 0.0, method="wolf", flow=False)
    assert_allclose(low, -1.0 - SYSTEMATIC["wolf"][0])


@pytest.mark.parametrize("method", METHODS)
def test_interval_carries_the_systematic_term_of_flows_and_maps(method) -> None:
    from chaoskit.lyapunov._common import SYSTEMATIC

    name = "rosenstein" if method is lyapunov_rosenstein else "wolf"
    for x, dt, flow, truth in (
        (_lorenz_x(10_000, 0), 0.01, True, LORENZ),
        (systems.henon(5000)[:, 0], 1.0, False, HENON),
    ):
        res = method(x, dt=dt)
        sys_half = res.params["ci_systematic_half_width"]
        assert_allclose(sys_half, SYSTEMATIC[name][int(flow)] * abs(res.mle))
        assert res.mle - res.ci[0] >= sys_half and res.ci[1] - res.mle >= sys_half
        assert _covers(res, truth), (res.mle, res.ci)
        assert res.ci[0] > 0.0  # a well-resolved exponent stays clearly positive
