"""The verdict and its evidence: 0–1 test, IAAFT surrogates, section structure, classify.

The subpackage is ``chaoskit.verdict``; every name is re-exported from ``chaoskit``
(``chaoskit.classify`` is the function that returns a :class:`Verdict`).
"""

from __future__ import annotations

from ._analyze import analyze, classify_variables, verdict_table
from ._clusters import SectionStructure, section_structure
from ._motion import MotionVerdict, classify_motion
from ._surrogates import SurrogateResult, iaaft_surrogates, prediction_error, surrogate_test
from ._verdict import LABELS, Verdict, VerdictRule, classify
from ._zero_one import ZeroOneResult, zero_one_test

__all__ = [
    "LABELS",
    "MotionVerdict",
    "SectionStructure",
    "SurrogateResult",
    "Verdict",
    "VerdictRule",
    "ZeroOneResult",
    "analyze",
    "classify",
    "classify_motion",
    "classify_variables",
    "iaaft_surrogates",
    "prediction_error",
    "section_structure",
    "surrogate_test",
    "verdict_table",
    "zero_one_test",
]
