"""``predict_wear`` and ``mechanism wear``: blocks worn in sub-updates sized to the profile,
and the hard check that stops a prediction whose contact leaves the contact law's range.

On the slider-crank with a clearance joint at 5000 rpm, one revolution's wear extrapolated
over a block of 10 000 cycles used to carve a groove the journal then slammed into (the
penetration of the next state reached 150 % of the clearance, and later 680 %, while the
command exited 0). The numbers behind the bounds here are in ``docs/wear.md``.
"""

from __future__ import annotations

import pickle
import re
import warnings

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.studies import _wear_prediction as wear_module
from tests.mechanism.scenes import rigid_paper

SCENE = "slider-crank-clearance"
C0 = 5e-4  # its radial clearance (m)
LIMIT = wear_module.DEFAULT_MAX_DEPTH_INCREMENT


def _deepen_penetration_from_call(monkeypatch, first: int, factor: float = 50.0) -> list:
    """Make every simulation from the ``first``-th on report ``factor`` × its penetration
    (a state the hard check must stop; the unworn slider-crank penetrates 10–20 % of its
    clearance, so 50 × is far beyond it whatever the rounding)."""
    real = wear_module.simulate_turns
    calls: list = []

    def deeper(scene, revolutions, **kwargs):
        ds = real(scene, revolutions, **kwargs)
        calls.append(scene)
        if len(calls) >= first:
            ds = ds.assign(penetration=ds["penetration"] * factor)
        return ds

    monkeypatch.setattr(wear_module, "simulate_turns", deeper)
    return calls


def _run_cli(args: list[str]):
    return CliRunner().invoke(app, ["wear", SCENE, "--no-progress", *args])


# ----------------------------------------------------------------------------- the user's case


@pytest.fixture(scope="module")
def ten_thousand_cycles(tmp_path_factory):
    """``mechanism wear slider-crank-clearance --updates 1 --cycles-per-update 10000``."""
    out = tmp_path_factory.mktemp("wear") / "w.nc"
    result = _run_cli(["--updates", "1", "--cycles-per-update", "10000", "-o", str(out)])
    ds = None
    if out.exists():
        with xr.open_dataset(out, engine="h5netcdf") as f:
            ds = f.load()
    return result, ds


def test_a_large_block_is_worn_in_sub_updates_and_exits_0(ten_thousand_cycles):
    """One block of 10 000 cycles wears about 0.19 c₀ (measured 0.18–0.19): it is split into
    sub-updates of at most ``DEFAULT_MAX_DEPTH_INCREMENT`` × c₀ and all its cycles are worn."""
    result, ds = ten_thousand_cycles
    assert result.exit_code == 0, result.output
    assert ds.attrs["status"] == "complete"
    assert ds["cycles"].values.tolist() == [0.0, 10000.0]
    subs = ds["sub_update_cycles"].values
    assert subs.size >= 3  # 0.18 c₀ in steps of 0.05 c₀ at most
    assert subs.sum() == pytest.approx(10000.0, rel=1e-12)
    assert (ds["sub_update_of"].values == 0).all()
    assert int(ds["sub_updates"].values[0]) == subs.size
    assert (ds["sub_update_depth_increment"].values <= LIMIT * (1.0 + 1e-9)).all()
    assert f"10000 cycles in {subs.size} sub-updates" in result.output
    assert "the next 10000 cycles in" in result.output


