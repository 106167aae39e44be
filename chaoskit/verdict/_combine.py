"""The rule: :func:`combine` turns the votes of a :class:`RuleEvidence` into a
:class:`RuleOutcome`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._cycles import OrbitResidual
from ._rule import LOW_DIM, Label, VerdictRule, Vote
from ._section_structure import SectionStructure

_LINE_KINDS = (None, "periodic", "quasi-periodic", "broadband", "unresolved")


@dataclass(frozen=True, kw_only=True)
class RuleEvidence:
    """The evidence on one series that the rule of :func:`~chaoskit.classify` weighs.

    :func:`combine` turns it into a label; :func:`~chaoskit.classify` builds it from the
    estimators, and a caller may build one by hand to see how the rule reads a given
    combination of evidence.

    Attributes
    ----------
    structure
        The structure of the Poincaré or stroboscopic section (None: no section).
    rosenstein_positive, wolf_positive
        Whether each exponent estimate is clearly positive (None: the estimator failed).
    zero_one_k
        The 0–1 test's K (None: it failed).
    surrogates_rejected
        Whether the IAAFT surrogate test rejects linear noise (None: it failed).
    lines
        The kind of the recurrence / line-spectrum analysis: ``"periodic"``,
        ``"quasi-periodic"``, ``"broadband"`` or ``"unresolved"`` (None: it failed).
    lines_period
        The period of a periodic line spectrum, in the unit of the verdict's period.
    lines_bases
        The number of base frequencies of the line spectrum (≥ 0).
    n_cycles
        The characteristic times the series spans (≥ 0); ``cycle_unit`` names them.
    cycle_unit
        The name of those times ("drive periods", "samples", ...), stated in the needs.
    low_dim_rejected
        Whether a surrogate test repeated in a few delay coordinates, a delay or one
        sample ahead rejected (None: none ran).
    low_dim_confirmed
        Whether that rejection held when the test was repeated at half the significance
        level with twice as many surrogates (None: not repeated). For a forced series
        whose mean cycle carries at least ``1 - rule.max_residual`` of the variance it
        counts as determinism.
    kantz_positive
        Whether the referee (Kantz) exponent is clearly positive (None: it did not run).
    cycles_rejected
        Whether the noisy-periodic-orbit (cycle-shuffled surrogate) test of a forced
        series rejects (None: it did not run).
    driven
        Whether the series is forced; its chaos then needs evidence beyond a noisy
        periodic orbit.
    noise
        The estimated measurement-noise level, relative to the standard deviation
        (stated in the reason of a noisy periodic orbit).
    cycle_spread
        The cycle-to-cycle variation that is not white noise, relative to the standard
        deviation.
    phase_spread
        The part of the departure from the mean cycle whose variance depends on the phase
        of the cycle, relative to the standard deviation (NaN: not computed): stationary
        measurement noise, white or coloured, reads 0.
    orbit_residual
        The departure of a forced series from its mean cycle read as measurement noise
        (None: not computed).
    """

    structure: SectionStructure | None
    rosenstein_positive: bool | None
    wolf_positive: bool | None
    zero_one_k: float | None
    surrogates_rejected: bool | None
    lines: str | None = "broadband"
    lines_period: int | None = None
    lines_bases: int = 0
    n_cycles: float = float("inf")
    cycle_unit: str = "characteristic times"
    low_dim_rejected: bool | None = None
    low_dim_confirmed: bool | None = None
    kantz_positive: bool | None = None
    cycles_rejected: bool | None = None
    driven: bool = False
    noise: float = float("nan")
    cycle_spread: float = float("nan")
    phase_spread: float = float("nan")
    orbit_residual: OrbitResidual | None = None

    def __post_init__(self) -> None:
        if self.lines not in _LINE_KINDS:
            raise ValueError(
                "lines must be one of 'periodic', 'quasi-periodic', 'broadband', "
                f"'unresolved' or None, got {self.lines!r}"
            )
        if self.lines_period is not None and not self.lines_period >= 1:
            raise ValueError(f"lines_period must be None or ≥ 1, got {self.lines_period!r}")
        if not self.lines_bases >= 0:
            raise ValueError(f"lines_bases must be ≥ 0, got {self.lines_bases!r}")
        if not self.n_cycles >= 0:
            raise ValueError(f"n_cycles must be ≥ 0, got {self.n_cycles!r}")


@dataclass(frozen=True)
class RuleOutcome:
    """What :func:`combine` decides on a :class:`RuleEvidence`.

    Attributes
    ----------
    label
        ``"periodic"``, ``"quasi-periodic"``, ``"chaotic"``, ``"noise-like"`` or
        ``"undetermined"``.
    period
        The period of a periodic label (None otherwise).
    confidence
        The fraction of the deciding votes that support the label (NaN when undetermined).
    reason
        One sentence: why the label, or what the evidence lacks.
    votes
        Each piece of evidence: ``"supports"``, ``"opposes"``, ``"neutral"`` or
        ``"missing"``.
    needs
        What would decide an undetermined series (empty otherwise).
    """

    label: Label
    period: int | None
    confidence: float
    reason: str
    votes: dict[str, Vote]
    needs: tuple[str, ...]


@dataclass(frozen=True)
class _Evidence:
    """What :func:`combine` is given, and what the rule derives from it before deciding."""

    structure: SectionStructure | None
    exponents: dict[str, bool | None]  # Rosenstein, Wolf (and Kantz when it ran): positive?
    zero_one_k: float | None
    surrogates_rejected: bool | None
    rule: VerdictRule
    lines: str | None
    lines_period: int | None
    lines_bases: int
    n_cycles: float
    cycle_unit: str
    low_dim_rejected: bool | None
    kantz_ran: bool
    cycles_rejected: bool | None
    driven: bool
    noise: float
    cycle_spread: float
    residual: OrbitResidual | None = None
    phase_spread: float = float("nan")
    low_dim_confirmed: bool | None = None

    @property
    def n_positive(self) -> int:
        return sum(pos is True for pos in self.exponents.values())

    @property
    def both_positive(self) -> bool:
        # two estimators must agree on a clearly positive exponent
        return self.n_positive >= 2

    @property
    def long_enough(self) -> bool:
        return self.n_cycles >= self.rule.min_cycles

    @property
    def section(self) -> str:
        return "none" if self.structure is None else self.structure.kind

    @property
    def broadband_decides(self) -> bool:
        # a spectrum that is not lines, over enough cycles, outweighs a regular-looking
        # section
        return self.lines == "broadband" and self.long_enough

    @property
    def zero_one_witness(self) -> bool:
        # where nothing looks regular (broadband spectrum, scattered section), the 0–1 test
        # is the second witness of sensitive dependence beside one clearly positive exponent
        # (the surrogate test, required for chaos, rules out the noise that fools it)
        return (
            self.n_positive == 1
            and self.zero_one_k is not None
            and self.zero_one_k >= self.rule.zero_one_chaotic
            and self.broadband_decides
            and self.section == "scattered"
        )

    @property
    def lines_contradict_clusters(self) -> bool:
        # clusters alone make a period only where the spectrum cannot speak against them: a
        # spectrum of lines that are not one period's harmonics (unresolved, or a torus's)
        # contradicts k tight clusters (chaotic flows sampled coarsely show both)
        return self.lines in ("unresolved", "quasi-periodic")

    @property
    def coloured_orbit(self) -> bool:
        # coloured noise scatters the section beyond what the white-noise estimate allows:
        # a scattered section counts as a noisy orbit's when nothing carries over from one
        # cycle to the next (the cycle-shuffled test ran and does not reject)
        return self.section == "scattered" and self.cycles_rejected is False

    @property
    def noisy_orbit(self) -> bool:
        # a driven series whose section is k tight clusters and whose departure from its
        # mean cycle is measurement noise (white, or coloured but the same at every phase of
        # the cycle), up to the cluster tolerance, is a periodic orbit plus noise, whatever
        # the noise does to the spectrum and the exponents; chaos carries its departure
        # over, or makes it depend on the phase (then the spread exceeds the tolerance)
        return bool(
            self.driven
            and (self.section == "clusters" or self.coloured_orbit)
            and self.lines != "quasi-periodic"
            and self.cycle_spread <= self.rule.cluster_tol
        )

    @property
    def phase_dependent(self) -> bool:
        # the departure from the mean cycle depends on the phase beyond the tolerance: it
        # is not stationary measurement noise. A periodic call then rests on the lag-one
        # reading alone (the departure is not smooth over a sample), which cannot tell a
        # stable orbit jolted afresh every cycle from chaos that lives in the timing of
        # impacts: both are spiky departures confined to some phases
        return bool(self.driven and self.phase_spread > self.rule.cluster_tol)

    @property
    def beyond_orbit(self) -> bool:
        # what a chaotic driven series must show beyond a noisy periodic orbit: its
        # departure from the mean cycle carries over from one cycle to the next (the
        # cycle-shuffled surrogates reject), or is not white noise and larger than the
        # cluster tolerance
        return self.cycles_rejected is True or bool(self.cycle_spread > self.rule.cluster_tol)

    @property
    def dominant_cycle(self) -> bool:
        # the phase-locked mean cycle of a driven series carries most of its variance (as
        # much as a white residual of a line spectrum may leave): not stationary noise, whose
        # mean cycle carries about one part in the number of cycles
        r = self.residual
        return bool(self.driven and r is not None and r.fraction >= 1.0 - self.rule.max_residual)

    @property
    def linear_residual(self) -> bool:
        # ... and the departure from it is consistent with a linear Gaussian process: the
        # series is a periodic orbit plus coloured measurement noise. Such noise carries
        # over a cycle boundary by its own short memory, so a rejection of the
        # cycle-shuffled test does not count against it
        r = self.residual
        return bool(
            self.dominant_cycle
            and r is not None
            and not r.test.rejected
            # a larger departure is not all measurement noise (as for the cycle spread)
            and r.level <= self.rule.max_noise_allowance
        )

    @property
    def residual_rejected(self) -> bool:
        # the departure from a dominant mean cycle is more predictable than linear
        # Gaussian noise: determinism where the chaos of a driven series lives, which the
        # test of the whole series misses when the mean cycle dilutes it
        r = self.residual
        return bool(self.dominant_cycle and r is not None and r.test.rejected)

    @property
    def confirmed_low_dim(self) -> bool:
        # the test in a few delay coordinates rejected, and again at half the level with
        # twice as many surrogates: determinism, for a series dominated by its mean cycle
        # (not noise) whose departure a predictor in the full embedding dimension cannot
        # resolve (too few close neighbours among a few thousand points)
        return bool(
            self.dominant_cycle
            and self.surrogates_rejected is False
            and self.low_dim_confirmed is True
        )

    @property
    def coloured_noise_orbit(self) -> bool:
        # ... whose variance is the same at every phase of the cycle, up to the tolerance
        return (
            self.linear_residual
            and self.lines != "quasi-periodic"
            and self.cycle_spread <= self.rule.cluster_tol
        )


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
        blurred = ("rosenstein", "wolf", "kantz", "zero_one", "lines")
        if structure is not None and structure.kind == "scattered":
            blurred += ("section",)  # coloured noise scatters the section as well
        for name in blurred:
            if votes.get(name) in ("supports", "opposes"):
                votes[name] = "neutral"
    return votes


def _periodic(ev: _Evidence) -> tuple[int | None, str] | None:
    """Period and reason when the evidence shows a periodic orbit (with or without noise)."""
    rule, spread, noise = ev.rule, ev.cycle_spread, ev.noise
    if ev.lines == "periodic":
        return ev.lines_period, (
            "the series repeats: what is left after its period is white noise or nothing"
        )
    if ev.section == "clusters" and not ev.broadband_decides and not ev.lines_contradict_clusters:
        assert ev.structure is not None
        period = ev.structure.n_clusters
        return period, (
            f"the section is {period} tight cluster{'s' * (period != 1)} visited in a fixed "
            "cyclic order"
        )
    if ev.noisy_orbit and ev.coloured_orbit:
        return 1, (
            "the departure from the mean cycle is measurement noise: its variance is the "
            "same at every phase of the cycle, nothing carries over from one cycle to the "
            "next (the cycle-shuffled surrogate test does not reject) and what varies beyond "
            f"noise is {spread:.2g} of the standard deviation (at most "
            f"{rule.cluster_tol:g}): a periodic orbit plus coloured noise (correlated over "
            "several samples: it scatters the section beyond what white noise of about "
            f"{noise:.2g} of the standard deviation allows)"
        )
    if ev.noisy_orbit:
        assert ev.structure is not None
        period = ev.structure.n_clusters
        return period, (
            f"the section is {period} tight cluster{'s' * (period != 1)} and what varies from "
            f"cycle to cycle beyond stationary noise is {spread:.2g} of the standard "
            f"deviation (at most {rule.cluster_tol:g}): a periodic orbit plus noise "
            f"(measurement noise about {noise:.2g} of the standard deviation; the "
            "cycle-shuffled surrogate test "
            + ("rejects, within that tolerance)" if ev.cycles_rejected else "does not reject)")
        )
    if ev.coloured_noise_orbit:
        assert ev.residual is not None
        return ev.residual.cycles, _coloured_orbit_reason(ev)
    return None


def _coloured_orbit_reason(ev: _Evidence) -> str:
    """Why a driven series is a periodic orbit plus coloured measurement noise: the mean
    cycle's share, the noise's level and colour, and what varies beyond it."""
    r = ev.residual
    assert r is not None
    if 0.2 <= r.lag_one < 1.0:
        colour = f"coloured, correlation time {-1.0 / math.log(r.lag_one):.2g} samples"
    else:
        colour = "nearly white"
    head = (
        f"the mean cycle over the drive carries {100 * r.fraction:.0f} % of the variance "
        f"and the departure from it ({r.level:.2g} of the standard deviation, lag-one "
        f"autocorrelation {r.lag_one:.2f}: {colour}) is consistent with a linear Gaussian "
        "process (its IAAFT surrogate test does not reject)"
    )
    tol = ev.rule.cluster_tol
    if ev.cycle_spread <= tol:
        return (
            f"{head} whose variance is the same at every phase of the cycle (what varies "
            f"beyond it is {ev.cycle_spread:.2g} of the standard deviation, at most {tol:g}): "
            "a periodic orbit plus coloured measurement noise"
        )
    return (
        f"{head}: a periodic orbit plus coloured measurement noise rather than noise; but "
        f"what varies from cycle to cycle beyond stationary noise is {ev.cycle_spread:.2g} "
        f"of the standard deviation (above {tol:g}), which counts against it"
    )


def _quasi_periodic(ev: _Evidence) -> str | None:
    """The reason when the evidence shows a torus."""
    if ev.lines == "quasi-periodic":
        return (
            "the spectrum is lines at integer combinations of two or three incommensurate "
            "frequencies, and what is left is white noise or nothing"
        )
    if ev.section == "closed-curve" and not ev.both_positive and not ev.broadband_decides:
        return "the section fills a closed curve and not both exponents are clearly positive"
    return None


def _noise_like(ev: _Evidence) -> str | None:
    """The reason when the surrogate test cannot reject linear noise (broadband spectrum)."""
    if (
        ev.lines == "broadband"
        and ev.long_enough
        and ev.surrogates_rejected is False
        and ev.low_dim_rejected is not True
    ):
        return "the spectrum is not lines; the surrogate test cannot reject linear noise"
    return None


def _chaotic(ev: _Evidence) -> str | None:
    """The reason when the evidence shows chaos."""
    if not (
        (ev.both_positive or ev.zero_one_witness)
        and (ev.surrogates_rejected is True or ev.residual_rejected or ev.confirmed_low_dim)
        and (not ev.driven or ev.beyond_orbit)
        and ev.lines in ("broadband", "unresolved")
        # a regular-looking section does not count against a broadband spectrum either
        and (ev.section not in ("clusters", "closed-curve") or ev.broadband_decides)
        and (ev.section == "scattered" or (ev.lines == "broadband" and ev.long_enough))
    ):
        return None
    if ev.both_positive:
        head = (
            "both exponents are" if not ev.kantz_ran else "two of the three exponents are"
        ) + " clearly positive"
    else:
        (name,) = (n for n, pos in ev.exponents.items() if pos is True)
        head = (
            f"the {name} exponent is clearly positive and the 0–1 test finds the motion "
            f"irregular (K = {ev.zero_one_k:.2f})"
        )
    if ev.surrogates_rejected is True:
        determinism = "the data are more predictable than their IAAFT surrogates"
    elif ev.residual_rejected:
        assert ev.residual is not None
        determinism = (
            "the departure from the mean cycle over the drive (which carries "
            f"{100 * ev.residual.fraction:.0f} % of the variance) is more predictable than its "
            "IAAFT surrogates"
        )
    else:
        assert ev.residual is not None  # a confirmed low-dimensional test needs it
        determinism = (
            f"the data are more predictable than their IAAFT surrogates in {LOW_DIM} delay "
            f"coordinates, at {ev.rule.alpha:g} and again at {ev.rule.alpha / 2:g} with "
            "twice as many surrogates (not in the embedding dimension; the mean cycle over "
            f"the drive carries {100 * ev.residual.fraction:.0f} % of the variance)"
        )
    return (
        f"{head}, {determinism}"
        + (
            ""
            if not ev.driven
            else " and, across a cycle boundary, than their cycle-shuffled ones"
            if ev.cycles_rejected
            else f", their departure from the mean cycle is not white noise "
            f"({ev.cycle_spread:.2g} of the standard deviation)"
        )
        + ", and neither the spectrum nor the section is regular"
    )


def _decide(ev: _Evidence) -> tuple[Label, int | None, str | None]:
    """The label, its period and its reason (None when undetermined), in the rule's order."""
    periodic = _periodic(ev)
    if periodic is not None:
        return "periodic", periodic[0], periodic[1]
    reason = _quasi_periodic(ev)
    if reason is not None:
        return "quasi-periodic", None, reason
    reason = _noise_like(ev)
    if reason is not None and not ev.dominant_cycle:
        return "noise-like", None, reason
    if reason is not None and ev.linear_residual:
        # a noise label must beat "a periodic orbit plus coloured measurement noise", and a
        # series whose mean cycle carries most of its variance is not noise
        assert ev.residual is not None
        return "periodic", ev.residual.cycles, _coloured_orbit_reason(ev)
    reason = _chaotic(ev)
    if reason is not None:
        return "chaotic", None, reason
    return "undetermined", None, None


