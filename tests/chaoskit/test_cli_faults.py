"""The chaoskit CLI on everyday mistakes: one line naming the problem, exit code 2.

Exit codes: 0 success; 2 bad input (nothing analysed); 1 when every variable failed.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from chaoskit.cli import app
from tests.conftest import REPO

runner = CliRunner()
HENON = chaoskit.systems.henon(600)


def _files(tmp_path: Path) -> dict[str, Path]:
    good = chaoskit.save_trajectory(
        chaoskit.load_trajectory(HENON[:, 0], dt=0.01), tmp_path / "good.nc"
    )
    truncated = tmp_path / "truncated.nc"
    truncated.write_bytes(good.read_bytes()[:2000])
    text_nc = tmp_path / "text.nc"
    text_nc.write_text("time,x\n0,1\n")
    bad_zip = tmp_path / "bad.npz"
    bad_zip.write_bytes(b"PK\x03\x04 definitely not a zip archive")
    folder = tmp_path / "folder.csv"
    folder.mkdir()
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("time,x\n0;1\n1 2 3\n")
    header_only = tmp_path / "header.csv"
    header_only.write_text("time,x\n")
    dupes = tmp_path / "dupes.csv"
    dupes.write_text("time,x,x\n0,1,2\n1,2,3\n")
    unknown = tmp_path / "data.xlsx"
    unknown.write_text("x")
    return {
        "missing": tmp_path / "absent.nc",
        "truncated": truncated,
        "text_nc": text_nc,
        "bad_zip": bad_zip,
        "folder": folder,
        "ragged": ragged,
        "header_only": header_only,
        "dupes": dupes,
        "unknown": unknown,
    }


EXPECTED = {
    "missing": "no such trajectory file",
    "truncated": "not a readable netCDF-4 file",
    "text_nc": "not a readable netCDF-4 file",
    "bad_zip": "not a readable npz file",
    "folder": "is a folder",
    "ragged": "cannot tell the column delimiter",
    "header_only": "no data rows",
    "dupes": "duplicate column names",
    "unknown": "unknown file format",
}


@pytest.mark.parametrize("case", sorted(EXPECTED))
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, case: str) -> None:
    path = _files(tmp_path)[case]
    for command in (["analyze", str(path)], ["demo", str(path)]):
        out = runner.invoke(app, command)
        assert out.exit_code == 2, (case, out.output)
        assert out.stderr.count("\n") == 1 and out.stderr.startswith("error: "), out.stderr
        assert EXPECTED[case] in out.stderr
        assert "Traceback" not in out.output


def test_report_bad_input_is_one_line_and_exit_2(tmp_path: Path) -> None:
    path = _files(tmp_path)["truncated"]
    out = runner.invoke(app, ["report", str(path), "--var", "x", "-o", str(tmp_path / "r.html")])
    assert out.exit_code == 2 and out.stderr.count("\n") == 1
    assert "not a readable netCDF-4 file" in out.stderr


def test_analyze_exits_1_when_every_variable_failed(tmp_path: Path) -> None:
    short = tmp_path / "short.csv"
    rows = "".join(f"{0.01 * i!r},{float(v)!r}\n" for i, v in enumerate(HENON[:50, 0]))
    short.write_text("time,x\n" + rows)
    out = runner.invoke(app, ["analyze", str(short)])
    assert out.exit_code == 1, out.output
    assert "the analysis failed for every variable (x)" in out.stderr


def test_analyze_takes_time_dt_and_step(tmp_path: Path) -> None:
    x = HENON[:, 0]
    no_time = tmp_path / "no_time.csv"
    no_time.write_text("x\n" + "".join(f"{float(v)!r}\n" for v in x))
    out = runner.invoke(app, ["analyze", str(no_time)])
    assert out.exit_code == 2 and "no time column" in out.stderr
    out = runner.invoke(app, ["analyze", str(no_time), "--dt", "0.5"])
    assert out.exit_code == 0, out.output
    assert "600 samples along 'time'" in out.output
    out = runner.invoke(app, ["analyze", str(no_time), "--step", "step"])
    assert out.exit_code == 0, out.output
    assert "600 samples along 'step'" in out.output
    assert "per iteration" in out.output
    secs = tmp_path / "secs.csv"
    secs.write_text("secs,x\n" + "".join(f"{0.1 * i!r},{float(v)!r}\n" for i, v in enumerate(x)))
    out = runner.invoke(app, ["analyze", str(secs), "--time", "secs"])
    assert out.exit_code == 0, out.output
    out = runner.invoke(app, ["analyze", str(secs), "--time", "nope"])
    assert out.exit_code == 2 and "time column 'nope' not found" in out.stderr


def test_sample_path_finds_every_sample_and_refuses_others() -> None:
    from chaoskit._samples import SAMPLES

    for name in SAMPLES:
        assert chaoskit.sample_path(name).is_file()
    with pytest.raises(ValueError, match=r"no sample named 'nope\.nc'"):
        chaoskit.sample_path("nope.nc")


def test_the_wheel_ships_every_sample(tmp_path: Path) -> None:
    """Build the wheel with the project's build backend and look inside."""
    pytest.importorskip("hatchling")
    import zipfile

    from chaoskit._samples import SAMPLES

    proc = subprocess.run(
        [sys.executable, "-m", "hatchling", "build", "-t", "wheel", "-d", str(tmp_path)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    (wheel,) = tmp_path.glob("*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    assert {f"chaoskit/data/{name}" for name in SAMPLES} <= names
    sizes = {i.filename: i.file_size for i in zipfile.ZipFile(wheel).infolist()}
    for name in SAMPLES:
        assert sizes[f"chaoskit/data/{name}"] == (REPO / "data" / name).stat().st_size


def _journal_file(tmp_path: Path) -> Path:
    """A driven 'press': eccentricity per joint (B periodic, C quasi-periodic) and the crank."""

    t = np.arange(4000) * 0.005
    e_b = np.cos(2 * np.pi * t)
    e_c = np.cos(2 * np.pi * t) + 0.5 * np.cos(2 * np.pi * np.sqrt(2) * t)
    ds = xr.Dataset(
        {
            "eccentricity_x": (("time", "joint"), np.stack([e_b, e_c], axis=1)),
            "crank_angle": ("time", 2 * np.pi * t),
        },
        coords={"time": t, "joint": ["B", "C"]},
    )
    return chaoskit.save_trajectory(ds, tmp_path / "press.nc")


def test_analyze_expands_or_selects_multi_dimensional_variables(tmp_path: Path) -> None:
    path = str(_journal_file(tmp_path))
    figures = tmp_path / "figs"
    out = runner.invoke(app, ["analyze", path, "--phase-variable", "crank_angle",
                              "--figures", str(figures)])  # fmt: skip
    assert out.exit_code == 0, out.output
    rows = [line.split()[0] for line in out.output.splitlines() if line.startswith("ecc")]
    assert rows[:2] == ["eccentricity_x[joint=B]", "eccentricity_x[joint=C]"]
    assert "crank_angle " not in out.output  # the drive angle is the phase, not a series
    assert all(p.parent == figures for p in tmp_path.rglob("*.png"))
    assert any("joint_C" in p.name for p in figures.glob("*.png"))
    out = runner.invoke(app, ["analyze", path, "--var", "eccentricity_x[joint=C]",
                              "--phase-variable", "crank_angle"])  # fmt: skip
    assert out.exit_code == 0, out.output
    rows = [line.split()[0] for line in out.output.splitlines() if line.startswith("ecc")]
    assert rows[0] == "eccentricity_x[joint=C]"
    assert "joint=B" not in out.output
    out = runner.invoke(app, ["analyze", path, "--var", "eccentricity_x[joint=Z]"])
    assert out.exit_code == 2 and "joint='Z' not found" in out.stderr
    out = runner.invoke(app, ["report", path, "--var", "eccentricity_x",
                              "-o", str(tmp_path / "r.html")])  # fmt: skip
    assert out.exit_code == 2 and "eccentricity_x[joint=...]" in out.stderr


def test_report_refuses_a_bad_output_before_analysing(tmp_path: Path, monkeypatch) -> None:
    import sys

    report_pkg = sys.modules["chaoskit.reporting"]

    def refuse(*args, **kwargs):
        raise AssertionError("the output should have been refused before the analysis")

    monkeypatch.setattr(report_pkg, "report", refuse)
    good = _files(tmp_path)["truncated"].with_name("good.nc")
    folder = tmp_path / "out"
    folder.mkdir()
    a_file = tmp_path / "notes.txt"
    a_file.write_text("x")
    for output, message in [(folder, "is a folder"), (a_file / "r.html", "is not a folder")]:
        out = runner.invoke(app, ["report", str(good), "--var", "x", "-o", str(output)])
        assert out.exit_code == 2, out.output
        assert out.stderr.count("\n") == 1 and message in out.stderr
