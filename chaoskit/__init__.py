"""chaoskit — decide from a trajectory whether motion is periodic, quasi-periodic or chaotic.

The public API is re-exported here; everything in ``_``-prefixed modules is private.
``chaoskit`` never imports ``mechanism``.
"""

from __future__ import annotations

from ._jit_cache import refresh_jit_cache

# before any kernel is compiled or loaded: cached kernels compiled from other sources go
refresh_jit_cache(__file__)

from . import contract, systems
from ._contract import sampling_interval, validate_trajectory
from ._io import load_trajectory, save_trajectory
from ._samples import sample_path
from ._selection import select_series
from ._version import __version__

_foundation = [
    "__version__",
    "contract",
    "load_trajectory",
    "sample_path",
    "sampling_interval",
    "save_trajectory",
    "select_series",
    "systems",
    "validate_trajectory",
]

# --- estimators ---
from .embedding import (
    DelayCurve,
    DelayResult,
    DimensionResult,
    autocorrelation,
    cao,
    delay_embed,
    estimate_delay,
    estimate_embedding_dim,
    false_nearest_neighbors,
    mutual_information,
)
from .lyapunov import (
    KantzResult,
    LyapunovResult,
    lyapunov_kantz,
    lyapunov_rosenstein,
    lyapunov_wolf,
)

_estimators: list[str] = [
    "DelayCurve",
    "DelayResult",
    "DimensionResult",
    "KantzResult",
    "LyapunovResult",
    "autocorrelation",
    "cao",
    "delay_embed",
    "estimate_delay",
    "estimate_embedding_dim",
    "false_nearest_neighbors",
    "lyapunov_kantz",
    "lyapunov_rosenstein",
    "lyapunov_wolf",
    "mutual_information",
]

# --- views and verdict ---
from . import plot
from ._bifurcation import bifurcation_diagram
from ._portraits import phase_portrait
from .sections import poincare_section, stroboscopic_map
from .verdict import (
    MotionVerdict,
    SectionStructure,
    SurrogateResult,
    Verdict,
    VerdictRule,
    ZeroOneResult,
    analyze,
    classify,
    classify_motion,
    classify_variables,
    iaaft_surrogates,
    section_structure,
    surrogate_test,
    verdict_table,
    zero_one_test,
)

_views: list[str] = [
    "MotionVerdict",
    "SectionStructure",
    "SurrogateResult",
    "Verdict",
    "VerdictRule",
    "ZeroOneResult",
    "analyze",
    "bifurcation_diagram",
    "classify",
    "classify_motion",
    "classify_variables",
    "iaaft_surrogates",
    "phase_portrait",
    "plot",
    "poincare_section",
    "section_structure",
    "stroboscopic_map",
    "surrogate_test",
    "verdict_table",
    "zero_one_test",
]

# --- report ---
from .reporting import (
    Report,
    ReportFigure,
    ReportSection,
    ReportTable,
    SweepMap,
    report,
)

_report: list[str] = [
    "Report",
    "ReportFigure",
    "ReportSection",
    "ReportTable",
    "SweepMap",
    "report",
]

# --- measures toolbox ---
from .complexity import (
    ComplexityResult,
    detrended_fluctuation,
    hurst_exponent,
    sample_entropy,
)
from .dimension import CorrelationDimensionResult, correlation_dimension
from .lyapunov import LyapunovSpectrumResult, lyapunov_spectrum
from .recurrence import RecurrenceResult, recurrence_analysis

_measures: list[str] = [
    "ComplexityResult",
    "CorrelationDimensionResult",
    "LyapunovSpectrumResult",
    "RecurrenceResult",
    "correlation_dimension",
    "detrended_fluctuation",
    "hurst_exponent",
    "lyapunov_spectrum",
    "recurrence_analysis",
    "sample_entropy",
]

__all__ = _foundation + _estimators + _views + _report + _measures
