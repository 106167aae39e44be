"""mechanism — a planar multibody simulator for rigid-flexible mechanisms with clearance and wear.

Scenes are data (TOML); trajectories are :class:`xarray.Dataset` objects following the
chaoskit data contract (``docs/data-model.md``).
"""

from __future__ import annotations

from chaoskit.contract import __version__

_foundation = ["__version__"]

# --- scenes (issue 5, scene loading): add imports and names below this line only ---
from .core import scene  # noqa: E402
from .core.scene import (  # noqa: E402
    Scene,
    SceneError,
    list_scenes,
    load_scene,
    save_scene,
    scene_from_json,
)

_scenes: list[str] = [
    "Scene",
    "SceneError",
    "list_scenes",
    "load_scene",
    "save_scene",
    "scene",
    "scene_from_json",
]

# --- simulation (issue 5, core): add imports and names below this line only ---
from .core import (  # noqa: E402
    SimulationError,
    integrate,
    simulate,
)

_simulation: list[str] = ["SimulationError", "integrate", "simulate"]

# --- contact and wear (issues 5 and 7): add imports and names below this line only ---
from .core import WornProfile, archard_wear, contact_stiffness, hertz_stiffness  # noqa: E402  # noqa: E402
from .studies import (  # noqa: E402
    Comparison,
    WearPrediction,
    compare,
    plot_wear_profile,
    predict_wear,
    wear_profile_section,
)

_contact_wear: list[str] = [
    "Comparison",
    "WearPrediction",
    "WornProfile",
    "archard_wear",
    "compare",
    "contact_stiffness",
    "hertz_stiffness",
    "plot_wear_profile",
    "predict_wear",
    "wear_profile_section",
]

# --- flexibility (issue 6): add imports and names below this line only ---
from .core import (  # noqa: E402
    AncfMesh,
    BeamModes,
    BeamStaticSolution,
    beam_modes,
    euler_bernoulli_frequencies,
    solve_beam_static,
)
from .studies import ElementConvergence, element_convergence  # noqa: E402

_flexibility: list[str] = [
    "AncfMesh",
    "BeamModes",
    "BeamStaticSolution",
    "ElementConvergence",
    "beam_modes",
    "element_convergence",
    "euler_bernoulli_frequencies",
    "solve_beam_static",
]

# --- sweeps (issue 8): add imports and names below this line only ---
from .studies import (  # noqa: E402
    Analysis,
    GridTransform,
    SweepStoreBusy,
    SweepStoreMismatch,
    chaos_map,
    grid_transforms,
    load_sweep,
    register_grid_transform,
    stroboscopic_points,
    sweep,
)

_sweeps: list[str] = [
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

# --- bifurcation diagrams: add imports and names below this line only ---
from .studies import bifurcation, plot_bifurcation  # noqa: E402

_bifurcations: list[str] = ["bifurcation", "plot_bifurcation"]

# --- paper study (issue 8): add imports and names below this line only ---
from .studies import (  # noqa: E402
    PaperStudy,
    StudySettings,
    paper_claims,
    paper_tables,
    run_paper_study,
)

_paper_study: list[str] = [
    "PaperStudy",
    "StudySettings",
    "paper_claims",
    "paper_tables",
    "run_paper_study",
]

# --- chaos from the equations (issue 16): add imports and names below this line only ---
from .studies import SceneLyapunov, lyapunov_exponent  # noqa: E402

_chaos: list[str] = ["SceneLyapunov", "lyapunov_exponent"]

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
)
