"""``mechanism.wear_life_map``: one wear path per value of a scene key, as dask tasks.

Each value of ``parameter`` (``drive.speed_rpm``, ``joints.C.clearance``, ...) is its own
:func:`mechanism.wear_life` path, run as one task on the sweep's backends (in this
process, a ``LocalCluster`` or any dask scheduler) and written to its own file in a
store. A re-run into the same store reads the finished paths back instead of running them
again, and the result is always read from the store, so a fresh and a resumed run give
the same numbers. A path that ends early (a state the wear model does not represent) is a
result like any other; a path whose task raised is recorded with the reason and run
again by the next call. See ``docs/wear.md`` §7.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import os
import tempfile
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import __version__, safe_filename, stamp, variable, write_netcdf
from mechanism.core import Scene

from ._turns import revolution_time
from ._wear_life import (
    PathRun,
    WearLife,
    WearLifeSettings,
    check_wear_path,
    checked_settings,
    wear_path,
)
from .sweep import (
    MANIFEST_FORMAT,
    check_or_write_manifest,
    dask_client,
    key_attrs,
    locked,
    remove_stale_temporaries,
    resolve_scene,
)

__all__ = ["MAP_FILE", "WearLifeMap", "format_cycles", "path_id", "value_label", "wear_life_map"]

#: The gathered map in a store (rewritten by every run).
MAP_FILE = "wear-life-map.nc"
#: The per-value path files in a store.
POINTS = "points"
_STUDY = "mechanism.wear_life_map"
#: dask priority of a path: every path starts before any checkpoint's exponent and verdict
#: it hands on (a path is a chain of runs that cannot be split; the analyses fill the
#: gaps). An analysis's priority is −1 / (its revolution's duration in s), below 0: it runs
#: a fixed number of revolutions, so the slowest drive's analyses are the longest and run
#: first, and the last ones to finish are short.
_PATH_PRIORITY = 1.0


def format_cycles(n: float) -> str:
    """A cycle count with thin-space thousands, e.g. ``12 000``."""
    return f"{n:,.0f}".replace(",", "\u202f") if abs(n) >= 1e4 else f"{n:.6g}"


def value_label(parameter: str, value: float, units: str) -> str:
    """How a value reads in a sentence: ``150 rpm``, ``joints.C.clearance = 0.2 mm``."""
    if units == "rpm":
        return f"{value:g} rpm"
    if units == "m":
        return f"{parameter} = {value * 1e3:g} mm"
    shown = "" if units in ("1", "unknown", "") else f" {units}"
    return f"{parameter} = {value:g}{shown}"


# --------------------------------------------------------------------------- the result


@dataclass(frozen=True, kw_only=True, eq=False)
class WearLifeMap:
    """Result of :func:`wear_life_map`: one wear path per value of a scene key.

    Attributes
    ----------
    scene : Scene
        The starting scene (before the value is set).
    parameter : str
        The dotted scene key, e.g. ``"drive.speed_rpm"``.
    values : tuple of float
        Its values, in the order given.
    units : str
        Units of the values (from the scene's annotations, e.g. ``"rpm"``, ``"m"``).
    cycles : float
        The requested cycles of wear of every path.
    checkpoints : numpy.ndarray
        The planned checkpoints (cumulative cycles), 0 (unworn) first and ``cycles`` last.
    paths : tuple of WearLife or None
        The path of every value, read back from the store (see
        :meth:`mechanism.WearLife.from_dataset`); None where the task raised.
    statuses : tuple of str
        ``"complete"`` or ``"failed"`` per value (a path that ended early, or a task that
        raised).
    reasons : tuple of str
        One line per value: how far the path went and why it ended.
    cpu_times, wall_times : tuple of float
        CPU and wall seconds of every path's task (on its worker; NaN where unknown).
    store : str or None
        The store folder; None when a temporary one was used.
    """

    scene: Scene
    parameter: str
    values: tuple[float, ...]
    units: str
    cycles: float
    checkpoints: np.ndarray
    paths: tuple[WearLife | None, ...] = field(repr=False)
    statuses: tuple[str, ...]
    reasons: tuple[str, ...] = field(repr=False)
    cpu_times: tuple[float, ...] = field(repr=False)
    wall_times: tuple[float, ...] = field(repr=False)
    store: str | None = None

    @property
    def cycles_to_chaos(self) -> tuple[float | None, ...]:
        """The first chaotic checkpoint of every path (None: not within its cycles)."""
        return tuple(None if p is None else p.cycles_to_chaos for p in self.paths)

    def labels(self) -> list[str]:
        """Every value as it reads in a sentence (``150 rpm``, ``... = 0.2 mm``)."""
        return [value_label(self.parameter, v, self.units) for v in self.values]

    def answers(self) -> list[str]:
        """One sentence per value: after how many cycles the motion turns chaotic.

        "at 150 rpm the motion turns chaotic after 12 000 cycles (confidence 0.80)" or
        "at 30 rpm the motion is not chaotic within 40 000 cycles (periodic at the last
        checkpoint, confidence 0.90)", plus where and why a path ended early.
        """
        out = []
        for label, path, status, reason in zip(
            self.labels(), self.paths, self.statuses, self.reasons, strict=True
        ):
            if path is None:
                out.append(f"at {label} the path did not run: {reason}")
                continue
            ds = path.dataset
            reached = float(path.checkpoints[-1]) if path.checkpoints.size else 0.0
            if path.cycles_to_chaos is not None:
                i = int(np.flatnonzero(path.checkpoints == path.cycles_to_chaos)[0])
                conf = float(ds["motion_confidence"].values[i])
                text = (
                    f"at {label} the motion turns chaotic after "
                    f"{format_cycles(path.cycles_to_chaos)} cycles (confidence {conf:.2f})"
                )
            elif not path.checkpoints.size:
                text = f"at {label} no checkpoint was analysed"
            else:
                motion = str(ds["motion"].values[-1])
                conf = float(ds["motion_confidence"].values[-1])
                notes = [f"{motion} at the last checkpoint"]
                notes += [f"confidence {conf:.2f}"] if math.isfinite(conf) else []
                notes += [] if ds.attrs["exponent"] else ["no exponent computed"]
                text = (
                    f"at {label} the motion is not chaotic within {format_cycles(reached)} "
                    f"cycles ({', '.join(notes)})"
                )
            if status != "complete":
                text += f"; the path ended after {format_cycles(reached)} cycles: " + (
                    reason.split(": ", 1)[1] if reason.startswith("the path ended") else reason
                )
            out.append(text)
        return out

    def summary(self) -> str:
        """The answers, one line per value, under a heading naming the scene and key."""
        head = (
            f"wear life of scene {self.scene.name!r} over {self.parameter} "
            f"({len(self.values)} paths of {format_cycles(self.cycles)} cycles)"
        )
        lines = [head]
        for answer, path in zip(self.answers(), self.paths, strict=True):
            lines.append(f"  {answer}")
            if path is not None and path.cycles_to_chaos is not None:
                lines[-1] += f" — cycles to chaos: {path.cycles_to_chaos:.6g}"
            elif path is not None:
                reached = float(path.checkpoints[-1]) if path.checkpoints.size else 0.0
                lines[-1] += f" — not within {reached:.6g} cycles"
        return "\n".join(lines)

    def to_dataset(self) -> xr.Dataset:
        """The paths as one Dataset over dims ``value`` and ``checkpoint``.

        The variables of :meth:`mechanism.WearLife.to_dataset` with a leading ``value``
        dim, NaN (text: "") at the checkpoints a path did not reach; per value
        ``path_status``, ``path_reason``, ``cycles_to_chaos`` (NaN: none),
        ``chaos_confidence`` (of the verdict at ``cycles_to_chaos``), ``cpu_time`` and
        ``wall_time`` (s). Coordinate ``value`` carries the key's units and the key in
        ``long_name``; attrs ``parameter``, ``scene`` and the path settings.
        """
        return _map_dataset(self)


# --------------------------------------------------------------------------- one task


@dataclass(frozen=True)
class _PathTask:
    """Everything a worker needs for one value's path (pickled to the worker)."""

    point_id: str
    parameter: str
    value: float
    scene: Scene
    cycles: float
    checkpoints: tuple[float, ...]
    settings: WearLifeSettings
    store: str


