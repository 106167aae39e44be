"""Our response tables in the paper's units, from the sweeps' gathered metrics."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd
import xarray as xr

from ._published import (
    CLEARANCES,
    COLUMNS,
    DEFAULT_CLEARANCE,
    FROM_SWEEP,
    MICRO,
    RODS,
    SPEEDS,
)


def metrics_row(point: xr.Dataset) -> dict[str, float]:
    """One sweep point's metrics in the paper's units (rod strains in µε, NaN if rigid)."""
    row: dict[str, float] = {}
    for col, (name, factor) in FROM_SWEEP.items():
        row[col] = float(point[name].values) * factor if name in point else math.nan
    for col, rod in RODS.items():
        value = math.nan
        if "rod_strain_extreme" in point and "rod" in point["rod_strain_extreme"].dims:
            rods = [str(r) for r in point["rod"].values]
            if rod in rods:
                value = float(point["rod_strain_extreme"].sel(rod=rod).values) * MICRO
        row[col] = value
    return row


def table_frame(rows: Mapping[str, Mapping[str, float]], index_name: str) -> pd.DataFrame:
    """A response table: one row per entry of ``rows``, the columns :data:`COLUMNS`."""
    return pd.DataFrame(
        [dict(r) for r in rows.values()],
        index=pd.Index(list(rows), name=index_name),
        columns=list(COLUMNS),
    )


def select_point(ds: xr.Dataset, **sel: Any) -> xr.Dataset:
    """The point of a gathered sweep at ``sel`` (keys the sweep did not vary ignored)."""
    return ds.sel({k: v for k, v in sel.items() if k in ds.dims})


def speed_label(rpm: float) -> str:
    """Row label of a crank speed, e.g. "150 rpm"."""
    return f"{rpm:g} rpm"


def clearance_label(c: float) -> str:
    """Row label of a clearance in m, e.g. "0.2 mm"."""
    return f"{c * 1e3:g} mm"


def response_tables(
    *,
    before: xr.Dataset,
    after: Mapping[float, xr.Dataset],
    convergence: Mapping[int, list[float]],
    elements: Sequence[int],
    paper: Mapping[str, pd.DataFrame],
) -> dict[str, pd.DataFrame]:
    """Our tables keyed like :func:`paper_tables` (all but ``"chaos"``), in the paper's
    units: the before-wear sweep gives the clearance tables and the before-wear row, the
    after-wear sweeps (by speed, rpm) the speed table and the after-wear row (150 rpm), and
    ``convergence`` (rod strains by elements per rod) the convergence table over the
    elements run and the paper's. A missing building block leaves NaN."""
    c0 = DEFAULT_CLEARANCE
    tables: dict[str, pd.DataFrame] = {}
    rows = {
        "before wear": metrics_row(
            select_point(before, **{"joints.C.clearance": c0, "drive.speed_rpm": 150})
        )
    }
    if 150 in after:
        rows["after wear"] = metrics_row(after[150])
    tables["wear"] = table_frame(rows, "state")
    for rpm, key in ((150, "clearance"), (90, "clearance_90rpm")):
        tables[key] = table_frame(
            {
                clearance_label(c): metrics_row(
                    select_point(before, **{"joints.C.clearance": c, "drive.speed_rpm": rpm})
                )
                for c in CLEARANCES
            },
            "clearance",
        )
    tables["speed"] = table_frame(
        {
            speed_label(v): metrics_row(after[v])
            if v in after
            else dict.fromkeys(COLUMNS, math.nan)
            for v in SPEEDS
        },
        "speed",
    )
    rows_elements = sorted(set(elements) | {int(e) for e in paper["convergence"].index})
    tables["convergence"] = pd.DataFrame(
        [convergence.get(n, [math.nan] * len(RODS)) for n in rows_elements],
        index=pd.Index(rows_elements, name="elements"),
        columns=list(RODS),
    )
    return tables
