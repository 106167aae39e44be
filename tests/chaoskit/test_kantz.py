"""Kantz's exponent: maps, held-out-style flows, noise, the kernel against brute force."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from chaoskit import KantzResult, LyapunovResult, lyapunov_kantz, lyapunov_rosenstein, systems
from chaoskit.lyapunov._kantz import _Search, noise_level

LOGISTIC = math.log(2.0)
HENON = 0.4192
LORENZ = 0.9056
ROSSLER = 0.0714
# forced Duffing x'' + 0.3x' − x + x³ = 0.5 cos 1.2t: variational equations (DOP853,
# rtol 1e-10) over 2,900 drive periods after 100 of transient; recomputed in the slow test
DUFFING = 0.0986
N = 20_000


def _covers(res, value: float) -> bool:
    return res.ci[0] <= value <= res.ci[1]


def test_logistic_and_henon() -> None:
    for x, true in ((systems.logistic(10_000), LOGISTIC), (systems.henon(10_000)[:, 0], HENON)):
        res = lyapunov_kantz(x)
        assert_allclose(res.mle, true, rtol=0.02)
        assert _covers(res, true)
        assert math.isnan(res.noise_level)  # maps: noise cannot be told from dynamics


def _duffing_x() -> tuple[np.ndarray, float]:
    t, state = systems.duffing(N)
    return state[:, 0], float(t[1] - t[0])


def test_forced_duffing_improves_on_rosenstein() -> None:
    """Rosenstein's defaults are −26 % here (weak chaos per orbit); Kantz within 8 %. Both
    intervals cover the truth: Rosenstein's carries the spread over plausible fit windows."""
    x, dt = _duffing_x()
    res = lyapunov_kantz(x, dt=dt)
    ros = lyapunov_rosenstein(x, dt=dt)
    assert_allclose(res.mle, DUFFING, rtol=0.08)
    assert abs(res.mle / DUFFING - 1) < 0.5 * abs(ros.mle / DUFFING - 1)
    assert _covers(res, DUFFING) and _covers(ros, DUFFING)


def test_rossler_sampled_at_0_1_improves_on_rosenstein() -> None:
    """Rosenstein −10.8 % (its interval, once too narrow, now covers); Kantz (transverse)
    within 6 %."""
    x = systems.rossler(N, dt=0.1)[:, 0]
    res = lyapunov_kantz(x, dt=0.1)
    ros = lyapunov_rosenstein(x, dt=0.1)
    assert_allclose(res.mle, ROSSLER, rtol=0.06)
    assert abs(res.mle / ROSSLER - 1) < abs(ros.mle / ROSSLER - 1)
    assert _covers(res, ROSSLER) and _covers(ros, ROSSLER)
    assert res.params["distance"] == "transverse"


def test_clean_lorenz_is_biased_high_but_covered() -> None:
    """Known miss (docs/estimators.md): +9.7 % at N = 2·10⁴, interval covers λ1."""
    res = lyapunov_kantz(systems.lorenz(N)[:, 0], dt=0.01)
    assert 0.0 < res.mle / LORENZ - 1 < 0.12
    assert _covers(res, LORENZ)
    assert res.params["distance"] == "euclidean"


def test_noisy_lorenz_radius_sits_above_the_measured_noise() -> None:
    """1 % noise: σ is measured within 10 %, every radius is ≥ 4σ; the exponent stays
    within 16 % (a known miss: +14.8 %, see docs/estimators.md)."""
    x = systems.lorenz(N)[:, 0]
    noisy = x + 0.01 * x.std() * np.random.default_rng(0).standard_normal(N)
    res = lyapunov_kantz(noisy, dt=0.01)
    assert_allclose(res.noise_level, 0.01 * x.std(), rtol=0.1)
    assert res.epsilon[0] >= 4 * res.noise_level * (1 - 1e-12)
    assert "noise level" in res.params["epsilon_rule"]
    assert abs(res.mle / LORENZ - 1) < 0.16