def path_id(parameter: str, value: float) -> str:
    """The file stem of one value's path, e.g. ``speed_rpm-150.0_5b7ac62a8e``: the last
    part of the key and the value, then 10 hex digits of the SHA-1 of both (unique); the
    stem a one-key :func:`mechanism.sweep` gives the same point."""
    readable = safe_filename(f"{parameter.rsplit('.', 1)[-1]}-{value!r}", replacement="~")
    canonical = json.dumps([[parameter, value]], separators=(",", ":"))
    digest = hashlib.sha1(canonical.encode("utf-8")).hexdigest()[:10]
    return f"{readable}_{digest}"


def _path_file(store: Path, pid: str) -> Path:
    return store / POINTS / f"{pid}.nc"


def _write_path(task: _PathTask, ds: xr.Dataset, cpu: float, wall: float, notes: list[str]) -> None:
    ds.attrs.update(
        {
            "wear_life_parameter": task.parameter,
            "wear_life_value": task.value,
            "point_id": task.point_id,
            "cpu_time": cpu,
            "wall_time": wall,
            "warnings": "\n".join(dict.fromkeys(notes)),
        }
    )
    write_netcdf(ds, _path_file(Path(task.store), task.point_id))


def _failure(reason: str) -> xr.Dataset:
    return xr.Dataset(attrs={"status": "failed", "status_reason": reason, "path_error": 1})


