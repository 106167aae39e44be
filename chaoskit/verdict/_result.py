"""The result of :func:`chaoskit.classify`: :class:`Verdict`, a label with its evidence."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import xarray as xr

from ._line_spectrum import LineSpectrum
from ._rule import LABELS, Kind, Label, VerdictRule, Vote
from ._section_structure import SectionStructure
from ._surrogates import SurrogateResult
from ._table import stack_verdicts
from ._zero_one import ZeroOneResult

__all__ = ["Verdict"]


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
        ``zero_one``, ``surrogates``, and ``cycles`` for a forced series, ``phase`` for a
        periodic forced series whose departure depends on the phase): ``"supports"``,
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
    surrogates_confirmed
        For a forced series whose mean cycle carries at least ``1 - rule.max_residual`` of
        the variance, when the first surrogate test did not reject but the one in
        ``LOW_DIM`` delay coordinates (or one sample ahead) did: that test repeated at
        ``rule.alpha / 2`` with twice as many surrogates (the evidence of ``confirm_low_dim``); its
        rejection counts as determinism for a chaotic label (``votes["low_dim"]``). None
        otherwise.
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
    phase_spread
        For a forced series: the part of that departure whose variance depends on the
        phase of the cycle, relative to the standard deviation (the stationarity reading
        of :func:`~chaoskit.cycle_spread` alone: 0 for a periodic orbit plus stationary
        noise); NaN otherwise. Above ``rule.cluster_tol`` it votes against a periodic
        label (``votes["phase"]``).
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
    surrogates_confirmed: SurrogateResult | None = field(default=None, repr=False)
    cycle_spread: float = float("nan")
    phase_spread: float = float("nan")
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
