"""The measures toolbox through the CLI (``analyze --measures``) and the report."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from chaoskit import systems
from chaoskit._measure_registry import MEASURES, parse_measures
from chaoskit.cli import app

runner = CliRunner()
N = 3000


@pytest.fixture(scope="module")
def henon_file(tmp_path_factory) -> str:
    xy = systems.henon(N)
    ds = xr.Dataset(
        {"x": ("step", xy[:, 0], {"units": "1", "long_name": "Hénon x"})},
        coords={"step": np.arange(N)},
    )
    chaoskit.validate_trajectory(ds, fill_attrs=True)
    path = tmp_path_factory.mktemp("measures") / "henon.nc"
    chaoskit.save_trajectory(ds, path)
    return str(path)


def test_analyze_with_every_measure_prints_them_and_draws_them(henon_file, tmp_path) -> None:
    figures = tmp_path / "figs"
    out = runner.invoke(
        app, ["analyze", henon_file, "--measures", ",".join(MEASURES), "--figures", str(figures)]
    )
    assert out.exit_code == 0, out.output
    lines = out.output.splitlines()
    header = next(i for i, line in enumerate(lines) if line.lstrip().startswith("D2"))
    row = lines[header + 1]
    assert row.split()[0] == "x"

    def value(label: str) -> float:  # pandas right-aligns each value under its label
        end = lines[header].index(f" {label} ") + len(label) + 1
        return float(row[:end].split()[-1])

    for label in ("DET", "LAM", "SampEn", "DFA", "Hurst"):
        assert f" {label}" in lines[header], label
    d2 = value("D2")
    lam1 = value("λ1")
    assert d2 == pytest.approx(1.21, rel=0.1)  # Hénon's correlation dimension
    assert lam1 == pytest.approx(0.419, rel=0.1)  # and its largest exponent, per iteration
    for kind in ("local_slopes", "recurrence_plot", "lyapunov_spectrum"):
        assert (figures / f"x_{kind}.png").stat().st_size > 0, kind


def test_an_unknown_measure_is_a_user_error(henon_file) -> None:
    out = runner.invoke(app, ["analyze", henon_file, "--measures", "d2,lyap"])
    assert out.exit_code == 2
    assert "measures must be" in out.output and "lyap" in out.output
    assert "Traceback" not in out.output


def test_parse_measures() -> None:
    assert parse_measures("all") == MEASURES
    assert parse_measures(" d2 , RQA,d2") == ("d2", "rqa")
    assert parse_measures(None) == ()
    with pytest.raises(ValueError, match="measures must be"):
        parse_measures("d3")


def test_report_has_a_further_measures_section(henon_file, tmp_path) -> None:
    rep = chaoskit.report(
        [henon_file], variables=["x"], options=chaoskit.ReportOptions(measures=["d2", "rqa", "dfa"])
    )
    section = next(s for s in rep.sections if s.title == "Further measures")
    tables = [i for i in section.items if isinstance(i, chaoskit.ReportTable)]
    figures = [i for i in section.items if isinstance(i, chaoskit.ReportFigure)]
    assert len(tables) == 1 and len(figures) == 2
    data = tables[0].data
    assert data.loc[("x", "henon"), "d2"] == pytest.approx(1.21, rel=0.1)
    assert 0.0 < data.loc[("x", "henon"), "rqa_det"] <= 1.0
    written = rep.write(tmp_path / "r.html")
    assert "Further measures" in written["markdown"].read_text()


def test_report_command_takes_measures(henon_file, tmp_path) -> None:
    out = runner.invoke(
        app,
        ["report", henon_file, "--var", "x", "-o", str(tmp_path / "r.html"), "--measures", "dfa"],
    )
    assert out.exit_code == 0, out.output
    assert "DFA α" in (tmp_path / "r.md").read_text()
    bad = runner.invoke(
        app, ["report", henon_file, "--var", "x", "-o", str(tmp_path / "s.html"), "--measures", "x"]
    )
    assert bad.exit_code == 2 and "measures must be" in bad.output
