"""mechanism CLI on everyday mistakes: the output is checked before any simulation."""

from __future__ import annotations

import errno
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import mechanism
from chaoskit.cli import app as chaoskit_app
from mechanism.cli import _lyapunov, _paper, _simulate, _sweep, _wear, app

runner = CliRunner()


@pytest.fixture
def no_simulation(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args, **kwargs):
        raise AssertionError("the output should have been refused before simulating")

    # each command module calls the library through its own imported name
    for module, name in (
        (_simulate, "simulate"),
        (_wear, "predict_wear"),
        (_paper, "run_paper_study"),
        (_sweep, "bifurcation"),
        (_lyapunov, "lyapunov_exponent"),
    ):
        monkeypatch.setattr(module, name, refuse)


def _one_error_line(out, exit_code: int = 2) -> str:
    """The single stderr line of a refused command (no traceback, the exit status)."""
    assert out.exit_code == exit_code, out.output
    assert "Traceback" not in out.output
    assert out.exception is None or isinstance(out.exception, SystemExit)
    lines = out.stderr.splitlines()
    assert len(lines) == 1, out.stderr
    assert lines[0].startswith("Error: "), lines[0]
    return lines[0]


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
    monkeypatch.setattr(_simulate, "simulate", lambda *a, **k: _fake_run())

    def full(ds, path):
        raise OSError(errno.ENOSPC, "not enough free space")

    monkeypatch.setattr(chaoskit, "save_trajectory", full)
    out = runner.invoke(app, ["simulate", "slider-crank", "-o", str(tmp_path / "run.nc")])
    assert out.exit_code == 1, out.output
    assert out.stderr.count("\n") == 1 and "not enough free space" in out.stderr
    monkeypatch.undo()
    monkeypatch.setattr(_simulate, "simulate", lambda *a, **k: _fake_run())
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


# --- faults a run refuses: one line, exit status 2 ----------------------------------------


@pytest.mark.parametrize(
    ("options", "message"),
    [
        # grew to 24 GB and was killed
        (
            ["--set", "effects.wear=true", "--set", "joints.B.wear.regions=1000000000",
             "--set", "joints.B.wear.smoothing_regions=1"],
            "Error: joints.B.wear.regions: must be in [3, 36000]; got 1000000000",
        ),
        # "Maximum allowed dimension exceeded"
        (["--set", "joints.B.wear.regions=1e23"],
         "Error: joints.B.wear.regions: must be an integer in [3, 36000]; got 1e+23"),
        # sat at 0 % for more than ten minutes
        (["--set", "drive.speed_rpm=1e-9", "--revolutions", "0.1"],
         "Error: drive.speed_rpm: must be nonzero, with |speed_rpm| in [0.001, 1e+06]"),
        # validated, simulated, then failed at the write
        (["--set", 'name="crank\\u0000"'],
         "Error: name: must not contain control characters (U+0000 at position 5)"),
        # reported as a singular constraint Jacobian
        (["--set", "bodies.crank.mass=1e300"], "Error: bodies.crank.mass: must be in [1e-06, "),
        (["--set", "bodies.crank.inertia=1e-300"], "Error: bodies.crank.inertia: must be in "),
    ],
)  # fmt: skip
def test_scene_values_that_would_exhaust_or_mislead_are_refused(
    tmp_path: Path, no_simulation: None, options: list[str], message: str
) -> None:
    out = runner.invoke(
        app,
        ["simulate", "slider-crank-clearance", *options, "-o", str(tmp_path / "x.nc")],
    )
    assert _one_error_line(out).startswith(message)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        # numpy's "Maximum allowed size exceeded"
        (["--set", "solver.output_step=1e-300"],
         "Error: the output grid would hold 1.2e+298 samples (revolutions = 1 at "
         "drive.speed_rpm = 5000, 0.012 s, at solver.output_step = 1e-300 s)"),
        # a MemoryError traceback
        (["--revolutions", "1e6"], "Error: the output grid would hold 1e+10 samples"),
        (["--set", "solver.max_step=1e-13"], "Error: the run would take at least 1.2e+11 steps"),
        # bad option values ended with exit status 1
        (["--revolutions", "0"], "Error: revolutions must be finite and > 0; got 0.0."),
        (["--revolutions", "nan"], "Error: revolutions must be finite and > 0; got nan."),
        (["--rtol", "nan"], "Error: rtol must be finite and > 0; got nan."),
        (["--output-step", "-1"], "Error: output_step must be finite and > 0; got -1.0."),
        (["--record", "metrics", "--discard", "nan"],
         "Error: discard must be finite and >= 0; got nan."),
        (["--record", "everything"], "Error: record must be one of 'full', 'metrics', "),
        (["--var", "torque"], "Error: variables must be a non-empty list of names from "),
        (["--discard", "1"],
         "Error: --discard applies to --record metrics and sections; slice the full trajectory."),
        (["--record", "sections", "--var", "crank_angle"],
         "Error: --var applies to --record full only; got --record sections."),
    ],
)  # fmt: skip
def test_bad_run_options_exit_2_with_one_line(
    tmp_path: Path, options: list[str], message: str
) -> None:
    out = runner.invoke(
        app, ["simulate", "slider-crank-clearance", *options, "-o", str(tmp_path / "x.nc")]
    )
    assert _one_error_line(out).startswith(message)
    assert not (tmp_path / "x.nc").exists()


