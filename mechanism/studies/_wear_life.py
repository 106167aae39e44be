"""``mechanism.wear_life``: the motion of a mechanism over its joints' wear life.

One wear path (the update loop of :func:`mechanism.predict_wear`, with the wear per cycle
averaged over several revolutions) is run up to a number of cycles; at every checkpoint the
worn state is analysed as a motion: stroboscopic points of the journals, the largest
Lyapunov exponent from the equations (:func:`mechanism.lyapunov_exponent`), the motion
verdict (:func:`chaoskit.classify_motion`), contact forces and the time shares of free
flight, impacts and continuous contact. See ``docs/wear.md`` §6.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from chaoskit.contract import __version__, check_int, check_positive, stamp, variable
from mechanism.core import Scene, SimulationError, scene_from_json
from mechanism.core.record import WearRecord
from mechanism.core.scene import ClearanceRevolute
from mechanism.core.wear import SURFACES, WornProfile, surface_angle

from ._lyapunov import SceneLyapunov
from ._turns import revolution_time
from ._wear_life_analysis import CheckpointAnalysis, Judgements, observe
from ._wear_prediction import update_loop
from ._wear_settings import (
    DEFAULT_MAX_DEPTH_INCREMENT,
    check_averaged_revolutions,
    check_depth_increment,
    check_first_revolutions,
    check_fraction,
    check_increment_settle,
)

__all__ = [
    "DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS",
    "WearLife",
    "WearLifeSettings",
    "wear_life",
]

#: Default of ``averaged_revolutions`` in :func:`wear_life` (docs/wear.md §6: on the rigid
#: paper scene at 90 rpm the median relative 95 % half-width of the increments over
#: 20 000 cycles is 2.3 with 4 revolutions, 1.0 with 8 and 1.0 with 16, which costs twice
#: the CPU time of 8).
DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS = 8
#: Default of ``verdict_samples_per_revolution``: the trajectory handed to the motion
#: verdict is thinned to about this many samples per drive period (its cost grows with the
#: samples, its evidence with the periods; docs/accuracy-vs-cost.md, "Wear path").
VERDICT_SAMPLES_PER_PERIOD = 125
#: Default of ``lyapunov_first_revolutions``: the revolutions after which the exponent's
#: run ends when their interval decides the sign.
LYAPUNOV_FIRST_REVOLUTIONS = 6.0
#: The path ends when a state fails, with this status (as :class:`mechanism.WearPrediction`).
_COMPLETE, _FAILED = "complete", "failed"


@dataclass(frozen=True, kw_only=True, eq=False)
class WearLife:
    """Result of :func:`wear_life`: one wear path and its motion at every checkpoint.

    Attributes
    ----------
    scene, worn_scene : Scene
        The starting scene and the scene carrying the profiles of the last finished
        checkpoint.
    cycles : float
        The requested cycles of wear.
    checkpoints : numpy.ndarray
        Cumulative crank cycles of every finished checkpoint; the first is 0 (unworn).
    status : str
        ``"complete"`` when the path reached ``cycles``, ``"failed"`` when a state left
        what the wear model represents (then ``reason`` says where and why; every
        checkpoint before it is kept).
    reason : str
        One line: why the path ended.
    cycles_to_chaos : float or None
        The first checkpoint whose exponent's 95 % interval lies above zero and whose
        motion verdict is chaotic, else None (always None without ``exponent``).
    verdicts : tuple of chaoskit.MotionVerdict
        The motion verdict of every finished checkpoint (empty for a path read back with
        :meth:`from_dataset`).
    exponents : tuple of SceneLyapunov or None
        The exponent of every finished checkpoint (None: not computed or failed; empty for
        a path read back with :meth:`from_dataset`).
    dataset : xarray.Dataset
        See :meth:`to_dataset`.
    """

    scene: Scene
    worn_scene: Scene
    cycles: float
    checkpoints: np.ndarray
    status: str
    reason: str
    cycles_to_chaos: float | None
    verdicts: tuple[Any, ...] = field(repr=False)
    exponents: tuple[SceneLyapunov | None, ...] = field(repr=False)
    dataset: xr.Dataset = field(repr=False)

    @property
    def success(self) -> bool:
        """True when the path reached ``cycles``."""
        return self.status == _COMPLETE

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> WearLife:
        """The path of a Dataset written from :meth:`to_dataset` (e.g. read back from a file).

        Every number comes from the Dataset; ``verdicts`` and ``exponents`` are empty
        tuples (their labels, confidences and intervals are the Dataset's variables).
        """
        try:
            chaos = float(ds.attrs["cycles_to_chaos"])
            return cls(
                scene=scene_from_json(ds.attrs["scene"]),
                worn_scene=scene_from_json(ds.attrs["worn_scene"]),
                cycles=float(ds.attrs["cycles"]),
                checkpoints=np.asarray(ds["checkpoint"].values, dtype=np.float64),
                status=str(ds.attrs["status"]),
                reason=str(ds.attrs["status_reason"]),
                cycles_to_chaos=None if chaos < 0.0 else chaos,
                verdicts=(),
                exponents=(),
                dataset=ds,
            )
        except KeyError as exc:
            raise ValueError(
                f"the Dataset is not a wear path of mechanism.wear_life (no {exc.args[0]!r})."
            ) from None

    def to_dataset(self) -> xr.Dataset:
        """The path as a Dataset over dim ``checkpoint`` (coordinate: its cycles).

        ``max_wear_depth(checkpoint, joint, surface)`` (m), ``worn_volume(checkpoint,
        joint, surface)`` (m³), ``wear_depth(checkpoint, joint, surface, angle)`` (m),
        ``wear_rate_relative_halfwidth(checkpoint)``, ``strobe_x/strobe_y(checkpoint,
        joint, crossing)`` (m, the journal's eccentricity once per revolution),
        ``lyapunov_exponent``, ``lyapunov_ci_low``, ``lyapunov_ci_high`` (1/s),
        ``motion`` (verdict label), ``motion_confidence``, ``peak_contact_force``,
        ``mean_contact_force`` (N), ``free_flight_fraction``, ``impact_fraction``,
        ``continuous_contact_fraction`` (checkpoint, joint); the settings, ``status``,
        ``status_reason``, ``cycles_to_chaos`` (−1: none) and the CPU seconds of the
        path's phases (``phase_cpu_runs``: the simulations; ``phase_cpu_wear``: averaging
        their wear; ``phase_cpu_exponent``; ``phase_cpu_verdict``; ``phase_cpu_total``;
        of which ``phase_cpu_elsewhere`` on other threads than the path's, where an
        executor ran the exponents and verdicts) in attrs. Every variable has ``units``
        and ``long_name``.
        """
        return self.dataset.copy()

    def summary(self) -> str:
        """A few lines: the path, its end, and the cycles to chaos (or "not within N cycles")."""
        ds = self.dataset
        lines = [f"wear life of scene {self.scene.name!r}: {self.reason}"]
        for i, n in enumerate(self.checkpoints):
            lo = float(ds["lyapunov_ci_low"].values[i])
            hi = float(ds["lyapunov_ci_high"].values[i])
            lam = float(ds["lyapunov_exponent"].values[i])
            depth = float(ds["max_wear_depth"].values[i].max()) * 1e6
            exponent = "not computed" if math.isnan(lam) else f"{lam:.3g} [{lo:.3g}, {hi:.3g}] 1/s"
            conf = float(ds["motion_confidence"].values[i])
            lines.append(
                f"  {n:>10.6g} cycles: depth {depth:.3g} µm, exponent {exponent}, motion "
                f"{ds['motion'].values[i]} (confidence {conf:.2f})"
            )
        if self.cycles_to_chaos is not None:
            lines.append(f"chaotic: after {self.cycles_to_chaos:.6g} cycles of wear")
        else:
            reached = float(self.checkpoints[-1]) if self.checkpoints.size else 0.0
            note = "" if self.dataset.attrs["exponent"] else " (no exponent computed)"
            lines.append(f"chaotic: not within {reached:.6g} cycles{note}")
        return "\n".join(lines)


# --------------------------------------------------------------------------- input


@dataclass(frozen=True, kw_only=True)
class WearLifeSettings:
    """How :func:`wear_life` wears the joints and analyses each checkpoint's worn state.

    Every field is checked on construction (a ValueError names the field and its
    accepted range).

    Parameters
    ----------
    settle_revolutions : float
        Revolutions left out before the wear is measured and before the analysis (≥ 0).
    analysis_revolutions : int
        Revolutions analysed at each checkpoint, in [4, 10000] (one stroboscopic point
        each; the motion verdict needs at least 20 points to decide).
    lyapunov_revolutions, lyapunov_discard : float
        Revolutions of the exponent's run (> 0) and those left out of it (≥ 0, fewer).
    continuous_contact : float
        Shortest continuous-contact episode, as a fraction of the drive period, in (0, 1).
    averaged_revolutions : int
        Revolutions whose mean wear is the wear per cycle, in [1, 1000] (an argument of
        :func:`wear_life` given explicitly wins over this field).
    max_depth_increment : float
        Largest depth one increment may add, as a fraction of the radial clearance, in
        (0, 1] (an explicit argument of :func:`wear_life` wins).
    exponent : bool
        Compute the exponent from the equations at each checkpoint (an explicit argument
        of :func:`wear_life` wins).
    lyapunov_first_revolutions : float or None
        Revolutions after which the exponent's run ends when the 95 % interval of their
        kept part lies beyond zero by at least its half-width (the sign is decided;
        ``decide_after`` of :func:`mechanism.lyapunov_exponent`), > ``lyapunov_discard``,
        default 6; otherwise the same run goes on to ``lyapunov_revolutions``. None, or a
        value of at least ``lyapunov_revolutions``: always the full run.
    share_state_run : bool
        One run per checkpoint state gives both its analysis and the first increment worn
        from it (default True; False: two runs, whose samples differ only by rounding).
    verdict_samples_per_revolution : int
        Samples per drive period handed to the motion verdict, in [20, 100000]
        (default 125; the trajectory is thinned to about this many).
    increment_settle_revolutions : int or None
        With a periodic drive, the run of an increment that is not a checkpoint state
        starts from the last state of the previous run (``mechanism.simulate``'s
        ``start``) and settles this many whole revolutions, in [0, 100]; None: it starts
        from the scene's initial state and settles ``settle_revolutions``, like a
        checkpoint state (which always does).

    Examples
    --------
    >>> import mechanism
    >>> mechanism.WearLifeSettings(analysis_revolutions=40).lyapunov_revolutions
    10.0
    """

    settle_revolutions: float = 2.0
    analysis_revolutions: int = 25
    lyapunov_revolutions: float = 10.0
    lyapunov_discard: float = 2.0
    continuous_contact: float = 0.01
    averaged_revolutions: int = DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS
    max_depth_increment: float = DEFAULT_MAX_DEPTH_INCREMENT
    exponent: bool = True
    lyapunov_first_revolutions: float | None = LYAPUNOV_FIRST_REVOLUTIONS
    share_state_run: bool = True
    verdict_samples_per_revolution: int = VERDICT_SAMPLES_PER_PERIOD
    increment_settle_revolutions: int | None = None

    def __post_init__(self) -> None:
        settle = check_positive(self.settle_revolutions, name="settle_revolutions", allow_zero=True)
        analysis = check_int(
            self.analysis_revolutions, name="analysis_revolutions", minimum=4, maximum=10000
        )
        lyap_revs = check_positive(self.lyapunov_revolutions, name="lyapunov_revolutions")
        lyap_discard = check_positive(
            self.lyapunov_discard, name="lyapunov_discard", allow_zero=True
        )
        if lyap_discard >= lyap_revs:
            raise ValueError(
                f"lyapunov_discard must be in [0, lyapunov_revolutions) = [0, {lyap_revs:g}); "
                f"got {self.lyapunov_discard!r}."
            )
        checked = {
            "settle_revolutions": settle,
            "analysis_revolutions": analysis,
            "lyapunov_revolutions": lyap_revs,
            "lyapunov_discard": lyap_discard,
            "continuous_contact": check_fraction(self.continuous_contact, "continuous_contact"),
            "averaged_revolutions": check_averaged_revolutions(self.averaged_revolutions),
            "max_depth_increment": check_depth_increment(self.max_depth_increment),
            "exponent": _flag(self.exponent, "exponent"),
            "lyapunov_first_revolutions": check_first_revolutions(
                self.lyapunov_first_revolutions, lyap_discard
            ),
            "share_state_run": _flag(self.share_state_run, "share_state_run"),
            "verdict_samples_per_revolution": check_int(
                self.verdict_samples_per_revolution, name="verdict_samples_per_revolution",
                minimum=20, maximum=100000,
            ),
            "increment_settle_revolutions": check_increment_settle(
                self.increment_settle_revolutions
            ),
        }  # fmt: skip
        for name, value in checked.items():
            object.__setattr__(self, name, value)


def checked_settings(settings: Any) -> WearLifeSettings:
    """``settings`` (None: the defaults), or a TypeError when it is not a WearLifeSettings."""
    if settings is None:
        return WearLifeSettings()
    if not isinstance(settings, WearLifeSettings):
        raise TypeError(
            f"settings must be a mechanism.WearLifeSettings; got {type(settings).__name__}."
        )
    return settings


def check_wear_path(scene: Any, cycles: Any, checkpoints: Any) -> tuple[Scene, list[float]]:
    """The checks :func:`wear_life` makes before any work: the scene, ``cycles`` and the
    checkpoints (a ValueError or TypeError in one line). Returns the scene and the
    cumulative cycles at the end of every interval."""
    scene = _checked_scene(scene)
    _, targets = _checked_path(cycles, checkpoints)
    update_loop(
        scene, targets=targets, limit=DEFAULT_MAX_DEPTH_INCREMENT, settle=0.0, averaged=1,
        simulate_kwargs={}, caller="wear_life",
    )  # fmt: skip
    return scene, targets


def _checked_path(cycles: Any, checkpoints: Any) -> tuple[float, list[float]]:
    """``cycles`` and the sorted checkpoints ending at ``cycles``, or a ValueError."""
    total = check_positive(cycles, name="cycles")
    try:
        points = np.atleast_1d(np.asarray(checkpoints, dtype=np.float64))
    except (TypeError, ValueError):
        raise ValueError(
            f"checkpoints must be increasing cycle counts in (0, cycles]; got {checkpoints!r}."
        ) from None
    if points.ndim != 1 or points.size == 0 or not np.isfinite(points).all():
        raise ValueError(
            "checkpoints must be a non-empty list of finite cycle counts in (0, cycles]; "
            f"got {checkpoints!r}."
        )
    if points[0] <= 0.0 or points[-1] > total:
        raise ValueError(
            f"checkpoints must lie in (0, cycles] = (0, {total:g}]; got {points.tolist()}."
        )
    if (np.diff(points) <= 0.0).any():
        raise ValueError(f"checkpoints must be strictly increasing; got {points.tolist()}.")
    targets = points.tolist()
    if targets[-1] < total:
        targets.append(total)
    return total, targets


def _checked_scene(scene: Any) -> Scene:
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    if revolution_time(scene) is None:
        # a wear cycle is a crank revolution: a drive period, or a turn of a motor-driven
        # crank counted on its angle
        raise ValueError(
            "wear_life needs a scene with a periodic drive or a motor drive (cycles are "
            "crank turns)."
        )
    for name, joint in scene.joints.items():
        if isinstance(joint, ClearanceRevolute) and not joint.wear.coefficient > 0.0:
            raise ValueError(
                f"joints.{name}.wear.coefficient must be > 0 (m² N⁻¹) for a wear path; "
                f"got {joint.wear.coefficient!r}."
            )
    return scene


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"{name} must be True or False; got {value!r}.")
    return bool(value)


# --------------------------------------------------------------------------- the path


def wear_life(
    scene: Scene,
    *,
    cycles: float,
    checkpoints: Sequence[float],
    averaged_revolutions: int | None = None,
    exponent: bool | None = None,
    max_depth_increment: float | None = None,
    settings: WearLifeSettings | None = None,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    progress: bool = False,
) -> WearLife:
    """Wear the scene's clearance joints up to ``cycles`` and analyse the motion at checkpoints.

    The wear path is the update loop of :func:`mechanism.predict_wear` with one update per
    checkpoint interval: each increment is the Archard wear per cycle averaged over
    ``averaged_revolutions`` revolutions of the current worn state, with the increments
    capped at ``max_depth_increment`` × clearance. At the unworn state, at every checkpoint
    and at ``cycles`` the worn scene is simulated for ``settle_revolutions`` +
    ``analysis_revolutions`` revolutions (fields of ``settings``) and the last
    ``analysis_revolutions`` give:

    * the stroboscopic points of every journal (its eccentricity each time the crank
      passes its starting angle);
    * peak and time-mean contact force per joint;
    * the time shares of free flight (no contact force), impacts (contact episodes
      shorter than ``continuous_contact`` × the drive period) and continuous contact
      (longer episodes), per joint (``contact_modes``);
    * the largest Lyapunov exponent from the equations (:func:`mechanism.lyapunov_exponent`
      over ``lyapunov_revolutions``, ``lyapunov_discard`` left out) with its 95 % interval;
    * the motion verdict of the journals' eccentricities (:func:`chaoskit.classify_motion`,
      the exponent as evidence) and its confidence.

    ``cycles_to_chaos`` is the first checkpoint whose exponent interval lies above zero and
    whose verdict is chaotic; with ``exponent=False`` there is no interval, so it is None
    (the verdicts are still recorded).

    A state the wear model cannot represent — a penetration beyond the radial clearance, a
    non-finite force, a journal worn towards its centre, a failed simulation (the checks of
    :func:`mechanism.predict_wear`) — ends the path: the result has ``status == "failed"``,
    the reason, and every checkpoint before it. It is returned, not raised.

    Parameters
    ----------
    scene : Scene
        A mechanism with a periodic drive or a motor drive (whose cycles are counted as
        turns of the crank angle, and whose exponent runs over periods of the no-load
        speed) and at least one active clearance joint with a positive wear coefficient
        (``effects.wear`` is switched on).
    cycles : float
        Crank cycles of wear (> 0).
    checkpoints : sequence of float
        Strictly increasing cumulative cycle counts in (0, ``cycles``]; ``cycles`` is
        added as the last one when missing, and the unworn state is always the first.
    averaged_revolutions : int, optional
        Revolutions whose mean wear is the wear per cycle, in [1, 1000]; default the
        field of ``settings`` (8).
    exponent : bool, optional
        Compute the exponent from the equations at each checkpoint (the costliest part);
        default the field of ``settings`` (True).
    max_depth_increment : float, optional
        Largest depth one increment may add, as a fraction of the radial clearance, in
        (0, 1]; default the field of ``settings`` (0.025).
    settings : WearLifeSettings, optional
        The settle, analysed and exponent revolutions and the continuous-contact time of
        each checkpoint's analysis, and the defaults of the three arguments above;
        default ``WearLifeSettings()``.
    method, rtol, atol, output_step
        Passed to :func:`mechanism.simulate`.
    progress : bool
        Show a progress bar over the checkpoints.

    Returns
    -------
    WearLife

    Raises
    ------
    ValueError
        For bad settings (the parameter and its accepted range are named), a scene without
        an active clearance joint, or a wear coefficient of 0.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    >>> life = mechanism.wear_life(scene, cycles=20000, checkpoints=[5000, 10000])  # doctest: +SKIP
    >>> print(life.summary())  # doctest: +SKIP
    """
    scene = _checked_scene(scene)
    total, targets = _checked_path(cycles, checkpoints)
    settings = checked_settings(settings)
    overrides = {"averaged_revolutions": averaged_revolutions, "exponent": exponent,
                 "max_depth_increment": max_depth_increment}  # fmt: skip
    given = {k: v for k, v in overrides.items() if v is not None}
    if given:
        settings = dataclasses.replace(settings, **given)
    kwargs = {"method": method, "rtol": rtol, "atol": atol, "output_step": output_step}
    return wear_path(scene, total, targets, settings, PathRun(kwargs, progress=progress))


@dataclass(frozen=True)
class PathRun:
    """How a wear path runs, besides its settings: the keywords of
    :func:`mechanism.simulate` (``method``, ``rtol``, ``atol``, ``output_step``), a
    progress bar, and the executor the checkpoints' exponents and verdicts are submitted
    to while the path wears on (None: computed in turn; the numbers are the same)."""

    simulate_kwargs: dict[str, Any] = field(default_factory=dict)
    progress: bool = False
    executor: Executor | None = None


def wear_path(
    scene: Scene, cycles: float, targets: list[float], settings: WearLifeSettings, run: PathRun
) -> WearLife:
    """:func:`wear_life` of checked arguments (:func:`check_wear_path`, a
    :class:`WearLifeSettings`)."""
    cpu_start = time.thread_time()
    settle = settings.settle_revolutions
    lyap_revs, lyap_discard = settings.lyapunov_revolutions, settings.lyapunov_discard
    # the runs keep only what the wear and the analysis read (the same samples as the
    # full record, without the ideal companion: docs/wear.md §7)
    kwargs = {**run.simulate_kwargs, "record": WearRecord()}
    first = settings.lyapunov_first_revolutions
    first = lyap_revs if first is None else min(first, lyap_revs)
    how = CheckpointAnalysis(
        discard=settle, revolutions=settings.analysis_revolutions,
        exponent=bool(settings.exponent), lyapunov_revolutions=lyap_revs,
        lyapunov_discard=lyap_discard, lyapunov_first=first,
        continuous_fraction=settings.continuous_contact,
        verdict_samples=settings.verdict_samples_per_revolution, simulate_kwargs=kwargs,
    )  # fmt: skip
    loop = update_loop(
        scene, targets=targets, limit=settings.max_depth_increment, settle=settle,
        averaged=settings.averaged_revolutions, simulate_kwargs=kwargs, caller="wear_life",
    )  # fmt: skip
    if settings.share_state_run:
        loop.state_revolutions = float(how.revolutions)
    loop.warm_settle = settings.increment_settle_revolutions
    records: list[dict[str, Any]] = []
    judgements = Judgements(run.executor)
    analysis_failure: list[str] = []

    def on_state(current: Scene, update: int, at: float) -> bool:
        try:
            traj, loop.state_traj = loop.state_traj, None  # not held while it wears on
            record, motion = observe(current, loop.names, how, traj, loop.cpu)
        except SimulationError as exc:
            analysis_failure.append(
                f"the analysis of the state after {at:.6g} cycles failed: {exc}"
            )
            return False
        records.append(record)
        judgements.add(current, how, motion)
        return True

    loop.on_state = on_state
    bar = tqdm(total=len(targets) + 1, desc=f"wear_life {scene.name}", unit="checkpoint",
               disable=not run.progress)  # fmt: skip
    try:
        loop.run(len(targets), bar)
    finally:
        bar.close()
    for record, judged in zip(records, judgements.collect(loop.cpu), strict=True):
        record.update(judged)
    failure = loop.failure or (analysis_failure[0] if analysis_failure else "")
    states = loop.states[: len(records)]
    recorded = {
        "cycles": cycles, "averaged_revolutions": settings.averaged_revolutions,
        "max_depth_increment": settings.max_depth_increment,
        "settle_revolutions": settle, "analysis_revolutions": how.revolutions,
        "exponent": int(how.exponent), "lyapunov_revolutions": lyap_revs,
        "lyapunov_discard": lyap_discard, "lyapunov_first_revolutions": first,
        "continuous_contact": how.continuous_fraction,
        "share_state_run": int(settings.share_state_run),
        "verdict_samples_per_revolution": how.verdict_samples,
        # -1: increments start from the scene's initial state (no warm start)
        "increment_settle_revolutions": -1
        if settings.increment_settle_revolutions is None
        else settings.increment_settle_revolutions,
        # where the path's CPU time went (s, every thread it used): the runs, averaging
        # their wear, the exponent, the verdict; the rest is the analysis's bookkeeping
        **{f"phase_cpu_{k}": float(loop.cpu.get(k, 0.0))
           for k in ("runs", "wear", "exponent", "verdict")},
        "phase_cpu_total": time.thread_time() - cpu_start + judgements.elsewhere,
        # of which on other threads (the executor's)
        "phase_cpu_elsewhere": judgements.elsewhere,
    }  # fmt: skip
    return _result(scene, loop, states, records, cycles, failure, recorded)


def _first_chaotic(cum: np.ndarray, records: list[dict[str, Any]]) -> float | None:
    """The first checkpoint with an exponent interval above 0 and a chaotic verdict."""
    for n, r in zip(cum, records, strict=True):
        lam = r["lyapunov"]
        if lam is not None and float(lam.ci[0]) > 0.0 and r["verdict"].label == "chaotic":
            return float(n)
    return None


def _result(
    scene: Scene,
    loop: Any,
    states: list[dict[str, Any]],
    records: list[dict[str, Any]],
    total: float,
    failure: str,
    settings: dict[str, Any],
) -> WearLife:
    cum = np.array([s["cycles"] for s in states], dtype=np.float64)
    chaos = _first_chaotic(cum, records)
    reached = float(cum[-1]) if cum.size else 0.0
    if failure:
        status, reason = _FAILED, f"the path ended after {reached:.6g} cycles: {failure}"
    else:
        status = _COMPLETE
        reason = f"{len(states) - 1} checkpoints up to {total:.6g} cycles"
    if chaos is None and not failure:
        reason += f"; the motion did not turn chaotic within {total:.6g} cycles"
    settings = {**settings, "status": status, "status_reason": reason,
                "cycles_to_chaos": -1.0 if chaos is None else chaos}  # fmt: skip
    ds = _dataset(scene, loop, states, records, cum, settings)
    return WearLife(
        scene=scene, worn_scene=loop.kept, cycles=total, checkpoints=cum, status=status,
        reason=reason, cycles_to_chaos=chaos, verdicts=tuple(r["verdict"] for r in records),
        exponents=tuple(r["lyapunov"] for r in records), dataset=ds,
    )  # fmt: skip


def _strobe(records: list[dict[str, Any]], key: str, joints: int) -> np.ndarray:
    width = max((r[key].shape[-1] for r in records), default=0)
    out = np.full((len(records), joints, width), np.nan)
    for i, r in enumerate(records):
        out[i, :, : r[key].shape[-1]] = r[key]
    return out


def _per_joint(records: list[dict[str, Any]], key: str, names: list[str]) -> np.ndarray:
    """``key`` of every record as (checkpoint, joint), also when no state was analysed."""
    values = [r[key] for r in records]
    return np.array(values, dtype=np.float64).reshape(len(records), len(names))


def _dataset(
    scene: Scene,
    loop: Any,
    states: list[dict[str, Any]],
    records: list[dict[str, Any]],
    cum: np.ndarray,
    settings: dict[str, Any],
) -> xr.Dataset:
    names = loop.names
    regions = loop.profiles[names[0]].regions
    n = len(states)
    depth = np.stack([s["depth"] for s in states]) if n else np.zeros((0, len(names), 2, regions))
    volume = np.zeros(depth.shape[:3])
    for i in range(n):
        for j, name in enumerate(names):
            worn = WornProfile.from_joint(scene.joints[name]).with_depth(
                bearing_depth=depth[i, j, 0], journal_depth=depth[i, j, 1]
            )
            volume[i, j] = (worn.bearing_volume, worn.journal_volume)
    lam = [r["lyapunov"] for r in records]
    exp = [math.nan if x is None else float(x.exponent) for x in lam]
    lo = [math.nan if x is None else float(x.ci[0]) for x in lam]
    hi = [math.nan if x is None else float(x.ci[1]) for x in lam]
    verdicts = [r["verdict"] for r in records]
    modes = np.array([r["modes"] for r in records], dtype=np.float64).reshape(n, len(names), 3)
    cj, cjs = ("checkpoint", "joint"), ("checkpoint", "joint", "surface")
    data = {
        "max_wear_depth": variable(cjs, depth.max(axis=3, initial=0.0), "m", "largest wear depth"),
        "worn_volume": variable(cjs, volume, "m3", "worn volume"),
        "wear_depth": variable((*cjs, "angle"), depth, "m", "wear depth"),
        "wear_rate_relative_halfwidth": variable(
            ("checkpoint",), [s["relative_halfwidth"] for s in states], "1",
            "largest 95 % half-width / mean of the wear per cycle over the worn regions, of "
            "the increments worn from this checkpoint to the next (NaN: one revolution averaged)",
        ),
        "strobe_x": variable((*cj, "crossing"), _strobe(records, "strobe_x", len(names)), "m",
                             "journal eccentricity x once per crank revolution"),
        "strobe_y": variable((*cj, "crossing"), _strobe(records, "strobe_y", len(names)), "m",
                             "journal eccentricity y once per crank revolution"),
        "lyapunov_exponent": variable(("checkpoint",), exp, "1/s",
                                      "largest Lyapunov exponent from the equations"),
        "lyapunov_ci_low": variable(("checkpoint",), lo, "1/s",
                                    "lower end of the exponent's 95 % interval"),
        "lyapunov_ci_high": variable(("checkpoint",), hi, "1/s",
                                     "upper end of the exponent's 95 % interval"),
        "lyapunov_run_revolutions": variable(
            ("checkpoint",), [r["lyapunov_run"] for r in records], "1",
            "revolutions of the exponent's run (the first, shorter run when it decided "
            "the sign; NaN: not computed)"),
        "motion": variable(("checkpoint",), np.array([v.label for v in verdicts], dtype=object),
                           "1", "motion verdict (chaoskit.classify_motion)"),
        "motion_confidence": variable(("checkpoint",), [float(v.confidence) for v in verdicts],
                                      "1", "confidence of the motion verdict"),
        "peak_contact_force": variable(cj, _per_joint(records, "peak_force", names), "N",
                                       "peak contact force over the analysed revolutions"),
        "mean_contact_force": variable(cj, _per_joint(records, "mean_force", names), "N",
                                       "time-mean contact force over the analysed revolutions"),
        "free_flight_fraction": variable(cj, modes[:, :, 0], "1",
                                         "share of time without contact force"),
        "impact_fraction": variable(cj, modes[:, :, 1], "1",
                                    "share of time in contact episodes shorter than the "
                                    "continuous-contact time"),
        "continuous_contact_fraction": variable(cj, modes[:, :, 2], "1",
                                                "share of time in longer contact episodes"),
    }  # fmt: skip
    coords = {
        "checkpoint": ("checkpoint", cum, {"units": "1", "long_name": "crank cycles of wear"}),
        "joint": ("joint", np.array(names, dtype=object)),
        "surface": ("surface", np.array(SURFACES, dtype=object)),
        "angle": surface_angle(regions),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs["scene"] = scene.to_json()
    ds.attrs["worn_scene"] = loop.kept.to_json()
    ds.attrs["scene_name"] = scene.name
    ds.attrs.update(settings)
    return stamp(
        ds,
        title=f"wear life of scene {scene.name!r}",
        source=f"mechanism (chaoskit {__version__})",
        history=(
            f"mechanism.wear_life({scene.name!r}, cycles={settings['cycles']}, "
            f"averaged_revolutions={settings['averaged_revolutions']}, "
            f"max_depth_increment={settings['max_depth_increment']})"
        ),
    )
