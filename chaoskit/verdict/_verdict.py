"""The verdict: equilibrium, periodic, quasi-periodic, chaotic, noise-like or undetermined.

The evidence is computed by independent estimators; :func:`combine` applies the written rule
(see :func:`classify` and ``docs/verdict.md``) and nothing else decides the label.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
import xarray as xr
from scipy.signal import find_peaks, savgol_filter

from .._contract import sampling_interval, stamp
from .._io import load_trajectory
from .._portraits import savgol_derivative
from .._tables import has_time_index
from .._validate import (
    as_series,
    check_int,
    check_positive,
    check_probability,
    extreme_peak_exponent,
)
from ..embedding import estimate_delay, estimate_embedding_dim
from ..lyapunov import lyapunov_kantz, lyapunov_rosenstein, lyapunov_wolf
from ..sections import poincare_section, stroboscopic_map
from ._clusters import SectionStructure, section_structure
from ._cycles import cycle_spread, cycle_surrogate_test
from ._lines import LineSpectrum, line_spectrum
from ._rng import as_generator
from ._surrogates import SurrogateResult, check_surrogates, surrogate_test
from ._table import stack_verdicts
from ._zero_one import ZeroOneResult, zero_one_test

__all__ = ["LABELS", "Verdict", "VerdictRule", "classify"]

Label = Literal[
    "equilibrium", "periodic", "quasi-periodic", "chaotic", "noise-like", "undetermined"
]
LABELS: tuple[str, ...] = (
    "equilibrium",
    "periodic",
    "quasi-periodic",
    "chaotic",
    "noise-like",
    "undetermined",
)
Kind = Literal["map", "flow", "forced"]
Vote = Literal["supports", "opposes", "neutral", "missing"]
MIN_SAMPLES = 200
DIMENSION_POINTS = 2000  # FNN reference points: the fraction is known to about ±1 %
LOW_DIM = 3  # delay coordinates of the second surrogate test (a chaotic flow unfolds in 3)
# Smallest forecast gain of the cycle-shuffled test, in standard deviations: an exact orbit's
# cycles differ at round-off (1e-10), which any rank test would read as determinism.
CYCLE_MIN_GAIN = 1e-3


@dataclass(frozen=True, kw_only=True)
class VerdictRule:
    """The thresholds of the combination rule (see :func:`classify`).

    Attributes
    ----------
    min_growth
        An MLE counts as clearly positive when its 95 % interval lies above 0 *and*
        :math:`\\lambda_1 T \\ge` ``min_growth``, with :math:`T` the characteristic time
        (mean time between section points; the drive period; one iteration for maps).
        0.1 means neighbouring orbits separate by at least 10 % per cycle.
    alpha
        Significance level of the surrogate test.
    min_effect
        Smallest relative gain in predictability over the median surrogate for the
        surrogate test to reject.
    cluster_tol
        Largest cluster RMS radius, as a fraction of the signal's standard deviation, for
        clusters to count as distinct points of a periodic orbit.
    noise_factor, max_noise_allowance
        For flows the radius allowance grows to ``noise_factor`` times the estimated
        measurement-noise level (relative to the standard deviation), at most
        ``max_noise_allowance``.
    max_period
        Largest period looked for.
    zero_one_regular, zero_one_chaotic
        0–1 test K at or below which the series counts as regular, at or above which as
        irregular (between: no vote).
    equilibrium_rtol
        The series is an equilibrium when its standard deviation is at most this fraction
        of its mean magnitude (or exactly zero).
    min_cycles
        Characteristic times (section points, drive periods, oscillations; samples for
        maps) a series must span before its section, its spectrum or a surrogate test that
        does not reject can rule out a regular motion.
    max_residual
        Largest fraction of the variance the white residual of a line spectrum (or of
        folding at the period) may carry: 0.5 accepts a regular signal down to 3 dB SNR.
    """

    min_growth: float = 0.1
    alpha: float = 0.05
    min_effect: float = 0.1
    cluster_tol: float = 0.05
    noise_factor: float = 3.0
    max_noise_allowance: float = 0.3
    max_period: int = 32
    zero_one_regular: float = 0.2
    zero_one_chaotic: float = 0.8
    equilibrium_rtol: float = 1e-9
    min_cycles: int = 20
    max_residual: float = 0.5

    def __post_init__(self) -> None:
        check_positive(self.min_growth, name="min_growth")
        check_probability(self.alpha, name="alpha")
        if not 0.0 <= self.min_effect < 1.0:
            raise ValueError(f"min_effect must be in [0, 1); got {self.min_effect!r}.")
        check_positive(self.cluster_tol, name="cluster_tol")
        check_positive(self.noise_factor, name="noise_factor", allow_zero=True)
        check_positive(self.max_noise_allowance, name="max_noise_allowance")
        check_int(self.max_period, name="max_period", minimum=1)
        if not 0.0 <= self.zero_one_regular < self.zero_one_chaotic <= 1.0:
            raise ValueError("need 0 <= zero_one_regular < zero_one_chaotic <= 1.")
        check_positive(self.equilibrium_rtol, name="equilibrium_rtol", allow_zero=True)
        check_int(self.min_cycles, name="min_cycles", minimum=3)
        check_probability(self.max_residual, name="max_residual")


@dataclass(frozen=True, kw_only=True)
class Verdict:
    """A label with the evidence it rests on.

    Attributes
    ----------
    label
        One of ``"equilibrium"``, ``"periodic"``, ``"quasi-periodic"``, ``"chaotic"``,
        ``"noise-like"``, ``"undetermined"``.
    period
        :math:`k` of a period-:math:`k` orbit (section points per period), else None.
    confidence
        Fraction of the available, non-neutral pieces of evidence that agree with the label
        (1.0 for an exact equilibrium; NaN when undetermined). See ``votes``.
    reason
        The rule that fired, in words.
    needs
        When undetermined: what would decide, in the data's units (e.g. ``"≥ 20 drive
        periods; the series has 5"``). Empty for a decided label.
    votes
        For each piece of evidence (``lines``, ``section``, ``rosenstein``, ``wolf``,
        ``zero_one``, ``surrogates``, and ``cycles`` for a forced series): ``"supports"``,
        ``"opposes"``, ``"neutral"`` (present but unable to decide) or ``"missing"``.
    errors
        Evidence that could not be computed, with the estimator's message.
    variable, kind, dt, n_samples
        What was classified: the variable name, ``"map"``, ``"flow"`` or ``"forced"``,
        the sampling interval (s; 1 per iteration for maps) and the length.
    lag, embedding_dim
        Delay (samples) and embedding dimension used throughout.
    characteristic_time
        :math:`T` of the growth test (s, or iterations for maps).
    n_cycles
        Characteristic times the series spans (:math:`N\\,\\Delta t / T`).
    noise_level
        Estimated measurement-noise standard deviation over the signal's (flows; NaN for
        maps).
    rosenstein_positive, wolf_positive
        Whether each MLE is clearly positive (None if missing).
    kantz_positive
        Whether Kantz's exponent, the referee computed only when exactly one of the two
        others is clearly positive and everything else a chaotic label needs holds, is
        clearly positive (None when it was not computed or failed).
    delay, dimension, rosenstein, wolf, kantz, structure, section, zero_one, surrogates, lines
        The evidence itself: :class:`~chaoskit.DelayResult`,
        :class:`~chaoskit.DimensionResult`, two :class:`~chaoskit.LyapunovResult` (and
        the :class:`~chaoskit.KantzResult` when the referee ran), the
        :class:`SectionStructure` of the section points in ``section`` (a Dataset along
        ``crossing``), :class:`ZeroOneResult`, :class:`SurrogateResult` and the
        recurrence / line-spectrum analysis (``lines.kind``: ``"periodic"``,
        ``"quasi-periodic"``, ``"broadband"`` or ``"unresolved"``).
    surrogates_low_dim
        The surrogate test repeated in ``LOW_DIM`` (3) delay coordinates when the first one
        did not reject in more (None otherwise): a noise label needs both to fail.
    surrogates_one_step
        The surrogate test in three delay coordinates at a horizon of one sample of the
        (thinned) series when the first one, at a horizon of one delay, did not reject
        (None otherwise): a noise label needs it to fail as well.
    surrogates_cycle
        For a forced series: the test of the null hypothesis "a periodic orbit plus noise
        that does not carry over from one cycle to the next"
        (:func:`~chaoskit.cycle_surrogate_test`, cycles of :math:`k` drive periods for a
        section of :math:`k` clusters, else one); None for maps and autonomous flows, or
        when it could not run (``errors["cycles"]``).
    cycle_spread
        For a forced series: the cycle-to-cycle variation that is not white noise, relative
        to the standard deviation (:func:`~chaoskit.cycle_spread`, same cycles); NaN
        otherwise.
    rule
        The :class:`VerdictRule` applied.
    """

    label: Label
    period: int | None
    confidence: float
    reason: str
    votes: dict[str, Vote]
    errors: dict[str, str]
    variable: str | None
    kind: Kind
    dt: float
    n_samples: int
    needs: tuple[str, ...] = ()
    lag: int | None = None
    embedding_dim: int | None = None
    characteristic_time: float = float("nan")
    n_cycles: float = float("nan")
    noise_level: float = float("nan")
    rosenstein_positive: bool | None = None
    wolf_positive: bool | None = None
    kantz_positive: bool | None = None
    # The evidence objects carry curves and point sets: kept out of the repr.
    delay: Any = field(default=None, repr=False)
    dimension: Any = field(default=None, repr=False)
    rosenstein: Any = field(default=None, repr=False)
    wolf: Any = field(default=None, repr=False)
    kantz: Any = field(default=None, repr=False)
    structure: SectionStructure | None = field(default=None, repr=False)
    section: xr.Dataset | None = field(default=None, repr=False)
    zero_one: ZeroOneResult | None = field(default=None, repr=False)
    surrogates: SurrogateResult | None = field(default=None, repr=False)
    surrogates_low_dim: SurrogateResult | None = field(default=None, repr=False)
    surrogates_one_step: SurrogateResult | None = field(default=None, repr=False)
    surrogates_cycle: SurrogateResult | None = field(default=None, repr=False)
    cycle_spread: float = float("nan")
    lines: LineSpectrum | None = field(default=None, repr=False)
    rule: VerdictRule = field(default_factory=VerdictRule, repr=False)

    def summary(self) -> dict[str, Any]:
        """Scalar fields (NaN where undefined): one row of :func:`chaoskit.analyze`."""
        nan = float("nan")

        def mle(res: Any) -> tuple[float, float, float, float]:
            if res is None:
                return nan, nan, nan, nan
            return (
                float(res.mle),
                float(res.ci[0]),
                float(res.ci[1]),
                float(res.mle_bits_per_sample),
            )

        ros = mle(self.rosenstein)
        wolf = mle(self.wolf)
        st = self.structure
        return {
            "label": self.label,
            "period": nan if self.period is None else float(self.period),
            "confidence": float(self.confidence),
            "lag": nan if self.lag is None else float(self.lag),
            "lag_time": nan if self.lag is None else float(self.lag * self.dt),
            "embedding_dim": nan if self.embedding_dim is None else float(self.embedding_dim),
            "mle_rosenstein": ros[0],
            "mle_rosenstein_low": ros[1],
            "mle_rosenstein_high": ros[2],
            "mle_rosenstein_bits": ros[3],
            "mle_wolf": wolf[0],
            "mle_wolf_low": wolf[1],
            "mle_wolf_high": wolf[2],
            "mle_wolf_bits": wolf[3],
            "zero_one_k": nan if self.zero_one is None else float(self.zero_one.k),
            "surrogate_p_value": nan if self.surrogates is None else self.surrogates.p_value,
            "surrogate_effect": nan if self.surrogates is None else self.surrogates.effect,
            "section_points": nan if st is None else float(st.n_points),
            "section_structure": "none" if st is None else st.kind,
            "spectrum": "none" if self.lines is None else self.lines.kind,
            "needs": "; ".join(self.needs),
            "n_cycles": float(self.n_cycles),
            "characteristic_time": float(self.characteristic_time),
            "noise_level": float(self.noise_level),
            "dt": float(self.dt),
            "n_samples": float(self.n_samples),
        }

    def to_dataset(self) -> xr.Dataset:
        """The summary as a Dataset of scalars (see :func:`chaoskit.analyze` for units)."""
        return stack_verdicts({self.variable or "x": self}, LABELS)


# ---------------------------------------------------------------- input handling


@dataclass(frozen=True)
class _Input:
    x: np.ndarray
    t: np.ndarray
    dt: float
    kind: Kind
    variable: str | None
    angle: np.ndarray | None


def _pick_variable(ds: xr.Dataset, variable: str | None) -> str:
    if variable is None:
        names = [str(k) for k in ds.data_vars]
        if len(names) != 1:
            raise ValueError(f"the data hold several variables {names}; pass variable=...")
        return names[0]
    if variable not in ds.data_vars:
        raise ValueError(f"variable {variable!r} not found; available: {list(ds.data_vars)}.")
    return variable


def _read_input(
    data: Any, *, variable: str | None, dt: float | None, phase_variable: str | None
) -> _Input:
    if has_time_index(data):  # the index sets dt; load_trajectory refuses a contradicting dt=
        data, dt = load_trajectory(data, dt=dt, require_uniform=True), None
    if isinstance(data, (xr.Dataset, xr.DataArray)):
        ds = load_trajectory(data, dt=dt)  # refuses a dt= that contradicts a time coordinate
        name = _pick_variable(ds, variable)
        if ds[name].ndim != 1:
            raise ValueError(f"variable {name!r} must be one-dimensional; dims {ds[name].dims}.")
        x = np.asarray(ds[name].values, dtype=np.float64)
        angle = None
        if "time" in ds.coords:
            step = sampling_interval(ds)
            t = np.asarray(ds["time"].values, dtype=np.float64)
            if phase_variable is not None:
                angle = np.asarray(ds[_pick_variable(ds, phase_variable)].values, dtype=float)
            return _Input(x, t, step, "flow", name, angle)
        return _Input(x, np.arange(x.size, dtype=np.float64), 1.0, "map", name, None)
    if phase_variable is not None:
        raise ValueError("phase_variable needs a Dataset that holds the angle variable.")
    x = np.asarray(getattr(data, "values", data))
    given = variable if variable is not None else getattr(data, "name", None)
    label = None if given is None else str(given)
    if dt is None:
        return _Input(x, np.arange(x.size, dtype=np.float64), 1.0, "map", label, None)
    step = check_positive(dt, name="dt")
    return _Input(x, np.arange(x.size) * step, step, "flow", label, None)


def _scaled_to_unit_peak(inp: _Input) -> tuple[_Input, int]:
    """``inp`` with x scaled by an exact power of two if its peak is extreme, and the exponent.

    Every piece of evidence is scale-invariant, but near the float64 limits the variance
    over- or underflows (a series of amplitude 1e-300 would look constant).
    """
    x = inp.x
    if x.dtype.kind != "f" or x.ndim != 1 or not np.all(np.isfinite(x)):
        return inp, 0  # as_series reports it
    e = extreme_peak_exponent(x)
    return (inp, 0) if e == 0 else (replace(inp, x=np.ldexp(x, -e)), e)


def _is_equilibrium(x: np.ndarray, rtol: float) -> bool:
    if x.dtype.kind not in "fiu" or x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)):
        return False
    x = x.astype(np.float64)
    spread = float(np.std(x))
    return spread == 0.0 or spread <= rtol * float(np.abs(np.mean(x)))


def noise_level(x: np.ndarray) -> float:
    """Robust estimate of white measurement noise relative to the standard deviation.

    For a smooth, densely sampled signal the second difference is :math:`O(h^2)` and the
    noise contributes :math:`\\sqrt 6\\,\\sigma`; the median absolute deviation makes the
    estimate robust to the rare large curvature.
    """
    d2 = np.diff(x, 2)
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return 1.4826 * mad / np.sqrt(6.0) / float(np.std(x))


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


def _section_points(
    inp: _Input,
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


# ---------------------------------------------------------------- the rule


def describe_error(exc: Exception) -> str:
    """An estimator's failure in words: its message, with the type unless a ValueError."""
    return str(exc) if isinstance(exc, ValueError) else f"{type(exc).__name__}: {exc}"


