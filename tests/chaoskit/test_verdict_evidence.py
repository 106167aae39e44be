"""Each rule of the verdict that decides what evidence can decide: insufficient evidence is
said (``Verdict.needs``), regular series are recognised first (recurrence, line spectra)."""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import VerdictRule, analyze, classify, load_trajectory, surrogate_test, systems
from chaoskit.verdict import RuleEvidence, RuleOutcome, combine
from chaoskit.verdict._line_spectrum import line_spectrum, ljung_box_p
from chaoskit.verdict._surrogates import min_surrogates
from tests.chaoskit.test_classify import DRIVE, _structure, duffing_x


def _combine(**kwargs) -> RuleOutcome:
    """The rule on evidence given as keywords (``rule`` among them)."""
    rule = kwargs.pop("rule")
    return combine(RuleEvidence(**kwargs), rule)


def _fields(outcome: RuleOutcome) -> tuple:
    """The outcome's label, period, confidence, reason, votes and needs, in that order."""
    o = outcome
    return o.label, o.period, o.confidence, o.reason, o.votes, o.needs


RULE = VerdictRule()


def three_torus(n: int = 4000, dt: float = 0.05) -> np.ndarray:
    t = np.arange(n) * dt
    return np.sin(t) + 0.6 * np.sin(np.sqrt(2) * t) + 0.3 * np.sin(np.sqrt(5) * t)


# ----------------------------------------------------------------- surrogates and alpha


@pytest.mark.parametrize(("alpha", "n"), [(0.05, 19), (0.01, 99), (0.1, 9), (0.2, 4)])
def test_fewest_surrogates_reach_alpha(alpha: float, n: int) -> None:
    assert min_surrogates(alpha) == n
    assert 1.0 / (n + 1) <= alpha < 1.0 / n


def test_too_few_surrogates_are_refused_not_read_as_noise() -> None:
    x = systems.henon(600)[:, 0]
    with pytest.raises(ValueError, match=r"n_surrogates = 9 cannot reach alpha = 0.05.*>= 19"):
        classify(x, n_surrogates=9)
    with pytest.raises(ValueError, match=r">= 99"):
        classify(x, n_surrogates=19, rule=VerdictRule(alpha=0.01))
    with pytest.raises(ValueError, match="n_surrogates"):
        surrogate_test(x, embedding_dim=2, lag=1, n_surrogates=9)
    # analyze records a failure as data: undetermined, with the reason
    ds = load_trajectory(systems.henon(600), dt=1.0, variables=["x", "y"])
    table = analyze(ds, variables=["x"], n_surrogates=9)
    assert str(table.label.values[0]) == "undetermined"
    assert ">= 19" in table.attrs["reasons"]


# ----------------------------------------------------------------- needs


def test_too_few_drive_periods_is_undetermined_with_what_would_decide() -> None:
    # chaotic forced Duffing, but only 8 drive periods: no section, no surrogate verdict
    v = classify(duffing_x(0.5, 8), drive_period=DRIVE, rng=0)
    assert v.label == "undetermined" and np.isnan(v.confidence)
    assert v.n_cycles == pytest.approx(8, abs=0.5)
    assert v.needs[0] == "≥ 20 drive periods; the series has 8"
    assert v.votes["section"] == "neutral" and v.votes["lines"] == "neutral"
    assert v.summary()["needs"].startswith("≥ 20 drive periods")
    # the same oscillator in its period-2 window is decided from its line spectrum alone
    v = classify(duffing_x(0.28, 8), drive_period=DRIVE, rng=0)
    assert (v.label, v.period, v.needs) == ("periodic", 2, ())


