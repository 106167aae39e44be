"""``mechanism.continuation``: periodic orbits of a rigid scene followed over one scene
key, with their bifurcations and grazings labelled."""

from __future__ import annotations

import contextlib
import logging
import math
import time
import typing
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import xarray as xr

from mechanism.core import SimulationError, default_step, drive_period, step_limits
from mechanism.core.integrate import Dopri5, length_scale, project_state, section_latch
from mechanism.core.model import assemble, initial_state
from mechanism.core.scene import MotorDrive, Scene, SceneError

from ._continuation import (
    BifurcationPoint,
    ContinuationBranch,
    ContinuationPoint,
    ContinuationSettings,
    Follower,
    Solved,
)
from ._multiple import REFREEZE_ABOVE
from ._newton import CONTRACTION
from ._orbit import (
    DEFAULT_PERTURBATION,
    DEFAULT_TOLERANCE,
    MOTOR_REFUSAL,
    PeriodicOrbit,
    periodic_orbit,
)
from ._shooting import Section, StroboscopicMap, frozen_latches, newton_step

__all__ = [
    "Continuation",
    "contact_signature",
    "continuation",
    "damping_coefficients",
    "grazing_margin",
]

_LOG = logging.getLogger(__name__)

#: periods run from the scene's start before the doubled orbit is taken at a period
#: doubling (the attractor just past a supercritical doubling is the doubled orbit)
SWITCH_SETTLE = 40
#: chord iterations (the previous point's monodromy matrix as Newton's Jacobian) at most
#: before the shooting takes over; each must cut the residual at least this much
CHORD_ITERATIONS = 6
CHORD_RATE = 0.5


def contact_signature(orbit: PeriodicOrbit) -> tuple[str, ...]:
    """The orbit's contact modes as a cyclic word per clearance joint.

    Each joint's modes in time order (``"joint:mode"``), the phase that runs through the
    section counted once and the word rotated to its smallest rotation, so moving the
    section along the orbit does not change it; a contact phase that appears or
    vanishes does.
    """
    out: list[str] = []
    for joint in orbit.joint_names:
        modes = [p.mode for p in orbit.phases if p.joint == joint]
        if len(modes) > 1 and modes[0] == modes[-1]:
            modes = modes[:-1]
        if modes:
            rotations = [tuple(modes[i:] + modes[:i]) for i in range(len(modes))]
            modes = list(min(rotations))
        out.extend(f"{joint}:{m}" for m in modes)
    return tuple(out)


def damping_coefficients(scene: Scene, joints: tuple[str, ...]) -> np.ndarray:
    """χ of each clearance joint's contact law, F = Kδⁿ(1 + χ δ̇/δ̇⁻): 3(1 − e²)/4
    (Lankarani–Nikravesh), 8(1 − e)/(5e) (Flores), else 0 (the elastic part alone)."""
    out = np.zeros(len(joints))
    for i, name in enumerate(joints):
        joint = scene.joints.get(name)
        contact = getattr(joint, "contact", None)
        e = float(getattr(joint, "restitution", 1.0))
        law = getattr(contact, "law", "hertz")
        if law == "lankarani-nikravesh":
            out[i] = 0.75 * (1.0 - e * e)
        elif law == "flores" and e > 0.0:
            out[i] = 8.0 * (1.0 - e) / (5.0 * e)
    return out


