"""Studies built on the simulator core: sweeps and their store, bifurcation diagrams, the
largest Lyapunov exponent of a scene, wear prediction, element convergence, wear-profile
figures and report sections, and the paper study.

Everything here uses :mod:`mechanism.core`'s public names.
"""

from __future__ import annotations

from ._bifurcation import bifurcation
from ._convergence import ElementConvergence, element_convergence
from ._lyapunov import SceneLyapunov, lyapunov_exponent
from ._paper import PaperStudy, StudySettings, paper_claims, paper_tables, run_paper_study
from ._plot import plot_bifurcation
from ._sweep import (
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
from ._wear_prediction import (
    WearComparison,
    WearPrediction,
    WearPredictionError,
    compare_wear,
    predict_wear,
)
from ._wear_report import plot_wear_profile, wear_profile_section

__all__ = [
    "Analysis",
    "ElementConvergence",
    "GridTransform",
    "PaperStudy",
    "SceneLyapunov",
    "StudySettings",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "WearComparison",
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
    "plot_bifurcation",
    "plot_wear_profile",
    "predict_wear",
    "register_grid_transform",
    "run_paper_study",
    "stroboscopic_points",
    "sweep",
    "wear_profile_section",
]
