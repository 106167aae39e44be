"""The chaoskit CLI on everyday mistakes: one line naming the problem, exit code 2.

Exit codes: 0 success; 2 bad input (nothing analysed); 1 when every variable failed.
"""

from __future__ import annotations

import dataclasses
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import chaoskit._neighbors as neighbors_module
import chaoskit.dimension._pairs as pairs_module
import chaoskit.lyapunov._kantz as kantz_module
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


# ----------------------------------------------------------------- tables from real rigs


def stub_analysis(monkeypatch: pytest.MonkeyPatch) -> list[tuple[xr.Dataset, list[str]]]:
    """Replace the classification of ``chaoskit analyze`` by a stub that records the dataset
    and the variables it is given (the library's verdict has tests of its own)."""
    calls: list[tuple[xr.Dataset, list[str]]] = []

    def classify_variables(ds: xr.Dataset, *, variables: list[str], **kwargs) -> dict:
        calls.append((ds, list(variables)))
        n = ds.sizes.get("time", ds.sizes.get("step", 0))
        return {
            name: chaoskit.Verdict(
                label="periodic",
                period=1,
                confidence=1.0,
                reason="stub",
                votes={},
                errors={},
                variable=name,
                kind="flow",
                dt=1.0,
                n_samples=n,
            )
            for name in variables
        }

    monkeypatch.setattr("chaoskit.cli.classify_variables", classify_variables)
    monkeypatch.setattr("chaoskit.cli.classify_motion", lambda *args, **kwargs: None)
    return calls


def _one_line_exit_2(out) -> str:  # type: ignore[no-untyped-def]
    assert out.exit_code == 2, out.output
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("error: "), out.stderr
    assert "Traceback" not in out.output
    return out.stderr.strip()


X = HENON[:200, 0].tolist()


