"""The verdict and its evidence: 0–1 test, IAAFT and cycle surrogates, sections, classify.

The subpackage is ``chaoskit.verdict``; every name is re-exported from ``chaoskit``
(``chaoskit.classify`` is the function that returns a :class:`Verdict`).
"""

from __future__ import annotations

# for the command line and the report, not part of the public API
from ._analyze import analyze, classify_variables, series_dataset, verdict_table
from ._classify import classify
from ._combine import RuleEvidence, RuleOutcome, combine
from ._cycles import (
    CycleForecast,
    cycle_boundaries,
    cycle_shuffled_surrogates,
    cycle_spread,
    cycle_surrogate_test,
    twin_surrogates,
)
from ._motion_classify import classify_motion
from ._motion_result import MotionVerdict
from ._orbit import PeriodicOrbitEvidence
from ._result import Verdict
from ._rng import as_generator
from ._rule import LABELS, VerdictRule
from ._section_structure import SectionStructure, section_structure
from ._surrogates import SurrogateResult, iaaft_surrogates, prediction_error, surrogate_test
from ._zero_one import ZeroOneResult, zero_one_test

__all__ = [
    "LABELS",
    "CycleForecast",
    "MotionVerdict",
    "PeriodicOrbitEvidence",
    "RuleEvidence",
    "RuleOutcome",
    "SectionStructure",
    "SurrogateResult",
    "Verdict",
    "VerdictRule",
    "ZeroOneResult",
    "analyze",
    "classify",
    "classify_motion",
    "classify_variables",
    "combine",
    "cycle_boundaries",
    "cycle_shuffled_surrogates",
    "cycle_spread",
    "cycle_surrogate_test",
    "iaaft_surrogates",
    "prediction_error",
    "section_structure",
    "surrogate_test",
    "twin_surrogates",
    "verdict_table",
    "zero_one_test",
]
