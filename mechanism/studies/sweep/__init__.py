"""Parameter sweeps: one task per grid point on dask.distributed, results as one Dataset.

The driver (:func:`sweep`) resolves the grid, checks the store's manifest, skips points that
are already done and hands the rest to a backend — in-process (``client="serial"``) or
dask.distributed (a ``LocalCluster`` by default, any scheduler). Each point runs on a
worker: build the scene, simulate, write the trajectory and a summary (status, response
metrics, ``chaoskit.analyze`` fields) into the store. The driver then gathers every summary
from disk, so the result depends on the store's contents only and a serial run and a dask
run give the same Dataset.

Failure is data (as diffrax's ``throw=False``): a point that raises, or whose simulation does
not succeed, is recorded with ``status`` ("failed" or "diverged") and ``message``; the sweep
always finishes.

Modules, one concern each: ``_analysis`` (what a point analyses), ``_transforms`` (the
special grid keys and their registry), ``_point`` (the work of one point), ``_backends``
(serial and dask), ``_driver`` (:func:`sweep`), ``_gather`` (the Dataset from the store),
``_views`` (stroboscopic points, chaos maps) and ``_store`` (the on-disk layout).
"""

from __future__ import annotations

from ._analysis import Analysis
from ._backends import dask_client
from ._driver import resolve_scene, sweep
from ._gather import key_attrs, load_sweep
from ._point import STATUSES
from ._revolution import revolution_time, simulated_span
from ._store import (
    MANIFEST_FORMAT,
    SweepStoreBusy,
    SweepStoreMismatch,
    check_or_write_manifest,
    locked,
    remove_stale_temporaries,
)
from ._transforms import (
    WEAR_AFTER_SETTINGS,
    GridTransform,
    grid_transforms,
    register_grid_transform,
    wear_transform,
)
from ._views import chaos_map, stroboscopic_points

__all__ = [
    "MANIFEST_FORMAT",
    "STATUSES",
    "WEAR_AFTER_SETTINGS",
    "Analysis",
    "GridTransform",
    "SweepStoreBusy",
    "SweepStoreMismatch",
    "chaos_map",
    "check_or_write_manifest",
    "dask_client",
    "grid_transforms",
    "key_attrs",
    "load_sweep",
    "locked",
    "register_grid_transform",
    "remove_stale_temporaries",
    "resolve_scene",
    "revolution_time",
    "simulated_span",
    "stroboscopic_points",
    "sweep",
    "wear_transform",
]
