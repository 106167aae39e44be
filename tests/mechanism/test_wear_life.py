"""``mechanism.wear_life``: one wear path with the motion analysed at checkpoints, and the
wear per cycle averaged over revolutions with its interval (``predict_wear``).

The numbers behind the bounds are in ``docs/wear.md`` §3 and §6.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.studies import _wear_prediction as wear_module
from tests.mechanism.scenes import rigid_paper

JOINT = "C"


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        # worn states may warn about step limits; what matters is asserted
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        return fn(*args, **kwargs)


#: few revolutions everywhere, no exponent: the default-run cost
QUICK = {
    "averaged_revolutions": 2,
    "settings": mechanism.WearLifeSettings(settle_revolutions=1.0, analysis_revolutions=4),
    "exponent": False,
}


@pytest.fixture(scope="module")
def quick_path():
    """The rigid paper scene at 90 rpm, 1000 cycles with a checkpoint at 500."""
    scene = rigid_paper({"drive.speed_rpm": 90.0})
    return _quiet(mechanism.wear_life, scene, cycles=1000, checkpoints=[500], **QUICK)


@pytest.mark.slow
def test_a_regular_path_reports_not_within_n_cycles():
    """At 30 rpm (a low speed: the journal rides its bearing) the path stays regular over
    its first 500 cycles: the exponent's interval contains zero at both checkpoints
    (measured −2.34 [−12.9, 8.27] and 2.44 [−2.45, 7.32] 1/s; with the crank speed
    perturbed by 1e-12, −2.40 [−13.4, 8.65] and 1.54 [−7.88, 10.95]), so no checkpoint is
    chaotic, and the summary says so with the cycles it covered. (Further on the path
    turns chaotic: after 1000 cycles the perturbed path's interval is [8.2, 18.2] 1/s, and
    after 2000 cycles both lie above zero; docs/wear.md §7.)"""
    scene = rigid_paper({"drive.speed_rpm": 30.0})
    life = _quiet(
        mechanism.wear_life, scene, cycles=500, checkpoints=[500], averaged_revolutions=2,
        settings=mechanism.WearLifeSettings(
            settle_revolutions=1.0, analysis_revolutions=25, lyapunov_revolutions=3.0,
            lyapunov_discard=1.0,
        ),
    )  # fmt: skip
    assert life.status == "complete", life.reason
    assert life.checkpoints.tolist() == [0.0, 500.0]
    assert life.cycles_to_chaos is None
    assert "chaotic: not within 500 cycles" in life.summary()
    ds = life.to_dataset()
    assert ds.attrs["cycles_to_chaos"] == -1.0
    assert np.isfinite(ds["lyapunov_exponent"]).all()
    assert (ds["lyapunov_ci_low"] <= 0.0).all()
    assert (ds["lyapunov_ci_low"] <= ds["lyapunov_ci_high"]).all()


def test_without_the_exponent_no_checkpoint_is_called_chaotic(quick_path):
    assert quick_path.status == "complete", quick_path.reason
    assert quick_path.checkpoints.tolist() == [0.0, 500.0, 1000.0]
    assert quick_path.cycles_to_chaos is None
    assert "chaotic: not within 1000 cycles (no exponent computed)" in quick_path.summary()
    assert np.isnan(quick_path.to_dataset()["lyapunov_exponent"].values).all()


def test_the_depth_never_decreases_along_the_path(quick_path):
    ds = quick_path.to_dataset()
    depth = ds["wear_depth"].values  # (checkpoint, joint, surface, angle)
    assert (np.diff(depth, axis=0) >= 0.0).all()
    assert (np.diff(ds["max_wear_depth"].values, axis=0) >= 0.0).all()
    assert (np.diff(ds["worn_volume"].values, axis=0) >= 0.0).all()
    assert ds["max_wear_depth"].values[0].max() == 0.0
    assert ds["max_wear_depth"].sel(joint=JOINT, surface="bearing").values[-1] > 0.0


def test_the_path_dataset_describes_every_variable(quick_path):
    ds = quick_path.to_dataset()
    assert ds.sizes["checkpoint"] == 3
    for name in ds.data_vars:
        assert ds[name].attrs.get("units") and ds[name].attrs.get("long_name"), name
    shares = ds["free_flight_fraction"] + ds["impact_fraction"] + ds["continuous_contact_fraction"]
    np.testing.assert_allclose(shares.values, 1.0, rtol=0.0, atol=1e-12)
    # one stroboscopic point per analysed revolution (the last may fall at the very end)
    assert ds.sizes["crossing"] >= QUICK["settings"].analysis_revolutions - 1
    assert np.isfinite(ds["strobe_x"].isel(crossing=0)).all()
    assert (ds["peak_contact_force"] >= ds["mean_contact_force"]).all()
    assert set(ds["motion"].values) <= {
        "periodic", "quasi-periodic", "chaotic", "noise-like", "undetermined", "equilibrium"
    }  # fmt: skip
    assert mechanism.scene_from_json(ds.attrs["worn_scene"]) == quick_path.worn_scene


# ----------------------------------------------------------------------------- averaged wear


def _relative_halfwidth(averaged: int, k: int) -> float:
    """The largest 95 % half-width / mean of the wear per cycle over the worn regions at the
    unworn state of the rigid paper scene at 150 rpm (crank speed perturbed by k·1e-12)."""
    pred = _quiet(
        mechanism.predict_wear, rigid_paper({"drive.speed_rpm": 150.0 * (1.0 + k * 1e-12)}),
        updates=1, cycles_per_update=1.0, settle_revolutions=1.0, averaged_revolutions=averaged,
    )  # fmt: skip
    ds = pred.to_dataset()
    rate = ds["wear_rate"].isel(update=0).sel(joint=JOINT, surface="bearing").values
    half = ds["wear_rate_halfwidth"].isel(update=0).sel(joint=JOINT, surface="bearing").values
    assert np.isfinite(half).all() and (half >= 0.0).all()
    assert (rate >= 0.1 * rate.max()).sum() >= 20  # the worn arcs span many regions
    return float(ds["wear_rate_relative_halfwidth"].values[0])


def test_the_averaged_increment_interval_shrinks_with_more_revolutions():
    """The 95 % interval of the wear per cycle from batch means over 16 revolutions is
    narrower than over 4: the largest relative half-width over the worn regions measured
    1.82 → 0.80, 0.90 → 0.40 and 1.59 → 0.42 with the crank speed perturbed by 0, 1e-12
    and 2e-12 (asserted a factor 1.5). The motion at 150 rpm is irregular, so one
    revolution's wear scatters by tens of percent region by region."""
    four, sixteen = _relative_halfwidth(4, 0), _relative_halfwidth(16, 0)
    assert 0.0 < sixteen * 1.5 < four


