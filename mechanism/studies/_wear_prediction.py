"""Wear prediction: ``predict_wear`` (cycle extrapolation) and ``compare_wear`` (before/after).

The wear of one run (:func:`mechanism.core.wear.run_wear`) is part of the core; this study
builds on it:

* :func:`predict_wear` — the update loop of docs/paper-model.md §6 (Flores 2009; Mukras 2010):
  settle, accumulate one cycle's wear, extrapolate over a block of cycles with the depth
  increment limited relative to the clearance, smooth, update the profile, repeat.
* :func:`compare_wear` — the response metrics of docs/paper-model.md §7 before and after wear, side
  by side with their ratios (metric definitions shared with sweeps, ``_metrics.py``).

See ``docs/wear.md``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from chaoskit.contract import __version__, check_int, check_positive, stamp, variable
from mechanism.core import Scene, simulate
from mechanism.core.record import METRICS, ROD_STRAIN, response_metrics, window_start
from mechanism.core.scene import ClearanceRevolute
from mechanism.core.wear import SURFACES, WornProfile, clearance_joint, run_wear, surface_angle

__all__ = [
    "WearComparison",
    "WearPrediction",
    "compare_wear",
    "predict_wear",
]

# --------------------------------------------------------------------------- predict_wear


def _with_profiles(scene: Scene, profiles: dict[str, WornProfile]) -> Scene:
    joints = dict(scene.joints)
    for name, profile in profiles.items():
        joint = joints[name]
        if not isinstance(joint, ClearanceRevolute):
            raise TypeError(f"joint {name!r} is not a clearance_revolute joint; it has no profile.")
        joints[name] = profile.apply_to(joint)
    return dataclasses.replace(scene, joints=joints)


@dataclass(frozen=True, kw_only=True, eq=False)
class WearPrediction:
    """Result of :func:`predict_wear`.

    Attributes
    ----------
    scene, worn_scene : Scene
        The starting scene and the scene carrying the final profiles (``simulate`` runs it;
        ``save_scene``/``load_scene`` round-trip it).
    cycles : numpy.ndarray
        Cumulative crank cycles of wear at each update state 0…``updates``.
    reduced_updates : int
        Updates whose block of cycles was shortened by ``max_depth_increment``.
    dataset : xarray.Dataset
        See :meth:`to_dataset`.
    """

    scene: Scene
    worn_scene: Scene
    cycles: np.ndarray
    reduced_updates: int
    dataset: xr.Dataset

    @property
    def updates(self) -> int:
        return int(self.cycles.size - 1)

    def to_dataset(self) -> xr.Dataset:
        """``wear_depth(update, joint, surface, angle)`` (m), ``worn_volume(update, joint,
        surface)`` (m³), ``cycles(update)``, ``block_cycles(update)``, the response metrics
        of each update state (``peak_contact_force(update)``, …), the worn scene as JSON in
        ``attrs["worn_scene"]`` and the settings in attrs."""
        return self.dataset.copy()


def predict_wear(
    scene: Scene,
    *,
    updates: int,
    cycles_per_update: float,
    max_depth_increment: float = 0.25,
    settle_revolutions: float = 2.0,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    progress: bool = False,
) -> WearPrediction:
    """Predict the worn profile of every clearance joint by cycle extrapolation.

    For each update u = 0 … ``updates`` − 1 (docs/paper-model.md §6, Flores 2009, Mukras 2010):

    1. simulate ``settle_revolutions`` + 1 crank revolutions with the current profiles
       (the worn geometry shapes the contact) and take the response metrics and the
       Archard wear h_cyc of the last revolution (:func:`run_wear`);
    2. block ΔN = ``cycles_per_update``, reduced so that no region deepens by more than
       ``max_depth_increment`` × clearance (and no journal region wears through);
    3. h ← h + ΔN · smooth(h_cyc) with the joint's ``smoothing_regions`` moving average;
    4. rebuild the joint's local clearance, curvature and stiffness from h.

    A final run gives the metrics of the worn state. Depths stay finite and ≥ 0, so the
    local clearance never drops below the nominal one.

    Parameters
    ----------
    scene : Scene
        The mechanism; every clearance joint wears (``effects.wear`` is switched on).
    updates : int
        Number of profile updates (≥ 1; the paper-era practice is 2–10).
    cycles_per_update : float
        Crank cycles ΔN extrapolated per update (> 0).
    max_depth_increment : float
        Largest depth increment of one update, as a fraction of the joint's clearance
        (> 0); larger blocks are shortened.
    settle_revolutions : float
        Revolutions simulated before the cycle that is measured (≥ 0).
    method, rtol, atol, output_step
        Passed to :func:`mechanism.simulate`.
    progress : bool
        Show a progress bar over the updates.

    Returns
    -------
    WearPrediction

    Raises
    ------
    mechanism.SimulationError
        When a simulation fails.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper").replace({"drive.speed_rpm": 150.0})
    >>> pred = mechanism.predict_wear(scene, updates=1, cycles_per_update=1e4,
    ...                               settle_revolutions=0.5)  # doctest: +SKIP
    >>> pred.worn_scene.joints["C"].wear.bearing_profile[:1]  # doctest: +SKIP
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    updates = check_int(updates, name="updates", minimum=1)
    block = check_positive(cycles_per_update, name="cycles_per_update")
    limit = check_positive(max_depth_increment, name="max_depth_increment")
    settle = float(settle_revolutions)
    if not (math.isfinite(settle) and settle >= 0.0):
        raise ValueError(f"settle_revolutions must be >= 0; got {settle_revolutions!r}.")
    scene = scene.replace({"effects.wear": True})
    names = [n for n, j in scene.joints.items() if isinstance(j, ClearanceRevolute)]
    if not names or not scene.effects.clearance:
        raise ValueError("predict_wear needs a scene with an active clearance joint.")
    profiles = {n: WornProfile.from_joint(clearance_joint(scene, n)) for n in names}
    if len({p.regions for p in profiles.values()}) != 1:
        raise ValueError("all clearance joints must have the same wear.regions.")
    kwargs: dict[str, Any] = {
        "method": method,
        "rtol": rtol,
        "atol": atol,
        "output_step": output_step,
    }

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=updates + 1, desc=f"predict_wear {scene.name}", unit="update")
    depth_hist: list[np.ndarray] = []
    metrics_hist: list[dict[str, xr.DataArray]] = []
    block_hist: list[float] = []
    reduced = 0
    current = scene
    try:
        for u in range(updates + 1):
            depth_hist.append(
                np.stack([[p.bearing_depth, p.journal_depth] for p in profiles.values()])
            )
            traj = simulate(current, revolutions=settle + 1.0, **kwargs)
            start = window_start(traj, settle)
            metrics_hist.append(response_metrics(traj, start))
            if bar is not None:
                bar.update(1)
            if u == updates:
                block_hist.append(0.0)
                break
            wear = run_wear(current, traj, start=start)
            cycles = block
            increments = {}
            for name in names:
                p = profiles[name]
                # smoothed like the profile itself (its own smoothing_regions)
                step = p.with_depth(
                    bearing_depth=wear[name].depth[0], journal_depth=wear[name].depth[1]
                )
                dh = np.stack(
                    [step.smoothed_depth(surface="bearing"), step.smoothed_depth(surface="journal")]
                )
                if p.surfaces == "bearing":
                    dh[1] = 0.0
                if not np.all(np.isfinite(dh)):
                    raise ValueError(f"joint {name!r}: non-finite wear in update {u}.")
                increments[name] = dh
                peak = float(dh.max())
                if peak > 0.0:
                    cycles = min(cycles, limit * p.clearance / peak)
                jpeak = float(dh[1].max())
                if jpeak > 0.0:
                    room = 0.5 * (p.journal_radius - float(p.journal_depth.max()))
                    cycles = min(cycles, room / jpeak)
            if cycles < block:
                reduced += 1
            block_hist.append(cycles)
            profiles = {
                n: profiles[n].with_depth(
                    bearing_depth=profiles[n].bearing_depth + cycles * increments[n][0],
                    journal_depth=profiles[n].journal_depth + cycles * increments[n][1],
                )
                for n in names
            }
            current = _with_profiles(current, profiles)
    finally:
        if bar is not None:
            bar.close()
    worn_scene = current
    cum = np.concatenate([[0.0], np.cumsum(block_hist[:-1])])
    ds = _prediction_dataset(
        scene, worn_scene, names, profiles, depth_hist, metrics_hist, block_hist, cum,
        settings={
            "updates": updates,
            "cycles_per_update": block,
            "max_depth_increment": limit,
            "settle_revolutions": settle,
        },
    )  # fmt: skip
    return WearPrediction(
        scene=scene, worn_scene=worn_scene, cycles=cum, reduced_updates=reduced, dataset=ds
    )


