"""mechanism — a planar multibody simulator for rigid-flexible mechanisms with clearance and wear.

Scenes are data (TOML); trajectories are :class:`xarray.Dataset` objects following the
chaoskit data contract (``docs/data-model.md``). Two layers (``docs/architecture.md``):

* :mod:`mechanism.core` — scene → assemble → integrate → record, with the bodies, joints,
  contact laws and worn-joint geometry; it never imports the studies;
* :mod:`mechanism.studies` — sweeps and their store, wear prediction, element convergence
  and the paper study, built on the core's public names.

The names below are the public API of both.
"""

from __future__ import annotations

from chaoskit.contract import __version__, refresh_jit_cache

# before any kernel is compiled or loaded: cached kernels compiled from other sources go
refresh_jit_cache(__file__)

from .core import (
    AncfMesh,
    BeamModes,
    BeamStaticSolution,
    FullRecord,
    MetricsRecord,
    RecordMode,
    Scene,
    SceneError,
    SectionsRecord,
    SimulationError,
    SimulationWarning,
    WearRecord,
    WornProfile,
    archard_wear,
    beam_modes,
    contact_stiffness,
    euler_bernoulli_frequencies,
    hertz_stiffness,
    list_scenes,
    load_scene,
    save_scene,
    scene_from_json,
    simulate,
    solve_beam_static,
)

# two subpackages reachable as attributes (not names of __all__): the scene's parts
# (``mechanism.scene.RigidBody``, ...) and the integrator strategies (``mechanism.integrate``)
from .core import integrate as integrate
from .core import scene as scene
from .studies import (
    Analysis,
    Basins,
    BifurcationPoint,
    BifurcationSettings,
    Continuation,
    ContinuationBranch,
    ContinuationPoint,
    ContinuationSettings,
    ElementConvergence,
    GridTransform,
    LyapunovSettings,
    PaperStudy,
    PeriodicOrbit,
    RouteToChaos,
    SceneLyapunov,
    StudySettings,
    SweepStoreBusy,
    SweepStoreMismatch,
    WearComparison,
    WearLife,
    WearLifeMap,
    WearLifeSettings,
    WearPrediction,
    WearPredictionError,
    basins,
    bifurcation,
    chaos_map,
    compare_wear,
    continuation,
    continue_map,
    element_convergence,
    grid_transforms,
    load_sweep,
    lyapunov_exponent,
    paper_claims,
    paper_tables,
    periodic_orbit,
    plot_basins,
    plot_bifurcation,
    plot_wear_life,
    plot_wear_profile,
    predict_wear,
    register_grid_transform,
    regular_stretches,
    route,
    run_paper_study,
    stroboscopic_points,
    sweep,
    wear_life,
    wear_life_map,
    wear_life_report,
    wear_life_section,
    wear_profile_section,
)

_foundation = ["__version__"]
_scenes = [
    "Scene",
    "SceneError",
    "list_scenes",
    "load_scene",
    "save_scene",
    "scene_from_json",
]
_simulation = [
    "FullRecord",
    "MetricsRecord",
    "RecordMode",
    "SectionsRecord",
    "SimulationError",
    "SimulationWarning",
    "WearRecord",
    "simulate",
]
_contact_wear = [
    "WearComparison",
    "WearLife",
    "WearLifeMap",
    "WearLifeSettings",
    "WearPrediction",
    "WearPredictionError",
    "WornProfile",
    "archard_wear",
    "compare_wear",
    "contact_stiffness",
    "hertz_stiffness",
    "plot_wear_life",
    "plot_wear_profile",
    "predict_wear",
    "wear_life",
    "wear_life_map",
    "wear_life_report",
    "wear_life_section",
    "wear_profile_section",
]
_flexibility = [
    "AncfMesh",
    "BeamModes",
    "BeamStaticSolution",
    "ElementConvergence",
    "beam_modes",
    "element_convergence",
    "euler_bernoulli_frequencies",
    "solve_beam_static",
]
_sweeps = [
    "Analysis",
    "GridTransform",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "chaos_map",
    "grid_transforms",
    "load_sweep",
    "register_grid_transform",
    "stroboscopic_points",
    "sweep",
]
_bifurcations = ["BifurcationSettings", "bifurcation", "plot_bifurcation"]
_paper_study = ["PaperStudy", "StudySettings", "paper_claims", "paper_tables", "run_paper_study"]
_chaos = [
    "LyapunovSettings",
    "PeriodicOrbit",
    "SceneLyapunov",
    "lyapunov_exponent",
    "periodic_orbit",
    "Basins",
    "basins",
    "plot_basins",
]
_routes_to_chaos = [
    "BifurcationPoint",
    "Continuation",
    "ContinuationBranch",
    "ContinuationPoint",
    "ContinuationSettings",
    "RouteToChaos",
    "continuation",
    "continue_map",
    "regular_stretches",
    "route",
]

__all__ = (
    _foundation
    + _scenes
    + _simulation
    + _contact_wear
    + _flexibility
    + _sweeps
    + _bifurcations
    + _paper_study
    + _chaos
    + _routes_to_chaos
)
