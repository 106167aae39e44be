"""Scene loading, validation, dotted-key replacement and TOML/JSON round trips."""

from __future__ import annotations

import dataclasses
import doctest
import math
import tomllib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechanism
from mechanism.cli import _common as cli_common
from mechanism.cli import _sweep as cli_sweep
from mechanism.core.scene import (
    AncfBeam,
    AngleProfileDrive,
    ClearanceRevolute,
    ConstantSpeedDrive,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    Scene,
    SceneError,
    _load,
    _model,
    _scene,
    scene_from_dict,
    scene_from_json,
    scene_from_toml,
    validate_scene,
)

REQUIRED_BUILTINS = ("paper", "slider-crank", "slider-crank-clearance")


# --- built-in scenes ----------------------------------------------------------------


def test_list_scenes_has_the_required_builtins_with_one_line_descriptions() -> None:
    table = mechanism.list_scenes()
    for name in REQUIRED_BUILTINS:
        assert name in table
    for name, description in table.items():
        assert description and "\n" not in description, name


@pytest.mark.parametrize("name", sorted(mechanism.list_scenes()))
def test_every_builtin_loads_and_names_itself(name: str) -> None:
    scene = mechanism.load_scene(name)
    assert isinstance(scene, Scene)
    assert scene.name == name
    assert scene.drive is not None and scene.outputs.slider_joint is not None


def test_slider_crank_matches_s2() -> None:
    scene = mechanism.load_scene("slider-crank")
    crank, rod, slider = (scene.bodies[n] for n in ("crank", "rod", "slider"))
    assert isinstance(crank, RigidBody) and isinstance(rod, RigidBody)
    assert isinstance(slider, RigidBody)
    assert (crank.mass, rod.mass, slider.mass) == (0.30, 0.21, 0.14)
    assert (crank.inertia, rod.inertia, slider.inertia) == (1e-4, 2.5e-4, 1e-4)
    # link lengths from the joint points: crank O-A 0.05 m, rod A-B 0.12 m
    assert math.dist(crank.points["O"], crank.points["A"]) == pytest.approx(0.05, abs=1e-15)
    assert math.dist(rod.points["A"], rod.points["B"]) == pytest.approx(0.12, abs=1e-15)
    assert scene.gravity == (0.0, -9.81)
    assert all(not isinstance(j, ClearanceRevolute) for j in scene.joints.values())
    drive = scene.drive
    assert isinstance(drive, ConstantSpeedDrive)
    assert (drive.joint, drive.speed_rpm, drive.initial_angle) == ("O", 5000.0, 0.0)
    assert drive.speed == pytest.approx(5000 * 2 * math.pi / 60, rel=1e-15)
    guide = scene.joints[scene.outputs.slider_joint or ""]
    assert isinstance(guide, PrismaticJoint)
    assert guide.bodies == ("ground", "slider") and guide.axis == (1.0, 0.0)
    # horizontal guide through the crank pivot
    assert scene.ground_points[guide.points[0]][1] == 0.0
    assert scene.ground_points["O"] == (0.0, 0.0)


def test_slider_crank_clearance_matches_s1_and_s3() -> None:
    scene = mechanism.load_scene("slider-crank-clearance")
    ideal = mechanism.load_scene("slider-crank")
    assert scene.bodies == ideal.bodies and scene.drive == ideal.drive
    joint = scene.joints["B"]
    assert isinstance(joint, ClearanceRevolute)
    assert {joint.bearing[0], joint.journal[0]} == {"rod", "slider"}
    assert joint.bearing_radius == 0.010 and joint.clearance == 0.0005
    assert joint.journal_radius == pytest.approx(0.0095, abs=1e-15)
    assert joint.length == 0.040 and joint.restitution == 0.9
    assert joint.contact.law == "lankarani-nikravesh" and joint.contact.stiffness == "conformal"
    assert (joint.friction.law, joint.friction.coefficient) == ("ambrosio", 0.1)
    assert (joint.friction.v0, joint.friction.v1) == (1e-4, 1e-3)
    assert joint.initial_eccentricity == (0.0, 0.0)
    # S1: the scene's data give K = 6.6102e10 N/m^1.5 with the conformal radius
    e_star = 1.0 / sum(
        (1 - m.poisson_ratio**2) / m.youngs_modulus
        for m in (joint.bearing_material, joint.journal_material)
    )
    r_b, r_j = joint.bearing_radius, joint.journal_radius
    k = 4.0 / 3.0 * e_star * math.sqrt(r_b * r_j / (r_b - r_j))
    assert k == pytest.approx(6.6102e10, rel=1e-4)
    # the S3 frictionless variant is one replace away
    frictionless = scene.replace({"joints.B.friction.law": "none"})
    assert frictionless.joints["B"].friction.law == "none"  # type: ignore[union-attr]