def test_a_surrogate_test_on_too_short_a_series_cannot_call_noise() -> None:
    args = {"structure": _structure("too-few-points"), "rosenstein_positive": False,
            "wolf_positive": False, "zero_one_k": 1.0, "surrogates_rejected": False,
            "rule": RULE, "lines": "broadband"}  # fmt: skip
    label, _, _, _, votes, needs = _fields(_combine(**args, n_cycles=6, cycle_unit="drive periods"))
    assert label == "undetermined"
    assert votes["surrogates"] == "neutral" and votes["lines"] == "neutral"
    assert needs[0] == "≥ 20 drive periods; the series has 6"
    label, _, confidence, _, votes, needs = _fields(_combine(**args, n_cycles=40))
    assert label == "noise-like" and needs == ()
    # only the surrogate test and the spectrum could decide; the 0-1 test agrees
    assert votes["surrogates"] == "supports" and votes["lines"] == "supports"
    assert confidence == 1.0


def test_noise_needs_a_spectrum_that_is_not_lines() -> None:
    args = {"structure": _structure("scattered"), "rosenstein_positive": False,
            "wolf_positive": False, "zero_one_k": 0.5, "surrogates_rejected": False,
            "rule": RULE}  # fmt: skip
    assert _combine(**args, lines="unresolved").label == "undetermined"
    assert _combine(**args, lines=None).label == "undetermined"
    assert _combine(**args, lines="broadband").label == "noise-like"


def test_chaos_needs_regularity_ruled_out() -> None:
    args = {"rosenstein_positive": True, "wolf_positive": True, "zero_one_k": 1.0,
            "surrogates_rejected": True, "rule": RULE}  # fmt: skip
    assert _combine(structure=_structure("scattered"), lines="broadband", **args).label == "chaotic"
    # a broadband spectrum over enough cycles rules regular motion out without a section
    few = _structure("too-few-points")
    assert _combine(structure=few, lines="broadband", **args).label == "chaotic"
    # ... over too few, it does not
    label, *_, needs = _fields(_combine(structure=few, lines="broadband", n_cycles=12, **args))
    assert label == "undetermined" and needs == ("≥ 20 characteristic times; the series has 12",)
    # an unresolved spectrum needs the section
    label, *_, needs = _fields(_combine(structure=few, lines="unresolved", **args))
    assert label == "undetermined" and needs == ("≥ 20 section points; the section has 50",)
    assert (
        _combine(structure=_structure("scattered"), lines="unresolved", **args).label == "chaotic"
    )
    assert _combine(structure=_structure("scattered"), lines="periodic", **args).label == "periodic"


def test_needs_name_the_estimates_that_fell_short() -> None:
    label, *_, needs = _fields(_combine(
        structure=_structure("scattered"), rosenstein_positive=False, wolf_positive=None,
        zero_one_k=1.0, surrogates_rejected=True, rule=RULE, lines="broadband",
    ))  # fmt: skip
    assert label == "undetermined"
    assert any("clearly positive Rosenstein exponent" in s for s in needs)
    assert any("Wolf exponent (the estimator failed" in s for s in needs)


# ----------------------------------------------------------------- regular first


def test_period_three_logistic_as_map_and_as_sampled_signal() -> None:
    x = systems.logistic(4000, r=3.83)
    for kwargs in ({}, {"dt": 1.0}):
        v = classify(x, rng=1, **kwargs)
        assert (v.label, v.period) == ("periodic", 3), v.reason
        assert v.lines.method == "recurrence" and v.lines.period_samples == 3
        assert v.votes["lines"] == "supports" and v.needs == ()


def test_recurrence_survives_measurement_noise() -> None:
    g = np.random.default_rng(3)
    x = systems.logistic(3000, r=3.5)
    noisy = x + 0.01 * np.std(x) * g.standard_normal(x.size)  # 40 dB
    res = line_spectrum(noisy)
    assert (res.kind, res.period_samples) == ("periodic", 4)
    assert res.residual_fraction == pytest.approx(1e-4, rel=0.2)  # the noise, nothing else
    assert classify(noisy, rng=0).period == 4
    chaotic = line_spectrum(systems.logistic(3000, r=3.9))
    assert chaotic.kind == "broadband" and chaotic.residual_fraction > 0.5