def _prediction_dataset(
    scene: Scene,
    worn_scene: Scene,
    names: list[str],
    profiles: dict[str, WornProfile],
    depth_hist: list[np.ndarray],
    metrics_hist: list[dict[str, xr.DataArray]],
    block_hist: list[float],
    cum: np.ndarray,
    *,
    settings: dict[str, Any],
) -> xr.Dataset:
    depth = np.stack(depth_hist)  # (update, joint, surface, angle)
    regions = depth.shape[-1]
    volume = np.zeros(depth.shape[:3])
    for u in range(depth.shape[0]):
        for j, name in enumerate(names):
            state = profiles[name].with_depth(
                bearing_depth=depth[u, j, 0], journal_depth=depth[u, j, 1]
            )
            volume[u, j] = (state.bearing_volume, state.journal_volume)
    data: dict[str, Any] = {
        "wear_depth": variable(("update", "joint", "surface", "angle"), depth, "m", "wear depth"),
        "worn_volume": variable(("update", "joint", "surface"), volume, "m3", "worn volume"),
        "cycles": variable(("update",), cum, "1", "crank cycles of wear at this update state"),
        "block_cycles": variable(
            ("update",), block_hist, "1", "cycles extrapolated after this update state"
        ),
    }
    for name, (units, long_name) in METRICS.items():
        values = [float(m[name].values) for m in metrics_hist]
        data[name] = variable(("update",), values, units, long_name + " (last revolution)")
    coords: dict[str, Any] = {
        "update": ("update", np.arange(depth.shape[0]), {"long_name": "profile update"}),
        "joint": ("joint", np.array(names, dtype=object)),
        "surface": ("surface", np.array(SURFACES, dtype=object)),
        "angle": surface_angle(regions),
    }
    if all(ROD_STRAIN in m for m in metrics_hist):
        strain = xr.concat([m[ROD_STRAIN] for m in metrics_hist], dim="update")
        data[ROD_STRAIN] = variable(
            ("update", "rod"), strain.values, "1", strain.attrs.get("long_name", ROD_STRAIN)
        )
        coords["rod"] = ("rod", np.asarray(strain["rod"].values).astype(object))
    ds = xr.Dataset(data, coords=coords)
    ds.attrs["scene"] = scene.to_json()
    ds.attrs["worn_scene"] = worn_scene.to_json()
    ds.attrs["scene_name"] = scene.name
    for key, value in settings.items():
        ds.attrs[key] = value
    return stamp(
        ds,
        title=f"wear prediction of scene {scene.name!r}",
        source=f"mechanism (chaoskit {__version__})",
        history=(
            f"mechanism.predict_wear({scene.name!r}, updates={settings['updates']}, "
            f"cycles_per_update={settings['cycles_per_update']})"
        ),
    )


