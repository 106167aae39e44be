"""Correlation sum and correlation dimension D2 (Grassberger–Procaccia)."""

from __future__ import annotations

from ._correlation import CorrelationDimensionResult, correlation_dimension

__all__ = ["CorrelationDimensionResult", "correlation_dimension"]
