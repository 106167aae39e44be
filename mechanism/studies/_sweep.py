"""Parameter sweeps: one task per grid point on dask.distributed, results as one Dataset.

The driver (:func:`sweep`) resolves the grid, checks the store's manifest, skips points that
are already done and hands the rest to a backend — in-process (``client="serial"``) or
dask.distributed (a ``LocalCluster`` by default, any scheduler). Each point runs
:func:`_run_point` on a worker: build the scene, simulate, write the trajectory and a summary
(status, response metrics, ``chaoskit.analyze`` fields) into the store. The driver then
gathers every summary from disk, so the result depends on the store's contents only and a
serial run and a dask run give the same Dataset.

Failure is data (as diffrax's ``throw=False``): a point that raises, or whose simulation does
not succeed, is recorded with ``status`` ("failed" or "diverged") and ``message``; the sweep
always finishes.
"""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import json
import logging
import math
import os
import time
import typing
import uuid
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from chaoskit.contract import __version__, stamp
from mechanism.core import load_scene, simulate
from mechanism.core.record import (
    METRICS,
    response_metrics,
    window_start,
)

from . import _sweep_store as _store
from ._sweep_store import SweepStoreBusy, SweepStoreMismatch
from ._wear_prediction import predict_wear

__all__ = [
    "Analysis",
    "GridTransform",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "chaos_map",
    "dask_client",
    "grid_transforms",
    "load_sweep",
    "register_grid_transform",
    "stroboscopic_points",
    "sweep",
]

_log = logging.getLogger("mechanism.sweep")

STATUSES: tuple[str, ...] = ("ok", "failed", "diverged")
_TWO_PI = 2.0 * math.pi
_SOURCE = f"mechanism (chaoskit {__version__})"


# --------------------------------------------------------------------------- configuration


