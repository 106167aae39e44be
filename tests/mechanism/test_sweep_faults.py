"""Sweep stores under faults: racing sweeps, damaged point files, stale temporaries, full disk."""

from __future__ import annotations

import errno
import threading
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import mechanism
from mechanism.studies.sweep import _store as store_mod
from tests.mechanism import sweep_standins as standins

CLEARANCE = "joints.B.clearance"
METRICS_ONLY = mechanism.Analysis(variables=())


@pytest.fixture(scope="module")
def scene():
    return mechanism.load_scene("slider-crank-clearance").replace({"solver.output_step": 2.4e-5})


def _sweep(scene, store: Path, **kwargs):
    kwargs.setdefault("grid", {CLEARANCE: [1e-4, 2e-4]})
    kwargs.setdefault("revolutions", 2)
    kwargs.setdefault("analysis", METRICS_ONLY)
    kwargs.setdefault("client", "serial")
    return mechanism.sweep(scene, store=store, _simulator=standins.analytic_simulator, **kwargs)


def _manifest(revolutions: float) -> dict:
    return {"format": store_mod.MANIFEST_FORMAT, "revolutions": revolutions}


def _race(store: Path, n: int) -> dict[int, str]:
    """``n`` writers start at one instant; odd ones ask 0.5 revolutions, even ones 0.25."""
    barrier = threading.Barrier(n)
    outcome: dict[int, str] = {}

    def write(i: int) -> None:
        barrier.wait()
        try:
            resumed = store_mod.check_or_write_manifest(store, _manifest(0.5 if i % 2 else 0.25))
            outcome[i] = "resumed" if resumed else "created"
        except mechanism.SweepStoreMismatch:
            outcome[i] = "refused"

    threads = [threading.Thread(target=write, args=(i,)) for i in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return outcome


def test_racing_manifests_one_wins_the_other_is_refused(tmp_path: Path) -> None:
    for attempt in range(10):
        store = tmp_path / f"store{attempt}"
        store.mkdir()
        outcome = _race(store, 8)
        assert list(outcome.values()).count("created") == 1
        winner = next(i for i, v in outcome.items() if v == "created")
        same = [i for i in range(8) if i % 2 == winner % 2 and i != winner]
        assert {outcome[i] for i in same} == {"resumed"}
        assert {outcome[i] for i in range(8) if i % 2 != winner % 2} == {"refused"}
        assert [p.name for p in store.iterdir()] == ["sweep.json"]


def test_a_second_sweep_into_a_busy_store_is_refused(scene, tmp_path: Path) -> None:
    store = tmp_path / "store"
    with store_mod.locked(store):
        with pytest.raises(mechanism.SweepStoreBusy, match="in use by another sweep"):
            _sweep(scene, store)
    ds = _sweep(scene, store)  # free again
    assert (ds["status"] == "ok").all()


def test_resume_reruns_a_point_whose_file_is_damaged(scene, tmp_path: Path) -> None:
    store = tmp_path / "store"
    first = _sweep(scene, store)
    damaged = store / "points" / f"{first['point_id'].values[0]}.nc"
    damaged.write_bytes(damaged.read_bytes()[:500])  # present, but truncated
    second = _sweep(scene, store)
    assert "2 points: 1 to run, 1 already done" in second.attrs["history"]
    assert store_mod.readable_trajectory(damaged)
    xr.testing.assert_equal(first["peak_contact_force"], second["peak_contact_force"])


def test_stale_temporary_files_are_removed_on_the_next_run(scene, tmp_path: Path) -> None:
    store = tmp_path / "store"
    _sweep(scene, store)
    stale = [store / "points" / ".abc.nc.0123456789ab.tmp", store / ".summary.nc.ba98.tmp"]
    for path in stale:
        path.write_bytes(b"half a file")
    _sweep(scene, store)
    assert not any(path.exists() for path in stale)
    assert not list(store.rglob("*.tmp"))


def test_a_full_disk_is_a_recorded_point_failure(scene, tmp_path: Path, monkeypatch) -> None:
    """The trajectory cannot be written: the point fails with the reason, the sweep goes on."""
    store = tmp_path / "store"
    import chaoskit

    real = chaoskit.save_trajectory

    def save(ds, path):
        if "0.0002" in Path(path).name:
            raise OSError(errno.ENOSPC, f"not enough free space in {Path(path).parent}")
        return real(ds, path)

    monkeypatch.setattr(chaoskit, "save_trajectory", save)
    ds = _sweep(scene, store)
    assert list(ds["status"].values) == ["ok", "failed"]
    assert "not enough free space" in str(ds["message"].values[1])
    monkeypatch.undo()
    again = _sweep(scene, store)  # space is back: the failed point is retried
    assert list(again["status"].values) == ["ok", "ok"]


def test_when_nothing_can_be_written_the_sweep_stops_with_a_clear_error(
    scene, tmp_path: Path, monkeypatch
) -> None:
    store = tmp_path / "store"

    def full(ds, path):
        raise OSError(errno.ENOSPC, f"not enough free space in {Path(path).parent}")

    monkeypatch.setattr(store_mod, "_write_netcdf", full)
    with pytest.raises(OSError, match="not enough free space") as err:
        _sweep(scene, store)
    assert err.value.errno == errno.ENOSPC
    assert not list(store.rglob("*.tmp"))


def test_save_scene_is_atomic(tmp_path: Path, monkeypatch) -> None:
    """A write that fails midway (a full disk) leaves the good scene file in place."""
    good = mechanism.load_scene("slider-crank")
    path = mechanism.save_scene(good, tmp_path / "scene.toml")
    before = path.read_bytes()

    def full(self: Path, text: str, encoding: str | None = None) -> int:
        with open(self, "w", encoding=encoding) as fh:
            fh.write(text[: len(text) // 3])
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Path, "write_text", full)
    with pytest.raises(OSError, match="No space left"):
        mechanism.save_scene(good.replace({"drive.speed_rpm": 90.0}), path)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert mechanism.load_scene(path) == good
    assert [p.name for p in tmp_path.iterdir()] == ["scene.toml"]


def test_sweep_analysis_takes_the_selection_syntax(scene, tmp_path: Path) -> None:
    """``eccentricity_x[joint=B]`` selects as ``joint="B"`` does; the rows keep the spec."""
    grid = {CLEARANCE: [2e-4]}
    opts = {"n_surrogates": 19}
    by_spec = _sweep(
        scene,
        tmp_path / "a",
        grid=grid,
        analysis=mechanism.Analysis(variables=("eccentricity_x[joint=B]",), options=opts),
    )
    by_joint = _sweep(
        scene,
        tmp_path / "b",
        grid=grid,
        analysis=mechanism.Analysis(variables=("eccentricity_x",), joint="B", options=opts),
    )
    assert list(by_spec["variable"].values) == ["eccentricity_x[joint=B]"]
    assert by_spec["mle_wolf"].values.ravel() == pytest.approx(by_joint["mle_wolf"].values.ravel())

    def with_strain(scene, *, revolutions):
        ds = standins.analytic_simulator(scene, revolutions=revolutions)
        strain = np.zeros((ds.sizes["time"], 2, 3)) + ds["crank_angle"].values[:, None, None]
        ds["strain"] = (("time", "rod", "station"), strain, {"units": "1", "long_name": "e"})
        return ds.assign_coords(rod=["r3", "r4"], station=[0.0, 0.5, 1.0])

    two_dims = mechanism.sweep(scene, store=tmp_path / "c", grid=grid, revolutions=2,
                               client="serial", _simulator=with_strain,
                               analysis=mechanism.Analysis(variables=("strain",)))  # fmt: skip
    assert str(two_dims["status"].values.item()) == "failed"
    assert "strain[rod=...]" in str(two_dims["message"].values.item())


def test_a_summary_naming_a_file_outside_the_store_is_not_trusted(tmp_path: Path) -> None:
    store = tmp_path / "store"
    (store / "points").mkdir(parents=True)
    outside = tmp_path / "elsewhere.nc"
    for bad in ("../elsewhere.nc", str(outside), "points/../../elsewhere.nc"):
        with pytest.raises(ValueError, match="outside itself"):
            store_mod.point_file(store, bad)
    assert store_mod.point_file(store, "points/a.nc") == (store / "points" / "a.nc").resolve()
