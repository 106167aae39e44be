"""Any scene the validator accepts either runs or is refused with one line naming a key.

Hypothesis draws the values of the clearance slider-crank across the full ranges the scene
validator accepts (read from the model's annotations, so the test follows the validator):
masses, inertias, joint dimensions, clearance, contact stiffness and law, restitution,
friction, wear regions, drive speed, tolerances, output step and the simulated
revolutions. ``simulate`` must then

* return a Dataset whose recorded values are all finite, or
* refuse before running with a one-line ``ValueError`` (a ``SceneError`` for the scene)
  that names the key or argument at fault, or
* stop with a one-line :class:`mechanism.SimulationError` stating why the integrator gave
  up and naming the keys that change the outcome (``solver.rtol``, ``revolutions``,
  ``joints.B.contact.stiffness`` of a contact in force, ...). Every example runs with an
  integrator capped at ``MAX_STEPS`` attempted steps, so a valid but very stiff
  combination (a 100 t crank driving a 5 g rod through a 1 µm clearance at rtol = 1e-12)
  ends there, or as soon as its step count extrapolated from its progress exceeds the
  cap, instead of running for hours;

and never anything else: no other exception, no NaN or inf in the outputs, no run that
outgrows the cap (an absurd size is refused up front). RuntimeWarnings raised in mechanism
code are errors (pyproject), so an overflow inside the simulator fails the test too. The
default run draws ``EXAMPLES`` examples (about a minute); ``-m slow`` runs many more.
"""

from __future__ import annotations

import dataclasses
import math
import re
import typing
from typing import Any

import annotated_types as at
import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import mechanism
from mechanism.core.integrate import Dopri5
from mechanism.core.scene import (
    ClearanceRevolute,
    ContactLaw,
    FrictionLaw,
    RigidBody,
    SolverSettings,
    WearSettings,
    _model,
    _scene,
)

BASE = mechanism.load_scene("slider-crank-clearance")
MAX_STEPS = 20_000  # attempted steps per run (the companion has its own)
EXAMPLES = 80
SLOW_EXAMPLES = 400

# a refusal names a scene key or an argument of simulate
KEY = re.compile(
    r"\b(revolutions|t_end|output_step|rtol|atol|discard|name|gravity|"
    r"(bodies|joints|drive|solver|effects|outputs)\.[\w.\[\]]+)"
)


def _bounds(cls: type, name: str) -> tuple[float, float]:
    """The accepted [low, high] of a numeric field, from its annotations."""
    hint = typing.get_type_hints(cls, include_extras=True)[name]
    low, high = -math.inf, math.inf
    stack = [hint]
    while stack:
        tp = stack.pop()
        if typing.get_origin(tp) is typing.Annotated:
            base, *meta = typing.get_args(tp)
            stack.append(base)
            for item in meta:
                if isinstance(item, at.Ge | at.Gt):
                    low = float(getattr(item, "ge", getattr(item, "gt", low)))
                elif isinstance(item, at.Le | at.Lt):
                    high = float(getattr(item, "le", getattr(item, "lt", high)))
        elif typing.get_origin(tp) in (typing.Union, type(int | None)):
            stack.extend(a for a in typing.get_args(tp) if a is not type(None))
    assert math.isfinite(low) and math.isfinite(high), (cls.__name__, name, low, high)
    return low, high


def _log_uniform(low: float, high: float) -> st.SearchStrategy[float]:
    """Over [low, high] evenly in the logarithm, both ends included (low > 0)."""
    lo, hi = math.log10(low), math.log10(high)
    inner = st.floats(lo, hi).map(lambda e: min(max(10.0**e, low), high))
    return st.one_of(st.sampled_from([low, high]), inner)


