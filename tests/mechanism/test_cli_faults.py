"""mechanism CLI on everyday mistakes: the output is checked before any simulation."""

from __future__ import annotations

import errno
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from mechanism import cli as mechanism_cli
from mechanism.cli import app

runner = CliRunner()


@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args, **kwargs):
        raise AssertionError("the output should have been refused before simulating")

    monkeypatch.setattr(mechanism_cli, "simulate", refuse)
    monkeypatch.setattr(mechanism_cli, "predict_wear", refuse)


def _bad_outputs(tmp_path: Path) -> dict[str, tuple[str, str]]:
    folder = tmp_path / "folder.nc"
    folder.mkdir()
    a_file = tmp_path / "notes.txt"
    a_file.write_text("x")
    return {
        "csv": (str(tmp_path / "out.csv"), "the output is netCDF"),
        "no suffix": (str(tmp_path / "out"), "the output is netCDF"),
        "folder": (str(folder), "is a folder"),
        "under a file": (str(a_file / "out.nc"), "is not a folder"),
    }


@pytest.mark.parametrize("case", ["csv", "no suffix", "folder", "under a file"])
def test_simulate_and_wear_refuse_a_bad_output_before_running(
    tmp_path: Path, no_simulation: None, case: str
) -> None:
    output, message = _bad_outputs(tmp_path)[case]
    for command in (
        ["simulate", "slider-crank", "-o", output],
        ["wear", "paper", "-o", output, "--updates", "1", "--cycles-per-update", "10"],
    ):
        out = runner.invoke(app, command)
        assert out.exit_code == 2, out.output
        assert out.stderr.count("\n") == 1 and message in out.stderr
        assert "Traceback" not in out.output


def _fake_run() -> xr.Dataset:
    t = np.arange(10) * 0.1
    ds = xr.Dataset(
        {"crank_angle": ("time", t, {"units": "rad", "long_name": "crank angle"})},
        coords={"time": t},
        attrs={
            "t_end": 0.9,
            "solver_steps": 9,
            "solver_rejected_steps": 0,
            "solver_contact_events": 0,
            "solver_wall_time": 0.0,
            "ideal_solver_wall_time": 0.0,
        },
    )
    return chaoskit.validate_trajectory(ds, fill_attrs=True)


def test_simulate_write_failure_is_one_line_and_exit_1(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(mechanism_cli, "simulate", lambda *a, **k: _fake_run())

    def full(ds, path):
        raise OSError(errno.ENOSPC, "not enough free space")

    monkeypatch.setattr(chaoskit, "save_trajectory", full)
    out = runner.invoke(app, ["simulate", "slider-crank", "-o", str(tmp_path / "run.nc")])
    assert out.exit_code == 1, out.output
    assert out.stderr.count("\n") == 1 and "not enough free space" in out.stderr
    monkeypatch.undo()
    monkeypatch.setattr(mechanism_cli, "simulate", lambda *a, **k: _fake_run())
    out = runner.invoke(app, ["simulate", "slider-crank", "-o", str(tmp_path / "new" / "run.nc")])
    assert out.exit_code == 0, out.output
    assert chaoskit.load_trajectory(tmp_path / "new" / "run.nc").sizes["time"] == 10


def test_simulate_prints_a_deep_penetration_as_one_warning_line(tmp_path: Path) -> None:
    out = runner.invoke(
        app,
        ["simulate", "slider-crank-clearance", "--set", "joints.B.clearance=1e-7",
         "--no-progress", "-o", str(tmp_path / "run.nc")],
    )  # fmt: skip
    assert out.exit_code == 0, out.output
    lines = out.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("Warning: joint B: the largest penetration")
