"""``chaoskit report FILE ... --var ... -o report.html`` writes the page and its twin."""

from __future__ import annotations

import re

import pytest
from typer.testing import CliRunner

import chaoskit
from chaoskit.cli import app
from tests.chaoskit.test_report import _trajectory

runner = CliRunner()


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli")
    before, after = folder / "before.nc", folder / "after.nc"
    chaoskit.save_trajectory(_trajectory(0.28, 50, wear="before"), before)
    chaoskit.save_trajectory(_trajectory(0.5, 80, wear="after"), after)
    reference = folder / "paper-chaos.csv"
    reference.write_text(
        "# the paper's chaos table (X motion)\n"
        "variable,state,lag,embedding_dim,mle_wolf_bits\n"
        "X,before wear,24,5,0.001\nX,after wear,24,6,0.0042\n",
        encoding="utf-8",
    )
    return folder, before, after, reference


def test_report_command_writes_html_and_markdown(files) -> None:
    folder, before, after, reference = files
    out = folder / "study" / "report.html"
    result = runner.invoke(
        app,
        [
            "report",
            str(before),
            str(after),
            "--var",
            "X=eccentricity_x[joint=C]",
            "--label",
            "before wear",
            "--label",
            "after wear",
            "--phase-variable",
            "crank_angle",
            "--chaos-reference",
            str(reference),
            "--title",
            "CLI study",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    row = next(line for line in lines if line.startswith("X "))
    assert row.split()[1:] == ["periodic", "(period", "2)", "chaotic"]
    assert f"report: {out}" in result.output
    html = out.read_text(encoding="utf-8")
    md = out.with_suffix(".md").read_text(encoding="utf-8")
    assert "<title>CLI study</title>" in html and md.startswith("# CLI study")
    n_figures = html.count('src="data:image/png;base64,')
    assert n_figures == 3  # phase portrait, stroboscopic map, divergence of X
    assert len(list((folder / "study" / "report_figures").glob("*.png"))) == n_figures
    # the reference values sit beside ours in both files
    for text in (html, md):
        assert "0.0042" in text and "difference (%)" in text
    assert re.search(r"\| X \| after wear \| lag \(samples\) \| \d+ \| 24 \| ", md)


def test_report_command_selects_with_sel_and_embeds_figures(files) -> None:
    folder, before, _, _ = files
    out = folder / "one.html"
    result = runner.invoke(
        app,
        [
            "report",
            str(before),
            "--var",
            "eccentricity_x",
            "--sel",
            "joint=A",
            "--drive-period",
            "5.235987755982989",
            "--embed-figures",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    md = out.with_suffix(".md").read_text(encoding="utf-8")
    assert md.count("](data:image/png;base64,") == 3
    assert not (folder / "one_figures").exists()
    assert "journal centre minus bearing centre, x (joint A)" in md


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--var", "eccentricity_x"], "extra dimensions"),
        (["--var", "eccentricity_x", "--sel", "joint"], "DIM=VALUE"),
        (["--var", "nope"], "not found"),
    ],
)
def test_report_command_reports_bad_input(files, args, message) -> None:
    folder, before, _, _ = files
    result = runner.invoke(app, ["report", str(before), *args, "-o", str(folder / "bad.html")])
    assert result.exit_code == 2
    assert message in result.output
    assert not (folder / "bad.html").exists()
