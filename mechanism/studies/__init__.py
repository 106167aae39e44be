"""Studies built on the simulator core: sweeps and their store, bifurcation diagrams, the
largest Lyapunov exponent of a scene, periodic orbits and their multipliers, wear prediction
and the wear life, element convergence, wear-profile figures and report sections, and the
paper study.

Everything here uses :mod:`mechanism.core`'s public names. The sweeps
(:mod:`mechanism.studies.sweep`) and the paper study (:mod:`mechanism.studies.paper`) are
packages of one concern per module.
"""

from __future__ import annotations

from ._convergence import ElementConvergence, element_convergence
from ._lyapunov import (
    DEFAULT_DEVIATION_RTOL,
    LyapunovSettings,
    SceneLyapunov,
    lyapunov_exponent,
)
from ._orbit_diagram import BifurcationSettings, bifurcation, parse_values
from ._plot import plot_bifurcation
from ._wear_compare import WearComparison, compare_wear
from ._wear_life import (
    DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS,
    WearLife,
    WearLifeSettings,
    wear_life,
)
from ._wear_life_map import WearLifeMap, wear_life_map
from ._wear_life_plot import plot_wear_life
from ._wear_life_report import wear_life_report, wear_life_section
from ._wear_prediction import predict_wear
from ._wear_report import plot_wear_profile, wear_profile_section
from ._wear_result import WearPrediction, WearPredictionError
from ._wear_settings import DEFAULT_MAX_DEPTH_INCREMENT
from .orbits import (
    Basins,
    BifurcationPoint,
    ContactPhase,
    Continuation,
    ContinuationBranch,
    ContinuationPoint,
    ContinuationSettings,
    PeriodicOrbit,
    RouteToChaos,
    basins,
    continuation,
    continue_map,
    periodic_orbit,
    plot_basins,
    regular_stretches,
    route,
)
from .paper import PaperStudy, StudySettings, paper_claims, paper_tables, run_paper_study
from .sweep import (
    Analysis,
    GridTransform,
    SweepStoreBusy,
    SweepStoreMismatch,
    chaos_map,
    dask_client,
    grid_transforms,
    load_sweep,
    register_grid_transform,
    stroboscopic_points,
    sweep,
)

__all__ = [
    "DEFAULT_DEVIATION_RTOL",
    "DEFAULT_MAX_DEPTH_INCREMENT",
    "DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS",
    "Analysis",
    "Basins",
    "BifurcationPoint",
    "BifurcationSettings",
    "ContactPhase",
    "Continuation",
    "ContinuationBranch",
    "ContinuationPoint",
    "ContinuationSettings",
    "ElementConvergence",
    "GridTransform",
    "LyapunovSettings",
    "PaperStudy",
    "PeriodicOrbit",
    "RouteToChaos",
    "SceneLyapunov",
    "StudySettings",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "WearComparison",
    "WearLife",
    "WearLifeMap",
    "WearLifeSettings",
    "WearPrediction",
    "WearPredictionError",
    "basins",
    "bifurcation",
    "chaos_map",
    "compare_wear",
    "continuation",
    "continue_map",
    "dask_client",
    "element_convergence",
    "grid_transforms",
    "load_sweep",
    "lyapunov_exponent",
    "paper_claims",
    "paper_tables",
    "parse_values",
    "periodic_orbit",
    "plot_basins",
    "plot_bifurcation",
    "plot_wear_life",
    "plot_wear_profile",
    "predict_wear",
    "register_grid_transform",
    "regular_stretches",
    "route",
    "run_paper_study",
    "stroboscopic_points",
    "sweep",
    "wear_life",
    "wear_life_map",
    "wear_life_report",
    "wear_life_section",
    "wear_profile_section",
]