def run_path(task: _PathTask) -> str:
    """Run one value's wear path and write it to the store; never raises for the path's
    own errors (they are written as the value's reason). Returns the point id. On a dask
    worker the checkpoints' exponents and verdicts run as tasks of their own
    (:class:`_ClusterExecutor`)."""
    cpu0, wall0 = time.thread_time(), time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        # a worker's warnings would be lost on its stderr: they are kept in the file
        warnings.simplefilter("always")
        try:
            scene = task.scene.replace({task.parameter: task.value})
            turn = float(revolution_time(scene))  # type: ignore[arg-type]
            run = PathRun(executor=_ClusterExecutor.on_this_worker(-1.0 / turn))
            life = wear_path(scene, task.cycles, list(task.checkpoints), task.settings, run)
            ds = life.to_dataset()
            ds.attrs["path_error"] = 0
        except Exception as exc:  # failure is data: the value's reason, run again next time
            ds = _failure(f"the path could not run: {type(exc).__name__}: {exc}")
    notes = [f"{w.category.__name__}: {w.message}" for w in caught]
    cpu = time.thread_time() - cpu0 + float(ds.attrs.get("phase_cpu_elsewhere", 0.0))
    _write_path(task, ds, cpu, time.perf_counter() - wall0, notes)
    return task.point_id


class _ClusterExecutor(Executor):
    """The dask cluster a path task runs on, as the executor of its checkpoints'
    exponents and verdicts: they run on any worker, after every path has started (a lower
    priority). Shutting it down waits for them without this task's worker thread
    (``secede``), so that they can run there too."""

    def __init__(self, client: Any, priority: float) -> None:
        self._client = client
        self._priority = priority
        self._futures: list[Any] = []

    @classmethod
    def on_this_worker(cls, priority: float) -> _ClusterExecutor | None:
        """The executor of the dask cluster this task runs on, submitting at ``priority``
        (below the paths'); None outside a worker."""
        try:
            from distributed import get_client, get_worker

            get_worker()
        except (ImportError, ValueError):
            return None
        return cls(get_client(), priority)

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Any:
        """``fn(*args, **kwargs)`` as a dask task; a future with ``result()``."""
        future = self._client.submit(fn, *args, pure=False, priority=self._priority, **kwargs)
        self._futures.append(future)
        return future

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        from distributed import secede
        from distributed import wait as wait_for

        if cancel_futures:
            self._client.cancel(self._futures)
        elif wait and not all(f.done() for f in self._futures):
            secede()  # this thread only waits from here: the worker may run other tasks
            wait_for(self._futures)


def _record_lost(task: _PathTask, exc: BaseException) -> str:
    ds = _failure(f"the task was lost: {type(exc).__name__}: {exc}")
    _write_path(task, ds, math.nan, math.nan, [])
    return task.point_id


def _read_path(store: Path, pid: str) -> xr.Dataset | None:
    path = _path_file(store, pid)
    if not path.is_file():
        return None
    try:
        with xr.open_dataset(path, engine="h5netcdf") as opened:
            ds = opened.load()
    except (OSError, ValueError):  # damaged or foreign: the path is run again
        return None
    return ds if "status" in ds.attrs and "path_error" in ds.attrs else None


def _is_done(store: Path, pid: str) -> bool:
    ds = _read_path(store, pid)
    return ds is not None and int(ds.attrs["path_error"]) == 0


# --------------------------------------------------------------------------- backends


