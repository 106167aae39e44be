"""Files test rigs write (MATLAB .mat v5 and v7.3, NI TDMS, HDF5, WAV, Parquet) read into the
trajectory contract: each format round-trips a known signal written by its own library, and
every malformed file ends in one line naming the file, the variable and what was expected."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pandas as pd
import pytest
import scipy.io
import scipy.io.wavfile
import scipy.sparse
from nptdms import ChannelObject, TdmsWriter
from typer.testing import CliRunner

import chaoskit
from chaoskit import _formats
from chaoskit.cli import app
from chaoskit.contract import ParameterError
from tests.chaoskit.test_cli_faults import stub_analysis

runner = CliRunner()
N = 400
DT = 1e-3
T = DT * np.arange(N)
X = np.sin(2 * np.pi * 7.0 * T)
Y = np.cos(2 * np.pi * 3.0 * T) * 0.25


# ----------------------------------------------------------------- MATLAB v7.3 as MATLAB writes it

MAT73_HEADER = (
    b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  8 09:00:00 2024 "
    b"HDF5 schema 1.00 ."
)
MATLAB_CLASS = {"f8": "double", "f4": "single", "i2": "int16", "u1": "logical"}


def _mat73_char(parent: h5py.Group, name: str, text: str) -> h5py.Dataset:
    codes = np.array([[ord(c) for c in text]], dtype=np.uint16).T  # MATLAB 1 × n: HDF5 (n, 1)
    dset = parent.create_dataset(name, data=codes)
    dset.attrs["MATLAB_class"] = np.bytes_("char")
    dset.attrs["MATLAB_int_decode"] = np.int32(2)
    return dset


def _mat73_put(parent: h5py.Group, name: str, value: Any) -> None:
    if isinstance(value, dict):  # a scalar struct: a group, fields in MATLAB_fields order
        group = parent.create_group(name)
        group.attrs["MATLAB_class"] = np.bytes_("struct")
        fields = np.empty(len(value), dtype=object)
        for i, key in enumerate(value):
            fields[i] = np.array(list(key), dtype="S1")
        group.attrs.create("MATLAB_fields", fields, dtype=h5py.vlen_dtype(np.dtype("S1")))
        for key, item in value.items():
            _mat73_put(group, key, item)
    elif isinstance(value, str):
        _mat73_char(parent, name, value)
    elif isinstance(value, list):  # a cellstr: references to char arrays in #refs#
        refs = parent.file.require_group("#refs#")
        cells = np.empty((len(value), 1), dtype=h5py.ref_dtype)
        for i, text in enumerate(value):
            cells[i, 0] = _mat73_char(refs, f"{name}_{i}", text).ref
        dset = parent.create_dataset(name, data=cells)
        dset.attrs["MATLAB_class"] = np.bytes_("cell")
    else:
        arr = np.asarray(value)
        if arr.dtype.kind == "c":
            stored = np.empty(arr.shape, dtype=[("real", "f8"), ("imag", "f8")])
            stored["real"], stored["imag"] = arr.real, arr.imag
            cls = "double"
        else:
            stored, cls = arr, MATLAB_CLASS[arr.dtype.str[1:]]
        dset = parent.create_dataset(name, data=stored.T)  # column-major: the shape reversed
        dset.attrs["MATLAB_class"] = np.bytes_(cls)


def write_mat73(path: Path, variables: dict[str, Any]) -> Path:
    """A MATLAB v7.3 file: HDF5 behind a 512-byte user block holding MATLAB's header, every
    variable with its ``MATLAB_class``, arrays stored transposed (MATLAB is column-major)."""
    with h5py.File(path, "w", userblock_size=512) as f:
        for name, value in variables.items():
            _mat73_put(f, name, value)
    with path.open("r+b") as fh:
        fh.write(MAT73_HEADER.ljust(116) + b" " * 8 + b"\x00\x02" + b"IM")
    return path


def _tdms(path: Path, channels: list[ChannelObject]) -> Path:
    with TdmsWriter(path) as writer:
        writer.write_segment(channels)
    return path


def _waveform(dt: float = DT, offset: float = 0.0, unit: str | None = None) -> dict[str, Any]:
    props: dict[str, Any] = {"wf_increment": dt, "wf_start_offset": offset}
    if unit is not None:
        props["unit_string"] = unit
    return props


# ----------------------------------------------------------------- round trips


def test_mat_v5_vectors_either_way_round_and_a_matrix_with_names_and_units(tmp_path: Path):
    path = tmp_path / "rig.mat"
    scipy.io.savemat(
        path,
        {
            "t": T[None, :],  # 1 × n
            "x": X[:, None],  # n × 1
            "acc": np.c_[X, Y],  # one column per channel
            "names": np.array(["acc x", "acc y"]),  # a char matrix
            "units": np.array(["m/s^2", "m/s^2"]),
            "note": "bench 3, run 12",
        },
    )
    ds = chaoskit.load_trajectory(path)
    assert list(ds.data_vars) == ["x", "acc_x", "acc_y"]
    np.testing.assert_array_equal(ds["x"].values, X)
    np.testing.assert_array_equal(ds["acc_y"].values, Y)
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    assert (ds["acc_x"].attrs["units"], ds["acc_x"].attrs["long_name"]) == ("m s-2", "acc x")
    assert ds["x"].attrs["units"] == "unknown"
    assert ds.attrs["source"].startswith("MATLAB 5.0 MAT-file")
    # a matrix without names: columns numbered as MATLAB does
    scipy.io.savemat(path, {"t": T, "data": np.c_[X, Y]})
    ds = chaoskit.load_trajectory(path, variables=["data_2"])
    np.testing.assert_array_equal(ds["data_2"].values, Y)
    assert ds["data_2"].attrs["long_name"] == "data(:,2)"
    # a column picked by the name the file gives it; units of vectors from a struct
    scipy.io.savemat(
        path,
        {"t": T, "data": np.c_[X, Y], "names": ["x", "v"], "p": X, "units": {"p": "bar"}},
    )
    ds = chaoskit.load_trajectory(path, variables=["v", "p"])
    np.testing.assert_array_equal(ds["v"].values, Y)
    assert ds["p"].attrs["units"] == "bar"


def test_mat_v4_and_a_sample_rate_scalar_give_the_time(tmp_path: Path) -> None:
    path = tmp_path / "rig.mat"
    scipy.io.savemat(path, {"x": X, "fs": 1000.0}, format="4")
    ds = chaoskit.load_trajectory(path)
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    assert ds["time"].attrs["comment"] == "from the sampling rate fs = 1000 Hz in the file"
    with pytest.raises(ValueError, match=r"^dt=0\.002 contradicts the time index of "):
        chaoskit.load_trajectory(path, dt=0.002)


def test_mat_struct_of_vectors_and_the_group_option(tmp_path: Path) -> None:
    path = tmp_path / "runs.mat"
    scipy.io.savemat(path, {"run1": {"t": T, "x": X}, "run2": {"t": T, "x": 2 * X}})
    with pytest.raises(ParameterError) as info:
        chaoskit.load_trajectory(path)
    assert str(info.value) == (
        f"{path} holds the structs ['run1', 'run2']; pick one with group='run1' to load_trajectory."
    )
    ds = chaoskit.load_trajectory(path, group="run2")
    np.testing.assert_array_equal(ds["x"].values, 2 * X)
    assert ds.attrs["history"].endswith("loaded from runs.mat (struct 'run2')")
    with pytest.raises(ParameterError, match=r"has no struct 'run3'; its structs are \['run1', "):
        chaoskit.load_trajectory(path, group="run3")
    scipy.io.savemat(path, {"rig": {"t": T, "x": X}})  # the only struct: no group needed
    np.testing.assert_array_equal(chaoskit.load_trajectory(path)["x"].values, X)


def test_mat_v73_transposed_arrays_cellstr_names_char_units_and_structs(tmp_path: Path):
    path = write_mat73(
        tmp_path / "rig73.mat",
        {
            "t": T[None, :],
            "x": X[:, None],
            "acc": np.c_[X, Y],
            "names": ["acc x", "acc y"],
            "units": "mm",
            "run": {"tout": T[:, None], "y": np.float32(Y)[None, :], "flag": np.ones(N, "u1")},
        },
    )
    with h5py.File(path) as f:  # the layout MATLAB writes
        assert f.userblock_size == 512 and f["acc"].shape == (2, N) and f["x"].shape == (1, N)
    ds = chaoskit.load_trajectory(path)
    assert sorted(ds.data_vars) == ["acc_x", "acc_y", "x"]
    np.testing.assert_array_equal(ds["acc_x"].values, X)
    np.testing.assert_array_equal(ds["x"].values, X)
    assert ds["acc_y"].attrs["units"] == "mm" and ds["acc_y"].attrs["long_name"] == "acc y"
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    assert ds.attrs["source"].startswith("MATLAB 7.3 MAT-file")
    run = chaoskit.load_trajectory(path, group="run")  # Simulink's tout is the time
    np.testing.assert_array_equal(run["y"].values, np.float32(Y))
    assert float(run["time"][-1]) == pytest.approx(T[-1], rel=1e-15)
    # the suffix lies: the content decides
    lying = tmp_path / "rig73.h5"
    lying.write_bytes(path.read_bytes())
    np.testing.assert_array_equal(chaoskit.load_trajectory(lying)["x"].values, X)


def test_tdms_waveform_time_units_and_groups(tmp_path: Path) -> None:
    props = _waveform(offset=0.5, unit="m/s^2")
    props["wf_start_time"] = np.datetime64("2024-05-01T10:00:00")
    path = _tdms(
        tmp_path / "rig.tdms",
        [
            ChannelObject("bench", "acc x", X, properties=props),
            ChannelObject("bench", "y", Y, properties=_waveform(offset=0.5, unit="mm")),
            ChannelObject("bench", "operator", np.array(["ab"] * N)),
        ],
    )
    ds = chaoskit.load_trajectory(path)
    assert list(ds.data_vars) == ["acc_x", "y"]
    np.testing.assert_array_equal(ds["acc_x"].values, X)
    assert (ds["acc_x"].attrs["units"], ds["acc_x"].attrs["long_name"]) == ("m s-2", "acc x")
    assert ds["y"].attrs["units"] == "mm"
    assert float(ds["time"][0]) == 0.5
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    assert ds["time"].attrs["comment"].startswith("seconds since 2024-05-01T10:00:00, from ")
    assert list(chaoskit.load_trajectory(path, variables=["acc x"]).data_vars) == ["acc_x"]
    with pytest.raises(ParameterError, match=r"channel 'operator' of group 'bench' of .*"):
        chaoskit.load_trajectory(path, variables=["operator"])


def test_tdms_time_channel_and_microsecond_time_stamps(tmp_path: Path) -> None:
    seconds = _tdms(
        tmp_path / "secs.tdms",
        [
            ChannelObject("g", "Time", T * 1e3, properties={"unit_string": "ms"}),
            ChannelObject("g", "x", X),
        ],
    )
    ds = chaoskit.load_trajectory(seconds)
    assert float(ds["time"][1]) == pytest.approx(DT, rel=1e-12)
    assert ds["time"].attrs["comment"] == "converted from ms"
    # 3 kHz stamps rounded to whole microseconds: uniform up to their rounding
    start = np.datetime64("2024-05-01T10:00:00.000000")
    stamps = start + np.round(np.arange(N) / 3000 * 1e6).astype("timedelta64[us]")
    rounded = _tdms(
        tmp_path / "stamps.tdms",
        [ChannelObject("g", "Timestamp", stamps), ChannelObject("g", "x", X)],
    )
    ds = chaoskit.load_trajectory(rounded)
    assert chaoskit.sampling_interval(ds) == pytest.approx(1 / 3000, rel=1e-6)
    assert ds["time"].attrs["comment"] == "seconds since 2024-05-01T10:00:00"
    assert "rounded to 1e-06 s; regularised to a uniform grid" in ds.attrs["history"]


def test_hdf5_datasets_time_in_ms_units_attributes_and_groups(tmp_path: Path) -> None:
    path = tmp_path / "logger.h5"
    with h5py.File(path, "w") as f:
        run = f.create_group("run1")
        run.create_dataset("t", data=T * 1e3).attrs["units"] = "ms"
        run.create_dataset("x", data=X).attrs["units"] = "mm"
        run["x"].attrs["long_name"] = "slider position"
        run.create_dataset("forces", data=np.c_[X, Y]).attrs["names"] = [b"Fx", b"Fy"]
        f.create_group("run2").create_dataset("x", data=X)
    with pytest.raises(ParameterError, match=r"holds the groups \['run1', 'run2'\]; pick one "):
        chaoskit.load_trajectory(path)
    ds = chaoskit.load_trajectory(path, group="run1")
    assert list(ds.data_vars) == ["Fx", "Fy", "x"]
    assert (ds["x"].attrs["units"], ds["x"].attrs["long_name"]) == ("mm", "slider position")
    np.testing.assert_array_equal(ds["Fy"].values, Y)
    assert float(ds["time"][1]) == pytest.approx(DT, rel=1e-12)
    with pytest.raises(ParameterError, match=r"no group 'run3'; its groups are \['run1', "):
        chaoskit.load_trajectory(path, group="run3")
    # CF time units, and stamps in single precision: uniform up to their rounding
    with h5py.File(path, "w") as f:
        f["time"] = np.float32(T + 100.0)
        f["time"].attrs["units"] = "seconds since 2024-05-01 10:00:00"
        f["x"] = X
    ds = chaoskit.load_trajectory(path)
    assert ds["time"].attrs["comment"] == "seconds since 2024-05-01 10:00:00"
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-6)
    assert "rounded to 7.63e-06 s; regularised to a uniform grid" in ds.attrs["history"]


def test_hdf5_written_by_save_trajectory_stays_netcdf(tmp_path: Path) -> None:
    ds = chaoskit.load_trajectory(X, dt=DT)
    ds["x"].attrs["units"] = "m"
    path = chaoskit.save_trajectory(ds, tmp_path / "saved.h5")
    back = chaoskit.load_trajectory(path)
    np.testing.assert_array_equal(back["x"].values, X)
    assert back["x"].attrs["units"] == "m"


def test_wav_pcm_scaled_to_full_scale_and_float_kept(tmp_path: Path) -> None:
    counts = np.round(np.c_[X, -Y] * 32767).astype(np.int16)
    path = tmp_path / "logger.wav"
    scipy.io.wavfile.write(path, 2000, counts)
    ds = chaoskit.load_trajectory(path)
    assert list(ds.data_vars) == ["ch1", "ch2"]
    np.testing.assert_array_equal(ds["ch2"].values, counts[:, 1] / 32768.0)
    assert chaoskit.sampling_interval(ds) == pytest.approx(1 / 2000, rel=1e-12)
    attrs = ds["ch1"].attrs
    assert (attrs["units"], attrs["pcm_format"], attrs["pcm_full_scale"]) == ("1", "int16", 32768)
    assert attrs["comment"].startswith("fraction of full scale (int16 PCM: counts / 32768)")
    unsigned = tmp_path / "u8.wav"
    scipy.io.wavfile.write(unsigned, 100, np.array([0, 128, 255, 64], dtype=np.uint8))
    np.testing.assert_array_equal(
        chaoskit.load_trajectory(unsigned)["ch1"].values, [-1.0, 0.0, 127 / 128, -0.5]
    )
    floats = tmp_path / "f32.wav"
    scipy.io.wavfile.write(floats, 500, np.float32(X * 3.5))
    ds = chaoskit.load_trajectory(floats)
    np.testing.assert_array_equal(ds["ch1"].values, np.float32(X * 3.5))
    assert ds["ch1"].attrs["units"] == "unknown"  # the logger's units: the user supplies them


def test_parquet_like_a_csv_table(tmp_path: Path) -> None:
    path = tmp_path / "log.parquet"
    pd.DataFrame({"time (ms)": T * 1e3, "acc y [m/s^2]": X, "label": ["a"] * N}).to_parquet(
        path, engine="pyarrow"
    )
    ds = chaoskit.load_trajectory(path, variables=["acc y"])
    np.testing.assert_array_equal(ds["acc_y"].values, X)
    assert ds["acc_y"].attrs["units"] == "m s-2"
    assert float(ds["time"][1]) == pytest.approx(DT, rel=1e-12)
    stamped = tmp_path / "stamped.parquet"
    index = pd.date_range("2024-05-01 10:00", periods=N, freq="1ms", name="when")
    pd.DataFrame({"x": X}, index=index).to_parquet(stamped, engine="pyarrow")
    ds = chaoskit.load_trajectory(stamped)
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    assert ds["time"].attrs["comment"] == "seconds since 2024-05-01T10:00:00"
    titled = tmp_path / "titled.csv"  # text that starts like a MATLAB header is still text
    titled.write_text("MATLAB export of run 3\ntime,x\n0,1\n1,2\n")
    assert chaoskit.load_trajectory(titled, skip_rows=1).sizes["time"] == 2
    lying = tmp_path / "log.csv"  # a Parquet file with a .csv suffix
    lying.write_bytes(path.read_bytes())
    assert "acc_y" in chaoskit.load_trajectory(lying, variables=["acc_y"])


# ----------------------------------------------------------------- irregular time stamps


def test_irregular_stamps_are_refused_unless_resampled(tmp_path: Path) -> None:
    jitter = T.copy()
    jitter[1:-1:2] += 2e-4  # every other stamp late by 0.2 ms
    path = tmp_path / "jitter.mat"
    line = 3.0 * jitter - 1.0  # linear in time: interpolation reproduces it exactly
    scipy.io.savemat(path, {"t": jitter, "x": line})
    with pytest.raises(ParameterError) as info:
        chaoskit.load_trajectory(path)
    assert str(info.value) == (
        f"the time stamps of {path} are irregular: intervals from 0.0008 s to 0.0012 s "
        "(mean 0.001 s); the estimators need uniform sampling: pass resample='linear' to "
        "interpolate onto a uniform grid (with dt= for its interval) to load_trajectory."
    )
    ds = chaoskit.load_trajectory(path, resample="linear")
    assert chaoskit.sampling_interval(ds) == pytest.approx(1e-3, rel=1e-9)
    np.testing.assert_allclose(ds["x"].values, 3.0 * ds["time"].values - 1.0, atol=1e-12)
    assert ds.attrs["resample_method"] == "linear"
    assert ds.attrs["resample_interval"] == pytest.approx(1e-3, rel=1e-12)
    assert "onto 400 samples every 0.001 s, linear interpolation" in ds.attrs["history"]
    coarse = chaoskit.load_trajectory(path, resample="linear", dt=0.004)
    assert coarse.sizes["time"] == 100 and coarse.attrs["resample_interval"] == 0.004


def test_dropped_samples_are_a_gap_and_nan_is_handled_first(tmp_path: Path) -> None:
    keep = np.r_[0:100, 103:N]
    path = tmp_path / "gap.mat"
    x = X.copy()
    x[50] = np.nan
    scipy.io.savemat(path, {"t": T[keep], "x": x[keep]})
    with pytest.raises(ParameterError, match=r"variable 'x' of .* at row 50 \(0-based\)"):
        chaoskit.load_trajectory(path)
    with pytest.raises(ParameterError) as info:
        chaoskit.load_trajectory(path, nan="interpolate")
    assert "1 gap(s) longer than 1.5 intervals, the first at t = 0.099 s" in str(info.value)
    ds = chaoskit.load_trajectory(path, nan="interpolate", resample="linear")
    assert ds.sizes["time"] == N and ds["x"].attrs["interpolated_samples"] == 1
    assert float(ds["x"][101]) == pytest.approx(X[99] + (X[103] - X[99]) * 2 / 4, rel=1e-12)


# ----------------------------------------------------------------- malformed files


def _bad_files(tmp_path: Path) -> dict[str, tuple[Path, dict[str, Any], str]]:
    """name -> (file, options, the start of its one-line message after the path)."""
    out: dict[str, tuple[Path, dict[str, Any], str]] = {}

    def mat(name: str, variables: dict[str, Any], options: dict[str, Any], msg: str) -> None:
        path = tmp_path / f"{name}.mat"
        scipy.io.savemat(path, variables)
        out[name] = (path, options, msg)

    mat("text_only", {"note": "calibration"}, {}, " holds no numeric series (it holds 'note'")
    mat("unequal", {"rig": {"t": T, "x": X[:-1]}}, {}, "the variables of struct 'rig' of ")
    mat("cube", {"t": T, "frames": np.ones((N, 3, 2))}, {}, "variable 'frames' of ")
    mat("complex", {"t": T, "z": X + 1j * Y}, {}, "variable 'z' of ")
    mat("wide", {"data": np.ones((3, N))}, {}, "variable 'data' of ")
    runs = np.zeros((1, 2), dtype=[("t", "O"), ("x", "O")])
    runs[0, 0], runs[0, 1] = (T, X), (T, Y)
    mat("struct_array", {"runs": runs}, {}, "variable 'runs' of ")
    mat("sparse", {"t": T, "m": scipy.sparse.eye(N, format="csc")}, {}, "variable 'm' of ")
    good = tmp_path / "good.mat"
    scipy.io.savemat(good, {"t": T, "x": X})
    cut = tmp_path / "truncated.mat"
    cut.write_bytes(good.read_bytes()[:300])
    out["truncated"] = (cut, {}, " is not a readable MATLAB file (")
    good73 = write_mat73(tmp_path / "good73.mat", {"t": T, "x": X})
    cut73 = tmp_path / "truncated73.mat"
    cut73.write_bytes(good73.read_bytes()[:1500])
    out["truncated73"] = (cut73, {}, " is not a readable MATLAB v7.3 (HDF5) file (")
    complex73 = write_mat73(tmp_path / "complex73.mat", {"t": T, "z": X + 1j * Y})
    out["complex73"] = (complex73, {}, "variable 'z' of ")
    array73 = tmp_path / "struct_array73.mat"
    with h5py.File(array73, "w", userblock_size=512) as f:  # fields hold one reference each
        group = f.create_group("runs")
        group.attrs["MATLAB_class"] = np.bytes_("struct")
        refs = f.create_group("#refs#")
        cells = np.empty((2, 1), dtype=h5py.ref_dtype)
        for i, values in enumerate((X, Y)):
            refs[f"x{i}"] = values[None, :]
            refs[f"x{i}"].attrs["MATLAB_class"] = np.bytes_("double")
            cells[i, 0] = refs[f"x{i}"].ref
        group["x"] = cells
    with array73.open("r+b") as fh:
        fh.write(MAT73_HEADER.ljust(116) + b" " * 8 + b"\x00\x02" + b"IM")
    out["struct_array73"] = (array73, {}, "variable 'runs' of ")
    tdms = _tdms(tmp_path / "good.tdms", [ChannelObject("g", "x", X, properties=_waveform())])
    cut_tdms = tmp_path / "truncated.tdms"
    cut_tdms.write_bytes(tdms.read_bytes()[:200])
    out["truncated_tdms"] = (cut_tdms, {}, " is not a readable TDMS file (")
    bare = _tdms(tmp_path / "bare.tdms", [ChannelObject("g", "x", X)])
    out["no_increment"] = (bare, {}, "channel 'x' of group 'g' of ")
    rates = _tdms(
        tmp_path / "rates.tdms",
        [
            ChannelObject("g", "x", X, properties=_waveform(DT)),
            ChannelObject("g", "y", Y, properties=_waveform(2 * DT)),
        ],
    )
    out["two_rates"] = (rates, {}, "the channels of group 'g' of ")
    h5 = tmp_path / "good.h5"
    with h5py.File(h5, "w") as f:
        f["x"] = X
    cut_h5 = tmp_path / "truncated.h5"
    cut_h5.write_bytes(h5.read_bytes()[:1000])
    out["truncated_h5"] = (cut_h5, {}, " is not a readable HDF5 file (")
    wav = tmp_path / "bad.wav"
    wav.write_bytes(b"RIFF\x10\x00\x00\x00WAVEfmt \x02\x00\x00\x00")
    out["bad_wav"] = (wav, {}, " is not a readable WAV file (")
    parquet = tmp_path / "good.parquet"
    pd.DataFrame({"x": X}).to_parquet(parquet, engine="pyarrow")
    cut_pq = tmp_path / "truncated.parquet"
    cut_pq.write_bytes(parquet.read_bytes()[:100])
    out["truncated_parquet"] = (cut_pq, {}, " is not a readable Parquet file (")
    csv = tmp_path / "table.csv"
    csv.write_text("time,x\n0,1\n1,2\n")
    out["group_on_csv"] = (csv, {"group": "rig"}, "group= applies to files with groups or ")
    return out


MESSAGES = {
    "text_only": "; chaoskit reads vectors and matrices with one column per channel.",
    "unequal": " have unequal lengths (t: 400, x: 399); pass variables= with equally long "
    "ones to load_trajectory.",
    "cube": " has 3 dimensions (400 × 3 × 2); chaoskit reads vectors and matrices with one "
    "column per channel; pass variables= without it to load_trajectory.",
    "complex": " is complex; chaoskit reads real series: save real and imaginary parts as "
    "two variables; pass variables= without it to load_trajectory.",
    "complex73": " is complex; chaoskit reads real series: save real and imaginary parts as "
    "two variables; pass variables= without it to load_trajectory.",
    "struct_array": " is a 1 × 2 struct array; chaoskit reads a scalar struct: save one "
    "element as a struct of its own; pass variables= without it to load_trajectory.",
    "struct_array73": " is a struct array; chaoskit reads a scalar struct: save one element "
    "as a struct of its own; pass variables= without it to load_trajectory.",
    "sparse": " is a sparse matrix; store full(...); pass variables= without it to "
    "load_trajectory.",
    "wide": " is a 3 × 400 matrix: chaoskit reads one column per channel (samples down the "
    "rows); store its transpose.",
    "no_increment": " has no time increment (wf_increment) and the group has no time channel "
    "(looked for ['time', 't', 'Time', 'TIME', 't_s', 'time_s']); pass dt= (the sampling "
    "interval, s), time= (the time channel) or step= (a map) to load_trajectory.",
    "two_rates": " are sampled at different intervals (x: 0.001 s, y: 0.002 s); pass "
    "variables= with channels of one interval to load_trajectory.",
    "group_on_csv": "group= applies to files with groups or structs (.mat, .tdms, .h5) only.",
}


@pytest.mark.parametrize(
    "case",
    [
        "text_only",
        "unequal",
        "cube",
        "complex",
        "wide",
        "struct_array",
        "struct_array73",
        "sparse",
        "truncated",
        "truncated73",
        "complex73",
        "truncated_tdms",
        "no_increment",
        "two_rates",
        "truncated_h5",
        "bad_wav",
        "truncated_parquet",
        "group_on_csv",
    ],
)
def test_malformed_files_give_one_line_naming_file_and_variable(tmp_path: Path, case: str):
    path, options, start = _bad_files(tmp_path)[case]
    with pytest.raises(ValueError) as info:
        chaoskit.load_trajectory(path, **options)
    text = str(info.value)
    assert "\n" not in text and (str(path) in text or case == "group_on_csv"), text
    assert start in text, text
    if case in MESSAGES:
        assert text.endswith(MESSAGES[case]), text


def test_an_option_fixes_what_it_names(tmp_path: Path) -> None:
    files = _bad_files(tmp_path)
    ds = chaoskit.load_trajectory(files["no_increment"][0], dt=DT)
    assert chaoskit.sampling_interval(ds) == pytest.approx(DT, rel=1e-12)
    ds = chaoskit.load_trajectory(files["two_rates"][0], variables=["y"])
    assert chaoskit.sampling_interval(ds) == pytest.approx(2 * DT, rel=1e-12)
    path = tmp_path / "mixed.mat"
    frames = np.ones((N, 3, 2))
    scipy.io.savemat(path, {"t": T, "x": X, "z": X + 1j * Y, "cal": np.arange(3.0), "f": frames})
    np.testing.assert_array_equal(chaoskit.load_trajectory(path, variables=["x"])["x"], X)


def test_a_missing_optional_package_names_the_extra(tmp_path: Path, monkeypatch) -> None:
    tdms = _tdms(tmp_path / "rig.tdms", [ChannelObject("g", "x", X, properties=_waveform())])
    monkeypatch.setattr(_formats, "nptdms", None)
    with pytest.raises(ImportError) as info:
        chaoskit.load_trajectory(tdms)
    assert str(info.value) == (
        "reading .tdms files needs the npTDMS package, which is not installed: "
        'pip install "chaoskit[formats]"'
    )
    assert isinstance(info.value, ValueError)  # a user's setup problem: one line in the CLI
    out = runner.invoke(app, ["analyze", str(tdms)])
    assert out.exit_code == 2 and out.stderr == f"error: {info.value}\n"
    parquet = tmp_path / "log.parquet"
    pd.DataFrame({"t": T, "x": X}).to_parquet(parquet, engine="pyarrow")
    monkeypatch.setattr(_formats, "_HAS_PYARROW", False)
    with pytest.raises(ImportError, match=r'pyarrow package, .*"chaoskit\[formats\]"$'):
        chaoskit.load_trajectory(parquet)


# ----------------------------------------------------------------- the command line


def test_analyze_reads_a_mat_file_and_a_tdms_file(tmp_path: Path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    mat = tmp_path / "rig.mat"
    scipy.io.savemat(mat, {"t": T, "x": X, "y": Y})
    out = runner.invoke(app, ["analyze", str(mat)])
    assert out.exit_code == 0, out.output
    ds, names = calls[-1]
    assert names == ["x", "y"] and chaoskit.sampling_interval(ds) == pytest.approx(DT)
    tdms = _tdms(
        tmp_path / "rig.tdms",
        [
            ChannelObject("bench", "acc x", X, properties=_waveform(unit="m/s^2")),
            ChannelObject("spare", "x", X, properties=_waveform()),
        ],
    )
    out = runner.invoke(app, ["analyze", str(tdms)])
    assert out.exit_code == 2 and out.stderr == (
        f"error: {tdms} holds the groups ['bench', 'spare']; pick one with --group bench.\n"
    )
    spaced = _tdms(
        tmp_path / "spaced.tdms",
        [ChannelObject(g, "x", X, properties=_waveform()) for g in ("run 1", "run 2")],
    )
    out = runner.invoke(app, ["analyze", str(spaced)])
    assert out.exit_code == 2 and out.stderr == (
        f"error: {spaced} holds the groups ['run 1', 'run 2']; pick one with --group, e.g. "
        "'run 1'.\n"
    )
    out = runner.invoke(app, ["analyze", str(tdms), "--group", "bench", "--var", "acc_x"])
    assert out.exit_code == 0, out.output
    ds, names = calls[-1]
    assert names == ["acc_x"] and ds["acc_x"].attrs["units"] == "m s-2"
    np.testing.assert_array_equal(ds["acc_x"].values, X)


def test_analyze_names_dt_and_resample_for_rig_files(tmp_path: Path, monkeypatch) -> None:
    calls = stub_analysis(monkeypatch)
    bare = _tdms(tmp_path / "bare.tdms", [ChannelObject("g", "x", X)])
    out = runner.invoke(app, ["analyze", str(bare)])
    assert out.exit_code == 2 and out.stderr.endswith(
        "pass --dt (the sampling interval, s), --time (the time channel) or --step (a map).\n"
    )
    out = runner.invoke(app, ["analyze", str(bare), "--dt", "0.001"])
    assert out.exit_code == 0, out.output
    jitter = tmp_path / "jitter.mat"
    scipy.io.savemat(jitter, {"t": T + np.where(np.arange(N) % 2, 2e-4, 0.0), "x": X})
    out = runner.invoke(app, ["analyze", str(jitter)])
    assert out.exit_code == 2 and out.stderr.endswith(
        "pass --resample linear to interpolate onto a uniform grid (with --dt for its interval).\n"
    )
    out = runner.invoke(app, ["analyze", str(jitter), "--resample", "linear", "--dt", "0.002"])
    assert out.exit_code == 0, out.output
    assert chaoskit.sampling_interval(calls[-1][0]) == pytest.approx(0.002, rel=1e-12)
    out = runner.invoke(app, ["analyze", str(jitter), "--resample", "cubic"])
    assert out.exit_code == 2 and out.stderr == (
        "error: --resample must be one of 'linear'; got 'cubic'.\n"
    )
