"""A run's tolerances and step limits: one frozen object the integrators take."""

from __future__ import annotations

import dataclasses
import math

import pytest

from mechanism.core.integrate import StepSettings


def test_defaults_bound_nothing_but_the_step() -> None:
    steps = StepSettings(rtol=1e-8, atol=1e-9, max_step=1e-3)
    assert (steps.approach_floor, steps.projection, steps.step_budget) == (0.0, False, math.inf)
    with pytest.raises(dataclasses.FrozenInstanceError):
        steps.rtol = 1e-6  # type: ignore[misc]


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"rtol": 0.0}, "rtol must be a number > 0; got 0.0."),
        ({"atol": -1e-9}, "atol must be a number > 0; got -1e-09."),
        ({"max_step": math.nan}, "max_step must be a number > 0; got nan."),
        ({"step_budget": True}, "step_budget must be a number > 0; got True."),
        ({"approach_floor": -1.0}, "approach_floor must be a number >= 0 (s); got -1.0."),
    ],
)
def test_bad_settings_name_the_parameter_and_its_range(changes, message) -> None:
    settings = {"rtol": 1e-8, "atol": 1e-9, "max_step": math.inf, **changes}
    with pytest.raises(ValueError) as info:
        StepSettings(**settings)
    assert str(info.value) == message
