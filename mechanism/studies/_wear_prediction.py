"""Wear prediction: ``predict_wear`` (cycle extrapolation) and ``compare_wear`` (before/after).

The wear of one run (:func:`mechanism.core.wear.run_wear`) is part of the core; this study
builds on it:

* :func:`predict_wear` — the update loop of docs/paper-model.md §6 (Flores 2009; Mukras 2010):
  settle, accumulate one cycle's wear, extrapolate it over a block of cycles worn in
  sub-updates that each deepen the profile by at most a fraction of the clearance, smooth,
  update the profile, re-simulate, repeat; every simulated state must keep its
  penetration within the clearance, or the prediction stops (:class:`WearPredictionError`).
* :func:`compare_wear` — the response metrics of docs/paper-model.md §7 before and after
  wear, side by side with their ratios (metric definitions shared with sweeps,
  ``_metrics.py``).

See ``docs/wear.md``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from scipy.stats import t as student_t

from chaoskit.contract import __version__, check_int, check_positive, stamp, variable
from mechanism.core import Scene, SimulationError, simulate
from mechanism.core.record import METRICS, ROD_STRAIN, response_metrics, window_start
from mechanism.core.scene import ClearanceRevolute
from mechanism.core.wear import SURFACES, WornProfile, clearance_joint, run_wear, surface_angle

__all__ = [
    "DEFAULT_AVERAGED_REVOLUTIONS",
    "DEFAULT_MAX_DEPTH_INCREMENT",
    "MAX_AVERAGED_REVOLUTIONS",
    "MAX_SUB_UPDATES",
    "PENETRATION_LIMIT",
    "WearComparison",
    "WearPrediction",
    "WearPredictionError",
    "compare_wear",
    "predict_wear",
]

# --------------------------------------------------------------------------- predict_wear

#: Default of ``max_depth_increment``: the largest depth one sub-update may add, as a
#: fraction of the radial clearance (docs/wear.md, "Sub-updates").
DEFAULT_MAX_DEPTH_INCREMENT = 0.025
#: The hard check: a simulated state whose penetration exceeds this fraction of the joint's
#: radial clearance stops the prediction (the compliant contact law describes a small overlap).
PENETRATION_LIMIT = 1.0
#: Most sub-updates one update may be split into before the prediction stops.
MAX_SUB_UPDATES = 100
#: Default of ``averaged_revolutions`` in :func:`predict_wear`: one revolution, the
#: published update scheme (Flores 2009), so its results are unchanged; where the motion is
#: irregular use more (:func:`mechanism.wear_life` defaults to more; docs/wear.md).
DEFAULT_AVERAGED_REVOLUTIONS = 1
#: Largest accepted ``averaged_revolutions``.
MAX_AVERAGED_REVOLUTIONS = 1000
#: Most batches of consecutive revolutions behind the 95 % interval of the wear per cycle.
MAX_BATCHES = 10
#: Regions whose mean wear per cycle is at least this fraction of their surface's largest
#: enter the largest *relative* half-width (elsewhere the relative width of a vanishing
#: rate says nothing about the profile).
RELATIVE_HALFWIDTH_FLOOR = 0.1

_COMPLETE = "complete"
_FAILED = "failed"


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
    status: str = _COMPLETE
    reason: str = ""

    @property
    def updates(self) -> int:
        """Finished updates (the requested number unless the prediction failed)."""
        return max(int(self.cycles.size - 1), 0)

    @property
    def success(self) -> bool:
        """True when every requested update finished and passed the hard check."""
        return self.status == _COMPLETE

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


@dataclass(frozen=True)
class _Check:
    """The hard check of one simulated state (over the whole run, every clearance joint)."""

    fraction: float  # largest penetration / radial clearance
    joint: str  # where it is largest (or where a force is not finite)
    depth: float  # that penetration (m)
    clearance: float  # that joint's radial clearance (m)
    force: float  # peak contact force (N)
    finite: bool  # contact forces and penetrations finite

    @property
    def passed(self) -> bool:
        return self.finite and self.fraction <= PENETRATION_LIMIT


def _check_state(traj: xr.Dataset, scene: Scene) -> _Check:
    worst = _Check(0.0, "", 0.0, math.nan, 0.0, True)
    if "joint" not in traj.dims:
        return worst
    force_max = 0.0
    for name in np.asarray(traj["joint"].values).astype(str):
        sel = traj.sel(joint=name)
        force = np.asarray(sel["contact_force"].values, dtype=np.float64)
        depth = np.asarray(sel["penetration"].values, dtype=np.float64)
        clearance = float(clearance_joint(scene, name).clearance)
        if not (np.isfinite(force).all() and np.isfinite(depth).all()):
            return _Check(math.inf, name, math.nan, clearance, math.nan, False)
        force_max = max(force_max, float(force.max(initial=0.0)))
        deepest = float(depth.max(initial=0.0))
        if deepest / clearance > worst.fraction or not worst.joint:
            worst = _Check(deepest / clearance, name, deepest, clearance, 0.0, True)
    return dataclasses.replace(worst, force=force_max)


def predict_wear(
    scene: Scene,
    *,
    updates: int,
    cycles_per_update: float,
    max_depth_increment: float = DEFAULT_MAX_DEPTH_INCREMENT,
    settle_revolutions: float = 2.0,
    averaged_revolutions: int = DEFAULT_AVERAGED_REVOLUTIONS,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    progress: bool = False,
) -> WearPrediction:
    """Predict the worn profile of every clearance joint by cycle extrapolation.

    For each update u = 0 … ``updates`` − 1 (docs/paper-model.md §6, Flores 2009, Mukras 2010)
    the block of ΔN = ``cycles_per_update`` cycles is worn in sub-updates:

    1. simulate ``settle_revolutions`` + n crank revolutions (n = ``averaged_revolutions``)
       with the current profiles (the worn geometry shapes the contact) and take the
       response metrics of the last n revolutions and the Archard wear per cycle h_cyc,
       the mean of the n revolutions' wear (``run_wear`` on each), with its 95 %
       interval per region from batch means over consecutive revolutions;
    2. the sub-update takes the cycles left of the block, split into the fewest equal
       parts for which no region deepens by more than ``max_depth_increment`` × clearance;
    3. h ← h + ΔN_sub · smooth(h_cyc) with the joint's ``smoothing_regions`` moving average;
    4. rebuild the joint's local clearance, curvature and stiffness from h, and repeat from
       1 on the worn state until the block is used up.

    Every simulated state passes a hard check: its largest penetration over the whole run
    must not exceed the joint's radial clearance, and its contact forces must be finite.
    Otherwise — or when the simulation fails, or an update would need more than
    ``MAX_SUB_UPDATES`` sub-updates — the prediction stops and raises
    :class:`WearPredictionError`, whose ``prediction`` holds the updates that finished
    (``status == "failed"``, the reason also in the dataset's attrs). A returned
    prediction therefore always has ``status == "complete"``.

    Parameters
    ----------
    scene : Scene
        The mechanism; every clearance joint wears (``effects.wear`` is switched on).
    updates : int
        Number of profile updates (≥ 1; the paper-era practice is 2–10).
    cycles_per_update : float
        Crank cycles ΔN extrapolated per update (> 0); all of them are worn.
    max_depth_increment : float
        Largest depth one sub-update may add, as a fraction of the joint's radial
        clearance, in (0, 1]; larger blocks are split into sub-updates.
    settle_revolutions : float
        Revolutions simulated before the cycles that are measured (≥ 0).
    averaged_revolutions : int
        Revolutions n whose mean wear is the wear per cycle, in [1, 1000]. With n = 1 (the
        default, the published scheme) one revolution's wear is extrapolated and has no
        interval; where the motion is irregular one revolution is not the wear rate, and
        n ≥ 4 gives the interval (docs/wear.md, "Averaged wear").
    method, rtol, atol, output_step
        Passed to :func:`mechanism.simulate`.
    progress : bool
        Show a progress bar over the updates.

    Returns
    -------
    WearPrediction
        With ``status == "complete"``; ``to_dataset()`` records the cycles of every
        sub-update and the wear per cycle with its interval.

    Raises
    ------
    WearPredictionError
        When a state fails the hard check or its simulation fails (a
        :class:`mechanism.SimulationError`; ``exc.prediction`` keeps the finished updates).
    ValueError
        For bad settings (the parameter and its accepted range are named).

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
    updates, block, limit, settle = _checked_settings(
        updates, cycles_per_update, max_depth_increment, settle_revolutions
    )
    averaged = check_averaged_revolutions(averaged_revolutions)
    loop = update_loop(
        scene, targets=[(u + 1) * block for u in range(updates)], limit=limit,
        settle=settle, averaged=averaged,
        simulate_kwargs={"method": method, "rtol": rtol, "atol": atol, "output_step": output_step},
        caller="predict_wear",
    )  # fmt: skip
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=updates + 1, desc=f"predict_wear {scene.name}", unit="update")
    try:
        loop.run(updates, bar)
    finally:
        if bar is not None:
            bar.close()
    settings = {
        "updates": updates,
        "cycles_per_update": block,
        "max_depth_increment": limit,
        "settle_revolutions": settle,
        "averaged_revolutions": averaged,
        "penetration_limit": PENETRATION_LIMIT,
        "max_sub_updates": MAX_SUB_UPDATES,
    }
    prediction = loop.prediction(settings)
    if not prediction.success:
        raise WearPredictionError(prediction.reason, prediction=prediction)
    return prediction


