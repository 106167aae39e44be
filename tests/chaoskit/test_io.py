"""load_trajectory / save_trajectory: round trips and clear errors on bad input."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import chaoskit
from chaoskit._contract import REQUIRED_GLOBAL_ATTRS, stamp


@pytest.fixture
def trajectory() -> xr.Dataset:
    t = np.arange(200) * 0.01
    ds = xr.Dataset(
        {
            "x": ("time", np.sin(2 * np.pi * t), {"units": "m", "long_name": "position"}),
            "v": (
                "time",
                2 * np.pi * np.cos(2 * np.pi * t),
                {"units": "m s-1", "long_name": "speed"},
            ),
        },
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
    )
    ds = stamp(
        ds, title="test sine", history="made in a test", extra={"scene": json.dumps({"a": 1})}
    )
    return chaoskit.validate_trajectory(ds)


@pytest.mark.parametrize("suffix", [".nc", ".csv", ".npz"])
def test_round_trip_keeps_values_coords_and_attrs(tmp_path, trajectory, suffix) -> None:
    path = chaoskit.save_trajectory(trajectory, tmp_path / f"traj{suffix}")
    back = chaoskit.load_trajectory(path)
    xr.testing.assert_identical(back, trajectory)
    assert back["time"].dtype == np.float64
    assert json.loads(back.attrs["scene"]) == {"a": 1}
    for key in REQUIRED_GLOBAL_ATTRS:
        assert back.attrs[key] == trajectory.attrs[key]


def test_save_is_atomic_and_leaves_no_temporary_files(tmp_path, trajectory) -> None:
    target = tmp_path / "out.nc"
    chaoskit.save_trajectory(trajectory, target)
    chaoskit.save_trajectory(trajectory, target)  # overwrite
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


def test_failed_save_keeps_the_old_file(tmp_path, trajectory) -> None:
    target = tmp_path / "out.nc"
    chaoskit.save_trajectory(trajectory, target)
    before = target.read_bytes()
    bad = trajectory.copy()
    bad.attrs["oops"] = {"not": "storable"}
    with pytest.raises(TypeError, match="attribute 'oops'"):
        chaoskit.save_trajectory(bad, target)
    assert target.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


def test_sources_in_memory() -> None:
    x = np.cos(np.arange(50) * 0.1)
    from_array = chaoskit.load_trajectory(x, dt=0.1)
    assert list(from_array.data_vars) == ["x"]
    np.testing.assert_allclose(from_array["time"].values[:3], [0.0, 0.1, 0.2])
    assert from_array["x"].attrs["units"] == "unknown"
    assert "numpy array" in from_array.attrs["history"]

    frame = pd.DataFrame({"t": np.arange(50) * 0.1, "a": x, "b": 2 * x})
    from_frame = chaoskit.load_trajectory(frame)
    assert list(from_frame.data_vars) == ["a", "b"]
    only_b = chaoskit.load_trajectory(frame, variables=["b"])
    assert list(only_b.data_vars) == ["b"]

    da = xr.DataArray(x, dims="sample", name="signal")
    from_da = chaoskit.load_trajectory(da, dt=0.5)
    np.testing.assert_allclose(from_da["time"].values[1], 0.5)

    two_cols = chaoskit.load_trajectory(np.c_[x, x], dt=1.0, variables=["p", "q"])
    assert list(two_cols.data_vars) == ["p", "q"]


def test_map_with_integer_step(tmp_path) -> None:
    ds = xr.Dataset(
        {"x": ("step", chaoskit.systems.logistic(100), {"units": "1", "long_name": "x"})},
        coords={"step": ("step", np.arange(100))},
    )
    ds = stamp(ds, title="logistic")
    back = chaoskit.load_trajectory(chaoskit.save_trajectory(ds, tmp_path / "map.nc"))
    assert back["step"].dtype.kind == "i"
    with pytest.raises(ValueError, match="step must be integer"):
        chaoskit.validate_trajectory(ds.assign_coords(step=np.linspace(0, 1, 100)))


def test_sampling_interval(trajectory) -> None:
    assert chaoskit.sampling_interval(trajectory) == pytest.approx(0.01)
    t = trajectory["time"].values.copy()
    t[50:] += 0.003
    with pytest.raises(ValueError, match="not uniformly sampled"):
        chaoskit.sampling_interval(trajectory.assign_coords(time=t))


# --- bad input: each names the problem ------------------------------------------------


def _csv(tmp_path, text: str):
    path = tmp_path / "in.csv"
    path.write_text(text)
    return path


def test_missing_file(tmp_path) -> None:
    with pytest.raises(FileNotFoundError, match="no such trajectory file"):
        chaoskit.load_trajectory(tmp_path / "absent.nc")


def test_unknown_format(tmp_path) -> None:
    path = tmp_path / "data.xlsx"
    path.write_text("x")
    with pytest.raises(ValueError, match=r"unknown file format '\.xlsx'"):
        chaoskit.load_trajectory(path)


def test_no_time_column(tmp_path) -> None:
    with pytest.raises(ValueError, match="no time column"):
        chaoskit.load_trajectory(_csv(tmp_path, "a,b\n1,2\n3,4\n"))
    with pytest.raises(ValueError, match="carries no time"):
        chaoskit.load_trajectory(np.arange(10.0))


def test_named_time_column_missing(tmp_path) -> None:
    with pytest.raises(ValueError, match="time column 'secs' not found"):
        chaoskit.load_trajectory(_csv(tmp_path, "t,a\n0,1\n1,2\n"), time="secs")


def test_non_monotonic_time(tmp_path) -> None:
    with pytest.raises(ValueError, match="not monotonic increasing"):
        chaoskit.load_trajectory(_csv(tmp_path, "time,a\n0,1\n2,2\n1,3\n"))


def test_duplicated_time(tmp_path) -> None:
    with pytest.raises(ValueError, match="duplicated values"):
        chaoskit.load_trajectory(_csv(tmp_path, "time,a\n0,1\n1,2\n1,3\n"))


def test_nan_and_inf_values(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"column 'a' of .* a missing value \(NaN\) at line 3;"):
        chaoskit.load_trajectory(_csv(tmp_path, "time,a\n0,1\n1,nan\n2,3\n"))
    with pytest.raises(ValueError, match=r"column 'a' of .* holds an infinite value at line 3 "):
        chaoskit.load_trajectory(_csv(tmp_path, "time,a\n0,1\n1,inf\n2,3\n"))


def test_non_uniform_sampling_where_required(tmp_path) -> None:
    path = _csv(tmp_path, "time,a\n0,1\n1,2\n3,3\n")
    assert chaoskit.load_trajectory(path).sizes["time"] == 3
    with pytest.raises(ValueError, match="not uniformly sampled"):
        chaoskit.load_trajectory(path, require_uniform=True)


def test_non_numeric_column(tmp_path) -> None:
    with pytest.raises(ValueError, match=r"column 'label' .* is not numeric"):
        chaoskit.load_trajectory(_csv(tmp_path, "time,a,label\n0,1,x\n1,2,y\n"))
    frame = pd.DataFrame({"time": [0.0, 1.0], "label": ["x", "y"]})
    with pytest.raises(ValueError, match="is not numeric"):
        chaoskit.load_trajectory(frame)


def test_non_positive_dt() -> None:
    with pytest.raises(ValueError, match="dt must be a finite positive"):
        chaoskit.load_trajectory(np.arange(5.0), dt=0.0)


def test_unsupported_source_type() -> None:
    with pytest.raises(TypeError, match="cannot load a trajectory from dict"):
        chaoskit.load_trajectory({"a": 1})


def test_csv_refuses_multidimensional_variables(tmp_path, trajectory) -> None:
    ds = trajectory.assign(
        m=(("time", "axis"), np.zeros((200, 2)), {"units": "m", "long_name": "m"})
    )
    with pytest.raises(ValueError, match="Save to netCDF"):
        chaoskit.save_trajectory(ds, tmp_path / "x.csv")


def test_contract_requires_attrs(trajectory) -> None:
    bare = trajectory.copy()
    del bare["x"].attrs["units"]
    with pytest.raises(ValueError, match="variable 'x' has no 'units'"):
        chaoskit.validate_trajectory(bare)
    no_global = trajectory.copy()
    no_global.attrs.pop("created")
    with pytest.raises(ValueError, match="lacks the global attribute"):
        chaoskit.validate_trajectory(no_global)