def clearly_positive(res: Any, time_scale: float, rule: VerdictRule) -> bool | None:
    """Whether an exponent estimate is clearly positive (interval above 0 and λ₁T at least
    ``rule.min_growth``); None when it is missing."""
    if res is None:
        return None
    return bool(res.ci[0] > 0.0 and res.mle > 0.0 and res.mle * time_scale >= rule.min_growth)


def _votes(
    label: str,
    *,
    structure: SectionStructure | None,
    lines: str | None,
    positives: dict[str, bool | None],
    k: float | None,
    rejected: bool | None,
    long_enough: bool,
    n_bases: int,
    rule: VerdictRule,
    cycles: bool | None = None,
    noisy_orbit: bool = False,
) -> dict[str, Vote]:
    regular = label in ("periodic", "quasi-periodic")
    votes: dict[str, Vote] = {}
    if lines is None:
        votes["lines"] = "missing"
    elif lines == "unresolved" or (lines == "broadband" and not long_enough):
        votes["lines"] = "neutral"  # could not have decided
    elif regular:
        votes["lines"] = "supports" if lines == label else "opposes"
    else:
        votes["lines"] = "supports" if lines == "broadband" else "opposes"
    if structure is None or structure.kind == "too-few-points":
        votes["section"] = "missing" if structure is None else "neutral"
    elif label == "quasi-periodic" and n_bases >= 3 and structure.kind == "scattered":
        votes["section"] = "neutral"  # a three-torus's section fills a surface, not a curve
    else:
        wanted = {"periodic": "clusters", "quasi-periodic": "closed-curve"}.get(label, "scattered")
        votes["section"] = "supports" if structure.kind == wanted else "opposes"
    for name, pos in positives.items():
        if pos is None:
            votes[name] = "missing"
        elif label == "noise-like":
            votes[name] = "neutral"  # noise gives spurious positive exponents as often as not
        else:
            votes[name] = "supports" if pos == (label == "chaotic") else "opposes"
    if k is None:
        votes["zero_one"] = "missing"
    elif k <= rule.zero_one_regular:
        votes["zero_one"] = "supports" if regular else "opposes"
    elif k >= rule.zero_one_chaotic:
        votes["zero_one"] = "opposes" if regular else "supports"
    else:
        votes["zero_one"] = "neutral"
    if rejected is None:
        votes["surrogates"] = "missing"
    elif regular or (not rejected and not long_enough):
        # a periodic signal is its own linear surrogate; too short a series cannot reject
        votes["surrogates"] = "neutral"
    else:
        votes["surrogates"] = "supports" if rejected == (label == "chaotic") else "opposes"
    if cycles is not None:
        # cycles: the noisy-periodic null is rejected (by the cycle test or the spread)
        if noisy_orbit and cycles:
            votes["cycles"] = "neutral"  # what carries over is within the cluster tolerance
        elif label in ("periodic", "chaotic"):
            votes["cycles"] = "supports" if cycles == (label == "chaotic") else "opposes"
        else:
            votes["cycles"] = "neutral"  # a torus or noise carries over, or not, either way
    if noisy_orbit:
        # the cycle test found nothing beyond noise: what the noise does to the exponents,
        # the 0–1 test and the spectrum is no evidence (as for a noise label)
        for name in ("rosenstein", "wolf", "kantz", "zero_one", "lines"):
            if votes.get(name) in ("supports", "opposes"):
                votes[name] = "neutral"
    return votes


