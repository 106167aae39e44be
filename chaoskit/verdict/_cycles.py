"""Surrogates that keep a noisy periodic orbit, and the test of cycle-to-cycle determinism.

The null hypothesis of a driven series is not "linear noise" but "a periodic orbit plus
noise that does not carry over from one cycle to the next". Its surrogates keep every cycle
of the data (cycle-shuffled surrogates) or the orbit's mean cycle (twin surrogates) and
randomise only what links one cycle to the next.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.spatial import cKDTree

from .._progress import stage
from .._validate import as_series, check_int, check_positive, check_probability
from ._rng import as_generator
from ._surrogates import SurrogateResult, check_surrogates, surrogate_test

__all__ = [
    "CycleForecast",
    "cycle_boundaries",
    "cycle_shuffled_surrogates",
    "cycle_spread",
    "cycle_surrogate_test",
    "twin_surrogates",
]

MIN_CYCLES = 8  # fewer whole cycles leave too few permutations and neighbours


def _samples_per_cycle(period: Any, dt: Any) -> float:
    period = check_positive(period, name="period")
    dt = check_positive(dt, name="dt")
    spc = period / dt
    if spc < 4.0:
        raise ValueError(
            f"period must span at least 4 samples; got period / dt = {spc:.3g} (period = "
            f"{period:g}, dt = {dt:g})."
        )
    return spc


def cycle_boundaries(x: Any, period: float, *, dt: float = 1.0) -> np.ndarray:
    r"""Indices that cut ``x`` into whole cycles of length ``period`` at matching values.

    The cuts are :math:`c_n = \mathrm{round}(c_0 + n P/\Delta t)` for every whole cycle of
    the series. The phase :math:`c_0 \in [0, P/\Delta t)` is the one at which the cycles
    agree best — the smallest spread across cycles of the value and of the slope at the
    cut —, so that joining any cycle to any other leaves no jump larger than the
    cycle-to-cycle spread itself (Theiler 1995).

    Parameters
    ----------
    x
        The series (1-D, at least ``MIN_CYCLES`` (8) cycles).
    period
        Cycle length in the units of ``dt`` (e.g. the drive period in s), at least four
        samples.
    dt
        Sampling interval.

    Returns
    -------
    numpy.ndarray
        Increasing int64 indices; cycle :math:`n` is ``x[c[n]:c[n + 1]]``.
    """
    x = as_series(x, name="x", min_length=16)
    spc = _samples_per_cycle(period, dt)
    n_cycles = int((x.size - 1) // spc)
    if n_cycles < MIN_CYCLES:
        raise ValueError(
            f"x spans {n_cycles} whole cycles of period {period:g}; the cycle surrogates "
            f"need at least {MIN_CYCLES}."
        )
    width = int(np.floor(spc))
    starts = np.arange(n_cycles) * spc
    offsets = np.arange(width)
    idx = np.rint(offsets[:, None] + starts[None, :]).astype(np.int64)  # (offset, cycle)
    idx = np.minimum(idx, x.size - 2)
    value = x[idx]
    slope = x[idx + 1] - x[idx]
    cost = np.var(value, axis=1) + np.var(slope, axis=1)
    best = int(np.argmin(cost))
    last = int((x.size - 1 - best) // spc)  # whole cycles after the chosen phase
    return np.rint(best + np.arange(last + 1) * spc).astype(np.int64)


def cycle_shuffled_surrogates(
    x: Any,
    period: float,
    *,
    dt: float = 1.0,
    n_surrogates: int = 19,
    rng: Any = None,
) -> np.ndarray:
    r"""Cycle-shuffled surrogates: the data's own cycles in a random order.

    The series is cut into whole cycles at matching values (:func:`cycle_boundaries`) and
    each surrogate concatenates the same cycles, each kept sample for sample, in a random
    order. Everything within a cycle — the periodic orbit, its waveform, the noise on it —
    is the data's; only the link from one cycle to the next is randomised. A surrogate is
    a realisation of the null hypothesis "a periodic orbit plus fluctuations that are
    independent from cycle to cycle"; deterministic dynamics that carry a deviation over
    from one cycle to the next (chaos, a slow transient) are not.

    Parameters
    ----------
    x
        The series (1-D).
    period
        Cycle length in the units of ``dt``: the drive period, or :math:`k` drive periods
        for a period-:math:`k` orbit.
    dt
        Sampling interval.
    n_surrogates
        Number of surrogates (at least 1).
    rng
        Seed or :class:`numpy.random.Generator`.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_surrogates, c[-1] - c[0])`` with ``c = cycle_boundaries(x, period,
        dt=dt)``: the surrogates cover the whole cycles of ``x``, ``x[c[0]:c[-1]]``.

    References
    ----------
    J. Theiler, "On the evidence for low-dimensional chaos in an epileptic
    electroencephalogram", Phys. Lett. A 196, 335–341 (1995).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import cycle_shuffled_surrogates
    >>> t = np.arange(2000) * 0.05
    >>> x = np.sin(t) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> s = cycle_shuffled_surrogates(x, 2 * np.pi, dt=0.05, n_surrogates=3, rng=1)
    >>> s.shape
    (3, 1885)
    """
    cuts = cycle_boundaries(x, period, dt=dt)
    x = as_series(x, name="x", min_length=16)
    n_surrogates = check_int(n_surrogates, name="n_surrogates", minimum=1)
    gen = as_generator(rng)
    cycles = [x[a:b] for a, b in itertools.pairwise(cuts)]
    return np.stack(
        [
            np.concatenate([cycles[i] for i in gen.permutation(len(cycles))])
            for _ in range(n_surrogates)
        ]
    )


def _cycle_cuts_of(order: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Cut indices (relative to the first cut) of cycles concatenated in ``order``."""
    return np.concatenate([[0], np.cumsum(lengths[order])])


