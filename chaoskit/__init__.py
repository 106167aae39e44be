"""chaoskit — decide from a trajectory whether motion is periodic, quasi-periodic or chaotic.

The public API is re-exported here; everything in ``_``-prefixed modules is private.
``chaoskit`` never imports ``mechanism``.
"""

from __future__ import annotations

from ._jit_cache import refresh_jit_cache

# before any kernel is compiled or loaded: cached kernels compiled from other sources go
refresh_jit_cache(__file__)

# subpackages reachable as attributes (not names of __all__): the contract helpers a front end
# shares, reference systems, and the figures
from . import contract as contract
from . import plot as plot
from . import systems as systems
from ._contract import sampling_interval, validate_trajectory
from ._io import load_trajectory, save_trajectory
from ._orbit_diagram import bifurcation_diagram
from ._portraits import phase_portrait
from ._samples import sample_path
from ._selection import select_series
from ._version import __version__
from .complexity import (
    ComplexityResult,
    detrended_fluctuation,
    hurst_exponent,
    sample_entropy,
)
from .denoise import DenoiseResult, local_projective_denoise
from .dimension import CorrelationDimensionResult, correlation_dimension
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
    LyapunovSpectrumResult,
    lyapunov_kantz,
    lyapunov_rosenstein,
    lyapunov_spectrum,
    lyapunov_wolf,
)
from .recurrence import RecurrenceResult, recurrence_analysis
from .reporting import (
    Report,
    ReportExtras,
    ReportFigure,
    ReportOptions,
    ReportSection,
    ReportTable,
    SweepMap,
    report,
)
from .sections import poincare_section, stroboscopic_map
from .verdict import (
    CycleForecast,
    MotionVerdict,
    PeriodicOrbitEvidence,
    RuleEvidence,
    RuleOutcome,
    SectionStructure,
    SurrogateResult,
    Verdict,
    VerdictRule,
    ZeroOneResult,
    analyze,
    classify,
    classify_motion,
    classify_variables,
    combine,
    cycle_boundaries,
    cycle_shuffled_surrogates,
    cycle_spread,
    cycle_surrogate_test,
    iaaft_surrogates,
    section_structure,
    surrogate_test,
    twin_surrogates,
    verdict_table,
    zero_one_test,
)

# The public names, grouped by what they are for (docs/reference/chaoskit.md has the same
# groups), hence not sorted.
__all__ = [  # noqa: RUF022
    # trajectories
    "__version__",
    "load_trajectory",
    "save_trajectory",
    "validate_trajectory",
    "sampling_interval",
    "select_series",
    "sample_path",
    # delay embedding
    "mutual_information",
    "autocorrelation",
    "estimate_delay",
    "DelayCurve",
    "DelayResult",
    "false_nearest_neighbors",
    "cao",
    "estimate_embedding_dim",
    "DimensionResult",
    "delay_embed",
    # lyapunov exponents
    "lyapunov_rosenstein",
    "lyapunov_kantz",
    "lyapunov_wolf",
    "LyapunovResult",
    "KantzResult",
    "lyapunov_spectrum",
    "LyapunovSpectrumResult",
    # sections and portraits
    "poincare_section",
    "stroboscopic_map",
    "section_structure",
    "SectionStructure",
    "phase_portrait",
    "bifurcation_diagram",
    # tests for chaos
    "zero_one_test",
    "ZeroOneResult",
    "iaaft_surrogates",
    "surrogate_test",
    "SurrogateResult",
    "cycle_boundaries",
    "cycle_shuffled_surrogates",
    "twin_surrogates",
    "cycle_surrogate_test",
    "CycleForecast",
    "cycle_spread",
    # the verdict
    "classify",
    "Verdict",
    "VerdictRule",
    "RuleEvidence",
    "combine",
    "RuleOutcome",
    "classify_motion",
    "MotionVerdict",
    "PeriodicOrbitEvidence",
    "classify_variables",
    "verdict_table",
    "analyze",
    # noise reduction
    "local_projective_denoise",
    "DenoiseResult",
    # reports
    "report",
    "Report",
    "ReportExtras",
    "ReportOptions",
    "ReportSection",
    "ReportTable",
    "ReportFigure",
    "SweepMap",
    # measures
    "correlation_dimension",
    "CorrelationDimensionResult",
    "recurrence_analysis",
    "RecurrenceResult",
    "sample_entropy",
    "detrended_fluctuation",
    "hurst_exponent",
    "ComplexityResult",
]
