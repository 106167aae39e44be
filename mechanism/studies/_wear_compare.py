"""``compare_wear``: the response metrics of two trajectories (before and after wear) side
by side with their ratios (docs/paper-model.md §7; the metric definitions are shared with
sweeps)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from chaoskit.contract import variable
from mechanism.core.record import METRICS, ROD_STRAIN, response_metrics, window_start

__all__ = ["WearComparison", "compare_wear"]


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