@dataclass(frozen=True, kw_only=True)
class Analysis:
    """What each grid point analyses after its simulation, and over which samples.

    Parameters
    ----------
    variables
        Trajectory variables handed to :func:`chaoskit.analyze` (one row each in the
        result's ``variable`` dimension), each ``NAME`` or ``NAME[DIM=VALUE,...]`` as in
        ``chaoskit analyze`` (e.g. ``"eccentricity_x[joint=C]"``). With two or more, the
        point's motion is classified as a whole (:func:`chaoskit.classify_motion`) and the
        result gets one ``motion_label``, ``motion_confidence``, ``motion_period``, ... per
        point beside the rows. Default: the journal eccentricity ``x`` and ``y`` of the
        clearance joint, the paper's "X and Y direction" series. Empty: response metrics
        only.
    joint
        Clearance joint for the variables with a ``joint`` dimension whose name selects none;
        default the first.
    discard_revolutions
        Crank revolutions dropped from the start before metrics and analysis (transient), ≥ 0.
        The paper evaluates after the first revolution.
    decimation
        Keep every ``decimation``-th sample of the analysed series (≥ 1).
    max_samples
        Upper bound on the analysed series length; the stride grows to respect it (None: no
        bound). The estimators cost grows faster than linearly with the length, and the
        default output step gives 10 000 samples per revolution.
    options
        Extra keyword arguments for :func:`chaoskit.analyze` (e.g. ``n_surrogates``; with
        several variables, those of :func:`chaoskit.classify_motion`); must be
        JSON-serialisable, since they are stored in the sweep manifest. By default the sweep
        passes ``phase_variable="crank_angle"`` (the stroboscopic evidence of the verdict).
    seed
        Base seed of the random parts of the analysis (surrogates, the 0–1 test): each point
        gets ``rng`` derived from ``seed`` and its point name, so results depend neither on
        the backend nor on the order in which points run.

    Examples
    --------
    >>> import mechanism
    >>> mechanism.Analysis(variables=("eccentricity_y",), discard_revolutions=2.0)
    Analysis(variables=('eccentricity_y',), joint=None, discard_revolutions=2.0, \
decimation=1, max_samples=20000, options={}, seed=0)
    """

    variables: tuple[str, ...] = ("eccentricity_x", "eccentricity_y")
    joint: str | None = None
    discard_revolutions: float = 1.0
    decimation: int = 1
    max_samples: int | None = 20_000
    options: Mapping[str, Any] = field(default_factory=dict)
    seed: int = 0

    def __post_init__(self) -> None:
        if isinstance(self.variables, str):
            object.__setattr__(self, "variables", (self.variables,))
        object.__setattr__(self, "variables", tuple(str(v) for v in self.variables))
        if len(set(self.variables)) != len(self.variables):
            raise ValueError(f"Analysis.variables has duplicates: {self.variables}.")
        d = self.discard_revolutions
        if isinstance(d, bool) or not isinstance(d, (int, float)) or not (0 <= d < math.inf):
            raise ValueError(
                f"Analysis.discard_revolutions must be a finite number >= 0; got {d!r}."
            )
        dec = self.decimation
        if isinstance(dec, bool) or not isinstance(dec, int) or dec < 1:
            raise ValueError(f"Analysis.decimation must be an integer >= 1; got {dec!r}.")
        m = self.max_samples
        if m is not None and (isinstance(m, bool) or not isinstance(m, int) or m < 16):
            raise ValueError(f"Analysis.max_samples must be None or an integer >= 16; got {m!r}.")
        try:
            json.dumps(dict(self.options))
        except TypeError as exc:
            raise ValueError(f"Analysis.options must be JSON-serialisable: {exc}.") from None
        object.__setattr__(self, "options", dict(self.options))
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"Analysis.seed must be an integer >= 0; got {self.seed!r}.")

    def __hash__(self) -> int:  # options is a dict; hash the stored (JSON) form instead
        return hash(json.dumps(self.to_dict(), sort_keys=True))

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready form (stored in the sweep manifest and the result's attrs)."""
        return {
            "variables": list(self.variables),
            "joint": self.joint,
            "discard_revolutions": float(self.discard_revolutions),
            "decimation": self.decimation,
            "max_samples": self.max_samples,
            "options": dict(self.options),
            "seed": self.seed,
        }


@dataclass(frozen=True, kw_only=True)
class GridTransform:
    """A special grid key: ``apply(scene, value) -> scene`` for values the scene has no key for.

    ``apply`` runs on the worker (it may be expensive, e.g. a wear prediction) and must be a
    module-level function so it pickles. ``values``, when given, lists the accepted values
    (checked before anything runs).
    """

    name: str
    apply: Callable[[Any, Any], Any]
    values: tuple[Any, ...] | None = None
    long_name: str = ""
    units: str = "1"


_GRID_TRANSFORMS: dict[str, GridTransform] = {}


def register_grid_transform(
    name: str,
    apply: Callable[[Any, Any], Any],
    *,
    values: Sequence[Any] | None = None,
    long_name: str | None = None,
    units: str = "1",
    overwrite: bool = False,
) -> GridTransform:
    """Register a special grid key handled by ``apply(scene, value) -> scene``.

    Special keys are applied after the dotted scene keys of the same point, in grid order.

    Examples
    --------
    >>> import mechanism
    >>> def frictionless(scene, value):
    ...     return scene.replace({"joints.C.friction.law": "none"}) if value else scene
    >>> t = mechanism.register_grid_transform(
    ...     "frictionless", frictionless, values=[False, True], overwrite=True)
    >>> "frictionless" in mechanism.grid_transforms()
    True
    """
    if not isinstance(name, str) or not name or "." in name:
        raise ValueError(
            f"a special grid key must be a non-empty name without dots (dotted keys are scene "
            f"keys); got {name!r}."
        )
    if name in _GRID_TRANSFORMS and not overwrite:
        raise ValueError(f"grid key {name!r} is already registered; pass overwrite=True.")
    if not callable(apply):
        raise TypeError(f"apply must be callable(scene, value) -> scene; got {apply!r}.")
    transform = GridTransform(
        name=name,
        apply=apply,
        values=None if values is None else tuple(values),
        long_name=long_name or name,
        units=units,
    )
    _GRID_TRANSFORMS[name] = transform
    return transform


def grid_transforms() -> Mapping[str, GridTransform]:
    """The registered special grid keys (read-only view)."""
    return MappingProxyType(_GRID_TRANSFORMS)


#: predict_wear settings of the grid value wear = "after" (see docs/wear.md): the paper
#: scene reaches the paper's peak-contact-force ratio near this amount of wear.
WEAR_AFTER_SETTINGS: dict[str, float] = {
    "updates": 4,
    "cycles_per_update": 1000.0,
    "max_depth_increment": 0.25,
    "settle_revolutions": 1.0,
}


def _wear_transform(scene: Any, value: Any, **settings: Any) -> Any:
    """``"before"``: the scene as is; ``"after"``: the worn scene of
    :func:`mechanism.predict_wear` with :data:`WEAR_AFTER_SETTINGS` (overridden by
    ``settings``; register ``functools.partial(_wear_transform, ...)`` to change them)."""
    if value == "before":
        return scene
    options = {**WEAR_AFTER_SETTINGS, **settings}
    return predict_wear(
        scene,
        updates=int(options["updates"]),
        cycles_per_update=float(options["cycles_per_update"]),
        max_depth_increment=float(options["max_depth_increment"]),
        settle_revolutions=float(options["settle_revolutions"]),
    ).worn_scene


register_grid_transform(
    "wear",
    _wear_transform,
    values=("before", "after"),
    long_name="wear state of the clearance joints",
)


# --------------------------------------------------------------------------- per-point work


@dataclass(frozen=True, kw_only=True)
class _PointTask:
    """Everything a worker needs for one grid point (pickled to the worker)."""

    point_id: str
    params: tuple[tuple[str, Any], ...]
    scene: Any
    transforms: tuple[GridTransform, ...]
    revolutions: float
    analysis: Analysis
    store: str
    simulator: Callable[..., xr.Dataset]


def _simulate_point(scene: Any, *, revolutions: float) -> xr.Dataset:
    """The simulation of one grid point (the one place a test stand-in replaces)."""
    # failure as data: a failed integration returns its samples so far and solver_status < 0
    return simulate(scene, revolutions=revolutions, throw=False)


def _build_scene(task: _PointTask) -> Any:
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


def _string_var(value: str, long_name: str) -> xr.DataArray:
    return xr.DataArray(np.asarray(value, dtype=str), attrs={"units": "1", "long_name": long_name})


def _summary_dataset(
    task: _PointTask,
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
    ds["status"] = _string_var(status, "point status: " + ", ".join(STATUSES))
    ds["message"] = _string_var(message, "why the point did not succeed")
    ds["point_id"] = _string_var(task.point_id, "grid point name in the store")
    ds["trajectory_file"] = _string_var(trajectory_file, "trajectory file, relative to the store")
    ds.attrs.update(
        {
            "params": json.dumps(dict(task.params)),
            "source": _SOURCE,
            **(attrs or {}),
        }
    )
    return ds


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"


def _run_point(task: _PointTask) -> tuple[str, str]:
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


def _record_lost_point(task: _PointTask, exc: BaseException) -> tuple[str, str]:
    """Summary written by the driver when a task never returned (e.g. its worker kept dying)."""
    summary = _summary_dataset(
        task, status="failed", message=f"task lost: {_describe(exc)}", trajectory_file=""
    )
    _store.write_summary(summary, _store.summary_path(Path(task.store), task.point_id))
    return task.point_id, "failed"


# --------------------------------------------------------------------------- backends


def _progress_bar(total: int, enabled: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(total=total, desc="sweep", unit="point", disable=not enabled)


def _run_serial(tasks: Sequence[_PointTask], progress: bool) -> list[tuple[str, str]]:
    done = []
    with _progress_bar(len(tasks), progress) as bar:
        for task in tasks:
            done.append(_run_point(task))
            bar.update(1)
    return done


@contextlib.contextmanager
def dask_client(client: Any, n_workers: int | None, n_tasks: int) -> Iterator[Any]:
    """The dask ``Client`` a sweep runs on, as a context manager.

    ``client`` None starts a ``LocalCluster`` of ``n_workers`` single-threaded processes
    (default: CPU count, at most ``n_tasks``) and closes it on exit; an address connects to
    that scheduler (closing leaves it running); a ``Client`` is yielded unchanged. Studies
    that run several sweeps open one backend here and pass it as ``client=``.
    """
    from distributed import Client, LocalCluster

    if client is None:
        n = n_workers if n_workers is not None else min(os.cpu_count() or 1, n_tasks)
        with (
            LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address="127.0.0.1:0",  # any free local port: no clash on 8787
                silence_logs=logging.ERROR,
            ) as cluster,
            Client(cluster) as owned,
        ):
            yield owned
    elif isinstance(client, str):
        with Client(client) as connected:  # closing it leaves the remote scheduler running
            yield connected
    else:
        yield client


def _run_dask(
    tasks: Sequence[_PointTask], client: Any, n_workers: int | None, progress: bool
) -> list[tuple[str, str]]:
    from distributed import as_completed

    done = []
    with dask_client(client, n_workers, len(tasks)) as c:
        run = uuid.uuid4().hex[:8]
        futures = {
            c.submit(_run_point, task, key=f"sweep-{task.point_id}-{run}", pure=False): task
            for task in tasks
        }
        with _progress_bar(len(tasks), progress) as bar:
            for future in as_completed(futures):
                try:
                    done.append(future.result())
                except Exception as exc:  # KilledWorker, a store that cannot be written, ...
                    done.append(_record_lost_point(futures[future], exc))
                bar.update(1)
                future.release()
    return done


# --------------------------------------------------------------------------- the driver


def _resolve_scene(scene: Any) -> Any:
    if isinstance(scene, (str, os.PathLike)):
        return load_scene(scene if isinstance(scene, str) else Path(scene))
    if not (hasattr(scene, "replace") and hasattr(scene, "to_json")):
        raise TypeError(
            f"scene must be a mechanism.Scene, a built-in scene name or a TOML path; got "
            f"{type(scene).__name__}."
        )
    return scene


def _plain(value: Any, key: str) -> Any:
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, bool | int | str):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"grid[{key!r}] has a non-finite value {value!r}.")
        return value
    raise ValueError(
        f"grid[{key!r}] values must be numbers, strings or booleans; got {value!r} "
        f"({type(value).__name__})."
    )


