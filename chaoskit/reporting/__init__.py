"""Reporting: analyses, figures and tables of one or more trajectories as HTML and Markdown.

:func:`report` analyses each trajectory (one state each, e.g. before and after wear),
draws the figures with :mod:`chaoskit.plot` and assembles a frozen :class:`Report` of
captioned tables (pandas DataFrames) and figures (PNG bytes), with whatever tables, sweep
maps and bifurcation diagrams the caller adds. A :class:`Report` is a list of
:class:`ReportSection` objects that any caller can assemble or extend
(:meth:`Report.with_sections`); :meth:`Report.write` writes a self-contained HTML page and
its Markdown twin. See ``docs/reports.md``.

The subpackage is ``chaoskit.reporting``; its main names are re-exported from ``chaoskit``
(``chaoskit.report`` is the function).
"""

from __future__ import annotations

from ._build import CHAOS_COLUMNS, Report, SweepMap, VariableSpec, parse_variable, report
from ._items import MISSING, ReportCode, ReportFigure, ReportSection, ReportTable, format_number

__all__ = [
    "CHAOS_COLUMNS",
    "MISSING",
    "Report",
    "ReportCode",
    "ReportFigure",
    "ReportSection",
    "ReportTable",
    "SweepMap",
    "VariableSpec",
    "format_number",
    "parse_variable",
    "report",
]
