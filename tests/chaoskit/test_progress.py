"""Long analyses show which variable and estimator are running; library calls stay silent."""

from __future__ import annotations

import pytest

import chaoskit
from chaoskit import _progress

CHEAP = chaoskit.VerdictRule(alpha=0.25)  # 3 surrogates reach it; progress is the point here
HENON = chaoskit.load_trajectory(chaoskit.systems.henon(400), step="step", variables=["x", "y"])


def test_analysis_progress_counts_every_estimator_of_every_variable(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setattr(_progress, "PROGRESS_DELAY", 0.0)
    chaoskit.classify_variables(HENON, rng=0, n_surrogates=3, rule=CHEAP, progress=True)
    err = capsys.readouterr().err
    assert "analyze" in err and "12/12" in err  # 2 variables × 6 estimators


def test_estimators_report_their_stage_only_inside_an_analysis(
    capsys: pytest.CaptureFixture[str],
) -> None:
    x = HENON["x"].values
    chaoskit.lyapunov_rosenstein(x)  # no active bar: silent
    chaoskit.classify_variables(HENON, rng=0, n_surrogates=3, rule=CHEAP, progress=False)
    assert capsys.readouterr().err == ""


def test_the_stage_bar_names_the_running_estimator(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_progress, "PROGRESS_DELAY", 0.0)
    postfixes: list[str] = []
    with _progress.stage_bar(1, desc="analyze") as bar:
        monkeypatch.setattr(bar, "set_postfix_str", lambda s, refresh=True: postfixes.append(s))
        chaoskit.classify(HENON["x"], rng=0, n_surrogates=3, rule=CHEAP)
        assert bar.n == len(_progress.STAGES)
    assert postfixes == list(_progress.STAGES)