@pytest.mark.parametrize("snr_db", [40.0, 20.0, 10.0])
def test_noisy_sine_is_a_line_and_white_noise(snr_db: float) -> None:
    g = np.random.default_rng(int(snr_db))
    x = np.sin(2 * np.pi * 0.2 * np.arange(3000) * 0.05)
    noise_frac = 10 ** (-snr_db / 10)
    noisy = x + np.sqrt(noise_frac) * np.std(x) * g.standard_normal(x.size)
    res = line_spectrum(noisy, dt=0.05)
    assert res.kind == "periodic" and res.maxima_per_period == 1
    np.testing.assert_allclose(res.fundamental_period, 5.0, rtol=1e-3)
    np.testing.assert_allclose(res.residual_fraction, noise_frac / (1 + noise_frac), rtol=0.15)
    assert res.white_p >= 1e-3


def test_relaxation_oscillation_many_harmonics() -> None:
    x = systems.van_der_pol(4000, dt=0.05, mu=5.0)[:, 0]
    res = line_spectrum(x, dt=0.05)
    assert res.kind == "periodic" and res.maxima_per_period == 1
    assert res.frequencies.size > 20  # the harmonics of a relaxation oscillation
    # the limit-cycle period of van der Pol at mu = 5: 11.61 (Strogatz, Fig. 7.5.3 scale)
    np.testing.assert_allclose(res.fundamental_period, 11.612, rtol=2e-3)


def test_ljung_box_accepts_white_and_rejects_coloured_noise() -> None:
    g = np.random.default_rng(0)
    e = g.standard_normal(4000)
    assert ljung_box_p(e) > 1e-3
    ar = np.empty_like(e)
    ar[0] = e[0]
    for i in range(1, e.size):
        ar[i] = 0.3 * ar[i - 1] + e[i]
    assert ljung_box_p(ar) < 1e-10


# ----------------------------------------------------------------- quasi-periodic


def test_three_frequency_torus_is_quasi_periodic() -> None:
    x = three_torus()
    res = line_spectrum(x, dt=0.05)
    assert res.kind == "quasi-periodic"
    truth = np.array([1.0, np.sqrt(2), np.sqrt(5)]) / (2 * np.pi)
    np.testing.assert_allclose(np.sort(res.base_frequencies), truth, rtol=1e-8)
    np.testing.assert_allclose(np.sort(res.amplitudes), [0.3, 0.6, 1.0], rtol=1e-6)
    v = classify(x, dt=0.05, rng=1)
    assert v.label == "quasi-periodic", v.reason
    assert v.votes["lines"] == "supports" and v.votes["section"] == "neutral"


def test_two_torus_with_noise_and_combination_lines() -> None:
    g = np.random.default_rng(5)
    t = np.arange(4000) * 0.05
    theta1, theta2 = 2 * np.pi * t, 2 * np.pi * (np.sqrt(5) - 1) / 2 * t
    # a point on a torus in R^3 seen through x: lines at f1 and f1 ± f2
    x = (2.0 + np.cos(theta2)) * np.cos(theta1)
    res = line_spectrum(x, dt=0.05)
    assert res.kind == "quasi-periodic" and res.frequencies.size == 3
    noisy = x + 0.01 * np.std(x) * g.standard_normal(x.size)
    assert line_spectrum(noisy, dt=0.05).kind == "quasi-periodic"
    assert classify(noisy, dt=0.05, rng=0).label == "quasi-periodic"


def test_commensurate_lines_are_periodic_not_quasi_periodic() -> None:
    t = np.arange(4000) * 0.05
    res = line_spectrum(np.sin(t) + 0.5 * np.sin(1.5 * t), dt=0.05)
    assert res.kind == "periodic"
    np.testing.assert_allclose(res.fundamental_period, 4 * np.pi, rtol=1e-6)


