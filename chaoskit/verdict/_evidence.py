"""The evidence gathered for the verdict: the section, the exponents' reading, the cycle test."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr
from scipy.signal import find_peaks, savgol_filter

from .._contract import stamp
from .._portraits import savgol_derivative
from ..sections import poincare_section, stroboscopic_map
from ._cycles import CycleForecast, cycle_surrogate_test
from ._inputs import SeriesInput
from ._line_spectrum import LineSpectrum
from ._rule import CYCLE_MIN_GAIN, LOW_DIM, VerdictRule
from ._section_structure import SectionStructure
from ._surrogates import SurrogateResult, surrogate_test

# ---------------------------------------------------------------- sections


def _delay_dataset(
    x: np.ndarray, t: np.ndarray, lag: int, n_coords: int, name: str, extra: dict[str, Any]
) -> xr.Dataset:
    """Delay coordinates x(t), x(t − τ), … on the common time axis."""
    span = (n_coords - 1) * lag
    n = x.size - span
    data_vars: dict[str, Any] = {}
    for j in range(n_coords):
        key = name if j == 0 else f"{name}_lag{j}"
        long = name if j == 0 else f"{name}(t - {j} lag)"
        data_vars[key] = (
            "time",
            x[span - j * lag : span - j * lag + n],
            {"units": "1", "long_name": long},
        )
    for key, values in extra.items():
        data_vars[key] = ("time", values[span : span + n], {"units": "1", "long_name": key})
    ds = xr.Dataset(data_vars, coords={"time": ("time", t[span : span + n])})
    return stamp(ds, title="delay coordinates", history="chaoskit.classify: delay coordinates")


def section_points(
    inp: SeriesInput,
    x: np.ndarray,
    lag: int,
    n_coords: int,
    drive_period: float | None,
    noise: float,
) -> tuple[xr.Dataset, np.ndarray, float]:
    """Section Dataset, its points (rows) and the characteristic time T."""
    name = inp.variable or "x"
    if inp.kind == "map":
        n = x.size - (n_coords - 1) * lag
        data_vars = {
            (name if j == 0 else f"{name}_lag{j}"): (
                "crossing",
                x[j * lag : j * lag + n],
                {"units": "1", "long_name": name if j == 0 else f"{name}(n + {j} lag)"},
            )
            for j in range(n_coords)
        }
        sec = xr.Dataset(data_vars, coords={"crossing": np.arange(n)})
        sec.attrs["section_kind"] = "delay vectors of a map"
        points = np.column_stack([sec[k].values for k in sec.data_vars])
        return sec, points, 1.0
    if inp.kind == "forced":
        extra = {"__angle": inp.angle} if inp.angle is not None else {}
        ds = _delay_dataset(x, inp.t, lag, n_coords, name, extra)
        if inp.angle is not None:
            sec = stroboscopic_map(ds, phase_variable="__angle")
        else:
            sec = stroboscopic_map(ds, period=drive_period)
        points = np.column_stack([sec[k].values for k in sec.data_vars])
        times = sec["time"].values
        period = float(np.mean(np.diff(times))) if times.size > 1 else float("nan")
        return sec, points, period
    # Autonomous flow: the successive maxima M_n of the (lightly smoothed) signal, one per
    # loop, and their return map (M_n, M_n+1, M_n+2): Lorenz's own section of his flow.
    # Values at maxima do not depend, to first order, on where noise puts the maximum.
    window = max(5, 2 * (lag // 2) + 1)
    smooth = savgol_filter(x, window, 3) if x.size > window else x
    dwin = max(5, 2 * (lag // 4) + 1)
    rate = savgol_derivative(smooth, dt=inp.dt, window=dwin, polyorder=3)
    ds = _delay_dataset(smooth, inp.t, 1, 1, name, {"__rate": rate})
    sec = poincare_section(ds, variable="__rate", level=0.0, direction="down")
    # Noise leaves wiggles with maxima of their own: keep one crossing per maximum whose
    # prominence (scipy.signal.find_peaks) exceeds four noise standard deviations.
    peaks, _ = find_peaks(smooth, prominence=4.0 * noise * float(np.std(x)))
    times = sec["time"].values
    keep = np.arange(0)
    if peaks.size and times.size:
        peak_times = inp.t[peaks]
        right = np.clip(np.searchsorted(peak_times, times), 0, peak_times.size - 1)
        left = np.maximum(right - 1, 0)
        match = np.where(
            np.abs(peak_times[right] - times) < np.abs(peak_times[left] - times), right, left
        )
        gap = np.abs(peak_times[match] - times)
        order = np.lexsort((gap, match))
        first = order[np.r_[True, match[order][1:] != match[order][:-1]]]
        keep = np.sort(first[gap[first] <= 1.5 * inp.dt])
    maxima = sec[name].values[keep]
    times = times[keep]
    n_map = max(maxima.size - n_coords + 1, 0)
    data_vars = {
        (name if j == 0 else f"{name}_next{j}"): (
            "crossing",
            maxima[j : j + n_map],
            {"units": "1", "long_name": f"maximum {'n' if j == 0 else f'n + {j}'} of {name}"},
        )
        for j in range(n_coords)
    }
    sec = xr.Dataset(
        data_vars,
        coords={"crossing": np.arange(n_map), "time": ("crossing", times[:n_map], {"units": "s"})},
    )
    sec.attrs["section_kind"] = "return map of the maxima"
    points = np.column_stack([sec[k].values for k in sec.data_vars])
    period = float(np.mean(np.diff(times))) if times.size > 1 else 4.0 * lag * inp.dt
    return sec, points, period


# ---------------------------------------------------------------- reading the estimators


def describe_error(exc: Exception) -> str:
    """An estimator's failure in words: its message, with the type unless a ValueError."""
    return str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"