def _bar(total: int, done: int, parameter: str, enabled: bool) -> Any:
    from tqdm.auto import tqdm  # progress bars are opt-in

    return tqdm(
        total=total, initial=done, desc=f"wear paths over {parameter}", unit="path",
        disable=not enabled,
    )  # fmt: skip


def _run_serial(tasks: Sequence[_PathTask], bar: Any) -> None:
    for task in tasks:
        run_path(task)
        bar.update(1)


def _run_dask(tasks: Sequence[_PathTask], scheduler: Any, workers: int | None, bar: Any) -> None:
    from distributed import as_completed  # dask is the optional parallel backend

    with dask_client(scheduler, workers, len(tasks)) as client:
        run = os.urandom(4).hex()
        futures = {
            client.submit(
                run_path,
                t,
                key=f"wear-life-{t.point_id}-{run}",
                pure=False,
                priority=_PATH_PRIORITY,
            ): t
            for t in tasks
        }
        for future in as_completed(futures):
            try:
                future.result()
            except Exception as exc:  # KilledWorker, a store that cannot be written, ...
                _record_lost(futures[future], exc)
            bar.update(1)
            future.release()


# --------------------------------------------------------------------------- the driver


def _checked_values(values: Any, parameter: str) -> list[float]:
    if isinstance(values, str | bytes) or not isinstance(values, Sequence | np.ndarray):
        raise ValueError(f"values must be a list of numbers for {parameter}; got {values!r}.")
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
            raise ValueError(f"values must be finite numbers; got {v!r} for {parameter}.")
        if not math.isfinite(float(v)):
            raise ValueError(f"values must be finite numbers; got {v!r} for {parameter}.")
        out.append(float(v))
    if not out:
        raise ValueError(f"values must hold at least one value of {parameter}; got [].")
    if len(set(out)) != len(out):
        raise ValueError(f"values of {parameter} must not repeat; got {out}.")
    return out


def _checked_backend(workers: Any, scheduler: Any) -> None:
    if workers is not None:
        if scheduler is not None:
            raise ValueError("workers applies to the local cluster only (scheduler=None).")
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise ValueError(f"workers must be an integer >= 1; got {workers!r}.")
    if isinstance(scheduler, str) and not scheduler.strip():
        raise ValueError("scheduler must be None, 'serial', a scheduler address or a Client.")


@contextlib.contextmanager
def _store_folder(store: str | os.PathLike[str] | None) -> Iterator[Path]:
    if store is not None:
        yield Path(store).resolve()
        return
    with tempfile.TemporaryDirectory(prefix="mechanism-wear-life-") as tmp:
        yield Path(tmp)


