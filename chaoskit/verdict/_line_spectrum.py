"""Regular series first: exact recurrence and line spectra.

A periodic series repeats after some lag; a quasi-periodic one is a sum of sinusoids whose
frequencies are integer combinations of two or three base frequencies. Both are recognised
here directly — by folding the series at a lag of k samples, and by extracting refined
spectral lines until what is left is white noise — before any exponent is estimated.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy.linalg import solve_triangular
from scipy.optimize import minimize_scalar
from scipy.signal import find_peaks
from scipy.stats import chi2

from ._line_kernels import householder_qr

__all__ = ["LineSpectrum", "line_spectrum"]

LineKind = Literal["periodic", "quasi-periodic", "broadband", "unresolved"]

#: A residual below this fraction of the variance is zero to the integrator's accuracy.
EXACT = 1e-8
#: Ljung–Box lags and the p-value above which a residual counts as white.
WHITE_LAGS = 20
WHITE_P = 1e-3
#: Largest integer coefficient of a base frequency in a combination line (2 bases; 3 bases).
MAX_COEF = (12, 6)
#: Joint Gauss–Newton refinement only while samples × columns² stays below this.
GN_BUDGET = 2e7
#: The first lines get their amplitudes fitted jointly; later ones one at a time.
JOINT_LINES = 16
#: Lines that explain all but this fraction of the variance, with a residual that is not
#: white, are "unresolved": too many lines, or a weak continuous part — no decision.
UNRESOLVED = 1e-3


@dataclass(frozen=True, kw_only=True)
class LineSpectrum:
    """Outcome of :func:`line_spectrum`.

    Attributes
    ----------
    kind
        ``"periodic"`` (one fundamental), ``"quasi-periodic"`` (two or three incommensurate
        base frequencies), ``"broadband"`` (the series is not a few lines plus white
        noise) or ``"unresolved"`` (lines explain all but 0.1 % of the variance, yet what is
        left is not white: more lines than extracted, or a weak continuous part).
    method
        ``"recurrence"`` (folding at ``period_samples``), ``"drive recurrence"`` (folding
        at whole drive periods), ``"drive harmonics"`` (every harmonic of a subharmonic of
        the drive fitted at once) or ``"lines"``.
    frequencies, amplitudes
        The significant spectral lines (cycles per time unit; amplitude in the series'
        units), strongest first.
    base_frequencies
        The fundamental (periodic) or the independent base frequencies (quasi-periodic).
    fundamental_period
        1 / fundamental frequency (time units; NaN unless periodic).
    period_samples
        The lag k (samples) at which the series repeats, when folding found it, else None.
    maxima_per_period
        Local maxima of the fitted waveform in one fundamental period (periodic only).
    residual_fraction
        Variance of what the model leaves, over the series' variance.
    white_p
        Ljung–Box p-value of that residual (lags 1–20): large for white noise.
    n_cycles
        Cycles of the strongest line (or of the drive) in the series.
    """

    kind: LineKind
    method: str
    frequencies: np.ndarray = field(repr=False)
    amplitudes: np.ndarray = field(repr=False)
    base_frequencies: np.ndarray
    fundamental_period: float
    period_samples: int | None
    maxima_per_period: int | None
    residual_fraction: float
    white_p: float
    n_cycles: float


def ljung_box_p(r: np.ndarray, lags: int = WHITE_LAGS) -> float:
    """Ljung–Box p-value of the autocorrelations at lags 1…``lags`` (Ljung & Box 1978)."""
    n = r.size
    r = r - r.mean()
    var = float(np.dot(r, r))
    if n <= lags + 1 or var == 0.0:
        return 1.0
    k = np.arange(1, lags + 1)
    rho = np.array([np.dot(r[:-j], r[j:]) for j in k]) / var
    q = n * (n + 2.0) * float(np.sum(rho**2 / (n - k)))
    return float(chi2.sf(q, lags))


# ---------------------------------------------------------------- folding (recurrence)


def _fold(x0: np.ndarray, k: int) -> np.ndarray:
    """Residual of ``x0`` about its mean waveform of period ``k`` samples."""
    n = x0.size - x0.size % k
    template = x0[:n].reshape(-1, k).mean(axis=0)
    return x0 - np.resize(template, x0.size)


def _first_repeat(
    x0: np.ndarray, lags: range, max_residual: float
) -> tuple[int, float, float] | None:
    """The first lag whose folding residual is nothing (below ``EXACT`` of the variance) or
    white and at most ``max_residual`` of it: (lag, residual fraction, Ljung–Box p)."""
    var0 = float(np.var(x0))
    for lag in lags:
        r = _fold(x0, lag)
        frac = float(np.var(r)) / var0
        if frac <= EXACT:
            return lag, frac, 1.0
        if frac <= max_residual:
            p = ljung_box_p(r)
            if p >= WHITE_P:
                return lag, frac, p
    return None


def samples_per_drive_period(drive_period: float, dt: float, n: int) -> int | None:
    """The drive period in samples when it is a whole number to within 1 % of a sample over
    the record (so folding at it stays in phase to the end), else None."""
    p = drive_period / dt
    whole = round(p)
    if whole < 2 or abs(p - whole) * (n / p) > 0.01:
        return None
    return int(whole)


# ---------------------------------------------------------------- line extraction


def _dtft_power(r: np.ndarray, window: np.ndarray, f: float) -> float:
    n = np.arange(r.size)
    return float(np.abs(np.dot(r * window, np.exp(-2j * np.pi * f * n))) ** 2)


def _strongest_line(
    r: np.ndarray, window: np.ndarray, pad: int = 4, near: float | None = None
) -> float | None:
    """Frequency (cycles/sample) of the strongest line: zero-padded Hann spectrum, then the
    maximum of the windowed DTFT (Laskar's frequency analysis). With ``near``, only the
    maximum within half a bin of it is refined."""
    n = r.size
    half = 0.5 / (pad * n)
    if near is None:
        spec = np.abs(np.fft.rfft(r * window, n=pad * n))
        lo = 2 * pad  # leave out the DC lobe: below two cycles per record is a trend
        if spec.size <= lo + 2:
            return None
        i = lo + int(np.argmax(spec[lo:-1]))
        a, b, c = np.log(spec[i - 1 : i + 2] + 1e-300)
        denom = a - 2 * b + c
        shift = 0.5 * (a - c) / denom if denom < 0 else 0.0
        f = (i + shift) / (pad * n)
    else:
        f = near
    f = min(max(f, 0.0), 0.5)
    left, right = max(f - half, 0.0), min(f + half, 0.5)
    if right <= left:
        return f
    res = minimize_scalar(
        lambda g: -_dtft_power(r, window, g),
        bounds=(left, right),
        method="bounded",
        options={"xatol": 1e-7 / n},
    )
    return float(res.x)


def _line(f: float, n: int) -> np.ndarray:
    phase = 2 * np.pi * f * np.arange(n, dtype=np.float64)
    return np.column_stack([np.cos(phase), np.sin(phase)])


def _take_out(r: np.ndarray, f: float) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares amplitudes (cos, sin) of the line at f in r, and r without it (and
    without its mean)."""
    basis = np.column_stack([_line(f, r.size), np.ones(r.size)])
    coef = np.linalg.solve(basis.T @ basis, basis.T @ r)
    return coef[:2], r - basis @ coef


def _extract(x0: np.ndarray, max_lines: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Lines until the residual is white or exact.

    Returns the frequencies (cycles/sample), their (cos, sin) amplitudes, the residual and
    whether it converged. Each line is taken out by least squares as it is found; two passes
    then re-refine every line against the residual with the others removed (Laskar's
    frequency analysis), which corrects the bias neighbouring lines cause.
    """
    var0 = float(np.var(x0))
    n = x0.size
    window = np.hanning(n)
    freqs: list[float] = []
    coefs: list[np.ndarray] = []
    resid = x0.copy()

    def done(r: np.ndarray) -> bool:
        return float(np.var(r)) <= EXACT * var0 or ljung_box_p(r) >= WHITE_P

    converged = done(resid)
    while not converged and len(freqs) < max_lines:
        f = _strongest_line(resid, window)
        if f is None:
            break
        freqs.append(f)
        if len(freqs) <= JOINT_LINES:  # joint amplitudes: no leakage between lines
            basis = _basis(np.array(freqs), n)
            coef = _lstsq(basis, x0)
            resid = x0 - basis @ coef
            coefs = [np.array([coef[1 + i], coef[1 + len(freqs) + i]]) for i in range(len(freqs))]
        else:
            coef, resid = _take_out(resid, f)
            coefs.append(coef)
        converged = done(resid)
    for _ in range(2 if freqs else 0):
        for i, f in enumerate(freqs):
            r = resid + _line(f, n) @ coefs[i]
            freqs[i] = _strongest_line(r, window, near=f) or f
            coefs[i], resid = _take_out(r, freqs[i])
        converged = done(resid)
    arr, cs = np.array(freqs), np.array(coefs).reshape(-1, 2)
    keep = _distinct(arr, cs, resid, n) if arr.size else arr.astype(np.int64)
    if keep.size and (keep.size < arr.size or not converged):
        # Sequential removal leaves each line slightly off, and weak lines within a bin
        # of it compensate; a joint refinement of the distinct, significant lines fixes
        # both. It replaces the extraction when it explains the series as well.
        if n * (3 * keep.size + 1) ** 2 <= GN_BUDGET:
            f2, c2, r2 = _gauss_newton(x0, arr[keep])
            if done(r2) or float(np.var(r2)) < float(np.var(resid)):
                arr, cs, resid = f2, c2, r2
                converged = done(resid)
    return arr, cs, resid, converged


def _distinct(freqs: np.ndarray, coefs: np.ndarray, resid: np.ndarray, n: int) -> np.ndarray:
    """Indices of significant lines, each more than a bin from any stronger one."""
    amp = np.hypot(coefs[:, 0], coefs[:, 1])
    z = n * amp**2 / (4.0 * max(float(np.var(resid)), 1e-300))
    keep: list[int] = []
    for i in np.argsort(-amp):
        if z[i] < np.log(n / 2.0) + 7.0:
            break
        if all(abs(freqs[i] - freqs[j]) > 1.0 / n for j in keep):
            keep.append(int(i))
    return np.array(keep, dtype=np.int64)


def _basis(freqs: np.ndarray, n: int) -> np.ndarray:
    """The n × (2m + 1) basis (constant, cosines, sines) as the transpose of a C-order
    array: its columns are contiguous, as :func:`_lstsq` wants them."""
    phase = 2 * np.pi * np.arange(n, dtype=np.float64)[None, :] * freqs[:, None]
    return np.concatenate([np.ones((1, n)), np.cos(phase), np.sin(phase)], axis=0).T


def _lstsq(basis: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Least-squares coefficients of ``y`` in the columns of ``basis`` (n × m).

    The same solution as ``numpy.linalg.lstsq(basis, y, rcond=None)`` to rounding: a
    Householder QR on one thread, solved by back substitution when the singular values of
    R (those of ``basis``) are all well above the cut-off below which the SVD solver
    drops them; otherwise that solver itself, so a rank-deficient basis gets the same
    minimum-norm answer.
    """
    n, m = basis.shape
    if n < m:  # more columns than samples: the SVD solver's minimum-norm answer
        coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
        return coef
    r, qty = householder_qr(np.ascontiguousarray(basis.T), y)
    s = np.linalg.svd(r, compute_uv=False)
    # 1e3 above the cut-off (eps · max(n, m) of the largest): no rounding can put a
    # singular value on the other side of it
    if s[0] > 0.0 and s[-1] > 1e3 * np.finfo(np.float64).eps * max(n, m) * s[0]:
        return solve_triangular(r, qty)
    coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
    return coef


def _gauss_newton(
    x0: np.ndarray, freqs: np.ndarray, iterations: int = 4
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint least-squares refinement of every frequency and amplitude (few lines only)."""
    n, m = x0.size, freqs.size
    t = np.arange(n, dtype=np.float64)

    def fit(f: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        basis = _basis(f, n)
        coef = _lstsq(basis, x0)
        return coef, x0 - basis @ coef, basis, 2 * np.pi * t[:, None] * f[None, :]

    for _ in range(iterations):
        coef, resid, basis, phase = fit(freqs)
        a, b = coef[1 : m + 1], coef[m + 1 :]
        dfreq = 2 * np.pi * t[:, None] * (b * np.cos(phase) - a * np.sin(phase))
        step = _lstsq(np.concatenate([basis.T, dfreq.T], axis=0).T, resid)
        delta = np.clip(step[2 * m + 1 :], -0.25 / n, 0.25 / n)
        freqs = np.clip(freqs + delta, 1e-12, 0.5)
        if np.max(np.abs(delta)) < 1e-10 / n:
            break
    coef, resid, _, _ = fit(freqs)
    return freqs, np.column_stack([coef[1 : m + 1], coef[m + 1 :]]), resid


def _significant(
    x0: np.ndarray, freqs: np.ndarray, coefs: np.ndarray, resid: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Keep lines whose periodogram height beats the largest one white noise would give."""
    n = x0.size
    amp = np.hypot(coefs[:, 0], coefs[:, 1])
    noise = max(float(np.var(resid)), EXACT * float(np.var(x0)))
    z = n * amp**2 / (4.0 * noise)  # periodogram ordinate in units of its mean for noise
    keep = z >= np.log(n / 2.0) + 7.0  # false-alarm probability about 1e-3 per series
    order = np.argsort(-amp[keep])
    return freqs[keep][order], coefs[keep][order], amp[keep][order], z[keep][order]


# ---------------------------------------------------------------- structure of the lines


def _alias_distance(f: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Distance between frequencies in cycles per sample, modulo aliasing (f ≡ ±f mod 1)."""
    d1 = np.abs((f - g + 0.5) % 1.0 - 0.5)
    d2 = np.abs((f + g + 0.5) % 1.0 - 0.5)
    return np.minimum(d1, d2)


def _harmonic_distance(freqs: np.ndarray, f0: float) -> tuple[np.ndarray, np.ndarray]:
    """For each line, the nearest harmonic m·f0 (m ≥ 1, aliasing included: harmonics above
    the Nyquist frequency appear folded) and the distance to it (cycles per sample)."""
    top = min(int(np.ceil(2.0 / f0)) + 1, 4096)  # up to twice the sampling frequency
    m = np.arange(1, top + 1, dtype=np.float64)
    d = _alias_distance(freqs[:, None], m[None, :] * f0)
    best = np.argmin(d, axis=1)
    return m[best], d[np.arange(freqs.size), best]


def _fundamental(
    freqs: np.ndarray,
    amps: np.ndarray,
    tol: np.ndarray,
    spread: float,
    candidates: np.ndarray,
    n: int,
) -> tuple[float, int] | None:
    """First candidate fundamental of which every line is a harmonic (within tolerance;
    ``spread`` is the standard error of the reference line the candidates divide).

    Harmonics above the Nyquist frequency are accepted folded back only for weak lines
    (below 5 % of the strongest): folding makes the harmonics of a slow fundamental dense,
    and a strong line matching one by accident must not make a torus periodic.
    """
    weak = amps < 0.05 * amps[0]
    for j, f0 in enumerate(candidates):
        if f0 * n < 4.0:  # fewer than four repeats: a period cannot be claimed
            break
        # the m-th harmonic inherits m times the error of the fundamental
        h = np.maximum(np.round(freqs / f0), 1.0)
        ok = np.abs(freqs - h * f0) <= tol + 5.0 * h * spread / (j + 1)
        if not np.all(ok | weak):
            continue
        h, dist = _harmonic_distance(freqs, f0)
        if np.all(ok | (dist <= tol + 5.0 * h * spread / (j + 1))):
            return float(f0), j + 1
    return None


def _combination_rank(bases: list[float], f: float, tol: float) -> bool:
    """Whether f is an integer combination of the bases (coefficients up to MAX_COEF)."""
    limit = MAX_COEF[0] if len(bases) <= 2 else MAX_COEF[1]
    grid = np.arange(-limit, limit + 1)
    combos = np.array(list(itertools.product(grid, repeat=len(bases))), dtype=np.float64)
    values = combos @ np.array(bases)
    return bool(np.min(_alias_distance(np.full(values.size, f), values)) <= tol)


def _independent(bases: list[float], crlb: list[float], n: int, limit: int) -> bool:
    """No integer relation :math:`\\sum c_i f_i = 0` with :math:`|c_i| \\le` ``limit``
    that the record could not tell from exact: the residual frequency must drift by more
    than 0.05 cycles over the record (plus five standard errors)."""
    grid = np.arange(-limit, limit + 1)
    combos = np.array(list(itertools.product(grid, repeat=len(bases))), dtype=np.float64)
    combos = combos[np.any(combos != 0, axis=1)]
    tol = 0.05 / n + 5.0 * np.abs(combos) @ np.array(crlb)
    return bool(np.all(np.abs(combos @ np.array(bases)) > tol))


def _drive_harmonics(
    x0: np.ndarray, freqs: np.ndarray, f_drive: float, max_period: int, max_residual: float
) -> tuple[int, float, float, np.ndarray, np.ndarray] | None:
    """Smallest k for which every harmonic of f_drive / k (up to 24 drive harmonics) fits
    the series to white noise or nothing; tried only where the extracted lines sit within
    a bin of such harmonics. Returns k, residual fraction, Ljung–Box p, frequencies and
    their (cos, sin) amplitudes."""
    n = x0.size
    var0 = float(np.var(x0))
    for k in range(1, max_period + 1):
        f0 = f_drive / k
        if f0 * n < 4.0:
            break
        if np.any(_harmonic_distance(freqs, f0)[1] > 1.0 / n):
            continue
        top = max(1, min(int(0.5 / f0), 24 * k))
        hf = f0 * np.arange(1, top + 1)
        basis = _basis(hf, n)
        if basis.shape[1] > n // 2:
            continue
        coef = _lstsq(basis, x0)
        resid = x0 - basis @ coef
        frac = float(np.var(resid)) / var0
        p = ljung_box_p(resid)
        if frac <= EXACT or (frac <= max_residual and p >= WHITE_P):
            m = hf.size
            return k, frac, p, hf, np.column_stack([coef[1 : m + 1], coef[m + 1 :]])
    return None


def _maxima_per_period(freqs: np.ndarray, coefs: np.ndarray, f0: float, n: int) -> int:
    """Prominent maxima of the fitted waveform per fundamental period, counted at the
    sample times (harmonics above the Nyquist frequency are seen aliased, as sampled)."""
    t = np.arange(n, dtype=np.float64)
    phase = 2 * np.pi * t[:, None] * freqs[None, :]
    wave = np.cos(phase) @ coefs[:, 0] + np.sin(phase) @ coefs[:, 1]
    peaks, _ = find_peaks(wave, prominence=0.02 * float(np.ptp(wave)))
    return max(1, round(peaks.size / (n * f0)))


def line_spectrum(
    x: np.ndarray,
    *,
    dt: float = 1.0,
    drive_period: float | None = None,
    max_period: int = 32,
    max_lines: int = 48,
    max_residual: float = 0.5,
    max_samples: int = 4096,
    fold: bool = True,
) -> LineSpectrum:
    r"""Is the series periodic, quasi-periodic, or neither? Recurrence and refined lines.

    **Recurrence.** For :math:`k = 1, \ldots,` ``max_period`` the series is folded at a lag
    of :math:`k` samples: the mean waveform :math:`\bar x_{n \bmod k}` is subtracted. The
    smallest :math:`k` whose residual is exactly zero (below :math:`10^{-8}` of the
    variance) or white (Ljung–Box over 20 lags, :math:`p \ge 10^{-3}`) while carrying at
    most ``max_residual`` of the variance is the period: :math:`|x_{n+k} - x_n|` is then
    measurement noise only. A forced series (``drive_period`` given) sampled a whole number
    :math:`P` of times per drive period (to within 1 % of a sample over the record) is
    folded the same way at :math:`kP` samples, :math:`k = 1, \ldots,` ``max_period``, over
    the whole series and with at least four repeats: a forced impact orbit has harmonics up
    to the Nyquist frequency, more than lines can be extracted, yet repeats exactly.

    **Lines.** Otherwise the strongest line of the Hann-windowed, four-times zero-padded
    spectrum is located, refined to the maximum of the windowed DTFT (Laskar's frequency
    analysis), and removed by least squares; this repeats until the residual is white or
    exactly zero (at most ``max_lines`` lines). All frequencies are then refined jointly by
    Gauss–Newton. For a forced series whose extracted lines all lie within a bin of the
    harmonics of a subharmonic :math:`f_d/k` of the drive, those harmonics (up to 24
    drive harmonics) are fitted at once by least squares — exact where refinement one line
    at a time is not, on a few drive periods. Lines whose periodogram height does not beat
    what white noise of the residual's level would give (false-alarm probability about
    :math:`10^{-3}`) are dropped.
    A *line spectrum* leaves a white (or zero) residual carrying at most ``max_residual`` of
    the variance. It is *periodic* when every line is a harmonic of one fundamental
    :math:`f_1/k` (:math:`f_1` the strongest line, or the drive frequency for a forced
    series; :math:`k \le` ``max_period``, at least four repeats) and *quasi-periodic* when
    every line is an integer combination of two or three base frequencies with no
    small-integer relation between them. Lines that leave a coloured residual below
    0.1 % of the variance are *unresolved* (a relaxation oscillation has more harmonics
    than are extracted; a weakly chaotic flow has a faint continuous part) and decide
    nothing. Anything else is *broadband*; whether that decides anything depends on how
    many cycles the series spans (the caller's judgement).

    Parameters
    ----------
    x
        The series (finite, 1-D).
    dt
        Sampling interval (time units; 1 for maps).
    drive_period
        Period of an external drive (time units): the fundamental is sought among its
        subharmonics.
    max_period
        Largest period looked for (samples when folding; drive periods or periods of the
        strongest line otherwise).
    max_lines
        Largest number of lines extracted.
    max_residual
        Largest fraction of the variance the white residual may carry.
    max_samples
        Only the last ``max_samples`` samples are analysed (the cost grows with the length
        and the number of lines; exactness does not need more).
    fold
        Try the folding test at lags of samples first (off for forced series, whose period
        counts drive periods; they are folded at whole drive periods instead).

    Returns
    -------
    LineSpectrum

    References
    ----------
    J. Laskar, "Frequency analysis for multi-dimensional systems. Global dynamics and
    diffusion", Physica D 67, 257–281 (1993); G. M. Ljung and G. E. P. Box, Biometrika 65,
    297–303 (1978).
    """
    x_all = np.asarray(x, dtype=np.float64)
    x0 = x_all[-max_samples:]
    x0 = x0 - float(np.mean(x0))
    n = x0.size
    var0 = float(np.var(x0))
    empty = np.zeros(0)
    common = {"frequencies": empty, "amplitudes": empty}
    if drive_period is not None:
        # A forced response sampled a whole number of times per drive period repeats after
        # k drive periods: folding there is exact whatever its number of harmonics (an
        # impact orbit has harmonics up to the Nyquist frequency, more than lines can be
        # extracted). The whole series is folded: it is cheap and sees more repeats.
        per = samples_per_drive_period(drive_period, dt, x_all.size)
        # at least four repeats of the folding lag
        lags = range(per, min(max_period * per, x_all.size // 4) + 1, per) if per else range(0)
        found = _first_repeat(x_all - float(np.mean(x_all)), lags, max_residual)
        if found is not None and per:
            k, frac, p = found[0] // per, found[1], found[2]
            return LineSpectrum(
                kind="periodic", method="drive recurrence",
                base_frequencies=np.array([1.0 / (k * drive_period)]),
                fundamental_period=k * drive_period, period_samples=None,
                maxima_per_period=None, residual_fraction=frac, white_p=p,
                n_cycles=x_all.size * dt / drive_period, **common,
            )  # fmt: skip
    if fold:
        found = _first_repeat(x0, range(1, min(max_period, n // 10) + 1), max_residual)
        if found is not None:
            k, frac, p = found
            return LineSpectrum(
                kind="periodic", method="recurrence", base_frequencies=np.array([1.0 / (k * dt)]),
                fundamental_period=k * dt, period_samples=k, maxima_per_period=None,
                residual_fraction=frac, white_p=p, n_cycles=n / k, **common,
            )  # fmt: skip
    freqs, coefs, resid, converged = _extract(x0, max_lines)
    if drive_period is not None and not converged and freqs.size:
        # A forced response: its fundamental is a known subharmonic of the drive, so the
        # harmonics can be fitted exactly instead of refined one by one. The lines that
        # carry all but 1e-6 of the power say which subharmonic to try.
        power = np.sum(coefs**2, axis=1)
        order = np.argsort(-power)
        share = np.cumsum(power[order]) / np.sum(power)
        main = freqs[order[: int(np.searchsorted(share, 1.0 - 1e-6)) + 1]]
        found_k = _drive_harmonics(x0, main, dt / drive_period, max_period, max_residual)
        if found_k is not None:
            k, frac, p, hf, hc = found_k
            return LineSpectrum(
                kind="periodic", method="drive harmonics", frequencies=hf / dt,
                amplitudes=np.hypot(hc[:, 0], hc[:, 1]),
                base_frequencies=np.array([1.0 / (k * drive_period)]),
                fundamental_period=k * drive_period, period_samples=None,
                maxima_per_period=_maxima_per_period(hf, hc, hf[0], n), residual_fraction=frac,
                white_p=p, n_cycles=n * dt / drive_period,
            )  # fmt: skip
    frac = float(np.var(resid)) / var0
    p = ljung_box_p(resid)
    lines, coefs, amps, z = _significant(x0, freqs, coefs, resid)
    if drive_period is not None:
        f_ref = dt / drive_period
    elif lines.size:
        f_ref = float(lines[0])
    else:
        f_ref = float("nan")
    n_cycles = f_ref * n if np.isfinite(f_ref) else 0.0
    base: dict[str, object] = {
        "method": "lines", "frequencies": lines / dt, "amplitudes": amps,
        "residual_fraction": frac, "white_p": p, "n_cycles": n_cycles,
        "period_samples": None,
    }  # fmt: skip
    nan = float("nan")
    if converged and lines.size and frac <= max_residual:
        # Uncertainty of each refined frequency: Cramér–Rao for a line in white noise,
        # sqrt(3/z)/(2πn), with a floor for the interference of the other lines.
        crlb = np.sqrt(3.0 / z) / (2 * np.pi * n)
        tol = 5.0 * crlb + 0.02 / n
        cands = f_ref / np.arange(1, max_period + 1)
        spread = 0.0 if drive_period is not None else float(crlb[0])
        found = _fundamental(lines, amps, tol, spread, cands, n)
        if found is not None:
            f0, _ = found
            return LineSpectrum(
                kind="periodic", base_frequencies=np.array([f0 / dt]),
                fundamental_period=dt / f0,
                maxima_per_period=_maxima_per_period(lines, coefs, f0, n), **base,  # type: ignore[arg-type]
            )  # fmt: skip
        bases: list[float] = [float(lines[0])] if drive_period is None else [f_ref]
        errs: list[float] = [float(crlb[0])] if drive_period is None else [0.0]
        ok = True
        for f, t, e in zip(lines, tol, crlb, strict=True):
            if _combination_rank(bases, float(f), float(t)):
                continue
            if len(bases) == 3:
                ok = False
                break
            bases.append(float(f))
            errs.append(float(e))
        limit = max_period if len(bases) == 2 else MAX_COEF[1]
        if ok and len(bases) >= 2 and _independent(bases, errs, n, limit):
            return LineSpectrum(
                kind="quasi-periodic", base_frequencies=np.array(bases) / dt,
                fundamental_period=nan, maxima_per_period=None, **base,  # type: ignore[arg-type]
            )  # fmt: skip
    return LineSpectrum(
        kind="unresolved" if frac <= UNRESOLVED and not converged else "broadband",
        base_frequencies=empty, fundamental_period=nan,
        maxima_per_period=None, **base,  # type: ignore[arg-type]
    )  # fmt: skip