def clearly_positive(res: Any, time_scale: float, rule: VerdictRule) -> bool | None:
    """Whether an exponent estimate is clearly positive (interval above 0 and λ₁T at least
    ``rule.min_growth``); None when it is missing."""
    if res is None:
        return None
    return bool(res.ci[0] > 0.0 and res.mle > 0.0 and res.mle * time_scale >= rule.min_growth)


def needs_referee(
    positives: dict[str, bool | None],
    structure: SectionStructure | None,
    lines: LineSpectrum | None,
    surrogates: SurrogateResult | None,
    long_enough: bool,
    confirmed: bool = False,
) -> bool:
    """Whether Kantz's exponent can decide: exactly one of Rosenstein's and Wolf's is
    clearly positive while everything else a chaotic label needs holds (determinism beyond
    linear noise — the surrogate test rejects, or ``confirmed``: the confirmed
    low-dimensional test of :func:`confirm_low_dim` does —, a spectrum that is not lines,
    regular motion ruled out)."""
    if sum(pos is True for pos in positives.values()) != 1:
        return False
    if not confirmed and (surrogates is None or not surrogates.rejected):
        return False
    if lines is None or lines.kind not in ("broadband", "unresolved"):
        return False
    section = "none" if structure is None else structure.kind
    broadband_decides = lines.kind == "broadband" and long_enough
    if section in ("clusters", "closed-curve") and not broadband_decides:
        return False
    return section == "scattered" or broadband_decides


