"""The sweep driver: resolve and check the grid, check the store's manifest, skip the
points already done, hand the rest to a backend, then gather from disk."""

from __future__ import annotations

import itertools
import json
import logging
import math
import os
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from mechanism.core import load_scene

from . import _store
from ._analysis import Analysis
from ._backends import run_dask, run_serial
from ._gather import gather
from ._point import PointTask, simulate_point
from ._transforms import grid_transforms

_log = logging.getLogger("mechanism.sweep")


def resolve_scene(scene: Any) -> Any:
    """A scene from a :class:`mechanism.Scene`, a built-in scene name or a TOML path."""
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
        transform = grid_transforms().get(key)
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
                f"nor a registered special key {sorted(grid_transforms())}."
            )
        for value in values:
            try:
                scene.replace({key: value})
            except Exception as exc:
                raise ValueError(f"grid[{key!r}] = {value!r}: {exc}") from exc


#: The manifest's name of the default simulator. Stores written before the sweep became a
#: package record the function under its old module; keeping the name lets them resume.
DEFAULT_SIMULATOR_NAME = "mechanism.studies._sweep._simulate_point"


def _callable_name(func: Callable[..., Any]) -> str:
    """The simulator's name recorded in the manifest (a resumed sweep must use the same)."""
    if func is simulate_point:
        return DEFAULT_SIMULATOR_NAME
    return f"{getattr(func, '__module__', '?')}.{getattr(func, '__qualname__', repr(func))}"


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
    :func:`register_grid_transform`; built in: ``"wear"``, ``"samples_per_revolution"``),
    simulated for ``revolutions`` crank revolutions. Each point writes
    ``STORE/points/<id>.nc`` (its trajectory) and ``<id>.summary.nc``: its status, the
    response metrics of docs/paper-model.md §7 over the revolutions after
    ``analysis.discard_revolutions``,

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
        Crank revolutions simulated per point (> ``analysis.discard_revolutions``). A
        motor-driven crank has no drive period: its points run for ``revolutions``
        periods 2π/ω₀ of the motor's no-load speed ω₀ (at most about as many crank turns),
        and ``analysis.discard_revolutions`` counts turns of its crank angle.
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
    simulator = _simulator if _simulator is not None else simulate_point

    scene = resolve_scene(scene)
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
    registered = grid_transforms()
    used = tuple(registered[k] for k in plain_grid if k in registered)
    todo = [
        PointTask(
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
            run_serial(todo, progress)
        else:
            run_dask(todo, client, n_workers, progress)

    result = gather(
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
