"""A stratified slice of the verdict corpus (``benchmarks/corpus.py``), N = 2000.

The whole corpus — with the ``dysts`` flows, the driven pendulum and N = 20 000 — runs in
``benchmarks/verdict_corpus.py``; here one or a few series of every family, generated from
their equations with numpy and scipy, so the default test run needs no optional package.
"""

from __future__ import annotations

import pytest

from benchmarks.corpus import DUFFING_KW, Case, true_period
from chaoskit import classify

N = 2000
DUFFING = DUFFING_KW

SLICE = [
    Case("logistic r=3.83", "window", "periodic", N, "logistic", {"r": 3.83}),
    Case("henon a=1.25", "window", "periodic", N, "henon", {"a": 1.25}),
    Case("duffing gamma=0.29", "window", "periodic", N, "duffing", {"gamma": 0.29}, DUFFING),
    Case("van der Pol mu=2", "window", "periodic", N, "van_der_pol", {"mu": 2.0, "dt": 0.2},
         {"dt": 0.2}),
    Case("logistic r=4", "chaos", "chaotic", N, "logistic", {"r": 4.0}),
    Case("henon a=1.4", "chaos", "chaotic", N, "henon", {"a": 1.4}),
    Case("lorenz", "chaos", "chaotic", N, "lorenz", {"dt": 0.03}, {"dt": 0.03}),
    Case("rossler", "chaos", "chaotic", N, "rossler", {"dt": 0.2}, {"dt": 0.2}),
    Case("two sines", "torus", "quasi-periodic", N, "torus",
         {"dt": 0.05, "form": "two sines"}, {"dt": 0.05}),
    Case("two-torus in R3 + 1%", "torus", "quasi-periodic", N, "torus",
         {"dt": 0.1, "form": "two-torus in R3", "snr_db": 40.0}, {"dt": 0.1}),
    Case("three-torus product", "torus", "quasi-periodic", N, "torus",
         {"dt": 0.1, "form": "three-torus product"}, {"dt": 0.1}),
    Case("white", "noise", "noise-like", N, "noise", {"kind": "white", "seed": 0}),
    Case("ar1=0.9", "noise", "noise-like", N, "noise", {"kind": "ar1=0.9", "seed": 1},
         {"dt": 0.01}),
    Case("1/f", "noise", "noise-like", N, "noise", {"kind": "1/f", "seed": 0}),
    Case("random-walk increments", "noise", "noise-like", N, "noise",
         {"kind": "random-walk increments", "seed": 1}, {"dt": 0.01}),
    Case("van der Pol at 20 dB", "noisy", "periodic", N, "van_der_pol",
         {"mu": 1.0, "dt": 0.2, "snr_db": 20.0, "seed": 7}, {"dt": 0.2}),
    Case("duffing gamma=0.28 at 10 dB", "noisy", "periodic", N, "duffing",
         {"gamma": 0.28, "snr_db": 10.0, "seed": 7}, DUFFING),
    Case("lorenz at 20 dB", "noisy", "chaotic", N, "lorenz",
         {"dt": 0.03, "snr_db": 20.0, "seed": 7}, {"dt": 0.03}),
    Case("logistic r=3.9 at 40 dB", "noisy", "chaotic", N, "logistic",
         {"r": 3.9, "snr_db": 40.0, "seed": 7}),
]  # fmt: skip


@pytest.mark.parametrize("case", SLICE, ids=[c.name for c in SLICE])
def test_corpus_slice(case: Case) -> None:
    v = classify(case.make(), rng=case.seed(), **case.classify_kwargs)
    assert v.label == case.label, v.reason
    if case.label == "periodic":
        assert v.period == true_period(case.builder, case.params)
    if case.label != "chaotic":
        assert v.label != "chaotic"


def test_ground_truth_periods_come_from_the_equations() -> None:
    assert true_period("logistic", {"r": 3.83}) == 3
    assert true_period("henon", {"a": 1.25}) == 7
    assert true_period("duffing", {"gamma": 0.29}) == 4
    assert true_period("logistic", {"r": 3.9}) is None


def test_a_series_that_failed_to_build_is_remembered_and_not_retried(tmp_path, monkeypatch):
    from benchmarks import corpus, verdict_corpus

    calls = []

    def fails(n: int) -> None:
        calls.append(n)
        raise ValueError("does not integrate")

    monkeypatch.setitem(corpus.BUILDERS, "fails", fails)
    case = Case(name="broken", family="dysts", label="chaotic", n=100, builder="fails")
    first = verdict_corpus.run_case((case, str(tmp_path)))
    second = verdict_corpus.run_case((case, str(tmp_path)))
    assert first["status"] == "skipped: ValueError: does not integrate"
    assert second["status"] == "skipped: ValueError: does not integrate (in an earlier run)"
    assert calls == [100]  # the second run read the reason and did not build again