def cycle_test(
    x: np.ndarray,
    dt: float,
    lag: int,
    period: float,
    rule: VerdictRule,
    n_surrogates: int,
    gen: np.random.Generator,
) -> SurrogateResult:
    """The noisy-periodic-orbit test of a forced series over cycles of ``period``: the
    series thinned as for the IAAFT test, to at least 16 samples per cycle; three delay
    coordinates, a horizon of one delay."""
    step = max(1, min(lag // 4, int(period / dt // 16)))
    thin_lag = max(1, round(lag / step))
    return cycle_surrogate_test(
        x[::step],
        period,
        dt=dt * step,
        forecast=CycleForecast(
            embedding_dim=LOW_DIM,
            lag=thin_lag,
            # at least 1: a cycle under two samples is then refused by the test itself
            horizon=max(1, min(thin_lag, int(period / (dt * step)) - 1)),
        ),
        n_surrogates=n_surrogates,
        alpha=rule.alpha,
        min_effect=rule.min_effect,
        min_gain=CYCLE_MIN_GAIN,
        rng=gen,
    )


def any_rejected(*tests: SurrogateResult | None) -> bool | None:
    """Whether any of the tests that ran rejected (None if none ran)."""
    ran = [t.rejected for t in tests if t is not None]
    return any(ran) if ran else None


def count_cycles(inp: SeriesInput, n: int, time_scale: float) -> tuple[float, str]:
    """Characteristic times the series spans, and their name in the user's terms."""
    if inp.kind == "map":
        return float(n), "samples"
    unit = "drive periods" if inp.kind == "forced" else "oscillations (maxima)"
    if not np.isfinite(time_scale) or time_scale <= 0:
        return 0.0, unit
    return n * inp.dt / time_scale, unit


def line_period(lines: LineSpectrum, inp: SeriesInput, time_scale: float) -> int | None:
    """The period k of a periodic line analysis in the verdict's terms: samples for maps
    and for series that repeat after k samples; drive periods for forced flows; maxima per
    period for autonomous flows."""
    if lines.kind != "periodic":
        return None
    if lines.period_samples is not None:
        return int(lines.period_samples)
    if inp.kind == "map":
        return max(1, round(lines.fundamental_period))
    if inp.kind == "forced":
        return max(1, round(lines.fundamental_period / time_scale))
    return lines.maxima_per_period


def surrogate_evidence(
    x: np.ndarray,
    *,
    lag: int,
    embedding_dim: int,
    rosenstein: Any,
    n_surrogates: int,
    max_samples: int,
    rule: VerdictRule,
    gen: np.random.Generator,
    errors: dict[str, str],
) -> tuple[SurrogateResult | None, SurrogateResult | None, SurrogateResult | None]:
    """The IAAFT surrogate test of the series, and when it does not reject, the same in
    ``LOW_DIM`` delay coordinates and one (thinned) sample ahead: (first, low_dim,
    one_step), None for a test that did not run. A test that fails records its message in
    ``errors`` under its name."""
    surrogates = None
    try:
        # A densely sampled flow is thinned to about four samples per delay: the statistic
        # only has to discriminate, and it costs less for the data and every surrogate alike.
        step = max(1, lag // 4)
        theiler = embedding_dim * lag
        if rosenstein is not None:
            theiler = int(rosenstein.theiler_window)
        surrogates = surrogate_test(
            x[::step][-max_samples:],
            embedding_dim=embedding_dim,
            lag=max(1, round(lag / step)),
            theiler_window=-(-theiler // step),
            n_surrogates=n_surrogates,
            alpha=rule.alpha,
            min_effect=rule.min_effect,
            rng=gen,
        )
    except ValueError as exc:
        errors["surrogates"] = str(exc)
    low_dim = one_step = None
    if surrogates is not None and not surrogates.rejected:
        # These tests withhold a noise label; chaos still needs the first test to reject,
        # unless confirm_low_dim repeats a rejection here at half the level. A locally
        # constant predictor in many coordinates finds no close neighbours in a few
        # thousand points, so its failure to beat the surrogates is no
        # evidence of noise; a low-dimensional attractor (coarsely sampled, or with a
        # dimension that FNN could not resolve) still shows in a few coordinates. And a
        # flow whose orbits separate within one delay is unpredictable at a horizon of one
        # delay, data and surrogates alike; one (thinned) sample ahead it still shows.
        # The Theiler window is the span of the three delay coordinates: both series share
        # the autocorrelation, so temporal neighbours help data and surrogates alike, while
        # the period-long window of the exponent can leave a slowly forced flow no
        # neighbours at all.
        thinned = x[::step][-max_samples:]
        runs = {  # each unless the first test was this one already
            "surrogates_low_dim": (surrogates.horizon, embedding_dim > LOW_DIM),
            "surrogates_one_step": (1, surrogates.horizon > 1),
        }
        for name, (horizon, needed) in runs.items():
            if not needed:
                continue
            try:
                res = surrogate_test(
                    thinned,
                    embedding_dim=LOW_DIM,
                    lag=surrogates.lag,
                    horizon=horizon,
                    theiler_window=LOW_DIM * surrogates.lag,
                    n_surrogates=n_surrogates,
                    alpha=rule.alpha,
                    min_effect=rule.min_effect,
                    rng=gen,
                )
            except ValueError as exc:
                errors[name] = str(exc)
                continue
            if name == "surrogates_low_dim":
                low_dim = res
            else:
                one_step = res
    return surrogates, low_dim, one_step


def confirm_low_dim(
    x: np.ndarray,
    *,
    lag: int,
    tests: tuple[SurrogateResult | None, ...],
    n_surrogates: int,
    max_samples: int,
    rule: VerdictRule,
    gen: np.random.Generator,
    errors: dict[str, str],
) -> SurrogateResult | None:
    """The first of the low-dimensional surrogate ``tests`` that rejected, repeated on the
    same thinned series at half the significance level with ``2 (n_surrogates + 1) - 1``
    fresh surrogates (None when none rejected, or when it fails: ``errors`` says why).

    A rejection of both is evidence of determinism at a family-wise level of at most
    1.5 α beside the first test (union bound), which the rule accepts only for a forced
    series whose mean cycle carries most of its variance: there a predictor in the full
    embedding dimension finds too few close neighbours in the departure where the chaos
    lives, while three delay coordinates still resolve it."""
    first = next((t for t in tests if t is not None and t.rejected), None)
    if first is None:
        return None
    step = max(1, lag // 4)
    try:
        return surrogate_test(
            x[::step][-max_samples:],
            embedding_dim=first.embedding_dim,
            lag=first.lag,
            horizon=first.horizon,
            theiler_window=first.theiler_window,
            n_surrogates=2 * (n_surrogates + 1) - 1,
            alpha=rule.alpha / 2,
            min_effect=rule.min_effect,
            rng=gen,
        )
    except ValueError as exc:
        errors["surrogates_confirmed"] = str(exc)
    return None