# --- round trips ----------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(mechanism.list_scenes()))
def test_toml_and_json_round_trips_are_exact(name: str, tmp_path) -> None:
    scene = mechanism.load_scene(name)
    text = scene.to_toml()
    again = scene_from_toml(text)
    assert again == scene
    assert again.to_toml() == text  # the emitter is a fixed point
    assert scene_from_json(scene.to_json()) == scene
    path = mechanism.save_scene(scene, tmp_path / f"{name}.toml")
    assert mechanism.load_scene(path) == scene
    assert mechanism.load_scene(str(path)) == scene


def _exotic_scene() -> Scene:
    """Everything the emitter must handle: profiles, numbers as stiffness, optionals set
    and unset, an angle-profile drive, odd strings, a fixed joint."""
    rng = np.random.default_rng(7)
    data = mechanism.load_scene("slider-crank-clearance").to_dict()
    # named entries are added through the data, replace() only changes existing keys
    data["bodies"]["extra"] = {"mass": 1.0, "inertia": 0.1, "points": {"c": [0.1 / 3, -2 / 7]}}
    data["joints"]["W"] = {"type": "fixed", "bodies": ["ground", "extra"], "points": ["O", "c"]}
    return scene_from_dict(data).replace(
        {
            "description": 'line 1\nline "2" \\ tab\t é ∂ \r\n',  # no other control characters
            "joints.B.wear.bearing_profile": rng.random(360) * 1e-5,
            "joints.B.wear.journal_profile": np.zeros(360),
            "joints.B.contact.stiffness": 1.234e10,
            "solver.max_step": 1e-6,
            "solver.output_step": 2.5e-6,
            "bodies.extra.position": [0.3, 0.4],
            "drive": {
                "type": "angle_profile",
                "joint": "O",
                "time": [0.0, 0.004, 0.008],
                "angle": [0.0, 2.0, 4.0],
                "period": 0.012,
            },
        }
    )


def test_round_trip_with_every_kind_of_value(tmp_path) -> None:
    scene = _exotic_scene()
    assert isinstance(scene.drive, AngleProfileDrive)
    assert len(scene.joints["B"].wear.bearing_profile) == 360  # type: ignore[union-attr]
    assert scene_from_toml(scene.to_toml()) == scene
    assert scene_from_json(scene.to_json()) == scene
    assert mechanism.load_scene(mechanism.save_scene(scene, tmp_path / "x.toml")) == scene
    # unset optionals are omitted from TOML and load back as None
    plain = mechanism.load_scene("paper")
    assert plain.solver.output_step is None and "output_step" not in plain.to_toml()
    assert scene_from_toml(plain.to_toml()).solver.output_step is None


def test_to_dict_is_plain_data() -> None:
    data = mechanism.load_scene("paper").to_dict()
    assert isinstance(data["gravity"], list) and data["drive"]["speed_rpm"] == 150.0
    assert data["solver"]["output_step"] is None
    assert data["bodies"]["rod3"]["type"] == "ancf_beam"
    assert scene_from_dict(data) == mechanism.load_scene("paper")


def _within(limit: float) -> st.SearchStrategy[float]:
    return st.floats(-limit, limit, allow_nan=False, allow_infinity=False, width=64)


# any printable text, with the line breaks and tabs a description may hold
_description = st.text(
    st.characters(blacklist_categories=("Cs", "Cc")) | st.sampled_from("\n\t\r"), max_size=40
)


@settings(max_examples=60, deadline=None)
@given(
    text=_description,
    gx=_within(_model.GRAVITY_LIMIT),
    gy=_within(_model.GRAVITY_LIMIT),
    angle=_within(_model.ANGLE_LIMIT),
)
def test_emitter_round_trips_arbitrary_strings_and_floats(
    text: str, gx: float, gy: float, angle: float
) -> None:
    scene = mechanism.load_scene("slider-crank").replace(
        {"description": text, "gravity": [gx, gy], "bodies.crank.angle": angle}
    )
    assert scene_from_toml(scene.to_toml()) == scene


