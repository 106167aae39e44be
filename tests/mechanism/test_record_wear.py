"""``simulate(record="wear")``: only what the wear of a run and a wear path's analysis read.

The lean record is the full record's samples of the same integration (the ideal companion
does not run, and nothing else is kept), so every kept variable and the Archard wear of
the run are the full record's bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

import mechanism
from mechanism.core.wear import run_wear
from tests.mechanism.scenes import rigid_paper

PERIOD = 0.4  # s, the paper scene at 150 rpm
KEPT = (
    "crank_angle", "eccentricity_x", "eccentricity_y", "penetration", "contact_force",
    "sliding_velocity", "contact_angle", "contact_angle_journal",
)  # fmt: skip


@pytest.fixture(scope="module")
def scene():
    return rigid_paper({"effects.wear": True})


@pytest.fixture(scope="module")
def runs(scene):
    """One revolution at T/2000, recorded in full and lean."""
    step = PERIOD / 2000
    full = mechanism.simulate(scene, revolutions=1, output_step=step)
    lean = mechanism.simulate(scene, revolutions=1, output_step=step, record=mechanism.WearRecord())
    return full, lean


def test_the_wear_record_keeps_the_full_records_samples_bit_for_bit(runs) -> None:
    full, lean = runs
    assert sorted(lean.data_vars) == sorted(KEPT)
    assert np.array_equal(lean["time"].values, full["time"].values)
    for name in KEPT:
        assert np.array_equal(lean[name].values, full[name].values), name
        assert lean[name].attrs == full[name].attrs, name
    assert lean.attrs["record"] == "wear"
    assert lean.attrs["motion_variables"] == "eccentricity_x eccentricity_y"
    assert not [k for k in lean.attrs if k.startswith("ideal_")]


def test_the_wear_of_a_lean_run_is_the_full_runs_bit_for_bit(scene, runs) -> None:
    full, lean = runs
    a, b = run_wear(scene, full, start=200), run_wear(scene, lean, start=200)
    assert a and set(a) == set(b)
    for name in a:
        assert a[name].depth.max() > 0.0
        assert np.array_equal(a[name].depth, b[name].depth)
        assert a[name].volume == b[name].volume


def test_the_wear_record_by_name(scene) -> None:
    ds = mechanism.simulate(scene, revolutions=0.05, output_step=PERIOD / 200, record="wear")
    assert ds.attrs["record"] == "wear"
    assert ds.sizes["time"] == 11


def test_the_wear_record_needs_a_clearance_joint() -> None:
    scene = rigid_paper({"effects.clearance": False})
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, revolutions=0.05, record="wear")
    assert str(info.value) == (
        "record='wear' needs a clearance joint; scene 'paper' has none (use record='full')."
    )
