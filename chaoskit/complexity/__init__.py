"""Complexity measures computed by nolds behind chaoskit's validation and result objects."""

from __future__ import annotations

from ._nolds import (
    MAX_SAMPLES,
    ComplexityResult,
    detrended_fluctuation,
    hurst_exponent,
    sample_entropy,
)

__all__ = [
    "MAX_SAMPLES",
    "ComplexityResult",
    "detrended_fluctuation",
    "hurst_exponent",
    "sample_entropy",
]