# --- replace ----------------------------------------------------------------------------


def test_replace_nested_keys_returns_a_new_validated_scene() -> None:
    paper = mechanism.load_scene("paper")
    changed = paper.replace(
        {
            "joints.C.clearance": 2e-4 * 2.5,
            "drive.speed_rpm": 90,
            "joints.C.contact.law": "flores",
            "effects.clearance": False,
            "bodies.plate.points.A": (0.0, 0.0),
            "solver.max_step": np.float64(1e-5),
            "bodies.rod3.elements": np.int64(8),
        }
    )
    c = changed.joints["C"]
    assert isinstance(c, ClearanceRevolute)
    assert c.clearance == 5e-4 and c.contact.law == "flores"
    assert changed.drive.speed_rpm == 90.0 and type(changed.drive.speed_rpm) is float  # type: ignore[union-attr]
    assert changed.effects.clearance is False
    assert changed.bodies["plate"].points["A"] == (0.0, 0.0)  # type: ignore[union-attr]
    assert changed.solver.max_step == 1e-5
    assert changed.bodies["rod3"].elements == 8 and type(changed.bodies["rod3"].elements) is int  # type: ignore[union-attr]
    # the original is untouched, everything else is equal
    assert paper.joints["C"].clearance == 2e-4  # type: ignore[union-attr]
    assert changed.joints["O"] == paper.joints["O"] and changed.gravity == paper.gravity
    assert paper.replace({}) == paper


def test_replace_with_a_table_replaces_the_whole_table() -> None:
    paper = mechanism.load_scene("paper")
    changed = paper.replace({"joints.C.friction": {"law": "coulomb", "coefficient": 0.2}})
    friction = changed.joints["C"].friction  # type: ignore[union-attr]
    assert (friction.law, friction.coefficient, friction.v0) == ("coulomb", 0.2, 1e-4)
    # keys apply in order: a table first, then a key inside it
    sc = mechanism.load_scene("slider-crank").replace(
        {"drive": {"joint": "O", "speed_rpm": 60.0}, "drive.initial_angle": 0.5}
    )
    assert sc.drive == ConstantSpeedDrive(joint="O", speed_rpm=60.0, initial_angle=0.5)


@pytest.mark.parametrize(
    ("key", "fragments"),
    [
        ("joints.C.clearence", ["joints.C.clearence", "clearence", "clearance", "bearing_radius"]),
        ("drive.speed_rmp", ["drive.speed_rmp", "speed_rpm", "initial_angle"]),
        ("bodies.krank.mass", ["krank", "crank", "plate", "rod3"]),
        ("nonsense", ["nonsense", "the top level", "joints", "solver"]),
        ("effects.wear.depth", ["'effects.wear' is a value"]),
        ("joints..C", ["not a dotted key"]),
    ],
)
def test_replace_rejects_unknown_keys_listing_the_valid_ones(
    key: str, fragments: list[str]
) -> None:
    paper = mechanism.load_scene("paper")
    with pytest.raises(SceneError) as info:
        paper.replace({key: 1.0})
    for fragment in fragments:
        assert fragment in str(info.value)


def test_replace_into_an_unset_table_says_so() -> None:
    scene = mechanism.load_scene("slider-crank")
    no_drive = Scene(
        **{**{f.name: getattr(scene, f.name) for f in dataclasses.fields(scene)}, "drive": None}
    )
    with pytest.raises(SceneError, match="'drive' is not set"):
        no_drive.replace({"drive.speed_rpm": 100.0})


def test_rho_780_switch_by_dotted_keys() -> None:
    """Paper-model A4: the printed density 780 is a sensitivity switch (rods 10x lighter)."""
    light = mechanism.load_scene("paper").replace(
        {
            "bodies.rod3.density": 780.0,
            "bodies.rod3.mass": 0.4708,
            "bodies.rod4.density": 780.0,
            "bodies.rod4.mass": 0.3663,
        }
    )
    rod3, rod4 = light.bodies["rod3"], light.bodies["rod4"]
    assert isinstance(rod3, AncfBeam) and isinstance(rod4, AncfBeam)
    assert rod3.total_mass == 0.4708 and rod4.total_mass == 0.3663


# --- validation errors ------------------------------------------------------------------