def combine(
    *,
    structure: SectionStructure | None,
    rosenstein_positive: bool | None,
    wolf_positive: bool | None,
    zero_one_k: float | None,
    surrogates_rejected: bool | None,
    rule: VerdictRule,
    lines: str | None = "broadband",
    lines_period: int | None = None,
    lines_bases: int = 0,
    n_cycles: float = float("inf"),
    cycle_unit: str = "characteristic times",
    low_dim_rejected: bool | None = None,
    kantz_positive: bool | None = None,
    cycles_rejected: bool | None = None,
    driven: bool = False,
    noise: float = float("nan"),
    cycle_spread: float = float("nan"),
) -> tuple[Label, int | None, float, str, dict[str, Vote], tuple[str, ...]]:
    """Apply the rule of :func:`classify` to the evidence.

    ``lines`` is the kind of the recurrence / line-spectrum analysis (None if it failed),
    ``lines_period`` its period, ``lines_bases`` its number of base frequencies,
    ``n_cycles`` the characteristic times the series spans
    (``cycle_unit`` names them), ``low_dim_rejected`` whether a surrogate test repeated
    in a few delay coordinates, a delay or one sample ahead, rejected (None: none ran),
    ``kantz_positive`` whether the referee exponent is clearly positive (None: not run),
    ``driven`` whether the series is forced (its chaos then needs ``cycles_rejected``:
    the noisy-periodic-orbit test rejected; None: it did not run), ``cycle_spread`` its
    cycle-to-cycle variation that is not white noise (relative to the standard deviation)
    and ``noise`` the estimated measurement-noise level (both stated in the reason of a
    noisy periodic orbit).
    Returns label, period, confidence, reason, votes and needs.
    """
    exponents = {"Rosenstein": rosenstein_positive, "Wolf": wolf_positive}
    if kantz_positive is not None:
        exponents["Kantz"] = kantz_positive
    # two estimators must agree on a clearly positive exponent
    n_positive = sum(pos is True for pos in exponents.values())
    both_positive = n_positive >= 2
    long_enough = n_cycles >= rule.min_cycles
    section = "none" if structure is None else structure.kind
    # a spectrum that is not lines, over enough cycles, outweighs a regular-looking section
    broadband_decides = lines == "broadband" and long_enough
    # where nothing looks regular (broadband spectrum, scattered section), the 0–1 test is
    # the second witness of sensitive dependence beside one clearly positive exponent (the
    # surrogate test, required below, rules out the noise that fools it)
    zero_one_witness = (
        n_positive == 1
        and zero_one_k is not None
        and zero_one_k >= rule.zero_one_chaotic
        and broadband_decides
        and section == "scattered"
    )
    # clusters alone make a period only where the spectrum cannot speak against them: a
    # spectrum of lines that are not one period's harmonics (unresolved, or a torus's)
    # contradicts k tight clusters (chaotic flows sampled coarsely show both)
    lines_contradict_clusters = lines in ("unresolved", "quasi-periodic")
    # a driven series whose section is k tight clusters and whose departure from its mean
    # cycle is white noise, up to the cluster tolerance, is a periodic orbit plus noise,
    # whatever the noise does to the spectrum and the exponents
    noisy_orbit = bool(
        driven
        and section == "clusters"
        and lines != "quasi-periodic"
        and cycle_spread <= rule.cluster_tol
    )
    # what a chaotic driven series must show beyond a noisy periodic orbit: its departure
    # from the mean cycle carries over from one cycle to the next (the cycle-shuffled
    # surrogates reject), or is not white noise and larger than the cluster tolerance
    beyond_orbit = cycles_rejected is True or bool(cycle_spread > rule.cluster_tol)
    period: int | None = None
    label: Label
    needs: list[str] = []
    if lines == "periodic":
        label, period = "periodic", lines_period
        reason = "the series repeats: what is left after its period is white noise or nothing"
    elif section == "clusters" and not broadband_decides and not lines_contradict_clusters:
        assert structure is not None
        label, period = "periodic", structure.n_clusters
        reason = (
            f"the section is {period} tight cluster{'s' * (period != 1)} visited in a fixed "
            "cyclic order"
        )
    elif noisy_orbit:
        assert structure is not None
        label, period = "periodic", structure.n_clusters
        reason = (
            f"the section is {period} tight cluster{'s' * (period != 1)} and what varies from "
            f"cycle to cycle beyond white noise is {cycle_spread:.2g} of the standard "
            f"deviation (at most {rule.cluster_tol:g}): a periodic orbit plus noise "
            f"(measurement noise about {noise:.2g} of the standard deviation; the "
            "cycle-shuffled surrogate test "
            + ("rejects, within that tolerance)" if cycles_rejected else "does not reject)")
        )
    elif lines == "quasi-periodic":
        label = "quasi-periodic"
        reason = (
            "the spectrum is lines at integer combinations of two or three incommensurate "
            "frequencies, and what is left is white noise or nothing"
        )
    elif section == "closed-curve" and not both_positive and not broadband_decides:
        label = "quasi-periodic"
        reason = "the section fills a closed curve and not both exponents are clearly positive"
    elif (
        lines == "broadband"
        and long_enough
        and surrogates_rejected is False
        and low_dim_rejected is not True
    ):
        label = "noise-like"
        reason = "the spectrum is not lines; the surrogate test cannot reject linear noise"
    elif (
        (both_positive or zero_one_witness)
        and surrogates_rejected is True
        and (not driven or beyond_orbit)
        and lines in ("broadband", "unresolved")
        # a regular-looking section does not count against a broadband spectrum either
        and (section not in ("clusters", "closed-curve") or broadband_decides)
        and (section == "scattered" or (lines == "broadband" and long_enough))
    ):
        label = "chaotic"
        if both_positive:
            head = (
                "both exponents are" if kantz_positive is None else "two of the three exponents are"
            ) + " clearly positive"
        else:
            (name,) = (n for n, pos in exponents.items() if pos is True)
            head = (
                f"the {name} exponent is clearly positive and the 0–1 test finds the motion "
                f"irregular (K = {zero_one_k:.2f})"
            )
        reason = (
            f"{head}, the data are more predictable than their "
            "IAAFT surrogates"
            + (
                ""
                if not driven
                else " and, across a cycle boundary, than their cycle-shuffled ones"
                if cycles_rejected
                else f", their departure from the mean cycle is not white noise "
                f"({cycle_spread:.2g} of the standard deviation)"
            )
            + ", and neither the spectrum nor the section is regular"
        )
    else:
        label = "undetermined"
        if not long_enough:
            # nothing else could decide at this length: say only what would
            needs.append(f"≥ {rule.min_cycles} {cycle_unit}; the series has {n_cycles:.0f}")
        else:
            if section == "too-few-points":
                assert structure is not None
                needs.append(
                    f"≥ {rule.min_cycles} section points; the section has {structure.n_points}"
                )
            if section in ("clusters", "closed-curve") and broadband_decides:
                needs.append(
                    f"a longer series: the section looks regular ({section}) but the "
                    "spectrum is not lines"
                )
            elif section == "clusters" and lines_contradict_clusters:
                assert structure is not None
                needs.append(
                    f"a longer or cleaner series: the section is {structure.n_clusters} tight "
                    f"cluster{'s' * (structure.n_clusters != 1)} but the spectrum is not the "
                    f"harmonics of one period ({lines})"
                )
            elif section == "closed-curve":
                needs.append(
                    "a longer series to tell a torus from a thin chaotic band (the section "
                    "is a closed curve but both exponents are clearly positive)"
                )
            elif surrogates_rejected is False and low_dim_rejected is True:
                needs.append(
                    "a longer or more finely sampled series: the data are more predictable "
                    f"than their surrogates in {LOW_DIM} delay coordinates or one sample "
                    "ahead, but not in the embedding dimension one delay ahead, so neither "
                    "noise nor determinism is shown"
                )
            elif driven and not beyond_orbit and surrogates_rejected is True:
                needs.append(
                    "evidence beyond a noisy periodic orbit: a cycle-shuffled surrogate test "
                    + (
                        "(it could not run; see errors)"
                        if cycles_rejected is None
                        else "that rejects, or a departure from the mean cycle that is not "
                        f"white noise and exceeds {rule.cluster_tol:g} of the standard "
                        f"deviation (it is {cycle_spread:.2g})"
                    )
                )
            elif surrogates_rejected is not False:
                for name, pos in exponents.items():
                    if pos is False:
                        needs.append(
                            f"a clearly positive {name} exponent (λ₁T ≥ {rule.min_growth:g}, "
                            "95 % interval above 0), or a line spectrum or section that "
                            "shows the motion regular"
                        )
                    elif pos is None:
                        needs.append(f"a {name} exponent (the estimator failed; see errors)")
                if surrogates_rejected is None:
                    needs.append("a surrogate test (it failed; see errors)")
        if lines is None:
            needs.append("a recurrence / line-spectrum analysis (it failed; see errors)")
        if lines == "unresolved" and not needs:
            needs.append(
                "a longer or cleaner series: spectral lines explain all but 0.1 % of the "
                "variance, yet the rest is not white"
            )
        if not needs:
            needs.append("a longer series")
        reason = "the evidence cannot decide: needs " + "; ".join(needs)
    votes = _votes(
        label,
        structure=structure,
        lines=lines,
        positives={
            "rosenstein": rosenstein_positive,
            "wolf": wolf_positive,
            **({} if kantz_positive is None else {"kantz": kantz_positive}),
        },
        k=zero_one_k,
        rejected=surrogates_rejected,
        long_enough=long_enough,
        n_bases=lines_bases,
        rule=rule,
        cycles=None if not driven or cycles_rejected is None else beyond_orbit,
        noisy_orbit=noisy_orbit and label == "periodic" and lines != "periodic",
    )
    if label == "undetermined":
        confidence = float("nan")
    else:
        counted = [v for v in votes.values() if v in ("supports", "opposes")]
        confidence = sum(v == "supports" for v in counted) / len(counted) if counted else 0.0
    return label, period, confidence, reason, votes, tuple(needs)


