"""Basins of a motor-driven scene over initial journal eccentricities and initial crank
speeds: the lubricated press slider-crank settles on one period-1 motion (a stable orbit
of the crank-angle section, |μ_max| = 0.61 per turn) from rest and from 1500 rpm, so
every start inside the disc carries the same label; a 1e-12 change of the starts cannot
change a label that every start shares with a margin (the strobes repeat within 1e-3 of
the clearance after 20 turns, the orbit contracting by 0.61 per turn)."""

from __future__ import annotations

import numpy as np
import pytest

import mechanism


@pytest.mark.slow
def test_basins_of_a_motor_scene_over_initial_crank_speeds() -> None:
    scene = mechanism.load_scene("slider-crank-motor-lubricated")
    grid = mechanism.basins(
        scene, points=3, extent=0.5, revolutions=30, discard=20, max_period=2,
        crank_speeds=[0.0, 1500.0],
    )  # fmt: skip
    assert grid.label.shape == (2, 3, 3)
    np.testing.assert_array_equal(grid.crank_speed, [0.0, 1500.0])
    inside = grid.label != "outside"
    assert int(inside.sum()) == 10  # the centre and the 4 edge midpoints, per speed
    assert set(grid.label[inside]) == {"period 1 #0"}
    assert grid.attractors == ("period 1 #0",)
    assert not grid.coexisting
    ds = grid.to_dataset()
    assert ds["label"].dims == ("crank_speed", "y", "x")
    assert ds["crank_speed"].attrs["units"] == "rpm"


def test_basins_refuse_crank_speeds_for_a_prescribed_drive() -> None:
    scene = mechanism.load_scene("slider-crank-clearance")
    with pytest.raises(ValueError) as err:
        mechanism.basins(scene, crank_speeds=[100.0])
    assert str(err.value) == (
        "crank_speeds needs a motor drive (the crank speed of a constant_speed or "
        "prescribed drive is not an initial condition); leave it None."
    )
