"""``mechanism wear``: a thin layer over ``predict_wear``."""

from __future__ import annotations

import numpy as np
import xarray as xr
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app


def test_wear_command_writes_the_prediction_and_the_worn_scene(tmp_path):
    out = tmp_path / "wear.nc"
    args = [
        "wear", "paper", "--updates", "1", "--cycles-per-update", "500",
        "--settle-revolutions", "0", "--set", "solver.output_step=4e-4",
        "--set", "effects.flexibility=false",  # calibrated with rigid rods
        "--no-progress", "-o", str(out),
    ]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "1 updates, 500 cycles" in result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds["wear_depth"].dims == ("update", "joint", "surface", "angle")
        assert ds.sizes["update"] == 2
        worn = mechanism.scene_from_json(ds.attrs["worn_scene"])
        depth = ds["wear_depth"].sel(joint="C", surface="bearing").isel(update=-1).values
    np.testing.assert_array_equal(np.asarray(worn.joints["C"].wear.bearing_profile), depth)
    assert worn.solver.output_step == 4e-4  # --set reached the scene


def test_wear_command_reports_bad_input(tmp_path):
    args = ["wear", "paper", "--updates", "0", "--cycles-per-update", "1", "-o",
            str(tmp_path / "w.nc"), "--no-progress"]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 2
    assert result.output.strip().splitlines()[-1] == "Error: updates must be in [1, ∞]; got 0."