def twin_surrogates(
    x: Any,
    *,
    embedding_dim: int,
    lag: int,
    radius: float | None = None,
    n_surrogates: int = 19,
    max_points: int = 6000,
    rng: Any = None,
) -> np.ndarray:
    r"""Twin surrogates: new trajectories of the data's recurrence structure.

    In delay coordinates :math:`\mathbf y_i = (x_i, x_{i-\tau}, \ldots)` two points are
    *twins* when they have the same neighbours, :math:`R_{ik} = R_{jk}` for all :math:`k`,
    with :math:`R_{ik} = \Theta(\varepsilon - \|\mathbf y_i - \mathbf y_k\|)`. A surrogate
    starts at a random point and, at every step, jumps with equal probability to the
    successor of the current point or of any of its twins. It follows the same orbit
    through state space — a periodic orbit's mean cycle is reproduced — but wherever the
    recurrence structure cannot tell two points apart, their futures are exchanged: the
    null hypothesis is "a process with the data's recurrence structure at resolution
    :math:`\varepsilon`", for a noisy periodic orbit the orbit plus noise that does not
    carry over.

    Parameters
    ----------
    x
        The series (1-D).
    embedding_dim, lag
        Delay embedding (``lag`` in samples).
    radius
        Recurrence threshold :math:`\varepsilon` in the units of ``x`` (default: the
        distance that gives each point 5 % of the points as neighbours, estimated on 200
        points).
    n_surrogates
        Number of surrogates.
    max_points
        Largest number of embedded points (the last ones are kept): the recurrence sets
        cost memory proportional to their total size.
    rng
        Seed or :class:`numpy.random.Generator`.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_surrogates, n_points)``: the first delay coordinate of each surrogate
        trajectory, ``n_points`` the number of embedded points used.

    References
    ----------
    M. Thiel, M. C. Romano, J. Kurths, M. Rolfs and R. Kliegl, "Twin surrogates to test for
    complex synchronisation", Europhys. Lett. 75, 535–541 (2006); M. Small and C. K. Tse,
    "Applying the method of surrogate data to cyclic time series", Physica D 164, 187–201
    (2002).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import twin_surrogates
    >>> t = np.arange(1000) * 0.1
    >>> x = np.sin(t) + 0.05 * np.random.default_rng(0).standard_normal(t.size)
    >>> twin_surrogates(x, embedding_dim=2, lag=15, n_surrogates=2, rng=0).shape
    (2, 985)
    """
    x = as_series(x, name="x", min_length=16)
    embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1)
    lag = check_int(lag, name="lag", minimum=1)
    n_surrogates = check_int(n_surrogates, name="n_surrogates", minimum=1)
    max_points = check_int(max_points, name="max_points", minimum=16)
    gen = as_generator(rng)
    span = (embedding_dim - 1) * lag
    if x.size - span < 16:
        raise ValueError(
            f"x has {x.size} samples, too few for {embedding_dim} delay coordinates at lag "
            f"{lag} (need at least {span + 16})."
        )
    idx = np.arange(span, x.size)[-max_points:]
    points = np.stack([x[idx - k * lag] for k in range(embedding_dim)], axis=1)
    n = points.shape[0]
    tree = cKDTree(points)
    if radius is None:
        probe = points[np.unique(np.linspace(0, n - 1, min(200, n)).astype(np.int64))]
        k = max(2, int(0.05 * n))
        dist, _ = tree.query(probe, k=k)
        radius = float(np.median(dist[:, -1]))
    radius = check_positive(radius, name="radius")
    neighbours = tree.query_ball_point(points, r=radius, return_sorted=True)
    groups: dict[tuple[int, ...], list[int]] = {}
    for i, nb in enumerate(neighbours):
        groups.setdefault(tuple(nb), []).append(i)
    twins = [None] * n
    for members in groups.values():
        arr = np.array(members, dtype=np.int64)
        for i in members:
            twins[i] = arr
    out = np.empty((n_surrogates, n))
    for s in range(n_surrogates):
        i = int(gen.integers(n - 1))
        for step in range(n):
            out[s, step] = points[i, 0]
            choices = twins[i]
            choices = choices[choices < n - 1]  # a successor must exist
            j = (
                int(choices[gen.integers(choices.size)])
                if choices.size
                else int(gen.integers(n - 1))
            )
            i = j + 1
    return out


