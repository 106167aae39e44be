"""Scenes built in Python for the simulator tests, beside the built-in TOML scenes.

``rotating_guide`` exercises every constraint primitive with moving frames: a driven arm
(angle-profile drive) carrying a prismatic guide, a slider on it, a body welded to the
slider (fixed joint) and a free link hanging in a clearance joint of that body.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

import mechanism
from mechanism.core.scene import (
    AngleProfileDrive,
    ClearanceRevolute,
    ConstantSpeedDrive,
    ContactLaw,
    Effects,
    FixedJoint,
    FrictionLaw,
    Material,
    Outputs,
    PrismaticJoint,
    RevoluteJoint,
    RigidBody,
    Scene,
    SolverSettings,
)

STEEL = Material(youngs_modulus=207e9, poisson_ratio=0.3)


def rigid_paper(changes: Mapping[str, object] | None = None) -> Scene:
    """The built-in ``paper`` scene with rigid rods 3 and 4 (``effects.flexibility = false``).

    The paper scene is flexible by default; tests about something other than the rods'
    flexibility (kinematics, contact, wear, sweeps, sample data, CLI) were calibrated with
    rigid rods and say so with this scene. ``changes`` are further dotted-key replacements.
    """
    base: dict[str, object] = {"effects.flexibility": False}
    base.update(changes or {})
    return mechanism.load_scene("paper").replace(base)


def s3(*, friction: float = 0.0, **changes: object) -> Scene:
    """The S3 slider-crank with clearance; frictionless unless ``friction`` > 0."""
    scene = mechanism.load_scene("slider-crank-clearance")
    base: dict[str, object] = {
        "joints.B.friction.law": "ambrosio" if friction > 0 else "none",
        "joints.B.friction.coefficient": friction,
        "effects.friction": friction > 0,
    }
    base.update(changes)
    return scene.replace(base)


def profile_drive(period: float = 0.5, samples: int = 9) -> AngleProfileDrive:
    """A crank turning once per period with a superposed wobble, as samples."""
    t = np.linspace(0.0, period, samples)
    angle = 2.0 * math.pi * t / period + 0.2 * np.sin(2.0 * math.pi * t / period)
    return AngleProfileDrive(
        joint="O", time=tuple(t.tolist()), angle=tuple(angle.tolist()), period=period
    )


def rotating_guide(*, clearance: bool = True, drive: str = "profile") -> Scene:
    bodies = {
        "arm": RigidBody(
            mass=1.0,
            inertia=0.02,
            position=(0.1, 0.0),
            angle=0.0,
            points={"O": (-0.1, 0.0), "G": (0.0, 0.01)},
        ),
        "slider": RigidBody(
            mass=0.3, inertia=1e-3, position=(0.15, 0.01), angle=0.0, points={"S": (0.0, 0.0)}
        ),
        "tag": RigidBody(
            mass=0.2,
            inertia=5e-4,
            position=(0.15, 0.04),
            angle=0.0,
            points={"W": (0.0, -0.03), "H": (0.02, 0.01)},
        ),
        "link": RigidBody(
            mass=0.1,
            inertia=2e-4,
            position=(0.17, -0.03),
            angle=-math.pi / 2,
            points={"P": (-0.08, 0.0)},
        ),
    }
    joints: dict[str, object] = {
        "O": RevoluteJoint(bodies=("ground", "arm"), points=("O", "O")),
        "G": PrismaticJoint(bodies=("arm", "slider"), points=("G", "S"), axis=(1.0, 0.0)),
        "W": FixedJoint(bodies=("slider", "tag"), points=("S", "W")),
    }
    if clearance:
        joints["H"] = ClearanceRevolute(
            bearing=("tag", "H"),
            journal=("link", "P"),
            bearing_radius=0.005,
            clearance=2e-4,
            length=0.01,
            bearing_material=STEEL,
            journal_material=STEEL,
            contact=ContactLaw(law="lankarani-nikravesh", stiffness="conformal"),
            friction=FrictionLaw(law="ambrosio", coefficient=0.1, v0=1e-4, v1=1e-3),
        )
    else:
        joints["H"] = RevoluteJoint(bodies=("tag", "link"), points=("H", "P"))
    drv = profile_drive() if drive == "profile" else ConstantSpeedDrive(joint="O", speed_rpm=120.0)
    return Scene(
        name="rotating-guide",
        effects=Effects(clearance=True, friction=True, gravity=True),
        ground_points={"O": (0.0, 0.0)},
        bodies=bodies,
        joints=joints,  # type: ignore[arg-type]
        drive=drv,
        solver=SolverSettings(rtol=1e-8, atol=1e-8),
        outputs=Outputs(slider_joint="G"),
    )


def drop_scene(
    law: str,
    restitution: float,
    *,
    gap: float = 0.0,
    floor: float = 1e-3,
    rule: str = "latched",
) -> Scene:
    """A free pin (0.1 kg, no drive) falling under gravity inside a fixed bearing.

    ``gap`` is the initial distance to the wall below (0: centred journal, it falls the
    whole clearance c = 0.5 mm and hits at √(2 g c) ≈ 0.099 m/s, 99× the default floor);
    ``floor`` the impact-velocity floor and ``rule`` the contact law's approach speed.
    """
    c = 5e-4
    return Scene(
        name="drop",
        effects=Effects(clearance=True, friction=False, gravity=True),
        gravity=(0.0, -9.81),
        ground_points={"H": (0.0, 0.0)},
        bodies={
            "pin": RigidBody(
                mass=0.1, inertia=1e-5, position=(0.0, 0.0), angle=0.0, points={"P": (0.0, 0.0)}
            )
        },
        joints={
            "H": ClearanceRevolute(
                bearing=("ground", "H"),
                journal=("pin", "P"),
                bearing_radius=0.01,
                clearance=c,
                length=0.01,
                restitution=restitution,
                initial_eccentricity=(0.0, -(c - gap)) if gap else (0.0, 0.0),
                bearing_material=STEEL,
                journal_material=STEEL,
                contact=ContactLaw(
                    law=law,
                    stiffness="conformal",
                    impact_velocity_floor=floor,
                    approach_speed=rule,
                ),
                friction=FrictionLaw(law="none"),
            )
        },
    )
