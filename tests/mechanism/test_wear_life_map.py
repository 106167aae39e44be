"""``mechanism.wear_life_map``: one wear path per value of a scene key, in a resumable
store, failures kept as data; its figures, report section and command.

The default-run cases use a few cycles and revolutions in this process
(``scheduler="serial"``); the measured map over speed is in ``docs/wear.md`` §7.
"""

from __future__ import annotations

import math
import os
import warnings

import matplotlib
import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import mechanism
from mechanism.cli import app
from mechanism.studies import _wear_life_map as map_module
from mechanism.studies import _wear_prediction as wear_module
from tests.mechanism.scenes import rigid_paper

matplotlib.use("Agg")

#: a few revolutions everywhere, no exponent: the default-run cost
QUICK = mechanism.WearLifeSettings(
    settle_revolutions=1.0, analysis_revolutions=4, averaged_revolutions=1, exponent=False
)
PATH = {"cycles": 100, "checkpoints": [50]}


def _map(store, values, **kwargs):
    kwargs = {"settings": QUICK, **PATH, **kwargs}
    with warnings.catch_warnings():
        # worn states may warn about step limits; what matters is asserted
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        return mechanism.wear_life_map(
            rigid_paper(), parameter="drive.speed_rpm", values=values, store=store,
            scheduler="serial", **kwargs,
        )  # fmt: skip


def _stamps(store):
    return {p.name: p.stat().st_mtime_ns for p in sorted((store / "points").glob("*.nc"))}


def _numbers(ds: xr.Dataset) -> xr.Dataset:
    """The Dataset without the attributes that date it (created, history)."""
    return ds.drop_attrs(deep=False)


@pytest.fixture(scope="module")
def speed_map(tmp_path_factory):
    store = tmp_path_factory.mktemp("wear-map")
    return store, _map(store, [90.0, 150.0])


def test_a_resumed_store_gives_identical_numbers(speed_map):
    """A re-run into the same store reads both finished paths back (their files are not
    rewritten) and gives the same numbers, bit for bit."""
    store, first = speed_map
    before = _stamps(store)
    assert len(before) == 2
    again = _map(store, [90.0, 150.0])
    assert _stamps(store) == before
    xr.testing.assert_identical(_numbers(again.to_dataset()), _numbers(first.to_dataset()))
    assert again.statuses == first.statuses == ("complete", "complete")
    stored = xr.open_dataset(store / "wear-life-map.nc", engine="h5netcdf").load()
    np.testing.assert_array_equal(stored["wear_depth"].values, first.to_dataset()["wear_depth"])


def test_the_map_dataset_is_over_value_and_checkpoint(speed_map):
    _, life = speed_map
    ds = life.to_dataset()
    assert ds["wear_depth"].dims == ("value", "checkpoint", "joint", "surface", "angle")
    assert ds["value"].values.tolist() == [90.0, 150.0]
    assert ds["value"].attrs == {"units": "rpm", "long_name": "scene key drive.speed_rpm"}
    assert ds["checkpoint"].values.tolist() == [0.0, 50.0, 100.0]
    for name in ds.data_vars:
        assert ds[name].attrs.get("units") and ds[name].attrs.get("long_name"), name
    assert ds.attrs["parameter"] == "drive.speed_rpm" and ds.attrs["averaged_revolutions"] == 1


def test_the_depth_never_decreases_along_a_path(speed_map):
    _, life = speed_map
    ds = life.to_dataset()
    assert (ds["wear_depth"].diff("checkpoint") >= 0.0).all()
    assert (ds["worn_volume"].diff("checkpoint") >= 0.0).all()
    assert (ds["max_wear_depth"].isel(checkpoint=0) == 0.0).all()
    assert (ds["max_wear_depth"].isel(checkpoint=-1).sel(surface="bearing") > 0.0).all()


def test_without_the_exponent_every_value_is_not_within_the_cycles(speed_map):
    _, life = speed_map
    assert life.cycles_to_chaos == (None, None)
    lines = life.summary().splitlines()
    assert lines[0] == "wear life of scene 'paper' over drive.speed_rpm (2 paths of 100 cycles)"
    assert lines[1].startswith("  at 90 rpm the motion is not chaotic within 100 cycles (")
    assert lines[1].endswith("no exponent computed) — not within 100 cycles")
    assert np.isnan(life.to_dataset()["cycles_to_chaos"].values).all()


