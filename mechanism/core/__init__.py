"""The simulator core: scene → assemble → integrate → record.

Bodies (rigid, ANCF), joints (ideal, clearance), contact laws and the worn-joint geometry are
the building blocks; :func:`simulate` runs a scene and returns a Dataset. Nothing here imports
:mod:`mechanism.studies`; studies are built on the names this package exports.
"""

from __future__ import annotations

from . import bodies, contact, integrate, joints, model, record, scene, wear
from ._run_checks import SimulationWarning
from ._simulate import (
    SimulationError,
    default_step,
    drive_period,
    output_grid,
    simulate,
    step_limits,
)
from .bodies import (
    AncfMesh,
    BeamModes,
    BeamStaticSolution,
    beam_modes,
    euler_bernoulli_frequencies,
    solve_beam_static,
)
from .contact import contact_stiffness, hertz_stiffness
from .record import FullRecord, MetricsRecord, RecordMode, SectionsRecord, WearRecord
from .scene import Scene, SceneError, list_scenes, load_scene, save_scene, scene_from_json
from .wear import WornProfile, archard_wear

__all__ = [
    "AncfMesh",
    "BeamModes",
    "BeamStaticSolution",
    "FullRecord",
    "MetricsRecord",
    "RecordMode",
    "Scene",
    "SceneError",
    "SectionsRecord",
    "SimulationError",
    "SimulationWarning",
    "WearRecord",
    "WornProfile",
    "archard_wear",
    "beam_modes",
    "bodies",
    "contact",
    "contact_stiffness",
    "default_step",
    "drive_period",
    "euler_bernoulli_frequencies",
    "hertz_stiffness",
    "integrate",
    "joints",
    "list_scenes",
    "load_scene",
    "model",
    "output_grid",
    "record",
    "save_scene",
    "scene",
    "scene_from_json",
    "simulate",
    "solve_beam_static",
    "step_limits",
    "wear",
]