def grazing_margin(orbit: PeriodicOrbit, damping: np.ndarray | None = None) -> float:
    """How far the orbit is from a grazing (0 at one), the smallest over its joints.

    A joint in contact the whole period: its smallest contact force over the mean along
    the orbit, F ∝ δ^1.5 max(0, 1 + χ δ̇/δ̇⁻) with ``damping`` χ per joint (default 0)
    and δ̇⁻ its latched impact velocity (the exponent moves the ratio, not where F
    vanishes). The journal lifts off where F reaches 0, through
    the penetration or through the damping factor (a journal pulled away faster than
    1/χ times its latched speed is released while still pressed in). Any other joint:
    the smallest interior extreme of the penetration inside a phase over the clearance
    (a free flight closest to touching, a contact closest to lifting off); only samples
    whose neighbours along the periodic orbit are in the same contact state count, so
    the entries and exits of contacts, where the penetration passes 0 by definition, do
    not. NaN when no joint has such an extreme.
    """
    flags = np.asarray(orbit.in_contact[:-1]) != 0
    pen = np.asarray(orbit.penetration[:-1], dtype=np.float64)
    chi = np.zeros(pen.shape[1]) if damping is None else np.asarray(damping, dtype=np.float64)
    rate = np.gradient(np.asarray(orbit.penetration, dtype=np.float64), orbit.time, axis=0)[:-1]
    best = math.inf
    for j in range(pen.shape[1]):
        f, a = flags[:, j], np.abs(pen[:, j])
        if np.all(f):
            latch = max(abs(float(orbit.section_latch[j])), 1e-12)
            factor = np.maximum(1.0 + chi[j] * rate[:, j] / latch, 0.0)
            force = np.maximum(pen[:, j], 0.0) ** 1.5 * factor
            mean = float(np.mean(force))
            if mean > 0.0:
                best = min(best, float(np.min(force)) / mean)
            continue
        fp, fn = np.roll(f, 1), np.roll(f, -1)
        extreme = (f == fp) & (f == fn) & (a <= np.roll(a, 1)) & (a <= np.roll(a, -1))
        if np.any(extreme):
            best = min(best, float(np.min(a[extreme])) / orbit.clearance)
    return best if math.isfinite(best) else math.nan


@dataclass(frozen=True, kw_only=True)
class Continuation:
    """Periodic orbits of a scene followed over one scene key.

    Attributes
    ----------
    parameter : str
        The scene key followed (e.g. ``"drive.speed_rpm"``).
    units : str
        Its units.
    scene_name : str
    branches : tuple of ContinuationBranch
        The first from the start of the span; further ones switched to at period
        doublings.
    bifurcations : tuple of BifurcationPoint
        Located period doublings, folds, Neimark–Sacker points and grazings, in the
        order found.
    settings : ContinuationSettings
    orbit_solves : int
        Calls of :func:`mechanism.periodic_orbit` (converged or not).
    cpu_time : float
        Process CPU time (s).
    """

    parameter: str
    units: str
    scene_name: str
    branches: tuple[ContinuationBranch, ...]
    bifurcations: tuple[BifurcationPoint, ...]
    settings: ContinuationSettings
    orbit_solves: int = 0
    cpu_time: float = 0.0

    def first_loss_of_stability(self, branch: int = 0) -> BifurcationPoint | None:
        """The first located point on ``branch`` past which its orbit is unstable, or
        the branch's end when it ends stable (no stable orbit followed past it)."""
        for bif in self.bifurcations:
            if bif.branch != branch:
                continue
            before = bool(np.all(np.abs(bif.multipliers_before) < 1.0))
            after = bool(np.all(np.abs(bif.multipliers_after) < 1.0))
            if before and (bif.branch_end or not after):
                return bif
        return None

    def to_dataset(self) -> xr.Dataset:
        """Points of every branch and the labelled bifurcations as a Dataset (units and
        long names)."""
        return _dataset(self)


