"""The joint evidence of a motion: drive followers, the joint section, the mixed embedding."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr
from scipy.interpolate import CubicSpline

from ..sections import stroboscopic_map
from ._result import Verdict

#: A drive follower's stroboscopic set is one point to round-off: its RMS radius is at most
#: this fraction of the variable's standard deviation (a response converged to a period-1
#: orbit meets it as well, and is then periodic with the drive, which is what it says).
DRIVE_TOL = 1e-6


def is_drive_follower(v: Verdict) -> bool:
    """Periodic with period 1 and a stroboscopic set that is one point to round-off."""
    st = v.structure
    return (
        v.kind == "forced"
        and v.label == "periodic"
        and v.period == 1
        and st is not None
        and st.kind == "clusters"
        and st.n_clusters == 1
        and st.cluster_radius <= DRIVE_TOL
    )


def _unit(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    peak = float(np.max(np.abs(x)))
    if peak == 0.0:
        return np.zeros_like(x)  # constant: no spread to scale (never a voter)
    y = x / peak - float(np.mean(x / peak))
    spread = float(np.std(y))
    return y / spread if spread > 0.0 else y


def reference_variable(voters: Mapping[str, Verdict]) -> str:
    """The voter whose section sets the instants of the joint section: most points."""

    def points(name: str) -> int:
        st = voters[name].structure
        return -1 if st is None else st.n_points

    return max(voters, key=points)


def joint_section(
    ds: xr.Dataset,
    voters: Mapping[str, Verdict],
    ref: str,
    *,
    kind: str,
    drive_period: float | None,
    phase_variable: str | None,
) -> tuple[xr.Dataset, np.ndarray]:
    """Every voter (unit spread) at the joint section's instants n and n + 1."""
    names = list(voters)
    scaled = {n: _unit(ds[n].values) for n in names}
    resolution = 0.0  # the instants are samples (maps) or interpolated to 1e-8 (strobes)
    if kind == "map":
        at = np.column_stack([scaled[n] for n in names])
        crossing_time = np.asarray(ds["step"].values, dtype=np.float64)
    elif kind == "forced":
        strobe_in = xr.Dataset(
            {n: ("time", scaled[n]) for n in names}, coords={"time": ds["time"].values}
        )
        if phase_variable is not None:
            strobe_in["__angle"] = ("time", np.asarray(ds[phase_variable].values, float))
            sec = stroboscopic_map(strobe_in, phase_variable="__angle")
        else:
            sec = stroboscopic_map(strobe_in, period=drive_period)
        at = np.column_stack([sec[n].values for n in names])
        crossing_time = np.asarray(sec["time"].values, dtype=np.float64)
    else:
        ref_section = voters[ref].section
        if ref_section is None or "time" not in ref_section.coords:
            raise ValueError(f"no section of {ref!r} to take the joint section's instants from.")
        crossing_time = np.asarray(ref_section["time"].values, dtype=np.float64)
        t = np.asarray(ds["time"].values, dtype=np.float64)
        at = np.column_stack([CubicSpline(t, scaled[n])(crossing_time) for n in names])
        # what the sampling cannot resolve between samples: cubic against linear interpolation
        linear = np.column_stack([np.interp(crossing_time, t, scaled[n]) for n in names])
        resolution = float(np.sqrt(np.mean((at - linear) ** 2))) if at.size else 0.0
    m = max(at.shape[0] - 1, 0)
    data_vars: dict[str, Any] = {}
    for j, n in enumerate(names):
        data_vars[n] = ("crossing", at[:m, j], {"units": "1", "long_name": f"{n} / std"})
        data_vars[f"{n}_next"] = (
            "crossing",
            at[1 : m + 1, j],
            {"units": "1", "long_name": f"{n} / std at the next crossing"},
        )
    sec_ds = xr.Dataset(
        data_vars,
        coords={"crossing": np.arange(m), "time": ("crossing", crossing_time[:m])},
    )
    sec_ds.attrs["interpolation_rms"] = resolution
    sec_ds.attrs["section_kind"] = {
        "map": "iterates of every variable",
        "forced": "stroboscopic map of every variable",
        "flow": f"every variable at the maxima of {ref}",
    }[kind]
    points = np.column_stack([sec_ds[k].values for k in data_vars])
    return sec_ds, points


def mixed_embedding(ds: xr.Dataset, voters: Mapping[str, Verdict]) -> tuple[np.ndarray, int]:
    """Mixed delay vectors of the voters (each at unit spread, its own delay) and the lag
    that tells a flow from a map.

    The dimension is the largest of the voters' embedding dimensions (at least one
    coordinate per variable), shared evenly among the variables (Cao, Mees & Judd 1998).
    """
    names = list(voters)
    lags = [int(voters[n].lag or 1) for n in names]
    total = max([len(names), *[int(voters[n].embedding_dim or 1) for n in names]])
    each = max(1, math.ceil(total / len(names)))
    span = max((each - 1) * lag for lag in lags)
    rows = ds.sizes[next(iter(ds[names[0]].dims))] - span
    if rows < 1:
        raise ValueError("the series is too short for the mixed embedding.")
    columns: list[np.ndarray] = []
    for n, lag in zip(names, lags, strict=True):
        x = _unit(ds[n].values)
        columns.extend(x[i * lag : i * lag + rows] for i in range(each))
    return np.ascontiguousarray(np.column_stack(columns)), max(lags)


def count_bases(voters: Mapping[str, Verdict]) -> int:
    return max(
        (int(v.lines.base_frequencies.size) for v in voters.values() if v.lines is not None),
        default=0,
    )