BAD_CHANGES = [
    # (changes, fragments that must all appear in the message)
    ({"joints.B.clearance": -0.001}, ["joints.B.clearance: must be in [1e-08, 1] (m); got -0.001"]),
    ({"joints.B.clearance": 0.01}, ["joints.B.clearance", "< bearing_radius = 0.01", "got 0.01"]),
    ({"joints.B.restitution": 1.2}, ["joints.B.restitution", "in [0.01, 1]", "1.2"]),
    ({"joints.B.restitution": 0.0}, ["joints.B.restitution", "in [0.01, 1]"]),
    ({"bodies.crank.mass": "heavy"}, ["bodies.crank.mass", "a number in [1e-06, 1e+06] (kg)"]),
    ({"bodies.crank.mass": True}, ["bodies.crank.mass", "a number in [1e-06, 1e+06] (kg)"]),
    ({"bodies.crank.inertia": -1.0}, ["bodies.crank.inertia", "in [1e-12, 1e+06] (kg m2)"]),
    ({"bodies.crank.position": [1.0]}, ["bodies.crank.position", "array of 2 numbers (m)"]),
    ({"bodies.crank.position": [1, 2, 3]}, ["bodies.crank.position", "array of 2 numbers"]),
    ({"effects.wear": "yes"}, ["effects.wear", "true or false", "'yes'"]),
    ({"solver.rtol": float("nan")}, ["solver.rtol", "finite"]),
    ({"solver.rtol": 2.0}, ["solver.rtol", "in [1e-13, 1)"]),
    ({"solver.max_step": -1.0}, ["solver.max_step", "> 0 (s)"]),
    ({"joints.B.bearing_material.poisson_ratio": 0.5}, ["poisson_ratio", "in [0, 0.5)"]),
    ({"joints.B.contact.law": "hooke"}, ["joints.B.contact.law", "'hertz'", "'hooke'"]),
    ({"joints.B.contact.stiffness": "stiff"}, ["joints.B.contact.stiffness", "'sum-of-radii'"]),
    ({"joints.B.contact.stiffness": -5.0}, ["joints.B.contact.stiffness", "[1000, 1e+16]"]),
    ({"joints.B.friction.v1": 1e-5}, ["joints.B.friction.v1", "> v0"]),
    ({"joints.B.wear.bearing_profile": [0.0] * 10}, ["bearing_profile", "360", "10 values"]),
    (
        {"joints.B.wear.bearing_profile": [-1.0] * 360},
        ["bearing_profile[0]: must be in [0, 1] (m); got -1.0 (and 359 more entries)"],
    ),
    ({"joints.B.wear.regions": 2}, ["joints.B.wear.regions: must be in [3, 36000]; got 2"]),
    ({"joints.B.initial_eccentricity": [1e-3, 0.0]}, ["initial_eccentricity", "<= clearance"]),
    ({"drive.speed_rpm": 0.0}, ["drive.speed_rpm", "nonzero"]),
    ({"bodies.crank.type": "blob"}, ["bodies.crank.type", "'rigid'", "'ancf_beam'", "'blob'"]),
    (
        {"joints.A": {"bodies": ["crank", "rod"], "points": ["A", "A"]}},
        ["joints.A.type", "missing"],
    ),
    ({"joints.A": 5}, ["joints.A", "must be a table"]),
    ({"bodies.crank": {"inertia": 1.0}}, ["bodies.crank.mass", "required key is missing", "kg"]),
    ({"joints.P.axis": [1.0, 1.0]}, ["joints.P.axis", "unit vector"]),
    ({"name": ""}, ["name", "non-empty"]),
    # unknown keys inside a table given as a whole
    (
        {"joints.B.friction": {"law": "none", "mu": 0.1}},
        ["joints.B.friction.mu", "unknown key", "coefficient"],
    ),
    # missing bodies and points
    ({"joints.A.bodies": ["crank", "nobody"]}, ["joints.A.bodies[1]", "no body 'nobody'", "rod"]),
    ({"joints.A.points": ["A", "Q"]}, ["joints.A.points[1]", "no point 'Q'", "its points: A, B"]),
    ({"joints.B.bearing": ["slider", "X"]}, ["joints.B.bearing[1]", "no point 'X'"]),
    ({"joints.B.journal": ["ghost", "B"]}, ["joints.B.journal[0]", "no body 'ghost'"]),
    ({"joints.P.points": ["nowhere", "B"]}, ["joints.P.points[0]", "body 'ground' has no point"]),
    ({"joints.A.bodies": ["rod", "rod"]}, ["joints.A.bodies", "two different bodies"]),
    ({"ground_points": {"O": [0, 0], "a b": [1, 1]}}, ["ground_points.a b", "letters"]),
    # the drive and outputs
    ({"drive.joint": "B"}, ["drive.joint", "'clearance_revolute'", "'revolute'"]),
    ({"drive.joint": "P"}, ["drive.joint", "'prismatic'", "must be a 'revolute' joint"]),
    ({"drive.joint": "Q"}, ["drive.joint", "no joint 'Q'", "O, A, B, P"]),
    (
        {"outputs.slider_joint": "O"},
        ["outputs.slider_joint", "must be a 'prismatic' or 'clearance_prismatic' joint"],
    ),
    ({"outputs.crank_joint": "P"}, ["outputs.crank_joint", "'revolute' or 'clearance_revolute'"]),
    (
        {
            "drive": {
                "type": "angle_profile",
                "joint": "O",
                "time": [0.0, 0.2, 0.1],
                "angle": [0.0, 1.0, 2.0],
                "period": 1.0,
            }
        },
        ["drive.time", "strictly increasing"],
    ),
]