def _needs_referee(
    positives: dict[str, bool | None],
    structure: SectionStructure | None,
    lines: LineSpectrum | None,
    surrogates: SurrogateResult | None,
    long_enough: bool,
) -> bool:
    """Whether Kantz's exponent can decide: exactly one of Rosenstein's and Wolf's is
    clearly positive while everything else a chaotic label needs holds (determinism beyond
    linear noise, a spectrum that is not lines, regular motion ruled out)."""
    if sum(pos is True for pos in positives.values()) != 1:
        return False
    if surrogates is None or not surrogates.rejected:
        return False
    if lines is None or lines.kind not in ("broadband", "unresolved"):
        return False
    section = "none" if structure is None else structure.kind
    broadband_decides = lines.kind == "broadband" and long_enough
    if section in ("clusters", "closed-curve") and not broadband_decides:
        return False
    return section == "scattered" or broadband_decides


def _cycle_test(
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
        embedding_dim=LOW_DIM,
        lag=thin_lag,
        horizon=min(thin_lag, int(period / (dt * step)) - 1),
        n_surrogates=n_surrogates,
        alpha=rule.alpha,
        min_effect=rule.min_effect,
        min_gain=CYCLE_MIN_GAIN,
        rng=gen,
    )


def _any_rejected(*tests: SurrogateResult | None) -> bool | None:
    """Whether any of the tests that ran rejected (None if none ran)."""
    ran = [t.rejected for t in tests if t is not None]
    return any(ran) if ran else None


