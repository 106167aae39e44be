"""Views of a gathered sweep: stroboscopic points per grid point and chaos maps."""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from chaoskit.contract import stamp

from . import _store
from ._analysis import Analysis
from ._gather import load_sweep
from ._point import SOURCE


def _as_sweep(data: Any) -> xr.Dataset:
    if isinstance(data, xr.Dataset):
        if "status" not in data or "trajectory_file" not in data:
            raise ValueError("expected the Dataset returned by mechanism.sweep (or its store).")
        return data
    return load_sweep(data)


def _grid_dims(ds: xr.Dataset) -> list[str]:
    if "grid" in ds.attrs:
        return list(json.loads(ds.attrs["grid"]))
    return [str(d) for d in ds["status"].dims]


def stroboscopic_points(
    data: Any,
    *,
    variables: Sequence[str] | None = None,
    joint: str | None = None,
    discard_revolutions: float | None = None,
    phase: float = 0.0,
    store: str | os.PathLike[str] | None = None,
) -> xr.Dataset:
    """Stroboscopic points (one per crank revolution) of every grid point of a sweep.

    For each successful point, the trajectory is sampled where the unwrapped ``crank_angle``
    passes :math:`\\varphi + 2\\pi k` (:func:`chaoskit.stroboscopic_map`, interpolated), for
    revolutions :math:`k \\ge` ``discard_revolutions``. Plotted against one swept parameter
    (the others fixed) this is the bifurcation diagram of the sweep; a period-:math:`n`
    response gives :math:`n` distinct values, chaos a scattered set.

    Parameters
    ----------
    data
        The Dataset returned by :func:`sweep`, or its store folder.
    variables
        Trajectory variables to sample (default: the sweep's analysis variables, or the
        journal eccentricities when it analysed none).
    joint
        Clearance joint for variables with a ``joint`` dimension (default: the first).
    discard_revolutions
        Revolutions treated as transient (default: the sweep's ``discard_revolutions``).
    phase
        Crank phase :math:`\\varphi` of the strobe, rad.
    store
        Store folder, when ``data`` is a Dataset that has been moved (default: its attrs).

    Returns
    -------
    xarray.Dataset
        The variables over the grid dimensions and ``crossing`` (whose coordinate is the
        crank revolution :math:`k`), NaN where a point has no such revolution (failed, or a
        shorter run), with the strobe instants as coordinate ``time`` (s). The ``crossing``
        layout is that of :func:`chaoskit.stroboscopic_map`, so one grid line of it goes
        straight into :func:`chaoskit.bifurcation_diagram` and
        :func:`chaoskit.plot.bifurcation`.

    Examples
    --------
    >>> import chaoskit, mechanism
    >>> pts = mechanism.stroboscopic_points("sweep-store")  # doctest: +SKIP
    >>> line = pts.sel({"joints.C.clearance": 2e-4})  # doctest: +SKIP
    >>> diagram = chaoskit.bifurcation_diagram(  # doctest: +SKIP
    ...     line, parameter="drive.speed_rpm", variable="eccentricity_x")
    >>> chaoskit.plot.bifurcation(diagram)  # doctest: +SKIP
    """
    ds = _as_sweep(data)
    root = Path(store) if store is not None else Path(ds.attrs.get("store", "."))
    settings = json.loads(ds.attrs.get("analysis", "{}"))
    if variables is None:
        variables = settings.get("variables") or Analysis().variables
    names = [variables] if isinstance(variables, str) else list(variables)
    if not names:
        raise ValueError("no variables to sample; pass variables=[...].")
    if discard_revolutions is None:
        discard_revolutions = float(settings.get("discard_revolutions", 0.0))
    dims = _grid_dims(ds)
    shape = tuple(ds.sizes[d] for d in dims)
    files = np.asarray(ds["trajectory_file"].transpose(*dims).values)
    status = np.asarray(ds["status"].transpose(*dims).values)

    per_point: dict[tuple[int, ...], xr.Dataset] = {}
    attrs: dict[str, dict[str, Any]] = {}
    for index in np.ndindex(shape):
        if str(status[index]) != "ok" or not str(files[index]):
            continue
        traj = chaoskit.load_trajectory(_store.point_file(root, str(files[index])))
        columns = {}
        for name in names:
            if name not in traj:
                raise ValueError(
                    f"variable {name!r} is not in the trajectories; available: "
                    f"{sorted(map(str, traj.data_vars))}."
                )
            var = traj[name]
            if "joint" in var.dims:
                var = var.sel(joint=joint) if joint is not None else var.isel(joint=0)
            columns[name] = var.drop_vars([c for c in var.coords if c != "time"])
            attrs.setdefault(name, dict(traj[name].attrs))
        columns["crank_angle"] = traj["crank_angle"]
        sub = xr.Dataset(columns, attrs=traj.attrs)
        pts = chaoskit.stroboscopic_map(
            sub, phase_variable="crank_angle", phase=phase, coords=names
        )
        keep = np.flatnonzero(np.asarray(pts["drive_cycle"].values) >= discard_revolutions)
        per_point[index] = pts.isel(crossing=keep)
    cycles = sorted({int(k) for p in per_point.values() for k in p["drive_cycle"].values})
    position = {k: i for i, k in enumerate(cycles)}
    full = (*shape, len(cycles))
    times = np.full(full, np.nan)
    values = {name: np.full(full, np.nan) for name in names}
    for index, pts in per_point.items():
        slots = np.array([position[int(k)] for k in pts["drive_cycle"].values])
        where: tuple[Any, ...] = (*index, slots)
        times[where] = pts["time"].values
        for name in names:
            values[name][where] = pts[name].values
    dims_out = (*dims, "crossing")
    coords: dict[str, Any] = {d: ds[d] for d in dims}
    coords["crossing"] = xr.DataArray(
        np.asarray(cycles, dtype=np.int64),
        dims="crossing",
        attrs={"units": "1", "long_name": "crank revolution k (crank angle = phase + 2 pi k)"},
    )
    coords["time"] = xr.DataArray(
        times, dims=dims_out, attrs={"units": "s", "long_name": "time of the stroboscopic sample"}
    )
    result = xr.Dataset(
        {
            name: (dims_out, values[name], attrs.get(name, {"units": "unknown", "long_name": name}))
            for name in names
        },
        coords=coords,
    )
    return stamp(
        result,
        title="stroboscopic points of a parameter sweep (one per crank revolution)",
        source=SOURCE,
        history=(
            f"mechanism.stroboscopic_points(variables={names}, phase={phase!r}, "
            f"discard_revolutions={discard_revolutions!r})"
        ),
        extra={
            "section_kind": "stroboscopic",
            "phase_variable": "crank_angle",
            "drive_phase": float(phase),
            "discard_revolutions": float(discard_revolutions),
        },
    )