def continuation(
    scene: Scene,
    *,
    parameter: str,
    values: Sequence[float] | None = None,
    span: tuple[float, float] | None = None,
    orbit: PeriodicOrbit | None = None,
    settings: ContinuationSettings | None = None,
    seeds: Sequence[float] | None = None,
) -> Continuation:
    """Follow a periodic orbit of a rigid scene over one scene key and label where it
    bifurcates.

    Natural-parameter continuation: each point is :func:`mechanism.periodic_orbit` at
    the next value with the previous orbit as guess (secant-predicted section state,
    moved onto the new value's constraint manifold); the step halves when shooting does
    not converge and grows after an easy point. Between consecutive points the
    multipliers' test functions mark a period doubling (a real multiplier crosses −1),
    a fold (+1) or a Neimark–Sacker bifurcation (a complex pair leaves the unit
    circle), and a change of the orbit's contact-mode signature (per clearance joint,
    the cyclic sequence of its contact phases) marks a grazing; each is bisected down to
    ``settings.locate_tolerance``. At a period doubling the doubled orbit one step past
    it is started from the orbit displaced along the Floquet vector of the multiplier
    nearest −1 (else from a run of the scene settled for 40 periods) and followed too,
    up to ``settings.max_period``.
    When shooting fails at every step down to ``settings.min_step``, the branch ends
    there: the end is reported among the bifurcations with ``branch_end`` set, bracketed
    by the last converged value and the first failed one, and named a grazing (the
    orbit's grazing margin extrapolates to 0 inside twice that bracket), a fold or a
    period doubling (a multiplier within 0.2 of +1 or −1), else ``"end"``.

    Parameters
    ----------
    scene : mechanism.scene.Scene
        A rigid scene with a periodic drive (as for :func:`mechanism.periodic_orbit`).
    parameter : str
        Dotted scene key to vary, e.g. ``"drive.speed_rpm"``.
    values : sequence of float, optional
        Values to pass through in order (steps between them under step control).
    span : tuple of float, optional
        (start, stop); exactly one of ``values`` and ``span``.
    orbit : PeriodicOrbit, optional
        An orbit at the first value (default: :func:`mechanism.periodic_orbit` there
        from the scene's start).
    settings : ContinuationSettings, optional
        Default: steps of 1/100 of the span (at most 1/25, at least 1/10 000; grown
        after a point that converged in at most 5 Newton iterations, halved after 8
        without convergence) and bifurcations located to 1/1 000 of it.
    seeds : sequence of float, optional
        Values inside the span where further period-1 branches start, each from a run
        of the scene settled for 40 periods (one per regular stretch of an orbit
        diagram, say): a seed not on a branch followed before is followed down to the
        start of the span and up to its end, each way until it ends or runs onto a
        branch followed before (its section eccentricities within 5 % of the clearance
        of that branch's there), so every edge of a regular stretch is a located point.

    Returns
    -------
    Continuation

    Raises
    ------
    ValueError
        On a bad key, span, values or seeds, or when the first orbit does not converge.
    """
    cpu0 = time.process_time()
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    if isinstance(scene.drive, MotorDrive):
        raise ValueError(MOTOR_REFUSAL.format(caller="continuation"))
    targets = _targets(values, span)
    extra = _seeds(seeds, targets)
    try:
        first_scene = scene.replace({parameter: targets[0]})
    except SceneError as exc:
        raise ValueError(f"parameter {parameter!r} is not a scene key: {exc}") from None
    width = abs(targets[-1] - targets[0])
    if settings is None:
        settings = ContinuationSettings(
            step=width / 100, min_step=width / 1e4, max_step=width / 25,
            locate_tolerance=width / 1e3, easy_iterations=5, max_iterations=8,
        )  # fmt: skip
    corrector = _SceneCorrector(scene, parameter, settings)
    start = orbit if orbit is not None else periodic_orbit(first_scene)
    corrector.solves += orbit is None
    seed = (
        corrector.wrap(start, targets[0])
        if start.converged
        else corrector.at(targets[0], corrector.wrap(start, targets[0]))
    )
    if seed is None:
        raise ValueError(
            f"no periodic orbit converged at {parameter} = {targets[0]:g} (residual "
            f"{start.residual:.3g} of the clearance); pass orbit= a converged orbit there."
        )
    branches: list[ContinuationBranch] = []
    solved: list[list[Solved]] = []
    follower = Follower(
        corrector, settings,
        stop_when=lambda new: _joins(new, branches, solved, corrector.period),
    )  # fmt: skip
    found: list[BifurcationPoint] = []
    queue: list[tuple[Solved, int, str, float]] = [(seed, 1, "start", targets[-1])]
    while queue or extra:
        if not queue:
            value = extra.pop(0)
            covered = _covered(value, branches)
            if covered is not None:
                _LOG.info("seed %.6g lies on branch %d: not started again", value, covered)
                continue
            fresh = corrector.settled(value)
            if fresh is not None:
                origin = f"settled run at {value:.6g}"
                queue.append((fresh, 1, f"{origin}, followed down", min(targets[0], targets[-1])))
                queue.append((fresh, 1, f"{origin}, followed up", max(targets[0], targets[-1])))
            continue
        first, k, origin, stop = queue.pop(0)
        corrector.period = k
        branch, located, points = follower.follow(
            first, stop, period=k, branch=len(branches), origin=origin,
            targets=targets[1:] if not branches else None,
        )  # fmt: skip
        branches.append(branch)
        solved.append(points)
        found.extend(located)
        last = branch.points[-1].parameter
        _LOG.info("branch %d (period %d, %s) ends at %.6g: %s", len(branches) - 1, k, origin,
                  last, branch.end)  # fmt: skip
        for bif in located:
            _LOG.info("%s at %.6g %s: %s", bif.kind, bif.parameter, bif.bracket, bif.explanation)
        if (settings.reseed and k == 1 and stop == targets[-1]
                and branch.end.startswith("the corrector failed")):  # fmt: skip
            fresh = corrector.reseed(last, targets[-1])
            if fresh is not None:
                queue.append((fresh, 1, f"settled run at {fresh.point.parameter:.6g}",
                              targets[-1]))  # fmt: skip
        if not settings.switch_branches or 2 * k > settings.max_period:
            continue
        for bif in located:
            if bif.kind == "period-doubling":
                ends = [x for x in follower.brackets if x[0] is bif]
                near = ends[0][1].payload if ends else None
                doubled = corrector.doubled(bif, stop, near)
                if doubled is not None:
                    queue.append((doubled, 2 * k, f"period doubling at {bif.parameter:.6g}",
                                  stop))  # fmt: skip
    return Continuation(
        parameter=parameter,
        units=_key_units(scene, parameter),
        scene_name=scene.name,
        branches=tuple(branches),
        bifurcations=tuple(found),
        settings=settings,
        orbit_solves=corrector.solves,
        cpu_time=time.process_time() - cpu0,
    )


