"""The report model: the frozen result types :class:`Report` and :class:`SweepMap`.

A :class:`Report` is an ordered list of :class:`ReportSection` objects (tables, figures,
code) with the analysis behind them; :class:`SweepMap` is the caller's request for a map
of the exponent and the verdict over two swept parameters. Both sit below everything that
builds them (:func:`chaoskit.report`); the output methods of :class:`Report` call the
writer, which knows nothing of this module.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import pandas as pd
import xarray as xr

from ..verdict import MotionVerdict
from ._answer import answer_table
from ._content import ReportFigure, ReportSection, ReportTable
from ._writer import figure_filename, render_html, render_markdown, write_report

__all__ = ["APPENDIX", "MOTION", "PROVENANCE", "SECTION_ORDER", "Report", "SweepMap", "now"]

#: Section headings in the order they appear; other sections named by the caller's tables
#: and figures come after "Sweeps", and the provenance always last.
MOTION = "Motion verdict"
SECTION_ORDER = (
    MOTION,
    "Verdicts",
    "Response metrics",
    "Chaos identification",
    "Phase portraits",
    "Poincaré and stroboscopic maps",
    "Divergence curves",
    "Sweeps",
)
PROVENANCE = "Parameters and provenance"
#: The evidence behind the verdicts: after the results, before the provenance.
APPENDIX = "Appendix: evidence behind the verdicts"


def now() -> str:
    """The current UTC time, ISO 8601, to the second."""
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()


# ----------------------------------------------------------------- sweeps


@dataclass(frozen=True, kw_only=True, eq=False)
class SweepMap:
    """A map of the largest Lyapunov exponent and the verdict over two swept parameters.

    Parameters
    ----------
    data
        A sweep Dataset (grid dimensions, a ``variable`` dimension for the analysis fields,
        e.g. ``mle_rosenstein`` and ``label``, and ``status``) or an already reduced 2-D map
        (``mle(y, x)``, ``verdict(y, x)``).
    x, y
        Grid dimensions along the horizontal and vertical axes.
    select
        Values of the other grid dimensions (e.g. ``{"wear": "before"}``).
    variable
        Analysed variable (default: the motion verdict of each point, ``motion_label`` with
        the mixed-embedding exponent ``motion_mle``, when the sweep has it; else the first
        along ``variable``).
    mle, verdict
        Field names (default: as above, or ``mle`` or the first numeric field whose name
        starts with ``mle``; ``verdict`` or ``label``).
    caption
        Figure caption (default: generated).
    """

    data: xr.Dataset
    x: str
    y: str
    select: Mapping[str, Any] = field(default_factory=dict)
    variable: str | None = None
    mle: str | None = None
    verdict: str | None = None
    caption: str | None = None

    def to_map(self) -> xr.Dataset:
        """``mle(y, x)``, ``verdict(y, x)`` and, if the sweep has it, ``status(y, x)``."""
        ds = self.data
        if not isinstance(ds, xr.Dataset):
            raise ValueError(f"SweepMap.data must be an xarray.Dataset; got {type(ds).__name__}.")
        variable = self.variable
        motion = variable is None and self.verdict is None and "motion_label" in ds
        if motion:
            ds = ds[[k for k, v in ds.data_vars.items() if "variable" not in v.dims]]
            variable = "motion"
        if "variable" in ds.dims:
            names = [str(v) for v in ds["variable"].values]
            variable = variable if variable is not None else names[0]
            if variable not in names:
                raise ValueError(f"variable {variable!r} not in the sweep's variables {names}.")
            ds = ds.sel(variable=variable)
        mle = "motion_mle" if motion and self.mle is None else self.mle
        if mle is None:
            numeric = [
                str(k)
                for k, v in ds.data_vars.items()
                if str(k).lower().startswith("mle") and v.dtype.kind in "fiu"
            ]
            mle = "mle" if "mle" in numeric else (numeric[0] if numeric else None)
        if mle is None or mle not in ds.data_vars:
            raise ValueError(f"no exponent field {mle!r}; fields: {list(ds.data_vars)}.")
        verdict = self.verdict or next(
            (v for v in ("verdict", "label", "motion_label") if v in ds), None
        )
        dims = [str(d) for d in ds[mle].dims]
        for key in (self.x, self.y):
            if key not in dims:
                raise ValueError(f"{key!r} is not a dimension of {mle!r}; dims {dims}.")
        if self.x == self.y:
            raise ValueError("x and y must be two different dimensions.")
        others = [d for d in dims if d not in (self.x, self.y)]
        missing = [d for d in others if d not in self.select]
        if missing:
            raise ValueError(f"select a value for the other grid dimensions {missing}.")
        pick = {d: self.select[d] for d in others}
        fields = {"mle": mle}
        if verdict is not None:
            fields["verdict"] = verdict
        if "status" in ds.data_vars:
            fields["status"] = "status"
        out = xr.Dataset({k: ds[v].sel(pick).transpose(self.y, self.x) for k, v in fields.items()})
        out = out.drop_vars([c for c in out.coords if c not in (self.x, self.y)])
        out.attrs = {
            "variable": "" if variable is None else str(variable),
            "mle_field": mle,
            "select": json.dumps({k: _plain(v) for k, v in pick.items()}),
        }
        return out


def _plain(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return value


# ----------------------------------------------------------------- the report


@dataclass(frozen=True, kw_only=True, eq=False)
class Report:
    """A report: ordered sections of captioned tables (pandas), figures (PNG) and text.

    Any caller can assemble one from :class:`ReportSection` objects; tables and figures are
    numbered in print order (and told their section) when the report is made, so sections
    built separately combine into one consistent document. :func:`report` builds the
    analysis sections; :meth:`with_sections` adds a caller's own.

    Attributes
    ----------
    title
        Heading of the page.
    sections
        :class:`ReportSection` objects in print order (:func:`report` puts the provenance
        last).
    created
        ISO 8601 UTC time of assembly (default: now).
    analysis
        The scalar analysis rows (:func:`chaoskit.analyze` fields) over ``(state,
        variable)``, or None when no trajectory was analysed.
    verdicts
        ``{state: {variable: Verdict}}`` with all evidence (curves, section points).
    motions
        ``{state: MotionVerdict}``: one verdict per state from all its analysed variables
        (states analysed through a single variable have none).
    """

    title: str
    sections: tuple[ReportSection, ...]
    created: str = field(default_factory=now)
    analysis: xr.Dataset | None = None
    verdicts: Mapping[str, Mapping[str, Any]] = field(default_factory=dict, repr=False)
    motions: Mapping[str, MotionVerdict] = field(default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        numbered: list[ReportSection] = []
        n_table = n_figure = 0
        for section in self.sections:
            if not isinstance(section, ReportSection):
                raise ValueError(
                    f"sections must hold ReportSection objects; got {type(section).__name__}."
                )
            items = []
            for item in section.items:
                if isinstance(item, ReportTable):
                    n_table += 1
                    item = dataclasses.replace(item, number=n_table, section=section.title)
                elif isinstance(item, ReportFigure):
                    n_figure += 1
                    item = dataclasses.replace(item, number=n_figure, section=section.title)
                items.append(item)
            numbered.append(dataclasses.replace(section, items=tuple(items)))
        object.__setattr__(self, "sections", tuple(numbered))

    def with_sections(
        self, *sections: ReportSection, before: str | None = None, after: str | None = None
    ) -> Report:
        """A copy with ``sections`` inserted before the section titled ``before`` or after
        the one titled ``after``.

        When neither names a section of this report, they go before the appendix and the
        provenance section of :func:`report`, or last if there are none. Tables and figures
        are renumbered.

        Examples
        --------
        >>> import pandas as pd, chaoskit
        >>> rep = chaoskit.Report(title="demo", sections=())
        >>> notes = chaoskit.ReportSection(title="Notes", items=(), text="measured")
        >>> table = chaoskit.ReportTable(caption="A table", data=pd.DataFrame({"x": [1.0]}))
        >>> extra = chaoskit.ReportSection(title="Results", items=(table,))
        >>> rep = rep.with_sections(notes).with_sections(extra, before="Notes")
        >>> [s.title for s in rep.sections], rep.tables[0].number
        (['Results', 'Notes'], 1)
        """
        titles = [s.title for s in self.sections]
        if before in titles:
            at = titles.index(before)
        elif after in titles:
            at = titles.index(after) + 1
        else:
            tail = [k for k, t in enumerate(titles) if t in (APPENDIX, PROVENANCE)]
            at = tail[0] if tail else len(titles)
        merged = (*self.sections[:at], *sections, *self.sections[at:])
        return dataclasses.replace(self, sections=merged)

    @property
    def tables(self) -> tuple[ReportTable, ...]:
        """Every table, in print order."""
        return tuple(i for s in self.sections for i in s.items if isinstance(i, ReportTable))

    @property
    def figures(self) -> tuple[ReportFigure, ...]:
        """Every figure, in print order."""
        return tuple(i for s in self.sections for i in s.items if isinstance(i, ReportFigure))

    def answer_table(self) -> pd.DataFrame:
        """The answer, one row per state: verdict, confidence, λ₁ [95 %] and its source.

        From the motion verdicts when the report has them (two or more variables), else
        from the verdict of the one analysed variable (rows ``state``), or of each variable
        (rows ``state: variable``). See ``chaoskit.reporting.answer_table``; the
        ``chaoskit report`` command prints it.
        """
        if self.motions:
            return answer_table(self.motions)
        names = {name for per in self.verdicts.values() for name in per}
        if len(names) <= 1:
            return answer_table({s: v for s, per in self.verdicts.items() for v in per.values()})
        return answer_table(
            {f"{s}: {n}": v for s, per in self.verdicts.items() for n, v in per.items()}
        )

    def table(self, caption: str) -> ReportTable:
        """The first table whose caption contains ``caption`` (case-insensitive)."""
        for t in self.tables:
            if caption.lower() in t.caption.lower():
                return t
        raise KeyError(f"no table caption contains {caption!r}.")

    def to_html(self) -> str:
        """The self-contained HTML page (figures embedded as base64 PNG)."""
        return render_html(self)

    def to_markdown(
        self, *, figures: Literal["files", "embed"] = "files", figure_dir: str = "figures"
    ) -> str:
        """The Markdown twin: figures linked as ``figure_dir/<name>.png`` or embedded."""
        return render_markdown(self, figures=figures, figure_dir=figure_dir)

    def figure_filename(self, figure: ReportFigure) -> str:
        """File name of a figure next to the Markdown twin."""
        return figure_filename(figure)

    def write(
        self,
        path: str | os.PathLike[str],
        *,
        markdown: bool = True,
        markdown_figures: Literal["files", "embed"] = "files",
    ) -> dict[str, Any]:
        """Write ``path`` (HTML) and its Markdown twin ``path`` with suffix ``.md``.

        With ``markdown_figures="files"`` the PNGs go to the folder ``<stem>_figures``
        beside the Markdown file (linked relatively); with ``"embed"`` they are inlined as
        data URIs (one file, but some Markdown viewers do not show data URIs). Every file
        is written atomically.

        Returns
        -------
        dict
            ``{"html": Path, "markdown": Path or None, "figures": [Path, ...]}``.
        """
        return write_report(self, path, markdown=markdown, markdown_figures=markdown_figures)
