"""The wear of one simulated run: Archard wear from the run's contact samples.

:func:`run_wear` integrates k Fₙ |v_t| over a window of a trajectory for every clearance
joint; :func:`add_run_wear` stores the wear of the whole run in the Dataset (``simulate``
calls it when ``effects.wear`` is on). Wear *prediction* over many cycles is a study:
:func:`mechanism.predict_wear`. See ``docs/wear.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from chaoskit.contract import variable
from mechanism.core.contact import contact_parameters
from mechanism.core.scene import ClearanceRevolute, Scene

from ._archard import archard_wear
from ._profile import WornProfile

__all__ = ["SURFACES", "JointWear", "add_run_wear", "clearance_joint", "run_wear", "surface_angle"]

SURFACES = ("bearing", "journal")


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


def clearance_joint(scene: Scene, name: str) -> ClearanceRevolute:
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
    form as K, docs/paper-model.md "Contact stiffness"), ΔV = k Fₙ Δs to the region
    containing the contact angle (spread
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
        joint = clearance_joint(scene, str(name))
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


def surface_angle(regions: int) -> tuple[str, np.ndarray, dict[str, str]]:
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
        surface=("surface", np.array(SURFACES, dtype=object)),
        angle=surface_angle(depth.shape[2]),
    )
    ds["wear_depth"] = variable(
        ("joint", "surface", "angle"), depth, "m", "wear depth accumulated during this run"
    )
    ds["worn_volume"] = variable(
        ("joint", "surface"), volume, "m3", "volume worn off during this run"
    )
    ds["sliding_distance"] = variable(
        ("joint",),
        [wear[n].sliding_distance for n in names],
        "m",
        "sliding distance in contact during this run",
    )
    return ds