def _crossing_error(
    x: np.ndarray,
    cuts: np.ndarray,
    *,
    embedding_dim: int,
    lag: int,
    horizon: int,
    theiler_window: int,
    n_neighbors: int,
    n_reference: int,
) -> float:
    """Normalised error of a locally constant forecast over the points whose forecast
    crosses a cycle boundary (``cuts`` relative to ``x``)."""
    n = x.size
    first = (embedding_dim - 1) * lag
    last = n - 1 - horizon
    idx = np.arange(first, last + 1)
    points = np.stack([x[idx - k * lag] for k in range(embedding_dim)], axis=1)
    # reference points: a cut lies in (i, i + horizon]
    after = np.searchsorted(cuts, idx, side="right")
    crosses = (after < cuts.size) & (cuts[np.minimum(after, cuts.size - 1)] <= idx + horizon)
    ref = np.flatnonzero(crosses)
    if ref.size > n_reference:
        ref = ref[np.unique(np.linspace(0, ref.size - 1, n_reference).astype(np.int64))]
    tree = cKDTree(points)
    k = min(n_neighbors + 2 * theiler_window + 1, idx.size)
    _, cand = tree.query(points[ref], k=k)
    admissible = np.abs(cand - ref[:, None]) > theiler_window
    keep = admissible & (np.cumsum(admissible, axis=1) <= n_neighbors)
    count = np.maximum(keep.sum(axis=1), 1)
    forecast = np.sum(np.where(keep, x[idx[cand] + horizon], 0.0), axis=1) / count
    err = forecast - x[idx[ref] + horizon]
    spread = float(np.std(x))
    return float(np.sqrt(np.mean(err**2)) / spread) if spread > 0.0 else 0.0


def _whole_samples_per_cycle(x: np.ndarray, spc: float) -> tuple[np.ndarray, float]:
    """``x`` resampled (cubic spline) to a whole number of samples per cycle, and the ratio
    of the new sampling rate to the old.

    With a fractional number of samples per cycle the cuts fall up to half a sample off
    the common phase, and joining two cycles in a surrogate slips the phase by up to one
    sample: a jump that white noise of a few per cent would not make, and that the data
    are spared.
    """
    whole = round(spc)
    if abs(spc - whole) <= 1e-9 * spc:
        return x, 1.0
    scale = whole / spc
    n_new = int(np.floor((x.size - 1) * scale)) + 1
    return CubicSpline(np.arange(x.size), x)(np.arange(n_new) / scale), scale