def test_the_report_section_states_the_answer_first(speed_map, tmp_path):
    _, life = speed_map
    section = mechanism.wear_life_section(life)
    assert section.title == "Wear life"
    assert section.text.startswith("At 90 rpm the motion is not chaotic within 100 cycles")
    figures = [i for i in section.items if isinstance(i, chaoskit.ReportFigure)]
    assert [f.name for f in figures] == [
        "wear-life-exponent", "wear-life-spread", "wear-life-orbit", "wear-life-depth"
    ]  # fmt: skip
    rep = mechanism.wear_life_report(life, output=tmp_path / "life.html", command="test")
    assert rep.sections[0].title == "Wear life"
    markdown = (tmp_path / "life.md").read_text(encoding="utf-8")
    assert "At 150 rpm the motion is not chaotic within 100 cycles" in markdown


# ----------------------------------------------------------------------------- failures


@pytest.mark.slow
def test_a_failed_path_is_a_row_with_its_reason_and_the_checkpoints_before(tmp_path, monkeypatch):
    """At 150 rpm the third simulated wear state has its penetration inflated 50× (far
    beyond the clearance whatever the rounding): that path ends after 50 cycles, keeping
    the unworn state and the checkpoint at 50; the task of 120 rpm raises. Both are rows
    of the map; a re-run keeps the ended path (it is a result) and runs the raised one."""
    real_simulate, real_wear_life = wear_module.simulate_turns, map_module.wear_life
    calls: list = []

    def deeper(scene, revolutions, **kwargs):
        ds = real_simulate(scene, revolutions, **kwargs)
        if scene.drive.speed_rpm == 150.0:
            calls.append(scene)
            if len(calls) >= 3:
                ds = ds.assign(penetration=ds["penetration"] * 50.0)
        return ds

    def broken(scene, **kwargs):
        if scene.drive.speed_rpm == 120.0:
            raise RuntimeError("stand-in failure")
        return real_wear_life(scene, **kwargs)

    monkeypatch.setattr(wear_module, "simulate_turns", deeper)
    monkeypatch.setattr(map_module, "wear_life", broken)
    life = _map(tmp_path, [120.0, 150.0])
    assert life.statuses == ("failed", "failed")
    assert life.paths[0] is None
    assert life.reasons[0] == "the path could not run: RuntimeError: stand-in failure"
    ended = life.paths[1]
    assert ended.checkpoints.tolist() == [0.0, 50.0]
    assert life.reasons[1].startswith("the path ended after 50 cycles: joint C:")
    assert "penetration reached" in life.reasons[1]
    ds = life.to_dataset()
    assert ds["path_status"].values.tolist() == ["failed", "failed"]
    assert np.isnan(ds["max_wear_depth"].sel(value=120.0)).all()
    depth = ds["max_wear_depth"].sel(value=150.0, surface="bearing").values[:, 0]
    assert depth[0] == 0.0 and depth[1] > 0.0 and math.isnan(depth[2])
    answers = life.answers()
    assert answers[0] == "at 120 rpm the path did not run: " + life.reasons[0]
    assert "the path ended after 50 cycles: joint C:" in answers[1]
    # the report's sentences and notes end each reason with one full stop, not two
    section = mechanism.wear_life_section(life)
    (table,) = [i for i in section.items if isinstance(i, chaoskit.ReportTable)]
    assert ".." not in section.text and ".;" not in table.notes
    assert section.text.endswith("cycles.") and not table.notes.endswith(".")

    monkeypatch.setattr(map_module, "wear_life", real_wear_life)
    (ended_file,) = (tmp_path / "points").glob("speed_rpm-150.0_*.nc")
    stamp = os.stat(ended_file).st_mtime_ns
    again = _map(tmp_path, [120.0, 150.0])
    assert os.stat(ended_file).st_mtime_ns == stamp
    assert again.statuses[0] == "complete"
    assert again.reasons[1] == life.reasons[1]


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"values": []}, "values must hold at least one value of drive.speed_rpm; got []."),
        ({"values": [30, 30]}, "values of drive.speed_rpm must not repeat; got [30.0, 30.0]."),
        (
            {"values": [30, "fast"]},
            "values must be finite numbers; got 'fast' for drive.speed_rpm.",
        ),
        ({"values": [30], "cycles": 0}, "cycles must be finite and > 0; got 0."),
        (
            {"values": [30], "checkpoints": [80, 40]},
            "checkpoints must be strictly increasing; got [80.0, 40.0].",
        ),
        ({"values": [30], "workers": 0}, "workers must be an integer >= 1; got 0."),
        (
            {"values": [30], "parameter": "speed"},
            "parameter must be a dotted scene key (e.g. 'drive.speed_rpm'); got 'speed'.",
        ),
    ],
)
def test_bad_input_is_one_line_before_any_path_runs(tmp_path, kwargs, message):
    call = {"parameter": "drive.speed_rpm", **PATH, "settings": QUICK, **kwargs}
    with pytest.raises(ValueError) as info:
        mechanism.wear_life_map(rigid_paper(), store=tmp_path / "s", **call)
    assert str(info.value) == message
    assert not (tmp_path / "s").exists()


