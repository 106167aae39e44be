"""The analysis figures of a report: phase portraits, Poincaré-type maps and divergence
curves, one figure per variable with one panel per state.

The panels are drawn with :mod:`chaoskit.plot`; the figures show each variable in its
display unit while the analysis stays in SI units.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import xarray as xr

from .. import plot
from .._portraits import phase_portrait
from .._selection import VariableSpec
from ..sections import poincare_section, stroboscopic_map
from ._answer import plural
from ._content import ReportFigure, format_number
from ._states import State, display_view, states_text

__all__ = ["analysis_figures", "report_figure"]


def report_figure(
    draw: Callable[[Any], None],
    *,
    nrows: int,
    ncols: int,
    caption: str,
    name: str,
    section: str,
    panel: tuple[float, float] = (4.2, 3.4),
) -> ReportFigure:
    """A captioned figure of ``nrows`` x ``ncols`` panels drawn by ``draw(axes)``."""
    fig = plot.panel_figure(draw, nrows=nrows, ncols=ncols, panel=panel)
    return ReportFigure.from_matplotlib(fig, caption=caption, name=name, section=section)


def _unit_suffix(units: Any) -> str:
    return f" [{units}]" if units not in (None, "", "1", "unknown") else ""


def _rate_units(units: Any) -> str:
    if units in (None, "", "1", "unknown"):
        return "s-1" if units in ("", "1") else ""
    return f"{units} s-1"


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


def analysis_figures(
    states: list[State],
    specs: list[VariableSpec],
    put: Callable[..., None],
    *,
    kind: str,
    drive_period: float | None,
    phase: VariableSpec | None,
    display_units: Mapping[str, str],
) -> None:
    """Put the phase portraits (flows only), the maps and the divergence curves of every
    variable, one panel per state."""
    phase_alias = None if phase is None else phase.alias
    # the figures show each variable in its display unit; the analysis stays in SI
    shown = {st.label: display_view(st.view, display_units) for st in states}
    for spec in specs:
        if kind != "map":
            put(_portrait_figure(states, spec, shown))
        put(
            _section_figure(states, spec, shown, drive_period=drive_period, phase_alias=phase_alias)
        )
        put(_divergence_figure(states, spec))


def _grid(n: int) -> tuple[int, int]:
    ncols = min(n, 3)
    return math.ceil(n / ncols), ncols


def _portrait_figure(
    states: list[State], spec: VariableSpec, shown: Mapping[str, xr.Dataset]
) -> ReportFigure:
    """Phase portraits (x, dx/dt) of one variable, one panel per state."""
    alias = spec.alias
    n = len(states)

    def draw_portraits(axes: Any) -> None:
        for k, ax in enumerate(axes.flat):
            if k >= n:
                ax.set_visible(False)
                continue
            st = states[k]
            ax.set_title(f"{alias}: {st.label}", fontsize=9)
            try:
                portrait = phase_portrait(shown[st.label], variable=alias)
            except ValueError as exc:  # e.g. too short for the derivative filter
                plot.blank_panel(ax, f"no phase portrait: {exc}")
                continue
            plot.phase_portrait(portrait, ax=ax)
            ax.set_title(f"{alias}: {st.label}", fontsize=9)
            units = shown[st.label][alias].attrs.get("units")
            plot.label_axes(
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
    nrows, ncols = _grid(n)
    return report_figure(
        draw_portraits,
        nrows=nrows,
        ncols=ncols,
        section="Phase portraits",
        name=f"phase-portrait-{alias}",
        caption=f"Phase portraits of {alias} ({spec.spec}) against its rate of "
        f"change, {how}, for {states_text(states)}.",
    )


def _section_figure(
    states: list[State],
    spec: VariableSpec,
    shown: Mapping[str, xr.Dataset],
    *,
    drive_period: float | None,
    phase_alias: str | None,
) -> ReportFigure:
    """The Poincaré-type map of one variable (the points its verdict used), one panel per
    state."""
    alias = spec.alias
    n = len(states)
    how: dict[str, str] = {}

    def draw_sections(axes: Any) -> None:
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
                plot.blank_panel(ax, f"no section: {exc}")
            if sec is not None:
                title += f", {_draw_section(ax, sec, view, alias)}"
            ax.set_title(title, fontsize=9)

    nrows, ncols = _grid(n)
    fig = report_figure(
        draw_sections,
        nrows=nrows,
        ncols=ncols,
        section="Poincaré and stroboscopic maps",
        name=f"section-{alias}",
        caption="pending",
    )
    # the caption names the kind of map, known only once the panels are drawn
    return dataclasses.replace(
        fig,
        caption=f"Poincaré-type map of {alias}: "
        f"{how.get('text', 'no points')}, for {states_text(states)}; "
        "the points the verdict's section used (their number is the evidence "
        "table's section points).",
    )


def _draw_section(ax: Any, sec: xr.Dataset, view: xr.Dataset, alias: str) -> str:
    """Draw the section points ``sec`` of ``alias`` on ``ax``; their count as text."""
    count = sec.sizes.get("crossing", 0)
    one = [v for v in sec.data_vars if sec[v].dims == ("crossing",)]
    points = count - 1 if len(one) == 1 else count  # a return map: pairs
    if count < 2:
        plot.blank_panel(ax, "fewer than 2 section points")
    else:
        plot.poincare(sec, ax=ax)
        units = view[alias].attrs.get("units")
        if len(one) == 1 or f"{alias}_next" in sec:
            plot.label_axes(
                ax,
                f"{alias}(n){_unit_suffix(units)}",
                f"{alias}(n+1){_unit_suffix(units)}",
            )
        else:
            plot.label_axes(
                ax,
                f"{alias}{_unit_suffix(units)}",
                f"d{alias}/dt{_unit_suffix(_rate_units(units))}",
            )
    return plural(points, "point")


def _divergence_figure(states: list[State], spec: VariableSpec) -> ReportFigure:
    """Divergence curves of one variable: Rosenstein on top, Wolf below, one column per
    state."""
    alias = spec.alias
    n = len(states)

    def draw_divergence(axes: Any) -> None:
        for k in range(n):
            st = states[k]
            v = st.verdicts[alias]
            for row, method in enumerate(("rosenstein", "wolf")):
                ax = axes[row, k]
                result = getattr(v, method)
                if result is None:
                    plot.blank_panel(ax, f"{method}: {v.errors.get(method, 'not computed')}")
                else:
                    plot.divergence(result, ax=ax)
                ax.set_title(f"{alias}, {st.label}: {method}", fontsize=9)

    return report_figure(
        draw_divergence,
        nrows=2,
        ncols=n,
        section="Divergence curves",
        name=f"divergence-{alias}",
        caption=f"Divergence curves of {alias} for {states_text(states)}: top, "
        "Rosenstein's mean log divergence with the fitted range shaded and the "
        "fitted line (slope = MLE); bottom, Wolf's running estimate with its "
        "averaging window shaded and the MLE as a dashed line.",
    )
