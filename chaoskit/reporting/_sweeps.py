"""The Sweeps section of a report: chaos maps over two swept parameters with the values
behind them, and bifurcation diagrams."""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any

import xarray as xr

from .. import plot
from ._analysis_figures import report_figure
from ._content import ReportTable
from ._model import SweepMap

__all__ = ["bifurcation_items", "sweep_items"]


def sweep_items(m: SweepMap, put: Callable[..., None]) -> None:
    """Put the chaos map of ``m`` and the table of the values behind it."""
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
        report_figure(
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


def bifurcation_items(diagrams: Any, put: Callable[..., None]) -> None:
    """Put one figure per bifurcation diagram (a Dataset, a sequence or ``{caption: Dataset}``)."""
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
            report_figure(
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