def test_a_value_without_wear_is_rejected_before_any_path_runs(tmp_path):
    with pytest.raises(ValueError) as info:
        mechanism.wear_life_map(
            rigid_paper(), parameter="joints.C.wear.coefficient", values=[1e-14, 0.0],
            store=tmp_path / "s", settings=QUICK, **PATH,
        )  # fmt: skip
    assert str(info.value) == (
        "joints.C.wear.coefficient must be > 0 (m² N⁻¹) for a wear path; got 0.0."
    )


def test_a_store_of_another_map_is_refused(speed_map):
    store, _ = speed_map
    with pytest.raises(mechanism.SweepStoreMismatch, match=r"holds a different sweep \(cycles:"):
        _map(store, [90.0], cycles=200, checkpoints=[50])


# ----------------------------------------------------------------------------- slow


@pytest.mark.slow
def test_a_regular_path_reports_not_within_n_cycles(tmp_path):
    """At 30 rpm the journal rides its bearing: over 100 cycles the exponent's interval
    contains zero at every checkpoint, so the value is "not within 100 cycles"."""
    settings = mechanism.WearLifeSettings(
        settle_revolutions=1.0, analysis_revolutions=25, averaged_revolutions=2,
        lyapunov_revolutions=3.0, lyapunov_discard=1.0,
    )  # fmt: skip
    life = _map(tmp_path, [30.0], settings=settings)
    assert life.statuses == ("complete",)
    assert life.cycles_to_chaos == (None,)
    ds = life.to_dataset()
    assert np.isfinite(ds["lyapunov_exponent"]).all()
    assert (ds["lyapunov_ci_low"] <= 0.0).all()
    assert life.answers()[0].startswith("at 30 rpm the motion is not chaotic within 100 cycles (")
    assert "— not within 100 cycles" in life.summary()


# ----------------------------------------------------------------------------- the command


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["paper", "--cycles", "0", "--checkpoint", "50"],
            "Error: cycles must be finite and > 0; got 0.0.",
        ),
        (
            ["paper", "--cycles", "100", "--checkpoint", "80", "--checkpoint", "40"],
            "Error: checkpoints must be strictly increasing; got [80.0, 40.0].",
        ),
        (
            ["slider-crank", "--cycles", "100", "--checkpoint", "50"],
            "Error: wear_life needs a scene with an active clearance joint (a "
            "clearance_revolute joint and effects.clearance = true).",
        ),
        (
            ["paper", "--cycles", "100", "--checkpoint", "50", "--set",
             "joints.C.wear.coefficient=0.0"],
            "Error: joints.C.wear.coefficient must be > 0 (m² N⁻¹) for a wear path; got 0.0.",
        ),
        (
            ["paper", "--cycles", "100", "--checkpoint", "50", "--averaged-revolutions", "0"],
            "Error: averaged_revolutions must be in [1, 1000]; got 0.",
        ),
        (
            ["paper", "--cycles", "100", "--checkpoint", "50", "--workers", "2",
             "--scheduler", "serial"],
            "Error: workers applies to the local cluster only (scheduler=None).",
        ),
    ],
)  # fmt: skip
def test_the_command_rejects_bad_input_in_one_line_with_exit_2(tmp_path, args, message):
    out = tmp_path / "out"
    result = CliRunner().invoke(
        app, ["wear-life", *args, "--grid", "drive.speed_rpm=90,150", "--no-progress",
              "-o", str(out)],
    )  # fmt: skip
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [message]
    assert not (out / "wear-life-map.nc").exists()


def test_the_command_rejects_a_malformed_grid_in_one_line(tmp_path):
    result = CliRunner().invoke(
        app, ["wear-life", "paper", "--cycles", "100", "--checkpoint", "50", "--grid",
              "drive.speed_rpm", "--no-progress", "-o", str(tmp_path / "out")],
    )  # fmt: skip
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines() == [
        "Error: --grid: 'drive.speed_rpm': expected KEY=V1,V2,... e.g. joints.C.clearance=1e-4,2e-4"
    ]