def cycle_spread(
    x: Any, period: float, *, dt: float = 1.0, noise: str = "stationary", max_noise: float = 0.3
) -> float:
    r"""RMS cycle-to-cycle variation beyond measurement noise, over the standard deviation.

    With :math:`r_t = x_t - \bar x(\phi_t)` the departure of the series from its mean cycle
    (the average over whole cycles at the same phase :math:`\phi`), white measurement noise
    contributes nothing to the lag-one covariance :math:`C_1 = \langle r_t r_{t+1} \rangle`,
    while any variation that is smooth over one sample — a chaotic wandering about the
    orbit, a slow transient, integration jitter — contributes its variance. The result is
    :math:`\sqrt{\max(C_1 - 2 \langle r^2 \rangle / \sqrt N, 0)} / \sigma_x` (less two
    standard errors of :math:`C_1` for white :math:`r`, and the share of the noise the mean
    cycle carries): 0 for a periodic orbit plus white noise of any level, the relative size
    of the wandering otherwise. It reads the series at its own sampling (fast events such as
    impacts are lost when it is thinned) and never interpolates it (that would make white
    noise smooth): with a fractional number of samples per cycle the mean cycle is averaged
    in phase bins and interpolated instead.

    Coloured (linear, e.g. AR(1)) measurement noise is smooth over one sample too, so with
    ``noise="stationary"`` (the default) the spread is the smallest of that reading and
    two that hold for any stationary additive noise, white or coloured. Such noise
    has the same variance at every phase of the cycle, while a deviation the dynamics
    produce (a chaotic wandering, a transient) is larger at some phases than at others.
    The second reading is :math:`\sqrt{\max(\bar v - v_0, 0)} / \sigma_x`, with
    :math:`v_j` the mean of :math:`r^2` in each of ten phase bins, :math:`\bar v` their
    mean and :math:`v_0 = \min_j (v_j + 2 s_j)` the noise variance at most (:math:`s_j`
    the standard error of :math:`v_j` over the cycles): 0 for a periodic orbit plus
    stationary noise of any colour and level, the phase-dependent part of the departure
    otherwise. A departure whose variance does not depend on the phase (a second frequency,
    a slow drift) reads small here; the cycle-shuffled test (:func:`cycle_surrogate_test`)
    is the one that sees it carried over from cycle to cycle. A third reading discounts
    the colour of stationary noise from the lag-one covariance itself: such noise has the
    same lag-one covariance at every phase, so the departure's lag-one covariance in its
    quietest phase bin (smallest variance), plus two standard errors, bounds the noise's;
    the lag-one reading less that bound reads 0 for a periodic orbit plus AR(1) noise even
    where the orbit's own departure (the ringing after an impact) makes the second reading
    large. The spread is the smallest of the three. Noise is discounted only up to
    ``max_noise``: a departure whose RMS exceeds that fraction of the standard deviation
    is not all measurement noise, and the spread is then the larger of the two readings.

    Parameters
    ----------
    x
        The series (1-D, at least ``MIN_CYCLES`` (8) cycles).
    period
        Cycle length in the units of ``dt``.
    dt
        Sampling interval.
    noise
        ``"stationary"`` (default): the noise may be white or coloured;
        ``"white"``: only white noise is discounted (the lag-one reading alone).
    max_noise
        Largest RMS departure from the mean cycle, relative to the standard deviation,
        that ``noise="stationary"`` may attribute to measurement noise (the default is
        ``VerdictRule.max_noise_allowance``).

    Returns
    -------
    float
        The cycle-to-cycle spread measurement noise does not explain, relative to the
        standard deviation of ``x``.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import cycle_spread
    >>> t = np.arange(8000) * 0.05
    >>> x = np.sin(t) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> cycle_spread(x, 2 * np.pi, dt=0.05)
    0.0
    """
    x = as_series(x, name="x", min_length=16)
    spc = _samples_per_cycle(period, dt)
    n = int(x.size // spc)
    if n < MIN_CYCLES:
        raise ValueError(
            f"x spans {n} whole cycles of period {period:g}; the cycle spread needs at least "
            f"{MIN_CYCLES}."
        )
    if noise not in ("stationary", "white"):
        raise ValueError(f'noise must be "stationary" or "white"; got {noise!r}.')
    max_noise = check_positive(max_noise, name="max_noise")
    r = x - _mean_cycle_at_samples(x, spc)
    c1 = float(np.mean(r[:-1] * r[1:]))
    power = float(np.mean(r * r))
    # the mean cycle carries 1/n of the noise variance, smooth over neighbouring samples
    # once interpolated: remove that share of the white part; and C1 of white noise
    # scatters about 0 with a standard error of about power / sqrt(N): keep only what
    # exceeds two standard errors
    c1 -= max(power - c1, 0.0) / n + 2.0 * power / np.sqrt(r.size)
    sigma = float(np.std(x))
    white = float(np.sqrt(max(c1, 0.0)) / sigma)
    if noise == "white":
        return white
    phased = _phase_dependent_spread(r, spc) / sigma
    if np.sqrt(power) > max_noise * sigma:
        return max(white, phased)  # too large to be measurement noise
    # stationary noise has the same lag-one covariance at every phase: the quietest phase
    # bounds it, whatever its colour
    coloured = float(np.sqrt(max(c1 - _quiet_lag_one(r, spc), 0.0)) / sigma)
    return min(white, phased, coloured)  # each reading is a valid one for its kind of noise


PHASE_BINS = 10  # phase bins per cycle of the stationarity reading (fewer for short cycles)


def phase_spread(x: np.ndarray, period: float, *, dt: float = 1.0) -> float:
    """The phase-dependent part of the departure of ``x`` from its mean cycle, over the
    standard deviation: the second reading of :func:`cycle_spread` alone (0 for a periodic
    orbit plus stationary noise of any colour and level). Where it exceeds the cluster
    tolerance while the lag-one reading does not, the departure is neither stationary
    measurement noise nor smooth: a stable orbit jolted afresh every cycle looks like
    that, and so does chaos that lives in the timing of impacts."""
    x = as_series(x, name="x", min_length=16)
    spc = _samples_per_cycle(period, dt)
    if int(x.size // spc) < MIN_CYCLES:
        raise ValueError(
            f"x spans {int(x.size // spc)} whole cycles of period {period:g}; the phase "
            f"spread needs at least {MIN_CYCLES}."
        )
    sigma = float(np.std(x))
    if sigma == 0.0:
        return 0.0
    return _phase_dependent_spread(x - _mean_cycle_at_samples(x, spc), spc) / sigma


def _phase_binned(r: np.ndarray, spc: float, lag: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean of :math:`r_t r_{t+lag}` in each phase bin over whole cycles, and its
    standard error from the scatter over the cycles (independent replicates under the
    null: the noise does not carry over a cycle)."""
    n = int(r.size // spc)
    bins = min(PHASE_BINS, int(np.floor(spc)))
    index = np.arange(min(int(n * spc), r.size - lag))  # whole cycles only
    cycle = np.minimum((index / spc).astype(np.int64), n - 1)
    phase = np.minimum((((index / spc) % 1.0) * bins).astype(np.int64), bins - 1)
    key = cycle * bins + phase
    count = np.bincount(key, minlength=n * bins).reshape(n, bins)
    product = r[index] * r[index + lag]
    sums = np.bincount(key, weights=product, minlength=n * bins).reshape(n, bins)
    per_cycle = sums / np.maximum(count, 1)  # (cycle, bin): mean product in the bin
    return per_cycle.mean(axis=0), per_cycle.std(axis=0, ddof=1) / np.sqrt(n)


def _phase_dependent_spread(r: np.ndarray, spc: float) -> float:
    """RMS of the part of the departure ``r`` from the mean cycle whose variance depends on
    the phase: the mean over phase bins of the variance above the smallest one, which
    bounds the variance of any stationary noise (less two standard errors over the cycles,
    so that the scatter of noise alone reads 0)."""
    v, se = _phase_binned(r, spc, 0)
    floor = float(np.min(v + 2.0 * se))
    return float(np.sqrt(max(float(np.mean(v)) - floor, 0.0)))


def _quiet_lag_one(r: np.ndarray, spc: float) -> float:
    """The lag-one covariance of the departure ``r`` in its quietest phase bin (the one
    whose variance, plus two standard errors, is smallest), plus two standard errors.

    Stationary measurement noise, white or coloured, has the same variance and lag-one
    covariance at every phase; in the quietest bin the departure is mostly that noise, so
    its lag-one covariance there bounds the noise's (the noise's colour, estimated from
    the data). A smooth dynamic wandering in that bin raises the bound; a spiky one
    (negative lag-one covariance) lowers it, which only keeps more of the spread."""
    v, sv = _phase_binned(r, spc, 0)
    c, sc = _phase_binned(r, spc, 1)
    quiet = int(np.argmin(v + 2.0 * sv))
    return float(c[quiet] + 2.0 * sc[quiet])


def _mean_cycle_at_samples(x: np.ndarray, spc: float) -> np.ndarray:
    """The mean cycle (average of the samples of every cycle at the same phase) at each
    sample's phase.

    With a whole number of samples per cycle it is the plain average over cycles; with a
    fractional one the samples are averaged in ``floor(spc)`` phase bins and the bin means
    interpolated linearly (periodically) at each sample's phase. The series itself is never
    interpolated: that would make white noise smooth over neighbouring samples.
    """
    whole = round(spc)
    if abs(spc - whole) <= 1e-9 * spc:
        n = x.size // whole
        template = x[: n * whole].reshape(n, whole).mean(axis=0)
        return np.resize(template, x.size)
    bins = int(np.floor(spc))
    phase = (np.arange(x.size) / spc) % 1.0
    index = np.minimum((phase * bins).astype(np.int64), bins - 1)
    count = np.bincount(index, minlength=bins)
    sums = np.bincount(index, weights=x, minlength=bins)
    centre = np.bincount(index, weights=phase, minlength=bins)
    filled = count > 0
    mean, centre = sums[filled] / count[filled], centre[filled] / count[filled]
    return np.interp(phase, centre, mean, period=1.0)


@dataclass(frozen=True, kw_only=True)
class CycleForecast:
    """The locally constant forecast of :func:`cycle_surrogate_test`.

    Attributes
    ----------
    embedding_dim, lag
        Delay embedding of the forecast (``lag`` in samples), each at least 1.
    horizon
        Forecast horizon in samples (None: ``lag``), at least 1 and shorter than one cycle.
    theiler_window
        Temporal exclusion for neighbours, samples (None: ``embedding_dim * lag``), at
        least 0; less than one cycle so that the same phase of other cycles is found.
    n_neighbors
        Neighbours averaged by the forecast, at least 1.
    n_reference
        Largest number of reference points (evenly spaced among those that cross a
        boundary), at least 10.

    Examples
    --------
    >>> from chaoskit.verdict import CycleForecast
    >>> CycleForecast(lag=30).horizon is None
    True
    """

    embedding_dim: int = 3
    lag: int = 1
    horizon: int | None = None
    theiler_window: int | None = None
    n_neighbors: int = 5
    n_reference: int = 1000

    def __post_init__(self) -> None:
        checked = {
            "embedding_dim": check_int(self.embedding_dim, name="embedding_dim", minimum=1),
            "lag": check_int(self.lag, name="lag", minimum=1),
            "n_neighbors": check_int(self.n_neighbors, name="n_neighbors", minimum=1),
            "n_reference": check_int(self.n_reference, name="n_reference", minimum=10),
        }
        if self.horizon is not None:
            checked["horizon"] = check_int(self.horizon, name="horizon", minimum=1)
        if self.theiler_window is not None:
            checked["theiler_window"] = check_int(
                self.theiler_window, name="theiler_window", minimum=0
            )
        for key, value in checked.items():
            object.__setattr__(self, key, value)  # frozen: store the validated integers


def cycle_surrogate_test(
    x: Any,
    period: float,
    *,
    dt: float = 1.0,
    forecast: CycleForecast | None = None,
    n_surrogates: int = 19,
    alpha: float = 0.05,
    min_effect: float = 0.1,
    min_gain: float = 0.05,
    rng: Any = None,
) -> SurrogateResult:
    r"""Test the null hypothesis "a periodic orbit plus noise" with cycle-shuffled surrogates.

    The series is cut into whole cycles (:func:`cycle_boundaries`) and compared with
    ``n_surrogates`` cycle-shuffled surrogates (:func:`cycle_shuffled_surrogates`). The
    statistic is the normalised error of a locally constant forecast
    (``prediction_error``: mean future of the ``n_neighbors`` nearest delay
    vectors outside the Theiler window, RMS error over the standard deviation of the series)
    evaluated only at the points whose forecast crosses a cycle boundary,
    :math:`c_n \in (i, i + h]`. Within a cycle data and surrogates are identical; across a
    boundary the data continue deterministically where the dynamics carry a deviation from
    one cycle into the next, while a surrogate continues with a random other cycle. A
    periodic orbit with noise that is independent from cycle to cycle is forecast equally
    badly in both; chaotic driven motion is forecast better in the data. A series sampled
    a fractional number of times per cycle is first resampled (cubic spline) to the nearest
    whole number, so that every cut falls at the same phase. The test is
    one-sided and rank-based; rejection needs ``p_value <= alpha`` and ``effect >=
    min_effect`` as in :func:`~chaoskit.surrogate_test`, and a gain of at least
    ``min_gain``.

    Parameters
    ----------
    x
        The series.
    period
        Cycle length in the units of ``dt``: the drive period, or :math:`k` drive periods
        for a period-:math:`k` orbit.
    dt
        Sampling interval.
    forecast
        The forecast's embedding, horizon, Theiler window and neighbours
        (:class:`CycleForecast`; None: its defaults, three delay coordinates of lag 1).
    n_surrogates
        At least :math:`1/\alpha - 1`.
    alpha, min_effect
        Significance level and smallest relative gain over the median surrogate.
    min_gain
        Smallest absolute gain, median surrogate statistic minus the data's, in units of
        the standard deviation of ``x``: cycle-to-cycle determinism that improves the
        forecast by less is too small to matter (:func:`~chaoskit.classify` uses
        ``VerdictRule.cluster_tol``, the radius within which a section's points count as
        one point of a periodic orbit).
    rng
        Seed or :class:`numpy.random.Generator`.

    Returns
    -------
    SurrogateResult
        With ``null = "noisy periodic orbit"``; ``statistic`` and ``surrogate_statistics``
        are normalised errors (1 = no better than the mean).

    References
    ----------
    J. Theiler, Phys. Lett. A 196, 335 (1995); M. Small and C. K. Tse, Physica D 164, 187
    (2002); Kantz & Schreiber, *Nonlinear Time Series Analysis*, 2nd ed. (Cambridge,
    2004), §4.2 and §7.1.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import cycle_surrogate_test
    >>> from chaoskit.verdict import CycleForecast
    >>> t = np.arange(4000) * 0.05
    >>> x = np.sin(t) + 0.05 * np.random.default_rng(0).standard_normal(t.size)
    >>> cycle_surrogate_test(x, 2 * np.pi, dt=0.05, forecast=CycleForecast(lag=30), rng=0).rejected
    False
    """
    stage("cycle surrogates")
    x = as_series(x, name="x", min_length=16)
    spc = _samples_per_cycle(period, dt)
    x, scale = _whole_samples_per_cycle(x, spc)
    spc = float(round(spc))
    cuts = cycle_boundaries(x, spc)
    forecast = CycleForecast() if forecast is None else forecast
    if not isinstance(forecast, CycleForecast):
        raise TypeError(f"forecast must be a CycleForecast or None; got {type(forecast).__name__}.")
    embedding_dim = forecast.embedding_dim
    lag = max(1, round(forecast.lag * scale))
    horizon = lag if forecast.horizon is None else forecast.horizon
    horizon = max(1, round(horizon * scale))
    if horizon >= spc:
        raise ValueError(
            f"horizon must be shorter than one cycle ({spc:.4g} samples); got {horizon}."
        )
    theiler_window = forecast.theiler_window
    if theiler_window is None:
        theiler_window = embedding_dim * lag
    theiler_window = round(theiler_window * scale)
    if theiler_window >= spc:
        theiler_window = int(spc) // 2  # the same phase of the next cycle must stay admissible
    alpha = check_probability(alpha, name="alpha")
    n_surrogates = check_surrogates(n_surrogates, alpha)
    min_effect = float(min_effect)
    if not 0.0 <= min_effect < 1.0:
        raise ValueError(f"min_effect must be in [0, 1); got {min_effect!r}.")
    min_gain = float(min_gain)
    if not 0.0 <= min_gain < 1.0:
        raise ValueError(f"min_gain must be in [0, 1); got {min_gain!r}.")
    gen = as_generator(rng)
    x = x[cuts[0] : cuts[-1]]
    lengths = np.diff(cuts)
    options = {
        "embedding_dim": embedding_dim,
        "lag": lag,
        "horizon": horizon,
        "theiler_window": theiler_window,
        "n_neighbors": forecast.n_neighbors,
        "n_reference": forecast.n_reference,
    }
    inner = (cuts - cuts[0])[1:-1]
    stat = _crossing_error(x, inner, **options)
    starts = (cuts - cuts[0])[:-1]
    stats = np.empty(n_surrogates)
    for s in range(n_surrogates):
        order = gen.permutation(lengths.size)
        surrogate = np.concatenate([x[starts[i] : starts[i] + lengths[i]] for i in order])
        stats[s] = _crossing_error(surrogate, _cycle_cuts_of(order, lengths)[1:-1], **options)
    p_value = (1.0 + np.count_nonzero(stats <= stat)) / (n_surrogates + 1.0)
    median = float(np.median(stats))
    effect = 1.0 - stat / median if median > 0 else 0.0
    return SurrogateResult(
        statistic=float(stat),
        surrogate_statistics=stats,
        p_value=float(p_value),
        effect=float(effect),
        rejected=bool(p_value <= alpha and effect >= min_effect and median - stat >= min_gain),
        alpha=alpha,
        min_effect=min_effect,
        n_surrogates=n_surrogates,
        embedding_dim=embedding_dim,
        lag=lag,
        horizon=horizon,
        theiler_window=theiler_window,
        null="noisy periodic orbit",
    )


@dataclass(frozen=True)
class OrbitResidual:
    """The departure of a driven series from its phase-locked mean cycle, read as
    measurement noise: the alternative a noise-like verdict must beat.

    ``fraction`` is the share of the variance the mean cycle carries, ``level`` the RMS of
    the departure over the standard deviation, ``lag_one`` its lag-one autocorrelation at
    the series' own sampling (0 for white noise, near 1 for noise correlated over many
    samples), ``cycles`` the drive periods per cycle and ``test`` the IAAFT surrogate test
    of the departure (does it reject a linear Gaussian process?)."""

    fraction: float
    level: float
    lag_one: float
    cycles: int
    test: SurrogateResult


def orbit_residual(
    x: np.ndarray,
    *,
    dt: float,
    period: float,
    cycles: int,
    lag: int,
    embedding_dim: int,
    n_surrogates: int,
    max_samples: int,
    alpha: float,
    min_effect: float,
    gen: np.random.Generator,
) -> OrbitResidual:
    """The departure of ``x`` from its mean cycle over ``period`` (``cycles`` drive
    periods) and the IAAFT surrogate test of that departure, thinned and embedded as the
    test of the series itself."""
    residual = x - _mean_cycle_at_samples(x, period / dt)
    sigma = float(np.std(x))
    power = float(np.mean(residual * residual))
    lag_one = float(np.mean(residual[:-1] * residual[1:]) / power) if power > 0 else 0.0
    step = max(1, lag // 4)
    test = surrogate_test(
        residual[::step][-max_samples:],
        embedding_dim=embedding_dim,
        lag=max(1, round(lag / step)),
        n_surrogates=n_surrogates,
        alpha=alpha,
        min_effect=min_effect,
        rng=gen,
    )
    return OrbitResidual(
        fraction=1.0 - power / sigma**2 if sigma > 0 else 0.0,
        level=float(np.sqrt(power)) / sigma if sigma > 0 else 0.0,
        lag_one=lag_one,
        cycles=int(cycles),
        test=test,
    )