#: a branch that comes within this share of the clearance (section eccentricities) of a
#: branch followed before, inside that branch's range, has joined it
JOIN_TOLERANCE = 0.05


def _seeds(seeds: Sequence[float] | None, targets: list[float]) -> list[float]:
    """The seed values, checked to be finite numbers inside the span."""
    if seeds is None:
        return []
    lo, hi = min(targets[0], targets[-1]), max(targets[0], targets[-1])
    try:
        out = [float(v) for v in seeds]
    except (TypeError, ValueError):
        raise ValueError(f"seeds must be numbers; got {seeds!r}.") from None
    for v in out:
        if not (math.isfinite(v) and lo <= v <= hi):
            raise ValueError(f"seeds must be finite values in [{lo:g}, {hi:g}]; got {v!r}.")
    return out


def _covered(value: float, branches: list[ContinuationBranch]) -> int | None:
    """Index of a period-1 branch whose followed range holds ``value``."""
    for i, b in enumerate(branches):
        if b.period == 1 and len(b.points) > 1:
            ps = b.parameter
            if ps.min() <= value <= ps.max():
                return i
    return None


def _joins(
    new: Solved, branches: list[ContinuationBranch], solved: list[list[Solved]], period: int
) -> str | None:
    """Why the branch ends at ``new``: it lies on a branch of the same period followed
    before (inside its range, its section eccentricities within ``JOIN_TOLERANCE`` of
    the clearance of that branch's, interpolated linearly); else None."""
    orbit = new.payload
    if not isinstance(orbit, PeriodicOrbit):
        return None
    p = new.point.parameter
    for i, (b, pts) in enumerate(zip(branches, solved, strict=True)):
        if b.period != period or len(pts) < 2:
            continue
        ps = b.parameter
        order = np.argsort(ps)
        if not ps[order[0]] < p < ps[order[-1]]:
            continue
        j = int(np.searchsorted(ps[order], p))
        a, c = pts[order[j - 1]], pts[order[j]]
        ea, ec = (getattr(x.payload, "section_eccentricity", None) for x in (a, c))
        if ea is None or ec is None or ea.shape != orbit.section_eccentricity.shape:
            continue
        pa, pc = a.point.parameter, c.point.parameter
        theta = (p - pa) / (pc - pa) if pc != pa else 0.0
        there = (1.0 - theta) * ea + theta * ec
        gap = float(np.max(np.abs(orbit.section_eccentricity - there))) / orbit.clearance
        if gap <= JOIN_TOLERANCE:
            return f"joins branch {i} at {p:.6g}"
    return None


