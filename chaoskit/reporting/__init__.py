"""Reporting: analyses, figures and tables of one or more trajectories as HTML and Markdown.

:func:`report` analyses each trajectory (one state each, e.g. before and after wear),
draws the figures with :mod:`chaoskit.plot` and assembles a frozen :class:`Report` of
captioned tables (pandas DataFrames) and figures (PNG bytes), with whatever tables, sweep
maps and bifurcation diagrams the caller adds. A :class:`Report` is a list of
:class:`ReportSection` objects that any caller can assemble or extend
(:meth:`Report.with_sections`); :meth:`Report.write` writes a self-contained HTML page and
its Markdown twin (every string in it escaped as text: :func:`markdown_text`).
:func:`answer_table` and :meth:`Report.answer_table` give the answer, one row per state, and
:func:`decided_by` says in one line which evidence decided a verdict.
:class:`ReportExtras` (what a caller adds) and :class:`ReportOptions` (finer settings) group
the arguments of :func:`report`. See ``docs/reports.md``.

The subpackage is ``chaoskit.reporting``; its main names are re-exported from ``chaoskit``
(``chaoskit.report`` is the function).
"""

from __future__ import annotations

from .._selection import VariableSpec, parse_variable
from ._analysis_tables import CHAOS_COLUMNS
from ._answer import (
    CONFIDENCE_FORMAT,
    CONFIDENCE_NOTE,
    answer_table,
    decided_by,
    format_confidence,
    plural,
)
from ._assembly import report
from ._content import MISSING, ReportCode, ReportFigure, ReportSection, ReportTable, format_number
from ._model import Report, SweepMap
from ._options import ReportExtras, ReportOptions
from ._writer import markdown_text

__all__ = [
    "CHAOS_COLUMNS",
    "CONFIDENCE_FORMAT",
    "CONFIDENCE_NOTE",
    "MISSING",
    "Report",
    "ReportCode",
    "ReportExtras",
    "ReportFigure",
    "ReportOptions",
    "ReportSection",
    "ReportTable",
    "SweepMap",
    "VariableSpec",
    "answer_table",
    "decided_by",
    "format_confidence",
    "format_number",
    "markdown_text",
    "parse_variable",
    "plural",
    "report",
]
