"""The chaoskit CLI: analyze prints a table and writes figures; demo analyses the sample."""

from __future__ import annotations

import numpy as np
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from chaoskit import systems
from chaoskit.cli import app

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
