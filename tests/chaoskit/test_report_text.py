"""What a report says agrees with itself, names its deciding evidence and cannot be injected.

Two states of a forced Duffing oscillator (γ = 0.28 period 2 "before", γ = 0.5 chaotic
"after"), its position X and velocity Y stored in m and m/s like a journal's displacement,
driven by a crank angle: one report with a motion verdict per state. The checks are
consistencies that hold whatever the rounding (the figure's points are the ones the verdict
counted, a mark sits exactly where a verdict voted against an estimate), plus the text of
the Markdown twin with hostile names, confidence formats and plurals.
"""

from __future__ import annotations

import html
import re
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from matplotlib.figure import Figure

import chaoskit
from chaoskit import plot, systems
from chaoskit.reporting import (
    CONFIDENCE_NOTE,
    Report,
    ReportCode,
    ReportFigure,
    ReportSection,
    ReportTable,
    answer_table,
    decided_by,
    markdown_text,
    parse_variable,
)
from chaoskit.reporting._analysis_tables import set_aside_marks

OMEGA = 1.2
PERIOD = 2 * np.pi / OMEGA
HOSTILE = "<script>alert(1)</script> | *b* `c` [d](javascript:e) & _f_"


def _duffing(gamma: float, n_periods: int) -> xr.Dataset:
    t, s = systems.duffing(n_periods * 25, gamma=gamma, samples_per_period=25, discard_periods=200)
    return chaoskit.load_trajectory(
        xr.Dataset(
            {
                "x": ("time", 1e-4 * s[:, 0], {"units": "m", "long_name": "journal x"}),
                "y": ("time", 1e-4 * s[:, 1], {"units": "m", "long_name": "journal y"}),
                "crank_angle": ("time", OMEGA * t, {"units": "rad", "long_name": "crank"}),
            },
            coords={"time": ("time", t, {"units": "s"})},
        )
    )


