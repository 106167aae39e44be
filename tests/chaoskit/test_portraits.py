"""Phase portraits: derivative from the data when present, Savitzky–Golay otherwise."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import phase_portrait


def _ds(t: np.ndarray, **series: np.ndarray) -> xr.Dataset:
    return chaoskit.load_trajectory(
        xr.Dataset(
            {k: ("time", v, {"units": "m", "long_name": k}) for k, v in series.items()},
            coords={"time": ("time", t, {"units": "s"})},
        )
    )


def test_estimated_derivative_of_a_sine_matches_the_analytic_one() -> None:
    omega = 2 * np.pi / 3.0
    t = np.arange(0.0, 30.0, 3.0 / 50)  # 50 samples per period
    pp = phase_portrait(_ds(t, x=2.0 * np.sin(omega * t + 0.4)), variable="x")
    exact = 2.0 * omega * np.cos(omega * t + 0.4)
    rate = pp["dx_dt"].values
    scale = 2.0 * omega
    assert np.max(np.abs(rate - exact)[5:-5]) / scale < 5e-6
    assert np.max(np.abs(rate - exact)) / scale < 5e-4  # one-sided fits at the ends
    assert pp["dx_dt"].attrs["units"] == "m s-1"
    assert pp.attrs["derivative_source"].startswith("savitzky-golay")
    np.testing.assert_array_equal(pp["x"].values, 2.0 * np.sin(omega * t + 0.4))


def test_polynomial_derivative_is_exact_inside() -> None:
    t = np.arange(0.0, 2.0, 0.01)
    x = 1.0 + 2.0 * t - 3.0 * t**2 + 0.5 * t**5
    pp = phase_portrait(_ds(t, x=x), variable="x")
    np.testing.assert_allclose(pp["dx_dt"].values, 2.0 - 6.0 * t + 2.5 * t**4, atol=1e-9)


@pytest.mark.parametrize("name", ["x_dot", "dx_dt", "vx"])
def test_derivative_taken_from_the_data(name: str) -> None:
    t = np.arange(0.0, 5.0, 0.1)
    marker = np.full(t.size, 7.0)  # not the derivative of x: proves it was not estimated
    pp = phase_portrait(_ds(t, x=np.sin(t), **{name: marker}), variable="x")
    assert pp.attrs["derivative_source"] == "data"
    assert pp.attrs["portrait_derivative"] == name
    np.testing.assert_array_equal(pp[name].values, marker)


def test_explicit_derivative_name() -> None:
    t = np.arange(0.0, 5.0, 0.1)
    pp = phase_portrait(_ds(t, pos=np.sin(t), speed=np.cos(t)), variable="pos",
                        derivative="speed")  # fmt: skip
    np.testing.assert_array_equal(pp["speed"].values, np.cos(t))


def test_bad_input() -> None:
    t = np.arange(0.0, 5.0, 0.1)
    ds = _ds(t, x=np.sin(t))
    with pytest.raises(ValueError, match="not found"):
        phase_portrait(ds, variable="y")
    with pytest.raises(ValueError, match="not found"):
        phase_portrait(ds, variable="x", derivative="v")
    with pytest.raises(ValueError, match="odd"):
        phase_portrait(ds, variable="x", window=10)
    with pytest.raises(ValueError, match="uniformly"):
        phase_portrait(_ds(np.r_[t, 5.5], x=np.sin(np.r_[t, 5.5])), variable="x")
    step = xr.Dataset({"x": ("step", np.arange(10.0))}, coords={"step": np.arange(10)})
    with pytest.raises(ValueError, match="step"):
        phase_portrait(step, variable="x")
