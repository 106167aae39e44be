"""Wear prediction: ``predict_wear``, the cycle extrapolation of docs/paper-model.md §6.

The wear of one run (:func:`mechanism.core.wear.run_wear`) is part of the core; this study
builds on it (Flores 2009; Mukras 2010): settle, accumulate one cycle's wear, extrapolate it
over a block of cycles worn in sub-updates that each deepen the profile by at most a fraction
of the clearance, smooth, update the profile, re-simulate, repeat; every simulated state must
keep its penetration within the clearance, or the prediction stops
(:class:`WearPredictionError`).

This module holds the update loop (shared with :func:`mechanism.wear_life`); its settings
are in ``_wear_settings``, the statistics of the averaged wear in ``_wear_statistics``, the
result and its Dataset in ``_wear_result``, and ``compare_wear`` in ``_wear_compare``.

See ``docs/wear.md``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from mechanism.core import Scene, SimulationError, drive_period
from mechanism.core.record import response_metrics, window_start
from mechanism.core.scene import ClearanceRevolute
from mechanism.core.wear import WornProfile, clearance_joint, run_wear

from ._turns import simulate_turns
from ._wear_result import COMPLETE, FAILED, WearPrediction, WearPredictionError, prediction_dataset
from ._wear_settings import (
    DEFAULT_AVERAGED_REVOLUTIONS,
    DEFAULT_MAX_DEPTH_INCREMENT,
    MAX_SUB_UPDATES,
    PENETRATION_LIMIT,
    check_averaged_revolutions,
    checked_settings,
)
from ._wear_statistics import batch_halfwidth, nanmax, relative_halfwidth, revolution_bounds

__all__ = ["predict_wear"]


def _with_profiles(scene: Scene, profiles: dict[str, WornProfile]) -> Scene:
    joints = dict(scene.joints)
    for name, profile in profiles.items():
        joint = joints[name]
        if not isinstance(joint, ClearanceRevolute):
            raise TypeError(f"joint {name!r} is not a clearance_revolute joint; it has no profile.")
        joints[name] = profile.apply_to(joint)
    return dataclasses.replace(scene, joints=joints)


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

    1. simulate ``settle_revolutions`` + n crank revolutions (n = ``averaged_revolutions``;
       drive periods, or turns of a motor-driven crank's angle) with the current profiles
       (the worn geometry shapes the contact) and take the response metrics of the last
       n revolutions and the Archard wear per cycle h_cyc, the mean of the n revolutions'
       wear (``run_wear`` on each), with its 95 % interval per region from batch means
       over consecutive revolutions;
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
    updates, block, limit, settle = checked_settings(
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


def update_loop(
    scene: Scene,
    *,
    targets: list[float],
    limit: float,
    settle: float,
    averaged: int,
    simulate_kwargs: dict[str, Any],
    caller: str,
) -> UpdateLoop:
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
    return UpdateLoop(
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


class UpdateLoop:
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
        # revolutions after the settle simulated at an update state (one that ends an
        # update, and the unworn one) when a hook analyses that state's run: the state's
        # increment reads the first ``averaged`` of them, the hook all (``state_traj``);
        # None: no run is shared (the hook makes its own)
        self.state_revolutions: float | None = None
        self.state_traj: xr.Dataset | None = None
        # CPU seconds (this process) of the runs and of averaging their wear, and of what
        # a hook adds under its own keys
        self.cpu: dict[str, float] = {"runs": 0.0, "wear": 0.0}
        # whole revolutions settled by a run that is not an update state when it starts
        # from the last state of the previous run (a periodic drive; None: every run
        # starts from the scene's initial state and settles ``settle``)
        self.warm_settle: int | None = None
        self.end_state: tuple[np.ndarray, np.ndarray] | None = None  # after whole periods
        self.run_settle = settle  # the settle of the last run

    # -- one simulated state
    def _simulate(
        self, label: str, *, update_state: bool = False
    ) -> tuple[xr.Dataset, int, _Check] | None:
        """The run of the current state, its settled start and its check; None (and
        ``self.failure`` set) when it fails. An update state's run lasts
        ``state_revolutions`` after the settle (kept whole in ``state_traj``) and is cut
        after ``averaged`` of them, so the increment and its check see the same
        revolutions as a run of ``settle + averaged`` (the same steps: the samples differ
        from the shorter run's by the rounding of the dense output only)."""
        self.last_check = None
        extra = self.state_revolutions if update_state else None
        shared = extra is not None
        span = self.averaged if extra is None else max(extra, float(self.averaged))
        longer = span > self.averaged
        warm = not update_state and self.warm_settle is not None and self.end_state is not None
        settle = self.run_settle = float(self.warm_settle) if warm else self.settle
        revolutions = settle + span
        kwargs = {**self.kwargs, "start": self.end_state} if warm else self.kwargs
        cpu = time.thread_time()
        try:
            traj = simulate_turns(self.current, revolutions, **kwargs)
        except SimulationError as exc:
            self.failure = f"the simulation of {label} failed: {exc}"
            return None
        finally:
            self.cpu["runs"] += time.thread_time() - cpu
        self.end_state = self._end_state(traj, revolutions)
        self.state_traj = traj if shared else None
        if longer:
            end = window_start(traj, settle + self.averaged)
            traj = traj.isel(time=slice(0, end + 1))
        check = self.last_check = _check_state(traj, self.current)
        if not check.passed:
            self.failure = self._check_message(check, label)
            return None
        return traj, window_start(traj, settle), check

    def _end_state(
        self, traj: xr.Dataset, revolutions: float
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The last state of ``traj`` when the next run may start from it: warm starts on,
        a periodic drive, and the run ended after whole drive periods (the drive's phase
        at t = 0); else None."""
        if self.warm_settle is None or drive_period(self.current) is None:
            return None
        if abs(revolutions - round(revolutions)) > 1e-9 or "final_q" not in traj.attrs:
            return None
        return traj.attrs["final_q"], traj.attrs["final_v"]

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
        state = self._simulate(self._label(0.0, 0, updates, 0), update_state=True)
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
            state = self._simulate(label, update_state=parts == 1)
            last = self.last_check
            self.subs.append(
                {"update": u, "cycles": cycles, "depth_increment": cycles * rate,
                 "penetration": last.fraction if last else math.nan,
                 "force": last.force if last else math.nan,
                 "relative_halfwidth": rates.relative_halfwidth}
            )  # fmt: skip
            self.states[-1]["relative_halfwidth"] = nanmax(
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
        cpu = time.thread_time()
        try:
            return self._averaged_rates(traj, start, label=label)
        finally:
            self.cpu["wear"] += time.thread_time() - cpu

    def _averaged_rates(self, traj: xr.Dataset, start: int, *, label: str) -> _Rates | None:
        bounds = revolution_bounds(traj, self.run_settle, self.averaged)
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
            relative = nanmax(relative, relative_halfwidth(dh, halfwidth[name]))
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
        status = FAILED if self.failure else COMPLETE
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
        ds = prediction_dataset(self, cum, settings=settings)
        return WearPrediction(
            scene=self.scene, worn_scene=self.kept, cycles=cum, reduced_updates=self.reduced,
            dataset=ds, status=status, reason=reason,
        )  # fmt: skip
