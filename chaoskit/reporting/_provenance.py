"""The provenance section of a report: when and how it was made, package versions, the
inputs, the analysis settings, the caller's parameters, scenes and processing histories."""

from __future__ import annotations

import json
import platform
import shlex
import sys
from collections.abc import Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

import pandas as pd

from .._selection import VariableSpec
from .._version import __version__
from ._content import MISSING, ReportCode, ReportTable, format_number
from ._model import PROVENANCE
from ._states import State, sampling_step

__all__ = ["provenance_items"]

_PACKAGES = ("numpy", "scipy", "numba", "xarray", "pandas", "matplotlib", "jinja2", "h5netcdf")


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


def provenance_items(
    states: list[State],
    *,
    specs: list[VariableSpec],
    created: str,
    title: str,
    command: str | None,
    settings: Mapping[str, Any],
    parameters: Mapping[str, Any] | None,
) -> list[Any]:
    """The tables and code blocks of the provenance section, in print order."""
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
            dt = sampling_step(st.view)
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
