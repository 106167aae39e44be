"""Studies built on the simulator core: sweeps and their store, wear prediction, element
convergence, the paper study and the largest Lyapunov exponent of a scene. Everything here
uses :mod:`mechanism.core`'s public names.
"""

from __future__ import annotations

from ._convergence import ElementConvergence, element_convergence
from ._lyapunov import SceneLyapunov, lyapunov_exponent
from ._paper import PaperStudy, StudySettings, paper_tables, run_paper_study
from ._sweep import (
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
from ._wear_prediction import Comparison, WearPrediction, compare, predict_wear

__all__ = [
    "Analysis",
    "Comparison",
    "ElementConvergence",
    "GridTransform",
    "PaperStudy",
    "SceneLyapunov",
    "StudySettings",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "WearPrediction",
    "chaos_map",
    "compare",
    "element_convergence",
    "grid_transforms",
    "load_sweep",
    "lyapunov_exponent",
    "paper_tables",
    "predict_wear",
    "register_grid_transform",
    "run_paper_study",
    "stroboscopic_points",
    "sweep",
]
