"""Where and in which order the study runs: the sweeps' dask backend, the process
pool of the long runs and their queue, the stores, and the prior cost of each stage."""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import threading
from concurrent.futures import Future, ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

from ..sweep import dask_client
from ._published import (
    BEFORE_SPEEDS,
    CLEARANCES,
    SPEEDS,
)
from ._runs import at_speed, chaos_run, equation_exponent, predict_worn, wear_scene_of
from ._settings import StudySettings


def store_name(kind: str, settings: StudySettings, quick: bool) -> str:
    """Folder name of a sweep store: its kind, the settings' name and a digest of the
    settings (a re-run with other settings does not resume a store)."""
    digest = hashlib.sha1(json.dumps(settings.to_dict(), sort_keys=True).encode()).hexdigest()
    return f"{kind}-{'quick' if quick else 'paper'}-{digest[:8]}"


def session_client(client: Any, n_workers: int | None, n_tasks: int) -> Any:
    """A context manager giving the backend of the sweeps (one cluster for the study)."""
    if client == "serial":
        return contextlib.nullcontext("serial")
    return dask_client(client, n_workers, n_tasks)


def process_pool(client: Any, n_workers: int | None) -> Any:
    """Processes for the long compiled runs (wear, chaos, exponents), or this process.

    A long compiled run holds the GIL, so on a dask worker it misses the heartbeats and is
    restarted; separate processes run them in parallel without that limit.
    """
    if client == "serial":
        return contextlib.nullcontext(None)
    workers = n_workers or min(os.cpu_count() or 1, 2)
    return ProcessPoolExecutor(max_workers=max(1, workers), mp_context=get_context("spawn"))


def submit(pool: Any, fn: Any, *args: Any, **kwargs: Any) -> Any:
    """``fn(*args, **kwargs)`` in the pool, or here when there is none; a Future either way."""
    if pool is None:
        done: Future[Any] = Future()
        try:
            done.set_result(fn(*args, **kwargs))
        except Exception as exc:
            done.set_exception(exc)
        return done
    return pool.submit(fn, *args, **kwargs)


def folder_size(folder: Path) -> int:
    """Bytes in the files under ``folder``."""
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def drop_trajectories(store: Path) -> None:
    """Remove a sweep store's point trajectories, keep its summaries (the metrics)."""
    for path in (store / "points").glob("*.nc"):
        if not path.name.endswith(".summary.nc"):
            path.unlink(missing_ok=True)


def stage_weights(settings: StudySettings, n_conv: int) -> dict[str, float]:
    """Prior wall time of each stage, in CPU seconds of one core (for the time left).

    Calibrated on the quick settings (CPU seconds per revolution at 150 rpm; a slower
    speed v costs 150/v times as much, the step being fixed in time): a flexible response
    point with its ideal companion 1.55 at the output grid T/2500 (2.6 at T/10000; rigid
    0.25); a rigid orbit revolution 0.08 before wear and 0.29 after (0.18 on average;
    flexible 1.2, on the paper settings); a convergence run 2 per revolution; a flexible
    chaos run 0.70 before and 1.19 after wear; a flexible exponent 2.8 (rigid 1.3). The
    long runs (wear, chaos runs, exponents) run in the pool beside the sweeps and the
    orbit diagrams, and the four processes share the two cores: a dask stage takes about
    its own CPU time in wall time, the pool doing as much meanwhile, and the long-runs
    stage is what the pool has left, on two cores. The analysis runs on one core.
    """
    flex = (1.2 + 0.35 * settings.samples_per_revolution / 2500) if settings.flexible_rods else 0.25
    speeds = sum(150.0 / v for v in SPEEDS)
    before_speeds = sum(150.0 / v for v in BEFORE_SPEEDS)
    orbit = (1.2 if settings.orbit_flexible_rods else 0.18) * sum(
        150.0 / v for v in settings.orbit_speeds
    )
    long_run = settings.discard_revolutions + settings.chaos_revolutions
    dask = {
        "before-wear sweep": len(CLEARANCES) * settings.revolutions * before_speeds * flex,
        "after-wear sweeps": settings.revolutions * speeds * flex,
        "orbit diagrams over speed": 2 * settings.orbit_revolutions * orbit,
    }
    exponent = (
        (2.8 + (1.3 if settings.rigid_rod_exponent else 0.0)) if settings.flexible_rods else 1.3
    )
    pool = (
        0.5 * (settings.wear_updates + 1) * (settings.wear_settle_revolutions + 1) * speeds * flex
        + 2 * long_run * (0.95 if settings.flexible_rods else 0.2)
        + 2 * (settings.discard_revolutions + settings.exponent_revolutions) * exponent
    )
    samples = min(
        long_run * settings.chaos_samples_per_revolution, settings.max_samples or math.inf
    )
    return {
        # left out of the estimate: minutes on a fresh install, seconds with the cache
        "compiling the kernels (first run only)": 0.0,
        "before-wear sweep": dask["before-wear sweep"],
        # done in the pool while the before-wear sweep runs
        "wear prediction at 30, 90, 150 rpm": 0.0,
        "after-wear sweeps": dask["after-wear sweeps"],
        "element convergence": n_conv * settings.convergence_revolutions * 2.0,
        "orbit diagrams over speed": dask["orbit diagrams over speed"],
        "long runs for the chaos analysis and exponents": max(pool - sum(dask.values()), 0.0) / 2.0,
        "chaos analysis and report": 4 * (8.0 + 0.04e-3 * samples),
    }


