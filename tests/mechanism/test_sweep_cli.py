"""``mechanism sweep``: grid parsing, a serial and a local-cluster run, resume, errors."""

from __future__ import annotations

import numpy as np
import pytest
import typer
import xarray as xr
from typer.testing import CliRunner

import mechanism
from mechanism.cli import SWEEP_REVOLUTIONS, app, parse_grid_options, sweep_table

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
    # wear = "after" runs on the worn scene of predict_wear
    assert "4 points: 4 ok, 0 failed, 0 diverged" in result.output
    # the result table: one row per point, before the tally
    lines = result.output.splitlines()
    head = next(i for i, line in enumerate(lines) if line.startswith("joints.B.clearance"))
    assert lines[head].split() == ["joints.B.clearance", "wear", "status", "peak", "contact",
                                   "force", "(N)"]  # fmt: skip
    rows = [line.split() for line in lines[head + 2 : head + 6]]
    assert [row[:3] for row in rows] == [
        ["0.0002", "before", "ok"],
        ["0.0002", "after", "ok"],
        ["0.0005", "before", "ok"],
        ["0.0005", "after", "ok"],
    ]
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


def test_sweep_table_shows_every_verdict_even_undetermined():
    # with the former default of 3 revolutions every point was undetermined and the
    # command printed only the tally
    ds = xr.Dataset(
        {
            "status": (("drive.speed_rpm",), ["ok", "ok", "failed"]),
            "motion_label": (("drive.speed_rpm",), ["chaotic", "undetermined", ""]),
            "motion_confidence": (("drive.speed_rpm",), [0.6667, np.nan, np.nan]),
            "peak_contact_force": (("drive.speed_rpm",), [4494.3, 6504.0, np.nan]),
        },
        coords={"drive.speed_rpm": [150.0, 5000.0, 9000.0]},
    )
    assert sweep_table(ds).splitlines() == [
        "drive.speed_rpm  status  verdict       confidence  peak contact force (N)",
        "---------------  ------  ------------  ----------  ----------------------",
        "150              ok      chaotic       0.667       4494",
        "5000             ok      undetermined  —           6504",
        "9000             failed  —             —           —",
    ]


def test_the_default_revolutions_leave_a_verdict_enough_drive_periods():
    # a verdict needs 20 drive periods and 20 section points after the discarded
    # revolution: 3 (the former default) and 10 (the documented example) leave too few
    assert SWEEP_REVOLUTIONS == 25.0
    out = CliRunner().invoke(app, ["sweep", "--help"])
    assert "[default: 25.0]" in out.output
    assert "a motion verdict needs at least 20 after --discard" in " ".join(out.output.split())
