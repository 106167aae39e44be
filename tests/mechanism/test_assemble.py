"""Assembly of scenes into the compiled model: layout, mass, gravity, tables, errors."""

from __future__ import annotations

import dataclasses
import doctest
import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import mechanism
from mechanism.core.bodies import rigid_bar_from_beam
from mechanism.core.joints import _kernels as jk
from mechanism.core.model import _assemble, assemble, initial_state
from mechanism.core.scene import AncfBeam, RevoluteJoint
from tests.mechanism.scenes import rigid_paper, rotating_guide


def test_slider_crank_layout_mass_and_gravity() -> None:
    model = assemble(mechanism.load_scene("slider-crank"))
    assert model.n_dof == 9 and model.n_rows == 9  # 3 pins, prismatic (2), drive
    assert model.body_names == ("crank", "rod", "slider")
    assert model.body_offsets == (0, 3, 6)
    assert model.dof_names[:3] == ("crank.x", "crank.y", "crank.theta")
    km = model.kernel
    assert_allclose(np.diag(km.mass), [0.30, 0.30, 1e-4, 0.21, 0.21, 2.5e-4, 0.14, 0.14, 1e-4])
    assert_allclose(km.minv @ km.mass, np.eye(9), atol=1e-12)
    assert_allclose(km.gravity_force[1::3], [-0.30 * 9.81, -0.21 * 9.81, -0.14 * 9.81])
    assert_allclose(km.gravity_force[0::3], 0.0)
    assert model.clearance_joints == ()
    assert [j.name for j in model.ideal_joints] == ["O", "A", "B", "P"]
    assert model.drive_row == 8
    assert model.slider is not None and model.slider.axis == (1.0, 0.0)


def test_clearance_joint_becomes_a_force_element() -> None:
    model = assemble(mechanism.load_scene("slider-crank-clearance"))
    assert model.n_dof == 9 and model.n_rows == 7
    assert model.clearance_joints == ("B",)
    cj = model.kernel.cj_f[0]
    # S1: conformal Hertz stiffness of a 10 mm bearing with 0.5 mm clearance
    assert cj[2] == pytest.approx(5e-4)
    assert cj[3] == pytest.approx(6.6102e10, rel=1e-4)
    assert (cj[0], cj[1]) == pytest.approx((0.010, 0.0095))
    # the ideal companion and the clearance-off scene have a pin instead
    for m in (
        assemble(mechanism.load_scene("slider-crank-clearance"), ideal=True),
        assemble(
            mechanism.load_scene("slider-crank-clearance").replace({"effects.clearance": False})
        ),
    ):
        assert m.clearance_joints == () and m.n_rows == 9
        assert m.kernel.cj_i.shape == (0, 5)  # [bearing, journal, law, friction, kind]


def test_rigid_bar_replaces_an_ancf_beam_when_flexibility_is_off() -> None:
    scene = rigid_paper()
    rod3 = scene.bodies["rod3"]
    assert isinstance(rod3, AncfBeam) and not scene.effects.flexibility
    bar = rigid_bar_from_beam(rod3)
    assert bar.mass == pytest.approx(4.708)
    assert bar.inertia == pytest.approx(4.708 * 0.584**2 / 12)
    assert bar.points == {"start": (-0.292, 0.0), "end": (0.292, 0.0)}
    sx, sy = rod3.start
    ex, ey = rod3.end
    assert bar.position == pytest.approx(((sx + ex) / 2, (sy + ey) / 2))
    assert bar.angle == pytest.approx(math.atan2(ey - sy, ex - sx))
    override = rigid_bar_from_beam(dataclasses.replace(rod3, rigid_inertia=0.5))
    assert override.inertia == 0.5
    model = assemble(scene)
    assert model.n_dof == 15 and model.rigid_bodies == model.body_names
    i = model.body_offsets[model.body_names.index("rod3")]
    assert model.kernel.mass[i + 2, i + 2] == pytest.approx(bar.inertia)