def test_one_averaged_revolution_has_no_interval():
    pred = _quiet(
        mechanism.predict_wear, rigid_paper({"drive.speed_rpm": 30.0}), updates=1,
        cycles_per_update=1.0, settle_revolutions=0.0, averaged_revolutions=1,
    )  # fmt: skip
    ds = pred.to_dataset()
    assert ds.attrs["averaged_revolutions"] == 1
    assert np.isnan(ds["wear_rate_halfwidth"].values).all()
    assert np.isnan(ds["wear_rate_relative_halfwidth"].values).all()
    assert ds["wear_rate"].attrs["units"] == "m"


@pytest.mark.parametrize(
    ("value", "shown"), [(0, "0"), (1001, "1001"), (2.5, "2.5"), (True, "True")]
)
def test_averaged_revolutions_is_validated(value, shown):
    with pytest.raises(ValueError, match=r"^averaged_revolutions must be") as info:
        mechanism.predict_wear(rigid_paper(), updates=1, cycles_per_update=1.0,
                               averaged_revolutions=value)  # fmt: skip
    message = str(info.value)
    assert "\n" not in message
    assert "[1, 1000]" in message or "integer" in message


# ----------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"cycles": 0, "checkpoints": [1]}, "cycles must be finite and > 0; got 0."),
        ({"cycles": -5.0, "checkpoints": [1]}, "cycles must be finite and > 0; got -5.0."),
        (
            {"cycles": 2000, "checkpoints": [1500, 1000]},
            "checkpoints must be strictly increasing; got [1500.0, 1000.0].",
        ),
        (
            {"cycles": 2000, "checkpoints": [0, 1000]},
            "checkpoints must lie in (0, cycles] = (0, 2000]; got [0.0, 1000.0].",
        ),
        (
            {"cycles": 2000, "checkpoints": [-10]},
            "checkpoints must lie in (0, cycles] = (0, 2000]; got [-10.0].",
        ),
        (
            {"cycles": 2000, "checkpoints": [1000, 3000]},
            "checkpoints must lie in (0, cycles] = (0, 2000]; got [1000.0, 3000.0].",
        ),
        (
            {"cycles": 2000, "checkpoints": []},
            "checkpoints must be a non-empty list of finite cycle counts in (0, cycles]; got [].",
        ),
        (
            {"cycles": 2000, "checkpoints": [1000], "averaged_revolutions": 0},
            "averaged_revolutions must be in [1, 1000]; got 0.",
        ),
        (
            {"cycles": 2000, "checkpoints": [1000], "max_depth_increment": 0.0},
            "max_depth_increment must be in (0, 1] (a fraction of the radial clearance); got 0.0.",
        ),
    ],
)
def test_wear_life_rejects_bad_settings_in_one_line(kwargs, message):
    with pytest.raises(ValueError) as info:
        mechanism.wear_life(rigid_paper(), **kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"continuous_contact": 1.0},
            "continuous_contact must be in (0, 1) (a fraction of the drive period); got 1.0.",
        ),
        (
            {"lyapunov_revolutions": 3.0, "lyapunov_discard": 3.0},
            "lyapunov_discard must be in [0, lyapunov_revolutions) = [0, 3); got 3.0.",
        ),
        (
            {"analysis_revolutions": 3},
            "analysis_revolutions must be in [4, 10000]; got 3.",
        ),
    ],
)
def test_the_settings_object_rejects_bad_fields_in_one_line(kwargs, message):
    """The analysis settings are checked on construction, before any wear is run."""
    with pytest.raises(ValueError) as info:
        mechanism.WearLifeSettings(**kwargs)
    assert str(info.value) == message