def _targets(values: Sequence[float] | None, span: tuple[float, float] | None) -> list[float]:
    if (values is None) == (span is None):
        raise ValueError("pass exactly one of values= (a list of values) and span=(start, stop).")
    if span is not None:
        seq = list(span)
        if len(seq) != 2:
            raise ValueError(f"span must be (start, stop); got {span!r}.")
    else:
        seq = list(values)  # type: ignore[arg-type]
    try:
        out = [float(v) for v in seq]
    except (TypeError, ValueError):
        raise ValueError(f"values must be numbers; got {seq!r}.") from None
    if len(out) < 2 or not all(math.isfinite(v) for v in out):
        raise ValueError(f"values must be at least two finite numbers; got {seq!r}.")
    steps = np.diff(out)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        raise ValueError(f"values must be strictly increasing or decreasing; got {seq!r}.")
    return out


def _key_units(scene: Scene, key: str) -> str:
    """Units of a dotted scene key from the scene's annotations (``"unknown"`` if none)."""
    units = "unknown"
    with contextlib.suppress(Exception):
        *path, last = key.split(".")
        obj: Any = scene
        for part in path:
            obj = obj[part] if isinstance(obj, Mapping) else getattr(obj, part)
        hints = typing.get_type_hints(type(obj), include_extras=True)
        for meta in getattr(hints[last], "__metadata__", ()):
            if type(meta).__name__ == "Unit":
                units = meta.symbol or "unknown"
    if units == "unknown" and key.endswith("_rpm"):
        units = "rpm"
    return units


