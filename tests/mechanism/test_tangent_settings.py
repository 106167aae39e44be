"""The tangent integration's settings object and the cost of its deviation.

``TangentSettings`` groups the step control and the deviation's options of
``integrate_tangent`` and ``integrate_tangent_flexible``; ``difference="directional"``
differences the deviation's rate in one right-hand side per stage instead of two.
"""

from __future__ import annotations

import dataclasses
import math
import re

import numpy as np
import pytest

import mechanism
from mechanism.core.integrate import (
    GeneralizedAlpha,
    StepSettings,
    TangentSettings,
    integrate_tangent_flexible,
)
from mechanism.core.model import assemble, initial_state

STEPS = StepSettings(rtol=1e-8, atol=1e-8, max_step=1e-4)


def _rigid_paper() -> mechanism.Scene:
    return mechanism.load_scene("paper").replace({"effects.flexibility": False})


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"time_scale": 0.0}, "time_scale must be finite and > 0; got 0.0."),
        ({"renormalize_every": 0}, "renormalize_every must be in [1, ∞]; got 0."),
        ({"deviation_rtol": 2.0}, "deviation_rtol must be in [0, 1]; got 2.0."),
        ({"deviation_rtol": -1.0}, "deviation_rtol must be finite and >= 0; got -1.0."),
        ({"neutral_latch_after": 0.0}, "neutral_latch_after must be finite and > 0; got 0.0."),
        ({"max_steps": 0}, "max_steps must be in [1, ∞]; got 0."),
        ({"chunk_steps": 0}, "chunk_steps must be an integer ≥ 1 (steps); got 0."),
        ({"difference": "central"}, "difference must be one of split, directional; got 'central'."),
    ],
)
def test_bad_settings_raise_one_line_naming_the_field(changes: dict, message: str) -> None:
    fields = {"steps": STEPS, "time_scale": 0.1, **changes}
    with pytest.raises(ValueError) as info:
        TangentSettings(**fields)
    assert str(info.value) == message


def test_settings_need_step_settings_and_are_frozen() -> None:
    with pytest.raises(TypeError, match=re.escape("steps must be a mechanism.core.integrate.")):
        TangentSettings(steps={"rtol": 1e-8}, time_scale=0.1)
    settings = TangentSettings(steps=STEPS, time_scale=0.1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        settings.time_scale = 1.0  # type: ignore[misc]
    assert (settings.renormalize_every, settings.deviation_rtol, settings.difference) == (
        1,
        0.0,
        "split",
    )


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"deviation_rtol": 1e-4}, "settings.deviation_rtol must be 0 on generalized-alpha"),
        ({"neutral_latch_after": 0.4}, "settings.neutral_latch_after must be None on"),
        ({"difference": "directional"}, "settings.difference must be 'split' on"),
    ],
)
def test_flexible_tangent_refuses_the_dormand_prince_options(changes: dict, message: str) -> None:
    model = assemble(mechanism.load_scene("paper"))
    y0 = np.concatenate(initial_state(model))
    settings = TangentSettings(steps=STEPS, time_scale=0.1, **changes)
    with pytest.raises(ValueError, match=re.escape(message)):
        integrate_tangent_flexible(
            model, y0, np.zeros_like(y0), np.array([0.0, 1e-3]), method=GeneralizedAlpha(),
            settings=settings,
        )  # fmt: skip


def _evaluations_per_step(result: mechanism.SceneLyapunov) -> float:
    stats = result.stats
    assert stats is not None
    return stats.function_evaluations / (stats.steps + stats.rejected_steps)


def test_directional_difference_takes_one_evaluation_per_stage() -> None:
    """Over 1/20 revolution of the rigid paper scene (impacts and the friction ramp
    included) the exponent costs the reference's six right-hand sides per step and the
    deviation's six with the directional difference (measured 12.9 per attempted step:
    the mirrored differences at the contact law's kinks and the rate after each
    renormalisation add the rest), against two per stage with the split one (19.8, the
    default before the directional difference)."""
    scene = _rigid_paper()
    directional = mechanism.lyapunov_exponent(scene, revolutions=0.05)
    split = mechanism.lyapunov_exponent(
        scene, revolutions=0.05, settings=mechanism.LyapunovSettings(difference="split")
    )
    assert directional.settings["difference"] == "directional"
    assert _evaluations_per_step(directional) < 14.0
    assert _evaluations_per_step(split) > 18.0


def test_directional_and_split_differences_agree_on_the_same_steps() -> None:
    """On the reference's own steps (``deviation_rtol=0``) the two differences share the
    reference, so the growth of the deviation compares the two linearisations: over the
    first revolution of the rigid paper scene (11 – 15 contact events) they agree within
    1.1e-5 of each other, and within 1.4e-5 – 8.3e-4 from crank angles moved by 1e-12 to
    3e-12 of a revolution (bound 1 %)."""
    base = _rigid_paper()
    for shift in (0.0, 1e-12 * 2.0 * math.pi):
        scene = base.replace({"drive.initial_angle": base.drive.initial_angle + shift})
        directional, split = (
            mechanism.lyapunov_exponent(
                scene,
                revolutions=1,
                settings=mechanism.LyapunovSettings(deviation_rtol=0.0, difference=difference),
            )
            for difference in ("directional", "split")
        )
        assert directional.stats is not None and split.stats is not None
        assert directional.stats.steps == split.stats.steps
        assert directional.exponent == pytest.approx(split.exponent, rel=0.01)