@pytest.mark.parametrize(("changes", "fragments"), BAD_CHANGES, ids=lambda v: str(v)[:40])
def test_each_validation_error_names_the_key_path(changes, fragments) -> None:
    scene = mechanism.load_scene("slider-crank-clearance")
    with pytest.raises(SceneError) as info:
        scene.replace(changes)
    assert isinstance(info.value, ValueError)
    message = str(info.value)
    for fragment in fragments:
        assert fragment in message, message


def test_ground_is_not_a_body_name() -> None:
    data = mechanism.load_scene("slider-crank").to_dict()
    data["bodies"]["ground"] = {"mass": 1.0, "inertia": 1.0}
    with pytest.raises(SceneError, match=r"bodies\.ground: 'ground' is the frame"):
        scene_from_dict(data)


def test_several_problems_are_reported_together() -> None:
    scene = mechanism.load_scene("slider-crank-clearance")
    with pytest.raises(SceneError) as info:
        scene.replace({"bodies.crank.mass": -1.0, "joints.B.restitution": 2.0})
    assert len(info.value.problems) == 2
    assert info.value.problems[0].startswith("bodies.crank.mass:")
    assert info.value.problems[1].startswith("joints.B.restitution:")


# Every key that sizes an array has an upper bound: a wear profile of 1e9 regions grew a
# run to 24 GB before it was killed, 1e23 regions ended in a numpy error without a key.
SIZE_KEYS = [
    ("slider-crank-clearance", {"joints.B.wear.regions": 10**9}, "joints.B.wear.regions: must "
     "be in [3, 36000]; got 1000000000"),
    ("slider-crank-clearance", {"joints.B.wear.regions": 1e23}, "joints.B.wear.regions: must "
     "be an integer in [3, 36000]; got 1e+23"),
    ("slider-crank-clearance", {"joints.B.wear.smoothing_regions": 10**9},
     "joints.B.wear.smoothing_regions: must be in [1, 36000]; got 1000000000"),
    ("paper", {"bodies.rod3.elements": 10**6}, "bodies.rod3.elements: must be in [1, 256]; "
     "got 1000000"),
    ("flexible-slider-crank", {"bodies.rod.initial_sine_velocities": [0.0] * 100_001},
     "bodies.rod.initial_sine_velocities: must be an array of numbers (m s-1)"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "changes", "message"), SIZE_KEYS, ids=lambda v: str(v)[:30])
def test_every_size_key_has_an_upper_bound_named_in_one_line(name, changes, message) -> None:
    with pytest.raises(SceneError) as info:
        mechanism.load_scene(name).replace(changes)
    assert len(info.value.problems) == 1 and "\n" not in str(info.value)
    assert str(info.value).startswith(message), str(info.value)