class _SceneCorrector:
    """Shooting at a fixed value of the scene key, from a (predicted) orbit."""

    def __init__(self, scene: Scene, key: str, settings: ContinuationSettings) -> None:
        self.scene = scene
        self.key = key
        self.settings = settings
        self.period = 1
        self.solves = 0
        #: chord iterations run and the map runs they cost, summed over the points
        self.chord_iterations = 0
        self.chord_runs = 0

    def chord(self, scene: Scene, base: PeriodicOrbit, state: np.ndarray) -> np.ndarray | None:
        """The predicted section state corrected by chord iterations: Newton steps with
        the previous orbit's monodromy matrix as the Jacobian (no tangent runs), on the
        map's own adaptive steps, while each cuts the residual by ``CHORD_RATE`` and it is
        above ``REFREEZE_ABOVE`` (below it the shooting freezes the steps). Worth it only
        where the map does not contract by itself (``|mu_max|`` of the previous orbit above
        the shooting's ``CONTRACTION``); None when no iteration helped."""
        jac = np.asarray(base.monodromy, dtype=np.float64)
        mu = base.multipliers
        if jac.size == 0 or not mu.size or float(np.abs(mu[0])) <= CONTRACTION:
            return None
        smap = _map_of(scene, self.period)
        latch, contact = section_latch(smap.model, state, base.section_latch)
        sec = Section(y=state, latch=latch, contact=contact)
        end = smap.run(sec, smap.stops)
        self.chord_runs += 1
        if not end.stats.success:
            return None
        rho = first = smap.residual(sec, end, sec.contact != 0)
        for _ in range(CHORD_ITERATIONS):
            if rho <= REFREEZE_ABOVE:
                break
            basis = smap.basis(sec)
            latches = np.flatnonzero(sec.contact != 0)
            n_free = basis.shape[1]
            if jac.shape[0] != n_free + latches.size:
                break  # other latches than the previous orbit's: its matrix does not fit
            keep = np.setdiff1d(np.arange(jac.shape[0]), n_free + frozen_latches(jac, n_free))
            r = smap.reduced_residual(sec, end, basis, latches)
            dz = np.zeros_like(r)
            dz[keep] = newton_step(jac[np.ix_(keep, keep)], r[keep])
            trial = smap.corrected(sec, basis, latches, dz)
            tend = smap.run(trial, smap.stops)
            self.chord_runs += 1
            if not tend.stats.success:
                break
            trho = smap.residual(trial, tend, trial.contact != 0)
            if not trho < CHORD_RATE * rho:
                break
            sec, end, rho = trial, tend, trho
            self.chord_iterations += 1
        _LOG.info("chord: residual %.3g -> %.3g", first, rho)
        return sec.y if rho < first else None

    def wrap(self, orbit: PeriodicOrbit, parameter: float) -> Solved:
        point = ContinuationPoint(
            parameter=float(parameter), state=orbit.section_state.copy(),
            multipliers=np.asarray(orbit.multipliers, dtype=np.complex128),
            stable=orbit.stable, residual=float(orbit.residual),
            signature=contact_signature(orbit),
            eccentricity=np.linalg.norm(orbit.section_eccentricity, axis=-1),
            margin=grazing_margin(orbit, damping_coefficients(self.scene, orbit.joint_names)),
        )  # fmt: skip
        return Solved(point=point, iterations=orbit.iterations, payload=orbit)

    def at(self, parameter: float, guess: Solved) -> Solved | None:
        scene = self.scene.replace({self.key: parameter})
        base: PeriodicOrbit = guess.payload
        try:
            # the predicted state, moved onto this value's constraint manifold (a drive
            # speed changes the prescribed velocities)
            state = project_state(assemble(scene), guess.point.state, t=0.0)
            corrected = self.chord(scene, base, state)
            start = replace(base, section_state=state if corrected is None else corrected)
            self.solves += 1
            orbit = periodic_orbit(
                scene, period=self.period, guess=start,
                max_iterations=self.settings.max_iterations, segments=self.settings.segments,
                **({} if self.settings.shooting_tolerance is None
                   else {"tol": self.settings.shooting_tolerance}),
            )  # fmt: skip
        except (SimulationError, ValueError, np.linalg.LinAlgError):
            return None
        _LOG.info(
            "%s = %.6g, period %d: residual %.3g after %d iterations, |mu_max| %.4g",
            self.key, parameter, self.period, orbit.residual, orbit.iterations,
            float(np.abs(orbit.multipliers[0])) if orbit.multipliers.size else 0.0,
        )  # fmt: skip
        if not orbit.converged:
            return None
        if self.period > 1 and _collapsed(orbit):
            return None
        return self.wrap(orbit, parameter)

    def reseed(self, last: float, stop: float) -> Solved | None:
        """A period-1 orbit from a settled run of the scene, every ``max_step`` past
        ``last`` until one converges (None if none does before ``stop``)."""
        direction = 1.0 if stop >= last else -1.0
        p = last + direction * self.settings.max_step
        while direction * (stop - p) >= 0:
            fresh = self.settled(p)
            if fresh is not None:
                return fresh
            p += direction * self.settings.max_step
        return None

    def settled(self, p: float) -> Solved | None:
        """The period-1 orbit at ``p`` from a run of the scene settled for
        ``SWITCH_SETTLE`` periods (None when shooting does not converge)."""
        try:
            self.solves += 1
            orbit = periodic_orbit(
                self.scene.replace({self.key: p}), settle=SWITCH_SETTLE,
                max_iterations=max(self.settings.max_iterations, 12),
                segments=self.settings.segments,
                **({} if self.settings.shooting_tolerance is None
                   else {"tol": self.settings.shooting_tolerance}),
            )  # fmt: skip
        except (SimulationError, ValueError, np.linalg.LinAlgError):
            orbit = None
        ok = orbit is not None and orbit.converged
        _LOG.info("%s = %.6g, settled start: %s", self.key, p, "orbit" if ok else "none")
        if orbit is None or not ok:
            return None
        self.period = 1
        return self.wrap(orbit, p)

    def doubled(
        self, bif: BifurcationPoint, stop: float, near: PeriodicOrbit | None
    ) -> Solved | None:
        """A doubled orbit one step past a period doubling: from the orbit ``near`` it
        displaced along the Floquet vector of the multiplier nearest −1, else from a
        settled run of the scene."""
        step = self.settings.step
        direction = 1.0 if stop >= bif.parameter else -1.0
        k = 2 * self.period
        for side in (direction, -direction):
            p = bif.parameter + side * step
            scene = self.scene.replace({self.key: p})
            for guess in _doubling_guesses(near):
                try:
                    self.solves += 1
                    if guess is None:
                        orbit = periodic_orbit(scene, period=k, settle=SWITCH_SETTLE)
                    else:
                        state = project_state(assemble(scene), guess.section_state, t=0.0)
                        orbit = periodic_orbit(
                            scene, period=k, guess=replace(guess, section_state=state)
                        )
                except (SimulationError, ValueError, np.linalg.LinAlgError):
                    continue
                if orbit.converged and not _collapsed(orbit):
                    return self.wrap(orbit, p)
        return None