def _blocking_needs(ev: _Evidence) -> list[str] | None:
    """What would decide when the section, the low-dimensional surrogate tests or the
    noisy-orbit null stand in the way (None when none does)."""
    rule, section, structure = ev.rule, ev.section, ev.structure
    if section in ("clusters", "closed-curve") and ev.broadband_decides:
        return [
            f"a longer series: the section looks regular ({section}) but the spectrum is not lines"
        ]
    if section == "clusters" and ev.lines_contradict_clusters:
        assert structure is not None
        return [
            f"a longer or cleaner series: the section is {structure.n_clusters} tight "
            f"cluster{'s' * (structure.n_clusters != 1)} but the spectrum is not the "
            f"harmonics of one period ({ev.lines})"
        ]
    if section == "closed-curve":
        return [
            "a longer series to tell a torus from a thin chaotic band (the section "
            "is a closed curve but both exponents are clearly positive)"
        ]
    if ev.dominant_cycle and _noise_like(ev) is not None and not ev.residual_rejected:
        r = ev.residual
        assert r is not None
        return [
            f"a departure from the mean cycle over the drive that is more predictable than "
            f"linear Gaussian noise: the mean cycle carries {100 * r.fraction:.0f} % of the "
            f"variance (not noise), but the departure from it, {r.level:.2g} of the "
            "standard deviation, is too large for the measurement noise of a periodic orbit "
            f"(above {rule.max_noise_allowance:g}) and its IAAFT surrogate test does not reject"
        ]
    if ev.surrogates_rejected is False and ev.low_dim_rejected is True:
        if ev.confirmed_low_dim:
            return None  # determinism is shown; what else chaos needs is asked below
        return [
            "a longer or more finely sampled series: the data are more predictable "
            f"than their surrogates in {LOW_DIM} delay coordinates or one sample "
            "ahead, but not in the embedding dimension one delay ahead, so neither "
            "noise nor determinism is shown"
        ]
    if ev.driven and not ev.beyond_orbit and ev.surrogates_rejected is True:
        return [
            "evidence beyond a noisy periodic orbit: a cycle-shuffled surrogate test "
            + (
                "(it could not run; see errors)"
                if ev.cycles_rejected is None
                else "that rejects, or a departure from the mean cycle that is not "
                f"white noise and exceeds {rule.cluster_tol:g} of the standard "
                f"deviation (it is {ev.cycle_spread:.2g})"
            )
        ]
    return None


