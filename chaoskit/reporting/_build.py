"""Collect analyses into a frozen :class:`Report`: tables as DataFrames, figures as PNG bytes.

``report`` analyses every trajectory (one state of the system each) with
:func:`chaoskit.classify_variables`, draws the figures with :mod:`chaoskit.plot` and adds
whatever the caller passes in (tables with reference values, sweep maps, bifurcation
diagrams, figures, parameters). A :class:`Report` is an ordered list of sections; a caller
adds its own with :meth:`Report.with_sections`. Nothing here knows about the simulator or
any particular study: tables come in as plain pandas and xarray objects.
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import math
import os
import platform
import shlex
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd
import xarray as xr

from .. import plot
from .._io import _atomic_write, load_trajectory
from .._measures import parse_measures
from .._paths import safe_filename
from .._portraits import DERIVATIVE_NAMES, phase_portrait
from .._selection import VariableSpec, parse_variable, select_series
from .._version import __version__
from ..sections import poincare_section, stroboscopic_map
from ..verdict import MotionVerdict, classify_motion, classify_variables, verdict_table
from ..verdict._rng import as_generator
from ._answer import CONFIDENCE_FORMAT, CONFIDENCE_NOTE, answer_table, decided_by, plural
from ._items import MISSING, ReportCode, ReportFigure, ReportSection, ReportTable, format_number
from ._measures import measure_items
from ._render import render_html, render_markdown

__all__ = ["Report", "SweepMap", "VariableSpec", "parse_variable", "report", "select_series"]

_LN2 = math.log(2.0)

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

#: Columns of the chaos table (see :func:`report`); the reference table uses these names.
CHAOS_COLUMNS = (
    "lag",
    "lag_time",
    "embedding_dim",
    "mle_wolf",
    "mle_wolf_low",
    "mle_wolf_high",
    "mle_wolf_bits",
    "mle_wolf_bits_low",
    "mle_wolf_bits_high",
    "mle_rosenstein",
    "mle_rosenstein_low",
    "mle_rosenstein_high",
    "mle_rosenstein_bits",
    "mle_rosenstein_bits_low",
    "mle_rosenstein_bits_high",
    "verdict",
    "confidence",
)
_VOTES = ("section", "rosenstein", "wolf", "zero_one", "surrogates")
_PACKAGES = ("numpy", "scipy", "numba", "xarray", "pandas", "matplotlib", "jinja2", "h5netcdf")


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
    created: str = field(default_factory=lambda: _now())
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
        (rows ``state: variable``). See :func:`chaoskit.reporting.answer_table`; the
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
        return safe_filename(f"figure-{figure.number:02d}-{figure.name}") + ".png"

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
        if markdown_figures not in ("files", "embed"):
            raise ValueError(
                f"markdown_figures must be 'files' or 'embed'; got {markdown_figures!r}."
            )
        path = Path(path)
        html_path = path if path.suffix.lower() in (".html", ".htm") else path.with_suffix(".html")
        written: dict[str, Any] = {"html": html_path, "markdown": None, "figures": []}
        html = self.to_html()
        _atomic_write(html_path, lambda p: p.write_text(html, encoding="utf-8"))
        if markdown:
            md_path = html_path.with_suffix(".md")
            folder = f"{html_path.stem}_figures"
            text = self.to_markdown(figures=markdown_figures, figure_dir=folder)
            if markdown_figures == "files":
                for fig in self.figures:
                    target = html_path.parent / folder / self.figure_filename(fig)
                    _atomic_write(target, lambda p, b=fig.png: p.write_bytes(b))
                    written["figures"].append(target)
            _atomic_write(md_path, lambda p: p.write_text(text, encoding="utf-8"))
            written["markdown"] = md_path
        return written


@dataclass(kw_only=True)
class _State:
    label: str
    source: str
    view: xr.Dataset
    verdicts: dict[str, Any]
    motion: MotionVerdict | None
    original_samples: int
    stride: int
    scene: str | None
    scene_name: str | None
    title: str
    history: str


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()


def _normalise_trajectories(
    trajectories: Any, labels: Sequence[str] | None
) -> list[tuple[str, Any]]:
    if trajectories is None:
        items: list[tuple[str | None, Any]] = []
    elif isinstance(trajectories, Mapping):
        if labels is not None:
            raise ValueError("give labels either as the keys of trajectories or as labels=.")
        items = [(str(k), v) for k, v in trajectories.items()]
    elif isinstance(trajectories, (str, os.PathLike, xr.Dataset, xr.DataArray)):
        items = [(None, trajectories)]
    elif isinstance(trajectories, Sequence):
        items = [(None, t) for t in trajectories]
    else:
        raise ValueError(
            "trajectories must be a Dataset, a file path, a sequence of them or a mapping "
            f"label -> trajectory; got {type(trajectories).__name__}."
        )
    if labels is not None:
        labels = [labels] if isinstance(labels, str) else list(labels)
        if len(labels) != len(items):
            raise ValueError(
                f"labels has {len(labels)} entries but there are {len(items)} trajectories."
            )
        items = [(str(lab), t) for lab, (_, t) in zip(labels, items, strict=True)]
    out: list[tuple[str, Any]] = []
    for i, (lab, t) in enumerate(items):
        if lab is None:
            lab = Path(t).stem if isinstance(t, (str, os.PathLike)) else f"trajectory {i + 1}"
        out.append((lab, t))
    names = [lab for lab, _ in out]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise ValueError(f"state labels must be distinct; repeated: {dupes}.")
    return out


def _normalise_variables(variables: Any) -> list[VariableSpec]:
    if variables is None:
        return []
    if isinstance(variables, str):
        variables = [variables]
    if isinstance(variables, Mapping):
        specs = [parse_variable(str(v), alias=str(k)) for k, v in variables.items()]
    else:
        specs = [parse_variable(v) for v in variables]
    aliases = [s.alias for s in specs]
    dupes = sorted({a for a in aliases if aliases.count(a) > 1})
    if dupes:
        raise ValueError(f"variable names in the report must be distinct; repeated: {dupes}.")
    return specs


def _derivative_of(ds: xr.Dataset, spec: VariableSpec, sel: Mapping[str, Any] | None) -> Any:
    for pattern in DERIVATIVE_NAMES:
        name = pattern.format(v=spec.name)
        if name in ds.data_vars:
            try:
                return select_series(
                    ds,
                    VariableSpec(alias=f"{spec.alias}_dot", name=name, selectors=spec.selectors),
                    sel=sel,
                )
            except ValueError:
                return None
    return None


def _prepare_state(
    label: str,
    source: Any,
    *,
    specs: list[VariableSpec],
    sel: Mapping[str, Any] | None,
    phase: VariableSpec | None,
    discard: float,
    max_samples: int | None,
) -> tuple[xr.Dataset, dict[str, Any]]:
    ds = load_trajectory(source)
    index = "time" if "time" in ds.coords else "step"
    start = ds[index].values[0]
    if discard > 0:
        ds = ds.sel({index: ds[index] >= start + discard})
    n = ds.sizes[index]
    if n == 0:
        raise ValueError(f"{label!r}: nothing left after discarding {discard} {index} units.")
    stride = 1 if max_samples is None else max(1, math.ceil(n / max_samples))
    data: dict[str, xr.DataArray] = {}
    for spec in specs:
        data[spec.alias] = select_series(ds, spec, sel=sel)
        if index == "time":
            rate = _derivative_of(ds, spec, sel)
            if rate is not None:
                data[f"{spec.alias}_dot"] = rate
    if phase is not None:
        if phase.alias in data:
            raise ValueError(f"phase variable name {phase.alias!r} clashes with a report variable.")
        data[phase.alias] = select_series(ds, phase, sel=sel)
    view = xr.Dataset({k: v.variable for k, v in data.items()}, coords={index: ds[index]}).isel(
        {index: slice(None, None, stride)}
    )
    view.attrs = dict(ds.attrs)
    view = load_trajectory(view)
    info = {
        "source": str(source) if isinstance(source, (str, os.PathLike)) else "in-memory Dataset",
        "original_samples": n,
        "stride": stride,
        "scene": ds.attrs.get("scene"),
        "scene_name": ds.attrs.get("scene_name"),
        "title": str(ds.attrs.get("title", "")),
        "history": str(ds.attrs.get("history", "")),
    }
    return view, info


# ----------------------------------------------------------------- figure drawing


def _draw(
    draw: Callable[[Any], None],
    *,
    nrows: int,
    ncols: int,
    caption: str,
    name: str,
    section: str,
    panel: tuple[float, float] = (4.2, 3.4),
) -> ReportFigure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(panel[0] * ncols, panel[1] * nrows), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    draw(axes)
    return ReportFigure.from_matplotlib(fig, caption=caption, name=name, section=section)


def _empty_panel(ax: Any, text: str) -> None:
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=8, wrap=True, transform=ax.transAxes)
    ax.set_xticks([])
    ax.set_yticks([])


def _unit_suffix(units: Any) -> str:
    return f" [{units}]" if units not in (None, "", "1", "unknown") else ""


def _tidy(ax: Any, xlabel: str, ylabel: str) -> None:
    """Short axis labels and compact scientific tick labels (long names live in captions)."""
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    try:
        ax.ticklabel_format(axis="both", style="sci", scilimits=(-3, 4), useMathText=True)
    except AttributeError:  # not a plain numeric axis
        pass


def _rate_units(units: Any) -> str:
    if units in (None, "", "1", "unknown"):
        return "s-1" if units in ("", "1") else ""
    return f"{units} s-1"


#: Length units a figure can show a variable in, in metres.
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "um": 1e-6, "nm": 1e-9}


def _check_display_units(
    display_units: Mapping[str, str] | None, specs: list[VariableSpec]
) -> dict[str, str]:
    if display_units is None:
        return {}
    if not isinstance(display_units, Mapping):
        raise ValueError("display_units must be a mapping {variable: unit}, e.g. {'X': 'mm'}.")
    aliases = [s.alias for s in specs]
    out = {}
    for alias, unit in display_units.items():
        if alias not in aliases:
            raise ValueError(f"display_units names {alias!r}, not a report variable {aliases}.")
        if unit not in LENGTH_UNITS:
            raise ValueError(
                f"display_units[{alias!r}] = {unit!r}: the accepted units are "
                f"{', '.join(LENGTH_UNITS)} (a length stored in m)."
            )
        out[str(alias)] = str(unit)
    return out


def _display_view(view: xr.Dataset, display_units: Mapping[str, str]) -> xr.Dataset:
    """``view`` with each variable of ``display_units`` (and its stored rate) converted
    from its stored length unit to the display unit, for the figures only."""
    if not display_units:
        return view
    out = view.copy()
    for alias, unit in display_units.items():
        stored = str(view[alias].attrs.get("units", ""))
        if stored not in LENGTH_UNITS:
            raise ValueError(
                f"display_units[{alias!r}] = {unit!r} needs {alias} stored in a length unit "
                f"({', '.join(LENGTH_UNITS)}); its units are {stored!r}."
            )
        factor = LENGTH_UNITS[stored] / LENGTH_UNITS[unit]
        for name, units in ((alias, unit), (f"{alias}_dot", f"{unit} s-1")):
            if name in out:
                out[name] = (out[name] * factor).assign_attrs({**view[name].attrs, "units": units})
    return out


def _section_points(
    view: xr.Dataset,
    alias: str,
    *,
    drive_period: float | None,
    phase_alias: str | None,
    used: xr.Dataset | None = None,
) -> tuple[xr.Dataset | None, str]:
    """The (x, dx/dt) stroboscopic points, the return map of maxima, or of a map's samples.

    ``used`` is the section the verdict of ``alias`` used (``Verdict.section``): when it
    carries the instants of its points (``time``), only the points at those instants are
    kept, so the figure shows exactly the points the evidence table counts (not, e.g., the
    initial state or the crossings the verdict's delay embedding left out).
    """
    if "step" in view.coords:
        x = np.asarray(view[alias].values, dtype=np.float64)
        sec = xr.Dataset(
            {alias: ("crossing", x, dict(view[alias].attrs))},
            attrs={"section_kind": "return map"},
        )
        return sec, "the return map x(n+1) against x(n) of the iterates"
    portrait = phase_portrait(view, variable=alias)
    rate = portrait.attrs["portrait_derivative"]
    if drive_period is not None or phase_alias is not None:
        pts = view[[alias]].assign({rate: portrait[rate]})
        if phase_alias is not None:
            pts = pts.assign({phase_alias: view[phase_alias]})
            sec = stroboscopic_map(pts, phase_variable=phase_alias, coords=[alias, rate])
            how = f"once per revolution of {phase_alias} (stroboscopic map)"
        else:
            sec = stroboscopic_map(pts, period=drive_period, coords=[alias, rate])
            how = f"once per drive period T = {format_number(drive_period)} s (stroboscopic map)"
        sec = _at_instants(sec, used)
        return sec, f"{alias} against its rate, sampled {how}"
    pts = view[[alias]].assign({rate: portrait[rate]})
    sec = poincare_section(pts, variable=rate, level=0.0, direction="down", coords=[alias])
    if used is not None and "time" in used.coords:
        # one point (M_n, M_n+1) per return-map point of the verdict, at its instants
        pairs = sec.isel(crossing=slice(None, -1)).assign(
            {f"{alias}_next": ("crossing", sec[alias].values[1:], dict(sec[alias].attrs))}
        )
        sec = _at_instants(pairs, used)
    return sec, (
        f"the return map of the successive maxima of {alias} (Poincaré section "
        f"d{alias}/dt = 0, decreasing)"
    )


def _at_instants(sec: xr.Dataset, used: xr.Dataset | None) -> xr.Dataset:
    """The crossings of ``sec`` at the instants of ``used`` (nearest, within a quarter of
    the spacing of the crossings); ``sec`` itself when ``used`` has no instants."""
    if used is None or "time" not in used.coords or sec.sizes.get("crossing", 0) == 0:
        return sec
    t = np.asarray(sec["time"].values, dtype=np.float64)
    wanted = np.asarray(used["time"].values, dtype=np.float64)
    if wanted.size == 0:
        return sec.isel(crossing=slice(0, 0))
    spacing = float(np.median(np.diff(t))) if t.size > 1 else math.inf
    right = np.clip(np.searchsorted(t, wanted), 0, t.size - 1)
    left = np.maximum(right - 1, 0)
    nearest = np.where(np.abs(t[left] - wanted) <= np.abs(t[right] - wanted), left, right)
    close = np.abs(t[nearest] - wanted) <= 0.25 * spacing
    return sec.isel(crossing=np.unique(nearest[close]))


# ----------------------------------------------------------------- tables


def _chaos_frame(states: list[_State], specs: list[VariableSpec]) -> pd.DataFrame:
    rows, keys = [], []
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            s = v.summary()
            row = {c: s.get(c, float("nan")) for c in CHAOS_COLUMNS if c in s}
            for method in ("wolf", "rosenstein"):
                res = getattr(v, method)
                factor = float(v.dt) / _LN2
                lo, hi = (float("nan"), float("nan")) if res is None else res.ci
                row[f"mle_{method}_bits_low"] = lo * factor
                row[f"mle_{method}_bits_high"] = hi * factor
            row["verdict"] = v.label
            keys.append((spec.alias, st.label))
            rows.append({c: row.get(c, float("nan")) for c in CHAOS_COLUMNS})
    index = pd.MultiIndex.from_tuples(keys, names=["variable", "state"])
    frame = pd.DataFrame(rows, index=index, columns=list(CHAOS_COLUMNS))
    return frame.astype({c: object for c in ("verdict",)})


#: Footnote of the estimates a verdict did not follow (see :func:`_set_aside_marks`).
SET_ASIDE_MARK = "†"
SET_ASIDE_NOTE = (
    f"{SET_ASIDE_MARK} set aside: the verdict of this variable and state did not follow this "
    "estimate — it points the other way (clearly positive for a regular label, or not clearly "
    "positive for chaos) and the other evidence decided (votes in the appendix)."
)


def _set_aside_marks(states: list[_State], specs: list[VariableSpec]) -> dict[tuple[Any, str], str]:
    """Chaos-table cells of the exponents that the row's verdict voted against."""
    marks: dict[tuple[Any, str], str] = {}
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            if v.label == "undetermined":
                continue  # nothing was decided, so nothing was set aside
            for method in ("wolf", "rosenstein"):
                if v.votes.get(method) == "opposes":
                    for col in (f"mle_{method}", f"mle_{method}_bits"):
                        marks[((spec.alias, st.label), col)] = SET_ASIDE_MARK
    return marks


def _chaos_labels(kind: str) -> dict[str, str]:
    per = "1/iteration" if kind == "map" else "1/s"
    return {
        "lag": "lag (samples)",
        "lag_time": "lag (iterations)" if kind == "map" else "lag (s)",
        "embedding_dim": "embedding dimension",
        "mle_wolf": f"MLE Wolf ({per}) [95% CI]",
        "mle_wolf_bits": "MLE Wolf (bit/sample) [95% CI]",
        "mle_rosenstein": f"MLE Rosenstein ({per}) [95% CI]",
        "mle_rosenstein_bits": "MLE Rosenstein (bit/sample) [95% CI]",
        "verdict": "verdict",
        "confidence": "confidence",
    }


def _chaos_intervals() -> dict[str, tuple[str, str]]:
    out = {}
    for method in ("wolf", "rosenstein"):
        for suffix in ("", "_bits"):
            base = f"mle_{method}{suffix}"
            out[base] = (f"{base}_low", f"{base}_high")
    return out


def _evidence_frame(states: list[_State], specs: list[VariableSpec]) -> pd.DataFrame:
    rows, keys = [], []
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            s = v.summary()
            row: dict[str, Any] = {
                "verdict": v.label,
                "period": s["period"],
                "confidence": s["confidence"],
            }
            for name in _VOTES:
                row[f"vote_{name}"] = v.votes.get(name, "missing")
            row.update(
                zero_one_k=s["zero_one_k"],
                surrogate_p_value=s["surrogate_p_value"],
                section_structure=s["section_structure"],
                section_points=s["section_points"],
                n_samples=s["n_samples"],
                dt=s["dt"],
                reason=v.reason,
            )
            rows.append(row)
            keys.append((spec.alias, st.label))
    index = pd.MultiIndex.from_tuples(keys, names=["variable", "state"])
    return pd.DataFrame(rows, index=index).astype(object)


_EVIDENCE_LABELS = {
    "period": "period k",
    "vote_section": "section",
    "vote_rosenstein": "Rosenstein",
    "vote_wolf": "Wolf",
    "vote_zero_one": "0-1 test",
    "vote_surrogates": "surrogates",
    "zero_one_k": "0-1 K",
    "surrogate_p_value": "surrogate p",
    "section_structure": "section structure",
    "section_points": "section points",
    "n_samples": "samples",
    "dt": "dt",
}


def _motion_table(states: list[_State], kind: str) -> ReportTable:
    """One row per state: the motion verdict and the joint evidence it rests on."""
    rows, index = [], []
    for st in states:
        mv = st.motion
        if mv is None:
            continue
        row = mv.summary()
        rows.append(
            {
                "verdict": mv.label if mv.period is None else f"{mv.label} (period {mv.period})",
                "confidence": mv.confidence,
                "section": _joint_section_text(
                    row["motion_section_structure"], row["motion_section_points"]
                ),
                "mle": row["motion_mle"],
                "mle_low": row["motion_mle_low"],
                "mle_high": row["motion_mle_high"],
                "equations": row["motion_mle_equations"],
                "equations_low": row["motion_mle_equations_low"],
                "equations_high": row["motion_mle_equations_high"],
                "set_aside": ", ".join((*mv.drive_variables, *mv.constant_variables)) or "—",
                "why": decided_by(mv),
            }
        )
        index.append(st.label)
    unit = "1/iteration" if kind == "map" else "1/s"
    return ReportTable(
        caption="The motion verdict: one label per state from all its analysed variables "
        "together — their joint section, the largest exponent of their mixed delay "
        "embedding, the exponent from the equations of motion when given, and each "
        "variable's verdict (docs/verdict.md). Variables that follow the drive alone are set "
        'aside; "why" names the evidence that decided.',
        data=pd.DataFrame(rows, index=pd.Index(index, name="state")),
        labels={
            "verdict": "motion verdict",
            "confidence": "confidence",
            "section": "joint section",
            "mle": f"joint MLE ({unit})",
            "equations": f"equations MLE ({unit})",
            "set_aside": "set aside",
            "why": "why",
        },
        intervals={
            "mle": ("mle_low", "mle_high"),
            "equations": ("equations_low", "equations_high"),
        },
        digits=3,
        formats={"confidence": CONFIDENCE_FORMAT},
        notes=CONFIDENCE_NOTE,
        section=MOTION,
    )


def _joint_section_text(structure: str, points: float) -> str:
    """``"clusters (198 points)"``; ``"none"`` when there is no joint section."""
    if not math.isfinite(points):
        return str(structure)
    return f"{structure} ({plural(int(points), 'point')})"


def _overview_frame(states: list[_State], specs: list[VariableSpec]) -> pd.DataFrame:
    data = {}
    for st in states:
        col = []
        for spec in specs:
            v = st.verdicts[spec.alias]
            text = v.label if v.period is None else f"{v.label} (period {v.period})"
            col.append(text)
        data[st.label] = col
    return pd.DataFrame(data, index=pd.Index([s.alias for s in specs], name="variable"))


# ----------------------------------------------------------------- provenance


def _versions() -> dict[str, str]:
    out = {"chaoskit": __version__, "python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    out["platform"] = platform.platform()
    return out


def _pretty_json(text: str) -> str:
    try:
        return json.dumps(json.loads(text), indent=2, sort_keys=False, ensure_ascii=False)
    except (TypeError, ValueError):
        return str(text)


def _value_text(value: Any) -> str:
    if isinstance(value, (Mapping, list, tuple)):
        return json.dumps(value, default=str, ensure_ascii=False)
    return format_number(value, 6) if not isinstance(value, str) else value


# ----------------------------------------------------------------- assembly


def report(
    trajectories: Any = None,
    *,
    variables: Sequence[str] | Mapping[str, str] | None = None,
    labels: Sequence[str] | None = None,
    sel: Mapping[str, Any] | None = None,
    discard: float = 0.0,
    max_samples: int | None = None,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    exponents: Mapping[str, Any] | None = None,
    n_surrogates: int = 19,
    rng: Any = 0,
    chaos_reference: pd.DataFrame | None = None,
    reference_name: str = "reference",
    chaos_notes: str = "",
    tables: Sequence[ReportTable] = (),
    sweep_maps: Sequence[SweepMap] = (),
    bifurcations: Any = None,
    figures: Sequence[ReportFigure] = (),
    measures: Sequence[str] | str = (),
    display_units: Mapping[str, str] | None = None,
    parameters: Mapping[str, Any] | None = None,
    title: str = "chaoskit report",
    command: str | None = None,
    output: str | os.PathLike[str] | None = None,
    markdown_figures: Literal["files", "embed"] = "files",
    progress: bool = False,
) -> Report:
    r"""Analyse trajectories and assemble a captioned report (HTML page and Markdown twin).

    Each trajectory is one *state* of the system (e.g. "before wear", "after wear"). For
    every state the report runs :func:`chaoskit.classify_motion` on its variables (with
    ``exponents`` from the equations when given; :func:`chaoskit.classify_variables` when
    there is one variable) and shows

    * first, the motion verdict: one label per state from all its variables together, with
      the joint section, the exponent of the mixed embedding, the equations' exponent and
      what would decide an undetermined motion;
    * the verdicts (one line per variable, one column per state);
    * the chaos table: delay :math:`\tau` (samples and s), embedding dimension :math:`m`,
      the largest Lyapunov exponent by Wolf's and Rosenstein's method with its 95 %
      interval in 1/s (natural log) and in bits per sample,
      :math:`\lambda_\text{bit} = \lambda\,\Delta t/\ln 2` — the unit of Wolf et al.'s
      (1985) program used by most papers — the verdict and its confidence; with
      ``chaos_reference`` each reference value is shown beside ours with the difference;
    * the evidence behind each verdict (votes, 0–1 K, surrogate p-value, reason);
    * phase portraits :math:`(x, \dot x)`, Poincaré/stroboscopic maps (stroboscopic
      :math:`(x, \dot x)` once per drive period when ``drive_period`` or
      ``phase_variable`` is given; otherwise the return map of successive maxima; for
      maps the return map of the iterates), and the divergence curves of both methods
      with their fit ranges — one figure per variable, one panel per state.

    Then the caller's material: ``tables`` (e.g. response metrics with a paper's values,
    ratios and differences),
    ``sweep_maps`` (MLE/verdict maps over two swept parameters, with a table),
    ``bifurcations`` (diagrams from :func:`chaoskit.bifurcation_diagram`), ``figures``;
    and at the end the parameters and provenance: date, command, package versions, every
    input (source, samples, sampling interval), the analysis settings, ``parameters`` and
    the scene JSON stored in each trajectory's ``scene`` attribute. Every table and figure
    is numbered and captioned.

    Parameters
    ----------
    trajectories
        A trajectory (Dataset or file path), a sequence of them, or a mapping
        ``{state label: trajectory}``; None for a report of tables and figures only.
    variables
        Series to analyse: specs ``"NAME"``, ``"NAME[DIM=VALUE,...]"`` (one element along
        extra dimensions, e.g. ``"eccentricity_x[joint=C]"``) or ``"ALIAS=SPEC"``, or a
        mapping ``{alias: spec}`` (e.g. ``{"X": "eccentricity_x[joint=C]"}``). Extra
        dimensions of length 1 are squeezed.
    labels
        State labels for a sequence of trajectories (default: file stems, or
        "trajectory 1", ...).
    sel
        Selections applied to every variable that has the dimension, e.g.
        ``{"joint": "C"}``; a spec's own selection wins.
    discard
        Transient dropped from the start of each trajectory, in units of its index (s for
        ``time``, iterations for ``step``).
    max_samples
        Subsample (plain stride, no filter) so that at most this many samples are
        analysed; the lag in samples and the exponent in bits per sample refer to the
        analysed sampling interval, which the provenance lists.
    drive_period, phase_variable
        Drive of a forced system (s, or an angle variable such as ``crank_angle``, which
        may also be a spec): used by the verdict's stroboscopic section and the maps.
    exponents
        ``{state label: exponent}``: the largest exponent from the equations of motion of
        each state (e.g. :func:`mechanism.lyapunov_exponent`; any object with ``exponent``
        in 1/s and a 95 % interval ``ci``), a vote in the motion verdict.
    n_surrogates, rng
        Passed to :func:`chaoskit.classify_variables`; each state gets its own stream
        spawned from ``rng``.
    chaos_reference
        Reference values for the chaos table, indexed by ``(variable alias, state)`` with
        columns among ``lag``, ``lag_time``, ``embedding_dim``, ``mle_wolf``,
        ``mle_wolf_bits``, ``mle_rosenstein``, ``mle_rosenstein_bits``, ``verdict``,
        ``confidence``.
    reference_name
        Header of the reference values in the chaos table.
    chaos_notes
        Text under the chaos table (e.g. how the settings differ from the paper's).
    tables
        :class:`ReportTable` objects, placed in their ``section`` (default "Response
        metrics").
    sweep_maps
        :class:`SweepMap` objects (exponent and verdict over two swept parameters).
    bifurcations
        Datasets from :func:`chaoskit.bifurcation_diagram`, or ``{caption: Dataset}``.
    figures
        Further :class:`ReportFigure` objects, placed in their ``section``.
    measures
        Further measures for every state and variable, in a section of their own (table and
        figures): a subset of ``"d2"``, ``"rqa"``, ``"spectrum"``, ``"sampen"``, ``"dfa"``,
        ``"hurst"`` (a sequence or a comma-separated string, or ``"all"``).
    display_units
        ``{variable: unit}``: the unit a length variable is drawn in (``"m"``, ``"mm"``,
        ``"µm"``, ``"nm"``), e.g. ``{"X": "mm"}`` for journal displacements stored in m.
        Figures only: the analysis and the tables stay in the stored (SI) units.
    parameters
        Run parameters to list in the provenance (values: numbers, text, JSON-able).
    title
        Page title.
    command
        The command that produced the report (default: this process's command line).
    output
        If given, write the HTML page there and the Markdown twin beside it
        (:meth:`Report.write`).
    markdown_figures
        ``"files"`` (PNG files in ``<stem>_figures/``) or ``"embed"`` (data URIs).
    progress
        Show a tqdm bar over the variables of each state.

    Returns
    -------
    Report

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> t, s = chaoskit.systems.duffing(3000, gamma=0.28, samples_per_period=50)
    >>> before = chaoskit.load_trajectory(s, dt=t[1] - t[0], variables=["x", "v"])
    >>> t, s = chaoskit.systems.duffing(3000, gamma=0.5, samples_per_period=50)
    >>> after = chaoskit.load_trajectory(s, dt=t[1] - t[0], variables=["x", "v"])
    >>> rep = chaoskit.report({"before": before, "after": after}, variables=["x"],
    ...                       drive_period=2 * np.pi / 1.2, rng=0)
    >>> rep.table("chaos").data.loc[("x", "after"), "verdict"]
    'chaotic'
    """
    created = _now()
    pairs = _normalise_trajectories(trajectories, labels)
    specs = _normalise_variables(variables)
    if pairs and not specs:
        raise ValueError("give variables=[...] (the series to analyse) with the trajectories.")
    if specs and not pairs:
        raise ValueError("variables= given but no trajectories to analyse.")
    discard = float(discard)
    if not math.isfinite(discard) or discard < 0:
        raise ValueError(f"discard must be a finite number >= 0; got {discard!r}.")
    if max_samples is not None and (not isinstance(max_samples, int) or max_samples < 200):
        raise ValueError(f"max_samples must be an integer >= 200 or None; got {max_samples!r}.")
    if markdown_figures not in ("files", "embed"):
        raise ValueError(f"markdown_figures must be 'files' or 'embed'; got {markdown_figures!r}.")
    for t in tables:
        if not isinstance(t, ReportTable):
            raise ValueError(f"tables must hold ReportTable objects; got {type(t).__name__}.")
    for f in figures:
        if not isinstance(f, ReportFigure):
            raise ValueError(f"figures must hold ReportFigure objects; got {type(f).__name__}.")
    phase = parse_variable(phase_variable) if phase_variable is not None else None
    measure_names = parse_measures(measures)
    shown_units = _check_display_units(display_units, specs)
    if exponents is not None:
        if not isinstance(exponents, Mapping):
            raise ValueError("exponents must be a mapping {state label: exponent}.")
        unknown = [k for k in exponents if k not in [lab for lab, _ in pairs]]
        if unknown:
            raise ValueError(
                f"exponents names states {unknown} that are not among {[lab for lab, _ in pairs]}."
            )

    streams = as_generator(rng).spawn(len(pairs)) if pairs else []
    states: list[_State] = []
    for (label, source), stream in zip(pairs, streams, strict=True):
        view, info = _prepare_state(
            label,
            source,
            specs=specs,
            sel=sel,
            phase=phase,
            discard=discard,
            max_samples=max_samples,
        )
        common: dict[str, Any] = {
            "variables": [s.alias for s in specs],
            "drive_period": drive_period,
            "phase_variable": None if phase is None else phase.alias,
            "n_surrogates": n_surrogates,
            "rng": stream,
            "progress": progress,
        }
        motion = None
        if len(specs) > 1:
            exponent = None if exponents is None else exponents.get(label)
            motion = classify_motion(view, exponent=exponent, **common)
            verdicts = dict(motion.variables)
        else:
            verdicts = classify_variables(view, **common)
        states.append(_State(label=label, view=view, verdicts=verdicts, motion=motion, **info))

    sections: dict[str, list[Any]] = {name: [] for name in SECTION_ORDER}
    texts: dict[str, str] = {}

    def put(item: Any, section: str | None = None) -> None:
        sections.setdefault(section or item.section, []).append(item)

    for t in tables:
        put(t)
    analysis = None
    if states:
        _analysis_items(
            states,
            specs,
            put,
            texts,
            drive_period=drive_period,
            phase=phase,
            chaos_reference=chaos_reference,
            reference_name=reference_name,
            chaos_notes=chaos_notes,
            display_units=shown_units,
        )
        if measure_names:
            seed = int(rng) if isinstance(rng, (int, np.integer)) else 0
            measure_items(states, specs, measure_names, put, _draw, rng=seed)
        analysis = xr.concat(
            [verdict_table(st.verdicts) for st in states],
            dim=pd.Index([st.label for st in states], name="state"),
        )
    for m in sweep_maps:
        _sweep_items(m, put)
    if bifurcations is not None:
        _bifurcation_items(bifurcations, put)
    for f in figures:
        put(f)
    prov = _provenance_items(
        states,
        specs=specs,
        created=created,
        title=title,
        command=command,
        settings={
            "variables": {s.alias: s.spec for s in specs},
            "sel": dict(sel or {}),
            "discard": discard,
            "max_samples": max_samples,
            "drive_period": drive_period,
            "phase_variable": None if phase is None else phase.spec,
            "n_surrogates": n_surrogates,
            "rng": rng if isinstance(rng, (int, np.integer)) else repr(rng),
            **({"display_units": shown_units} if shown_units else {}),
        },
        parameters=parameters,
    )
    sections.pop(PROVENANCE, None)
    appendix = sections.pop(APPENDIX, [])
    ordered = [(name, items) for name, items in sections.items() if items]
    if appendix:
        ordered.append((APPENDIX, appendix))
    ordered.append((PROVENANCE, prov))
    rep = Report(
        title=title,
        sections=tuple(
            ReportSection(title=name, items=tuple(items), text=texts.get(name, ""))
            for name, items in ordered
        ),
        created=created,
        analysis=analysis,
        verdicts={st.label: dict(st.verdicts) for st in states},
        motions={st.label: st.motion for st in states if st.motion is not None},
    )
    if output is not None:
        rep.write(output, markdown_figures=markdown_figures)
    return rep


def _sampling_step(view: xr.Dataset) -> float:
    index = "time" if "time" in view.coords else "step"
    t = np.asarray(view[index].values, dtype=np.float64)
    return float(np.median(np.diff(t))) if t.size > 1 else float("nan")


def _states_text(states: list[_State]) -> str:
    names = [st.label for st in states]
    if len(names) == 1:
        return names[0]
    if len(names) == 2:
        return f"{names[0]} (left) and {names[1]} (right)"
    return ", ".join(names[:-1]) + f" and {names[-1]}, left to right"


def _analysis_items(
    states: list[_State],
    specs: list[VariableSpec],
    put: Callable[..., None],
    texts: dict[str, str],
    *,
    drive_period: float | None,
    phase: VariableSpec | None,
    chaos_reference: pd.DataFrame | None,
    reference_name: str,
    chaos_notes: str,
    display_units: Mapping[str, str],
) -> None:
    kinds = {v.kind for st in states for v in st.verdicts.values()}
    kind = "map" if kinds == {"map"} else "flow"
    motion = any(st.motion is not None for st in states)
    if motion:
        put(_motion_table(states, kind), MOTION)
    described = "; ".join(
        f"{s.alias} = {s.spec} ({states[0].view[s.alias].attrs.get('long_name', s.name)}, "
        f"{states[0].view[s.alias].attrs.get('units', '')})"
        for s in specs
    )
    put(
        ReportTable(
            caption=f"Verdict per variable and state. Variables: {described}.",
            data=_overview_frame(states, specs),
        ),
        "Verdicts",
    )
    texts["Chaos identification"] = (
        "Delay τ from the delay curve, embedding dimension m from false nearest neighbours, "
        "largest Lyapunov exponent (MLE) by Wolf's and Rosenstein's methods with 95 % "
        "intervals, in "
        + ("1/iteration" if kind == "map" else "1/s (natural log)")
        + " and in bits per sample (λ·Δt/ln 2, the unit of Wolf's program and of most "
        "papers). The verdict combines all evidence (docs/verdict.md)."
    )
    frame = _chaos_frame(states, specs)
    ref = None
    if chaos_reference is not None:
        if not isinstance(chaos_reference, pd.DataFrame):
            raise ValueError("chaos_reference must be a pandas DataFrame.")
        unknown = [c for c in chaos_reference.columns if c not in CHAOS_COLUMNS]
        if unknown:
            raise ValueError(
                f"chaos_reference has columns {unknown} that the chaos table does not have; "
                f"use {list(CHAOS_COLUMNS)}."
            )
        if chaos_reference.index.nlevels != 2:
            raise ValueError("chaos_reference must be indexed by (variable, state).")
        ref = chaos_reference
    dts = sorted({format_number(_sampling_step(st.view)) for st in states})
    marks = _set_aside_marks(states, specs)
    notes = " ".join(
        n
        for n in (chaos_notes, SET_ASIDE_NOTE if marks else "", "" if motion else CONFIDENCE_NOTE)
        if n
    )
    put(
        ReportTable(
            caption=(
                "Chaos table: embedding and largest Lyapunov exponent per variable and state "
                f"(analysed sampling interval Δt = {', '.join(dts)} "
                + ("iterations" if kind == "map" else "s")
                + ")."
            ),
            data=frame,
            reference=ref,
            reference_name=reference_name,
            intervals=_chaos_intervals(),
            labels=_chaos_labels(kind),
            # beside a reference, one row per quantity keeps the table at five columns
            layout="long" if ref is not None else "wide",
            formats={"confidence": CONFIDENCE_FORMAT},
            marks=marks,
            notes=notes,
            section="Chaos identification",
        )
    )
    put(
        ReportTable(
            caption=(
                "Evidence behind each verdict: how each test voted (supports / opposes / "
                "neutral / missing), the 0-1 test's K, the surrogate test's p-value, the "
                "structure of the section set, and the rule that fired."
            ),
            data=_evidence_frame(states, specs),
            labels=_EVIDENCE_LABELS,
            formats={"confidence": CONFIDENCE_FORMAT},
            layout="long",
            section=APPENDIX,
        )
    )
    n = len(states)
    ncols = min(n, 3)
    nrows = math.ceil(n / ncols)
    phase_alias = None if phase is None else phase.alias
    # the figures show each variable in its display unit; the analysis stays in SI
    shown = {st.label: _display_view(st.view, display_units) for st in states}
    for spec in specs:
        alias = spec.alias
        if kind != "map":

            def draw_portraits(axes: Any, alias: str = alias) -> None:
                for k, ax in enumerate(axes.flat):
                    if k >= n:
                        ax.set_visible(False)
                        continue
                    st = states[k]
                    ax.set_title(f"{alias}: {st.label}", fontsize=9)
                    try:
                        portrait = phase_portrait(shown[st.label], variable=alias)
                    except ValueError as exc:  # e.g. too short for the derivative filter
                        _empty_panel(ax, f"no phase portrait: {exc}")
                        continue
                    plot.phase_portrait(portrait, ax=ax)
                    ax.set_title(f"{alias}: {st.label}", fontsize=9)
                    units = shown[st.label][alias].attrs.get("units")
                    _tidy(
                        ax,
                        f"{alias}{_unit_suffix(units)}",
                        f"d{alias}/dt{_unit_suffix(_rate_units(units))}",
                    )

            try:
                source = phase_portrait(states[0].view, variable=alias).attrs["derivative_source"]
            except ValueError:
                source = "none"
            how = (
                "the rate taken from the data"
                if source == "data"
                else f"the rate estimated by a Savitzky–Golay filter ({source})"
            )
            put(
                _draw(
                    draw_portraits,
                    nrows=nrows,
                    ncols=ncols,
                    section="Phase portraits",
                    name=f"phase-portrait-{alias}",
                    caption=f"Phase portraits of {alias} ({spec.spec}) against its rate of "
                    f"change, {how}, for {_states_text(states)}.",
                )
            )
        sections_how: dict[str, str] = {}

        def draw_sections(axes: Any, alias: str = alias, how: dict = sections_how) -> None:
            for k, ax in enumerate(axes.flat):
                if k >= n:
                    ax.set_visible(False)
                    continue
                st = states[k]
                view = shown[st.label]
                title = f"{alias}: {st.label}"
                try:
                    sec, how["text"] = _section_points(
                        view,
                        alias,
                        drive_period=drive_period,
                        phase_alias=phase_alias,
                        used=st.verdicts[alias].section,
                    )
                except ValueError as exc:
                    sec = None
                    _empty_panel(ax, f"no section: {exc}")
                if sec is not None:
                    count = sec.sizes.get("crossing", 0)
                    one = [v for v in sec.data_vars if sec[v].dims == ("crossing",)]
                    points = count - 1 if len(one) == 1 else count  # a return map: pairs
                    title += f", {plural(points, 'point')}"
                    if count < 2:
                        _empty_panel(ax, "fewer than 2 section points")
                    else:
                        plot.poincare(sec, ax=ax)
                        units = view[alias].attrs.get("units")
                        if len(one) == 1 or f"{alias}_next" in sec:
                            _tidy(
                                ax,
                                f"{alias}(n){_unit_suffix(units)}",
                                f"{alias}(n+1){_unit_suffix(units)}",
                            )
                        else:
                            _tidy(
                                ax,
                                f"{alias}{_unit_suffix(units)}",
                                f"d{alias}/dt{_unit_suffix(_rate_units(units))}",
                            )
                ax.set_title(title, fontsize=9)

        fig = _draw(
            draw_sections,
            nrows=nrows,
            ncols=ncols,
            section="Poincaré and stroboscopic maps",
            name=f"section-{alias}",
            caption="pending",
        )
        put(
            dataclasses.replace(
                fig,
                caption=f"Poincaré-type map of {alias}: "
                f"{sections_how.get('text', 'no points')}, for {_states_text(states)}; "
                "the points the verdict's section used (their number is the evidence "
                "table's section points).",
            )
        )

        def draw_divergence(axes: Any, alias: str = alias) -> None:
            for k in range(n):
                st = states[k]
                v = st.verdicts[alias]
                for row, method in enumerate(("rosenstein", "wolf")):
                    ax = axes[row, k]
                    result = getattr(v, method)
                    if result is None:
                        _empty_panel(ax, f"{method}: {v.errors.get(method, 'not computed')}")
                    else:
                        plot.divergence(result, ax=ax)
                    ax.set_title(f"{alias}, {st.label}: {method}", fontsize=9)

        put(
            _draw(
                draw_divergence,
                nrows=2,
                ncols=n,
                section="Divergence curves",
                name=f"divergence-{alias}",
                caption=f"Divergence curves of {alias} for {_states_text(states)}: top, "
                "Rosenstein's mean log divergence with the fitted range shaded and the "
                "fitted line (slope = MLE); bottom, Wolf's running estimate with its "
                "averaging window shaded and the MLE as a dashed line.",
            )
        )


def _sweep_items(m: SweepMap, put: Callable[..., None]) -> None:
    if not isinstance(m, SweepMap):
        raise ValueError(f"sweep_maps must hold SweepMap objects; got {type(m).__name__}.")
    grid = m.to_map()
    where = json.loads(grid.attrs["select"])
    context = ", ".join(f"{k} = {v}" for k, v in where.items())
    what = grid.attrs["variable"] or "the analysed variable"
    units = grid["mle"].attrs.get("units", "")
    caption = m.caption or (
        f"Largest Lyapunov exponent ({grid.attrs['mle_field']}, {units}) of {what} over "
        f"{m.y} and {m.x}"
        + (f" ({context})" if context else "")
        + "; the verdict is written in each cell, blank cells are failed points."
    )

    def draw(axes: Any) -> None:
        plot.chaos_map(grid, mle="mle", x=m.x, y=m.y, ax=axes[0, 0])

    put(
        _draw(
            draw,
            nrows=1,
            ncols=1,
            panel=(6.0, 4.2),
            section="Sweeps",
            name=f"chaos-map-{what}-{m.y}-{m.x}",
            caption=caption,
        )
    )
    frame = grid.to_dataframe()[[c for c in ("mle", "verdict", "status") if c in grid]]
    frame = frame.astype(object)
    put(
        ReportTable(
            caption=f"Values behind the map: {caption[:1].lower()}{caption[1:]}",
            data=frame,
            labels={"mle": f"MLE ({units})" if units else "MLE"},
            section="Sweeps",
        )
    )


def _bifurcation_items(diagrams: Any, put: Callable[..., None]) -> None:
    if isinstance(diagrams, xr.Dataset):
        items: list[tuple[str | None, xr.Dataset]] = [(None, diagrams)]
    elif isinstance(diagrams, Mapping):
        items = [(str(k), v) for k, v in diagrams.items()]
    else:
        items = [(None, d) for d in diagrams]
    for caption, diagram in items:
        if not isinstance(diagram, xr.Dataset) or "diagram_parameter" not in diagram.attrs:
            raise ValueError("bifurcations must be Datasets from chaoskit.bifurcation_diagram.")
        param = diagram.attrs["diagram_parameter"]
        var = diagram.attrs["diagram_variable"]
        kind = diagram.attrs.get("section_kind", "section")

        def draw(axes: Any, d: xr.Dataset = diagram) -> None:
            plot.bifurcation(d, ax=axes[0, 0])

        put(
            _draw(
                draw,
                nrows=1,
                ncols=1,
                panel=(6.0, 4.0),
                section="Sweeps",
                name=f"bifurcation-{var}-{param}",
                caption=caption
                or f"Bifurcation diagram: {kind} points of {var} against "
                f"{param}; one point set per run (a period-k response gives k points).",
            )
        )


def _provenance_items(
    states: list[_State],
    *,
    specs: list[VariableSpec],
    created: str,
    title: str,
    command: str | None,
    settings: Mapping[str, Any],
    parameters: Mapping[str, Any] | None,
) -> list[Any]:
    if command is None:
        command = shlex.join([Path(sys.argv[0]).name, *sys.argv[1:]]) if sys.argv else ""
    info = {"title": title, "created (UTC)": created, "command": command, **_versions()}
    items: list[Any] = [
        ReportTable(
            caption="Provenance: when and how the report was made, and the package versions.",
            data=pd.DataFrame({"value": list(info.values())}, index=pd.Index(info, name="item")),
            section=PROVENANCE,
        )
    ]
    if states:
        rows = {}
        for st in states:
            index = "time" if "time" in st.view.coords else "step"
            t = st.view[index].values
            dt = _sampling_step(st.view)
            rows[st.label] = {
                "source": st.source,
                "title": st.title,
                "scene": st.scene_name or (MISSING if st.scene is None else "yes"),
                "samples after discard": st.original_samples,
                "stride": st.stride,
                "samples analysed": int(t.size),
                "sampling interval": dt,
                "start": float(t[0]),
                "stop": float(t[-1]),
            }
        frame = pd.DataFrame.from_dict(rows, orient="index").astype(object)
        frame.index.name = "state"
        items.append(
            ReportTable(
                caption="Inputs: one trajectory per state; sampling interval, start and stop "
                "in the unit of the index (s for time).",
                data=frame,
                section=PROVENANCE,
            )
        )
        items.append(
            ReportTable(
                caption="Analysis settings.",
                data=pd.DataFrame(
                    {"value": [_value_text(v) for v in settings.values()]},
                    index=pd.Index(list(settings), name="setting"),
                ),
                section=PROVENANCE,
            )
        )
    if parameters:
        items.append(
            ReportTable(
                caption="Parameters of the run (as given by the caller).",
                data=pd.DataFrame(
                    {"value": [_value_text(v) for v in parameters.values()]},
                    index=pd.Index([str(k) for k in parameters], name="parameter"),
                ),
                section=PROVENANCE,
            )
        )
    seen: dict[str, list[str]] = {}
    for st in states:
        if st.scene:
            seen.setdefault(str(st.scene), []).append(st.label)
    for scene, owners in seen.items():
        items.append(
            ReportCode(
                caption=f"Scene of {', '.join(owners)} (JSON from the trajectory's scene "
                "attribute).",
                text=_pretty_json(scene),
                language="json",
            )
        )
    for st in states:
        if st.history.strip():
            items.append(ReportCode(caption=f"Processing history of {st.label}.", text=st.history))
    return items