def _checked_settings(
    updates: Any, cycles_per_update: Any, max_depth_increment: Any, settle_revolutions: Any
) -> tuple[int, float, float, float]:
    """The settings of :func:`predict_wear`, or a ValueError naming the one out of range."""
    n = check_int(updates, name="updates", minimum=1)
    block = check_positive(cycles_per_update, name="cycles_per_update")
    limit = check_depth_increment(max_depth_increment)
    settle = float(settle_revolutions)
    if not (math.isfinite(settle) and settle >= 0.0):
        raise ValueError(f"settle_revolutions must be >= 0; got {settle_revolutions!r}.")
    return n, block, limit, settle


def check_depth_increment(value: Any) -> float:
    """``max_depth_increment`` as a float in (0, 1], or a ValueError naming its range."""
    try:
        limit = float(value)
    except (TypeError, ValueError):
        limit = math.nan
    if not 0.0 < limit <= 1.0:  # NaN fails too
        raise ValueError(
            "max_depth_increment must be in (0, 1] (a fraction of the radial clearance); "
            f"got {value!r}."
        )
    return limit


def check_averaged_revolutions(value: Any) -> int:
    """``averaged_revolutions`` as an int, or a ValueError naming its range."""
    return check_int(
        value, name="averaged_revolutions", minimum=1, maximum=MAX_AVERAGED_REVOLUTIONS
    )


