"""Recurrence plots and recurrence quantification analysis (RQA)."""

from __future__ import annotations

from ._rqa import RecurrenceResult, recurrence_analysis

__all__ = ["RecurrenceResult", "recurrence_analysis"]