def _normalize_grid(grid: Mapping[str, Sequence[Any]]) -> dict[str, tuple[Any, ...]]:
    if not isinstance(grid, Mapping) or not grid:
        raise ValueError(
            "grid must be a non-empty mapping {key: [values, ...]}, e.g. "
            '{"joints.C.clearance": [1e-4, 2e-4]}.'
        )
    out: dict[str, tuple[Any, ...]] = {}
    for key, values in grid.items():
        if not isinstance(key, str) or not key:
            raise ValueError(f"grid keys must be non-empty strings; got {key!r}.")
        if isinstance(values, (str, bytes)) or not isinstance(values, (Sequence, np.ndarray)):
            raise ValueError(f"grid[{key!r}] must be a sequence of values; got {values!r}.")
        plain = tuple(_plain(v, key) for v in values)
        if not plain:
            raise ValueError(f"grid[{key!r}] is empty; give at least one value.")
        if len(set(plain)) != len(plain):
            raise ValueError(f"grid[{key!r}] has repeated values: {list(plain)}.")
        out[key] = plain
    return out


def _check_grid_against_scene(scene: Any, grid: Mapping[str, tuple[Any, ...]]) -> None:
    """Fail before any work for unknown keys or values the scene rejects."""
    for key, values in grid.items():
        transform = _GRID_TRANSFORMS.get(key)
        if transform is not None:
            if transform.values is not None:
                bad = [v for v in values if v not in transform.values]
                if bad:
                    raise ValueError(
                        f"grid[{key!r}]: {bad} not accepted; accepted values are "
                        f"{list(transform.values)}."
                    )
            continue
        if "." not in key:
            raise ValueError(
                f"grid key {key!r} is neither a dotted scene key (e.g. 'joints.C.clearance') "
                f"nor a registered special key {sorted(_GRID_TRANSFORMS)}."
            )
        for value in values:
            try:
                scene.replace({key: value})
            except Exception as exc:
                raise ValueError(f"grid[{key!r}] = {value!r}: {exc}") from exc