class LongRuns:
    """The study's long compiled runs in the process pool, in the order that finishes
    first: the three wear predictions (short; the after-wear sweeps wait for them) at once;
    as soon as the profile worn at 150 rpm exists, the after-wear chaos run (the longest
    run) first, then the before-wear chaos run, the two exponents and, when asked for, the
    rigid-rod ones. The pool's two processes then finish within a short run of each other
    (measured on the quick settings: 240 s of CPU for the after-wear chaos run against
    141 + 62 + 54 s for the rest).

    With no pool (``client="serial"``) everything runs here, in that order.
    """

    def __init__(self, pool: Any, base_scene: Any, settings: StudySettings) -> None:
        self._pool = pool
        self._settings = settings
        before = wear_scene_of(base_scene)
        # the wear predictions are short, and the after-wear sweeps wait for them
        self._wear = {
            float(rpm): submit(pool, predict_worn, at_speed(base_scene, rpm), settings)
            for rpm in sorted(SPEEDS, reverse=True)
        }
        self._states: dict[str, list[Any]] = {}
        self._queue = threading.Thread(
            target=self._then, args=(before,), name="paper-long-runs", daemon=True
        )
        if pool is None:
            self._then(before)
        else:
            self._queue.start()

    def _then(self, before: Any) -> None:
        pool, settings = self._pool, self._settings
        try:
            worn = self._wear[150.0].result()[0]
        except Exception:
            worn = None
        scenes = {"before wear": before, "after wear": worn}
        order = [s for s in ("after wear", "before wear") if scenes[s] is not None]
        runs: dict[str, list[Any]] = {s: [] for s in order}
        for state in order:
            runs[state].append(submit(pool, chaos_run, scenes[state], settings))
        for state in order:
            runs[state].append(submit(pool, equation_exponent, scenes[state], settings))
        # the rigid-rod model's exponent beside the flexible one
        rigid = settings.flexible_rods and settings.rigid_rod_exponent
        for state in order:
            runs[state].append(
                submit(pool, equation_exponent, scenes[state], settings, rigid=True)
                if rigid
                else None
            )
        self._states = {s: runs[s] for s in ("before wear", "after wear") if s in runs}
        self._scenes = scenes

    def rigid_exponent(self, state: str) -> Future[Any]:
        """The rigid-rod exponent of ``state``: the queued one, or queued now (a series
        that fell back to rigid rods is judged with it even when the settings leave it
        out)."""
        self._queued()
        queued = self._states[state][2]
        if queued is not None:
            return queued
        scene = self._scenes[state]
        return submit(self._pool, equation_exponent, scene, self._settings, rigid=True)

    def _queued(self) -> None:
        if self._queue.is_alive():
            self._queue.join()

    def wear(self) -> dict[float, Future[Any]]:
        """The wear predictions by speed (rpm), in increasing speed."""
        return {rpm: self._wear[rpm] for rpm in sorted(self._wear)}

    def states(self) -> dict[str, tuple[Future[Any], Future[Any], Future[Any] | None]]:
        """(chaos run, exponent on the series' model, rigid-rod exponent or None when the
        series are rigid) of each state whose scene exists."""
        self._queued()
        return {state: (f[0], f[1], f[2]) for state, f in self._states.items() if len(f) == 3}
