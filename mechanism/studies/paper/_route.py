"""The report's route to chaos of the rigid scene over crank speed: which bifurcation
opens each chaotic window and what coexists at 150 rpm, from a stored result.

The result is computed once by ``benchmarks/continuation.py`` (periodic orbits followed
over crank speed from a seed in every regular stretch of the orbit diagram, both ways,
each window edge located to 0.5 rpm; the basins of attraction at 150 rpm from
``benchmarks/basins.py``) and shipped as ``data/route_rigid.json`` in this package: a
continuation over 30 – 300 rpm costs minutes of CPU, more than a quick study has.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pandas as pd

import chaoskit

__all__ = ["RECOMPUTE", "ROUTE_DATA", "TITLE", "route_section", "stored_route"]

#: the stored result
ROUTE_DATA = Path(__file__).parent / "data" / "route_rigid.json"
#: how to recompute it (from the repository's root)
RECOMPUTE = (
    "NUMBA_NUM_THREADS=1 python benchmarks/continuation.py sweep --start 30 --stop 300 "
    "--step 2 --locate 0.5 --figure (writes data/route_rigid.json of "
    "mechanism/studies/paper; the basins at 150 rpm: python benchmarks/basins.py)"
)
#: the section's heading
TITLE = "Route to chaos over crank speed (rigid scene)"
_KEYS = ("scene", "span_rpm", "windows", "branches", "coexistence", "cost")


def stored_route(path: Path | None = None) -> dict[str, Any]:
    """The stored route of the rigid scene (``data/route_rigid.json``).

    Raises
    ------
    ValueError
        When the file is not such a result (a key missing).
    """
    data = json.loads((path or ROUTE_DATA).read_text(encoding="utf-8"))
    missing = [k for k in _KEYS if k not in data]
    if missing:
        raise ValueError(f"{path or ROUTE_DATA} is not a stored route: no {', '.join(missing)}.")
    return data


def _edge(edge: dict[str, Any] | None) -> str:
    if not edge:
        return "none located"
    lo, hi = edge["bracket_rpm"]
    where = "end of a branch" if edge["branch_end"] else "on a branch"
    return (
        f"{edge['kind']} at {edge['rpm']:.2f} rpm [{lo:.2f}, {hi:.2f}] "
        f"({where} of period {edge['period']})"
    )


def _window_table(data: dict[str, Any]) -> chaoskit.ReportTable:
    rows = []
    for w in data["windows"]:
        lo, hi = w["rpm"]
        rows.append(
            {
                "chaotic window (rpm)": f"{lo:.1f} – {hi:.1f}",
                "opened from below by": _edge(w.get("onset")),
                "regular motion above it ends in": _edge(w.get("closing")),
            }
        )
    frame = pd.DataFrame(rows).set_index("chaotic window (rpm)")
    return chaoskit.ReportTable(
        caption="Chaotic windows of the rigid scene's orbit diagram (95 % interval of the "
        "largest Lyapunov exponent above 0) and the located points of the followed "
        "periodic orbits at their edges; brackets are the last converged and first "
        "failed speeds (branch ends) or the bisection's last bracket.",
        data=frame,
        section=TITLE,
    )


def _coexistence(data: dict[str, Any]) -> str:
    co = data["coexistence"]
    stable = co.get("stable_orbits_followed", [])
    orbits = (
        "no stable periodic orbit was followed there"
        if not stable
        else "stable periodic orbits followed there: " + ", ".join(stable)
    )
    basins = co.get("basins")
    if not basins:
        return f"At {co['rpm']:g} rpm {orbits}; the basins were not computed."
    periodic = int(basins["periodic"])
    verdict = (
        "nothing periodic coexists with the chaotic motion"
        if periodic == 0
        else f"{periodic} starts settle on a periodic motion beside the chaotic one"
    )
    return (
        f"At {co['rpm']:g} rpm {verdict}: of {basins['starts']} starts (journal at rest, "
        f"eccentricity inside {basins['extent']:g} of the clearance, {basins['grid']} grid, "
        f"{basins['revolutions']} revolutions) {periodic} settle on a period up to "
        f"{basins['max_period']} and {basins['undetermined']} stay undetermined; {orbits}."
    )


def route_section(data: dict[str, Any] | None = None) -> chaoskit.ReportSection:
    """The report section on the rigid scene's route to chaos over crank speed.

    Parameters
    ----------
    data : dict, optional
        A stored route (default :func:`stored_route`).
    """
    data = stored_route() if data is None else data
    lo, hi = data["span_rpm"]
    sentences = []
    for w in data["windows"]:
        a, b = w["rpm"]
        onset = w.get("onset")
        closing = w.get("closing")
        where = f"{a:.0f} – {b:.0f} rpm" if round(a) != round(b) else f"at {a:.0f} rpm"
        text = f"The chaotic window {where} is opened by "
        text += f"the {onset['kind']} at {onset['rpm']:.2f} rpm" if onset else "no located point"
        if closing and closing["rpm"] < b:
            text += (
                f"; going down from the regular motion above it, a stable period-"
                f"{closing['period']} orbit persists into the window down to "
                f"{closing['rpm']:.2f} rpm, where it ends in the {closing['kind']}: from "
                f"{closing['rpm']:.0f} to {b:.0f} rpm it coexists with the chaotic motion "
                "that the orbit diagram's runs from the scene's start settle on"
            )
        elif closing:
            how = (
                "abruptly (no multiplier near +-1, no grazing margin closing)"
                if closing["kind"] == "end"
                else f"in the {closing['kind']}"
            )
            text += (
                f"; going down from the regular motion above it, the periodic orbit ends "
                f"{how} at {closing['rpm']:.2f} rpm"
            )
        spans = [f"{x:.1f} – {y:.1f} rpm" for x, y in w.get("stable_inside", [])]
        if spans:
            text += (
                "; stable periodic orbits were followed inside it over "
                + ", ".join(spans)
                + " (the orbit diagram's chaos is the motion from the scene's start)"
            )
        sentences.append(text + ".")
    cost = data["cost"]
    return chaoskit.ReportSection(
        title=TITLE,
        text=(
            f"Periodic orbits of the rigid scene ({data['scene']}) followed over crank "
            f"speed from {lo:g} to {hi:g} rpm, from a settled run in every regular stretch "
            "of the orbit diagram and both ways, each located edge bracketed to "
            f"{data['locate_rpm']:g} rpm. " + " ".join(sentences) + " " + _coexistence(data)
        ),
        items=(_window_table(data),),
        footer=(
            f"Stored result ({cost['date']}: {cost['cpu_s']:.0f} s of CPU, "
            f"{cost['orbit_solves']} orbit solves, {cost.get('processes', 1)} "
            f"process(es)). {data.get('note', '')} Recompute: {RECOMPUTE}."
        ),
    )