def wear_life_map(
    scene: Any,
    *,
    parameter: str,
    values: Sequence[float],
    cycles: float,
    checkpoints: Sequence[float],
    settings: WearLifeSettings | None = None,
    store: str | os.PathLike[str] | None = None,
    workers: int | None = None,
    scheduler: Any = None,
    progress: bool = False,
) -> WearLifeMap:
    """Wear paths over the values of one scene key: after how many cycles does each turn chaotic.

    For every value of ``parameter`` the scene with that value is worn along one
    :func:`mechanism.wear_life` path up to ``cycles``, its motion analysed at the
    ``checkpoints`` (exponent from the equations, motion verdict, strobe points, forces,
    contact modes). Each path is one task; the paths run in this process
    (``scheduler="serial"``), on a local dask cluster of ``workers`` processes (default)
    or on a dask scheduler. Each writes ``STORE/points/<id>.nc``; the gathered map is
    ``STORE/wear-life-map.nc``. A re-run into the same store reads the finished paths
    instead of running them (so it gives identical numbers, and values may be added);
    a store made for another scene, key, cycles, checkpoints or settings raises
    :class:`mechanism.SweepStoreMismatch`, one in use :class:`mechanism.SweepStoreBusy`.

    A path that ends early (a state the wear model does not represent) keeps its
    checkpoints and its reason; a path whose task raised is a value with status "failed",
    its reason, no checkpoints, and is run again by the next call. Warnings of a path are
    kept in its file's ``warnings`` attribute.

    Parameters
    ----------
    scene
        A :class:`mechanism.Scene`, a built-in scene name or a TOML path, with an active
        clearance joint whose wear coefficient is positive.
    parameter
        A dotted scene key, e.g. ``"drive.speed_rpm"`` or ``"joints.C.clearance"`` (m).
    values
        Its values (finite numbers, no repeats); each must give a scene
        :func:`mechanism.wear_life` accepts.
    cycles, checkpoints
        As for :func:`mechanism.wear_life`, for every path.
    settings
        The wear and analysis settings of every path (:class:`mechanism.WearLifeSettings`,
        including ``averaged_revolutions``, ``max_depth_increment`` and ``exponent``).
    store
        Folder of the path files (a re-run resumes); default a temporary folder, removed
        afterwards.
    workers
        Processes of the local dask cluster (default: CPU count, at most the paths to run).
    scheduler
        None (a local cluster), ``"serial"`` (this process), a scheduler address or a
        ``distributed.Client``.
    progress
        A progress bar over the paths with the time left.

    Returns
    -------
    WearLifeMap

    Raises
    ------
    ValueError
        Bad settings, values or a scene :func:`mechanism.wear_life` rejects (one line
        naming the parameter and its accepted range), before any path runs.

    Notes
    -----
    With dask, scripts must guard the call with ``if __name__ == "__main__":``.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    >>> if __name__ == "__main__":  # doctest: +SKIP
    ...     life = mechanism.wear_life_map(
    ...         scene, parameter="drive.speed_rpm", values=[30, 90, 150], cycles=40000,
    ...         checkpoints=[5000, 10000, 20000], store="wear-store", workers=2)
    ...     print(life.summary())
    """
    scene = resolve_scene(scene)
    settings = checked_settings(settings)
    if not isinstance(parameter, str) or "." not in parameter:
        raise ValueError(
            f"parameter must be a dotted scene key (e.g. 'drive.speed_rpm'); got {parameter!r}."
        )
    plain = _checked_values(values, parameter)
    _checked_backend(workers, scheduler)
    scene, targets = check_wear_path(scene, cycles, checkpoints)
    for value in plain:
        try:
            changed = scene.replace({parameter: value})
        except Exception as exc:
            raise ValueError(f"{parameter} = {value:g}: {exc}") from None
        check_wear_path(changed, cycles, checkpoints)
    manifest = {
        "format": MANIFEST_FORMAT,
        "study": _STUDY,
        "scene": json.loads(scene.to_json()),
        "parameter": parameter,
        "cycles": float(targets[-1]),
        "checkpoints": [float(t) for t in targets],
        "settings": dataclasses.asdict(settings),
    }
    with _store_folder(store) as folder:
        (folder / POINTS).mkdir(parents=True, exist_ok=True)
        with locked(folder):
            check_or_write_manifest(folder, manifest)
            remove_stale_temporaries(folder)
            ids = [path_id(parameter, v) for v in plain]
            tasks = [
                _PathTask(
                    point_id=pid,
                    parameter=parameter,
                    value=v,
                    scene=scene,
                    cycles=float(targets[-1]),
                    checkpoints=tuple(targets),
                    settings=settings,
                    store=str(folder),
                )
                for v, pid in zip(plain, ids, strict=True)
                if not _is_done(folder, pid)
            ]
            with _bar(len(ids), len(ids) - len(tasks), parameter, progress) as bar:
                if tasks and scheduler == "serial":
                    _run_serial(tasks, bar)
                elif tasks:
                    _run_dask(tasks, scheduler, workers, bar)
            result = _gather(folder, scene, parameter, plain, ids, targets)
            if store is not None:
                result = dataclasses.replace(result, store=str(folder))
            write_netcdf(result.to_dataset(), folder / MAP_FILE)
    return result


def _gather(
    folder: Path,
    scene: Scene,
    parameter: str,
    values: list[float],
    ids: list[str],
    targets: list[float],
) -> WearLifeMap:
    paths: list[WearLife | None] = []
    statuses, reasons, cpu, wall = [], [], [], []
    for pid in ids:
        ds = _read_path(folder, pid)
        if ds is None:  # not written at all: a store that cannot be written
            ds = _failure("the path wrote no file")
        cpu.append(float(ds.attrs.get("cpu_time", math.nan)))
        wall.append(float(ds.attrs.get("wall_time", math.nan)))
        statuses.append(str(ds.attrs["status"]))
        reasons.append(str(ds.attrs["status_reason"]))
        paths.append(None if int(ds.attrs["path_error"]) else WearLife.from_dataset(ds))
    return WearLifeMap(
        scene=scene, parameter=parameter, values=tuple(values),
        units=key_attrs(scene, parameter)["units"], cycles=float(targets[-1]),
        checkpoints=np.array([0.0, *targets]), paths=tuple(paths), statuses=tuple(statuses),
        reasons=tuple(reasons), cpu_times=tuple(cpu), wall_times=tuple(wall),
    )  # fmt: skip