def update_loop(
    scene: Scene,
    *,
    targets: list[float],
    limit: float,
    settle: float,
    averaged: int,
    simulate_kwargs: dict[str, Any],
    caller: str,
) -> _UpdateLoop:
    """The update loop of ``scene`` (wear switched on) before it runs; shared with
    :func:`mechanism.wear_life`. ``targets`` are the cumulative cycles at the end of
    each update (increasing). A ValueError when the scene has no clearance joint to
    wear (``caller`` names the function in the message)."""
    scene = scene.replace({"effects.wear": True})
    names = [n for n, j in scene.joints.items() if isinstance(j, ClearanceRevolute)]
    if not names or not scene.effects.clearance:
        raise ValueError(
            f"{caller} needs a scene with an active clearance joint (a clearance_revolute "
            "joint and effects.clearance = true)."
        )
    profiles = {n: WornProfile.from_joint(clearance_joint(scene, n)) for n in names}
    if len({p.regions for p in profiles.values()}) != 1:
        raise ValueError("all clearance joints must have the same wear.regions.")
    return _UpdateLoop(
        scene, names, profiles, targets=targets, limit=limit, settle=settle,
        averaged=averaged, simulate_kwargs=simulate_kwargs,
    )  # fmt: skip


@dataclass(frozen=True)
class _Rates:
    """The wear per cycle of one simulated state, from ``averaged`` revolutions."""

    increments: dict[str, np.ndarray]  # (2, regions) smoothed mean depth per cycle (m)
    halfwidth: dict[str, np.ndarray]  # (2, regions) its 95 % half-width (m; NaN for n = 1)
    rate: float  # largest mean increment / clearance
    room: float  # cycles a journal may wear before losing half of what is left
    relative_halfwidth: float  # largest half-width / mean over the worn regions


