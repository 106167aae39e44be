"""The pipeline of :func:`chaoskit.classify`: read the series, gather evidence, apply the rule."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import (
    as_series,
    check_int,
    check_positive,
)
from ..embedding import estimate_delay, estimate_embedding_dim
from ..lyapunov import lyapunov_kantz, lyapunov_rosenstein, lyapunov_wolf
from ._combine import RuleEvidence, combine
from ._cycles import cycle_spread, orbit_residual, phase_spread
from ._evidence import (
    any_rejected,
    clearly_positive,
    confirm_low_dim,
    count_cycles,
    cycle_test,
    describe_error,
    line_period,
    needs_referee,
    section_points,
    surrogate_evidence,
)
from ._inputs import SeriesInput, is_equilibrium, noise_level, read_input, scaled_to_unit_peak
from ._line_spectrum import line_spectrum
from ._result import Verdict
from ._rng import as_generator
from ._rule import DIMENSION_POINTS, MIN_SAMPLES, VerdictRule
from ._section_structure import section_structure
from ._surrogates import check_surrogates
from ._zero_one import zero_one_test

__all__ = ["classify"]


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
      and what varies from cycle to cycle beyond stationary noise (:func:`cycle_spread`) is at
      most ``rule.cluster_tol`` of the standard deviation: a periodic orbit plus noise,
      whatever the noise does to the spectrum and the exponents; and *periodic* when the
      mean cycle carries at least ``1 - rule.max_residual`` of the variance and the
      departure from it, at most ``rule.max_noise_allowance`` of the standard deviation, is
      consistent with a linear Gaussian process (its IAAFT surrogate test does not
      reject) and within ``rule.cluster_tol`` beyond stationary noise: a periodic orbit
      plus coloured measurement noise, its level and colour (lag-one autocorrelation) in
      the reason;
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
      surrogates alike); for a forced series only if the mean cycle carries less than
      ``1 - rule.max_residual`` of the variance: else the label must beat a periodic orbit
      plus coloured noise, and is *periodic* when the departure from the mean cycle is as
      above (the spread then votes against it when it exceeds ``rule.cluster_tol``);
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
      white noise and exceeds ``rule.cluster_tol`` of the standard deviation; for it, the
      IAAFT surrogate test of the departure from a mean cycle carrying at least
      ``1 - rule.max_residual`` of the variance stands in for the test of the series (the
      mean cycle dilutes the departure where the chaos lives), and so does the test in
      three delay coordinates (or one sample ahead) when it rejects at ``rule.alpha`` and,
      repeated with twice as many surrogates, at ``rule.alpha / 2``;
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
    Where the mean cycle carries most of the variance, the IAAFT test of the departure
    from it votes too (``residual``): for *chaotic* when it rejects, for a periodic orbit
    plus coloured noise when it does not; the confirmed test in three delay coordinates
    votes for *chaotic* when it stands in for the surrogate test (``low_dim``). A
    periodic label of a forced series also
    counts the departure's phase-dependent part (``Verdict.phase_spread``, the stationarity
    reading of :func:`cycle_spread` alone): above ``rule.cluster_tol`` it opposes (``phase``),
    since a departure confined to some phases is not stationary measurement noise and shows
    no stable orbit (a stable orbit jolted afresh every cycle and chaos in the timing of
    impacts both look like that).

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
    inp, drive_period, exponent = _read_series(data, variable, dt, drive_period, phase_variable)
    base: dict[str, Any] = {"variable": inp.variable, "kind": inp.kind, "dt": inp.dt, "rule": rule}
    if is_equilibrium(inp.x, rule.equilibrium_rtol):
        return Verdict(
            label="equilibrium", period=None, confidence=1.0,
            reason="the series is constant", votes={}, errors={},
            n_samples=int(inp.x.size), **base,
        )  # fmt: skip
    x = as_series(inp.x, name=inp.variable or "x", min_length=MIN_SAMPLES)
    errors: dict[str, str] = {}
    delay, dimension, lag, embedding_dim = _embedding(x, lag, embedding_dim)
    noise = noise_level(x) if inp.kind != "map" else float("nan")
    # the steps run in this order, each drawing from the same generator ``gen``: the 0-1
    # test, the surrogate tests, the cycle test, the departure's test, the confirmation
    section, structure, time_scale = _section(
        inp, x, lag, embedding_dim, drive_period, noise, rule, errors
    )
    lyap, positives = _exponents(x, embedding_dim, lag, inp.dt, time_scale, rule, errors)
    zero_one = _zero_one(x, inp, lag, gen, errors)
    surrogates, low_dim, one_step = surrogate_evidence(
        x,
        lag=lag,
        embedding_dim=embedding_dim,
        rosenstein=lyap.get("rosenstein"),
        n_surrogates=n_surrogates,
        max_samples=surrogate_max_samples,
        rule=rule,
        gen=gen,
        errors=errors,
    )
    lines = _lines(x, inp, drive_period, time_scale, rule, errors)
    n_cycles, unit = count_cycles(inp, x.size, time_scale)
    cycles, (spread, phased), residual = _cycle_null(
        x, inp, (lag, embedding_dim), structure, lines, time_scale, rule,
        (n_surrogates, surrogate_max_samples), gen, errors,
    )  # fmt: skip
    confirmed = None
    if residual is not None and residual.fraction >= 1.0 - rule.max_residual:
        # drawn last: every other result keeps its random numbers
        confirmed = confirm_low_dim(
            x, lag=lag, tests=(low_dim, one_step), n_surrogates=n_surrogates,
            max_samples=surrogate_max_samples, rule=rule, gen=gen, errors=errors,
        )  # fmt: skip
    kantz = None
    kantz_positive = None
    if needs_referee(
        positives, structure, lines, surrogates, n_cycles >= rule.min_cycles,
        confirmed=confirmed is not None and confirmed.rejected,
    ):  # fmt: skip
        kantz, kantz_positive = _referee(x, embedding_dim, lag, inp.dt, time_scale, rule, errors)
    evidence = RuleEvidence(
        structure=structure,
        rosenstein_positive=positives["rosenstein"],
        wolf_positive=positives["wolf"],
        zero_one_k=None if zero_one is None else zero_one.k,
        surrogates_rejected=None if surrogates is None else surrogates.rejected,
        lines=None if lines is None else lines.kind,
        lines_period=None if lines is None else line_period(lines, inp, time_scale),
        lines_bases=0 if lines is None else int(lines.base_frequencies.size),
        n_cycles=n_cycles,
        cycle_unit=unit,
        low_dim_rejected=any_rejected(low_dim, one_step),
        low_dim_confirmed=None if confirmed is None else confirmed.rejected,
        kantz_positive=kantz_positive,
        cycles_rejected=None if cycles is None else cycles.rejected,
        driven=inp.kind == "forced",
        noise=noise,
        cycle_spread=spread,
        phase_spread=phased,
        orbit_residual=residual,
    )
    outcome = combine(evidence, rule)
    reason = outcome.reason
    return Verdict(
        label=outcome.label,
        period=outcome.period,
        confidence=outcome.confidence,
        reason=reason if exponent == 0 else f"{reason} (analysed as x * 2**{-exponent})",
        votes=outcome.votes,
        errors=errors,
        n_samples=int(x.size),
        needs=outcome.needs,
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
        surrogates_confirmed=confirmed,
        cycle_spread=spread,
        phase_spread=phased,
        **base,
    )


# --- the steps of the pipeline, in the order classify calls them ---------------------------


def _read_series(
    data: Any,
    variable: str | None,
    dt: float | None,
    drive_period: float | None,
    phase_variable: str | None,
) -> tuple[SeriesInput, float | None, int]:
    """The series (a forced one when a drive is given), the checked drive period and the
    power of two the series was scaled by."""
    inp = read_input(data, variable=variable, dt=dt, phase_variable=phase_variable)
    if drive_period is not None or inp.angle is not None:
        if inp.kind == "map":
            raise ValueError("drive_period needs a continuous-time series (a 'time' axis or dt).")
        if drive_period is not None and inp.angle is not None:
            raise ValueError("give drive_period or phase_variable, not both.")
        if drive_period is not None:
            drive_period = check_positive(drive_period, name="drive_period")
        inp = SeriesInput(inp.x, inp.t, inp.dt, "forced", inp.variable, inp.angle)
    inp, exponent = scaled_to_unit_peak(inp)
    return inp, drive_period, exponent


def _embedding(
    x: np.ndarray, lag: int | None, embedding_dim: int | None
) -> tuple[Any, Any, int, int]:
    """The delay and the embedding dimension: estimated (with their estimates) or given."""
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
    return delay, dimension, lag, embedding_dim


def _section(
    inp: SeriesInput,
    x: np.ndarray,
    lag: int,
    embedding_dim: int,
    drive_period: float | None,
    noise: float,
    rule: VerdictRule,
    errors: dict[str, str],
) -> tuple[Any, Any, float]:
    """The section, its structure and the characteristic time T (the section's, else the
    first guess); a section that cannot be built is recorded in ``errors``."""
    structure = section = None
    # T of the growth test until the section gives a better one: a delay is about a quarter
    # of the mean period of a flow.
    time_scale = 1.0 if inp.kind == "map" else (drive_period or 4.0 * lag * inp.dt)
    try:
        n_coords = 3 if inp.kind == "flow" else max(2, embedding_dim)
        section, points, time_scale = section_points(inp, x, lag, n_coords, drive_period, noise)
        tol = rule.cluster_tol
        if inp.kind != "map":
            tol = max(tol, min(rule.noise_factor * noise, rule.max_noise_allowance))
        structure = section_structure(
            points, scale=float(np.std(x)), cluster_tol=tol, max_clusters=rule.max_period
        )
    except ValueError as exc:
        errors["section"] = str(exc)
    return section, structure, time_scale


def _exponents(
    x: np.ndarray,
    embedding_dim: int,
    lag: int,
    dt: float,
    time_scale: float,
    rule: VerdictRule,
    errors: dict[str, str],
) -> tuple[dict[str, Any], dict[str, bool]]:
    """Rosenstein's and Wolf's exponents (None when an estimator fails, its reason in
    ``errors``) and whether each is clearly positive."""
    lyap: dict[str, Any] = {}
    for name, func in (("rosenstein", lyapunov_rosenstein), ("wolf", lyapunov_wolf)):
        try:
            lyap[name] = func(x, embedding_dim=embedding_dim, lag=lag, dt=dt)
        except Exception as exc:  # failure is data: the verdict records it and goes on
            lyap[name] = None
            errors[name] = describe_error(exc)
    positives = {name: clearly_positive(res, time_scale, rule) for name, res in lyap.items()}
    return lyap, positives


def _zero_one(
    x: np.ndarray, inp: SeriesInput, lag: int, gen: np.random.Generator, errors: dict[str, str]
) -> Any:
    """The 0-1 test (flows subsampled every delay), or None with the reason in ``errors``."""
    try:
        phi = x if inp.kind == "map" else x[::lag]
        return zero_one_test(phi, rng=gen)
    except ValueError as exc:
        errors["zero_one"] = str(exc)
    return None


def _lines(
    x: np.ndarray,
    inp: SeriesInput,
    drive_period: float | None,
    time_scale: float,
    rule: VerdictRule,
    errors: dict[str, str],
) -> Any:
    """The line spectrum, or None with the reason in ``errors``."""
    try:
        forced_period = None
        if inp.kind == "forced":
            forced_period = drive_period or time_scale
        return line_spectrum(
            x,
            dt=inp.dt,
            drive_period=forced_period,
            max_period=rule.max_period,
            max_residual=rule.max_residual,
            fold=inp.kind != "forced",
        )
    except (ValueError, np.linalg.LinAlgError) as exc:
        errors["lines"] = describe_error(exc)
    return None


def _cycle_null(
    x: np.ndarray,
    inp: SeriesInput,
    embedding: tuple[int, int],
    structure: Any,
    lines: Any,
    time_scale: float,
    rule: VerdictRule,
    surrogates: tuple[int, int],
    gen: np.random.Generator,
    errors: dict[str, str],
) -> tuple[Any, tuple[float, float], Any]:
    """For a forced series, the null of a noisy periodic orbit: the cycle-shuffled
    surrogate test, the correlated departure from the mean cycle with its phase-dependent
    part, and that departure read as measurement noise (None, (NaN, NaN) and None
    otherwise, or when they cannot be computed). ``embedding`` is (lag, dimension),
    ``surrogates`` (number, most samples)."""
    cycles = residual = None
    spread = phased = float("nan")
    lag, embedding_dim = embedding
    n_surrogates, max_samples = surrogates
    if inp.kind == "forced":
        try:
            # cycles of k drive periods for a section of k clusters or a series that repeats
            # after k: a period-k orbit keeps its order
            k = structure.n_clusters if structure and structure.kind == "clusters" else 1
            if lines is not None and lines.kind == "periodic" and k == 1:
                k = line_period(lines, inp, time_scale) or 1
            cycles = cycle_test(x, inp.dt, lag, k * time_scale, rule, n_surrogates, gen)
            spread = cycle_spread(x, k * time_scale, dt=inp.dt, max_noise=rule.max_noise_allowance)
            phased = phase_spread(x, k * time_scale, dt=inp.dt)
        except ValueError as exc:
            errors["cycles"] = str(exc)
            return cycles, (spread, phased), residual
        try:
            # drawn after the cycle test: every other result keeps its random numbers
            residual = orbit_residual(
                x, dt=inp.dt, period=k * time_scale, cycles=k, lag=lag,
                embedding_dim=embedding_dim, n_surrogates=n_surrogates,
                max_samples=max_samples, alpha=rule.alpha,
                min_effect=rule.min_effect, gen=gen,
            )  # fmt: skip
        except ValueError as exc:
            errors["orbit_residual"] = str(exc)
    return cycles, (spread, phased), residual


def _referee(
    x: np.ndarray,
    embedding_dim: int,
    lag: int,
    dt: float,
    time_scale: float,
    rule: VerdictRule,
    errors: dict[str, str],
) -> tuple[Any, bool | None]:
    """Kantz's exponent and whether it is clearly positive (None when it cannot be said)."""
    kantz = None
    try:
        kantz = lyapunov_kantz(x, embedding_dim=embedding_dim, lag=lag, dt=dt)
        return kantz, clearly_positive(kantz, time_scale, rule)
    except Exception as exc:  # failure is data, as for the other two
        errors["kantz"] = describe_error(exc)
    return kantz, None
