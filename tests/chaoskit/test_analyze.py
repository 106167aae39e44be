"""analyze: one row per variable, scalar fields, NaN where undefined, stackable over a grid."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import analyze, classify_variables, systems, verdict_table
from chaoskit.verdict._analyze import FIELDS


def _henon_dataset(n: int = 800, a: float = 1.4) -> xr.Dataset:
    xy = systems.henon(n, a=a)
    ds = xr.Dataset(
        {
            "x": ("step", xy[:, 0], {"units": "1", "long_name": "Hénon x"}),
            "y": ("step", xy[:, 1], {"units": "1", "long_name": "Hénon y"}),
            "c": ("step", np.full(n, 0.3), {"units": "1", "long_name": "a constant"}),
        },
        coords={"step": np.arange(n)},
    )
    return chaoskit.load_trajectory(ds)


def test_one_row_per_variable_with_every_field() -> None:
    table = analyze(_henon_dataset(), rng=0)
    assert list(table["variable"].values) == ["x", "y", "c"]
    assert set(table.data_vars) == set(FIELDS)
    for name, var in table.data_vars.items():
        assert var.dims == ("variable",), name
        assert "long_name" in var.attrs
        if var.dtype.kind == "f":
            assert "units" in var.attrs
    labels = [str(v) for v in table["label"].values]
    assert labels == ["chaotic", "chaotic", "equilibrium"]
    row = table.sel(variable="x")
    assert float(row["mle_rosenstein_low"]) < float(row["mle_rosenstein"])
    assert float(row["mle_rosenstein"]) < float(row["mle_rosenstein_high"])
    assert float(row["lag"]) == 1 and float(row["embedding_dim"]) == 2
    assert table["mle_rosenstein"].attrs["units"] == "1"  # per iteration for a map
    # undefined fields are NaN: no period unless periodic, no exponent for a constant
    assert np.isnan(table["period"].values).all()
    const = table.sel(variable="c")
    assert np.isnan(float(const["mle_wolf"])) and float(const["confidence"]) == 1.0
    assert "c: the series is constant" in table.attrs["reasons"]


def test_flow_units_and_verdicts() -> None:
    ds = chaoskit.load_trajectory(systems.lorenz(10_000, dt=0.01), dt=0.01,
                                  variables=["x", "y", "z"])  # fmt: skip
    verdicts = classify_variables(ds, variables=["x"], rng=0)
    table = verdict_table(verdicts)
    same = analyze(ds, variables=["x"], rng=0)
    for name in ("mle_rosenstein", "mle_wolf", "zero_one_k", "surrogate_p_value", "confidence"):
        np.testing.assert_array_equal(same[name].values, table[name].values)
    assert table["mle_rosenstein"].attrs["units"] == "s-1"
    assert table["lag_time"].attrs["units"] == "s"
    assert str(table["label"].values[0]) == "chaotic"
    assert verdicts["x"].label == "chaotic"
    assert float(table["lag_time"].values[0]) == pytest.approx(0.01 * verdicts["x"].lag)
    # Lorenz λ1 = 0.9056 s⁻¹: a generous check that units are per second, not per sample
    assert 0.5 < float(table["mle_rosenstein"].values[0]) < 1.5


def test_results_stack_over_a_parameter_grid() -> None:
    rows = [analyze(_henon_dataset(600, a=a), variables=["x"], rng=0) for a in (1.0, 1.4)]
    grid = xr.concat(rows, dim="a", combine_attrs="drop").assign_coords(a=[1.0, 1.4])
    assert grid["mle_wolf"].dims == ("a", "variable")
    labels = [str(v) for v in grid["label"].sel(variable="x").values]
    assert labels == ["periodic", "chaotic"]  # Hénon a = 1.0 is a period-4 orbit
    assert float(grid["period"].sel(a=1.0, variable="x")) == 4.0


def test_failure_is_recorded_and_the_rest_analysed(monkeypatch: pytest.MonkeyPatch) -> None:
    from chaoskit.verdict import _analyze

    def classify(data, *, variable, **kwargs):
        if variable == "y":
            raise ValueError("y cannot be analysed")
        return chaoskit.classify(data, variable=variable, **kwargs)

    monkeypatch.setattr(_analyze, "classify", classify)
    table = analyze(_henon_dataset(400), variables=["y", "x"], rng=0)
    assert [str(v) for v in table["label"].values] == ["undetermined", "chaotic"]
    assert np.isnan(float(table["mle_wolf"].sel(variable="y")))
    assert "y: analysis failed: y cannot be analysed" in table.attrs["reasons"]


def test_multi_dimensional_variables_are_analysed_per_label() -> None:
    ds = _henon_dataset(400)
    image = np.stack([ds["x"].values, np.ones(400)], axis=1)
    ds["image"] = (("step", "pixel"), image, {"units": "1", "long_name": "2-D"})
    table = analyze(ds, variables=["image", "x"], rng=0)
    assert [str(v) for v in table["variable"].values] == ["image[pixel=0]", "image[pixel=1]", "x"]
    assert [str(v) for v in table["label"].values] == ["chaotic", "equilibrium", "chaotic"]
    one = analyze(ds, variables=["image[pixel=0]"], rng=0)
    assert float(one["mle_wolf"].item()) == float(table["mle_wolf"].sel(variable="x"))


def test_netcdf_round_trip(tmp_path) -> None:
    table = analyze(_henon_dataset(600), variables=["x", "c"], rng=0)
    path = tmp_path / "table.nc"
    table.to_netcdf(path, engine="h5netcdf")
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert [str(v) for v in back["label"].values] == ["chaotic", "equilibrium"]
        np.testing.assert_allclose(back["mle_wolf"].values, table["mle_wolf"].values)


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="not found"):
        analyze(_henon_dataset(), variables=["nope"])


def test_missing_phase_variable_is_named() -> None:
    with pytest.raises(ValueError, match="crank_angle"):
        analyze(_henon_dataset(), variables=["x"], phase_variable="crank_angle")