def batch_halfwidth(samples: np.ndarray, batches: int = MAX_BATCHES) -> np.ndarray:
    """95 % half-width of the mean of ``samples`` along axis 0, from batch means.

    The samples (one per revolution) are split into at most ``batches`` groups of
    consecutive samples; t(0.975, B − 1) s_B / √B with s_B the standard deviation of the
    B group means. NaN for fewer than two samples.
    """
    n = samples.shape[0]
    b = min(n, batches)
    if b < 2:
        return np.full(samples.shape[1:], math.nan)
    means = np.stack([g.mean(axis=0) for g in np.array_split(samples, b, axis=0)])
    return float(student_t.ppf(0.975, b - 1)) * means.std(axis=0, ddof=1) / math.sqrt(b)


def _relative_halfwidth(mean: np.ndarray, halfwidth: np.ndarray) -> float:
    """Largest half-width / mean over the regions whose mean is at least
    :data:`RELATIVE_HALFWIDTH_FLOOR` of their surface's largest (NaN when nothing wears)."""
    worst = math.nan
    for m, h in zip(mean, halfwidth, strict=True):
        top = float(m.max())
        if top <= 0.0 or not np.isfinite(h).all():
            continue
        worn = m >= RELATIVE_HALFWIDTH_FLOOR * top
        value = float((h[worn] / m[worn]).max())
        worst = value if math.isnan(worst) else max(worst, value)
    return worst


def _nanmax(a: float, b: float) -> float:
    """The larger of two values, ignoring NaN (NaN only when both are)."""
    if math.isnan(a):
        return b
    return a if math.isnan(b) else max(a, b)


def revolution_bounds(traj: xr.Dataset, settle: float, revolutions: int) -> list[int]:
    """Sample indices that start the ``revolutions`` revolutions after ``settle`` and end
    the last one (its last sample)."""
    bounds = [window_start(traj, settle + k) for k in range(revolutions)]
    return [*bounds, int(traj.sizes["time"]) - 1]