@pytest.mark.parametrize(
    ("make", "dt"),
    [(lambda: systems.rossler(4000, dt=0.1)[:, 0], 0.1),
     (lambda: systems.lorenz(4000, dt=0.01)[:, 0], 0.01)],
    ids=["rossler", "lorenz"],
)  # fmt: skip
def test_chaotic_flows_are_not_lines(make, dt: float) -> None:
    x = make()
    res = line_spectrum(x, dt=dt)
    assert res.kind == "broadband" and res.white_p < 1e-6
    g = np.random.default_rng(1)
    noisy = x + np.sqrt(0.1) * np.std(x) * g.standard_normal(x.size)  # 10 dB
    assert line_spectrum(noisy, dt=dt).kind == "broadband"


def test_a_broadband_spectrum_outweighs_a_regular_looking_section() -> None:
    args = {"rosenstein_positive": False, "wolf_positive": True, "zero_one_k": 0.5,
            "surrogates_rejected": True, "rule": RULE}  # fmt: skip
    # an unresolved spectrum (lines, yet not one period's harmonics) speaks against clusters
    unresolved = _combine(structure=_structure("clusters", 1), lines="unresolved", **args)
    assert unresolved.label == "undetermined"
    assert _combine(structure=_structure("closed-curve", 1), lines="unresolved",
                   **args).label == "quasi-periodic"  # fmt: skip
    for kind, label in (("clusters", "periodic"), ("closed-curve", "quasi-periodic")):
        assert _combine(structure=_structure(kind, 1), lines="broadband", n_cycles=8,
                       **args).label == label  # fmt: skip
        out, *_, needs = _fields(_combine(structure=_structure(kind, 1), lines="broadband", **args))
        assert out == "undetermined"
        assert needs[0] == (f"a longer series: the section looks regular ({kind}) but the "
                            "spectrum is not lines")  # fmt: skip
        # ... nor against chaos, when two exponents and the surrogate test say chaotic;
        # the section's vote lowers the confidence
        label, _, conf, _, votes, _ = _fields(
            _combine(
                structure=_structure(kind, 1),
                lines="broadband",
                **{**args, "rosenstein_positive": True},
            )
        )
        assert label == "chaotic" and votes["section"] == "opposes" and conf < 1.0


def impact_orbit(n_periods: int, *, spp: int = 100, period: int = 1, seed: int = 0) -> np.ndarray:
    """A forced impact-like response: within each drive period the signal rebounds off a
    wall (|sin| kinks and a short decaying ring), so its harmonics reach the Nyquist
    frequency — more than lines can be extracted. ``period`` > 1 alternates the rebound
    height, a period-``period`` orbit of the drive."""
    phase = np.arange(n_periods * spp) / spp  # drive periods
    cycle = np.floor(phase).astype(int)
    frac = phase - cycle
    height = 1.0 + 0.3 * (cycle % period)
    ring = np.exp(-frac * 25.0) * np.sin(2 * np.pi * 9.0 * frac)
    return height * np.abs(np.sin(np.pi * frac)) ** 0.5 + 0.2 * ring


@pytest.mark.parametrize("period", [1, 2, 3])
def test_a_forced_impact_orbit_repeats_after_whole_drive_periods(period: int) -> None:
    """Sampled a whole number of times per drive period, a forced orbit with harmonics up to
    the Nyquist frequency is found by folding at k drive periods (line extraction leaves it
    unresolved: more harmonics than lines)."""
    x = impact_orbit(60, period=period)
    res = line_spectrum(x, dt=0.01, drive_period=1.0, fold=False)
    assert res.kind == "periodic" and res.method == "drive recurrence"
    np.testing.assert_allclose(res.fundamental_period, period, rtol=1e-12)
    assert res.residual_fraction < 1e-20
    v = classify(x, dt=0.01, drive_period=1.0, rng=0)
    assert (v.label, v.period) == ("periodic", period)