def test_the_worn_state_stays_within_the_clearance(ten_thousand_cycles):
    """Simulated again, the worn slider-crank's journal penetrates well under its clearance
    (measured below 0.4 c₀ under 1e-12 perturbations; the single 10 000-cycle block of the
    old rule gave 1.5 c₀)."""
    _, ds = ten_thousand_cycles
    worn = mechanism.scene_from_json(ds.attrs["worn_scene"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechanism.SimulationWarning)  # the bound is asserted
        traj = mechanism.simulate(worn, revolutions=3)
    deepest = float(traj["penetration"].max())
    assert np.isfinite(traj["contact_force"].values).all()
    assert deepest < 0.75 * C0
    for name in ("penetration_fraction", "sub_update_penetration"):
        assert float(ds[name].max()) < 0.75, name


@pytest.mark.slow
def test_halving_the_depth_increment_leaves_the_end_profile_within_tolerance(
    ten_thousand_cycles,
):
    """The same 10 000 cycles with half the default increment (0.0125 c₀): the worn volume
    of each surface within 5 % (measured 0.0–2.4 % over six 1e-12 perturbations of the
    crank speed), the profile within 30 % in the L1 sense (7.9–21.1 %) and the deepest
    bearing region within 15 % (1.2–8.4 %). One revolution's wear of this chaotic response
    scatters from state to state, so the profile converges in the mean, not pointwise; from
    0.05 c₀ to 0.025 c₀ the volume still moved by up to 19.6 % and the profile by 39 %."""
    _, ds = ten_thousand_cycles
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechanism.SimulationWarning)  # bounded by the check
        finer = mechanism.predict_wear(
            mechanism.load_scene(SCENE), updates=1, cycles_per_update=10000.0,
            max_depth_increment=LIMIT / 2.0,
        ).to_dataset()  # fmt: skip
    assert finer["sub_update_cycles"].size > ds["sub_update_cycles"].size
    a = ds.isel(update=-1).sel(joint="B")
    b = finer.isel(update=-1).sel(joint="B")
    volume = np.abs(a["worn_volume"].values - b["worn_volume"].values) / b["worn_volume"].values
    assert (volume < 0.05).all(), volume
    depth_a, depth_b = a["wear_depth"].values, b["wear_depth"].values  # (surface, angle)
    l1 = np.abs(depth_a - depth_b).sum(axis=1) / depth_b.sum(axis=1)
    assert (l1 < 0.30).all(), l1
    assert depth_a[0].max() == pytest.approx(depth_b[0].max(), rel=0.15)


# ----------------------------------------------------------------------------- the hard check


def test_a_state_deeper_than_the_clearance_stops_the_command_with_exit_1(tmp_path, monkeypatch):
    _deepen_penetration_from_call(monkeypatch, first=3)  # the state after update 2
    out = tmp_path / "w.nc"
    args = ["--updates", "3", "--cycles-per-update", "100", "--settle-revolutions", "0"]
    result = _run_cli([*args, "-o", str(out)])
    assert result.exit_code == 1, result.output
    assert "Traceback" not in result.output
    last = result.output.strip().splitlines()[-1]
    m = re.fullmatch(
        r"Error: joint B: the penetration reached (\d+) % of the radial clearance \(.+\) in the "
        r"state after 200 cycles \(update 2 of 3\), so the wear prediction stopped there; "
        r"lower max_depth_increment \(--max-depth-increment, now [0-9.]+\) or predict fewer "
        r"cycles\.",
        last,
    )
    assert m is not None, last
    assert int(m.group(1)) > 100
    assert "written with the 1 of 3 updates that finished (status failed)" in result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.attrs["status"] == "failed"
        assert ds.attrs["status_reason"] == last.removeprefix("Error: ")
        assert "FAILED" in ds.attrs["title"]
        assert ds["cycles"].values.tolist() == [0.0, 100.0]  # the finished states only
        assert ds["penetration_fraction"].values.max() <= 1.0
        # the sub-update that led to the failed state is recorded with its penetration
        assert ds["sub_update_cycles"].values.tolist() == [100.0, 100.0]
        assert ds["sub_update_penetration"].values[-1] > 1.0
        worn = mechanism.scene_from_json(ds.attrs["worn_scene"])
        depth = ds["wear_depth"].sel(joint="B", surface="bearing").isel(update=-1).values
    np.testing.assert_array_equal(np.asarray(worn.joints["B"].wear.bearing_profile), depth)