class _Memory:
    def __init__(self, available: float) -> None:
        self.available = int(available)


def test_a_run_larger_than_the_memory_is_refused_unless_forced(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # 62.6 GB on a 23 GB machine: a warning, then the machine ran out of memory
    monkeypatch.setattr(mechanism.simulate.__globals__["psutil"], "virtual_memory",
                        lambda: _Memory(23e9))  # fmt: skip
    args = ["simulate", "paper", "--revolutions", "3000", "--set", "effects.flexibility=false"]
    out = runner.invoke(app, [*args, "-o", str(tmp_path / "x.nc")])
    line = _one_error_line(out)
    assert line.startswith("Error: this run would hold about 62.9 GB (3e+07 samples")
    assert "18.4 GB it may use (80% of the 23 GB of memory available)" in line
    assert "output_step >= 0.00014 s (--output-step)" in line
    assert "(--var; light samples only); record='metrics' or 'sections' (--record)" in line
    assert line.endswith("force=True (--force) runs it anyway.")
    # forced: a small run on a machine that seems to have no memory left
    monkeypatch.setattr(mechanism.simulate.__globals__["psutil"], "virtual_memory",
                        lambda: _Memory(5e4))  # fmt: skip
    small = ["simulate", "slider-crank", "--revolutions", "0.02", "--no-progress"]
    out = runner.invoke(app, [*small, "-o", str(tmp_path / "y.nc")])
    assert _one_error_line(out).startswith("Error: this run would hold about 0.")
    out = runner.invoke(app, [*small, "--force", "-o", str(tmp_path / "y.nc")])
    assert out.exit_code == 0, out.output
    assert chaoskit.load_trajectory(tmp_path / "y.nc").sizes["time"] == 201
    out = runner.invoke(app, [*small, "--var", "slider_position", "-o", str(tmp_path / "z.nc")])
    assert out.exit_code == 0, out.output
    assert list(chaoskit.load_trajectory(tmp_path / "z.nc").data_vars) == ["slider_position"]


def test_paper_refuses_an_output_that_is_no_folder_before_running(
    tmp_path: Path, no_simulation: None
) -> None:
    a_file = tmp_path / "afile.txt"
    a_file.write_text("x")
    out = runner.invoke(app, ["paper", "--quick", "-o", str(a_file)])
    assert _one_error_line(out) == f"Error: -o {a_file}: {a_file} is not a folder."
    out = runner.invoke(app, ["paper", "--quick", "-o", str(a_file / "report")])
    assert _one_error_line(out) == f"Error: -o {a_file / 'report'}: {a_file} is not a folder."


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs a /proc file system")
def test_outputs_under_proc_are_refused_before_running(no_simulation: None) -> None:
    # ended in FileNotFoundError / NotADirectoryError tracebacks; root passes os.access
    # on /proc, so the check creates a file
    for command in (
        ["paper", "--quick", "-o", "/proc/nope"],
        ["simulate", "slider-crank", "-o", "/proc/nope.nc"],
        ["lyapunov", "slider-crank-clearance", "-o", "/proc/nope.nc"],
        ["bifurcation", "slider-crank-clearance", "--param", "drive.speed_rpm", "--values",
         "1000,2000", "-o", "/proc/nope.nc"],
        ["bifurcation", "slider-crank-clearance", "--param", "drive.speed_rpm", "--values",
         "1000,2000", "--store", "/proc/nope"],
        ["bifurcation", "slider-crank-clearance", "--param", "drive.speed_rpm", "--values",
         "1000,2000", "--figure", "/proc/nope.png"],
        ["sweep", "slider-crank-clearance", "--grid", "drive.speed_rpm=1000", "--store",
         "/proc/nope"],
    ):  # fmt: skip
        out = runner.invoke(app, command)
        assert "/proc/nope" in _one_error_line(out) and "is not writable" in out.stderr, command


@pytest.mark.parametrize(
    ("command", "message"),
    [
        (["lyapunov", "slider-crank-clearance", "-o", "run.csv"], "the output is netCDF"),
        (["bifurcation", "slider-crank-clearance", "--param", "drive.speed_rpm", "--values",
          "1000,2000", "-o", "orbit.txt"], "the output is netCDF"),
    ],
)  # fmt: skip
def test_every_command_with_an_output_checks_it_before_running(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, no_simulation: None, command, message
) -> None:
    monkeypatch.chdir(tmp_path)
    out = runner.invoke(app, command)
    assert message in _one_error_line(out)


def test_wear_reports_a_bad_value_with_exit_2(tmp_path: Path) -> None:
    out = runner.invoke(
        app,
        ["wear", "slider-crank-clearance", "-o", str(tmp_path / "w.nc"), "--updates", "1",
         "--cycles-per-update", "10", "--max-depth-increment", "nan", "--no-progress"],
    )  # fmt: skip
    assert "max_depth_increment" in _one_error_line(out)


@pytest.mark.parametrize(
    ("command", "fragments"),
    [
        (["bifurcation", "--help"],
         ["--exponent-revolutions <float>", "(tcp://host:8786)", "--exponent  "]),
        (["paper", "--help"], ["--quick  ", "(tcp://host:8786)", "--keep-trajectories  "]),
        (["simulate", "--help"], ["--force  ", "--var <"]),
        (["--help"], ["Predict the worn profile (cycle extrapolation) and write it with the "
                      "worn scene."]),
    ],
)  # fmt: skip
def test_help_is_shown_in_full_with_flags_as_flags(command: list[str], fragments) -> None:
    out = runner.invoke(app, command)
    assert out.exit_code == 0, out.output
    for fragment in fragments:
        assert fragment in out.output, out.output
    assert "<bool>" not in out.output and "…" not in out.output  # no value type, nothing cut
    assert not any(line.rstrip().endswith("...") for line in out.output.splitlines()[1:])
    assert max(len(line) for line in out.output.splitlines()) <= 100


def test_the_chaoskit_command_line_shows_help_in_full_and_exits_2_on_a_bad_period() -> None:
    # the chaoskit CLI had the same cut rich panels and "<bool>" flags; a drive period of
    # nan made every variable's analysis fail and the command exit 1 after the analysis
    for command in (["--help"], ["analyze", "--help"], ["report", "--help"]):
        out = runner.invoke(chaoskit_app, command)
        assert out.exit_code == 0, out.output
        assert "<bool>" not in out.output and "…" not in out.output
        assert max(len(line) for line in out.output.splitlines()) <= 100
    sample = str(chaoskit.sample_path("lorenz.nc"))
    for period in ("nan", "-1"):
        out = runner.invoke(chaoskit_app, ["analyze", sample, "--drive-period", period])
        assert out.exit_code == 2, out.output
        assert out.stderr == f"error: --drive-period must be finite and > 0; got {float(period)}.\n"


def test_help_lists_the_commands_in_a_fixed_order() -> None:
    """The order does not depend on which command module imports which first."""
    out = runner.invoke(app, ["--help"])
    assert out.exit_code == 0, out.output
    listed = out.output.split("Commands:")[1].splitlines()
    names = [line.split()[0] for line in listed if line.startswith("  ")]
    assert names[:10] == [
        "scenes", "show", "simulate", "wear", "wear-life", "convergence", "sweep",
        "bifurcation", "paper", "lyapunov",
    ]  # fmt: skip
