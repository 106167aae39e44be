"""The rule's vocabulary and thresholds: the labels, the votes and :class:`VerdictRule`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from .._validate import (
    check_int,
    check_positive,
    check_probability,
)

__all__ = ["LABELS", "VerdictRule"]

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