def _callable_name(func: Callable[..., Any]) -> str:
    return f"{getattr(func, '__module__', '?')}.{getattr(func, '__qualname__', repr(func))}"


def _key_attrs(scene: Any, key: str) -> dict[str, str]:
    """``units`` and ``long_name`` of a grid coordinate (units from the scene annotations)."""
    transform = _GRID_TRANSFORMS.get(key)
    if transform is not None:
        return {"units": transform.units, "long_name": transform.long_name}
    units = "unknown"
    with contextlib.suppress(Exception):
        *path, last = key.split(".")
        obj = scene
        for part in path:
            obj = obj[part] if isinstance(obj, Mapping) else getattr(obj, part)
        hints = typing.get_type_hints(type(obj), include_extras=True)
        for meta in getattr(hints[last], "__metadata__", ()):
            if type(meta).__name__ == "Unit":
                units = meta.symbol or "unknown"
    return {"units": units, "long_name": f"scene key {key}"}


def _grid_points(grid: Mapping[str, tuple[Any, ...]]) -> list[dict[str, Any]]:
    keys = list(grid)
    return [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*grid.values())]


def _is_done(store: Path, pid: str) -> bool:
    summary = _store.read_summary(_store.summary_path(store, pid))
    if _store.summary_status(summary) != "ok":
        return False
    assert summary is not None
    rel = str(np.asarray(summary["trajectory_file"].values).item())
    if not rel:
        return False
    try:
        path = _store.point_file(store, rel)
    except ValueError:
        return False  # a summary naming a file elsewhere: run the point again
    return _store.readable_trajectory(path)  # present is not enough


