"""The states of a report: each trajectory loaded, cut, subsampled and its series picked.

One :class:`State` per trajectory (e.g. before and after wear) holds the analysed view and
its verdicts; the display units convert a length variable for the figures only.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .._io import load_trajectory
from .._portraits import DERIVATIVE_NAMES
from .._selection import VariableSpec, parse_variable, select_series
from ..verdict import MotionVerdict

__all__ = [
    "LENGTH_UNITS",
    "State",
    "check_display_units",
    "display_view",
    "normalise_trajectories",
    "normalise_variables",
    "prepare_state",
    "sampling_step",
    "states_text",
]


@dataclass(kw_only=True)
class State:
    """One analysed trajectory: its view (the picked series), verdicts and provenance."""

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


def normalise_trajectories(
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


def normalise_variables(variables: Any) -> list[VariableSpec]:
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


def prepare_state(
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


#: Length units a figure can show a variable in, in metres.
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "um": 1e-6, "nm": 1e-9}


def check_display_units(
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


def display_view(view: xr.Dataset, display_units: Mapping[str, str]) -> xr.Dataset:
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


def sampling_step(view: xr.Dataset) -> float:
    index = "time" if "time" in view.coords else "step"
    t = np.asarray(view[index].values, dtype=np.float64)
    return float(np.median(np.diff(t))) if t.size > 1 else float("nan")


def states_text(states: list[State]) -> str:
    names = [st.label for st in states]
    if len(names) == 1:
        return names[0]
    if len(names) == 2:
        return f"{names[0]} (left) and {names[1]} (right)"
    return ", ".join(names[:-1]) + f" and {names[-1]}, left to right"
