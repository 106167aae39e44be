"""The rule: :func:`combine` turns the votes of the evidence into a label."""

from __future__ import annotations

from ._clusters import SectionStructure
from ._rule import LOW_DIM, Label, VerdictRule, Vote


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
    # cycle is measurement noise (white, or coloured but the same at every phase of the
    # cycle), up to the cluster tolerance, is a periodic orbit plus noise, whatever the
    # noise does to the spectrum and the exponents. Coloured noise also scatters the
    # section beyond what the white-noise estimate allows: a scattered section counts too
    # when nothing carries over from one cycle to the next (the cycle-shuffled test ran
    # and does not reject); chaos carries its departure over, or makes it depend on the
    # phase (then the spread exceeds the tolerance)
    coloured_orbit = section == "scattered" and cycles_rejected is False
    noisy_orbit = bool(
        driven
        and (section == "clusters" or coloured_orbit)
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
    elif noisy_orbit and coloured_orbit:
        label, period = "periodic", 1
        reason = (
            "the departure from the mean cycle is measurement noise: its variance is the "
            "same at every phase of the cycle, nothing carries over from one cycle to the "
            "next (the cycle-shuffled surrogate test does not reject) and what varies beyond "
            f"noise is {cycle_spread:.2g} of the standard deviation (at most "
            f"{rule.cluster_tol:g}): a periodic orbit plus coloured noise (correlated over "
            "several samples: it scatters the section beyond what white noise of about "
            f"{noise:.2g} of the standard deviation allows)"
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