# --------------------------------------------------------------------------- compare_wear


@dataclass(frozen=True, kw_only=True, eq=False)
class WearComparison:
    """Response metrics before and after wear with their ratios (:func:`compare_wear`).

    ``table`` is a pandas DataFrame indexed by metric with columns ``before``, ``after``,
    ``ratio`` (after/before) and ``units``; rod strains appear as
    ``rod_strain_extreme[<rod>]``.
    """

    table: pd.DataFrame
    discard_revolutions: float

    def to_dataset(self) -> xr.Dataset:
        """Variables ``before``, ``after``, ``ratio`` over dim ``metric`` with ``units``."""
        t = self.table
        ds = xr.Dataset(
            {
                "before": variable(("metric",), t["before"].to_numpy(float), "", "value before"),
                "after": variable(("metric",), t["after"].to_numpy(float), "", "value after"),
                "ratio": variable(("metric",), t["ratio"].to_numpy(float), "1", "after / before"),
            },
            coords={
                "metric": ("metric", np.array(t.index, dtype=object)),
                "units": ("metric", np.array(t["units"], dtype=object)),
            },
        )
        for v in ("before", "after"):
            ds[v].attrs["units"] = "see the units coordinate"
        ds.attrs["discard_revolutions"] = self.discard_revolutions
        return ds


