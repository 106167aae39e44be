"""The chaoskit CLI: analyze prints a table and writes figures; demo analyses the sample."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from chaoskit import systems
from chaoskit.cli import app
from tests.chaoskit.test_cli_faults import stub_analysis

runner = CliRunner()


def _henon_file(tmp_path) -> str:
    xy = systems.henon(800)
    ds = xr.Dataset(
        {
            "x": ("step", xy[:, 0], {"units": "1", "long_name": "Hénon x"}),
            "y": ("step", xy[:, 1], {"units": "1", "long_name": "Hénon y"}),
        },
        coords={"step": np.arange(800)},
    )
    chaoskit.validate_trajectory(ds, fill_attrs=True)
    path = tmp_path / "henon.nc"
    chaoskit.save_trajectory(ds, path)
    return str(path)


def test_analyze_prints_a_table_and_writes_figures(tmp_path) -> None:
    figures = tmp_path / "figs"
    out = runner.invoke(app, ["analyze", _henon_file(tmp_path), "--var", "x", "--figures",
                              str(figures)])  # fmt: skip
    assert out.exit_code == 0, out.output
    lines = out.output.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("variable"))
    assert "verdict" in lines[header] and "MLE Rosenstein (per iteration)" in lines[header]
    assert lines[header + 2].split()[:2] == ["x", "chaotic"]
    written = sorted(p.name for p in figures.glob("*.png"))
    assert written == [
        "x_divergence_rosenstein.png",
        "x_divergence_wolf.png",
        "x_false_nearest_neighbors.png",
        "x_mutual_information.png",
        "x_poincare.png",
    ]  # a map has no phase portrait
    assert all((figures / name).stat().st_size > 1000 for name in written)


def test_analyze_several_variables(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _henon_file(tmp_path), "--var", "x", "--var", "y"])
    assert out.exit_code == 0, out.output
    rows = [line.split()[0] for line in out.output.splitlines() if line.startswith(("x ", "y "))]
    assert rows == ["x", "y"]


def test_analyze_reports_bad_input(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _henon_file(tmp_path), "--var", "nope"])
    assert out.exit_code == 2 and "not found" in out.output
    out = runner.invoke(app, ["analyze", str(tmp_path / "missing.nc")])
    assert out.exit_code == 2


def test_demo_analyses_the_sample_file_from_any_folder(tmp_path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # the shipped sample is found wherever the user stands
    out = runner.invoke(app, ["demo"])
    assert out.exit_code == 0, out.output
    rows = {line.split()[0]: line.split()[1] for line in out.output.splitlines()
            if line[:2] in ("x ", "y ", "z ")}  # fmt: skip
    assert rows == {"x": "chaotic", "y": "chaotic", "z": "chaotic"}


def test_version_still_works() -> None:
    out = runner.invoke(app, ["--version"])
    assert out.exit_code == 0 and chaoskit.__version__ in out.output


def test_analyze_shows_the_motion_verdict_first(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _henon_file(tmp_path)])  # default: x and y together
    assert out.exit_code == 0, out.output
    lines = out.output.splitlines()
    motion = next(i for i, line in enumerate(lines) if line.startswith("Motion (x, y): "))
    header = next(i for i, line in enumerate(lines) if line.startswith("variable"))
    assert motion < header
    assert lines[motion].startswith("Motion (x, y): chaotic (confidence ")


def test_analyze_motion_none_or_one_variable_keeps_the_per_variable_table(tmp_path) -> None:
    path = _henon_file(tmp_path)
    for extra in (["--motion", "none"], ["--var", "x"], ["--motion", "x"]):
        out = runner.invoke(app, ["analyze", path, *extra])
        assert out.exit_code == 0, out.output
        assert "Motion (" not in out.output
    out = runner.invoke(app, ["analyze", path, "--motion", "x,nope"])
    assert out.exit_code == 2 and "not found" in out.output
    out = runner.invoke(app, ["analyze", path, "--motion", " , "])
    assert out.exit_code == 2 and "--motion" in out.output


def test_analyze_motion_sets_aside_a_drive_variable(tmp_path) -> None:
    t, s = systems.duffing(3000, gamma=0.5, samples_per_period=40)
    ds = chaoskit.load_trajectory(
        np.column_stack([s[:, 0], np.cos(1.2 * t)]), dt=t[1] - t[0], variables=["x", "phase"]
    )
    path = tmp_path / "duffing.nc"
    chaoskit.save_trajectory(ds, path)
    out = runner.invoke(app, ["analyze", str(path), "--motion", "x,phase",
                              "--drive-variable", "phase"])  # fmt: skip
    assert out.exit_code == 0, out.output
    assert "Motion (x, phase): chaotic" in out.output
    assert "following the drive alone: phase" in out.output


def _press_file(tmp_path, *, listed: bool) -> str:
    """A simulator-like file: the journal motion per joint, the crank angle, an ideal-mechanism
    copy and a constraint residual marked auxiliary, a constant angle and a slider speed."""
    t = np.arange(2000) * 0.001
    wave = np.stack([np.cos(2 * np.pi * 5 * t), np.cos(2 * np.pi * 7 * t)], axis=1)
    aux = {"coverage_content_type": "referenceInformation"}
    quality = {"coverage_content_type": "qualityInformation"}
    ds = xr.Dataset(
        {
            "crank_angle": ("time", 2 * np.pi * 5 * t, {"units": "rad"}),
            "eccentricity_x": (("time", "joint"), 1e-4 * wave, {"units": "m"}),
            "eccentricity_y": (("time", "joint"), 1e-4 * wave[:, ::-1], {"units": "m"}),
            "slider_position_ideal": ("time", np.sin(2 * np.pi * 5 * t), aux),
            "constraint_violation": ("time", 1e-9 * t, quality),
            "ground_angle": ("time", np.zeros(t.size), {"units": "rad"}),
            "slider_velocity": ("time", np.cos(2 * np.pi * 5 * t), {"units": "m s-1"}),
        },
        coords={"time": t, "joint": ["B", "C"]},
    )
    if listed:
        ds.attrs["motion_variables"] = "eccentricity_x eccentricity_y"
        ds.attrs["phase_variable"] = "crank_angle"
    path = tmp_path / ("listed.nc" if listed else "plain.nc")
    chaoskit.save_trajectory(ds, path)
    return str(path)


def test_analyze_defaults_to_the_variables_of_the_motion(tmp_path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    journal = ["eccentricity_x[joint=B]", "eccentricity_x[joint=C]",
               "eccentricity_y[joint=B]", "eccentricity_y[joint=C]"]  # fmt: skip
    out = runner.invoke(app, ["analyze", _press_file(tmp_path, listed=True)])
    assert out.exit_code == 0, out.output
    assert calls[-1][1] == journal
    assert f"series: {', '.join(journal)} (4 of 8: the motion variables the file names)" in (
        out.output
    )
    assert "others: --var NAME (repeat, or comma-separated); every series: --var all" in out.output
    assert "drive phase: crank_angle (the file's phase_variable attribute)" in out.output
    out = runner.invoke(app, ["analyze", _press_file(tmp_path, listed=False)])
    assert out.exit_code == 0, out.output
    assert calls[-1][1] == ["crank_angle", *journal, "slider_velocity"]
    assert ("(6 of 9: every series but the auxiliary constraint_violation, "
            "slider_position_ideal; 1 constant one left out)") in out.output  # fmt: skip
    out = runner.invoke(app, ["analyze", _press_file(tmp_path, listed=False), "--var", "all"])
    assert out.exit_code == 0, out.output
    assert len(calls[-1][1]) == 9 and "series:" not in out.output
    pick = "slider_velocity,eccentricity_x[joint=C]"
    out = runner.invoke(app, ["analyze", _press_file(tmp_path, listed=False), "--variables", pick])
    assert out.exit_code == 0, out.output
    assert calls[-1][1] == ["slider_velocity", "eccentricity_x[joint=C]"]


def test_analyze_discards_the_transient(tmp_path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    path = _press_file(tmp_path, listed=True)
    out = runner.invoke(app, ["analyze", path, "--discard", "0.5"])
    assert out.exit_code == 0, out.output
    assert "  1500 samples along 'time' after the first 0.5 s" in out.output
    assert float(calls[-1][0]["time"][0]) == pytest.approx(0.5, rel=1e-12)
    out = runner.invoke(app, ["analyze", path, "--discard", "5"])
    assert out.exit_code == 2
    assert out.stderr == "error: --discard 5 leaves 0 samples: the record spans 1.999 s.\n"