def sweep(
    scene: Any,
    *,
    grid: Mapping[str, Sequence[Any]],
    revolutions: float,
    analysis: Analysis | None = None,
    client: Any = None,
    n_workers: int | None = None,
    store: str | os.PathLike[str],
    progress: bool = False,
    _simulator: Callable[..., xr.Dataset] | None = None,
) -> xr.Dataset:
    """Simulate and analyse a scene over a parameter grid, one task per grid point.

    Every combination of the ``grid`` values is one point: the scene with the dotted keys
    replaced (``scene.replace``) and then the special keys applied (registered with
    :func:`register_grid_transform`; built in: ``"wear"``), simulated for ``revolutions``
    crank revolutions. Each point writes ``STORE/points/<id>.nc`` (its trajectory) and
    ``<id>.summary.nc``: its status, the response metrics of docs/paper-model.md §7 over the
    revolutions after ``analysis.discard_revolutions``,

    * ``peak_contact_force`` :math:`\\max F_n` (N), ``max_penetration`` :math:`\\max\\delta` (m),
    * ``max_displacement_error`` :math:`\\max|y_5 - y_{5,ideal}|` (m),
      ``max_speed_error`` :math:`\\max|\\dot y_5 - \\dot y_{5,ideal}|` (m/s),
    * ``driving_torque_extreme`` (signed, N m) and, for flexible rods,
      ``rod_strain_extreme`` (signed, per rod),

    and the fields of :func:`chaoskit.analyze` for ``analysis.variables``. A point that
    raises or whose simulation does not succeed gets ``status`` "failed" or "diverged" and a
    ``message``; the sweep goes on. Re-running into the same ``store`` skips the points
    already "ok" and retries the others; a store made for another scene, grid, revolutions
    or analysis raises :class:`SweepStoreMismatch`, and a store another sweep is running into
    raises :class:`SweepStoreBusy` (the store is locked while a sweep runs; temporary files
    that an interrupted run left are removed, and a done point whose trajectory file no
    longer reads is run again). A point whose files cannot be written (e.g. a full disk)
    fails with the reason; when not even its summary can be written, the sweep stops with
    that ``OSError``.

    Parameters
    ----------
    scene
        A :class:`mechanism.Scene`, a built-in scene name or a TOML path.
    grid
        ``{key: [values, ...]}``; keys are dotted scene keys (``"joints.C.clearance"``,
        ``"drive.speed_rpm"``) or special keys (``"wear": ["before", "after"]``). The key
        order is the dimension order of the result.
    revolutions
        Crank revolutions simulated per point (> ``analysis.discard_revolutions``).
    analysis
        What to analyse (:class:`Analysis`; default ``Analysis()``).
    client
        Backend: None → a ``LocalCluster`` (processes, one thread each, ``n_workers``
        workers, default min(CPU count, points to run)) closed afterwards; ``"serial"`` →
        in this process, no dask; a scheduler address → ``Client(address)``; a
        ``distributed.Client`` → used as is.
    n_workers
        Workers of the default ``LocalCluster`` (only with ``client=None``).
    store
        Folder for the manifest, the point files and ``summary.nc``.
    progress
        Show a tqdm bar over finished points (and how many were skipped).

    Returns
    -------
    xarray.Dataset
        Dimensions: the grid keys (coordinates: the values as given) and ``variable`` for the
        analysis fields (``rod`` for rod strains). Variables: the metrics, the analysis
        fields (numeric as float64 with NaN where a point has none, text as strings),
        ``status``, ``message``, ``point_id``, ``trajectory_file`` (relative to the store).
        Attributes: the data contract's (``Conventions``, ``title``, ``source``,
        ``history``, ``created``), ``scene`` (JSON), ``grid`` (JSON), ``revolutions``,
        ``analysis`` (JSON) and ``store``. Also written to ``STORE/summary.nc``.

    Notes
    -----
    With dask, scripts must guard the call with ``if __name__ == "__main__":`` (workers are
    started by spawning Python processes that import the main module). A worker process
    that dies mid-point is replaced by its nanny and dask reruns the point (up to the
    scheduler's ``allowed-failures``); after that, the point is recorded as failed.

    Examples
    --------
    >>> import mechanism
    >>> if __name__ == "__main__":  # doctest: +SKIP
    ...     ds = mechanism.sweep(
    ...         "slider-crank-clearance",
    ...         grid={"joints.C.clearance": [1e-4, 2e-4], "drive.speed_rpm": [3000, 5000]},
    ...         revolutions=4,
    ...         store="sweep-store",
    ...     )
    ...     ds["peak_contact_force"].to_pandas()
    """
    if isinstance(revolutions, bool) or not isinstance(revolutions, (int, float)):
        raise ValueError(f"revolutions must be a number > 0; got {revolutions!r}.")
    revolutions = float(revolutions)
    if not (0 < revolutions < math.inf):
        raise ValueError(f"revolutions must be finite and > 0; got {revolutions!r}.")
    analysis = Analysis() if analysis is None else analysis
    if not isinstance(analysis, Analysis):
        raise TypeError(f"analysis must be a mechanism.Analysis; got {type(analysis).__name__}.")
    if revolutions <= analysis.discard_revolutions:
        raise ValueError(
            f"revolutions ({revolutions:g}) must exceed analysis.discard_revolutions "
            f"({analysis.discard_revolutions:g}); nothing would be left to evaluate."
        )
    if n_workers is not None:
        if client is not None:
            raise ValueError("n_workers applies to the default LocalCluster only (client=None).")
        if isinstance(n_workers, bool) or not isinstance(n_workers, int) or n_workers < 1:
            raise ValueError(f"n_workers must be an integer >= 1; got {n_workers!r}.")
    if isinstance(client, str) and client != "serial" and not client.strip():
        raise ValueError("client must be None, 'serial', a scheduler address or a Client.")
    simulator = _simulator if _simulator is not None else _simulate_point

    scene = _resolve_scene(scene)
    plain_grid = _normalize_grid(grid)
    _check_grid_against_scene(scene, plain_grid)
    store_path = Path(store).resolve()
    scene_json = scene.to_json()
    manifest = {
        "format": _store.MANIFEST_FORMAT,
        "scene": json.loads(scene_json),
        "grid": {k: list(v) for k, v in plain_grid.items()},
        "revolutions": revolutions,
        "analysis": analysis.to_dict(),
        "simulator": _callable_name(simulator),
    }
    (store_path / _store.POINTS).mkdir(parents=True, exist_ok=True)
    with _store.locked(store_path):
        _store.check_or_write_manifest(store_path, manifest)
        _store.remove_stale_temporaries(store_path)
        return _run_locked(
            store_path,
            manifest=manifest,
            scene=scene,
            scene_json=scene_json,
            plain_grid=plain_grid,
            analysis=analysis,
            revolutions=revolutions,
            simulator=simulator,
            client=client,
            n_workers=n_workers,
            progress=progress,
        )