def _map_of(scene: Scene, period: int) -> StroboscopicMap:
    """The k-fold stroboscopic map of a rigid scene with the defaults of
    :func:`mechanism.periodic_orbit` (tolerances, steps, perturbation)."""
    model = assemble(scene)
    big_t = drive_period(scene)
    max_step, floor = step_limits(model, Dopri5(), default_step(scene, big_t))
    q0, v0 = initial_state(model)
    return StroboscopicMap(
        model, drive_period=big_t, period=period, rtol=DEFAULT_TOLERANCE,
        atol=DEFAULT_TOLERANCE, max_step=max_step, approach_floor=floor,
        perturbation=DEFAULT_PERTURBATION,
        clearance=length_scale(model, np.concatenate([q0, v0])),
    )  # fmt: skip


def _doubling_guesses(near: PeriodicOrbit | None) -> list[PeriodicOrbit | None]:
    """Orbits displaced by ±h along the Floquet vector of the multiplier nearest −1
    (h = 1 % and 5 % of the clearance), then ``None`` (settle a run instead)."""
    out: list[PeriodicOrbit | None] = []
    vectors = getattr(near, "floquet_vectors", None)
    if near is not None and vectors is not None and vectors.shape[1] == near.multipliers.size:
        i = int(np.argmin(np.abs(near.multipliers + 1.0)))
        v = np.real(vectors[:, i])
        for h in (0.01, 0.05):
            for sign in (1.0, -1.0):
                out.append(
                    replace(near, section_state=near.section_state + sign * h * near.clearance * v)
                )
    out.append(None)
    return out


def _collapsed(orbit: PeriodicOrbit) -> bool:
    """A k-periodic orbit whose section states coincide: the orbit of half the period."""
    e = orbit.section_eccentricity
    gap = float(np.max(np.linalg.norm(e[1:] - e[:1], axis=-1))) if e.shape[0] > 1 else 0.0
    return gap <= 1e-6 * orbit.clearance


def _eccentricities(pts: list[tuple[int, int, ContinuationPoint]]) -> np.ndarray:
    """(points, largest k, joints) |e| at the section times, NaN past a point's k."""
    k = max([p.eccentricity.shape[0] for _, _, p in pts] + [1])
    joints = max([p.eccentricity.shape[1] for _, _, p in pts if p.eccentricity.ndim == 2]
                 + [1])  # fmt: skip
    out = np.full((len(pts), k, joints), np.nan)
    for i, (_, _, p) in enumerate(pts):
        e = p.eccentricity
        out[i, : e.shape[0], : e.shape[1]] = e
    return out


