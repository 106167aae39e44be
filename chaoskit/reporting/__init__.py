"""Reporting: analyses, figures and tables of one or more trajectories as HTML and Markdown.

:func:`report` analyses each trajectory (one state each, e.g. before and after wear),
draws the figures with :mod:`chaoskit.plot` and assembles a frozen :class:`Report` of
captioned tables (pandas DataFrames) and figures (PNG bytes), with whatever tables, sweep
maps and bifurcation diagrams the caller adds. A :class:`Report` is a list of
:class:`ReportSection` objects that any caller can assemble or extend
(:meth:`Report.with_sections`); :meth:`Report.write` writes a self-contained HTML page and
its Markdown twin (every string in it escaped as text: :func:`markdown_text`).
:func:`answer_table` and :meth:`Report.answer_table` give the answer, one row per state, and
:func:`decided_by` says in one line which evidence decided a verdict. See
``docs/reports.md``.

The subpackage is ``chaoskit.reporting``; its main names are re-exported from ``chaoskit``
(``chaoskit.report`` is the function).
"""

from __future__ import annotations

from ._answer import (
    CONFIDENCE_FORMAT,
    CONFIDENCE_NOTE,
    answer_table,
    decided_by,
    format_confidence,
    plural,
)
from ._build import CHAOS_COLUMNS, Report, SweepMap, VariableSpec, parse_variable, report
from ._items import MISSING, ReportCode, ReportFigure, ReportSection, ReportTable, format_number
from ._render import markdown_text

__all__ = [
    "CHAOS_COLUMNS",
    "CONFIDENCE_FORMAT",
    "CONFIDENCE_NOTE",
    "MISSING",
    "Report",
    "ReportCode",
    "ReportFigure",
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