def test_noise_level_of_a_finely_sampled_sine() -> None:
    t = np.arange(20_000) * 0.01
    clean = np.sin(t) + 0.5 * np.sin(2.3 * t)
    noise = 0.02 * clean.std() * np.random.default_rng(1).standard_normal(t.size)
    sigma = noise_level((clean + noise) / (clean + noise).std(), lag=10)
    assert_allclose(sigma, 0.02 * clean.std() / (clean + noise).std(), rtol=0.05)
    assert math.isnan(noise_level(clean, lag=1))


def test_noisy_henon_beats_rosenstein() -> None:
    """1 % noise on a map (noise level not resolved): Kantz −11 %, Rosenstein −16 %; a
    known miss of the 5 % target (docs/estimators.md)."""
    x = systems.henon(20_000)[:, 0]
    noisy = x + 0.01 * x.std() * np.random.default_rng(2).standard_normal(x.size)
    res = lyapunov_kantz(noisy)
    ros = lyapunov_rosenstein(noisy)
    assert abs(res.mle / HENON - 1) < 0.12
    assert abs(res.mle / HENON - 1) < abs(ros.mle / HENON - 1)


@pytest.mark.parametrize(
    "signal",
    [
        np.sin(0.05 * np.arange(10_000)),
        systems.torus(10_000),
    ],
)
def test_regular_signals_give_no_confident_positive(signal) -> None:
    res = lyapunov_kantz(signal, dt=0.05)
    assert res.ci[0] <= 0.0 or res.mle * 0.05 < 0.01


def _brute(pts, ref, w, eps, ks, transverse):
    """Independent numpy reference of the kernel (no neighbour cap)."""
    out = np.full((ref.size, eps.size, ks.size), np.nan)
    usable = pts.shape[0] - ks[-1]
    for r, i in enumerate(ref):
        d0 = np.abs(pts[:usable] - pts[i]).max(axis=1)
        far = np.abs(np.arange(usable) - i) > w
        for e, radius in enumerate(eps):
            nb = np.flatnonzero(far & (d0 < radius))
            if nb.size == 0:
                continue
            for q, k in enumerate(ks):
                d = pts[nb + k] - pts[i + k]
                if transverse:
                    lo, hi = max(i + k - 1, 0), min(i + k + 1, pts.shape[0] - 1)
                    v = pts[hi] - pts[lo]
                    d2 = (d * d).sum(axis=1) - (d @ v) ** 2 / (v @ v)
                    dist = np.sqrt(np.maximum(d2, 0.0))
                else:
                    dist = np.linalg.norm(d, axis=1)
                out[r, e, q] = np.log(dist.mean())
    return out


@pytest.mark.parametrize("transverse", [False, True])
def test_kernel_matches_brute_force(transverse: bool) -> None:
    pts = np.ascontiguousarray(np.random.default_rng(3).standard_normal((600, 3)))
    ks = np.array([0, 1, 3, 7], dtype=np.int64)
    usable = pts.shape[0] - ks[-1]
    ref = np.arange(0, usable, 17, dtype=np.int64)
    eps = np.array([0.4, 0.6, 0.9])
    search = _Search(pts, pts[:usable], ref, 5, eps, ks, 10_000)
    out, used, total, count = search.log_distances(transverse, eps.size - 1)
    expect = _brute(pts, ref, 5, eps, ks, transverse)
    assert_allclose(out, expect, rtol=1e-12, equal_nan=True)
    assert ((used > 0) == np.isfinite(expect[:, :, 0])).all()
    finite = np.isfinite(expect)
    assert_allclose(total, np.where(finite, expect, 0.0).sum(axis=0), rtol=1e-12)
    assert (count == finite.sum(axis=0)).all()


