"""Tables as measurement rigs and loggers write them: units in headers, title lines, decimal
commas, missing values, pandas time indexes; and errors that name the parameter to pass."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import chaoskit
from chaoskit._units import cf_units
from chaoskit.contract import ParameterError, variable_name

SINE = np.sin(0.3 * np.arange(40)).tolist()  # Python floats: repr is a plain number


def _write(tmp_path: Path, text: str, name: str = "rig.csv") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _rows(values: list[float], dt: float = 0.01, sep: str = ",") -> str:
    return "".join(f"{dt * i!r}{sep}{v!r}{sep}{2 * v!r}\n" for i, v in enumerate(values))


# ----------------------------------------------------------------- headers with units


def test_headers_with_units_give_name_long_name_and_cf_units(tmp_path: Path) -> None:
    path = _write(tmp_path, "time (s),acc y [m/s^2],x / mm\n" + _rows(SINE))
    ds = chaoskit.load_trajectory(path)
    assert list(ds.data_vars) == ["acc_y", "x"]
    assert (ds["acc_y"].attrs["units"], ds["acc_y"].attrs["long_name"]) == ("m s-2", "acc y")
    assert (ds["x"].attrs["units"], ds["x"].attrs["long_name"]) == ("mm", "x")
    assert float(ds["time"][3]) == pytest.approx(0.03, rel=1e-15)
    np.testing.assert_array_equal(ds["x"].values, 2 * np.asarray(SINE))
    # the header as written, its name part and the variable name all select a column
    for name in ("acc y [m/s^2]", "acc y", "acc_y"):
        assert list(chaoskit.load_trajectory(path, variables=[name]).data_vars) == ["acc_y"]


def test_a_time_column_in_milliseconds_becomes_seconds(tmp_path: Path) -> None:
    rows = "".join(f"{10 * i},{v!r}\n" for i, v in enumerate(SINE))
    ds = chaoskit.load_trajectory(_write(tmp_path, "t [ms],x\n" + rows))
    assert float(ds["time"][1]) == pytest.approx(0.01, rel=1e-15)
    assert ds["time"].attrs["units"] == "s" and ds["time"].attrs["comment"] == "converted from ms"
    with pytest.raises(ValueError, match=r"in 'fortnights'; chaoskit reads time in s, "):
        chaoskit.load_trajectory(_write(tmp_path, "time (fortnights),x\n0,1\n1,2\n"))


def test_unit_spellings_and_variable_names() -> None:
    assert cf_units("m/s^2") == "m s-2"
    assert cf_units("kg*m/s**2") == "kg m s-2"
    assert cf_units("1/s") == "s-1"
    assert cf_units("m·s⁻¹") == "m s-1"
    assert cf_units("µm") == "um"
    assert cf_units("%") == "percent"
    assert cf_units("-") == "1"
    assert cf_units("counts (raw)") == "counts (raw)"  # kept as written
    assert variable_name("acc y") == "acc_y"
    assert variable_name("2nd sensor") == "x_2nd_sensor"
    assert variable_name("eccentricity_x") == "eccentricity_x"


def test_headers_that_become_the_same_name_are_refused(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"columns \['a b', 'a-b'\] of .* all become the var"):
        chaoskit.load_trajectory(_write(tmp_path, "time,a b,a-b\n0,1,2\n1,2,3\n"))


# ----------------------------------------------------------------- title lines


def test_a_title_line_is_named_and_skip_rows_skips_it(tmp_path: Path) -> None:
    with pytest.raises(ValueError) as err:
        chaoskit.load_trajectory(_write(tmp_path, "Rig 3 run 7\ntime,x,y\n" + _rows(SINE)))
    assert str(err.value).endswith(
        "its first line (line 1) has 1 field(s) where the lines below have 3 (','-separated); "
        "if the first line is a title, skip it with skip_rows=1 to load_trajectory."
    )
    # a title with as many commas as the header: the header reads as the first data row
    rows = "".join(f"{i},{v!r}\n" for i, v in enumerate(SINE))
    path = _write(tmp_path, "Rig 3, run 7\n\ntime,x\n" + rows)
    with pytest.raises(ValueError) as err:
        chaoskit.load_trajectory(path)
    assert str(err.value) == (
        f"line 3 of {path} holds words where numbers belong, below the header on line 1 "
        "('Rig 3, run 7'); if that line is a title, skip it with skip_rows=1 to "
        "load_trajectory; units belong in the header, as in 'time (s)'."
    )
    ds = chaoskit.load_trajectory(path, skip_rows=1)
    assert list(ds.data_vars) == ["x"] and ds.sizes["time"] == len(SINE)
    with pytest.raises(ValueError, match=r"skip_rows must be in \[0, ∞\]; got -1"):
        chaoskit.load_trajectory(path, skip_rows=-1)
    nc = chaoskit.save_trajectory(ds, tmp_path / "rig.nc")
    with pytest.raises(ValueError, match=r"skip_rows= and decimal= apply to text tables"):
        chaoskit.load_trajectory(nc, skip_rows=1)


# ----------------------------------------------------------------- decimal comma


def test_decimal_comma_is_named_and_read_with_decimal(tmp_path: Path) -> None:
    text = "time;x;y\n" + _rows(SINE, sep=";").replace(".", ",")
    path = _write(tmp_path, text)
    with pytest.raises(ValueError) as err:
        chaoskit.load_trajectory(path)
    assert str(err.value).endswith(
        "holds '0,0', a number with a decimal comma (pass decimal=',' to load_trajectory)."
    )
    ds = chaoskit.load_trajectory(path, decimal=",")
    np.testing.assert_array_equal(ds["y"].values, 2 * np.asarray(SINE))
    assert float(ds["time"][1]) == 0.01
    with pytest.raises(ValueError, match=r"decimal must be one of '\.', ','; got ' '"):
        chaoskit.load_trajectory(path, decimal=" ")
    with pytest.raises(
        ValueError,
        match=r"c\.csv is comma-separated, so its decimal mark cannot be a comma; leave out "
        r"decimal=','\.$",
    ):
        chaoskit.load_trajectory(_write(tmp_path, "time,x\n0,1\n1,2\n", "c.csv"), decimal=",")


# ----------------------------------------------------------------- missing values

GAPPY = "time,x,y\n0,0,0\n0.5,,1\n1,2,\n1.5,3,3\n2,4,4\n2.5,5,\n"


def test_missing_values_are_refused_with_column_and_line(tmp_path: Path) -> None:
    with pytest.raises(ValueError) as err:
        chaoskit.load_trajectory(_write(tmp_path, GAPPY))
    assert str(err.value).startswith("column 'x' of ")
    assert str(err.value).endswith(
        "has a missing value (NaN) at line 3 (3 missing values in 2 column(s)); fill the gaps, "
        "or pass nan='interpolate' (linear in time) or nan='drop' to load_trajectory."
    )
    with pytest.raises(ValueError, match=r"nan must be one of 'refuse', 'drop', 'interpolate'"):
        chaoskit.load_trajectory(_write(tmp_path, GAPPY), nan="zero")


def test_missing_values_are_interpolated_in_time_and_recorded(tmp_path: Path) -> None:
    ds = chaoskit.load_trajectory(_write(tmp_path, GAPPY), nan="interpolate")
    np.testing.assert_allclose(ds["time"].values, [0.0, 0.5, 1.0, 1.5, 2.0], rtol=0, atol=0)
    np.testing.assert_allclose(ds["x"].values, [0.0, 1.0, 2.0, 3.0, 4.0], rtol=1e-15)
    np.testing.assert_allclose(ds["y"].values, [0.0, 1.0, 2.0, 3.0, 4.0], rtol=1e-15)
    assert ds["x"].attrs["interpolated_samples"] == 1
    assert ds["x"].attrs["interpolated_gaps"] == "line 3 (t = 0.5 s)"
    assert ds["y"].attrs["interpolated_gaps"] == "line 4 (t = 1 s)"
    assert "dropped 1 row(s) at the ends: line 7 (t = 2.5 s)" in ds.attrs["history"]
    # non-uniform time: linear in time, not in rows
    ds = chaoskit.load_trajectory(_write(tmp_path, "time,x\n0,0\n1,\n4,4\n"), nan="interpolate")
    assert float(ds["x"][1]) == pytest.approx(1.0, rel=1e-15)


def test_drop_keeps_a_uniform_sampling_uniform(tmp_path: Path) -> None:
    with pytest.raises(ValueError) as err:
        chaoskit.load_trajectory(_write(tmp_path, GAPPY), nan="drop")
    assert "nan='drop' would leave gaps in the uniform sampling of" in str(err.value)
    assert "2 row(s) with missing values inside the record, the first at line 3" in str(err.value)
    ends = "time,x\n0,\n1,1\n2,2\n3,3\n4,\n"
    ds = chaoskit.load_trajectory(_write(tmp_path, ends), nan="drop")
    np.testing.assert_array_equal(ds["time"].values, [1.0, 2.0, 3.0])
    assert "dropped 2 row(s) with missing values: line 2 (t = 0 s), line 6" in ds.attrs["history"]
    ragged = "time,x\n0,0\n1,\n3,3\n7,7\n"  # already non-uniform: a drop changes nothing
    assert chaoskit.load_trajectory(_write(tmp_path, ragged), nan="drop").sizes["time"] == 3


def test_infinite_values_are_always_refused_and_maps_not_interpolated(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"holds an infinite value at line 3 \(1 in all\)"):
        chaoskit.load_trajectory(_write(tmp_path, "time,x\n0,1\n1,inf\n2,3\n"), nan="drop")
    frame = pd.DataFrame({"x": [0.1, np.nan, 0.3, 0.4]})
    missing = r"column 'x' of the DataFrame has a missing value \(NaN\) at row 1 \(0-based\)"
    with pytest.raises(ValueError, match=missing):
        chaoskit.load_trajectory(frame, step="step")
    with pytest.raises(ValueError, match="the iterations of a map cannot be interpolated"):
        chaoskit.load_trajectory(frame, step="step", nan="interpolate")


# ----------------------------------------------------------------- pandas and xarray time


def test_a_pandas_time_index_sets_the_time_in_seconds() -> None:
    x = np.asarray(SINE)
    stamps = pd.date_range("2020-03-01", periods=len(x), freq="10ms")
    offsets = pd.timedelta_range(0, periods=len(x), freq="10ms")
    for index in (stamps, offsets, pd.Index(np.arange(len(x)) * 0.01)):
        ds = chaoskit.load_trajectory(pd.Series(x, index=index, name="x"))
        assert chaoskit.sampling_interval(ds) == pytest.approx(0.01, rel=1e-12)
        assert float(ds["time"][0]) == 0.0
    ds = chaoskit.load_trajectory(pd.DataFrame({"x": x}, index=stamps))
    assert ds["time"].attrs["comment"] == "seconds since 2020-03-01T00:00:00"
    assert chaoskit.load_trajectory(pd.Series(x, index=stamps), dt=0.01).sizes["time"] == 40
    contradicts = (
        r"^dt=0\.02 contradicts the time index of the Series \(sampling interval 0\.01 s\)"
    )
    with pytest.raises(ValueError, match=contradicts):
        chaoskit.load_trajectory(pd.Series(x, index=stamps), dt=0.02)
    jitter = stamps.to_numpy().copy()
    jitter[10:] += np.timedelta64(5, "ms")
    uneven = pd.Series(x, index=pd.DatetimeIndex(jitter))
    assert chaoskit.load_trajectory(uneven).sizes["time"] == 40  # loading alone is fine
    uneven_index = (
        r"^the time index of the Series is not uniform \(intervals from 0\.01 s to 0\.015 s\)"
    )
    with pytest.raises(ValueError, match=uneven_index):
        chaoskit.load_trajectory(uneven, require_uniform=True)


def test_datetime_time_and_a_named_time_variable_in_a_dataset() -> None:
    stamps = pd.date_range("2020", periods=5, freq="250ms").to_numpy()
    ds = xr.Dataset({"x": ("time", np.arange(5.0))}, coords={"time": stamps})
    out = chaoskit.load_trajectory(ds)
    np.testing.assert_allclose(out["time"].values, [0.0, 0.25, 0.5, 0.75, 1.0], rtol=0, atol=0)
    with pytest.raises(ValueError, match=r"dt=0\.5 contradicts the time coordinate"):
        chaoskit.load_trajectory(ds, dt=0.5)
    clock = ("n", np.arange(5) * 20.0, {"units": "ms"})
    bare = xr.Dataset({"x": ("n", np.arange(5.0)), "clock": clock})
    out = chaoskit.load_trajectory(bare, time="clock")
    np.testing.assert_allclose(out["time"].values, np.arange(5) * 0.02, rtol=1e-15)
    assert list(out.data_vars) == ["x"]


# ----------------------------------------------------------------- parameter errors


def test_errors_name_parameters_for_python_and_for_the_command_line() -> None:
    bare = xr.Dataset({"x": ("n", np.arange(5.0))})
    with pytest.raises(ParameterError) as err:
        chaoskit.validate_trajectory(bare)
    python = str(err.value)
    assert python.endswith(
        "pass time= (the variable holding the time, s), dt= (the sampling interval, s) or "
        "step= (a map) to load_trajectory."
    )
    assert err.value.render(command_line=True).endswith(
        "pass --time (the variable holding the time, s), --dt (the sampling interval, s) or "
        "--step (a map)."
    )
    again = pickle.loads(pickle.dumps(err.value))
    assert str(again) == python and again.render(command_line=True).endswith("--step (a map).")
    literal = ParameterError(f"file {ParameterError.literal('{a}.csv')}: pass {{skip_rows=2}}")
    assert str(literal) == "file {a}.csv: pass skip_rows=2"
    assert literal.render(command_line=True) == "file {a}.csv: pass --skip-rows 2"
