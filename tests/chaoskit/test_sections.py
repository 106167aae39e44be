"""Poincaré sections and stroboscopic maps against analytic crossings and known orbits."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import poincare_section, section_structure, stroboscopic_map, systems

OMEGA = 2.0 * np.pi  # 1 Hz


def _trajectory(t: np.ndarray, **series: np.ndarray) -> xr.Dataset:
    ds = xr.Dataset(
        {k: ("time", v, {"units": "m", "long_name": k}) for k, v in series.items()},
        coords={"time": ("time", t, {"units": "s"})},
    )
    return chaoskit.load_trajectory(ds)


def _sine(samples_per_period: int, *, t0: float = 999.75, phase: float = 0.3) -> xr.Dataset:
    # 11 up- and 10 down-crossings, none within a fifth of a period of either end
    t = t0 + np.arange(int(10.5 * samples_per_period)) / samples_per_period
    return _trajectory(t, x=np.sin(OMEGA * t + phase), v=np.cos(OMEGA * t + phase))


def _max_errors(sec: xr.Dataset, *, phase: float, level_value: float) -> tuple[float, float]:
    """Largest crossing-time error (relative to the 1 s period) and value error."""
    t = sec["time"].values
    k = np.round(t + phase / OMEGA)
    exact = k - phase / OMEGA
    return float(np.max(np.abs(t - exact))), float(np.max(np.abs(sec["v"].values - level_value)))


@pytest.mark.parametrize("samples_per_period", [25, 50, 100])
def test_sine_crossings_exact_to_1e8(samples_per_period: int) -> None:
    ds = _sine(samples_per_period)
    up = poincare_section(ds, variable="x", level=0.0, direction="up")
    down = poincare_section(ds, variable="x", level=0.0, direction="down")
    assert up.sizes["crossing"] == 11 and down.sizes["crossing"] == 10
    t_err, v_err = _max_errors(up, phase=0.3, level_value=1.0)
    assert t_err < 1e-8 and v_err < 1e-8 * 1.0  # relative to period 1 s and amplitude 1
    # down-crossings of sin(ωt + φ) happen half a period later, where cos = -1
    t = down["time"].values
    exact = np.round(t - 0.5 + 0.3 / OMEGA) + 0.5 - 0.3 / OMEGA
    assert np.max(np.abs(t - exact)) < 1e-8
    np.testing.assert_allclose(down["v"].values, -1.0, atol=1e-8)


def _worst_value_error(samples_per_second: int, order: int) -> float:
    # An irrational frequency puts the crossings at every position between samples.
    f = (np.sqrt(5.0) - 1.0) / 2.0
    t = np.arange(0.0, 300.0, 1.0 / samples_per_second)
    ds = _trajectory(t, x=np.sin(2 * np.pi * f * t), v=np.cos(2 * np.pi * f * t))
    sec = poincare_section(ds, variable="x", order=order)
    return float(np.max(np.abs(sec["v"].values - 1.0)))


def test_crossings_next_to_the_ends_are_less_accurate_but_found() -> None:
    t = np.linspace(0.0, 3.0, 76)  # spacing 0.04 s
    ds = _trajectory(t, x=np.sin(OMEGA * (t - 2.98)), v=np.cos(OMEGA * (t - 2.98)))
    sec = poincare_section(ds, variable="x")  # the last crossing is between the last samples
    np.testing.assert_allclose(sec["time"].values, [0.98, 1.98, 2.98], atol=1e-6)


def test_interpolation_order_converges_at_its_rate() -> None:
    # The error of a degree-p interpolant falls as h^(p+1): doubling the sampling divides the
    # cubic's error by about 16 and the quintic's by about 64.
    for order, expected in ((3, 16.0), (5, 64.0)):
        ratio = _worst_value_error(20, order) / _worst_value_error(40, order)
        assert expected / 1.5 < ratio < expected * 1.5
    assert _worst_value_error(20, 3) > 1e-6  # a cubic is not enough for 1e-8 here
    assert _worst_value_error(20, 7) < 1e-8  # the default degree is


def test_nonzero_level_and_both_directions() -> None:
    ds = _sine(50)
    sec = poincare_section(ds, variable="x", level=0.5, direction="both")
    assert sec.sizes["crossing"] == 21
    # sin(θ) = 0.5 upward at θ = π/6, downward at 5π/6; v = cos θ = ±√3/2 there
    v = sec["v"].values
    np.testing.assert_allclose(np.abs(v), np.sqrt(3.0) / 2.0, atol=1e-8)
    assert np.all(np.sign(v[1:]) == -np.sign(v[:-1]))  # up and down alternate


def test_nonuniform_sampling_is_allowed() -> None:
    rng = np.random.default_rng(3)
    t = np.sort(np.cumsum(rng.uniform(0.5, 1.5, 800)) / 40.0)
    ds = _trajectory(t, x=np.sin(OMEGA * t + 0.3), v=np.cos(OMEGA * t + 0.3))
    sec = poincare_section(ds, variable="x")
    t_err, v_err = _max_errors(sec, phase=0.3, level_value=1.0)
    assert t_err < 1e-7 and v_err < 1e-6


def test_section_dataset_layout() -> None:
    ds = _sine(50)
    sec = poincare_section(ds, variable="x", coords=["v"])
    assert set(sec.data_vars) == {"v"}
    assert sec["v"].attrs["units"] == "m" and sec["time"].attrs["units"] == "s"
    assert sec.attrs["section_kind"] == "poincare" and sec.attrs["section_variable"] == "x"
    assert "chaoskit.poincare_section" in sec.attrs["history"]
    assert np.all(np.diff(sec["time"].values) > 0)


def test_a_sample_on_the_level_counts_once() -> None:
    t = np.arange(0.0, 4.0, 0.125)  # the sine passes zero exactly on samples
    ds = _trajectory(t, x=np.sin(OMEGA * t), v=np.cos(OMEGA * t))
    sec = poincare_section(ds, variable="x", direction="up")
    np.testing.assert_allclose(sec["time"].values, [1.0, 2.0, 3.0], atol=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"variable": "nope"}, "not found"),
        ({"variable": "x", "direction": "sideways"}, "direction"),
        ({"variable": "x", "order": 4}, "order"),
        ({"variable": "x", "order": 11}, "order"),
        ({"variable": "x", "level": float("nan")}, "level"),
        ({"variable": "x", "coords": ["w"]}, "not found"),
    ],
)
def test_poincare_bad_input(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        poincare_section(_sine(20), **kwargs)


def test_maps_have_no_section() -> None:
    ds = xr.Dataset({"x": ("step", systems.logistic(50))}, coords={"step": np.arange(50)})
    with pytest.raises(ValueError, match="step"):
        poincare_section(ds, variable="x")


# ------------------------------------------------------------------ stroboscopic maps


def test_clock_strobe_of_a_sine() -> None:
    t = np.arange(0.0, 20.0, 0.03)  # the strobe instants fall between samples
    ds = _trajectory(t, x=np.sin(OMEGA * t), v=np.cos(OMEGA * t))
    strobe = stroboscopic_map(ds, period=1.0, phase=0.7)
    np.testing.assert_allclose(strobe["x"].values, np.sin(0.7), atol=1e-8)
    np.testing.assert_allclose(strobe["v"].values, np.cos(0.7), atol=1e-8)
    assert strobe.attrs["section_kind"] == "stroboscopic"
    cycles = strobe["drive_cycle"].values
    np.testing.assert_array_equal(cycles, np.arange(cycles[0], cycles[0] + cycles.size))
    np.testing.assert_allclose(strobe["time"].values, cycles + 0.7 / OMEGA, atol=1e-12)


@pytest.mark.parametrize("wrapped", [False, True])
def test_angle_strobe_matches_the_clock(wrapped: bool) -> None:
    t = np.arange(0.0, 20.0, 0.03)
    angle = OMEGA * t + 0.05 * np.sin(3 * t)  # a slightly non-uniform rotation
    stored = np.mod(angle, 2 * np.pi) if wrapped else angle
    ds = _trajectory(t, crank_angle=stored, x=np.sin(angle))
    strobe = stroboscopic_map(ds, phase_variable="crank_angle", phase=1.0)
    assert "crank_angle" not in strobe.data_vars
    np.testing.assert_allclose(strobe["x"].values, np.sin(1.0), atol=1e-8)
    # the angle passes 1 + 2πk once per turn
    assert strobe.sizes["crossing"] == int((angle[-1] - 1.0) // (2 * np.pi)) + 1


def test_strobe_bad_input() -> None:
    ds = _sine(20)
    with pytest.raises(ValueError, match="exactly one"):
        stroboscopic_map(ds)
    with pytest.raises(ValueError, match="exactly one"):
        stroboscopic_map(ds, period=1.0, phase_variable="x")
    with pytest.raises(ValueError, match="period"):
        stroboscopic_map(ds, period=-1.0)
    tb = np.arange(0.0, 10.0, 0.01)
    backwards = _trajectory(tb, angle=-OMEGA * tb, x=np.zeros(tb.size))
    # a clockwise drive passes phase - 2πk: once per turn, t = 0 included as in clock mode
    strobe = stroboscopic_map(backwards, phase_variable="angle")
    np.testing.assert_allclose(strobe["time"].values, np.arange(10.0), atol=1e-12)


# Forced Duffing x'' + 0.3x' − x + x³ = γ cos 1.2t: γ → period of the response (in drive
# periods) for the default initial state (1, 0); the classic double-well cascade.
DUFFING_PERIODS = {0.20: 1, 0.28: 2, 0.29: 4, 0.37: 5, 0.65: 2}


def duffing_dataset(gamma: float, n_periods: int, spp: int = 100) -> xr.Dataset:
    t, state = systems.duffing(n_periods * spp, gamma=gamma, samples_per_period=spp,
                               discard_periods=200)  # fmt: skip
    ds = xr.Dataset(
        {
            "x": ("time", state[:, 0], {"units": "1", "long_name": "displacement"}),
            "v": ("time", state[:, 1], {"units": "s-1", "long_name": "velocity"}),
        },
        coords={"time": ("time", t, {"units": "s"})},
    )
    return chaoskit.load_trajectory(ds)


@pytest.mark.parametrize(("gamma", "k"), sorted(DUFFING_PERIODS.items()))
def test_period_k_duffing_has_exactly_k_strobe_clusters(gamma: float, k: int) -> None:
    strobe = stroboscopic_map(duffing_dataset(gamma, 60), period=2 * np.pi / 1.2)
    points = np.column_stack([strobe["x"].values, strobe["v"].values])
    # exactly k distinct points (to 1e-5 of the motion's size), repeating every k periods
    scale = float(np.ptp(points))
    distinct = np.unique(np.round(points / (1e-5 * scale)), axis=0)
    assert distinct.shape[0] == k
    np.testing.assert_allclose(points[k:], points[:-k], atol=1e-5 * scale)
    found = section_structure(points, scale=float(np.std(points)))
    assert found.kind == "clusters" and found.n_clusters == k


def test_chaotic_duffing_strobe_is_not_a_few_clusters() -> None:
    strobe = stroboscopic_map(duffing_dataset(0.5, 300, spp=40), period=2 * np.pi / 1.2)
    points = np.column_stack([strobe["x"].values, strobe["v"].values])
    found = section_structure(points, scale=float(np.std(points)))
    assert found.kind == "scattered"