def test_a_failed_prediction_raises_with_the_finished_updates(monkeypatch):
    """Library callers get :class:`mechanism.WearPredictionError` (a ``SimulationError``)
    whose ``prediction`` has ``status == "failed"``; it survives pickling (process pools)."""
    _deepen_penetration_from_call(monkeypatch, first=2)
    scene = mechanism.load_scene(SCENE)
    with pytest.raises(mechanism.WearPredictionError, match="update 1 of 2") as info:
        mechanism.predict_wear(scene, updates=2, cycles_per_update=100.0, settle_revolutions=0.0)
    assert isinstance(info.value, mechanism.SimulationError)
    pred = info.value.prediction
    assert pred.status == "failed" and not pred.success
    assert pred.reason == str(info.value)
    assert pred.updates == 0 and pred.cycles.tolist() == [0.0]
    assert pred.worn_scene == pred.scene  # nothing finished: the unworn profile
    assert pred.to_dataset().attrs["status"] == "failed"
    back = pickle.loads(pickle.dumps(info.value))
    assert str(back) == str(info.value) and back.prediction.status == "failed"


def test_an_unworn_state_beyond_the_clearance_names_the_scene_not_the_step(monkeypatch):
    _deepen_penetration_from_call(monkeypatch, first=1)
    scene = mechanism.load_scene(SCENE)
    with pytest.raises(mechanism.WearPredictionError) as info:
        mechanism.predict_wear(scene, updates=1, cycles_per_update=100.0, settle_revolutions=0.0)
    message = str(info.value)
    assert "in the unworn state" in message
    assert "check the speed, clearance and contact stiffness" in message
    assert "max_depth_increment" not in message
    ds = info.value.prediction.to_dataset()
    assert ds.sizes["update"] == 0 and ds.attrs["status"] == "failed"


def test_non_finite_contact_forces_stop_the_prediction(monkeypatch):
    real = wear_module.simulate_turns

    def broken(scene, revolutions, **kwargs):
        ds = real(scene, revolutions, **kwargs)
        return ds.assign(contact_force=ds["contact_force"] * np.nan)

    monkeypatch.setattr(wear_module, "simulate_turns", broken)
    with pytest.raises(mechanism.WearPredictionError, match="not finite"):
        mechanism.predict_wear(
            mechanism.load_scene(SCENE), updates=1, cycles_per_update=1.0, settle_revolutions=0.0
        )


def test_an_update_needing_too_many_sub_updates_stops_with_the_reason(monkeypatch):
    monkeypatch.setattr(wear_module, "MAX_SUB_UPDATES", 2)
    paper = rigid_paper()
    with pytest.raises(mechanism.WearPredictionError, match="has used 2 sub-updates") as info:
        mechanism.predict_wear(
            paper, updates=1, cycles_per_update=1e9, max_depth_increment=0.1,
            settle_revolutions=0.0, output_step=paper.drive.period / 2000,
        )  # fmt: skip
    ds = info.value.prediction.to_dataset()
    assert ds["sub_update_cycles"].size == 2
    # each sub-update is an equal part of what is left, within the limit and binding:
    # 1e9 cycles in parts of ~1e4 fall short of 0.1 c₀ by at most 1e-4 of it
    steps = ds["sub_update_depth_increment"].values
    assert (steps <= 0.1 * (1.0 + 1e-12)).all() and (steps > 0.1 * (1.0 - 1e-4)).all()


@pytest.mark.parametrize("value", [0.0, -0.1, 1.5, float("nan"), float("inf")])
def test_max_depth_increment_is_validated(value):
    with pytest.raises(ValueError, match="max_depth_increment must be"):
        mechanism.predict_wear(
            mechanism.load_scene(SCENE), updates=1, cycles_per_update=1.0,
            max_depth_increment=value,
        )  # fmt: skip


def test_the_command_rejects_a_depth_increment_above_the_clearance(tmp_path):
    result = _run_cli(
        ["--updates", "1", "--cycles-per-update", "1", "--max-depth-increment", "2",
         "-o", str(tmp_path / "w.nc")]
    )  # fmt: skip
    assert result.exit_code == 2
    assert result.output.strip().splitlines()[-1] == (
        "Error: max_depth_increment must be in (0, 1] (a fraction of the radial clearance); "
        "got 2.0."
    )
    assert not (tmp_path / "w.nc").exists()