def _dataset(c: Continuation) -> xr.Dataset:
    pts = [(i, b.period, p) for i, b in enumerate(c.branches) for p in b.points]
    n_mu = max([p.multipliers.size for _, _, p in pts] + [1])
    n_state = max([p.state.size for _, _, p in pts] + [1])

    def padded(arrays: list[np.ndarray], width: int, dtype: Any) -> np.ndarray:
        out = np.full((len(arrays), width), np.nan, dtype=dtype)
        for i, a in enumerate(arrays):
            out[i, : a.size] = a
        return out

    mu = padded([p.multipliers for _, _, p in pts], n_mu, np.complex128)
    bifs = c.bifurcations
    b_mu = max([b.multipliers_before.size for b in bifs] + [b.multipliers_after.size
               for b in bifs] + [1])  # fmt: skip
    before = padded([b.multipliers_before for b in bifs], b_mu, np.complex128)
    after = padded([b.multipliers_after for b in bifs], b_mu, np.complex128)
    units = c.units
    data = {
        "parameter": (("point",), np.array([p.parameter for _, _, p in pts]), {
            "units": units, "long_name": f"scene key {c.parameter}"}),
        "branch": (("point",), np.array([i for i, _, _ in pts], dtype=np.int64), {
            "units": "1", "long_name": "index of the branch"}),
        "period": (("point",), np.array([k for _, k, _ in pts], dtype=np.int64), {
            "units": "1", "long_name": "drive periods per orbit period"}),
        "stable": (("point",), np.array([p.stable for _, _, p in pts], dtype=np.int8), {
            "units": "1", "long_name": "every non-neutral multiplier inside the unit circle"}),
        "residual": (("point",), np.array([p.residual for _, _, p in pts]), {
            "units": "1", "long_name": "shooting residual over the clearance"}),
        "section_state": (("point", "state"), padded([p.state for _, _, p in pts], n_state,
                                                      np.float64), {
            "units": "SI (m, rad, m s-1, rad s-1)",
            "long_name": "section state [q; dq/dt] of the orbit"}),
        "multiplier_real": (("point", "multiplier"), mu.real, {
            "units": "1", "long_name": "Floquet multiplier (non-neutral), real part"}),
        "multiplier_imag": (("point", "multiplier"), mu.imag, {
            "units": "1", "long_name": "Floquet multiplier (non-neutral), imaginary part"}),
        "multiplier_modulus": (("point", "multiplier"), np.abs(mu), {
            "units": "1", "long_name": "modulus of the Floquet multiplier"}),
        "section_eccentricity": (("point", "section", "joint"), _eccentricities(pts), {
            "units": "m", "long_name": "journal eccentricity |e| at the orbit's section times"}),
        "grazing_margin": (("point",), np.array([p.margin for _, _, p in pts]), {
            "units": "1", "long_name": "grazing margin of the orbit over the clearance"}),
        "signature": (("point",), np.array([" | ".join(p.signature) for _, _, p in pts],
                                           dtype=object), {
            "units": "1", "long_name": "contact-mode signature of the orbit"}),
        "bifurcation_parameter": (("bifurcation",), np.array([b.parameter for b in bifs]), {
            "units": units, "long_name": "located value of the bifurcation"}),
        "bifurcation_low": (("bifurcation",), np.array([b.bracket[0] for b in bifs]), {
            "units": units, "long_name": "lower end of the bifurcation's last bracket"}),
        "bifurcation_high": (("bifurcation",), np.array([b.bracket[1] for b in bifs]), {
            "units": units, "long_name": "upper end of the bifurcation's last bracket"}),
        "bifurcation_kind": (("bifurcation",), np.array([b.kind for b in bifs], dtype=object), {
            "units": "1",
            "long_name": "period-doubling, fold, neimark-sacker, grazing or end (unnamed)"}),
        "bifurcation_branch_end": (("bifurcation",), np.array([b.branch_end for b in bifs],
                                                              dtype=np.int8), {
            "units": "1", "long_name": "the branch ends there (nothing converged past it)"}),
        "bifurcation_branch": (("bifurcation",), np.array([b.branch for b in bifs],
                                                          dtype=np.int64), {
            "units": "1", "long_name": "index of the branch it lies on"}),
        "bifurcation_explanation": (("bifurcation",), np.array(
            [b.explanation for b in bifs], dtype=object), {
            "units": "1", "long_name": "what happens at the bifurcation"}),
        "modulus_before": (("bifurcation", "multiplier_side"), np.abs(before), {
            "units": "1", "long_name": "multiplier moduli on the side followed from"}),
        "modulus_after": (("bifurcation", "multiplier_side"), np.abs(after), {
            "units": "1", "long_name": "multiplier moduli on the side followed to"}),
    }  # fmt: skip
    attrs = {
        "scene_name": c.scene_name,
        "continuation_parameter": c.parameter,
        "parameter_units": units,
        "orbit_solves": c.orbit_solves,
        "cpu_time": c.cpu_time,
        "cpu_time_units": "s",
        "locate_tolerance": c.settings.locate_tolerance,
    }
    return xr.Dataset(data, attrs=attrs)