# A mass of 1e300 or 1e-300 kg, or an inertia of 1e-300 kg m2, was reported as "the
# constraint Jacobian became singular (a locked or redundant configuration)".
PHYSICAL_KEYS = [
    ({"bodies.crank.mass": 1e300}, "bodies.crank.mass: must be in [1e-06, 1e+06] (kg)"),
    ({"bodies.crank.mass": 1e-300}, "bodies.crank.mass: must be in [1e-06, 1e+06] (kg)"),
    ({"bodies.rod.inertia": 1e-300}, "bodies.rod.inertia: must be in [1e-12, 1e+06] (kg m2)"),
    ({"bodies.rod.angle": 1e300}, "bodies.rod.angle: must be in [-1000, 1000] (rad)"),
    ({"bodies.rod.points.A": [-1e300, 0.0]}, "bodies.rod.points.A[0]: must be in [-1000, "
     "1000] (m)"),
    ({"gravity": [0.0, -1e300]}, "gravity[1]: must be in [-1000, 1000] (m s-2)"),
    ({"drive.speed_rpm": 1e-9}, "drive.speed_rpm: must be nonzero, with |speed_rpm| in [0.001, "
     "1e+06] (rpm; negative turns clockwise); got 1e-09"),
    ({"drive.speed_rpm": -1e9}, "drive.speed_rpm: must be nonzero, with |speed_rpm|"),
    ({"joints.B.clearance": 1e-300}, "joints.B.clearance: must be in [1e-08, 1] (m)"),
    ({"joints.B.bearing_radius": 1e300}, "joints.B.bearing_radius: must be in [1e-06, 10] (m)"),
    ({"joints.B.length": 0.0}, "joints.B.length: must be in [1e-06, 10] (m)"),
    ({"joints.B.bearing_material.youngs_modulus": 1e300}, "joints.B.bearing_material."
     "youngs_modulus: must be in [1000, 1e+13] (Pa)"),
    ({"joints.B.contact.stiffness": 1e300}, "joints.B.contact.stiffness: must be 'conformal', "
     "'sum-of-radii' or a number in [1000, 1e+16] (N m^-n)"),
    ({"joints.B.contact.impact_velocity_floor": 1e-300}, "joints.B.contact."
     "impact_velocity_floor: must be in [1e-06, 1] (m s-1)"),
    ({"joints.B.restitution": 1e-300}, "joints.B.restitution: must be in [0.01, 1]"),
    ({"joints.B.friction.coefficient": 1e300}, "joints.B.friction.coefficient: must be in [0, 5]"),
    ({"joints.B.friction.v0": 1e-300}, "joints.B.friction.v0: must be in [1e-07, 10] (m s-1)"),
    ({"joints.B.wear.coefficient": 1.0}, "joints.B.wear.coefficient: must be in [0, 1e-08] "
     "(m2 N-1)"),
    ({"joints.B.wear.radius_ratio_limit": 1e300}, "joints.B.wear.radius_ratio_limit: must be in "
     "[1, 1e+06]"),
    ({"solver.rtol": 1e-300}, "solver.rtol: must be in [1e-13, 1)"),
    ({"solver.atol": 1e300}, "solver.atol: must be in [1e-15, 1]"),
    ({"solver.baumgarte_alpha": 1e300}, "solver.baumgarte_alpha: must be in [0, 10000] (s-1)"),
]  # fmt: skip


@pytest.mark.parametrize(("changes", "message"), PHYSICAL_KEYS, ids=lambda v: str(v)[:40])
def test_physical_keys_have_stated_ranges(changes, message) -> None:
    with pytest.raises(SceneError) as info:
        mechanism.load_scene("slider-crank-clearance").replace(changes)
    assert len(info.value.problems) == 1
    assert str(info.value).startswith(message), str(info.value)


def test_a_beam_whose_default_mass_is_outside_the_range_must_give_its_mass() -> None:
    paper = mechanism.load_scene("paper")
    with pytest.raises(SceneError, match=r"^bodies\.rod3\.mass: density × area × length = "):
        paper.replace({"bodies.rod3.mass": None, "bodies.rod3.area": 1e-12})
    light = paper.replace({"bodies.rod3.mass": 1e-5, "bodies.rod3.area": 1e-12})
    assert light.bodies["rod3"].total_mass == 1e-5  # type: ignore[union-attr]