@pytest.mark.parametrize("dim", [1, 2, 3, 4])
def test_kernel_on_consecutive_horizons_matches_brute_force(dim: int) -> None:
    # 64 or more consecutive horizons take the fused distance-root-sum pass for up to
    # three coordinates, the general one beyond
    pts = np.ascontiguousarray(np.random.default_rng(5 + dim).standard_normal((700, dim)))
    ks = np.arange(0, 70, dtype=np.int64)
    usable = pts.shape[0] - ks[-1]
    ref = np.arange(0, usable, 13, dtype=np.int64)
    eps = np.array([0.3, 0.5, 0.8]) * dim**0.5
    search = _Search(pts, pts[:usable], ref, 2, eps, ks, 10_000)
    out, used, total, count = search.log_distances(False, eps.size - 1)
    expect = _brute(pts, ref, 2, eps, ks, False)
    assert ((used > 0) == np.isfinite(expect[:, :, 0])).all()
    assert np.isfinite(expect).sum() > 100
    # (absolute tolerance: a mean distance near 1 has a log near 0)
    assert_allclose(out, expect, rtol=1e-12, atol=1e-14, equal_nan=True)
    finite = np.isfinite(expect)
    assert_allclose(total, np.where(finite, expect, 0.0).sum(axis=0), rtol=1e-12, atol=1e-12)
    assert (count == finite.sum(axis=0)).all()


def _brute_delay(series, m, lag, ref, w, eps, ks, ball, squared):
    """Independent numpy reference on a delay embedding, any norm and average."""
    pts = np.column_stack([series[c * lag : series.size - (m - 1 - c) * lag] for c in range(m)])
    out = np.full((ref.size, eps.size, ks.size), np.nan)
    usable = pts.shape[0] - ks[-1]
    for r, i in enumerate(ref):
        diff0 = pts[:usable] - pts[i]
        d0 = np.sqrt((diff0 * diff0).sum(axis=1)) if ball else np.abs(diff0).max(axis=1)
        far = np.abs(np.arange(usable) - i) > w
        for e, radius in enumerate(eps):
            nb = np.flatnonzero(far & (d0 < radius))
            if nb.size == 0:
                continue
            for q, k in enumerate(ks):
                d = pts[nb + k] - pts[i + k]
                d2 = (d * d).sum(axis=1)
                out[r, e, q] = 0.5 * np.log(d2.mean()) if squared else np.log(np.sqrt(d2).mean())
    return pts, out


@pytest.mark.parametrize("squared", [False, True])
@pytest.mark.parametrize("ball", [False, True])
@pytest.mark.parametrize(
    ("m", "lag", "nk"), [(1, 1, 21), (2, 1, 21), (3, 4, 21), (3, 4, 70), (4, 2, 21)]
)
def test_delay_kernel_norms_and_averages_match_brute_force(m, lag, nk, ball, squared) -> None:
    """The delay-embedding pass (each squared sample difference once), the Euclidean ball
    and the RMS average against numpy, within 1e-12: short curves take the delay pass,
    long ones of at most three coordinates the fused pass."""
    series = np.random.default_rng(11 + m + lag).standard_normal(900)
    ks = np.arange(0, nk, dtype=np.int64)
    pts, expect = _brute_delay(
        series, m, lag, np.empty(0, np.int64), 3, np.ones(1), ks, ball, squared
    )
    usable = pts.shape[0] - ks[-1]
    ref = np.arange(0, usable, 11, dtype=np.int64)
    eps = np.array([0.35, 0.6, 0.9]) * m**0.5
    pts, expect = _brute_delay(series, m, lag, ref, 3, eps, ks, ball, squared)
    search = _Search(
        np.ascontiguousarray(pts),
        pts[:usable],
        ref,
        3,
        eps,
        ks,
        10_000,
        series=series,
        lag=lag,
        ball=ball,
        squared=squared,
    )
    out, used, total, count = search.log_distances(False, eps.size - 1)
    assert np.isfinite(expect).sum() > 100
    assert ((used > 0) == np.isfinite(expect[:, :, 0])).all()
    assert_allclose(out, expect, rtol=1e-12, atol=1e-14, equal_nan=True)
    finite = np.isfinite(expect)
    assert_allclose(total, np.where(finite, expect, 0.0).sum(axis=0), rtol=1e-12, atol=1e-12)
    assert (count == finite.sum(axis=0)).all()


