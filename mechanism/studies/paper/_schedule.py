"""Where and in which order the study runs: the sweeps' dask backend, the process
pool of the long runs and their queue, the stores, and the prior cost of each stage."""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import json
import math
import os
import threading
from concurrent.futures import Future, ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

from .._wear_life import LYAPUNOV_FIRST_REVOLUTIONS
from ..sweep import dask_client
from ._published import (
    BEFORE_SPEEDS,
    CLEARANCES,
    SPEEDS,
    WEAR_PATHS,
)
from ._runs import (
    at_speed,
    chaos_run,
    equation_exponent,
    predict_worn,
    wear_path,
    wear_scene_of,
)
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


#: The progress stage that waits for the wear paths.
WEAR_PATHS_STAGE = "wear paths: cycles to chaos at 3 speeds and 3 clearances"


def wear_path_cost(rpm: float, settings: StudySettings, *, flexible: bool | None = None) -> float:
    """Prior CPU seconds of one wear path at ``rpm`` (one core; ``flexible`` overrides the
    settings' rods), as :func:`mechanism.wear_life` runs it with its default settings.

    Per analysed state (unworn, every checkpoint and the end): one run of the settled and
    analysed revolutions (it also gives the first increment worn from that state), the
    exponent (the unworn state the full run — its sign is undecided after the first
    revolutions at most speeds —, a worn state those first revolutions alone) and the
    motion verdict; per checkpoint interval: the increments after the first (one per 800
    cycles at any speed: the worn depth grows by 5–11 µm per 1 000 cycles at 30–150 rpm,
    faster as the grooves deepen, and an increment adds at most 0.025 of the 0.2 mm
    clearance), each its own run of
    settled and averaged revolutions. The rigid constants are fitted to the benchmark's
    five paths by phase (``benchmarks/wear_life.py``, ``docs/wear.md`` §7; each ended early
    by the model's limit: 30 rpm after 35 000 cycles, 566.4 CPU s; 60 rpm after 20 000,
    199.9 s; 90 rpm after 25 000, 148.7 s; 120 rpm after 20 000, 113.7 s; 150 rpm after
    15 000, 115.3 s; the prior gives 0.76–1.24 of them).
    Flexible rods take the study's fixed step in time, so a slower speed costs more per
    revolution (1.2 s per revolution at 150 rpm, 2.8 for the exponent).
    """
    flexible = settings.wear_path_flexible_rods if flexible is None else flexible
    points = [0.0, *settings.wear_path_checkpoints]
    if points[-1] < settings.wear_path_cycles:
        points.append(settings.wear_path_cycles)
    slower = 150.0 / rpm
    if flexible:
        revolution, exponent = 1.2 * slower, 2.8 * slower
    else:
        revolution = _RIGID_REVOLUTION * slower**_RIGID_REVOLUTION_POWER
        exponent = _RIGID_EXPONENT * slower**_RIGID_EXPONENT_POWER
    full = settings.wear_path_lyapunov_revolutions
    first = min(LYAPUNOV_FIRST_REVOLUTIONS, full)
    exponent_revolutions = full + (len(points) - 1) * first
    states = len(points) * ((2.0 + settings.wear_path_analysis_revolutions) * revolution + _VERDICT)
    increments = sum(
        max(1.0, (b - a) / _CYCLES_PER_INCREMENT) - 1.0 for a, b in itertools.pairwise(points)
    )
    return (
        states
        + exponent_revolutions * exponent
        + increments * (2.0 + settings.wear_path_averaged_revolutions) * revolution
    )


#: CPU seconds of the rigid paper scene at 150 rpm along a wear path: one simulated
#: revolution (with averaging its wear) and one revolution of the exponent, each times
#: (150 rpm / speed) to its power; one motion verdict (fitted to the benchmark's measured
#: paths by phase, docs/wear.md §7)
_RIGID_REVOLUTION, _RIGID_REVOLUTION_POWER = 0.202, 0.72
_RIGID_EXPONENT, _RIGID_EXPONENT_POWER = 0.647, 0.72
_VERDICT = 3.9
#: Crank cycles per wear increment (the depth cap reached about every 800 cycles)
_CYCLES_PER_INCREMENT = 800.0


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
    its own CPU time in wall time, the pool doing as much meanwhile, and the wear-paths and
    long-runs stages are what the pool has left, on two cores (the wear paths
    :func:`wear_path_cost` first). The analysis runs on one core.
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
    paths = (
        sum(wear_path_cost(rpm, settings) for rpm, _ in WEAR_PATHS) if settings.wear_paths else 0.0
    )
    pool = (
        paths
        + 0.5 * (settings.wear_updates + 1) * (settings.wear_settle_revolutions + 1) * speeds * flex
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
        # the pool's work left when the dask stages end, on two cores, the wear paths first
        WEAR_PATHS_STAGE: min(paths, max(pool - sum(dask.values()), 0.0)) / 2.0,
        "long runs for the chaos analysis and exponents": max(
            pool - paths - sum(dask.values()), 0.0
        )
        / 2.0,
        "chaos analysis and report": 4 * (8.0 + 0.04e-3 * samples),
    }


class LongRuns:
    """The study's long compiled runs in the process pool, in the order that finishes
    first: the three wear predictions (short; the after-wear sweeps wait for them) at once;
    as soon as the profile worn at 150 rpm exists, the after-wear chaos run (the longest
    run) first, then the before-wear chaos run, the five wear paths of the wear-life
    answer (each one task, the slowest speed first), the two exponents and, when asked
    for, the rigid-rod ones. Without the wear paths the pool's two processes finish within
    a short run of each other (measured on the quick settings: 240 s of CPU for the
    after-wear chaos run against 141 + 62 + 54 s for the rest); the paths, about as long
    as a chaos run each, are spread over both.

    With no pool (``client="serial"``) everything runs here, in that order.
    """

    def __init__(self, pool: Any, base_scene: Any, settings: StudySettings) -> None:
        self._pool = pool
        self._settings = settings
        self._base = base_scene
        before = wear_scene_of(base_scene)
        # the wear predictions are short, and the after-wear sweeps wait for them
        self._wear = {
            float(rpm): submit(pool, predict_worn, at_speed(base_scene, rpm), settings)
            for rpm in sorted(SPEEDS, reverse=True)
        }
        self._states: dict[str, list[Any]] = {}
        self._paths: dict[tuple[float, float], Future[Any]] = {}
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
        # the wear paths (each one task, the slowest speed first: its revolutions are the
        # longest) before the exponents, the shortest runs, so that the pool's two
        # processes end close together
        if settings.wear_paths:
            for rpm, clearance in sorted(WEAR_PATHS):
                self._paths[(rpm, clearance)] = submit(
                    pool, wear_path, self._base, rpm, clearance, settings
                )
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

    def paths(self) -> dict[tuple[float, float], Future[Any]]:
        """The wear paths by (crank speed in rpm, clearance in m); empty when the settings
        leave them out."""
        self._queued()
        return dict(self._paths)

    def states(self) -> dict[str, tuple[Future[Any], Future[Any], Future[Any] | None]]:
        """(chaos run, exponent on the series' model, rigid-rod exponent or None when the
        series are rigid) of each state whose scene exists."""
        self._queued()
        return {state: (f[0], f[1], f[2]) for state, f in self._states.items() if len(f) == 3}
