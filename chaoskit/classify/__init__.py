"""The verdict and its evidence: 0–1 test, IAAFT surrogates, section structure, classify.

Note that the top-level name ``chaoskit.classify`` is the function; import the other names
from ``chaoskit`` directly (they are all re-exported there).
"""

from __future__ import annotations

from ._analyze import analyze, classify_variables, verdict_table
from ._clusters import SectionStructure, section_structure
from ._surrogates import SurrogateResult, iaaft_surrogates, prediction_error, surrogate_test
from ._verdict import LABELS, Verdict, VerdictRule, classify
from ._zero_one import ZeroOneResult, zero_one_test

__all__ = [
    "LABELS",
    "SectionStructure",
    "SurrogateResult",
    "Verdict",
    "VerdictRule",
    "ZeroOneResult",
    "analyze",
    "classify",
    "classify_variables",
    "iaaft_surrogates",
    "prediction_error",
    "section_structure",
    "surrogate_test",
    "verdict_table",
    "zero_one_test",
]