def _metric_rows(traj: xr.Dataset, discard: float) -> dict[str, tuple[float, str]]:
    start = window_start(traj, discard)
    rows: dict[str, tuple[float, str]] = {}
    for name, da in response_metrics(traj, start).items():
        if name == ROD_STRAIN:
            for rod, value in zip(da["rod"].values, da.values, strict=True):
                rows[f"{ROD_STRAIN}[{rod}]"] = (float(value), "1")
        else:
            rows[name] = (float(da.values), METRICS[name][0])
    return rows


def compare_wear(
    before: xr.Dataset, after: xr.Dataset, *, discard_revolutions: float = 1.0
) -> WearComparison:
    """The paper's response metrics of two trajectories side by side, with ratios.

    Displacement error, speed error, peak contact force, maximum penetration, signed
    extreme driving torque and (when recorded) the signed extreme rod strains, each over
    the samples after ``discard_revolutions`` (docs/paper-model.md §7; the same definitions as
    the sweep's metrics). ratio = after/before (signed metrics keep their sign, so a
    torque extreme that grows in magnitude has a ratio > 1 when the sign is unchanged).

    Parameters
    ----------
    before, after : xarray.Dataset
        Trajectories from :func:`mechanism.simulate` (e.g. of ``pred.scene`` and
        ``pred.worn_scene``).
    discard_revolutions : float
        Transient dropped from both (crank revolutions).

    Returns
    -------
    WearComparison

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> a = xr.Dataset({"contact_force": ("time", [0.0, 1.0, 2.0, 1.0, 0.0])}, {"time": t})
    >>> b = a.assign(contact_force=2.0 * a.contact_force)
    >>> float(compare_wear(a, b, discard_revolutions=0).table.loc["peak_contact_force", "ratio"])
    2.0
    """
    for label, ds in (("before", before), ("after", after)):
        if not isinstance(ds, xr.Dataset):
            raise TypeError(f"{label} must be an xarray.Dataset; got {type(ds).__name__}.")
    discard = float(discard_revolutions)
    if not (math.isfinite(discard) and discard >= 0.0):
        raise ValueError(f"discard_revolutions must be >= 0; got {discard_revolutions!r}.")
    rb = _metric_rows(before, discard)
    ra = _metric_rows(after, discard)
    index = [k for k in rb if k in ra]
    b = np.array([rb[k][0] for k in index])
    a = np.array([ra[k][0] for k in index])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(b != 0.0, a / b, np.nan)
    table = pd.DataFrame(
        {"before": b, "after": a, "ratio": ratio, "units": [rb[k][1] for k in index]},
        index=pd.Index(index, name="metric"),
    )
    return WearComparison(table=table, discard_revolutions=discard)
