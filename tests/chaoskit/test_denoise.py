"""Local projective noise reduction (GHKSS): accuracy on known systems, inputs and errors.

The bounds were measured over five noise seeds (0–4) on the Hénon map's x with N = 5000
(``benchmarks/denoise_accuracy.py`` has the tables) and leave a margin; they concern
averages over thousands of samples, which a 1e-12 change of the initial state does not move.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from chaoskit import DenoiseResult, local_projective_denoise, lyapunov_rosenstein, systems

HENON_MLE = 0.419  # natural log per iteration


@pytest.fixture(scope="module")
def henon_x() -> np.ndarray:
    return systems.henon(5000)[:, 0]


def _noisy(x: np.ndarray, level: float, seed: int = 0) -> np.ndarray:
    return x + level * x.std() * np.random.default_rng(seed).standard_normal(x.size)


def _rms(a: np.ndarray) -> float:
    return float(np.sqrt(np.mean(a**2)))


@pytest.mark.parametrize("level", [0.05, 0.10])
def test_henon_noise_is_reduced(henon_x: np.ndarray, level: float) -> None:
    """RMS error to the clean series falls by at least 2.8× (measured 3.5–4.0 over five
    seeds); the noise level estimated from the data is within 30 % of the true one
    (measured −11 % at 5 %, −20 % at 10 %)."""
    noisy = _noisy(henon_x, level)
    res = local_projective_denoise(noisy)
    assert isinstance(res, DenoiseResult)
    assert _rms(noisy - henon_x) / _rms(res.cleaned - henon_x) >= 2.8
    assert res.noise_level == pytest.approx(level * henon_x.std(), rel=0.3)
    assert (res.lag, res.manifold_dim, res.iterations) == (1, 2, 3)
    # each pass corrects less than the one before: the radius follows the remaining noise
    assert np.all(np.diff(res.correction_rms) < 0)


def test_lyapunov_exponent_closer_to_truth_after_denoising(henon_x: np.ndarray) -> None:
    """At 5 % noise Rosenstein's estimate is biased low (by 0.08–0.09 on average over six
    noise seeds); on the cleaned series the mean absolute error over the same seeds is at
    most 0.70 of that (measured 0.38–0.70 on six orbits whose initial states differ by
    1e-12 to 1e-9): single seeds scatter too much (the cleaned series' estimate lies
    0.01–0.09 above the true value) to be compared one by one."""
    before, after = [], []
    for seed in range(6):
        noisy = _noisy(henon_x, 0.05, seed)
        before.append(lyapunov_rosenstein(noisy).mle - HENON_MLE)
        after.append(lyapunov_rosenstein(local_projective_denoise(noisy).cleaned).mle - HENON_MLE)
    assert np.mean(before) < -0.05
    assert np.mean(np.abs(after)) < 0.85 * np.mean(np.abs(before))


def test_clean_series_is_barely_changed(henon_x: np.ndarray) -> None:
    """Without noise the corrections stay below 0.5 % of the standard deviation (measured
    0.13 %): only the curvature of the attractor within a neighbourhood is seen."""
    res = local_projective_denoise(henon_x)
    assert np.all(res.correction_rms < 0.005 * henon_x.std())
    assert _rms(res.cleaned - henon_x) < 0.005 * henon_x.std()


def test_sine_on_a_plane_is_cleaned() -> None:
    """Delay vectors of a sine lie on an ellipse in a plane; projecting onto that plane
    (manifold_dim=2) removes noise: RMS error down by at least 1.8× (measured 2.3–2.7)."""
    t = np.arange(4000)
    clean = np.sin(2 * np.pi * t / 50)
    noisy = _noisy(clean, 0.10)
    res = local_projective_denoise(noisy, manifold_dim=2)
    assert res.manifold_dim_rule == "given"
    assert _rms(noisy - clean) / _rms(res.cleaned - clean) >= 1.8


def test_dataarray_in_and_out(henon_x: np.ndarray) -> None:
    """A trajectory variable keeps its axis, units and long name; dt comes from its time."""
    t = 0.002 * np.arange(2000)
    da = xr.DataArray(
        _noisy(henon_x[:2000], 0.05),
        dims="time",
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        name="gap",
        attrs={"units": "m", "long_name": "bearing gap"},
    )
    ds = xr.Dataset({"gap": da})
    res = local_projective_denoise(ds["gap"], embedding_dim=5, lag=1, manifold_dim=2)
    assert res.dt == pytest.approx(0.002, rel=1e-9)
    out = res.to_dataarray()
    assert out.name == "gap" and out.dims == ("time",)
    assert out.attrs["units"] == "m"
    assert out.attrs["long_name"] == "bearing gap, noise-reduced (local projective)"
    np.testing.assert_allclose(out["time"].values, t, rtol=0, atol=0)
    full = res.to_dataset()
    for name in ("gap", "gap_original", "correction", "correction_rms", "radius"):
        assert {"units", "long_name"} <= set(full[name].attrs)
    assert full["correction_rms"].sizes["iteration"] == 3
    assert full.attrs["embedding_dim_rule"] == "given"
    assert "chaoskit.local_projective_denoise: embedding_dim=5" in full.attrs["history"]
    np.testing.assert_allclose(full["gap_original"].values, da.values, rtol=0, atol=0)


def test_pandas_time_index_gives_dt(henon_x: np.ndarray) -> None:
    index = pd.timedelta_range(start="0s", periods=1000, freq="5ms")
    series = pd.Series(_noisy(henon_x[:1000], 0.05), index=index, name="acc")
    res = local_projective_denoise(series, embedding_dim=4, lag=1, manifold_dim=2)
    assert res.dt == pytest.approx(0.005, rel=1e-9)
    out = res.to_dataarray()
    assert out.dims == ("time",) and out.name == "acc"
    np.testing.assert_allclose(out["time"].values[:3], [0.0, 0.005, 0.01], rtol=1e-12)


def test_dt_contradicting_the_time_axis_is_refused(henon_x: np.ndarray) -> None:
    da = xr.DataArray(henon_x[:500], dims="time", coords={"time": 0.01 * np.arange(500)})
    with pytest.raises(
        ValueError,
        match=r"^dt=0\.02 contradicts the time axis of x \(sampling interval 0\.01\); leave "
        r"dt out, the interval is known\.$",
    ):
        local_projective_denoise(da, dt=0.02, embedding_dim=3, lag=1)


def test_scale_and_offset_do_not_matter(henon_x: np.ndarray) -> None:
    noisy = _noisy(henon_x[:2000], 0.05)
    opts = {"embedding_dim": 5, "lag": 1, "manifold_dim": 2, "iterations": 2}
    a = local_projective_denoise(noisy, **opts)
    b = local_projective_denoise(1e3 * noisy + 7.0, **opts)
    np.testing.assert_allclose(b.cleaned, 1e3 * a.cleaned + 7.0, rtol=1e-9, atol=1e-6)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"embedding_dim": 2}, r"^embedding_dim must be in \[3, 64\]; got 2\.$"),
        ({"embedding_dim": 5, "manifold_dim": 5}, r"^manifold_dim must be in \[1, 4\]; got 5\.$"),
        ({"lag": 0}, r"^lag must be in \[1, 500\]; got 0\.$"),
        ({"radius": -1.0}, r"^radius must be finite and > 0; got -1\.0\.$"),
        ({"iterations": 0}, r"^iterations must be in \[1, 100\]; got 0\.$"),
        ({"theiler_window": -1}, r"^theiler_window must be in \[0, ∞\]; got -1\.$"),
        ({"dt": 0.0}, r"^dt must be finite and > 0; got 0\.0\.$"),
        (
            {"embedding_dim": 3, "lag": 1, "theiler_window": 1000},
            r"^x is too short: 2000 samples, but embedding_dim=3, lag=1 and "
            r"theiler_window=1000 need at least 2304 \(the 30 neighbours of a delay vector, "
            r"outside its window, must be at most 1/10 of all delay vectors\)\.$",
        ),
    ],
)
def test_bad_parameters_name_themselves(henon_x, kwargs, message) -> None:
    with pytest.raises(ValueError, match=message) as info:
        local_projective_denoise(henon_x[:2000], **kwargs)
    assert "\n" not in str(info.value)


def test_bad_series_is_refused(henon_x: np.ndarray) -> None:
    bad = henon_x[:500].copy()
    bad[7] = np.nan
    with pytest.raises(ValueError, match=r"^x contains 1 non-finite value\(s\) \(first: NaN"):
        local_projective_denoise(bad)
    with pytest.raises(ValueError, match=r"^x is too short: 50 samples, the minimum here is 100"):
        local_projective_denoise(henon_x[:50])
    with pytest.raises(ValueError, match=r"^x is too short: 200 samples, but embedding_dim=3"):
        local_projective_denoise(henon_x[:200], embedding_dim=3, lag=1)
    with pytest.raises(ValueError, match=r"^x is a Dataset; pass one of its variables"):
        local_projective_denoise(xr.Dataset({"x": ("step", henon_x[:500])}))
