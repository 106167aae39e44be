"""The Dataset of :class:`mechanism.WearRecord`: what the wear of a run and a wear path's
analysis read, taken from the run's full samples (no ideal companion)."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import variable
from mechanism.core.integrate import Integration
from mechanism.core.model import Model
from mechanism.core.model import kernels as model_kernels

from ._record import crank_angle_variable, finish_dataset

__all__ = ["WEAR_VARIABLES", "wear_dataset"]

#: Per clearance joint: (name, column of the recording's clearance-joint block, units,
#: long_name), as the full record names them. ``penetration`` is max(δ, 0) of the
#: column ``CJ_DELTA``.
_JOINT_VARIABLES: tuple[tuple[str, int, str, str], ...] = (
    ("eccentricity_x", model_kernels.CJ_EX, "m", "journal centre minus bearing centre, x"),
    ("eccentricity_y", model_kernels.CJ_EY, "m", "journal centre minus bearing centre, y"),
    ("penetration", model_kernels.CJ_DELTA, "m", "penetration depth max(|e| - c, 0)"),
    ("contact_force", model_kernels.CJ_FN, "N", "normal contact force"),
    ("sliding_velocity", model_kernels.CJ_VT, "m s-1",
     "tangential velocity of the journal contact point"),
    ("contact_angle", model_kernels.CJ_PHI_B, "rad",
     "direction of the eccentricity in the bearing frame"),
    ("contact_angle_journal", model_kernels.CJ_PHI_J, "rad",
     "direction of the eccentricity in the journal frame"),
)  # fmt: skip

#: The per-joint variables of :class:`mechanism.WearRecord` (and ``crank_angle``).
WEAR_VARIABLES: tuple[str, ...] = tuple(v[0] for v in _JOINT_VARIABLES)


def wear_dataset(model: Model, run: Integration, *, attrs: dict[str, Any]) -> xr.Dataset:
    """``crank_angle`` and :data:`WEAR_VARIABLES` of a run recorded with full grid
    samples, with the units and names of the full record."""
    rec = run.recording
    data: dict[str, xr.Variable] = crank_angle_variable(model, rec)
    for name, column, units, long_name in _JOINT_VARIABLES:
        values = rec.cj[:, :, column]
        if name == "penetration":
            values = np.maximum(values, 0.0)
        data[name] = variable(("time", "joint"), values, units, long_name)
    coords: dict[str, Any] = {
        "time": ("time", rec.t.astype(np.float64), {"units": "s", "long_name": "time"}),
        "joint": ("joint", np.array(model.clearance_joints, dtype=object)),
    }
    return finish_dataset(xr.Dataset(data, coords=coords), model, run, attrs)
