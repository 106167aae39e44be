"""The correlated cycle spread discounts coloured measurement noise by its own colour.

Stationary measurement noise, white or coloured, has the same lag-one covariance at every
phase of the drive. The departure's lag-one covariance in its quietest phase bin bounds
the noise's, so the lag-one reading less that bound is 0 for a periodic orbit plus AR(1)
noise, even when the orbit is jolted afresh every cycle (a ringing impact at a fixed
phase, whose phase-dependent variance makes the stationarity reading large). A
deterministic wandering smooth over a sample (here driven by the logistic map) keeps its
spread: it is not the same at every phase.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from chaoskit import VerdictRule, classify, cycle_spread

RULE = VerdictRule()
PER_PERIOD = 100
CYCLES = 100


def _orbit() -> np.ndarray:
    """A journal that sweeps across its clearance once per drive period."""
    phase = (np.arange(PER_PERIOD * CYCLES) % PER_PERIOD) / PER_PERIOD
    return np.tanh(8.0 * np.sin(2.0 * np.pi * phase))


def _ar1(n: int, seed: int) -> np.ndarray:
    """Unit-variance AR(1) noise, phi = 0.9 (correlated over about ten samples)."""
    e = np.random.default_rng(seed).standard_normal(n)
    out = np.empty(n)
    out[0] = e[0]
    for i in range(1, n):
        out[i] = 0.9 * out[i - 1] + np.sqrt(1.0 - 0.81) * e[i]
    return out


def _jolted(seed: int) -> np.ndarray:
    """The orbit plus a ringing impact at a fixed phase whose amplitude is drawn afresh
    every cycle: a stable orbit kicked by independent shocks (spiky, phase-dependent)."""
    x = _orbit()
    amp = np.random.default_rng(seed).standard_normal(CYCLES)
    s = np.arange(30.0)
    ring = np.exp(-s / 4.0) * np.sin(1.6 * s)
    for c in range(CYCLES):
        x[c * PER_PERIOD + 20 : c * PER_PERIOD + 50] += 1.5 * amp[c] * ring
    return x


def _wandering(u0: float) -> np.ndarray:
    """The orbit plus a departure smooth over the cycle whose size each cycle is given by
    the logistic map (chaotic): deterministic, larger mid-cycle than at the boundaries."""
    x = _orbit()
    phase = np.arange(PER_PERIOD) / PER_PERIOD
    u = u0
    for c in range(CYCLES):
        u = 4.0 * u * (1.0 - u)
        x[c * PER_PERIOD : (c + 1) * PER_PERIOD] += 0.6 * (u - 0.5) * np.sin(np.pi * phase)
    return x


def _with_noise(x: np.ndarray, level: float, kind: str, seed: int) -> np.ndarray:
    e = _ar1(x.size, seed) if kind == "ar1" else np.random.default_rng(seed).standard_normal(x.size)
    return x + level * x.std() * e


@pytest.mark.parametrize("level", [0.10, 0.20])
def test_jolted_orbit_plus_ar1_noise_reads_no_spread(level):
    x = _with_noise(_jolted(seed=1), level, "ar1", seed=2)
    # the lag-one reading alone sees the noise's colour (about sqrt(0.9) of its level) ...
    assert cycle_spread(x, PER_PERIOD, noise="white") > 0.8 * level
    # ... and the default reading discounts it by its covariance in the quietest phase
    assert cycle_spread(x, PER_PERIOD) <= 0.02


@pytest.mark.slow
def test_jolted_orbit_plus_ar1_noise_is_periodic():
    x = _with_noise(_jolted(seed=1), 0.10, "ar1", seed=2)
    t = np.arange(x.size) / PER_PERIOD
    data = xr.Dataset({"x": ("time", x), "crank": ("time", 2.0 * np.pi * t)}, coords={"time": t})
    v = classify(data, variable="x", phase_variable="crank", rng=0)
    assert (v.label, v.period) == ("periodic", 1)
    assert v.cycle_spread <= RULE.cluster_tol
    # the jolts make the departure phase-dependent: the stationarity reading alone would
    # not discount the noise, and the label is not confident
    assert v.phase_spread > 2.0 * RULE.cluster_tol
    assert v.votes["phase"] == "opposes"
    assert "is 0 of the standard deviation (at most 0.05)" in v.reason


@pytest.mark.parametrize("u0", [0.3123, 0.3123 * (1.0 + 1e-12)])
@pytest.mark.parametrize("kind", ["white", "ar1"])
def test_chaotic_wandering_keeps_its_spread_under_ten_percent_noise(u0, kind):
    # the logistic map loses the 1e-12 perturbation within the series: only what holds
    # for either trajectory is asserted
    x = _with_noise(_wandering(u0), 0.10, kind, seed=5)
    assert cycle_spread(x, PER_PERIOD) > 2.0 * RULE.cluster_tol


@pytest.mark.parametrize("kind", ["white", "ar1"])
@pytest.mark.parametrize("level", [0.01, 0.10, 0.20])
def test_sine_plus_noise_reads_no_spread(kind, level):
    t = np.arange(PER_PERIOD * CYCLES)
    x = _with_noise(np.sin(2.0 * np.pi * t / PER_PERIOD), level, kind, seed=7)
    assert cycle_spread(x, PER_PERIOD) == 0.0