def test_drive_recurrence_takes_white_measurement_noise_but_not_drift() -> None:
    x = impact_orbit(60, period=2)
    noisy = x + 0.02 * np.random.default_rng(3).standard_normal(x.size)
    res = line_spectrum(noisy, dt=0.01, drive_period=1.0, fold=False)
    assert res.kind == "periodic" and res.fundamental_period == pytest.approx(2.0)
    # a drive period that is not a whole number of samples over the record is not folded
    # (its phase would slip by more than 1 % of a sample by the end)
    from chaoskit.verdict._line_spectrum import samples_per_drive_period

    assert samples_per_drive_period(1.0, 0.01, 6000) == 100
    assert samples_per_drive_period(1.0 + 1e-5, 0.01, 6000) is None
    # a slow drift of the orbit (a transient not yet over) is neither nothing nor white
    drift = x * (1.0 + 0.05 * np.exp(-np.arange(x.size) / 2000.0))
    res = line_spectrum(drift, dt=0.01, drive_period=1.0, fold=False)
    assert res.method != "drive recurrence"


def test_a_chaotic_forced_flow_does_not_fold() -> None:
    ds = duffing_x(0.5, 120)
    x = ds["x"].values
    dt = float(ds["time"][1] - ds["time"][0])
    res = line_spectrum(x, dt=dt, drive_period=DRIVE, fold=False)
    assert res.method != "drive recurrence" and res.kind != "periodic"


def test_kantz_referees_when_only_one_exponent_is_clearly_positive() -> None:
    # K between the thresholds: the 0–1 test cannot be the second witness
    args = {"zero_one_k": 0.5, "surrogates_rejected": True, "rule": RULE,
            "structure": _structure("scattered"), "lines": "broadband"}  # fmt: skip
    one = {"rosenstein_positive": True, "wolf_positive": False}
    # without the referee one exponent is not enough
    label, *_, needs = _fields(_combine(**one, **args))
    assert label == "undetermined" and any("Wolf" in n for n in needs)
    # the referee agreeing makes two: chaotic, and its vote counts
    label, _, conf, reason, votes, _ = _fields(_combine(**one, kantz_positive=True, **args))
    assert label == "chaotic" and reason.startswith("two of the three exponents")
    assert votes["kantz"] == "supports" and votes["wolf"] == "opposes"
    assert conf == pytest.approx(5 / 6)  # all but Wolf of: lines, section, 3 exponents, surr.
    # the referee disagreeing: undetermined, and both shortfalls are named
    label, *_, needs = _fields(_combine(**one, kantz_positive=False, **args))
    assert label == "undetermined"
    assert any("Wolf" in n for n in needs) and any("Kantz" in n for n in needs)


def test_the_zero_one_test_is_the_second_witness_only_where_nothing_looks_regular() -> None:
    """One clearly positive exponent and K ≥ rule.zero_one_chaotic make a chaotic label
    when noise is ruled out (surrogates reject), the section is scattered and the spectrum
    broadband over enough cycles; take away any one of these and it is undetermined."""
    base = {"rosenstein_positive": False, "wolf_positive": True, "kantz_positive": False,
            "zero_one_k": 0.95, "surrogates_rejected": True, "rule": RULE,
            "structure": _structure("scattered"), "lines": "broadband",
            "n_cycles": 100.0}  # fmt: skip
    label, _, conf, reason, votes, needs = _fields(_combine(**base))
    assert label == "chaotic" and needs == ()
    assert reason.startswith("the Wolf exponent is clearly positive and the 0–1 test")
    assert "K = 0.95" in reason
    # two of seven pieces disagree (Rosenstein, Kantz): the confidence says so
    assert votes["zero_one"] == "supports" and conf == pytest.approx(5 / 7)
    for change in (
        {"zero_one_k": RULE.zero_one_chaotic - 0.01},  # K does not say irregular
        {"zero_one_k": None},  # the 0–1 test failed
        {"wolf_positive": False},  # no exponent at all
        {"surrogates_rejected": False},  # noise not ruled out (then noise-like)
        {"structure": _structure("closed-curve")},  # the section looks regular
        {"structure": _structure("too-few-points")},  # the section cannot say
        {"lines": "unresolved"},  # the spectrum is not clearly broadband
        {"n_cycles": 19.0},  # too few cycles for the spectrum to rule out regularity
    ):
        label = _combine(**{**base, **change}).label
        assert label != "chaotic", change