def _cycles(inp: _Input, n: int, time_scale: float) -> tuple[float, str]:
    """Characteristic times the series spans, and their name in the user's terms."""
    if inp.kind == "map":
        return float(n), "samples"
    unit = "drive periods" if inp.kind == "forced" else "oscillations (maxima)"
    if not np.isfinite(time_scale) or time_scale <= 0:
        return 0.0, unit
    return n * inp.dt / time_scale, unit


def _line_period(lines: LineSpectrum, inp: _Input, time_scale: float) -> int | None:
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


# ---------------------------------------------------------------- classify


def classify(
    data: Any,
    *,
    variable: str | None = None,
    dt: float | None = None,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    lag: int | None = None,
    embedding_dim: int | None = None,
    n_surrogates: int = 19,
    surrogate_max_samples: int = 4096,
    rule: VerdictRule | None = None,
    rng: Any = None,
) -> Verdict:
    r"""Decide whether a series is an equilibrium, periodic, quasi-periodic, chaotic or noise.

    **Evidence.** From the series :math:`x` (one variable of a trajectory):

    1. delay :math:`\tau` (:func:`~chaoskit.estimate_delay`, ``method="auto"``) and
       embedding dimension :math:`m` (:func:`~chaoskit.estimate_embedding_dim`, FNN);
    2. the largest Lyapunov exponent by Rosenstein's and by Wolf's method, each with its
       95 % interval; an exponent is *clearly positive* when the interval lies above 0 and
       :math:`\lambda_1 T \ge` ``rule.min_growth`` (default 0.1), :math:`T` being the
       characteristic time below — a tiny but "significant" slope (e.g. 0.001 bits per
       sample) is not evidence of chaos;
    3. a section: for a map, the delay vectors :math:`(x_n, x_{n+\tau}, \ldots)` with
       :math:`\max(2, m)` coordinates; for a forced flow (``drive_period`` or
       ``phase_variable``), the stroboscopic map of those delay vectors; for an autonomous
       flow, the return map :math:`(M_n, M_{n+1}, M_{n+2})` of the successive maxima
       :math:`M_n` of :math:`x` (Lorenz's section of his own flow), taken after a
       Savitzky–Golay smoothing over about :math:`\tau` samples and keeping only maxima
       more prominent than four noise standard deviations. :math:`T` is one iteration, the
       drive period, or the mean time between maxima (:math:`4\tau` when there are too few).
       Its structure (:func:`section_structure`) is a few tight clusters visited
       cyclically, a closed curve, or scattered; the cluster-radius allowance is
       ``rule.cluster_tol`` of the signal's standard deviation, raised for noisy flows to
       ``rule.noise_factor`` times the estimated noise level (at most
       ``rule.max_noise_allowance``);
    4. the 0–1 test for chaos (:func:`zero_one_test`; flows subsampled every :math:`\tau`
       samples);
    5. a surrogate test (:func:`surrogate_test`): is :math:`x` more predictable than
       ``n_surrogates`` IAAFT surrogates sharing its spectrum and value distribution?
       ``n_surrogates`` must reach ``rule.alpha`` (:math:`n \ge 1/\alpha - 1`, 19 for
       0.05), else a ValueError: a test that can never reject is never read as noise;
    6. recurrence and line spectrum (``Verdict.lines``): the series folded at a lag of
       :math:`k \le` ``rule.max_period`` samples, then refined spectral lines extracted
       until the residual is white noise (Laskar's frequency analysis, Ljung–Box test).
       The outcome is *periodic* (harmonics of one fundamental; for a forced series a
       subharmonic of the drive), *quasi-periodic* (integer combinations of two or three
       incommensurate base frequencies), *broadband* or *unresolved* (lines explain all
       but 0.1 % of the variance, the rest is not white);
    7. for a forced series, the null hypothesis "a periodic orbit plus noise that does not
       carry over from one cycle to the next": the cycle-shuffled surrogate test
       (:func:`cycle_surrogate_test`; cycles of :math:`k` drive periods when the section is
       :math:`k` clusters, else one; three delay coordinates, a horizon of one delay, a
       forecast gain of at least 0.001 of the standard deviation) and the departure from
       the mean cycle that is not white noise (:func:`cycle_spread`).

    A series spans :math:`N\,\Delta t / T` characteristic times (``Verdict.n_cycles``:
    drive periods, oscillations, or samples of a map). Below ``rule.min_cycles`` (20) a
    broadband spectrum, a scattered section or a surrogate test that does not reject
    cannot rule out a regular motion: such evidence is *neutral*.

    **Rule.**

    * *equilibrium* if the series is constant (standard deviation at most
      ``rule.equilibrium_rtol`` of its mean magnitude); nothing else is computed;
    * else *periodic* (period :math:`k`) if the series repeats — folding or the line
      spectrum leaves white noise carrying at most ``rule.max_residual`` of the variance,
      or nothing — or if the section is :math:`k` tight clusters visited in a fixed cyclic
      order and the spectrum is not lines of another kind (unresolved, or a torus's);
      :math:`k` counts samples for maps and for series that repeat after :math:`k`
      samples, drive periods for forced flows, maxima per period for autonomous flows;
    * for a forced series (``drive_period`` or ``phase_variable``) also *periodic* (period
      :math:`k`) if the section is :math:`k` tight clusters, the spectrum is not a torus's
      and what varies from cycle to cycle beyond white noise (:func:`cycle_spread`) is at
      most ``rule.cluster_tol`` of the standard deviation: a periodic orbit plus noise,
      whatever the noise does to the spectrum and the exponents;
    * else *quasi-periodic* if the line spectrum is two or three incommensurate base
      frequencies and their combinations (white residual), or if the section fills a
      closed curve and not both exponents are clearly positive;
    * a regular-looking section (clusters, closed curve) does not count when the spectrum
      is broadband over at least ``rule.min_cycles`` characteristic times;
    * else *noise-like* if the spectrum is broadband, the series spans at least
      ``rule.min_cycles`` characteristic times and the surrogate test cannot reject linear
      Gaussian noise, neither in the embedding dimension nor (when that is larger) in
      three delay coordinates, nor in three coordinates one sample ahead (a flow whose
      orbits separate within one delay is unpredictable a delay ahead, data and
      surrogates alike);
    * else *chaotic* if two exponent estimates are clearly positive — Rosenstein's and
      Wolf's, or, when exactly one of them is, Kantz's as referee —, the surrogate test
      rejects, the spectrum is broadband or unresolved, and regular motion is ruled out by
      a scattered section or by a broadband spectrum over at least ``rule.min_cycles``
      characteristic times; one clearly positive estimate suffices when the 0–1 test
      finds the motion irregular (:math:`K \ge` ``rule.zero_one_chaotic``), the surrogate
      test rejects, the section is scattered and the spectrum broadband over at least
      ``rule.min_cycles`` characteristic times; a forced series must in addition reject
      the null hypothesis of a noisy periodic orbit: the cycle-shuffled surrogate test
      (:func:`cycle_surrogate_test`) rejects, or the departure from the mean cycle is not
      white noise and exceeds ``rule.cluster_tol`` of the standard deviation;
    * else *undetermined*, and ``Verdict.needs`` says what would decide: more drive
      periods or oscillations, more section points, a clearly positive exponent, an
      estimator that failed.

    Evidence that cannot be computed (e.g. an estimator refusing an exactly periodic series)
    counts as missing; *chaotic* needs all of its pieces. The 0–1 test alone never decides:
    it is consistent with chaos and with noise alike. Only where the surrogate test has
    ruled out linear noise and the spectrum and the section rule out regular motion does
    it stand in for a second exponent estimate.

    **Confidence** is the fraction of the pieces of evidence that could have decided
    (present and not neutral: line spectrum, section, each exponent — the referee's when
    it ran —, 0–1 test, surrogate test) that agree with the label (``Verdict.votes``):
    e.g. for *periodic*, an exponent that is not clearly positive and :math:`K \le 0.2`
    agree, a clearly positive exponent
    disagrees; the surrogate test is neutral for regular labels, the exponents for
    *noise-like*, a section with fewer than 20 points always, and a three-frequency
    torus's scattered section for *quasi-periodic*. For a forced series the null of a
    noisy periodic orbit votes too (``cycles``: rejected — by the cycle-shuffled test or
    the correlated spread — for *chaotic*, not rejected for *periodic*); for a periodic
    orbit plus noise the exponents, the 0–1 test and the spectrum are neutral (noise
    fools them), and so is a rejection of the cycle test within the cluster tolerance.

    Parameters
    ----------
    data
        A trajectory Dataset (``time`` in s: a flow; ``step``: a map) or DataArray, or a
        1-D array / Series (a map unless ``dt`` is given or the Series has a time index:
        ``DatetimeIndex``, ``TimedeltaIndex`` or float seconds, which must be uniform).
    variable
        The variable to classify (required if the Dataset has several).
    dt
        Sampling interval in s for array input without a time axis; refused when it
        contradicts the time of ``data``.
    drive_period
        Period of an external drive, s: use the stroboscopic map.
    phase_variable
        Name of a drive-angle variable (rad): stroboscopic map at each turn.
    lag, embedding_dim
        Override the estimated delay (samples) and dimension.
    n_surrogates
        IAAFT surrogates; at least :math:`1/\alpha - 1` for ``rule.alpha`` (19 gives a
        smallest p-value of 0.05), else a ValueError.
    surrogate_max_samples
        The surrogate test uses at most this many samples (the last ones).
    rule
        Thresholds of the rule (:class:`VerdictRule`).
    rng
        Seed or :class:`numpy.random.Generator` (0–1 frequencies, surrogates).

    Returns
    -------
    Verdict

    References
    ----------
    M. T. Rosenstein, J. J. Collins, C. J. De Luca, Physica D 65, 117 (1993); A. Wolf,
    J. B. Swift, H. L. Swinney, J. A. Vastano, Physica D 16, 285 (1985); G. A. Gottwald and
    I. Melbourne, SIAM J. Appl. Dyn. Syst. 8, 129 (2009); T. Schreiber and A. Schmitz,
    Phys. Rev. Lett. 77, 635 (1996); J. Theiler et al., Physica D 58, 77 (1992).

    Examples
    --------
    >>> from chaoskit import classify, systems
    >>> v = classify(systems.logistic(1000, r=3.5), rng=0)
    >>> v.label, v.period
    ('periodic', 4)
    """
    rule = VerdictRule() if rule is None else rule
    n_surrogates = check_surrogates(n_surrogates, rule.alpha)
    surrogate_max_samples = check_int(
        surrogate_max_samples, name="surrogate_max_samples", minimum=MIN_SAMPLES
    )
    gen = as_generator(rng)
    inp = _read_input(data, variable=variable, dt=dt, phase_variable=phase_variable)
    if drive_period is not None or inp.angle is not None:
        if inp.kind == "map":
            raise ValueError("drive_period needs a continuous-time series (a 'time' axis or dt).")
        if drive_period is not None and inp.angle is not None:
            raise ValueError("give drive_period or phase_variable, not both.")
        if drive_period is not None:
            drive_period = check_positive(drive_period, name="drive_period")
        inp = _Input(inp.x, inp.t, inp.dt, "forced", inp.variable, inp.angle)
    inp, exponent = _scaled_to_unit_peak(inp)
    base: dict[str, Any] = {"variable": inp.variable, "kind": inp.kind, "dt": inp.dt, "rule": rule}
    if _is_equilibrium(inp.x, rule.equilibrium_rtol):
        return Verdict(
            label="equilibrium", period=None, confidence=1.0,
            reason="the series is constant", votes={}, errors={},
            n_samples=int(inp.x.size), **base,
        )  # fmt: skip
    x = as_series(inp.x, name=inp.variable or "x", min_length=MIN_SAMPLES)
    errors: dict[str, str] = {}
    delay = estimate_delay(x, method="auto") if lag is None else None
    lag = delay.lag if delay is not None else check_int(lag, name="lag", minimum=1)
    dimension = None
    if embedding_dim is None:
        max_dim = min(10, (x.size - 10) // lag - 1)
        dimension = estimate_embedding_dim(
            x, lag=lag, max_dim=max(1, max_dim), max_points=DIMENSION_POINTS
        )
        embedding_dim = dimension.embedding_dim
    embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1)
    noise = noise_level(x) if inp.kind != "map" else float("nan")

    structure = section = None
    # T of the growth test until the section gives a better one: a delay is about a quarter
    # of the mean period of a flow.
    time_scale = 1.0 if inp.kind == "map" else (drive_period or 4.0 * lag * inp.dt)
    try:
        n_coords = 3 if inp.kind == "flow" else max(2, embedding_dim)
        section, points, time_scale = _section_points(inp, x, lag, n_coords, drive_period, noise)
        tol = rule.cluster_tol
        if inp.kind != "map":
            tol = max(tol, min(rule.noise_factor * noise, rule.max_noise_allowance))
        structure = section_structure(
            points, scale=float(np.std(x)), cluster_tol=tol, max_clusters=rule.max_period
        )
    except ValueError as exc:
        errors["section"] = str(exc)

    lyap: dict[str, Any] = {}
    for name, func in (("rosenstein", lyapunov_rosenstein), ("wolf", lyapunov_wolf)):
        try:
            lyap[name] = func(x, embedding_dim=embedding_dim, lag=lag, dt=inp.dt)
        except Exception as exc:  # failure is data: the verdict records it and goes on
            lyap[name] = None
            errors[name] = describe_error(exc)
    positives = {name: clearly_positive(res, time_scale, rule) for name, res in lyap.items()}

    zero_one = None
    try:
        phi = x if inp.kind == "map" else x[::lag]
        zero_one = zero_one_test(phi, rng=gen)
    except ValueError as exc:
        errors["zero_one"] = str(exc)

    surrogates = None
    try:
        # A densely sampled flow is thinned to about four samples per delay: the statistic
        # only has to discriminate, and it costs less for the data and every surrogate alike.
        step = max(1, lag // 4)
        theiler = embedding_dim * lag
        if lyap.get("rosenstein") is not None:
            theiler = int(lyap["rosenstein"].theiler_window)
        surrogates = surrogate_test(
            x[::step][-surrogate_max_samples:],
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
        # These tests can only withhold a noise label: chaos still needs the first test to
        # reject. A locally constant predictor in many coordinates finds no close
        # neighbours in a few thousand points, so its failure to beat the surrogates is no
        # evidence of noise; a low-dimensional attractor (coarsely sampled, or with a
        # dimension that FNN could not resolve) still shows in a few coordinates. And a
        # flow whose orbits separate within one delay is unpredictable at a horizon of one
        # delay, data and surrogates alike; one (thinned) sample ahead it still shows.
        # The Theiler window is the span of the three delay coordinates: both series share
        # the autocorrelation, so temporal neighbours help data and surrogates alike, while
        # the period-long window of the exponent can leave a slowly forced flow no
        # neighbours at all.
        thinned = x[::step][-surrogate_max_samples:]
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

    lines = None
    try:
        forced_period = None
        if inp.kind == "forced":
            forced_period = drive_period or time_scale
        lines = line_spectrum(
            x,
            dt=inp.dt,
            drive_period=forced_period,
            max_period=rule.max_period,
            max_residual=rule.max_residual,
            fold=inp.kind != "forced",
        )
    except (ValueError, np.linalg.LinAlgError) as exc:
        errors["lines"] = describe_error(exc)
    n_cycles, unit = _cycles(inp, x.size, time_scale)
    cycles = None
    spread = float("nan")
    if inp.kind == "forced":
        try:
            # cycles of k drive periods for a section of k clusters or a series that repeats
            # after k: a period-k orbit keeps its order
            k = structure.n_clusters if structure and structure.kind == "clusters" else 1
            if lines is not None and lines.kind == "periodic" and k == 1:
                k = _line_period(lines, inp, time_scale) or 1
            cycles = _cycle_test(x, inp.dt, lag, k * time_scale, rule, n_surrogates, gen)
            spread = cycle_spread(x, k * time_scale, dt=inp.dt)
        except ValueError as exc:
            errors["cycles"] = str(exc)
    kantz = None
    kantz_positive = None
    if _needs_referee(positives, structure, lines, surrogates, n_cycles >= rule.min_cycles):
        try:
            kantz = lyapunov_kantz(x, embedding_dim=embedding_dim, lag=lag, dt=inp.dt)
            kantz_positive = clearly_positive(kantz, time_scale, rule)
        except Exception as exc:  # failure is data, as for the other two
            errors["kantz"] = describe_error(exc)
    label, period, confidence, reason, votes, needs = combine(
        structure=structure,
        rosenstein_positive=positives["rosenstein"],
        wolf_positive=positives["wolf"],
        zero_one_k=None if zero_one is None else zero_one.k,
        surrogates_rejected=None if surrogates is None else surrogates.rejected,
        rule=rule,
        lines=None if lines is None else lines.kind,
        lines_period=None if lines is None else _line_period(lines, inp, time_scale),
        lines_bases=0 if lines is None else int(lines.base_frequencies.size),
        n_cycles=n_cycles,
        cycle_unit=unit,
        low_dim_rejected=_any_rejected(low_dim, one_step),
        kantz_positive=kantz_positive,
        cycles_rejected=None if cycles is None else cycles.rejected,
        driven=inp.kind == "forced",
        noise=noise,
        cycle_spread=spread,
    )
    return Verdict(
        label=label,
        period=period,
        confidence=confidence,
        reason=reason if exponent == 0 else f"{reason} (analysed as x * 2**{-exponent})",
        votes=votes,
        errors=errors,
        n_samples=int(x.size),
        needs=needs,
        n_cycles=float(n_cycles),
        lines=lines,
        lag=int(lag),
        embedding_dim=int(embedding_dim),
        characteristic_time=float(time_scale),
        noise_level=float(noise),
        rosenstein_positive=positives["rosenstein"],
        wolf_positive=positives["wolf"],
        kantz_positive=kantz_positive,
        delay=delay,
        dimension=dimension,
        rosenstein=lyap["rosenstein"],
        wolf=lyap["wolf"],
        kantz=kantz,
        structure=structure,
        section=section,
        zero_one=zero_one,
        surrogates=surrogates,
        surrogates_low_dim=low_dim,
        surrogates_one_step=one_step,
        surrogates_cycle=cycles,
        cycle_spread=spread,
        **base,
    )