def test_analyze_reads_headers_with_units(tmp_path: Path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    path = tmp_path / "rig.csv"
    rows = "".join(f"{0.001 * i!r},{v!r}\n" for i, v in enumerate(X))
    path.write_text("time (s),acc y [m/s^2]\n" + rows)
    out = runner.invoke(app, ["analyze", str(path)])
    assert out.exit_code == 0, out.output
    ((ds, names),) = calls
    assert names == ["acc_y"] and ds["acc_y"].attrs["units"] == "m s-2"
    assert chaoskit.sampling_interval(ds) == pytest.approx(0.001, rel=1e-9)


def test_analyze_skip_rows_decimal_and_nan_options(tmp_path: Path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    rows = "".join(f"{i};{v!r}\n" for i, v in enumerate(X))
    titled = tmp_path / "titled.csv"
    titled.write_text("Logger 12 export\ntime;x\n" + rows.replace(".", ","))
    gappy = tmp_path / "gappy.csv"
    gappy.write_text("time,x\n" + rows.replace(";", ",").replace(f",{X[5]!r}\n", ",\n"))
    cases = [
        (["analyze", str(titled)], "skip it with --skip-rows 1."),
        (["analyze", str(titled), "--skip-rows", "1"], "(pass --decimal ,)."),
        (
            ["analyze", str(gappy)],
            "line 7; fill the gaps, or pass --nan interpolate (linear in time) or --nan drop.",
        ),
        (
            ["analyze", str(gappy), "--nan", "zero"],
            "--nan must be one of 'refuse', 'drop', 'interpolate'; got 'zero'.",
        ),
        (
            ["analyze", str(gappy), "--discard", "-1"],
            "--discard must be finite and >= 0; got -1.0.",
        ),
    ]
    for command, message in cases:
        text = _one_line_exit_2(runner.invoke(app, command))
        assert text.endswith(message), (command, text)
        assert re.search(r"[a-z]=", text) is None, text  # options, not parameters
    out = runner.invoke(app, ["analyze", str(titled), "--skip-rows", "1", "--decimal", ","])
    assert out.exit_code == 0, out.output
    np.testing.assert_array_equal(calls[-1][0]["x"].values, X)
    out = runner.invoke(app, ["analyze", str(gappy), "--nan", "interpolate"])
    assert out.exit_code == 0, out.output
    ds = calls[-1][0]
    assert ds["x"].attrs["interpolated_gaps"] == "line 7 (t = 5 s)"
    assert float(ds["x"][5]) == pytest.approx(0.5 * (X[4] + X[6]), rel=1e-12)


def test_analyze_names_options_when_a_netcdf_file_has_no_time(tmp_path: Path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    path = tmp_path / "bare.nc"
    xr.Dataset({"x": ("sample", np.asarray(X))}).to_netcdf(path, engine="h5netcdf")
    text = _one_line_exit_2(runner.invoke(app, ["analyze", str(path)]))
    assert text.endswith(
        "pass --time (the variable holding the time, s), --dt (the sampling interval, s) or "
        "--step (a map)."
    )
    assert "load_trajectory" not in text and "dt=" not in text
    out = runner.invoke(app, ["analyze", str(path), "--dt", "0.01"])
    assert out.exit_code == 0, out.output
    assert chaoskit.sampling_interval(calls[-1][0]) == pytest.approx(0.01, rel=1e-12)


def test_analyze_refuses_a_figures_folder_it_cannot_write_before_the_analysis(
    tmp_path: Path, monkeypatch
) -> None:
    """``--figures`` under a file (no folder can be made there) is refused with one line
    and exit 2 before any series is classified."""
    calls = stub_analysis(monkeypatch)
    path = tmp_path / "rig.csv"
    path.write_text("time,x\n" + "".join(f"{0.001 * i!r},{v!r}\n" for i, v in enumerate(X)))
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    out = runner.invoke(app, ["analyze", str(path), "--figures", str(blocker / "figs")])
    assert out.exit_code == 2, out.output
    assert calls == []
    assert out.stderr.strip().splitlines() == [
        f"error: --figures {blocker / 'figs'}: {blocker} is not a folder."
    ]


def _same_result(a, b) -> None:
    """Two estimator results (dataclasses) hold exactly the same values."""
    for field in dataclasses.fields(a):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if isinstance(x, np.ndarray):
            nan = x.dtype.kind in "fc"
            assert np.array_equal(x, y, equal_nan=nan), field.name
        elif isinstance(x, float) and np.isnan(x):
            assert np.isnan(y), field.name
        elif isinstance(x, tuple) and any(isinstance(v, np.ndarray) for v in x):
            for u, v in zip(x, y, strict=True):
                assert np.array_equal(u, v, equal_nan=True), field.name
        else:
            assert x == y, field.name


LORENZ_X = chaoskit.systems.lorenz(20_000)[:, 0]


@pytest.mark.parametrize(
    ("module", "name", "tiny", "estimate"),
    [
        (kantz_module, "REF_CHUNK", 7, lambda: chaoskit.lyapunov_kantz(LORENZ_X, dt=0.01)),
        (
            neighbors_module,
            "CHUNK_POINTS",
            333,
            lambda: chaoskit.lyapunov_rosenstein(LORENZ_X, dt=0.01),
        ),
        (
            pairs_module,
            "EXACT_BLOCK",
            100,
            lambda: chaoskit.correlation_dimension(
                LORENZ_X[:4000], lag=10, pairs_per_radius=None, embedding_dims=(1, 2, 3, 4)
            ),
        ),
    ],
    ids=["kantz-references", "neighbour-queries", "exact-correlation-sum"],
)
def test_estimators_returning_to_python_in_chunks_are_bit_identical(
    monkeypatch, module, name: str, tiny: int, estimate
) -> None:
    """The compiled kernels of the long estimators run in chunks, so that Ctrl-C is seen
    between them; the result is the same to the last bit whatever the chunk."""
    monkeypatch.setattr(module, name, 10**12)  # one call: the kernel unchunked
    whole = estimate()
    monkeypatch.setattr(module, name, tiny)
    chunked = estimate()
    _same_result(whole, chunked)


def _chaoskit(*args: str) -> list[str]:
    """The command line as started from a terminal: a test run that is a background job
    of a non-interactive shell starts with SIGINT ignored, which its children inherit, so
    the child sets Python's default handler first."""
    code = (
        "import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
        "from chaoskit.cli import app; sys.argv[0] = 'chaoskit'; app()"
    )
    return [sys.executable, "-c", code, *args]


def _lorenz_csv(path: Path, n: int) -> Path:
    data = chaoskit.systems.lorenz(n)
    t = 0.01 * np.arange(n)
    np.savetxt(path, np.column_stack([t, data[:, 0]]), delimiter=",", header="time,x",
               comments="")  # fmt: skip
    return path


@pytest.mark.slow
def test_ctrl_c_stops_analyze_of_a_long_series_within_5_s(tmp_path: Path) -> None:
    """SIGINT inside the Lyapunov estimators of ``chaoskit analyze`` on 200 000 samples
    (kernels compiled first): exit 130 within 5 s, one line, no traceback.

    The signal is sent once the progress bar names the Rosenstein stage, whose neighbour
    search and divergence kernels (and Wolf's, next) are the estimator work; the line
    spectrum before the first stage runs least-squares fits of the whole series, each a
    single call of about a second (longer on a loaded machine)."""
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    # the same command on a short series compiles (or loads) every kernel it runs
    short = _lorenz_csv(tmp_path / "short.csv", 3000)
    subprocess.run(_chaoskit("analyze", str(short)), env=env, check=True,
                   capture_output=True, timeout=1200)  # fmt: skip
    long = _lorenz_csv(tmp_path / "long.csv", 200_000)
    proc = subprocess.Popen(
        _chaoskit("analyze", str(long)), env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    err: list[bytes] = []
    started = threading.Event()

    def read() -> None:
        assert proc.stderr is not None
        while chunk := proc.stderr.read1(4096):
            err.append(chunk)
            if b"rosenstein" in b"".join(err):  # the bar names the running stage
                started.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        assert started.wait(600), b"".join(err).decode(errors="replace")
        time.sleep(0.5)
        assert proc.poll() is None, "the analysis ended before the signal"
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        code = proc.wait(timeout=60)
        took = time.perf_counter() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    reader.join(timeout=5)
    text = b"".join(err).decode(errors="replace")
    assert code == 130, text
    assert took <= 5.0, took
    assert "Traceback" not in text
    # the progress bar redraws its line with carriage returns; what follows it is one line
    lines = [line for line in re.split(r"[\r\n]", text) if line.strip()]
    assert lines[-1] == "interrupted", text
    assert sum("stage" not in line for line in lines) == 1, text
