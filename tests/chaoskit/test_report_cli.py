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
    # the console's text is on stdout; a progress bar (stderr) appears on a slow machine
    lines = result.stdout.splitlines()
    row = next(line for line in lines if line.startswith("X "))
    assert row.split()[1:] == ["periodic", "(period", "2)", "chaotic"]
    assert f"report: {out}" in result.stdout
    assert re.search(r"\(3 figure files\)$", lines[-1]) and "(s)" not in result.stdout
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


def test_report_command_prints_the_answer_before_the_files(files) -> None:
    """The console ends with the verdict of each state (its confidence with two decimals
    and λ₁ with its interval), then the paths of the written files."""
    folder, before, after, _ = files
    out = folder / "answer.html"
    args = ["report", str(before), str(after), "--phase-variable", "crank_angle"]
    args += ["--var", "X=eccentricity_x[joint=C]", "--var", "S=slider_position", "-o", str(out)]
    result = runner.invoke(app, [*args, "--label", "before wear", "--label", "after wear"])
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()  # without a progress bar's lines (stderr)
    head = lines.index("Motion verdict per state:")
    assert lines[head + 1].split() == ["verdict", "confidence", "λ₁", "[95", "%]", "λ₁", "from"]
    report_line = next(k for k, line in enumerate(lines) if line.startswith("report: "))
    rows = lines[head + 3 : report_line - 1]
    assert [r.split()[0:2] for r in rows] == [["before", "wear"], ["after", "wear"]]
    for row in rows:
        assert re.search(r"  (\d\.\d\d|—)  ", row), row
        assert re.search(r"\[\S+, \S+\] 1/s", row), row
    assert lines[report_line + 1].startswith("markdown: ")


def test_report_command_writes_hostile_names_as_text_in_both_files(files) -> None:
    """A variable name, state label and title that are markup print as text: escaped in
    the HTML, escaped in the Markdown twin (no raw tag, no extra table column)."""
    folder, before, _, _ = files
    out = folder / "hostile.html"
    name = "<script>alert(1)</script> | `x` *y*"
    result = runner.invoke(
        app,
        [
            "report",
            str(before),
            "--var",
            f"{name}=eccentricity_x[joint=C]",
            "--label",
            f"{name} state",
            "--title",
            f"{name} title",
            "--phase-variable",
            "crank_angle",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    page = out.read_text(encoding="utf-8")
    md = out.with_suffix(".md").read_text(encoding="utf-8")
    assert "<script" not in page and "&lt;script&gt;" in page
    assert "<script" not in md and "&lt;script&gt;alert(1)&lt;/script&gt; \\| \\`x\\` \\*y\\*" in md
    assert md.startswith("# &lt;script&gt;")
    verdicts = md.split("**Table 1.**")[1].split("\n\n")[1].splitlines()
    # variable | state: two cells, the escaped "|" in the name is no column separator
    assert len(verdicts) == 3 and len(re.split(r"(?<!\\)\|", verdicts[2])) == 4


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
