"""``mechanism.basins``: initial journal eccentricities run to their motion and labelled."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

import mechanism

matplotlib.use("Agg")


def _rigid(rpm: float) -> mechanism.Scene:
    return mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )


@pytest.fixture(scope="module")
def grid30() -> mechanism.Basins:
    orbit = mechanism.periodic_orbit(_rigid(30.0), settle=5)
    return mechanism.basins(
        _rigid(30.0), points=3, revolutions=8, discard=5, max_period=1, orbits=[orbit]
    )


def test_every_start_at_30_rpm_settles_on_the_one_stable_orbit(grid30):
    """At 30 rpm the rigid scene has one stable period-1 orbit (multiplier about 2e-3 per
    period): the five starts inside the disc (centre and four at 0.9 of the clearance)
    settle on it within 1e-3 of the clearance and are named after it; the corners lie
    outside the clearance disc and are not run. Nothing coexists."""
    inside = grid30.label != "outside"
    assert int(inside.sum()) == 5
    assert set(grid30.label[inside]) == {"orbit 0 (period 1)"}
    assert np.all(grid30.period[inside] == 1)
    assert np.all(grid30.attractor[inside] == 0)
    assert grid30.attractors == ("orbit 0 (period 1)",)
    assert grid30.attractor_points[0].shape == (1, 1, 2)
    assert not grid30.coexisting
    np.testing.assert_allclose(grid30.x, [-1.8e-4, 0.0, 1.8e-4], rtol=0, atol=1e-15)


def test_dataset_and_figure(grid30):
    ds = grid30.to_dataset()
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs and "long_name" in var.attrs, name
    assert ds["x"].attrs["units"] == "m"
    assert ds.attrs["joint"] == "C"
    assert ds.attrs["setting_revolutions"] == 8
    ax = mechanism.plot_basins(grid30)
    assert "initial eccentricity x of C" in ax.get_xlabel()


def test_bad_arguments_are_refused():
    scene = _rigid(30.0)
    with pytest.raises(ValueError, match=r"points must be in \[2, 64\]; got 1"):
        mechanism.basins(scene, points=1)
    with pytest.raises(ValueError, match="extent must be in"):
        mechanism.basins(scene, extent=1.5)
    with pytest.raises(ValueError, match="at least 3 \\* max_period = 12"):
        mechanism.basins(scene, revolutions=10, discard=5, max_period=4)
    with pytest.raises(ValueError, match="joint must be one of the clearance joints"):
        mechanism.basins(scene, joint="A")