# --------------------------------------------------------------------------- the Dataset


def _padded(ds: xr.Dataset, planned: np.ndarray, width: int) -> xr.Dataset:
    """A path's Dataset on the planned checkpoints and ``width`` strobe crossings."""
    ds = ds.reindex(checkpoint=planned)
    if "crossing" in ds.dims and ds.sizes["crossing"] < width:
        ds = ds.pad(crossing=(0, width - ds.sizes["crossing"]))
    if "motion" in ds:
        text = np.asarray(ds["motion"].values, dtype=object)
        text[[not isinstance(t, str) for t in text]] = ""
        ds["motion"] = ds["motion"].copy(data=text.astype(str))
    return ds


def _per_value(life_map: WearLifeMap) -> dict[str, xr.Variable]:
    chaos, conf = [], []
    for path in life_map.paths:
        n = None if path is None else path.cycles_to_chaos
        chaos.append(math.nan if n is None else n)
        if n is None:
            conf.append(math.nan)
        else:
            i = int(np.flatnonzero(path.checkpoints == n)[0])  # type: ignore[union-attr]
            conf.append(float(path.dataset["motion_confidence"].values[i]))  # type: ignore[union-attr]
    v = ("value",)
    return {
        "path_status": variable(v, np.array(life_map.statuses, dtype=str), "1",
                                "wear path status: complete or failed"),
        "path_reason": variable(v, np.array(life_map.reasons, dtype=str), "1",
                                "how far the path went and why it ended"),
        "cycles_to_chaos": variable(v, chaos, "1", "first chaotic checkpoint, crank cycles "
                                    "of wear (NaN: not within the path)"),
        "chaos_confidence": variable(v, conf, "1",
                                     "confidence of the motion verdict at cycles_to_chaos"),
        "cpu_time": variable(v, list(life_map.cpu_times), "s", "CPU time of the path's task"),
        "wall_time": variable(v, list(life_map.wall_times), "s",
                              "wall time of the path's task"),
    }  # fmt: skip


def _map_dataset(life_map: WearLifeMap) -> xr.Dataset:
    planned = life_map.checkpoints
    found = [p.dataset for p in life_map.paths if p is not None]
    width = max((d.sizes.get("crossing", 0) for d in found), default=0)
    template = found[0] if found else None
    parts = []
    for path in life_map.paths:
        if path is not None:
            ds = path.dataset
        elif template is not None:  # a value whose task raised: every variable empty
            ds = template.isel(checkpoint=slice(0, 0))
        else:
            ds = xr.Dataset(coords={"checkpoint": ("checkpoint", np.zeros(0))})
        parts.append(_padded(ds.drop_attrs(deep=False), planned, width))
    attrs = key_attrs(life_map.scene, life_map.parameter)
    merged = xr.concat(parts, dim="value", data_vars="all", coords="minimal", join="outer",
                       combine_attrs="override")  # fmt: skip
    merged = merged.assign_coords(value=("value", np.array(life_map.values), attrs))
    for name, var in _per_value(life_map).items():
        merged[name] = var
    for name in ("checkpoint",):
        merged[name].attrs.update({"units": "1", "long_name": "crank cycles of wear"})
    settings = template.attrs if template is not None else {}
    merged.attrs.update(
        {k: settings[k] for k in ("averaged_revolutions", "max_depth_increment",
                                  "settle_revolutions", "analysis_revolutions", "exponent",
                                  "lyapunov_revolutions", "lyapunov_discard",
                                  "lyapunov_first_revolutions", "continuous_contact",
                                  "share_state_run", "verdict_samples_per_revolution",
                                  "increment_settle_revolutions")
         if k in settings}
    )  # fmt: skip
    merged.attrs.update(
        {"parameter": life_map.parameter, "cycles": life_map.cycles,
         "scene": life_map.scene.to_json(), "scene_name": life_map.scene.name}
    )  # fmt: skip
    if life_map.store is not None:
        merged.attrs["store"] = life_map.store
    return stamp(
        merged,
        title=f"wear life of scene {life_map.scene.name!r} over {life_map.parameter}",
        source=f"mechanism (chaoskit {__version__})",
        history=(
            f"mechanism.wear_life_map({life_map.scene.name!r}, parameter="
            f"{life_map.parameter!r}, values={list(life_map.values)}, cycles={life_map.cycles})"
        ),
    )