def _field(cls: type, name: str, *, zero: bool = False) -> st.SearchStrategy[float]:
    low, high = _bounds(cls, name)
    if low <= 0.0:  # a range from 0: zero itself and the decades above the smallest positive
        floor = max(high * 1e-12, 1e-300)
        return (
            st.one_of(st.just(0.0), _log_uniform(floor, high))
            if zero
            else _log_uniform(floor, high)
        )
    return _log_uniform(low, high)


def _rarely(draw: st.DrawFn) -> bool:
    """True one time in eight: the out-of-the-way branch of a draw."""
    return draw(st.integers(0, 7)) == 0


def _below(value: float) -> float:
    """The largest float below ``value`` (an open upper bound)."""
    return float(np.nextafter(value, -math.inf))


@st.composite
def scene_changes(draw: st.DrawFn) -> tuple[dict[str, Any], dict[str, Any]]:
    """Dotted-key changes of the clearance slider-crank and simulate's arguments."""
    changes: dict[str, Any] = {}
    for body in ("crank", "rod", "slider"):
        changes[f"bodies.{body}.mass"] = draw(_field(RigidBody, "mass"))
    low, high = _bounds(RigidBody, "inertia")
    limit = _scene.GYRATION_RATIO
    for body in ("crank", "rod"):  # the slider cannot rotate
        # the inertia through the radius of gyration, within (and a little beyond) the
        # factor the validator accepts around the farthest point: independent draws of
        # mass and inertia would be refused by that rule most of the time
        reach = max(math.hypot(*p) for p in BASE.bodies[body].points.values())
        mass = changes[f"bodies.{body}.mass"]
        # the band of inertias the rule leaves for this mass (one time in eight, anywhere)
        lo = max(low, mass * (reach / limit) ** 2)
        hi = min(high, mass * (reach * limit) ** 2)
        inside = lo <= hi and not _rarely(draw)
        changes[f"bodies.{body}.inertia"] = draw(
            _log_uniform(lo, hi) if inside else _log_uniform(low, high)
        )
    radius = draw(_field(ClearanceRevolute, "bearing_radius"))
    c_low, c_high = _bounds(ClearanceRevolute, "clearance")
    if radius > c_low:
        clearance = draw(_log_uniform(c_low, min(c_high, _below(radius))))
    else:  # the smallest bearing: the smallest clearance does not fit
        radius = draw(_log_uniform(c_low * 1.01, 10 * c_low))
        clearance = c_low
    changes["joints.B.bearing_radius"] = radius
    changes["joints.B.clearance"] = clearance
    changes["joints.B.length"] = draw(_field(ClearanceRevolute, "length"))
    r_low, r_high = _bounds(ClearanceRevolute, "restitution")
    changes["joints.B.restitution"] = draw(st.floats(r_low, r_high))
    changes["joints.B.contact.law"] = draw(
        st.sampled_from(["lankarani-nikravesh", "hertz", "flores", "hu-guo"])
    )
    changes["joints.B.contact.stiffness"] = draw(
        st.one_of(st.sampled_from(_model.STIFFNESS_FORMS), _log_uniform(*_model.STIFFNESS_RANGE))
    )
    e_low, e_high = _bounds(ContactLaw, "exponent")
    changes["joints.B.contact.exponent"] = draw(st.floats(e_low, e_high))
    changes["joints.B.contact.impact_velocity_floor"] = draw(
        _field(ContactLaw, "impact_velocity_floor")
    )
    changes["joints.B.friction.law"] = draw(st.sampled_from(["none", "coulomb", "ambrosio"]))
    changes["joints.B.friction.coefficient"] = draw(_field(FrictionLaw, "coefficient", zero=True))
    v_low, v_high = _bounds(FrictionLaw, "v0")
    v0 = draw(_log_uniform(v_low, _below(v_high)))
    changes["joints.B.friction.v0"] = v0
    changes["joints.B.friction.v1"] = draw(_log_uniform(float(np.nextafter(v0, math.inf)), v_high))
    changes["effects.wear"] = draw(st.booleans())
    g_low, g_high = _bounds(WearSettings, "regions")
    regions = draw(st.integers(int(g_low), int(g_high)))
    changes["joints.B.wear.regions"] = regions
    changes["joints.B.wear.smoothing_regions"] = draw(st.integers(1, regions // 2))
    changes["joints.B.wear.coefficient"] = draw(_field(WearSettings, "coefficient", zero=True))
    low, high = _model.SPEED_RPM_RANGE
    changes["drive.speed_rpm"] = draw(st.sampled_from([-1.0, 1.0])) * draw(_log_uniform(low, high))
    t_low, t_high = _bounds(SolverSettings, "rtol")
    changes["solver.rtol"] = draw(_log_uniform(t_low, _below(t_high)))
    changes["solver.atol"] = draw(_field(SolverSettings, "atol"))
    # the output step and largest step take any positive value; absurd ones are drawn
    # one time in eight, so that most examples run
    period = 60.0 / abs(changes["drive.speed_rpm"])
    for key in ("solver.output_step", "solver.max_step"):
        if _rarely(draw):
            changes[key] = draw(_log_uniform(1e-300, 1e3))
        else:  # unset, or a fraction of the drive period
            changes[key] = draw(st.none() | _log_uniform(1e-5 * period, 1e-2 * period))
    # tiny runs, or (one time in eight) absurdly long ones: refused up front or stopped
    # by the step cap
    absurd = _rarely(draw)
    revolutions = draw(_log_uniform(1e3, 1e15) if absurd else _log_uniform(1e-3, 0.05))
    return changes, {"revolutions": revolutions}


def _check(changes: dict[str, Any], arguments: dict[str, Any]) -> str:
    """Run one example; the outcome ("ran", "refused" or "stopped") or a failed assert."""
    try:
        scene = BASE.replace(changes)
        ds = mechanism.simulate(scene, method=Dopri5(max_steps=MAX_STEPS), **arguments)
    except mechanism.SimulationError as exc:
        # the integration gave up: one line naming the keys that change the outcome
        text = str(exc)
        assert "\n" not in text and " failed " in text, text
        assert KEY.search(text.partition("the keys that change the outcome:")[2]), text
        return "stopped"
    except mechanism.SceneError as exc:  # one line per problem, each naming its key
        for problem in exc.problems:
            assert "\n" not in problem and KEY.match(problem), problem
        return "refused"
    except ValueError as exc:
        text = str(exc)
        assert "\n" not in text, text
        assert KEY.search(text), text
        return "refused"
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "f":
            assert bool(np.isfinite(var.values).all()), (name, changes, arguments)
    assert ds.attrs["solver_status"] == 0
    return "ran"


_SETTINGS = dict(
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)


@pytest.mark.filterwarnings("ignore::UserWarning")  # advice such as deep penetration
@settings(max_examples=EXAMPLES, **_SETTINGS)
@given(drawn=scene_changes())
def test_any_accepted_scene_runs_or_is_refused_with_a_key(drawn) -> None:
    event(_check(*drawn))  # the outcomes' shares: --hypothesis-show-statistics


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::UserWarning")
@settings(max_examples=SLOW_EXAMPLES, **_SETTINGS)
@given(drawn=scene_changes())
def test_any_accepted_scene_runs_or_is_refused_with_a_key_long(drawn) -> None:
    event(_check(*drawn))


def test_the_ranges_drawn_are_the_validators() -> None:
    # the strategy reads the bounds from the model, so it follows any change of a range
    assert _bounds(RigidBody, "mass") == _model.MASS_RANGE
    assert _bounds(RigidBody, "inertia") == _model.INERTIA_RANGE
    assert _bounds(WearSettings, "regions") == (3.0, float(_model.MAX_REGIONS))
    assert _bounds(SolverSettings, "rtol") == (1e-13, 1.0)
    assert dataclasses.is_dataclass(ClearanceRevolute)
