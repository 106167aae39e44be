"""Wear paths over a scene key in a report: the answer per value first, then the evidence.

:func:`wear_life_section` builds the "Wear life" section (its first lines say, per value,
after how many cycles the motion turns chaotic or that it does not within the path), a
table per value and the four figures of :func:`mechanism.plot_wear_life`;
:func:`wear_life_report` puts it into a :class:`chaoskit.Report` with the parameters and
the provenance (HTML and its Markdown twin).
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
import pandas as pd

import chaoskit
from chaoskit import ReportFigure, ReportSection, ReportTable

from ._wear_life_map import WearLifeMap, format_cycles
from ._wear_life_plot import WEAR_LIFE_VIEWS, plot_wear_life, strobe_spread

__all__ = ["WEAR_LIFE_SECTION", "wear_life_report", "wear_life_section"]

#: Title of the section :func:`wear_life_section` builds.
WEAR_LIFE_SECTION = "Wear life"


def _table(life: WearLifeMap) -> ReportTable:
    ds = life.to_dataset()
    spread = strobe_spread(ds).max("joint", skipna=True)
    rows = []
    for i, label in enumerate(life.labels()):
        path = life.paths[i]
        reached = float(path.checkpoints[-1]) if path is not None and path.checkpoints.size else 0.0
        last = int(np.flatnonzero(ds["checkpoint"].values == reached)[0]) if reached else 0
        chaos = float(ds["cycles_to_chaos"].values[i])
        rows.append(
            {
                "value": label,
                "cycles to chaos": format_cycles(chaos) if math.isfinite(chaos) else "—",
                "confidence": float(ds["chaos_confidence"].values[i]),
                "path": life.statuses[i],
                "cycles reached": reached,
                "bearing depth (µm)": 1e6
                * float(ds["max_wear_depth"].sel(surface="bearing").max("joint").values[i, last]),
                "λ₁ (1/s)": float(ds["lyapunov_exponent"].values[i, last]),
                "low": float(ds["lyapunov_ci_low"].values[i, last]),
                "high": float(ds["lyapunov_ci_high"].values[i, last]),
                "motion": str(ds["motion"].values[i, last]) or "—",
                "strobe spread (µm)": 1e6 * float(spread.values[i, last]),
                "CPU s": float(ds["cpu_time"].values[i]),
            }
        )
    frame = pd.DataFrame(rows).set_index("value")
    notes = [
        f"{label}: {reason.rstrip('.')}"  # the notes are joined by "; "
        for label, reason, status in zip(life.labels(), life.reasons, life.statuses, strict=True)
        if status != "complete"
    ]
    return ReportTable(
        caption=(
            "Per value: the first chaotic checkpoint (exponent interval above 0 and a chaotic "
            "verdict) with the verdict's confidence, and the state at the last checkpoint "
            "reached"
        ),
        data=frame,
        intervals={"λ₁ (1/s)": ("low", "high")},
        formats={"confidence": ".2f", "cycles reached": ".6g", "CPU s": ".0f"},
        notes="; ".join(notes),
        section=WEAR_LIFE_SECTION,
    )


def _figures(life: WearLifeMap) -> list[ReportFigure]:
    import matplotlib.pyplot as plt  # plotting is optional

    figures = []
    for view, what in WEAR_LIFE_VIEWS.items():
        drawn = plot_wear_life(life, view=view)
        fig = (drawn[0] if isinstance(drawn, list) else drawn).figure
        figures.append(
            ReportFigure.from_matplotlib(
                fig,
                caption=f"{what[0].upper()}{what[1:]} against the cycles of wear.",
                name=f"wear-life-{view}",
                section=WEAR_LIFE_SECTION,
            )
        )
        plt.close(fig)
    return figures


def wear_life_section(life: WearLifeMap) -> ReportSection:
    """The "Wear life" report section of wear paths over a scene key.

    Its text starts with one sentence per value (:meth:`mechanism.WearLifeMap.answers`:
    "at 150 rpm the motion turns chaotic after 12 000 cycles (confidence 0.80)"), then a
    table per value and the four views of :func:`mechanism.plot_wear_life` (exponent,
    strobe spread, orbit diagram, wear depth); the footer holds the path settings.
    """
    if not isinstance(life, WearLifeMap):
        raise TypeError(f"life must be a mechanism.WearLifeMap; got {type(life).__name__}.")
    ds = life.to_dataset()
    # an answer may end with a reason's own full stop
    text = " ".join(f"{a[0].upper()}{a[1:].rstrip('.')}." for a in life.answers())
    footer = (
        f"{len(life.values)} wear paths of scene {life.scene.name!r} over {life.parameter}, "
        f"{format_cycles(life.cycles)} cycles each, checkpoints at "
        f"{', '.join(format_cycles(n) for n in life.checkpoints)} cycles; wear per cycle "
        f"averaged over {ds.attrs.get('averaged_revolutions', '—')} revolutions, increments "
        f"of at most {ds.attrs.get('max_depth_increment', '—')} of the clearance; at each "
        f"checkpoint {ds.attrs.get('analysis_revolutions', '—')} revolutions analysed and "
        f"the exponent over {ds.attrs.get('lyapunov_revolutions', '—')} revolutions "
        f"({ds.attrs.get('lyapunov_discard', '—')} left out){_first_run(ds)}."
    )
    if not ds.attrs.get("exponent", 1):
        footer += " No exponent was computed: no checkpoint can be called chaotic."
    return ReportSection(
        title=WEAR_LIFE_SECTION,
        items=(_table(life), *_figures(life)),
        text=text,
        footer=footer,
    )


def _first_run(ds: Any) -> str:
    """The exponent's first, shorter run, when it was tried (stores of older runs lack it)."""
    first, full = ds.attrs.get("lyapunov_first_revolutions"), ds.attrs.get("lyapunov_revolutions")
    if first is None or full is None or not float(first) < float(full):
        return ""
    return (
        f", or over the first {float(first):g} when their 95 % interval lies beyond zero by "
        "its half-width"
    )


def wear_life_report(
    life: WearLifeMap,
    *,
    title: str | None = None,
    output: str | os.PathLike[str] | None = None,
    command: str | None = None,
) -> Any:
    """A :class:`chaoskit.Report` of wear paths: the "Wear life" section, then provenance.

    Parameters
    ----------
    life
        The result of :func:`mechanism.wear_life_map`.
    title
        Page title (default names the scene and the key).
    output
        If given, write the HTML page there and its Markdown twin beside it.
    command
        The command that produced it (default: this process's command line).

    Returns
    -------
    chaoskit.Report
    """
    section = wear_life_section(life)
    parameters = {
        "scene": life.scene.name,
        "parameter": life.parameter,
        "values": list(life.values),
        "cycles": life.cycles,
        "checkpoints": [float(n) for n in life.checkpoints],
        "store": life.store or "",
    }
    rep = chaoskit.report(
        None,
        title=title or f"Wear life of scene {life.scene.name!r} over {life.parameter}",
        extras=chaoskit.ReportExtras(parameters=parameters, command=command),
    )
    rep = rep.with_sections(section, before=rep.sections[0].title if rep.sections else None)
    if output is not None:
        rep.write(output)
    return rep
