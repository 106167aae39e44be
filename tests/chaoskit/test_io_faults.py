"""Imports a new user tries first: odd CSV files, map data, damaged files, foreign attributes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit._contract import REQUIRED_GLOBAL_ATTRS

LOGISTIC = np.asarray(chaoskit.systems.logistic(300, r=3.9))
VALUES = LOGISTIC.tolist()  # Python floats, whose repr is a plain number


def _write(tmp_path: Path, text: str, name: str = "in.csv", encoding: str = "utf-8") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding=encoding)
    return path


def _column(values: np.ndarray) -> str:
    return "\n".join(repr(float(v)) for v in values) + "\n"


def test_one_column_csv_loads(tmp_path: Path) -> None:
    path = _write(tmp_path, "displacement\n" + _column(LOGISTIC))
    ds = chaoskit.load_trajectory(path, dt=0.5)
    assert list(ds.data_vars) == ["displacement"]
    np.testing.assert_array_equal(ds["displacement"].values, LOGISTIC)
    assert float(ds["time"][2]) == 1.0


def test_utf8_byte_order_mark_does_not_hide_the_time_column(tmp_path: Path) -> None:
    rows = "".join(f"{0.1 * i!r},{v!r}\n" for i, v in enumerate(VALUES))
    path = _write(tmp_path, "time,x\n" + rows, encoding="utf-8-sig")
    assert path.read_bytes()[:3] == b"\xef\xbb\xbf"
    ds = chaoskit.load_trajectory(path)
    assert list(ds.data_vars) == ["x"]
    np.testing.assert_allclose(ds["time"].values[:3], [0.0, 0.1, 0.2])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("time,x\n", "has a header but no data rows"),
        ("", "is empty"),
        ("time,x,x\n0,1,2\n1,2,3\n", r"duplicate column names \['x'\]"),
        ("time,x\n0;1\n1 2 3\n", "cannot tell the column delimiter"),
        ("time,x\n0,1\n1,oops\n", "not numeric"),
    ],
)
def test_bad_csv_gets_a_one_line_error(tmp_path: Path, text: str, message: str) -> None:
    with pytest.raises(ValueError, match=message) as err:
        chaoskit.load_trajectory(_write(tmp_path, text))
    assert "\n" not in str(err.value)


def test_other_delimiters_and_blank_separated_columns(tmp_path: Path) -> None:
    for sep in (";", "\t", "|", "  "):
        text = f"t{sep}a{sep}b\n" + "".join(
            f"{i}{sep}{v!r}{sep}{2 * v!r}\n" for i, v in enumerate(VALUES[:50])
        )
        ds = chaoskit.load_trajectory(_write(tmp_path, text, name="d.txt"))
        assert list(ds.data_vars) == ["a", "b"], sep
        np.testing.assert_array_equal(ds["b"].values, 2 * LOGISTIC[:50])


def test_map_indexed_by_a_step_column_or_by_row(tmp_path: Path) -> None:
    rows = "".join(f"{i + 100},{v!r}\n" for i, v in enumerate(VALUES))
    by_column = chaoskit.load_trajectory(_write(tmp_path, "n,x\n" + rows), step="n")
    assert "time" not in by_column.coords
    np.testing.assert_array_equal(by_column["step"].values, np.arange(100, 400))
    by_row = chaoskit.load_trajectory(_write(tmp_path, "x\n" + _column(LOGISTIC)), step="step")
    np.testing.assert_array_equal(by_row["step"].values, np.arange(300))
    from_array = chaoskit.load_trajectory(LOGISTIC, step="step")
    assert from_array["step"].dtype.kind == "i" and list(from_array.data_vars) == ["x"]
    assert chaoskit.classify(from_array, rng=0).kind == "map"
    with pytest.raises(ValueError, match="step column 'k' not found"):
        chaoskit.load_trajectory(_write(tmp_path, "n,x\n" + rows), step="k")
    with pytest.raises(ValueError, match="must hold integers"):
        chaoskit.load_trajectory(_write(tmp_path, "n,x\n0.5,1\n1.5,2\n"), step="n")
    with pytest.raises(ValueError, match="not dt and step"):
        chaoskit.load_trajectory(LOGISTIC, dt=1.0, step="step")


def test_step_indexed_csv_written_by_save_trajectory_loads_back(tmp_path: Path) -> None:
    ds = chaoskit.load_trajectory(LOGISTIC, step="step")
    back = chaoskit.load_trajectory(chaoskit.save_trajectory(ds, tmp_path / "map.csv"))
    xr.testing.assert_identical(back, ds)


def test_save_fills_missing_provenance_and_keeps_a_foreign_source(tmp_path: Path) -> None:
    bare = xr.Dataset(
        {"x": ("time", np.sin(np.arange(50) * 0.1))},
        coords={"time": np.arange(50) * 0.1},
        attrs={"source": "lab rig 3, accelerometer A"},
    )
    path = chaoskit.save_trajectory(bare, tmp_path / "bare.nc")
    assert bare.attrs == {"source": "lab rig 3, accelerometer A"}  # the input is not touched
    assert "units" not in bare["x"].attrs
    back = chaoskit.load_trajectory(path)
    for key in REQUIRED_GLOBAL_ATTRS:
        assert key in back.attrs
    assert back.attrs["source"] == "lab rig 3, accelerometer A"
    assert back["x"].attrs["units"] == "unknown"
    loaded = chaoskit.load_trajectory(bare)  # load keeps it too
    assert loaded.attrs["source"] == "lab rig 3, accelerometer A"


def test_damaged_and_wrong_paths_get_one_line_errors(tmp_path: Path) -> None:
    good = chaoskit.save_trajectory(
        chaoskit.load_trajectory(LOGISTIC, dt=0.1), tmp_path / "good.nc"
    )
    truncated = tmp_path / "cut.nc"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    not_zip = _write(tmp_path, "not a zip", name="bad.npz")
    folder = tmp_path / "folder.nc"
    folder.mkdir()
    for path, message in [
        (truncated, "not a readable netCDF-4 file"),
        (_write(tmp_path, "time,x\n0,1\n", name="text.nc"), "not a readable netCDF-4 file"),
        (not_zip, "not a readable npz file"),
        (folder, "is a folder"),
    ]:
        with pytest.raises(ValueError, match=message) as err:
            chaoskit.load_trajectory(path)
        assert "\n" not in str(err.value)
