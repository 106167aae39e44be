"""The result of a wear prediction: :class:`WearPrediction`, its Dataset and
:class:`WearPredictionError` (a prediction that stopped, with the updates that finished)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import __version__, stamp, variable
from mechanism.core import Scene, SimulationError
from mechanism.core.record import METRICS, ROD_STRAIN
from mechanism.core.wear import SURFACES, surface_angle

__all__ = ["WearPrediction", "WearPredictionError"]

#: ``status`` of a prediction whose every update finished, and of one that stopped
COMPLETE = "complete"
FAILED = "failed"


class WearPredictionError(SimulationError):
    """A wear prediction stopped before its last update.

    ``prediction`` is the :class:`WearPrediction` of the updates that finished, with
    ``status == "failed"`` and the reason in ``reason`` (the exception text). It is
    ``None`` only when the exception is built by hand.
    """

    def __init__(self, message: str, *, prediction: WearPrediction | None = None) -> None:
        super().__init__(message)
        self.prediction = prediction

    def __reduce__(self) -> tuple[Any, ...]:  # keeps ``prediction`` across processes
        return (_wear_prediction_error, (str(self), self.prediction))


def _wear_prediction_error(message: str, prediction: Any) -> WearPredictionError:
    return WearPredictionError(message, prediction=prediction)


@dataclass(frozen=True, kw_only=True, eq=False)
class WearPrediction:
    """Result of :func:`predict_wear`.

    Attributes
    ----------
    scene, worn_scene : Scene
        The starting scene and the scene carrying the profiles of the last finished update
        (``simulate`` runs it; ``save_scene``/``load_scene`` round-trip it).
    cycles : numpy.ndarray
        Cumulative crank cycles of wear at each finished update state 0, 1, ….
    reduced_updates : int
        Updates whose block of cycles was split into more than one sub-update.
    dataset : xarray.Dataset
        See :meth:`to_dataset`.
    status : str
        ``"complete"`` when every update finished, ``"failed"`` when the prediction stopped
        (then :func:`predict_wear` raised :class:`WearPredictionError` carrying this result).
    reason : str
        Why it stopped (one line), or a summary of the hard check when complete.
    """

    scene: Scene
    worn_scene: Scene
    cycles: np.ndarray
    reduced_updates: int
    dataset: xr.Dataset
    status: str = COMPLETE
    reason: str = ""

    @property
    def updates(self) -> int:
        """Finished updates (the requested number unless the prediction failed)."""
        return max(int(self.cycles.size - 1), 0)

    @property
    def success(self) -> bool:
        """True when every requested update finished and passed the hard check."""
        return self.status == COMPLETE

    def to_dataset(self) -> xr.Dataset:
        """The prediction as a Dataset.

        ``wear_depth(update, joint, surface, angle)`` (m), ``worn_volume(update, joint,
        surface)`` (m³), ``cycles(update)``, ``block_cycles(update)``,
        ``sub_updates(update)``, the response metrics of each update state
        (``peak_contact_force(update)``, … over its last revolution),
        ``penetration_fraction(update)`` (the hard check over the whole run), the sub-update
        records ``sub_update_cycles(sub_update)``, ``sub_update_of``,
        ``sub_update_depth_increment``, ``sub_update_penetration``,
        ``sub_update_peak_contact_force``, ``sub_update_relative_halfwidth``, the wear per
        cycle of each update state ``wear_rate(update, joint, surface, angle)`` (m) with
        its 95 % half-width ``wear_rate_halfwidth`` and ``wear_rate_relative_halfwidth(update)``
        (NaN with one averaged revolution), the worn scene as JSON in
        ``attrs["worn_scene"]``, ``attrs["status"]`` (``"complete"``/``"failed"``),
        ``attrs["status_reason"]`` and the settings in attrs.
        """
        return self.dataset.copy()


def prediction_dataset(loop: Any, cum: np.ndarray, *, settings: dict[str, Any]) -> xr.Dataset:
    """The Dataset of a finished update loop (``_wear_prediction.UpdateLoop``: its joints,
    states, sub-updates, profiles and scenes) at the cumulative cycles ``cum``."""
    names, states, subs = loop.names, loop.states, loop.subs
    regions = loop.profiles[names[0]].regions
    depth = (
        np.stack([s["depth"] for s in states]) if states else np.zeros((0, len(names), 2, regions))
    )
    volume = np.zeros(depth.shape[:3])
    rate = (
        np.stack([[s["rates"].increments[n] for n in names] for s in states]) if states else depth
    )
    halfwidth = (
        np.stack([[s["rates"].halfwidth[n] for n in names] for s in states]) if states else depth
    )
    for u in range(depth.shape[0]):
        for j, name in enumerate(names):
            state = loop.profiles[name].with_depth(
                bearing_depth=depth[u, j, 0], journal_depth=depth[u, j, 1]
            )
            volume[u, j] = (state.bearing_volume, state.journal_volume)
    # the cycles actually worn after each state (0 after the last; short when it failed)
    block = [sum(s["cycles"] for s in subs if s["update"] == u) for u in range(len(states))]
    data: dict[str, Any] = {
        "wear_depth": variable(("update", "joint", "surface", "angle"), depth, "m", "wear depth"),
        "worn_volume": variable(("update", "joint", "surface"), volume, "m3", "worn volume"),
        "cycles": variable(("update",), cum, "1", "crank cycles of wear at this update state"),
        "block_cycles": variable(
            ("update",), block, "1", "cycles extrapolated after this update state"
        ),
        "sub_updates": variable(
            ("update",), [s["sub_updates"] for s in states], "1",
            "sub-updates the block after this update state was worn in",
        ),
        "penetration_fraction": variable(
            ("update",), [s["check"].fraction for s in states], "1",
            "largest penetration over the whole run of this state / radial clearance",
        ),
        "sub_update_of": variable(
            ("sub_update",), [s["update"] for s in subs], "1",
            "update (0 = the first) this sub-update belongs to",
        ),
        "sub_update_cycles": variable(
            ("sub_update",), [s["cycles"] for s in subs], "1",
            "crank cycles extrapolated in this sub-update",
        ),
        "sub_update_depth_increment": variable(
            ("sub_update",), [s["depth_increment"] for s in subs], "1",
            "largest depth added by this sub-update / radial clearance",
        ),
        "sub_update_penetration": variable(
            ("sub_update",), [s["penetration"] for s in subs], "1",
            "largest penetration over the run of the state after this sub-update / radial "
            "clearance (NaN: its simulation failed)",
        ),
        "sub_update_peak_contact_force": variable(
            ("sub_update",), [s["force"] for s in subs], "N",
            "peak contact force over the run of the state after this sub-update",
        ),
        "sub_update_relative_halfwidth": variable(
            ("sub_update",), [s["relative_halfwidth"] for s in subs], "1",
            "largest 95 % half-width / mean of the wear per cycle this sub-update "
            "extrapolated, over the worn regions (NaN: one revolution averaged)",
        ),
        "wear_rate": variable(
            ("update", "joint", "surface", "angle"), rate, "m",
            "smoothed wear depth per crank cycle at this update state (mean over the "
            "averaged revolutions)",
        ),
        "wear_rate_halfwidth": variable(
            ("update", "joint", "surface", "angle"), halfwidth, "m",
            "95 % half-width of wear_rate from batch means over revolutions (NaN: one "
            "revolution averaged)",
        ),
        "wear_rate_relative_halfwidth": variable(
            ("update",), [s["relative_halfwidth"] for s in states], "1",
            "largest 95 % half-width / mean of the wear per cycle over the worn regions, "
            "of every increment worn from this update state on (NaN: one revolution averaged)",
        ),
    }  # fmt: skip
    metrics_hist = [s["traj_metrics"] for s in states]
    for name, (units, long_name) in METRICS.items():
        values = [float(m[name].values) for m in metrics_hist]
        data[name] = variable(("update",), values, units, long_name + " (last revolution)")
    coords: dict[str, Any] = {
        "update": ("update", np.arange(depth.shape[0]), {"long_name": "profile update"}),
        "sub_update": ("sub_update", np.arange(len(subs)), {"long_name": "sub-update"}),
        "joint": ("joint", np.array(names, dtype=object)),
        "surface": ("surface", np.array(SURFACES, dtype=object)),
        "angle": surface_angle(regions),
    }
    if metrics_hist and all(ROD_STRAIN in m for m in metrics_hist):
        strain = xr.concat([m[ROD_STRAIN] for m in metrics_hist], dim="update")
        data[ROD_STRAIN] = variable(
            ("update", "rod"), strain.values, "1", strain.attrs.get("long_name", ROD_STRAIN)
        )
        coords["rod"] = ("rod", np.asarray(strain["rod"].values).astype(object))
    ds = xr.Dataset(data, coords=coords)
    scene = loop.scene
    ds.attrs["scene"] = scene.to_json()
    ds.attrs["worn_scene"] = loop.kept.to_json()
    ds.attrs["scene_name"] = scene.name
    for key, value in settings.items():
        ds.attrs[key] = value
    failed = settings["status"] == FAILED
    title = f"wear prediction of scene {scene.name!r}"
    if failed:
        title += f" (FAILED after {max(len(states) - 1, 0)} of {settings['updates']} updates)"
    return stamp(
        ds,
        title=title,
        source=f"mechanism (chaoskit {__version__})",
        history=(
            f"mechanism.predict_wear({scene.name!r}, updates={settings['updates']}, "
            f"cycles_per_update={settings['cycles_per_update']}, "
            f"max_depth_increment={settings['max_depth_increment']})"
        ),
    )