def _run_locked(
    store_path: Path,
    *,
    manifest: dict[str, Any],
    scene: Any,
    scene_json: str,
    plain_grid: dict[str, tuple[Any, ...]],
    analysis: Analysis,
    revolutions: float,
    simulator: Callable[..., xr.Dataset],
    client: Any,
    n_workers: int | None,
    progress: bool,
) -> xr.Dataset:
    """The sweep proper, under the store's lock: run the points not done, then gather."""
    points = _grid_points(plain_grid)
    ids = [_store.point_id(p) for p in points]
    used = tuple(_GRID_TRANSFORMS[k] for k in plain_grid if k in _GRID_TRANSFORMS)
    todo = [
        _PointTask(
            point_id=pid,
            params=tuple(params.items()),
            scene=scene,
            transforms=used,
            revolutions=revolutions,
            analysis=analysis,
            store=str(store_path),
            simulator=simulator,
        )
        for params, pid in zip(points, ids, strict=True)
        if not _is_done(store_path, pid)
    ]
    skipped = len(points) - len(todo)
    note = f"{len(points)} points: {len(todo)} to run, {skipped} already done in {store_path}"
    _log.info(note)
    if progress and skipped:
        from tqdm.auto import tqdm

        tqdm.write(f"sweep: skipping {skipped} of {len(points)} points already done in the store")
    if todo:
        if client == "serial":
            _run_serial(todo, progress)
        else:
            _run_dask(todo, client, n_workers, progress)

    result = _gather(
        store_path,
        scene=scene,
        grid=plain_grid,
        ids=ids,
        attrs={
            "scene": scene_json,
            "grid": json.dumps(manifest["grid"]),
            "revolutions": revolutions,
            "analysis": json.dumps(manifest["analysis"]),
            "store": str(store_path),
        },
        history=f"mechanism.sweep: {note}",
    )
    summary_file = store_path / _store.SUMMARY
    _store.write_summary(result, summary_file)
    return result