@pytest.fixture(scope="module")
def drawn():
    """The report, and every section set its stroboscopic-map figure drew (by panel)."""
    sections: list[xr.Dataset] = []
    real = plot.poincare

    def record(section, **kwargs):
        sections.append(section)
        return real(section, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(plot, "poincare", record)
        rep = chaoskit.report(
            {"before wear": _duffing(0.28, 60), "after wear": _duffing(0.5, 60)},
            variables={"X": "x", "Y": "y"},
            phase_variable="crank_angle",
            options=chaoskit.ReportOptions(display_units={"X": "mm"}, rng=0),
        )
    return rep, sections


# ------------------------------------------------------------------ counts agree


def test_section_figures_draw_exactly_the_points_the_verdicts_counted(drawn) -> None:
    """Each panel of the stroboscopic-map figures holds the points of its variable's
    verdict section (the evidence table's "section points"): the same instants, none
    more. The strobe of the whole series has more: its first point is the initial state
    (the crank angle starts at 0), which the verdict's delay embedding leaves out."""
    rep, sections = drawn
    states = list(rep.verdicts)
    assert len(sections) == 2 * len(states)  # X and Y, one panel per state
    evidence = rep.table("Evidence behind each verdict").data
    for k, sec in enumerate(sections):
        alias, state = ("X", "Y")[k // len(states)], states[k % len(states)]
        verdict = rep.verdicts[state][alias]
        assert sec.sizes["crossing"] == verdict.structure.n_points
        assert sec.sizes["crossing"] == evidence.at[(alias, state), "section_points"]
        np.testing.assert_allclose(
            sec["time"].values, verdict.section["time"].values, rtol=0, atol=1e-9 * PERIOD
        )
        # the strobe of the analysed series has more points than the verdict used
        whole = chaoskit.stroboscopic_map(_duffing_view(state), phase_variable="crank_angle")
        assert whole.sizes["crossing"] > sec.sizes["crossing"]


def _duffing_view(state: str) -> xr.Dataset:
    """The analysed series of a state (the whole of it: nothing is discarded)."""
    return _duffing(0.28 if state == "before wear" else 0.5, 60)


def test_display_units_convert_the_figures_only(drawn) -> None:
    rep, sections = drawn
    x_panel = sections[0]
    assert x_panel["X"].attrs["units"] == "mm"
    verdict = rep.verdicts["before wear"]["X"]
    view = _duffing_view("before wear")
    strobe = chaoskit.stroboscopic_map(view, phase_variable="crank_angle", coords=["x"])
    at = np.searchsorted(strobe["time"].values, x_panel["time"].values - 1e-9)
    np.testing.assert_allclose(x_panel["X"].values, 1e3 * strobe["x"].values[at], rtol=1e-12)
    # the exponents stay in 1/s, the analysis in SI
    assert verdict.dt == pytest.approx(PERIOD / 25, rel=1e-12)
    settings = rep.table("Analysis settings").data["value"]
    assert settings["display_units"] == '{"X": "mm"}'
    with pytest.raises(ValueError, match=r"display_units\['X'\] = 'kg': the accepted units"):
        chaoskit.report(
            {"a": _duffing(0.28, 5)},
            variables={"X": "x"},
            options=chaoskit.ReportOptions(display_units={"X": "kg"}),
        )
    with pytest.raises(ValueError, match="display_units names 'Z'"):
        chaoskit.report(
            {"a": _duffing(0.28, 5)},
            variables={"X": "x"},
            options=chaoskit.ReportOptions(display_units={"Z": "mm"}),
        )


# ------------------------------------------------------------------ the why, the marks


def test_motion_table_says_which_evidence_decided_in_one_line(drawn) -> None:
    rep, _ = drawn
    table = rep.table("The motion verdict")
    for state, mv in rep.motions.items():
        why = table.data.at[state, "why"]
        assert why == decided_by(mv) and "\n" not in why
        if mv.label != "undetermined":
            assert re.search(r" (agree|decides?)( over |$)", why), why
    assert table.notes == CONFIDENCE_NOTE


def test_estimates_a_verdict_voted_against_are_marked_set_aside(drawn) -> None:
    rep, _ = drawn
    table = rep.table("Chaos table")
    shown = table.display()
    expected = set()
    for state, per in rep.verdicts.items():
        for alias, v in per.items():
            for method in ("wolf", "rosenstein"):
                if v.label != "undetermined" and v.votes.get(method) == "opposes":
                    expected |= {((alias, state), f"mle_{method}{s}") for s in ("", "_bits")}
    assert set(table.marks) == expected
    for (row, col), mark in table.marks.items():
        assert mark == "†"
        label = table.labels[col]
        assert shown.loc[row, (label, "")].endswith(" †")
    if expected:
        assert "† set aside: the verdict of this variable and state did not follow" in table.notes


def test_a_periodic_row_with_a_clearly_positive_wolf_exponent_is_marked() -> None:
    """The case a reader met: periodic, Wolf clearly positive, nothing said."""
    periodic = SimpleNamespace(
        label="periodic", votes={"wolf": "opposes", "rosenstein": "supports"}
    )
    unsure = SimpleNamespace(label="undetermined", votes={"wolf": "opposes"})
    states = [
        SimpleNamespace(label="before wear", verdicts={"X": periodic}),
        SimpleNamespace(label="after wear", verdicts={"X": unsure}),
    ]
    marks = set_aside_marks(states, [parse_variable("X=x")])
    assert marks == {
        (("X", "before wear"), "mle_wolf"): "†",
        (("X", "before wear"), "mle_wolf_bits"): "†",
    }


def test_decided_by_names_the_winning_and_the_overruled_evidence() -> None:
    variables = {
        "X": SimpleNamespace(label="periodic"),
        "Y": SimpleNamespace(label="periodic"),
    }
    mv = SimpleNamespace(
        label="chaotic",
        reason="the variables disagree",
        voting=("X", "Y"),
        variables=variables,
        equations_say="chaotic",
        exponent_positive=False,
        structure=SimpleNamespace(kind="scattered", n_points=198),
        votes={
            "section": "supports",
            "exponent": "opposes",
            "equations": "supports",
            "variable X": "opposes",
            "variable Y": "opposes",
        },
    )
    assert decided_by(mv) == (
        "the exponent from the equations (interval above zero) and the joint section "
        "(scattered) decide over the joint exponent of the data estimators (not clearly "
        "positive) and the variables X, Y (periodic)"
    )
    agree = SimpleNamespace(
        **{**vars(mv), "label": "periodic", "equations_say": "regular"},
    )
    agree.structure = SimpleNamespace(kind="clusters", n_clusters=1, n_points=198)
    agree.votes = {"section": "supports", "equations": "supports", "variable X": "supports"}
    assert decided_by(agree) == (
        "the exponent from the equations (interval not above zero), the joint section "
        "(1 tight cluster) and the variable X (periodic) agree"
    )
    undecided = SimpleNamespace(label="undetermined", reason="needs ≥ 20\ndrive periods")
    assert decided_by(undecided) == "needs ≥ 20 drive periods"


# ------------------------------------------------------------------ confidence


def test_confidence_prints_with_two_decimals_in_every_table(drawn, tmp_path) -> None:
    rep, _ = drawn
    seen = 0
    for table in rep.tables:
        shown = table.display()
        for col in shown.columns:
            if col[0] != "confidence":
                continue
            for cell in shown[col]:
                assert cell == "—" or re.fullmatch(r"\d\.\d\d", cell), (table.caption, cell)
                seen += 1
        if table.layout == "long":  # one row per quantity
            rows = [k for k in shown.index if k[-1] == "confidence"]
            for key in rows:
                cell = shown.loc[key].iloc[0]
                assert cell == "—" or re.fullmatch(r"\d\.\d\d", cell), (table.caption, cell)
                seen += 1
    assert seen >= 2 * 2 + 2  # chaos table and evidence (2 variables × 2 states), motion
    md = rep.write(tmp_path / "r.html")["markdown"].read_text(encoding="utf-8")
    assert md.count(markdown_text(CONFIDENCE_NOTE, block=True)) == 1
    assert "not a probability" in CONFIDENCE_NOTE and "docs/verdict.md" in CONFIDENCE_NOTE


def test_answer_table_is_one_row_per_state_with_the_exponent_and_its_source(drawn) -> None:
    rep, _ = drawn
    frame = rep.answer_table()
    assert list(frame.index) == ["before wear", "after wear"]
    assert list(frame.columns) == ["verdict", "confidence", "λ₁ [95 %]", "λ₁ from"]
    for state, mv in rep.motions.items():
        assert frame.at[state, "verdict"].startswith(mv.label)
        assert frame.at[state, "λ₁ from"] == "data, joint embedding (Rosenstein)"
        assert frame.at[state, "λ₁ [95 %]"].endswith(" 1/s")
    eq = SimpleNamespace(
        label="chaotic",
        period=None,
        confidence=2 / 3,
        kind="forced",
        equations=SimpleNamespace(exponent=180.0, ci=(150.0, 210.0)),
        exponent=None,
        voting=("X",),
    )
    one = answer_table({"after wear": eq})
    assert one.loc["after wear"].tolist() == [
        "chaotic",
        "0.67",
        "180 [150, 210] 1/s",
        "equations of motion",
    ]


# ------------------------------------------------------------------ plurals


def test_no_count_is_written_with_a_parenthesised_plural(drawn, tmp_path) -> None:
    rep, _ = drawn
    written = rep.write(tmp_path / "p.html")
    for path in (written["html"], written["markdown"]):
        # the verdicts' own reasons are quoted as the estimators wrote them
        text = "\n".join(
            line
            for line in path.read_text(encoding="utf-8").splitlines()
            if "| reason |" not in line and '<th scope="row">reason</th>' not in line
        )
        assert not re.search(r"\w\(s\)", text), re.search(r".{40}\w\(s\).{20}", text)
    assert chaoskit.reporting.plural(1, "update") == "1 update"
    assert chaoskit.reporting.plural(2, "update") == "2 updates"


# ------------------------------------------------------------------ Markdown injection


def _hostile_report() -> Report:
    data = pd.DataFrame(
        {HOSTILE: [HOSTILE, "ok"]}, index=pd.Index([HOSTILE, "# not a heading"], name=HOSTILE)
    )
    fig = Figure(figsize=(2, 2))
    fig.subplots().plot([0, 1])
    section = ReportSection(
        title=HOSTILE,
        text="# " + HOSTILE,
        footer="- " + HOSTILE,
        items=(
            ReportTable(caption=HOSTILE, data=data, notes="1. " + HOSTILE),
            ReportFigure.from_matplotlib(fig, caption=HOSTILE, name=HOSTILE),
            ReportCode(caption=HOSTILE, text="<b>kept verbatim</b>", language="json<x>"),
        ),
    )
    return Report(title=HOSTILE, sections=(section,), created=HOSTILE)


def _shown(md: str) -> str:
    """What a Markdown viewer shows of escaped text: no backslash escapes, no entities."""
    return html.unescape(re.sub(r"\\(.)", r"\1", md))


def test_markdown_twin_prints_hostile_strings_as_text() -> None:
    md = _hostile_report().to_markdown()
    outside_code = md.split("```")[0]
    assert "<script" not in md and "<b>" not in outside_code
    assert "](javascript" not in md.replace("\\]", "")  # no live link
    assert "`c`" not in outside_code and "*b*" not in outside_code
    # every user string is still readable as itself
    assert _shown(markdown_text(HOSTILE)) == HOSTILE
    assert md.count("&lt;script&gt;alert(1)&lt;/script&gt;") >= 8
    # the table keeps its shape: a "|" in a name does not add a column
    rows = [line for line in md.splitlines() if line.startswith("| ")]
    widths = {len(re.split(r"(?<!\\)\|", line)) for line in rows}
    assert len(rows) == 4 and len(widths) == 1
    # text that starts a paragraph cannot open a heading or a list
    lines = md.splitlines()
    assert "\\# " + markdown_text(HOSTILE) in lines
    assert "\\- " + markdown_text(HOSTILE) in lines
    assert "1\\. " + markdown_text(HOSTILE) in lines
    assert "| # not a heading | ok |" in lines  # inside a cell "#" is plain text
    # code stays verbatim inside its fence; the fence's language is a plain word
    assert "```jsonx\n<b>kept verbatim</b>\n```" in md


def test_html_page_escapes_the_same_strings() -> None:
    page = _hostile_report().to_html()
    assert "<script>" not in page and "&lt;script&gt;" in page
    assert 'class="language-jsonx"' in page