def _needs(ev: _Evidence) -> list[str]:
    """What would decide an undetermined series."""
    rule = ev.rule
    needs: list[str] = []
    if not ev.long_enough:
        # nothing else could decide at this length: say only what would
        needs.append(f"≥ {rule.min_cycles} {ev.cycle_unit}; the series has {ev.n_cycles:.0f}")
    else:
        if ev.section == "too-few-points":
            assert ev.structure is not None
            needs.append(
                f"≥ {rule.min_cycles} section points; the section has {ev.structure.n_points}"
            )
        blocking = _blocking_needs(ev)
        if blocking is not None:
            needs += blocking
        elif ev.surrogates_rejected is not False or ev.confirmed_low_dim:
            for name, pos in ev.exponents.items():
                if pos is False:
                    needs.append(
                        f"a clearly positive {name} exponent (λ₁T ≥ {rule.min_growth:g}, "
                        "95 % interval above 0), or a line spectrum or section that "
                        "shows the motion regular"
                    )
                elif pos is None:
                    needs.append(f"a {name} exponent (the estimator failed; see errors)")
            if ev.surrogates_rejected is None:
                needs.append("a surrogate test (it failed; see errors)")
    if ev.lines is None:
        needs.append("a recurrence / line-spectrum analysis (it failed; see errors)")
    if ev.lines == "unresolved" and not needs:
        needs.append(
            "a longer or cleaner series: spectral lines explain all but 0.1 % of the "
            "variance, yet the rest is not white"
        )
    if not needs:
        needs.append("a longer series")
    return needs