def test_tisean_definition_keeps_the_slope() -> None:
    """Euclidean balls and ln of the RMS distance (TISEAN's lyap_k) against the default
    cubes and ln of the mean distance, on the same radii and fit window."""
    x = systems.henon(20_000)[:, 0]
    kw = dict(epsilon=[0.02, 0.04], fit_range=(1, 8), max_horizon=20)
    a = lyapunov_kantz(x, **kw)
    b = lyapunov_kantz(x, definition="rms", **kw)
    assert b.params["norm"] == "euclidean" and b.params["average"] == "rms"
    assert a.params["norm"] == "maximum" and a.params["average"] == "distance"
    # measured: 0.4299 and 0.4406 (2.5 % apart); the true value 0.4192
    assert abs(b.mle / a.mle - 1.0) < 0.03
    assert abs(b.mle - HENON) < 0.03


def test_neighbour_cap_takes_a_strided_subset() -> None:
    pts = np.ascontiguousarray(np.random.default_rng(4).standard_normal((2000, 2)))
    ks = np.array([0, 2], dtype=np.int64)
    ref = np.array([100, 900], dtype=np.int64)
    search = _Search(pts, pts[:-2], ref, 0, np.array([1.0]), ks, 7)
    used = search.log_distances(False)[1]
    assert (used <= 7).all() and (used >= 4).all()


def test_result_carries_every_radius_and_converts(tmp_path) -> None:
    res = lyapunov_kantz(systems.henon(5_000)[:, 0], epsilon=[0.05, 0.1, 0.2])
    assert isinstance(res, KantzResult) and isinstance(res, LyapunovResult)
    assert res.params["epsilon_rule"] == "given"
    assert_allclose(res.epsilon, [0.05, 0.1, 0.2])
    assert res.curves.shape == (3, res.horizon.size)
    assert_allclose(res.curve, res.curves[res.epsilon_index])
    assert res.method == "kantz"
    with pytest.raises(AttributeError):
        res.mle = 1.0  # type: ignore[misc]
    ds = res.to_dataset()
    for name in ("log_divergence", "log_divergence_by_epsilon", "mle_by_epsilon", "epsilon"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    path = tmp_path / "kantz.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    back = xr.load_dataset(path, engine="h5netcdf")
    assert_allclose(back["log_divergence_by_epsilon"].values, res.curves)
    assert back.attrs["epsilon_chosen"] == res.epsilon[res.epsilon_index]


def test_amplitude_invariance() -> None:
    x = systems.henon(5_000)[:, 0]
    a = lyapunov_kantz(x)
    b = lyapunov_kantz(1e6 * x + 3.0)
    assert_allclose(b.mle, a.mle, rtol=1e-9)
    assert_allclose(b.epsilon, 1e6 * a.epsilon, rtol=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"epsilon": [-1.0]}, "epsilon"),
        ({"epsilon": [np.nan]}, "epsilon"),
        ({"max_neighbors": 0}, "max_neighbors"),
        ({"max_points": 3}, "max_points"),
        ({"distance": "manhattan"}, "distance"),
        ({"definition": "median"}, "definition must be one of"),
        ({"fit_range": (5, 2)}, "fit_range"),
        ({"epsilon": [1e-9]}, "neighbour"),
    ],
)
def test_bad_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        lyapunov_kantz(systems.henon(3_000)[:, 0], **kwargs)


@pytest.mark.slow
def test_duffing_reference_exponent() -> None:
    """Recompute DUFFING from the variational equations (Benettin, SciPy DOP853)."""
    from scipy.integrate import solve_ivp

    d, a, b, g, w = 0.3, -1.0, 1.0, 0.5, 1.2

    def rhs(t, s):
        x, v, p, q = s
        return [
            v,
            -d * v - a * x - b * x**3 + g * np.cos(w * t),
            q,
            -(a + 3 * b * x * x) * p - d * q,
        ]

    period = 2 * np.pi / w
    s = np.array([1.0, 0.0, 1.0, 0.0])
    total, t = 0.0, 0.0
    for i in range(1100):
        sol = solve_ivp(rhs, (t, t + period), s, method="DOP853", rtol=1e-10, atol=1e-12)
        s, t = sol.y[:, -1], t + period
        norm = float(np.hypot(s[2], s[3]))
        s[2:] /= norm
        if i >= 100:
            total += math.log(norm)
    assert_allclose(total / (1000 * period), DUFFING, rtol=0.03)
