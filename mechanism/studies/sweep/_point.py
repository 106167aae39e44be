"""The work of one grid point, on a worker: build the scene, simulate, write the
trajectory and a summary (status, response metrics, ``chaoskit.analyze`` fields).

Failure is data: a point that raises, or whose simulation does not succeed, is
recorded with ``status`` ("failed" or "diverged") and ``message``.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from chaoskit.contract import __version__
from mechanism.core import simulate
from mechanism.core.record import response_metrics, window_start

from . import _store
from ._analysis import Analysis
from ._revolution import simulated_span
from ._transforms import GridTransform

STATUSES: tuple[str, ...] = ("ok", "failed", "diverged")
SOURCE = f"mechanism (chaoskit {__version__})"


@dataclass(frozen=True, kw_only=True)
class PointTask:
    """Everything a worker needs for one grid point (pickled to the worker)."""

    point_id: str
    params: tuple[tuple[str, Any], ...]
    scene: Any
    transforms: tuple[GridTransform, ...]
    revolutions: float
    analysis: Analysis
    store: str
    simulator: Callable[..., xr.Dataset]


def simulate_point(scene: Any, *, revolutions: float) -> xr.Dataset:
    """The simulation of one grid point (the one place a test stand-in replaces)."""
    # failure as data: a failed integration returns its samples so far and solver_status < 0;
    # a motor-driven crank has no period: it runs for as many no-load periods
    return simulate(scene, throw=False, **simulated_span(scene, revolutions))


def _build_scene(task: PointTask) -> Any:
    changes = {k: v for k, v in task.params if k not in {t.name for t in task.transforms}}
    scene = task.scene.replace(changes) if changes else task.scene
    by_name = {t.name: t for t in task.transforms}
    for key, value in task.params:
        if key in by_name:
            scene = by_name[key].apply(scene, value)
    return scene


_DIVERGED_WORDS = ("diverg", "non-finite", "nonfinite", "not finite", "nan", "too small")


def _simulation_status(traj: xr.Dataset) -> tuple[str, str]:
    """Map the simulator's own report to a point status.

    ``mechanism.simulate`` reports ``solver_status`` / ``ideal_solver_status`` (0 success,
    negative failure) with ``*_message``; other simulators may set ``status`` (0, or a word
    such as "success") and ``success``. A failure whose message speaks of non-finite values
    or a collapsing step is "diverged", any other "failed"; so is a trajectory holding NaN.
    """
    attrs = traj.attrs
    for prefix in ("", "solver_", "ideal_solver_"):
        raw = attrs.get(f"{prefix}status")
        message = str(attrs.get(f"{prefix}message", ""))
        bad = False
        if isinstance(raw, (str, np.str_)):
            text = str(raw).strip().lower()
            bad = text not in {"ok", "success", "succeeded", "finished", "completed", "0"}
            message = message or text
            if "diverg" in text:
                return "diverged", message
        elif raw is not None and np.ndim(raw) == 0:
            bad = int(raw) != 0  # solve_ivp: 1 is a terminal event, -1 a failure
        success = attrs.get(f"{prefix}success")
        if success is not None and not bool(np.asarray(success).item()):
            bad = True
        if bad:
            what = "the ideal companion run: " if prefix == "ideal_solver_" else ""
            message = what + (message or f"the simulation reported status {raw!r}")
            lowered = message.lower()
            diverged = any(word in lowered for word in _DIVERGED_WORDS)
            return ("diverged" if diverged else "failed"), message
    for name, var in traj.data_vars.items():
        # scalar variables are summaries (a metric is NaN where it does not apply)
        if var.ndim and var.dtype.kind == "f" and not np.all(np.isfinite(var.values)):
            return "diverged", f"variable {name!r} has non-finite values"
    return "ok", ""


def _analysis_input(
    traj: xr.Dataset, analysis: Analysis, start: int, extra: Sequence[str] = ()
) -> xr.Dataset:
    """The analysed series (and ``extra`` ones): 1-D along time, after the discard, decimated.

    Each name is a selection as everywhere in chaoskit (``NAME`` or ``NAME[DIM=VALUE,...]``);
    a ``joint`` dimension not selected in the name takes ``analysis.joint`` (default: the
    first clearance joint).
    """
    columns = {}
    default: dict[str, Any] = {}
    if "joint" in traj.dims:
        if analysis.joint is not None:
            default["joint"] = analysis.joint
        elif traj.sizes["joint"] > 0:
            default["joint"] = str(traj["joint"].values[0]) if "joint" in traj.coords else "0"
    for name in (*analysis.variables, *extra):
        base = name.split("[", 1)[0].strip()
        if base not in traj:
            raise ValueError(
                f"analysis variable {name!r} is not in the trajectory; available: "
                f"{sorted(map(str, traj.data_vars))}."
            )
        if "joint" in traj[base].dims and traj.sizes["joint"] == 0:
            raise ValueError(f"analysis variable {name!r} has no clearance joint to select.")
        series = chaoskit.select_series(traj, name, sel=default)
        columns[name] = series.drop_vars([c for c in series.coords if c != "time"])
    data = xr.Dataset(columns).isel(time=slice(start, None))
    n = data.sizes["time"]
    stride = analysis.decimation
    if analysis.max_samples is not None:
        stride = max(stride, math.ceil(n / analysis.max_samples))
    data = data.isel(time=slice(None, None, stride))
    data.attrs = {k: v for k, v in traj.attrs.items() if isinstance(v, (str, int, float))}
    data.attrs["analysis_stride"] = stride
    return data


def _point_seed(seed: int, pid: str) -> int:
    digest = hashlib.sha1(f"{seed}:{pid}".encode()).hexdigest()
    return int(digest[:15], 16)


def _analyze_point(traj: xr.Dataset, analysis: Analysis, start: int, pid: str) -> xr.Dataset | None:
    if not analysis.variables:
        return None
    kwargs = dict(analysis.options)
    extra: tuple[str, ...] = ()
    if "phase_variable" not in kwargs and "drive_period" not in kwargs and "crank_angle" in traj:
        kwargs["phase_variable"] = "crank_angle"  # the verdict's stroboscopic evidence
        extra = ("crank_angle",)
    kwargs.setdefault("rng", _point_seed(analysis.seed, pid))
    data = _analysis_input(traj, analysis, start, extra)
    if len(analysis.variables) > 1:
        # one verdict for the point's motion (motion_* scalars) beside the per-variable rows
        motion = chaoskit.classify_motion(data, variables=list(analysis.variables), **kwargs)
        result = motion.to_dataset()
    else:
        result = chaoskit.analyze(data, variables=list(analysis.variables), **kwargs)
    result = result.assign_coords(variable=np.asarray(analysis.variables, dtype=str))
    result = result.drop_vars([c for c in result.coords if c != "variable"])
    out = xr.Dataset()
    for name, var in result.data_vars.items():
        if var.dims not in (("variable",), ()):
            continue  # the gathered sweep holds one scalar per (point, variable) or point
        if var.dtype.kind in "OUS":
            var = var.astype(str)
        out[f"{name}"] = var
    out["variable"].attrs.update({"long_name": "analysed trajectory variable", "units": "1"})
    out.attrs["analysis_stride"] = int(data.attrs["analysis_stride"])
    return out


def string_var(value: str, long_name: str) -> xr.DataArray:
    """A scalar text variable with ``units`` and ``long_name``."""
    return xr.DataArray(np.asarray(value, dtype=str), attrs={"units": "1", "long_name": long_name})


def _summary_dataset(
    task: PointTask,
    *,
    status: str,
    message: str,
    trajectory_file: str,
    parts: Sequence[Mapping[str, xr.DataArray] | xr.Dataset] = (),
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    ds = xr.Dataset()
    for part in parts:
        for name, var in part.items():
            ds[str(name)] = var
    ds["status"] = string_var(status, "point status: " + ", ".join(STATUSES))
    ds["message"] = string_var(message, "why the point did not succeed")
    ds["point_id"] = string_var(task.point_id, "grid point name in the store")
    ds["trajectory_file"] = string_var(trajectory_file, "trajectory file, relative to the store")
    ds.attrs.update(
        {
            "params": json.dumps(dict(task.params)),
            "source": SOURCE,
            **(attrs or {}),
        }
    )
    return ds


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"


def run_point(task: PointTask) -> tuple[str, str]:
    """Simulate, store and summarise one grid point; never raises for the point's own errors.

    Returns ``(point_id, status)``; the summary is on disk.
    """
    store = Path(task.store)
    t0 = time.perf_counter()
    status, message, trajectory_file = "failed", "", ""
    parts: list[Mapping[str, xr.DataArray] | xr.Dataset] = []
    attrs: dict[str, Any] = {}
    try:
        scene = _build_scene(task)
        traj = task.simulator(scene, revolutions=task.revolutions)
        status, message = _simulation_status(traj)
        traj.attrs["sweep_point"] = json.dumps(dict(task.params))
        traj.attrs["sweep_point_id"] = task.point_id
        target = _store.trajectory_path(store, task.point_id)
        if "time" not in traj.dims:
            # a section or summary record: its scalar variables are the point's metrics
            _store.write_netcdf(traj, target)
            trajectory_file = target.relative_to(store).as_posix()
            if status == "ok":
                parts.append({str(k): v for k, v in traj.data_vars.items() if v.ndim == 0})
        elif status == "ok":
            chaoskit.save_trajectory(traj, target)
            trajectory_file = target.relative_to(store).as_posix()
        else:
            # kept for diagnosis when it satisfies the contract (a run with NaNs does not)
            with contextlib.suppress(ValueError, TypeError, OSError):
                chaoskit.save_trajectory(traj, target)
                trajectory_file = target.relative_to(store).as_posix()
        if status == "ok" and "time" in traj.dims:
            start = window_start(traj, task.analysis.discard_revolutions)
            parts.append(response_metrics(traj, start))
            try:
                result = _analyze_point(traj, task.analysis, start, task.point_id)
            except Exception as exc:
                status, message = "failed", f"analysis failed: {_describe(exc)}"
            else:
                if result is not None:
                    attrs["analysis_stride"] = result.attrs.pop("analysis_stride")
                    parts.append(result)
        attrs.update(
            {
                k: v
                for k, v in traj.attrs.items()
                if k.startswith("solver_") and isinstance(v, (int, float, np.number))
            }
        )
    except Exception as exc:
        status = "diverged" if "diverg" in type(exc).__name__.lower() else "failed"
        message = _describe(exc)
    attrs["wall_time"] = time.perf_counter() - t0
    summary = _summary_dataset(
        task,
        status=status,
        message=message,
        trajectory_file=trajectory_file,
        parts=parts,
        attrs=attrs,
    )
    _store.write_summary(summary, _store.summary_path(store, task.point_id))
    return task.point_id, status


def record_lost_point(task: PointTask, exc: BaseException) -> tuple[str, str]:
    """Summary written by the driver when a task never returned (e.g. its worker kept dying)."""
    summary = _summary_dataset(
        task, status="failed", message=f"task lost: {_describe(exc)}", trajectory_file=""
    )
    _store.write_summary(summary, _store.summary_path(Path(task.store), task.point_id))
    return task.point_id, "failed"