def combine(evidence: RuleEvidence, rule: VerdictRule) -> RuleOutcome:
    """Apply the rule of :func:`~chaoskit.classify` to one series' evidence.

    Parameters
    ----------
    evidence
        What the estimators found (see :class:`RuleEvidence`).
    rule
        The thresholds of the rule.

    Returns
    -------
    RuleOutcome
        Label, period, confidence, reason, votes and needs.

    Examples
    --------
    >>> from chaoskit import RuleEvidence, VerdictRule, combine
    >>> ev = RuleEvidence(structure=None, rosenstein_positive=False, wolf_positive=False,
    ...                   zero_one_k=0.9, surrogates_rejected=False)
    >>> combine(ev, VerdictRule()).label
    'noise-like'
    """
    if not isinstance(evidence, RuleEvidence):
        raise TypeError(f"evidence must be a RuleEvidence, got {type(evidence).__name__}")
    if not isinstance(rule, VerdictRule):
        raise TypeError(f"rule must be a VerdictRule, got {type(rule).__name__}")
    e = evidence
    positives = {
        "rosenstein": e.rosenstein_positive,
        "wolf": e.wolf_positive,
        **({} if e.kantz_positive is None else {"kantz": e.kantz_positive}),
    }
    ev = _Evidence(
        structure=e.structure,
        exponents={name.capitalize(): pos for name, pos in positives.items()},
        zero_one_k=e.zero_one_k,
        surrogates_rejected=e.surrogates_rejected,
        rule=rule,
        lines=e.lines,
        lines_period=e.lines_period,
        lines_bases=e.lines_bases,
        n_cycles=e.n_cycles,
        cycle_unit=e.cycle_unit,
        low_dim_rejected=e.low_dim_rejected,
        kantz_ran=e.kantz_positive is not None,
        cycles_rejected=e.cycles_rejected,
        driven=e.driven,
        noise=e.noise,
        cycle_spread=e.cycle_spread,
        residual=e.orbit_residual,
        phase_spread=e.phase_spread,
        low_dim_confirmed=e.low_dim_confirmed,
    )
    label, period, reason = _decide(ev)
    needs: list[str] = []
    if reason is None:
        needs = _needs(ev)
        reason = "the evidence cannot decide: needs " + "; ".join(needs)
    # a periodic orbit plus coloured noise found by its departure from the mean cycle alone
    coloured = (
        label == "periodic"
        and e.lines != "periodic"
        and ev.linear_residual
        and not ev.noisy_orbit
        and not (
            ev.section == "clusters"
            and not ev.broadband_decides
            and not ev.lines_contradict_clusters
        )
    )
    votes = _votes(
        label,
        structure=e.structure,
        lines=e.lines,
        positives=positives,
        k=e.zero_one_k,
        rejected=e.surrogates_rejected,
        long_enough=ev.long_enough,
        n_bases=e.lines_bases,
        rule=rule,
        cycles=None if not e.driven or e.cycles_rejected is None else ev.beyond_orbit,
        noisy_orbit=(ev.noisy_orbit or coloured) and label == "periodic" and e.lines != "periodic",
    )
    if label == "chaotic" and ev.dominant_cycle:
        votes["residual"] = "supports" if ev.residual_rejected else "opposes"
    if label == "chaotic" and ev.confirmed_low_dim:
        votes["low_dim"] = "supports"
    if coloured:
        # the departure from the mean cycle is linear noise; a phase-dependent spread
        # beyond the tolerance counts against the orbit
        votes["residual"] = "supports"
        if e.cycle_spread > rule.cluster_tol:
            votes["cycles"] = "opposes"
    if (
        label == "periodic"
        and e.lines != "periodic"
        and ev.phase_dependent
        and votes.get("cycles") != "opposes"  # the same reading already counted
    ):
        # a departure that is not stationary noise is no evidence of a stable orbit
        votes["phase"] = "opposes"
        reason += (
            f"; but the departure's variance depends on the phase of the cycle "
            f"({e.phase_spread:.2g} of the standard deviation beyond stationary noise, above "
            f"{rule.cluster_tol:g}): not measurement noise, and nothing shows the orbit "
            "stable (chaos in the timing of impacts looks the same), which counts against it"
        )
    if label == "undetermined":
        confidence = float("nan")
    else:
        counted = [v for v in votes.values() if v in ("supports", "opposes")]
        confidence = sum(v == "supports" for v in counted) / len(counted) if counted else 0.0
    return RuleOutcome(
        label=label,
        period=period,
        confidence=confidence,
        reason=reason,
        votes=votes,
        needs=tuple(needs),
    )
