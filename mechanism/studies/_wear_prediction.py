"""Wear in the dynamics: run wear, ``predict_wear`` (cycle extrapolation) and ``compare``.

* :func:`run_wear` — the Archard wear one simulated run produces, from its contact samples
  (``simulate`` adds it to the Dataset when ``effects.wear`` is on).
* :func:`predict_wear` — the update loop of paper-model §2.7 (Flores 2009; Mukras 2010):
  settle, accumulate one cycle's wear, extrapolate over a block of cycles with the depth
  increment limited relative to the clearance, smooth, update the profile, repeat.
* :func:`compare` — the response metrics of paper-model §2.10 before and after wear, side
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

from chaoskit._contract import stamp
from chaoskit._validate import check_int, check_positive
from chaoskit._version import __version__
from mechanism.core.contact import contact_parameters
from mechanism.core.model._assemble import scene_to_json
from mechanism.core.record._metrics import METRICS, ROD_STRAIN, response_metrics, window_start
from mechanism.core.scene import ClearanceRevolute, Scene
from mechanism.core.wear import WornProfile, archard_wear
from mechanism.core.wear import _kernels as wk

__all__ = [
    "Comparison",
    "JointWear",
    "WearPrediction",
    "compare",
    "predict_wear",
    "run_wear",
]

_SURFACES = ("bearing", "journal")


def _var(dims: tuple[str, ...], data: Any, units: str, long_name: str) -> xr.Variable:
    return xr.Variable(dims, np.asarray(data), attrs={"units": units, "long_name": long_name})


# --------------------------------------------------------------------------- run wear


@dataclass(frozen=True, kw_only=True, eq=False)
class JointWear:
    """Wear one clearance joint accumulated over a window of a simulated run.

    Attributes
    ----------
    joint : str
        Joint name.
    depth : numpy.ndarray
        (2, regions) depth increments (m) of the bearing and journal regions.
    volume : tuple[float, float]
        Volume removed from the bearing and the journal (m³).
    requested_volume : float
        k Σ Fₙ |v_t| Δt over the window (m³); equals each surface's volume unless an
        increment was reduced (``reduced`` > 0).
    sliding_distance : float
        Σ |v_t| Δt over the samples in contact (m).
    reduced, rejected : int
        Increments scaled down by a depth limit, and non-finite samples skipped.
    """

    joint: str
    depth: np.ndarray
    volume: tuple[float, float]
    requested_volume: float
    sliding_distance: float
    reduced: int
    rejected: int


def _clearance_joint(scene: Scene, name: str) -> ClearanceRevolute:
    joint = scene.joints.get(name)
    if not isinstance(joint, ClearanceRevolute):
        raise ValueError(f"{name!r} is not a clearance joint of scene {scene.name!r}.")
    return joint


def _trapezoid_weights(t: np.ndarray) -> np.ndarray:
    """Weights w with Σ wᵢ fᵢ = trapezoidal ∫ f dt on the sample times ``t``."""
    w = np.zeros(t.size)
    if t.size > 1:
        dt = np.diff(t)
        w[:-1] += 0.5 * dt
        w[1:] += 0.5 * dt
    return w


def run_wear(
    scene: Scene,
    traj: xr.Dataset,
    *,
    start: int = 0,
    max_increment: float | None = None,
) -> dict[str, JointWear]:
    """Archard wear of every clearance joint over the samples ``traj.time[start:]``.

    Per output sample i in contact: slip Δsᵢ = |v_t,i| wᵢ with wᵢ the trapezoidal weight of
    the sample, Hertz half-width from the local R* of the scene's profile (same stiffness
    form as K, paper A7), ΔV = k Fₙ Δs to the region containing the contact angle (spread
    over ±a/R when ``spread_over_contact_width``). The volume Σ ΔV is therefore
    k ∫ Fₙ |v_t| dt by the trapezoidal rule on the output grid, which by default is also
    the largest step the integrator takes while clearance joints are active.

    Parameters
    ----------
    scene : Scene
        The scene the trajectory was simulated from (its profiles are the starting point).
    traj : xarray.Dataset
        Output of :func:`mechanism.simulate` (needs ``contact_force``,
        ``sliding_velocity``, ``contact_angle``, ``contact_angle_journal``).
    start : int
        First sample of the window.
    max_increment : float, optional
        Cap (m) on the depth any region may gain from one sample.

    Returns
    -------
    dict
        :class:`JointWear` by joint name.
    """
    if "joint" not in traj.dims:
        return {}
    t = np.asarray(traj["time"].values, dtype=np.float64)[start:]
    w = _trapezoid_weights(t)
    out: dict[str, JointWear] = {}
    for name in np.asarray(traj["joint"].values).astype(str):
        joint = _clearance_joint(scene, str(name))
        sel = traj.sel(joint=name).isel(time=slice(start, None))
        force = np.nan_to_num(np.asarray(sel["contact_force"].values, dtype=np.float64))
        slip = np.abs(np.asarray(sel["sliding_velocity"].values, dtype=np.float64)) * w
        slip = np.nan_to_num(slip)
        profile = WornProfile.from_joint(joint)
        n = profile.regions
        if joint.wear.coefficient == 0.0 or not (force > 0.0).any():
            out[str(name)] = JointWear(
                joint=str(name), depth=np.zeros((2, n)), volume=(0.0, 0.0),
                requested_volume=0.0, sliding_distance=float(slip[force > 0].sum()),
                reduced=0, rejected=0,
            )  # fmt: skip
            continue
        p = contact_parameters(joint)
        result = archard_wear(
            profile,
            bearing_angle=np.asarray(sel["contact_angle"].values, dtype=np.float64),
            journal_angle=np.asarray(sel["contact_angle_journal"].values, dtype=np.float64),
            normal_force=force,
            slip=slip,
            coefficient=joint.wear.coefficient,
            effective_modulus=p.effective_modulus,
            form=p.form if p.form is not None else "sum-of-radii",  # type: ignore[arg-type]
            spread=joint.wear.spread_over_contact_width,
            max_increment=max_increment,
            radius_ratio_limit=joint.wear.radius_ratio_limit,
        )
        depth = np.stack(
            [
                result.profile.bearing_depth - profile.bearing_depth,
                result.profile.journal_depth - profile.journal_depth,
            ]
        )
        out[str(name)] = JointWear(
            joint=str(name),
            depth=depth,
            volume=(result.bearing_volume, result.journal_volume),
            requested_volume=result.requested_volume,
            sliding_distance=float(slip[force > 0].sum()),
            reduced=result.reduced,
            rejected=result.rejected,
        )
    return out


def _angle_coord(regions: int) -> tuple[str, np.ndarray, dict[str, str]]:
    centres = (np.arange(regions) + 0.5) * (2.0 * math.pi / regions)
    return ("angle", centres, {"units": "rad", "long_name": "region centre in the part's frame"})


def add_run_wear(ds: xr.Dataset, scene: Scene) -> xr.Dataset:
    """``ds`` with the wear accumulated over the whole run (``effects.wear`` on).

    Adds ``wear_depth(joint, surface, angle)`` (m), ``worn_volume(joint, surface)`` (m³)
    and ``sliding_distance(joint)`` (m). All clearance joints must have the same number of
    regions (one ``angle`` coordinate).
    """
    wear = run_wear(scene, ds)
    if not wear:
        return ds
    names = list(wear)
    sizes = {wear[n].depth.shape[1] for n in names}
    if len(sizes) != 1:
        raise ValueError(
            f"the clearance joints {names} have different wear.regions {sorted(sizes)}; "
            "use one region count for all joints of a scene with effects.wear on."
        )
    depth = np.stack([wear[n].depth for n in names])
    volume = np.array([wear[n].volume for n in names])
    ds = ds.assign_coords(
        surface=("surface", np.array(_SURFACES, dtype=object)),
        angle=_angle_coord(depth.shape[2]),
    )
    ds["wear_depth"] = _var(
        ("joint", "surface", "angle"), depth, "m", "wear depth accumulated during this run"
    )
    ds["worn_volume"] = _var(("joint", "surface"), volume, "m3", "volume worn off during this run")
    ds["sliding_distance"] = _var(
        ("joint",),
        [wear[n].sliding_distance for n in names],
        "m",
        "sliding distance in contact during this run",
    )
    return ds


# --------------------------------------------------------------------------- predict_wear


def _smooth(values: np.ndarray, width: int) -> np.ndarray:
    """Circular centred moving average (the profile's own smoothing; keeps Σ values)."""
    if width <= 1:
        return values.copy()
    out = np.empty_like(values)
    for i in range(values.size):
        out[i] = wk.smoothed_depth(values, i, width)
    return out


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

    For each update u = 0 … ``updates`` − 1 (paper-model §2.7, Flores 2009, Mukras 2010):

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
    from mechanism.core._simulate import simulate

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
    profiles = {n: WornProfile.from_joint(_clearance_joint(scene, n)) for n in names}
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
                w = p.smoothing_regions
                dh = np.stack([_smooth(wear[name].depth[0], w), _smooth(wear[name].depth[1], w)])
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
            p = profiles[name]
            volume[u, j, 0] = wk.worn_volume(depth[u, j, 0], p.bearing_radius, p.length, True)
            volume[u, j, 1] = wk.worn_volume(depth[u, j, 1], p.journal_radius, p.length, False)
    data: dict[str, Any] = {
        "wear_depth": _var(("update", "joint", "surface", "angle"), depth, "m", "wear depth"),
        "worn_volume": _var(("update", "joint", "surface"), volume, "m3", "worn volume"),
        "cycles": _var(("update",), cum, "1", "crank cycles of wear at this update state"),
        "block_cycles": _var(
            ("update",), block_hist, "1", "cycles extrapolated after this update state"
        ),
    }
    for name, (units, long_name) in METRICS.items():
        values = [float(m[name].values) for m in metrics_hist]
        data[name] = _var(("update",), values, units, long_name + " (last revolution)")
    coords: dict[str, Any] = {
        "update": ("update", np.arange(depth.shape[0]), {"long_name": "profile update"}),
        "joint": ("joint", np.array(names, dtype=object)),
        "surface": ("surface", np.array(_SURFACES, dtype=object)),
        "angle": _angle_coord(regions),
    }
    if all(ROD_STRAIN in m for m in metrics_hist):
        strain = xr.concat([m[ROD_STRAIN] for m in metrics_hist], dim="update")
        data[ROD_STRAIN] = _var(
            ("update", "rod"), strain.values, "1", strain.attrs.get("long_name", ROD_STRAIN)
        )
        coords["rod"] = ("rod", np.asarray(strain["rod"].values).astype(object))
    ds = xr.Dataset(data, coords=coords)
    ds.attrs["scene"] = scene_to_json(scene)
    ds.attrs["worn_scene"] = scene_to_json(worn_scene)
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


# --------------------------------------------------------------------------- compare


@dataclass(frozen=True, kw_only=True, eq=False)
class Comparison:
    """Response metrics before and after wear with their ratios (:func:`compare`).

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
                "before": _var(("metric",), t["before"].to_numpy(float), "", "value before"),
                "after": _var(("metric",), t["after"].to_numpy(float), "", "value after"),
                "ratio": _var(("metric",), t["ratio"].to_numpy(float), "1", "after / before"),
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


def compare(
    before: xr.Dataset, after: xr.Dataset, *, discard_revolutions: float = 1.0
) -> Comparison:
    """The paper's response metrics of two trajectories side by side, with ratios.

    Displacement error, speed error, peak contact force, maximum penetration, signed
    extreme driving torque and (when recorded) the signed extreme rod strains, each over
    the samples after ``discard_revolutions`` (paper-model §2.10; the same definitions as
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
    Comparison

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> a = xr.Dataset({"contact_force": ("time", [0.0, 1.0, 2.0, 1.0, 0.0])}, {"time": t})
    >>> b = a.assign(contact_force=2.0 * a.contact_force)
    >>> float(compare(a, b, discard_revolutions=0).table.loc["peak_contact_force", "ratio"])
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
    return Comparison(table=table, discard_revolutions=discard)
