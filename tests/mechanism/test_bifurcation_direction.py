"""``mechanism.bifurcation`` with state continuation: a sweep up and a sweep down over
the rigid paper scene, and the checks of what continuation cannot do."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app

SPEEDS = [30.0, 33.0, 36.0]
PARAMETER = "drive.speed_rpm"


def _rigid() -> mechanism.Scene:
    return mechanism.load_scene("paper").replace({"effects.flexibility": False})


def _sweep(direction: str) -> object:
    return mechanism.bifurcation(
        _rigid(), parameter=PARAMETER, values=SPEEDS, revolutions=6, discard=3,
        client="serial", settings=mechanism.BifurcationSettings(direction=direction),
    )  # fmt: skip


@pytest.fixture(scope="module")
def sweeps():
    return _sweep("up"), _sweep("down")


def test_up_and_down_give_the_same_points_where_the_motion_is_periodic(sweeps):
    """From 30 to 36 rpm the rigid scene has one stable period-1 orbit in continuous
    contact, which contracts by about 2e-3 per period: up and down the last three
    strobes of each value coincide with each other (period 1) and with the other sweep's.

    The tolerance is 1e-3 of the clearance (0.2 µm): the journal never leaves the
    bearing, so its latched impact velocity is never renewed, and the orbit is one of a
    family parameterised by the latch the motion carries from its start (the neutral
    direction of ``mechanism.periodic_orbit``); a sweep that reaches a value from
    another speed carries another latch, which moved the points by 5e-5 of the
    clearance. Round-off of another machine moves them by far less."""
    up, down = sweeps
    clearance = 2e-4
    assert (up.status.values == "ok").all() and (down.status.values == "ok").all()
    a = up.eccentricity.sel({PARAMETER: SPEEDS}).values
    b = down.eccentricity.sel({PARAMETER: SPEEDS}).values
    assert np.all(np.isfinite(a)) and a.shape == (3, 4, 1)
    period_one = np.ptp(a[:, -3:], axis=1)
    assert np.max(period_one) < 1e-6 * clearance
    assert np.max(np.abs(a - b)) < 1e-3 * clearance


def test_the_records_carry_the_direction(sweeps):
    up, down = sweeps
    assert up.attrs["bifurcation_direction"] == "up"
    assert down.attrs["bifurcation_direction"] == "down"
    assert up[PARAMETER].values.tolist() == SPEEDS
    assert down[PARAMETER].values.tolist() == SPEEDS[::-1]
    assert up.start.values.tolist() == ["scene start", "continued", "continued"]
    assert "direction='down'" in down.attrs["history"]
    assert up.eccentricity.attrs["units"] == "m"


def test_direction_is_checked():
    with pytest.raises(ValueError, match="direction must be 'up', 'down' or None"):
        mechanism.BifurcationSettings(direction="sideways")
    settings = mechanism.BifurcationSettings(direction="up")
    with pytest.raises(ValueError, match="needs a rigid scene"):
        mechanism.bifurcation(
            mechanism.load_scene("paper"), parameter=PARAMETER, values=SPEEDS,
            revolutions=4, discard=2, settings=settings,
        )  # fmt: skip
    with pytest.raises(ValueError, match="revolutions must be a whole number"):
        mechanism.bifurcation(
            _rigid(), parameter=PARAMETER, values=SPEEDS, revolutions=4.5, discard=2,
            settings=settings,
        )  # fmt: skip
    with pytest.raises(ValueError, match="neither store nor a dask client"):
        mechanism.bifurcation(
            _rigid(), parameter=PARAMETER, values=SPEEDS, revolutions=4, discard=2,
            settings=settings, store="somewhere",
        )  # fmt: skip


def test_the_cli_passes_the_direction_and_refuses_a_bad_one():
    """``--direction`` reaches the settings: a bad value exits 2 with the settings' message
    and no traceback."""
    result = CliRunner().invoke(
        app,
        ["bifurcation", "paper", "--param", PARAMETER, "--values", "30,36",
         "--direction", "sideways", "--revolutions", "4", "--discard", "2"],
    )  # fmt: skip
    assert result.exit_code == 2
    assert "direction must be 'up', 'down' or None" in result.output
    assert "Traceback" not in result.output
