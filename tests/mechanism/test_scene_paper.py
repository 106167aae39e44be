"""The paper scenes reproduce paper-model.md §1.6 (geometry) and the §4 parameters."""

from __future__ import annotations

import math

import pytest

import mechanism
from mechanism.core.scene import AncfBeam, ClearanceRevolute, ConstantSpeedDrive, RigidBody, Scene

MM = 1e-3


def point(scene: Scene, body_name: str, name: str) -> tuple[float, float]:
    """Global position of a named point at t = 0, from the scene data alone."""
    if body_name == "ground":
        return scene.ground_points[name]
    body = scene.bodies[body_name]
    if isinstance(body, AncfBeam):
        return body.start if name == "start" else body.end
    assert isinstance(body, RigidBody)
    c, s = math.cos(body.angle), math.sin(body.angle)
    x, y = body.points[name]
    return (body.position[0] + c * x - s * y, body.position[1] + s * x + c * y)


def joint_positions(scene: Scene) -> dict[str, tuple[float, float]]:
    """Each joint's position; both ends of every joint must coincide at t = 0."""
    out = {}
    for name, joint in scene.joints.items():
        if isinstance(joint, ClearanceRevolute):
            a, b = point(scene, *joint.bearing), point(scene, *joint.journal)
            ecc = joint.initial_eccentricity
            b = (b[0] - ecc[0], b[1] - ecc[1])
        else:
            a = point(scene, joint.bodies[0], joint.points[0])
            b = point(scene, joint.bodies[1], joint.points[1])
        if name != "P":  # the prismatic joint only needs E on the guide line
            assert math.dist(a, b) < 1e-12, name
        out[name] = b
    return out


@pytest.mark.parametrize("name", ["paper", "paper-clearance-b"])
def test_g_a_loop_closure_distances(name: str) -> None:
    p = joint_positions(mechanism.load_scene(name))
    expected = {
        ("A", "B"): 555.14,
        ("B", "C"): 584.0,
        ("A", "D"): 473.66,
        ("B", "D"): 985.0,
        ("D", "E"): 450.0,
        ("O", "A"): 75.0,
    }
    for (i, j), mm in expected.items():
        assert math.dist(p[i], p[j]) == pytest.approx(mm * MM, abs=1e-6), (i, j)
    assert p["O"] == (0.0, 0.0) and p["C"] == (0.350, 0.060)


def test_g_a_coordinates_match_the_section_1_6_table() -> None:
    scene = mechanism.load_scene("paper")
    p = joint_positions(scene)
    table = {
        "A": (75.00, 0.00),
        "B": (38.41, 553.93),
        "C": (350.00, 60.00),
        "D": (362.99, -376.05),
        "E": (350.00, -825.87),
    }
    for name, (x, y) in table.items():  # the table is rounded to 0.01 mm
        assert p[name][0] == pytest.approx(x * MM, abs=0.006 * MM), name
        assert p[name][1] == pytest.approx(y * MM, abs=0.006 * MM), name
    plate = scene.bodies["plate"]
    assert isinstance(plate, RigidBody)
    assert plate.position[0] == pytest.approx(158.8 * MM, abs=0.05 * MM)  # centroid
    assert plate.position[1] == pytest.approx(59.3 * MM, abs=0.05 * MM)
    for (i, j), deg in {("A", "B"): 93.78, ("C", "B"): 122.24, ("D", "E"): -91.65}.items():
        angle = math.degrees(math.atan2(p[j][1] - p[i][1], p[j][0] - p[i][0]))
        assert angle == pytest.approx(deg, abs=0.005), (i, j)
    # the slider sits on the vertical guide through C, below D
    guide = scene.joints["P"]
    assert guide.axis == (0.0, 1.0)  # type: ignore[union-attr]
    assert scene.ground_points["guide"][0] == p["E"][0] == 0.350
    assert p["E"][1] < p["D"][1]
    # B lies above the O-C line (rocker branch)
    assert p["C"][0] * p["B"][1] - p["C"][1] * p["B"][0] > 0


def test_g_c_alternative_geometry() -> None:
    p = joint_positions(mechanism.load_scene("paper-gc"))
    for (i, j), mm in {
        ("A", "B"): 555.14,
        ("A", "D"): 985.0,
        ("B", "D"): 473.66,
        ("B", "C"): 584.0,
        ("D", "E"): 450.0,
    }.items():
        assert math.dist(p[i], p[j]) == pytest.approx(mm * MM, abs=1e-6), (i, j)
    for name, (x, y) in {
        "B": (38.41, 553.93),
        "D": (274.44, 964.60),
        "E": (350.00, 520.99),
    }.items():
        assert p[name][0] == pytest.approx(x * MM, abs=0.006 * MM), name
        assert p[name][1] == pytest.approx(y * MM, abs=0.006 * MM), name


