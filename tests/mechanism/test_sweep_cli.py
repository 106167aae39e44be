"""``mechanism sweep``: grid parsing, a serial and a local-cluster run, resume, errors."""

from __future__ import annotations

import pytest
import typer
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app, parse_grid_options

SCENE = ["slider-crank-clearance", "--set", "solver.output_step=2.4e-5"]


def test_parse_grid_options_reads_toml_literals():
    grid = parse_grid_options(
        ["joints.B.clearance=1e-4, 2e-4", "drive.speed_rpm=30,90", "wear=before,after"]
    )
    assert grid == {
        "joints.B.clearance": [1e-4, 2e-4],
        "drive.speed_rpm": [30, 90],
        "wear": ["before", "after"],
    }
    assert isinstance(grid["drive.speed_rpm"][0], int)
    for bad in ("joints.B.clearance", "=1,2", "joints.B.clearance=1e-4,,2e-4"):
        with pytest.raises(typer.BadParameter):
            parse_grid_options([bad])
    with pytest.raises(typer.BadParameter, match="given twice"):
        parse_grid_options(["wear=before", "wear=after"])


# The worn state of a 2-revolution slider-crank after one predicted update is a chaotic
# sample whose penetration passes the 50 % warning or not with the step sequence (fixed
# limits T/500, T/1000 and T/2000 give 23, 272 and 41 µm of c = 200 µm): the warning is
# not what this test is about, and as an error it would fail the point.
@pytest.mark.filterwarnings("default::mechanism.SimulationWarning")
def test_serial_sweep_from_the_command_line_and_resume(tmp_path):
    store = tmp_path / "store"
    args = [
        "sweep",
        *SCENE,
        "--grid",
        "joints.B.clearance=2e-4,5e-4",
        "--grid",
        "wear=before,after",
        "--store",
        str(store),
        "--revolutions",
        "2",
        "--scheduler",
        "serial",
        "--no-analysis",
        "--no-progress",
    ]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "4 points: 4 to run, 0 already done" in result.output
    # wear = "after" runs on the worn scene of predict_wear (issue 7)
    assert "4 points: 4 ok, 0 failed, 0 diverged" in result.output
    ds = mechanism.load_sweep(store)
    assert ds["status"].values.ravel().tolist() == ["ok"] * 4
    assert ds["peak_contact_force"].notnull().all()
    again = CliRunner().invoke(app, args)
    assert again.exit_code == 0, again.output
    assert "4 points: 0 to run, 4 already done" in again.output


def test_local_cluster_sweep_shows_progress(tmp_path):
    args = [
        "sweep",
        *SCENE,
        "--grid",
        "drive.speed_rpm=4000,5000",
        "--store",
        str(tmp_path / "store"),
        "--revolutions",
        "2",
        "--workers",
        "2",
        "--no-analysis",
    ]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "2 points: 2 ok, 0 failed, 0 diverged" in result.output
    assert "2/2" in result.output  # the tqdm bar over finished points (on stderr)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--grid", "joints.Z.clearance=1e-4"], "unknown key 'Z'"),
        (["--grid", "wear=middle"], "not accepted"),
        (["--grid", "wear=before", "--scheduler", "serial", "--workers", "2"], "not both"),
    ],
)
def test_bad_sweeps_exit_with_status_2(tmp_path, extra, message):
    args = ["sweep", *SCENE, "--store", str(tmp_path / "s"), "--no-progress", *extra]
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2
    assert message in result.output
    assert not (tmp_path / "s").exists()