def test_a_noisy_chaotic_map_is_decided_by_the_referee() -> None:
    """The logistic map at r = 3.9 with white noise at 20 dB SNR (N = 2000): Wolf's
    exponent is clearly positive, Rosenstein's is not (noise flattens its divergence curve
    at small separations), Kantz's averages over ε-neighbourhoods above the noise level and
    is: the verdict is chaotic (it was undetermined with Rosenstein alone as the second)."""
    x = systems.logistic(2000, r=3.9, discard=5000)
    x = x + np.std(x) * 10 ** (-20 / 20) * np.random.default_rng(7).standard_normal(x.size)
    v = classify(x, rng=1)
    assert v.rosenstein_positive is False and v.wolf_positive is True
    assert v.kantz_positive is True and v.kantz is not None
    assert v.label == "chaotic"
    # the Lyapunov exponent of the logistic map at r = 3.9 is 0.49 per iteration
    assert 0.3 < v.kantz.mle < 0.7


def test_the_referee_is_not_run_when_it_cannot_decide() -> None:
    v = classify(systems.logistic(2000, r=3.9, discard=5000), rng=1)  # both agree
    assert v.label == "chaotic" and v.kantz is None and "kantz" not in v.votes
    v = classify(np.random.default_rng(2).standard_normal(2000), rng=1)  # noise
    assert v.kantz is None


# ----------------------------------------------------------------- the rule's input and output


def test_rule_takes_an_evidence_object_and_returns_a_frozen_outcome() -> None:
    """The rule reads one evidence object and returns a frozen outcome, not a tuple."""
    evidence = RuleEvidence(
        structure=_structure("scattered"),
        rosenstein_positive=True,
        wolf_positive=True,
        zero_one_k=0.95,
        surrogates_rejected=True,
    )
    outcome = combine(evidence, RULE)
    assert isinstance(outcome, RuleOutcome)
    assert (outcome.label, outcome.period, outcome.needs) == ("chaotic", None, ())
    assert outcome.confidence == pytest.approx(1.0, abs=1e-12)
    assert outcome.votes["rosenstein"] == "supports"
    with pytest.raises(AttributeError):
        outcome.label = "periodic"  # type: ignore[misc]
    with pytest.raises(AttributeError):
        evidence.lines = "periodic"  # type: ignore[misc]
    with pytest.raises(TypeError, match="positional"):
        RuleEvidence(None, True, True, 0.9, True)  # type: ignore[misc]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            {"lines": "lines"},
            "lines must be one of 'periodic', 'quasi-periodic', 'broadband', 'unresolved' "
            "or None, got 'lines'",
        ),
        ({"lines_period": 0}, "lines_period must be None or ≥ 1, got 0"),
        ({"lines_bases": -1}, "lines_bases must be ≥ 0, got -1"),
        ({"n_cycles": float("nan")}, "n_cycles must be ≥ 0, got nan"),
    ],
)
def test_rule_evidence_rejects_what_the_rule_cannot_read(change: dict, message: str) -> None:
    base = {"structure": None, "rosenstein_positive": None, "wolf_positive": None,
            "zero_one_k": None, "surrogates_rejected": None}  # fmt: skip
    with pytest.raises(ValueError) as info:
        RuleEvidence(**base, **change)
    assert str(info.value) == message


def test_combine_names_a_wrong_argument() -> None:
    evidence = RuleEvidence(structure=None, rosenstein_positive=None, wolf_positive=None,
                            zero_one_k=None, surrogates_rejected=None)  # fmt: skip
    with pytest.raises(TypeError, match=r"^rule must be a VerdictRule, got dict$"):
        combine(evidence, {})  # type: ignore[arg-type]
    with pytest.raises(TypeError, match=r"^evidence must be a RuleEvidence, got dict$"):
        combine({}, RULE)  # type: ignore[arg-type]