def test_paper_parameters_follow_section_4() -> None:
    scene = mechanism.load_scene("paper")
    c = scene.joints["C"]
    assert isinstance(c, ClearanceRevolute)
    assert c.bearing == ("ground", "C") and c.journal == ("rod3", "start")
    assert (c.bearing_radius, c.length, c.clearance) == (0.015, 0.011, 0.0002)
    for material in (c.bearing_material, c.journal_material):
        assert (material.youngs_modulus, material.poisson_ratio) == (207e9, 0.3)
    assert c.restitution == 0.9
    assert (c.contact.law, c.contact.stiffness, c.contact.exponent) == (
        "lankarani-nikravesh",
        "sum-of-radii",
        1.5,
    )
    assert (c.friction.law, c.friction.coefficient, c.friction.v0, c.friction.v1) == (
        "ambrosio",
        0.15,
        1e-4,
        2e-4,
    )
    assert c.wear.coefficient == 1.827e-13 and c.wear.regions == 360
    # paper-model §2.5: the sum-of-radii stiffness the tables imply, 1.309e10 at c = 0.2 mm
    e_star = 1.0 / (2 * (1 - 0.3**2) / 207e9)
    r_b, r_j = c.bearing_radius, c.journal_radius
    k = 4.0 / 3.0 * e_star * math.sqrt(r_b * r_j / (r_b + r_j))
    assert k == pytest.approx(1.309e10, rel=1e-3)

    drive = scene.drive
    assert isinstance(drive, ConstantSpeedDrive)
    assert (drive.joint, drive.speed_rpm, drive.initial_angle) == ("O", 150.0, 0.0)
    assert drive.period == pytest.approx(0.4, rel=1e-14)
    s = scene.solver
    assert (s.rtol, s.atol, s.baumgarte_alpha, s.baumgarte_beta) == (1e-5, 1e-5, 50.0, 50.0)
    assert s.output_step is None  # (2 pi/omega)/10000, follows the speed
    assert scene.gravity == (0.0, -9.81)
    e = scene.effects
    assert (e.clearance, e.friction, e.gravity) == (True, True, True)
    # rods 3 and 4 flexible by default, integrator chosen by the assembled model
    assert (e.flexibility, e.wear) == (True, False)
    assert s.method == "auto"

    crank, plate, slider = (scene.bodies[n] for n in ("crank", "plate", "slider"))
    assert isinstance(crank, RigidBody) and isinstance(plate, RigidBody)
    assert isinstance(slider, RigidBody)
    assert (crank.mass, plate.mass, slider.mass) == (0.738, 21.483, 0.922)
    assert plate.inertia == 1.349
    # crank inertia about its CoM (mid-length): 1.977e-3 about O minus m (L1/2)^2 (A5)
    assert crank.inertia + crank.mass * 0.0375**2 == pytest.approx(1.977e-3, rel=1e-12)
    assert crank.position == (0.0375, 0.0)
    for name, mass, length in (("rod3", 4.708, 0.584), ("rod4", 3.663, 0.450)):
        rod = scene.bodies[name]
        assert isinstance(rod, AncfBeam)
        assert (rod.elements, rod.area, rod.second_moment) == (16, 1e-3, 3.33e-8)
        assert (rod.youngs_modulus, rod.density) == (207e9, 7800.0)
        assert (rod.mass, rod.length) == (mass, length)
        assert math.dist(rod.start, rod.end) == pytest.approx(length, abs=1e-12)


def test_paper_clearance_b_moves_the_clearance_to_the_plate() -> None:
    scene = mechanism.load_scene("paper-clearance-b")
    b, c = scene.joints["B"], scene.joints["C"]
    assert isinstance(b, ClearanceRevolute) and b.bearing == ("plate", "B")
    assert b.journal == ("rod3", "end")
    assert c.type == "revolute" and c.bodies == ("ground", "rod3")  # type: ignore[union-attr]
    paper_c = mechanism.load_scene("paper").joints["C"]
    assert isinstance(paper_c, ClearanceRevolute)
    for key in ("bearing_radius", "clearance", "length", "contact", "friction", "wear"):
        assert getattr(b, key) == getattr(paper_c, key), key