def test_wear_settings_the_wear_model_rejects_are_refused_with_their_key() -> None:
    # accepted before and refused only inside the run by the worn-profile model, as
    # "smoothing_regions must be in [1, 4]; got 5." without the key path
    scene = mechanism.load_scene("slider-crank-clearance")
    with pytest.raises(SceneError) as info:
        scene.replace({"joints.B.wear.regions": 8, "joints.B.wear.smoothing_regions": 5})
    assert str(info.value).startswith(
        "joints.B.wear.smoothing_regions: must be <= regions // 2 (4); got 5"
    )
    with pytest.raises(SceneError) as info:
        scene.replace({"joints.B.wear.journal_profile": [0.0095] * 360})
    assert str(info.value).startswith(
        "joints.B.wear.journal_profile: every depth must be < the journal radius "
        "(bearing_radius - clearance = 0.0095 m); got 0.0095"
    )
    # a clearance as large as the radius is one problem, not two
    with pytest.raises(SceneError) as info:
        scene.replace({"joints.B.clearance": 0.01})
    assert len(info.value.problems) == 1


# A NUL in the scene name passed validation and the run, then failed when written
# ("VLEN strings do not support embedded NULLs").
@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"name": "press\x00"}, "name: must not contain control characters (U+0000 at position 5)"),
        ({"name": "two\nlines"}, "name: must not contain control characters (U+000A"),
        ({"description": "a\x00b"}, "description: must not contain control characters (U+0000"),
        ({"description": "x\x1b[31m"}, "description: must not contain control characters (U+001B"),
        ({"solver.method": "dopri5\x00"}, "solver.method: must not contain control characters"),
        ({"drive.joint": "O\x7f"}, "drive.joint: must not contain control characters (U+007F"),
    ],
)
def test_control_characters_in_string_keys_are_refused(changes, message) -> None:
    with pytest.raises(SceneError) as info:
        mechanism.load_scene("slider-crank-clearance").replace(changes)
    assert str(info.value).startswith(message), str(info.value)
    assert "\n" not in str(info.value).replace("\\n", "")
    # a description keeps its line breaks and tabs
    text = "first line\n\tsecond line\r\n"
    scene = mechanism.load_scene("slider-crank").replace({"description": text})
    assert scene.description == text


def test_inertia_may_be_left_out_only_for_a_body_that_cannot_rotate() -> None:
    data = mechanism.load_scene("slider-crank").to_dict()
    del data["bodies"]["slider"]["inertia"]  # held by the prismatic joint P to the ground
    scene = scene_from_dict(data)
    slider = scene.bodies["slider"]
    assert isinstance(slider, RigidBody) and slider.inertia == slider.mass * 1.0
    assert scene_from_toml(scene.to_toml()) == scene  # stored resolved
    del data["bodies"]["rod"]["inertia"]
    with pytest.raises(SceneError) as info:
        scene_from_dict(data)
    assert str(info.value).startswith(
        "bodies.rod.inertia: required key is missing (expected a number in [1e-12, 1e+06] "
        "(kg m2)); only a body held to the ground by a prismatic or fixed joint"
    )
    # a Python-built body without inertia is resolved by validation
    built = dataclasses.replace(
        mechanism.load_scene("slider-crank"),
        bodies={**scene.bodies, "slider": RigidBody(mass=0.14, points={"B": (0.0, 0.0)})},
    )
    assert validate_scene(built).bodies["slider"].inertia == 0.14  # type: ignore[union-attr]


def test_the_slider_inertia_does_not_change_the_motion() -> None:
    given = mechanism.load_scene("slider-crank")
    data = given.to_dict()
    del data["bodies"]["slider"]["inertia"]
    default = scene_from_dict(data)
    assert default.bodies["slider"].inertia == 0.14  # type: ignore[union-attr]
    a = mechanism.simulate(given, revolutions=0.5, output_step=1e-4)
    b = mechanism.simulate(default, revolutions=0.5, output_step=1e-4)
    # the ideal slider-crank is regular: its motion survives rounding differences
    np.testing.assert_allclose(b.slider_position, a.slider_position, rtol=0, atol=1e-9)
    np.testing.assert_allclose(b.driving_torque, a.driving_torque, rtol=1e-6, atol=1e-9)


def test_beam_length_must_match_its_end_points() -> None:
    with pytest.raises(SceneError, match=r"bodies\.rod3\.length: 0\.5 m differs"):
        mechanism.load_scene("paper").replace({"bodies.rod3.length": 0.5})