def test_the_settings_object_must_be_one():
    with pytest.raises(TypeError, match=r"^settings must be a mechanism\.WearLifeSettings; got"):
        mechanism.wear_life(rigid_paper(), cycles=100, checkpoints=[50], settings={})


def test_wear_life_needs_a_clearance_joint_that_wears():
    scene = mechanism.load_scene("slider-crank")  # ideal joints only
    with pytest.raises(ValueError) as info:
        mechanism.wear_life(scene, cycles=100, checkpoints=[50])
    assert str(info.value) == (
        "wear_life needs a scene with an active clearance joint (a clearance_revolute "
        "joint and effects.clearance = true)."
    )
    unworn = rigid_paper({"joints.C.wear.coefficient": 0.0})
    with pytest.raises(ValueError) as info:
        mechanism.wear_life(unworn, cycles=100, checkpoints=[50])
    assert str(info.value) == (
        "joints.C.wear.coefficient must be > 0 (m² N⁻¹) for a wear path; got 0.0."
    )


# ----------------------------------------------------------------------------- a path that ends


def test_a_state_beyond_the_model_ends_the_path_and_keeps_the_checkpoints_before(monkeypatch):
    """From the third simulated wear state on the penetration is inflated 50× (far beyond
    the clearance whatever the rounding): the path ends there with the reason, keeping the
    unworn state and the checkpoint at 500 cycles (one increment each at 90 rpm)."""
    real = wear_module.simulate_turns
    calls: list = []

    def deeper(scene, revolutions, **kwargs):
        ds = real(scene, revolutions, **kwargs)
        calls.append(scene)
        if len(calls) >= 3:
            ds = ds.assign(penetration=ds["penetration"] * 50.0)
        return ds

    monkeypatch.setattr(wear_module, "simulate_turns", deeper)
    life = _quiet(
        mechanism.wear_life, rigid_paper({"drive.speed_rpm": 90.0}), cycles=1000,
        checkpoints=[500], **QUICK,
    )  # fmt: skip
    assert life.status == "failed" and not life.success
    assert life.checkpoints.tolist() == [0.0, 500.0]
    assert "penetration reached" in life.reason
    assert life.reason.startswith("the path ended after 500 cycles: joint C:")
    ds = life.to_dataset()
    assert ds.attrs["status"] == "failed" and ds.attrs["status_reason"] == life.reason
    assert ds.sizes["checkpoint"] == 2
    assert np.isnan(ds["lyapunov_exponent"].values).all()  # exponent=False
    assert "chaotic: not within 500 cycles" in life.summary()
    assert not math.isnan(float(ds["max_wear_depth"].values[-1].max()))


# ----------------------------------------------------------------------------- the command


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ["--cycles", "1000", "--checkpoint", "2000"],
            "Error: checkpoints must lie in (0, cycles] = (0, 1000]; got [2000.0].",
        ),
        (
            ["--cycles", "1000", "--checkpoint", "500", "--averaged-revolutions", "0"],
            "Error: averaged_revolutions must be in [1, 1000]; got 0.",
        ),
    ],
)
def test_the_wear_life_command_rejects_bad_input_with_exit_2(tmp_path, args, message):
    result = CliRunner().invoke(
        app, ["wear-life", "paper", "--no-progress", "-o", str(tmp_path / "out"), *args]
    )
    assert result.exit_code == 2, result.output
    assert result.output.strip().splitlines()[-1] == message
    assert "Traceback" not in result.output
    assert not (tmp_path / "out" / "wear-life.nc").exists()


@pytest.mark.slow
def test_the_wear_life_command_writes_the_path_and_the_worn_scene(tmp_path):
    out = tmp_path / "life"
    result = CliRunner().invoke(
        app,
        ["wear-life", "paper", "--no-progress", "--set", "effects.flexibility=false",
         "--set", "drive.speed_rpm=90", "--cycles", "1000", "--checkpoint", "500",
         "--no-exponent", "--averaged-revolutions", "2", "-o", str(out)],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "chaotic: not within 1000 cycles (no exponent computed)" in result.output
    with xr.open_dataset(out / "wear-life.nc", engine="h5netcdf") as f:
        ds = f.load()
    assert ds["checkpoint"].values.tolist() == [0.0, 500.0, 1000.0]
    worn = mechanism.load_scene(out / "worn.toml")
    assert mechanism.scene_from_json(ds.attrs["worn_scene"]) == worn