# --------------------------------------------------------------------------- gathering


def _fill_value(kind: str) -> Any:
    return "" if kind == "U" else np.nan


def _gather(
    store: Path,
    *,
    scene: Any,
    grid: Mapping[str, tuple[Any, ...]],
    ids: Sequence[str],
    attrs: Mapping[str, Any],
    history: str,
) -> xr.Dataset:
    """One Dataset over the grid from the per-point summaries on disk.

    Combine rule per field: numeric → float64 with NaN where a point has no value; text →
    strings, "" where missing; extra dimensions (``variable``, ``rod``) take the coordinate
    of the first point that has them.
    """
    shape = tuple(len(v) for v in grid.values())
    dims = tuple(grid)
    summaries: list[xr.Dataset] = []
    for pid in ids:
        summary = _store.read_summary(_store.summary_path(store, pid))
        if summary is None:
            summary = xr.Dataset(
                {
                    "status": _string_var("failed", ""),
                    "message": _string_var("no summary in the store for this point", ""),
                    "point_id": _string_var(pid, ""),
                    "trajectory_file": _string_var("", ""),
                }
            )
        summaries.append(summary)

    # the metrics are there even when no point succeeded, so a table of them never KeyErrors
    specs: dict[str, tuple[tuple[str, ...], str, dict[str, Any]]] = {
        name: ((), "f", {"units": units, "long_name": long_name})
        for name, (units, long_name) in METRICS.items()
    }
    extra_coords: dict[str, xr.DataArray] = {}
    for summary in summaries:
        for name, var in summary.data_vars.items():
            if name in specs:
                continue
            kind = "U" if var.dtype.kind in "OUS" else "f"
            specs[str(name)] = (tuple(map(str, var.dims)), kind, dict(var.attrs))
            for d in var.dims:
                if d not in extra_coords and d in summary.coords:
                    extra_coords[str(d)] = summary[d].copy()
    order = [n for n in specs if n not in {"status", "message", "point_id", "trajectory_file"}]
    order += ["status", "message", "point_id", "trajectory_file"]

    data_vars: dict[str, xr.Variable] = {}
    for name in order:
        extra, kind, var_attrs = specs[name]
        full = shape + tuple(extra_coords[d].size for d in extra)
        values = np.full(full, _fill_value(kind), dtype=object if kind == "U" else np.float64)
        for flat, summary in enumerate(summaries):
            if name not in summary:
                continue
            var = summary[name]
            if extra:
                var = var.reindex({d: extra_coords[d].values for d in extra})
            arr = np.asarray(var.values)
            if kind == "U":
                arr = arr.astype(str)
            elif arr.dtype.kind == "f" or arr.dtype.kind in "iub":
                arr = arr.astype(np.float64)
            values[np.unravel_index(flat, shape)] = arr
        if kind == "U":
            values = values.astype(str)
        data_vars[name] = xr.Variable(dims + extra, values, attrs=var_attrs)

    coords: dict[str, Any] = {
        key: xr.Variable((key,), np.asarray(values), attrs=_key_attrs(scene, key))
        for key, values in grid.items()
    }
    coords.update({d: c.variable for d, c in extra_coords.items()})
    ds = xr.Dataset(data_vars, coords=coords)
    name = getattr(scene, "name", "scene")
    stamp(
        ds,
        title=f"parameter sweep of the {name!r} scene over {', '.join(grid)}",
        source=_SOURCE,
        history=history,
        extra=dict(attrs),
    )
    return ds


def load_sweep(store: str | os.PathLike[str]) -> xr.Dataset:
    """The gathered Dataset of a sweep store (``STORE/summary.nc``), loaded into memory."""
    path = Path(store)
    file = path / _store.SUMMARY if path.is_dir() else path
    if not file.exists():
        raise FileNotFoundError(f"no sweep summary at {file}; run mechanism.sweep first.")
    with xr.open_dataset(file, engine="h5netcdf") as opened:
        return opened.load()


# --------------------------------------------------------------------------- views


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
        source=_SOURCE,
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
        source=_SOURCE,
        history=f"mechanism.chaos_map(x={x!r}, y={y!r}, variable={variable!r}, mle={mle!r})",
        extra={"variable": variable, "mle_field": mle, "verdict_field": verdict},
    )