def test_paper_scene_assembles_with_the_journal_centred() -> None:
    scene = mechanism.load_scene("paper")
    model = assemble(scene)
    q0, v0 = initial_state(model)
    km = model.kernel
    ws = model.workspace()
    jk.update_points(q0, v0, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    b, j = km.cj_i[0, 0], km.cj_i[0, 1]
    assert_allclose(ws.pcf[j, :2], ws.pcf[b, :2], atol=1e-12)
    # journal at rest relative to the (ground) bearing: ideal-mechanism velocities
    assert_allclose(ws.pcf[j, 2:4], 0.0, atol=1e-10)
    # crank at 150 rpm
    assert v0[2] == pytest.approx(150 * 2 * math.pi / 60)


def test_initial_eccentricity_is_honoured() -> None:
    scene = mechanism.load_scene("slider-crank-clearance").replace(
        {"joints.B.initial_eccentricity": [2e-4, -1e-4]}
    )
    model = assemble(scene)
    q0, v0 = initial_state(model)
    km = model.kernel
    ws = model.workspace()
    jk.update_points(q0, v0, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    b, j = km.cj_i[0, 0], km.cj_i[0, 1]
    assert_allclose(ws.pcf[j, :2] - ws.pcf[b, :2], [2e-4, -1e-4], atol=1e-12)
    q_ideal, _ = initial_state(model, eccentricity=False)
    jk.update_points(q_ideal, v0, km.pt_i, km.pt_f, ws.pci, ws.pcf)
    assert_allclose(ws.pcf[j, :2] - ws.pcf[b, :2], 0.0, atol=1e-12)


def test_every_primitive_is_tabulated_for_the_rotating_guide() -> None:
    model = assemble(rotating_guide(clearance=True))
    types = list(model.kernel.con_i[:, 0])
    assert types.count(jk.CON_COINCIDE) == 2  # pivot O, fixed joint W
    assert types.count(jk.CON_ANGLE) == 2  # prismatic G, fixed joint W
    assert types.count(jk.CON_NORMAL) == 1
    assert types.count(jk.CON_DRIVE) == 1
    assert model.n_rows == 8 and model.n_dof == 12
    assert model.kernel.drive_i[0] == jk.DRIVE_PROFILE
    kinds = {j.name: j.kind for j in model.ideal_joints}
    assert kinds == {"O": "revolute", "G": "prismatic", "W": "fixed"}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"joints": {"X": RevoluteJoint(bodies=("crank", "rod"), points=("Q", "A"))}}, "no point"),
        ({"joints": {"X": RevoluteJoint(bodies=("wheel", "rod"), points=("A", "A"))}}, "wheel"),
        ({"joints": {"X": RevoluteJoint(bodies=("ground", "rod"), points=("Z", "A"))}}, "'Z'"),
    ],
)
def test_bad_references_name_the_joint(change, message) -> None:
    scene = mechanism.load_scene("slider-crank")
    bad = dataclasses.replace(scene, joints={**scene.joints, **change["joints"]})
    with pytest.raises(ValueError, match=message) as info:
        assemble(bad)
    assert "joints.X" in str(info.value)


def test_drive_must_name_a_revolute_joint() -> None:
    scene = mechanism.load_scene("slider-crank")
    bad = dataclasses.replace(scene, drive=dataclasses.replace(scene.drive, joint="P"))
    with pytest.raises(ValueError, match=r"drive\.joint"):
        assemble(bad)


def test_unassemblable_guesses_raise() -> None:
    scene = mechanism.load_scene("slider-crank")
    # a slider guide 1 m above the crank pivot cannot be reached by a 12 cm rod
    far = dataclasses.replace(scene, ground_points={"O": (0.0, 0.0), "G": (0.0, 1.0)})
    far = dataclasses.replace(
        far,
        joints={
            **scene.joints,
            "P": dataclasses.replace(scene.joints["P"], points=("G", "B")),
        },
    )
    with pytest.raises(ValueError, match="cannot be assembled"):
        initial_state(assemble(far))


def test_docstring_examples_run() -> None:
    for module in (_assemble, mechanism.core.bodies._rigid):
        failures, _ = doctest.testmod(module, raise_on_error=False)
        assert failures == 0, module.__name__