def test_toml_file_errors_name_the_file_and_the_key(tmp_path) -> None:
    text = mechanism.load_scene("slider-crank").to_toml()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("mass = 0.3\n", "mass = 0.3\nmas = 1.0\n", 1))
    with pytest.raises(SceneError) as info:
        mechanism.load_scene(bad)
    assert "bodies.crank.mas: unknown key" in str(info.value) and str(bad) in str(info.value)
    # the old [scene] header of the skeleton docstring is not a key
    bad.write_text('[scene]\nname = "x"\n')
    with pytest.raises(SceneError, match=r"scene: unknown key"):
        mechanism.load_scene(bad)
    bad.write_text("name = \n")
    with pytest.raises(SceneError, match="not valid TOML"):
        mechanism.load_scene(bad)
    with pytest.raises(SceneError, match="no built-in scene or file named"):
        mechanism.load_scene(tmp_path / "missing.toml")
    with pytest.raises(SceneError, match="no built-in scene or file named 'papr'"):
        mechanism.load_scene("papr")


def test_json_errors() -> None:
    with pytest.raises(SceneError, match="not valid JSON"):
        scene_from_json("{")
    with pytest.raises(SceneError, match="table of keys"):
        scene_from_json("[1, 2]")
    with pytest.raises(SceneError, match=r"solver\.max_step: must be a number > 0 \(s\)"):
        scene_from_json(
            mechanism.load_scene("paper").to_json().replace('"max_step": null', '"max_step": "x"')
        )


def test_python_built_scenes_are_validated_on_request_and_on_save(tmp_path) -> None:
    good = Scene(
        name="pendulum",
        ground_points={"O": (0.0, 0.0)},
        bodies={
            "bob": RigidBody(mass=1.0, inertia=0.01, position=(0.5, 0.0), points={"p": (-0.5, 0.0)})
        },
        joints={"O": RevoluteJoint(bodies=("ground", "bob"), points=("O", "p"))},
    )
    assert validate_scene(good) == good
    bad = dataclasses.replace(
        good, bodies={"bob": RigidBody(mass=-1.0, inertia=0.01, points={"p": (0.0, 0.0)})}
    )
    with pytest.raises(SceneError, match=r"bodies\.bob\.mass: must be in \[1e-06, 1e\+06\] \(kg\)"):
        validate_scene(bad)
    with pytest.raises(SceneError):
        mechanism.save_scene(bad, tmp_path / "bad.toml")
    assert not (tmp_path / "bad.toml").exists()


def test_scenes_are_frozen() -> None:
    scene = mechanism.load_scene("paper")
    with pytest.raises(dataclasses.FrozenInstanceError):
        scene.name = "x"  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        scene.joints["C"].clearance = 1.0  # type: ignore[misc]


def test_load_scene_passes_a_scene_through() -> None:
    scene = mechanism.load_scene("paper")
    assert mechanism.load_scene(scene) is scene


# --- helpers, docs and docstrings -------------------------------------------------------


def test_beam_helpers() -> None:
    rod3 = mechanism.load_scene("paper").bodies["rod3"]
    assert isinstance(rod3, AncfBeam)
    assert rod3.total_mass == 4.708
    assert rod3.centroidal_inertia == pytest.approx(4.708 * 0.584**2 / 12, rel=1e-15)
    assert rod3.point_names == ("start", "end")
    default_mass = dataclasses.replace(rod3, mass=None, rigid_inertia=0.2)
    assert default_mass.total_mass == pytest.approx(7800 * 1e-3 * 0.584, rel=1e-15)
    assert default_mass.centroidal_inertia == 0.2


def _model_classes() -> list[type]:
    return [
        getattr(_model, name) for name in _model.__all__ if isinstance(getattr(_model, name), type)
    ]


def test_docs_describe_every_key() -> None:
    from tests.conftest import REPO

    text = (REPO / "docs" / "scenes.md").read_text(encoding="utf-8")
    for cls in _model_classes():
        for f in dataclasses.fields(cls):
            assert f"`{f.name}`" in text, f"{cls.__name__}.{f.name} missing from docs/scenes.md"
    for name in mechanism.list_scenes():
        assert f"`{name}`" in text


def test_builtin_toml_files_parse_with_tomllib_alone() -> None:
    for name in mechanism.list_scenes():
        data = tomllib.loads(_load.builtin_file(name).read_text(encoding="utf-8"))
        assert data["name"] == name


@pytest.mark.parametrize("module", [_scene, _load, _model, cli_common, cli_sweep])
def test_docstring_examples_run(module) -> None:
    result = doctest.testmod(module, globs={**vars(module)}, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