@pytest.mark.slow
def test_the_command_writes_the_map_the_report_and_the_answers(tmp_path):
    out = tmp_path / "life"
    args = ["wear-life", "paper", "--set", "effects.flexibility=false", "--cycles", "100",
            "--checkpoint", "50", "--no-exponent", "--averaged-revolutions", "1",
            "--grid", "drive.speed_rpm=90,150", "--scheduler", "serial", "--no-progress",
            "-o", str(out)]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "at 150 rpm the motion is not chaotic within 100 cycles" in result.output
    for name in ("wear-life-map.nc", "wear-life.html", "wear-life.md", "store/sweep.json"):
        assert (out / name).is_file(), name
    with xr.open_dataset(out / "wear-life-map.nc", engine="h5netcdf") as f:
        assert f["value"].values.tolist() == [90.0, 150.0]


def test_on_a_threaded_dask_client_the_analyses_are_tasks_with_the_same_numbers(tmp_path):
    """The same hand-over on a client of two in-process workers (threads: no process to
    start, the kernels already loaded): one path with a short exponent gives the numbers
    of the same path computed in turn, and its exponent's and verdict's CPU is counted as
    spent on other threads."""
    distributed = pytest.importorskip("distributed")
    settings = mechanism.WearLifeSettings(
        settle_revolutions=1.0, analysis_revolutions=4, averaged_revolutions=1,
        lyapunov_revolutions=2.0, lyapunov_discard=1.0, lyapunov_first_revolutions=None,
    )  # fmt: skip
    serial = _map(tmp_path / "serial", [150.0], settings=settings)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
        warnings.catch_warnings(),
    ):
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        threaded = mechanism.wear_life_map(
            rigid_paper(), parameter="drive.speed_rpm", values=[150.0],
            store=tmp_path / "threaded", settings=settings, scheduler=client, **PATH,
        )  # fmt: skip
    _assert_same_numbers(serial, threaded)
    stored = _stored_path(tmp_path / "threaded", 150.0)
    assert stored.attrs["phase_cpu_elsewhere"] > 0.0
    assert stored.attrs["phase_cpu_elsewhere"] == pytest.approx(
        stored.attrs["phase_cpu_exponent"] + stored.attrs["phase_cpu_verdict"]
    )


def _assert_same_numbers(serial, handed_over):
    """The analysed numbers of two maps, bit for bit (with a finite exponent)."""
    a, b = _numbers(serial.to_dataset()), _numbers(handed_over.to_dataset())
    assert np.isfinite(a["lyapunov_exponent"].values).all()
    for name in ("lyapunov_exponent", "lyapunov_ci_low", "lyapunov_ci_high", "motion",
                 "motion_confidence", "wear_depth", "strobe_x", "strobe_y",
                 "peak_contact_force", "mean_contact_force"):  # fmt: skip
        np.testing.assert_array_equal(b[name].values, a[name].values)


def _stored_path(store, value):
    path = store / "points" / f"{map_module.path_id('drive.speed_rpm', value)}.nc"
    return xr.open_dataset(path, engine="h5netcdf").load()


@pytest.mark.slow
def test_on_a_dask_cluster_the_analyses_run_as_tasks_with_the_same_numbers(tmp_path):
    """Two paths with the exponent on a local cluster of two workers, where each path
    hands its checkpoints' exponents and verdicts to the cluster as tasks of their own
    and waits for them without holding its worker: the same numbers, bit for bit, as the
    same paths computed in turn in this process; the exponent's and the verdict's CPU
    are counted in the path wherever they ran."""
    settings = mechanism.WearLifeSettings(
        settle_revolutions=1.0, analysis_revolutions=4, averaged_revolutions=1,
        lyapunov_revolutions=3.0, lyapunov_discard=1.0, lyapunov_first_revolutions=2.0,
    )  # fmt: skip
    serial = _map(tmp_path / "serial", [90.0, 150.0], settings=settings)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        cluster = mechanism.wear_life_map(
            rigid_paper(), parameter="drive.speed_rpm", values=[90.0, 150.0],
            store=tmp_path / "cluster", settings=settings, workers=2, **PATH,
        )  # fmt: skip
    _assert_same_numbers(serial, cluster)
    for value in (90.0, 150.0):
        stored = _stored_path(tmp_path / "cluster", value)
        assert stored.attrs["phase_cpu_exponent"] > 0.0 and stored.attrs["phase_cpu_verdict"] > 0.0
        assert stored.attrs["phase_cpu_elsewhere"] == pytest.approx(
            stored.attrs["phase_cpu_exponent"] + stored.attrs["phase_cpu_verdict"]
        )
        assert stored.attrs["cpu_time"] >= stored.attrs["phase_cpu_total"] - 1e-6
