"""Bifurcation diagrams of the logistic map and the forced Duffing oscillator."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from chaoskit import bifurcation_diagram, systems
from tests.chaoskit.test_sections import duffing_dataset


def _logistic_run(r: float, n: int = 200) -> xr.Dataset:
    return xr.Dataset(
        {"x": ("step", systems.logistic(n, r=r), {"units": "1", "long_name": "x"})},
        coords={"step": np.arange(n)},
        attrs={"r": r},
    )


def _branches(diagram: xr.Dataset, parameter: str, variable: str, value: float) -> int:
    pts = diagram[variable].values[diagram[parameter].values == value]
    return int(np.unique(np.round(pts, 6)).size)


def test_logistic_period_doubling_and_chaos() -> None:
    rs = [2.8, 3.2, 3.5, 3.56, 3.9]
    diagram = bifurcation_diagram([_logistic_run(r) for r in rs], parameter="r", variable="x",
                                  last=128)  # fmt: skip
    assert [_branches(diagram, "r", "x", r) for r in rs[:4]] == [1, 2, 4, 8]
    assert _branches(diagram, "r", "x", 3.9) > 100  # chaotic band
    assert diagram.sizes["point"] == 128 * len(rs)
    assert np.all(np.diff(diagram["r"].values) >= 0)
    assert diagram.attrs["diagram_parameter"] == "r" and diagram["x"].attrs["units"] == "1"


def test_sweep_dataset_and_explicit_values() -> None:
    rs = np.array([3.2, 3.5])
    sweep = xr.concat([_logistic_run(r).drop_attrs() for r in rs], dim="r").assign_coords(r=rs)
    diagram = bifurcation_diagram(sweep, parameter="r", variable="x", last=64)
    assert [_branches(diagram, "r", "x", r) for r in rs] == [2, 4]
    relabelled = bifurcation_diagram(
        [_logistic_run(3.2)], parameter="gain", variable="x", values=[10.0], section="samples"
    )
    assert set(np.unique(relabelled["gain"].values)) == {10.0}


def test_duffing_stroboscopic_diagram() -> None:
    gammas = [0.20, 0.28, 0.37]
    runs = [duffing_dataset(g, 40).assign_attrs(gamma=g) for g in gammas]
    diagram = bifurcation_diagram(
        runs,
        parameter="gamma",
        variable="x",
        section="stroboscopic",
        section_options={"period": 2 * np.pi / 1.2},
    )
    assert [_branches(diagram, "gamma", "x", g) for g in gammas] == [1, 2, 5]
    assert "time" in diagram.coords


def test_poincare_diagram_uses_crossing_values() -> None:
    ds = duffing_dataset(0.28, 40).assign_attrs(gamma=0.28)
    diagram = bifurcation_diagram(
        [ds],
        parameter="gamma",
        variable="x",
        section="poincare",
        section_options={"variable": "v", "level": 0.0, "direction": "down"},
    )
    # the period-2 orbit has one maximum of x per drive period, alternating between two values
    x = diagram["x"].values
    assert _branches(diagram, "gamma", "x", 0.28) == 2 and x.size == 40
    np.testing.assert_allclose(x[2:], x[:-2], rtol=1e-6)


def test_bad_input() -> None:
    run = _logistic_run(3.2)
    with pytest.raises(ValueError, match="carries no value"):
        bifurcation_diagram([run.drop_attrs()], parameter="r", variable="x")
    with pytest.raises(ValueError, match="values has"):
        bifurcation_diagram([run], parameter="r", variable="x", values=[1.0, 2.0])
    with pytest.raises(ValueError, match="section"):
        bifurcation_diagram([run], parameter="r", variable="x", section="maxima")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="not among"):
        bifurcation_diagram([run], parameter="r", variable="y")
    with pytest.raises(ValueError, match="needs section"):
        bifurcation_diagram([duffing_dataset(0.2, 5).assign_attrs(g=1.0)], parameter="g",
                            variable="x")  # fmt: skip
    with pytest.raises(ValueError, match="dimension"):
        bifurcation_diagram(run, parameter="r", variable="x")
