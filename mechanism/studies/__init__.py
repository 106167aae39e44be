"""Studies built on the simulator core: sweeps and their store, bifurcation diagrams, the
largest Lyapunov exponent of a scene, periodic orbits and their multipliers, wear prediction
and the wear life, element convergence, wear-profile figures and report sections, and the
paper study.

Everything here uses :mod:`mechanism.core`'s public names. The sweeps
(:mod:`mechanism.studies.sweep`) and the paper study (:mod:`mechanism.studies.paper`) are
packages of one concern per module.
"""

from __future__ import annotations

from ._bifurcation import BifurcationSettings, bifurcation, parse_values
from ._convergence import ElementConvergence, element_convergence
from ._lyapunov import (
    DEFAULT_DEVIATION_RTOL,
    LyapunovSettings,
    SceneLyapunov,
    lyapunov_exponent,
)
from ._plot import plot_bifurcation
from ._wear_life import (
    DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS,
    WearLife,
    WearLifeSettings,
    wear_life,
)
from ._wear_prediction import (
    DEFAULT_MAX_DEPTH_INCREMENT,
    WearComparison,
    WearPrediction,
    WearPredictionError,
    compare_wear,
    predict_wear,
)
from ._wear_report import plot_wear_profile, wear_profile_section
from .orbits import ContactPhase, PeriodicOrbit, periodic_orbit
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
    "BifurcationSettings",
    "ContactPhase",
    "ElementConvergence",
    "GridTransform",
    "LyapunovSettings",
    "PaperStudy",
    "PeriodicOrbit",
    "SceneLyapunov",
    "StudySettings",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "WearComparison",
    "WearLife",
    "WearLifeSettings",
    "WearPrediction",
    "WearPredictionError",
    "bifurcation",
    "chaos_map",
    "compare_wear",
    "dask_client",
    "element_convergence",
    "grid_transforms",
    "load_sweep",
    "lyapunov_exponent",
    "paper_claims",
    "paper_tables",
    "parse_values",
    "periodic_orbit",
    "plot_bifurcation",
    "plot_wear_profile",
    "predict_wear",
    "register_grid_transform",
    "run_paper_study",
    "stroboscopic_points",
    "sweep",
    "wear_life",
    "wear_profile_section",
]