def chaos_map(
    data: Any,
    *,
    x: str,
    y: str,
    variable: str | None = None,
    mle: str | None = None,
    verdict: str | None = None,
    select: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """Maps of the largest Lyapunov exponent and the verdict over two swept parameters.

    Parameters
    ----------
    data
        The Dataset returned by :func:`sweep`, or its store folder.
    x, y
        The two grid keys spanning the map (e.g. ``"drive.speed_rpm"`` and
        ``"joints.C.clearance"``).
    variable
        Analysed variable whose own verdict is mapped. Default: the motion verdict of each
        point (``motion_label``, with the exponent of the mixed embedding ``motion_mle``
        and ``motion_confidence``) when the sweep analysed several variables, else the
        first variable.
    mle, verdict
        Names of the analysis fields holding the MLE and the verdict label (default: as
        above, or the first field whose name starts with ``mle`` and the field ``label`` or
        ``verdict``).
    select
        Values for the other grid keys (``{"wear": "before"}``); required when there are any.

    Returns
    -------
    xarray.Dataset
        ``mle(y, x)``, ``verdict(y, x)`` (text) and ``status(y, x)``, and
        ``confidence(y, x)`` for the motion verdict; plot with ``ds["mle"].plot()`` or
        ``chaoskit.plot``. The attribute ``variable`` says what was mapped (``"motion"``
        for the motion verdict).
    """
    ds = _as_sweep(data)
    dims = _grid_dims(ds)
    for key in (x, y):
        if key not in dims:
            raise ValueError(f"{key!r} is not a grid key of this sweep; grid keys: {dims}.")
    if x == y:
        raise ValueError("x and y must be two different grid keys.")
    others = [d for d in dims if d not in (x, y)]
    select = dict(select or {})
    missing = [d for d in others if d not in select]
    if missing:
        raise ValueError(f"select a value for the other grid keys {missing} (select={{...}}).")
    if "variable" not in ds.dims:
        raise ValueError("this sweep has no analysis fields (it ran with Analysis(variables=())).")
    motion = variable is None and verdict is None and "motion_label" in ds
    fields = [str(k) for k, v in ds.data_vars.items() if "variable" in v.dims]
    if motion:
        variable, verdict = "motion", "motion_label"
        mle = "motion_mle" if mle is None else mle
        fields = [str(k) for k, v in ds.data_vars.items() if str(k).startswith("motion_")]
    variable = variable if variable is not None else str(ds["variable"].values[0])
    if mle is None:
        mle = next((f for f in fields if f.lower().startswith("mle")), None)
    if verdict is None:
        verdict = next((f for f in ("label", "verdict") if f in fields), None)
    for what, name in (("mle", mle), ("verdict", verdict)):
        if name is None or name not in ds:
            raise ValueError(f"no {what} field found; pass {what}= one of {fields}.")
    assert mle is not None and verdict is not None
    picked = ds.sel({k: select[k] for k in others})

    def grid(name: str) -> xr.DataArray:
        arr = picked[name]
        if "variable" in arr.dims:
            arr = arr.sel(variable=variable)
        return arr.transpose(y, x)

    maps = {"mle": grid(mle), "verdict": grid(verdict), "status": grid("status")}
    if motion:
        maps["confidence"] = grid("motion_confidence")
    out = xr.Dataset(maps)
    return stamp(
        out,
        title=f"largest Lyapunov exponent and verdict of {variable} over ({y}, {x})",
        source=SOURCE,
        history=f"mechanism.chaos_map(x={x!r}, y={y!r}, variable={variable!r}, mle={mle!r})",
        extra={"variable": variable, "mle_field": mle, "verdict_field": verdict},
    )
