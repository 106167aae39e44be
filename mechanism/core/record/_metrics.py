"""Response metrics of a trajectory (docs/paper-model.md §7), shared by sweeps and
``compare_wear``.

One definition of each metric: ``sweep`` stores them per grid point, ``compare_wear`` and
``predict_wear`` put them side by side before and after wear.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

__all__ = ["METRICS", "ROD_STRAIN", "friction_sign_flips", "response_metrics", "window_start"]

_TWO_PI = 2.0 * math.pi

# Response metrics: name -> (units, long_name). Evaluated over the window after the discard.
METRICS: dict[str, tuple[str, str]] = {
    "peak_contact_force": ("N", "peak normal contact force (all clearance joints)"),
    "max_penetration": ("m", "maximum penetration depth (all clearance joints)"),
    "max_displacement_error": ("m", "maximum |slider position - ideal slider position|"),
    "max_speed_error": ("m s-1", "maximum |slider velocity - ideal slider velocity|"),
    "driving_torque_extreme": ("N m", "signed extreme of the driving torque"),
}
METRIC_SOURCES: dict[str, tuple[str, str]] = {
    "peak_contact_force": ("contact_force", "max"),
    "max_penetration": ("penetration", "max"),
    "max_displacement_error": ("displacement_error", "absmax"),
    "max_speed_error": ("speed_error", "absmax"),
    "driving_torque_extreme": ("driving_torque", "extreme"),
}
ROD_STRAIN = "rod_strain_extreme"


def window_start(traj: xr.Dataset, discard_revolutions: float) -> int:
    """First sample after ``discard_revolutions`` crank turns (from ``crank_angle``)."""
    if discard_revolutions == 0:
        return 0
    if "crank_angle" not in traj:
        raise ValueError("the trajectory has no 'crank_angle'; cannot discard revolutions.")
    angle = np.asarray(traj["crank_angle"].values, dtype=np.float64)
    turned = np.abs(angle - angle[0])
    past = np.flatnonzero(turned >= _TWO_PI * discard_revolutions * (1.0 - 1e-12))
    if past.size == 0 or past[0] >= angle.size - 1:
        raise ValueError(
            f"the trajectory covers {turned.max() / _TWO_PI:.3g} revolutions, not more than "
            f"discard_revolutions={discard_revolutions}; simulate longer or discard less."
        )
    return int(past[0])


def reduce_values(values: np.ndarray, how: str) -> float:
    """``"max"``, ``"absmax"`` or the signed extreme (``"extreme"``); NaN when empty."""
    if values.size == 0:
        return math.nan
    if how == "max":
        return float(np.max(values))
    if how == "absmax":
        return float(np.max(np.abs(values)))
    return float(values.flat[int(np.argmax(np.abs(values)))])  # signed extreme


def response_metrics(traj: xr.Dataset, start: int = 0) -> dict[str, xr.DataArray]:
    """docs/paper-model.md §7 output definitions over ``time[start:]``; NaN where not simulated.

    Peak contact force and maximum penetration over all clearance joints, maximum
    displacement and speed error of the slider, signed extreme of the driving torque, and
    (when the trajectory has a ``*strain*`` variable over ``rod``) the signed extreme
    strain per rod.
    """
    window = traj.isel(time=slice(start, None))
    out: dict[str, xr.DataArray] = {}
    for name, (source, how) in METRIC_SOURCES.items():
        units, long_name = METRICS[name]
        value = math.nan
        if source in window:
            value = reduce_values(np.asarray(window[source].values, dtype=np.float64), how)
        out[name] = xr.DataArray(value, attrs={"units": units, "long_name": long_name})
    strains = [
        k
        for k, v in window.data_vars.items()
        if "strain" in str(k) and "rod" in v.dims and "time" in v.dims
    ]
    if strains:
        var = window[strains[0]].transpose("rod", ...)
        flat = np.asarray(var.values, dtype=np.float64).reshape(var.sizes["rod"], -1)
        extremes = np.array([reduce_values(row, "extreme") for row in flat])
        out[ROD_STRAIN] = xr.DataArray(
            extremes,
            dims=("rod",),
            coords={"rod": np.asarray(var["rod"].values).astype(str)},
            attrs={
                "units": "1",
                "long_name": f"signed extreme of {strains[0]} per rod (positive = tension)",
            },
        )
    return out


def friction_sign_flips(traj: xr.Dataset) -> tuple[int, int]:
    """Friction chatter of a trajectory: (number of sign changes of ``friction_force``
    between consecutive samples, longest run of consecutive changes), ignoring forces
    below 5 % of the peak. With the fixed-step generalized-α (a sample per step) a long
    run is the period-2 alternation of an unresolved stiff friction ramp (docs/ancf.md §8).
    """
    fr = np.asarray(traj["friction_force"].values, dtype=float).ravel()
    sign = np.sign(fr) * (np.abs(fr) > 0.05 * np.abs(fr).max())
    flips = sign[1:] * sign[:-1] < 0
    longest = run = 0
    for flip in flips:
        run = run + 1 if flip else 0
        longest = max(longest, run)
    return int(flips.sum()), longest