class _UpdateLoop:
    """The state of :func:`predict_wear`: profiles, the scene carrying them, the records."""

    def __init__(
        self,
        scene: Scene,
        names: list[str],
        profiles: dict[str, WornProfile],
        *,
        targets: list[float],
        limit: float,
        settle: float,
        averaged: int,
        simulate_kwargs: dict[str, Any],
    ) -> None:
        self.scene, self.names, self.profiles = scene, names, profiles
        self.targets, self.limit, self.settle, self.averaged = targets, limit, settle, averaged
        self.block = targets[0] if targets else 0.0  # the block being worn
        self.kwargs = simulate_kwargs
        self.current = scene  # carries self.profiles
        self.kept = scene  # the scene of the last finished update state
        self.updates = 0
        self.states: list[dict[str, Any]] = []  # one per finished update state
        self.subs: list[dict[str, float]] = []  # one per sub-update
        self.reduced = 0
        self.failure = ""
        self.last_check: _Check | None = None  # of the last simulated state, passed or not
        self.on_state: Callable[[Scene, int, float], bool] | None = None
        self.bar: Any = None

    # -- one simulated state
    def _simulate(self, label: str) -> tuple[xr.Dataset, int, _Check] | None:
        self.last_check = None
        try:
            traj = simulate(self.current, revolutions=self.settle + self.averaged, **self.kwargs)
        except SimulationError as exc:
            self.failure = f"the simulation of {label} failed: {exc}"
            return None
        check = self.last_check = _check_state(traj, self.current)
        if not check.passed:
            self.failure = self._check_message(check, label)
            return None
        return traj, window_start(traj, self.settle), check

    def _check_message(self, check: _Check, label: str) -> str:
        if not check.finite:
            what = f"joint {check.joint}: a contact force or penetration is not finite"
        else:
            what = (
                f"joint {check.joint}: the penetration reached {100.0 * check.fraction:.0f} % "
                f"of the radial clearance ({check.depth * 1e3:.3g} mm of "
                f"{check.clearance * 1e3:.3g} mm)"
            )
        if not self.states:
            return f"{what} in {label}; check the speed, clearance and contact stiffness."
        return (
            f"{what} in {label}, so the wear prediction stopped there; lower "
            f"max_depth_increment (--max-depth-increment, now {self.limit:g}) or predict "
            "fewer cycles."
        )

    def _label(self, cycles: float, update: int, total: int, sub: int) -> str:
        if update == 0 and sub == 0:
            return "the unworn state"
        where = f"update {update} of {total}" + (f", sub-update {sub}" if sub else "")
        return f"the state after {cycles:.6g} cycles ({where})"

    # -- the update loop
    def run(self, updates: int, bar: Any) -> None:
        """Run ``updates`` blocks (up to ``self.targets[updates - 1]``); on return ``self.states``
        holds every finished update state and ``self.failure`` why it stopped, if it did."""
        self.updates, self.bar = updates, bar
        state = self._simulate(self._label(0.0, 0, updates, 0))
        cycles = 0.0
        for u in range(updates + 1):
            if state is None:
                return
            traj, start, check = state
            rates = self._rates(traj, start, label=self._label(cycles, u, updates, 0))
            if rates is None:
                return
            self.states.append(
                {"traj_metrics": response_metrics(traj, start), "check": check, "cycles": cycles,
                 "depth": self._depth(), "sub_updates": 0, "rates": rates,
                 "relative_halfwidth": rates.relative_halfwidth}
            )  # fmt: skip
            # a hook (wear_life analyses the state here); False ends the loop
            if self.on_state is not None and not self.on_state(self.current, u, cycles):
                return
            self.kept = self.current
            if bar is not None:
                bar.update(1)
            if u == updates:
                return
            self.block = self.targets[u] - cycles
            state = self._wear_block(state, rates, u, updates, cycles)
            cycles = self.targets[u]

    def _wear_block(
        self,
        state: tuple[xr.Dataset, int, _Check],
        rates: _Rates | None,
        u: int,
        updates: int,
        start_cycles: float,
    ) -> tuple[xr.Dataset, int, _Check] | None:
        """Wear the block of update ``u`` in sub-updates; the state at its end, or None.
        ``rates`` are those of ``state``."""
        done, sub = 0.0, 0
        while True:
            traj, start, _ = state
            if rates is None:
                here = self._label(start_cycles + done, u + (sub > 0), updates, sub)
                rates = self._rates(traj, start, label=here)
                if rates is None:
                    return None
            rate, room = rates.rate, rates.room
            remaining = self.block - done
            if sub == MAX_SUB_UPDATES:
                self.failure = (
                    f"update {u + 1} of {updates} has used {MAX_SUB_UPDATES} sub-updates and "
                    f"{remaining:.6g} of its {self.block:.6g} cycles are left (one cycle now "
                    f"deepens the profile by {100.0 * rate:.3g} % of the radial clearance); "
                    "predict fewer cycles per update or raise max_depth_increment "
                    f"(--max-depth-increment, now {self.limit:g})."
                )
                return None
            allowed = min(self.limit / rate if rate > 0.0 else math.inf, room)
            # the fewest equal parts within the limit (1e-12: no split for rounding alone)
            parts = max(1, math.ceil(remaining / allowed * (1.0 - 1e-12)))
            cycles = remaining if parts == 1 else remaining / parts
            self._apply(rates.increments, cycles)
            sub += 1
            done = self.block if parts == 1 else done + cycles
            self.states[-1]["sub_updates"] = sub
            if self.bar is not None:
                self.bar.set_postfix_str(f"sub-update {sub}", refresh=True)
            label = self._label(start_cycles + done, u + 1, updates, 0 if parts == 1 else sub)
            state = self._simulate(label)
            last = self.last_check
            self.subs.append(
                {"update": u, "cycles": cycles, "depth_increment": cycles * rate,
                 "penetration": last.fraction if last else math.nan,
                 "force": last.force if last else math.nan,
                 "relative_halfwidth": rates.relative_halfwidth}
            )  # fmt: skip
            self.states[-1]["relative_halfwidth"] = _nanmax(
                self.states[-1]["relative_halfwidth"], rates.relative_halfwidth
            )
            rates = None
            if state is None or parts == 1:
                if sub > 1:
                    self.reduced += 1
                return state

    def _rates(self, traj: xr.Dataset, start: int, *, label: str) -> _Rates | None:
        """The wear per cycle of the state ``traj`` (mean of the revolutions after
        ``start``) by joint, smoothed like the profile, with its interval; None (and
        ``self.failure`` set) when it is not finite."""
        bounds = revolution_bounds(traj, self.settle, self.averaged)
        per_rev: dict[str, list[np.ndarray]] = {n: [] for n in self.names}
        for k in range(self.averaged):
            # each revolution's window ends on the sample that starts the next, so the
            # trapezoid weights of the windows add up to those of the whole window
            window = traj.isel(time=slice(0, bounds[k + 1] + 1))
            wear = run_wear(self.current, window, start=bounds[k])
            for name in self.names:
                p = self.profiles[name]
                step = p.with_depth(
                    bearing_depth=wear[name].depth[0], journal_depth=wear[name].depth[1]
                )
                dh = np.stack(
                    [step.smoothed_depth(surface="bearing"), step.smoothed_depth(surface="journal")]
                )
                if p.surfaces == "bearing":
                    dh[1] = 0.0
                if not np.all(np.isfinite(dh)):
                    self.failure = f"joint {name}: the wear of {label} is not finite."
                    return None
                per_rev[name].append(dh)
        increments, halfwidth = {}, {}
        rate, room, relative = 0.0, math.inf, math.nan
        for name in self.names:
            p = self.profiles[name]
            samples = np.stack(per_rev[name])
            dh = increments[name] = samples[0] if self.averaged == 1 else samples.mean(axis=0)
            halfwidth[name] = batch_halfwidth(samples)
            relative = _nanmax(relative, _relative_halfwidth(dh, halfwidth[name]))
            rate = max(rate, float(dh.max()) / p.clearance)
            jpeak = float(dh[1].max())
            if jpeak > 0.0:
                room = min(room, 0.5 * (p.journal_radius - float(p.journal_depth.max())) / jpeak)
        return _Rates(increments, halfwidth, rate, room, relative)

    def _apply(self, increments: dict[str, np.ndarray], cycles: float) -> None:
        self.profiles = {
            n: p.with_depth(
                bearing_depth=p.bearing_depth + cycles * increments[n][0],
                journal_depth=p.journal_depth + cycles * increments[n][1],
            )
            for n, p in self.profiles.items()
        }
        self.current = _with_profiles(self.current, self.profiles)

    def _depth(self) -> np.ndarray:
        return np.stack([[p.bearing_depth, p.journal_depth] for p in self.profiles.values()])

    # -- the result
    def prediction(self, settings: dict[str, Any]) -> WearPrediction:
        status = _FAILED if self.failure else _COMPLETE
        if self.failure:
            reason = self.failure
        else:
            worst = max(s["check"].fraction for s in self.states)
            reason = (
                f"all {self.updates} updates finished; the largest penetration of any state "
                f"is {100.0 * worst:.0f} % of the radial clearance"
            )
        cum = np.array([s["cycles"] for s in self.states], dtype=np.float64)
        settings = {**settings, "status": status, "status_reason": reason}
        ds = _prediction_dataset(self, cum, settings=settings)
        return WearPrediction(
            scene=self.scene, worn_scene=self.kept, cycles=cum, reduced_updates=self.reduced,
            dataset=ds, status=status, reason=reason,
        )  # fmt: skip


def _prediction_dataset(
    loop: _UpdateLoop, cum: np.ndarray, *, settings: dict[str, Any]
) -> xr.Dataset:
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
    failed = settings["status"] == _FAILED
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
