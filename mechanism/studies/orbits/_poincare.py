"""The Poincaré section on the crank angle of a motor-driven (autonomous) rigid scene.

A motor-driven crank has no prescribed period: the section is the crank angle returning
to its start value plus 2πk, and the return time is an unknown the map gives back. The
map's Jacobian is the monodromy matrix over the return time corrected for the moving
return (the saltation along the flow, δx⁺ = (I − f ∇gᵀ/(∇g·f)) Φ δx for the section
g = φ − φ₀), on the section's own tangent coordinates (the constraint manifold's with
δφ = 0), so the trivial multiplier 1 along the flow is not among the unknowns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from mechanism.core import SimulationError
from mechanism.core.integrate import (
    TangentIntegration,
    deviation_size,
    integrate_tangent,
    section_latch,
    state_derivative,
    tangent_basis,
)
from mechanism.core.model import Model
from mechanism.core.scene import MotorDrive

from ._newton import NewtonState, image_section, newton
from ._shooting import Section, StroboscopicMap

#: grid points per expected return of the adaptive map's first run (the bracket of the
#: crossing, refined by Newton on the return time from the grid point before it)
_GRID = 32
#: the adaptive search for the crossing extends its horizon at most this many times
_EXTENSIONS = 40
#: horizon of the first run (and of a frozen step schedule) over the expected return time
_HORIZON = 1.3
#: crossing located when the crank angle is this close to its target (rad, relative)
_ANGLE_TOL = 1e-14
#: the statement a crank-angle section orbit carries
SECTION_STATEMENT = (
    "Poincaré section on the crank angle (motor drive): the state each time the crank "
    "angle has turned 2πk from its value at the section; the period (drive_period × k, "
    "s) is an unknown found with the orbit; the monodromy is corrected for the return "
    "time (saltation along the flow), and the trivial multiplier 1 along the flow is not "
    "among the multipliers."
)

#: what the crank-angle section does not do
MOTOR_SECTION_LIMITS = (
    "periodic_orbit on a motor-driven scene shoots on the crank-angle section with single "
    "shooting from a settled run: search must be 0 and segments None or 1."
)


def no_load_turn(scene) -> float:
    """The time (s) of one crank turn at the motor's no-load speed (the scale of the
    default steps; 1 s when the motor has none)."""
    speed = scene.drive.no_load_speed
    if speed <= 0.0:
        speed = abs(scene.drive.initial_speed_rpm) * math.pi / 30.0
    return 2.0 * math.pi / speed if speed > 0.0 else 1.0


def crank_row(model: Model) -> np.ndarray:
    """Row r with r · q = the motor joint's relative angle (rad) plus a constant."""
    drive = model.scene.drive
    if not isinstance(drive, MotorDrive):
        raise ValueError("the crank-angle section needs a motor drive.")
    first, second = model.scene.joints[drive.joint].bodies
    row = np.zeros(model.n_dof)
    names = list(model.dof_names)
    for body, sign in ((second, 1.0), (first, -1.0)):
        name = f"{body}.theta"
        if name in names:  # the ground has no coordinates
            row[names.index(name)] += sign
    if not np.any(row):
        raise ValueError(f"the motor joint {drive.joint!r} turns no rigid body.")
    return row


@dataclass(frozen=True)
class Crossing:
    """The end of one map evaluation: the run (its final state the crossing state) and
    the steps it took (a schedule ending at the crossing, or None when adaptive)."""

    run: TangentIntegration
    time: float
    schedule: np.ndarray | None


class CrankSection(StroboscopicMap):
    """The k-turn return map of the crank angle of a motor-driven rigid model.

    Quacks like :class:`StroboscopicMap` for the Newton iteration: :meth:`run` without a
    deviation evaluates the map (to the crossing), :meth:`basis` is the section's tangent
    basis (δφ = 0), :meth:`monodromy` the section map's Jacobian. ``drive_period`` is
    the return time per crank turn of the last evaluation (``tau``, the velocities'
    scale, stays at its first value)."""

    def __init__(self, model: Model, *, return_time: float, **kw) -> None:
        super().__init__(model, drive_period=return_time / kw["period"], **kw)
        self.row = crank_row(model)
        self.return_time = return_time
        self.base: np.ndarray | None = None
        self.direction = 1.0

    @property
    def stops(self) -> np.ndarray:
        return np.array([0.0, self.return_time])

    @property
    def sections(self) -> np.ndarray:
        return self.drive_period * np.arange(self.period + 1, dtype=np.float64)

    def angle(self, y: np.ndarray) -> float:
        return float(self.row @ y[: self.model.n_dof])

    def rate(self, y: np.ndarray) -> float:
        return float(self.row @ y[self.model.n_dof :])

    # -- integration -------------------------------------------------------------
    def _plain(
        self,
        y: np.ndarray,
        latch: tuple[np.ndarray, np.ndarray],
        stops: np.ndarray,
        schedule: np.ndarray | None,
        *,
        record: bool = True,
        steps: bool = False,
        d0: np.ndarray | None = None,
        settings=None,
    ) -> TangentIntegration:
        run = integrate_tangent(
            self.model, y, np.zeros_like(y) if d0 is None else d0, stops,
            settings=self.settings if settings is None else settings, latch=latch,
            step_schedule=schedule, record_states=record, record_steps=steps,
        )  # fmt: skip
        self.evaluations += 1
        self.function_evaluations += run.stats.function_evaluations
        if not run.stats.success:
            raise SimulationError(
                f"periodic orbit: the integration failed after t = {run.t[-1]:.6g} s: "
                f"{run.stats.message}"
            )
        return run

    def cross(self, section: Section) -> Crossing:
        """Integrate from ``section`` until the crank angle has turned 2πk (k = ``period``)
        in the sense it turns at the start; the crossing is located by Newton on the
        time from the last step (or grid point) before it."""
        y0 = section.y
        self.direction = 1.0 if self.rate(y0) >= 0.0 else -1.0
        target = self.angle(y0) + self.direction * 2.0 * math.pi * self.period
        latch = (section.latch, section.contact)
        t0, events, evals = 0.0, 0, 0
        frozen = self.base is not None
        for _ in range(_EXTENSIONS):
            if frozen:
                stops = self.base
                run = self._plain(y0, latch, stops, self.base)
            else:
                stops = t0 + np.linspace(0.0, _HORIZON * self.return_time, _GRID + 1)
                run = self._plain(y0, latch, stops, None)
            evals += run.stats.function_evaluations
            phi = self.direction * (run.states[:, : self.model.n_dof] @ self.row - target)
            past = np.flatnonzero(phi >= 0.0)
            if past.size and past[0] > 0:
                i = int(past[0]) - 1
                break
            if frozen:  # the schedule ends short of the crossing: search adaptively
                frozen = False
            events += int(run.contact_events[-1])
            y0, t0 = run.final_state, float(run.t[-1])
            latch = (run.final_latch, run.final_contact)
        else:
            raise SimulationError(
                f"periodic orbit: the crank did not turn {self.period} time(s) within "
                f"{t0:.6g} s; the motor cannot drive the load."
            )
        ta, ya = float(run.t[i]), run.states[i]
        la = (run.latches[i], run.contact[i])
        events += int(run.contact_events[i])
        dt = (run.t[i + 1] - ta) * (-phi[i]) / (phi[i + 1] - phi[i])
        for _ in range(8):
            stops = np.array([ta, ta + dt])
            last = self._plain(ya, la, stops, stops if frozen else None, record=False)
            gap = target - self.angle(last.final_state)
            rate = self.rate(last.final_state)
            dt += gap / rate
            if abs(gap) <= _ANGLE_TOL * max(1.0, abs(target)):
                break
        time = float(last.t[-1])
        stats = replace(last.stats, contact_events=events + last.stats.contact_events,
                        function_evaluations=evals + last.stats.function_evaluations)  # fmt: skip
        schedule = None
        if frozen:
            schedule = np.concatenate([self.base[self.base < time], [time]])
        self.return_time = time
        self.drive_period = time / self.period
        return Crossing(run=replace(last, stats=stats, t=np.array([0.0, time])), time=time,
                        schedule=schedule)  # fmt: skip

    def run(
        self,
        section: Section,
        stops: np.ndarray,
        *,
        d0: np.ndarray | None = None,
        latch_deviation: np.ndarray | None = None,
        record: bool = False,
        tangent: bool = False,
        difference: str | None = None,
    ) -> TangentIntegration:
        """Without a deviation or recording: the map (to the crossing, whatever
        ``stops``); else an integration over ``stops`` as the stroboscopic map's."""
        if d0 is None and not record and not tangent:
            return self.cross(section).run
        return super().run(
            section, stops, d0=d0, latch_deviation=latch_deviation, record=record,
            tangent=tangent, difference=difference,
        )  # fmt: skip

    def freeze_steps(self, section: Section, basis: np.ndarray) -> None:
        """Freeze the steps of an adaptive run from ``section`` past its crossing (with a
        deviation along all the section's tangent directions under its own error
        control); :attr:`schedule` becomes those up to the crossing."""
        self.base = self.schedule = None
        crossing = self.cross(section)
        d0 = basis.sum(axis=1)
        d0 *= self.size / deviation_size(self.model, d0, time_scale=self.tau)
        settings = replace(self.settings, deviation_rtol=self.deviation_rtol)
        horizon = np.array([0.0, _HORIZON * crossing.time])
        run = self._plain(section.y, (section.latch, section.contact), horizon, None,
                          record=False, steps=True, d0=d0, settings=settings)  # fmt: skip
        self.base = run.step_times
        self.settle_on(section)

    def settle_on(self, section: Section) -> Crossing:
        """Evaluate the map at ``section`` and make :attr:`schedule` its steps (None while
        the steps are adaptive), so a recorded run over it ends at the crossing."""
        crossing = self.cross(section)
        self.schedule = crossing.schedule
        return crossing

    # -- tangent space -----------------------------------------------------------
    def basis(self, section: Section) -> np.ndarray:
        """Orthonormal basis (scaled norm) of the section's tangent space: the constraint
        manifold's directions that keep the crank angle (2f − 1 columns)."""
        full = tangent_basis(self.model, section.y, t=0.0, time_scale=self.tau)
        return full @ _null_of(self._dphi(full))

    def _dphi(self, vectors: np.ndarray) -> np.ndarray:
        return self.row @ vectors[: self.model.n_dof]

    def monodromy(self, section: Section, basis: np.ndarray, latches: np.ndarray) -> np.ndarray:
        """Jacobian of the section map in the section's tangent coordinates (then τ ×
        latch of the joints ``latches``): the tangent deviations over the return time,
        corrected by the saltation along the flow at the crossing; a latch that the
        reference never renews is frozen (unit row and column)."""
        crossing = self.settle_on(section)
        n_free = basis.shape[1]
        columns = np.concatenate([basis, np.repeat(basis[:, :1], latches.size, axis=1)], axis=1)
        latch = np.concatenate([np.full(n_free, -1), latches]).astype(np.int64)
        states, lat, run = self.carry(section, np.array([0.0, crossing.time]), columns, latch)
        f = state_derivative(self.model, run.final_state, t=crossing.time, latch=run.final_latch)
        # saltation along the flow: the deviation moved back onto the section φ = φ₀
        states -= np.outer(f, self._dphi(states) / (f[: self.model.n_dof] @ self.row))
        out = self.project_images(states, lat, basis, latches)
        jac = np.eye(n_free + latches.size)
        jac[:, :n_free] = out[:, :n_free]
        for pos, j in enumerate(latches):
            if run.stats.contact_events == 0 and run.final_contact[j] != 0:
                continue
            jac[:, n_free + pos] = out[:, n_free + pos] - out[:, 0]
        return jac

    def segmented(self, section: Section, segments: int, recorded=None) -> np.ndarray:
        """The section map's Jacobian without latches (all frozen) as the product of the
        Jacobians of ``segments`` pieces of the frozen steps up to the crossing, each in
        the manifold's tangent bases at its ends, the saltation applied to the last: a
        strongly contracting orbit's monodromy over one whole return is nearly of rank 1
        and loses its smaller directions to round-off (as for a prescribed drive)."""
        crossing = self.settle_on(section)
        if self.schedule is None:
            return self.monodromy(section, self.basis(section), np.zeros(0, dtype=np.int64))
        last = self.schedule.size - 1
        cut = np.unique(np.round(np.linspace(0, last, segments + 1)).astype(int))
        ref = super().run(section, self.schedule[cut], record=True)
        if not ref.stats.success:
            raise SimulationError(f"the integration failed: {ref.stats.message}")
        none = np.zeros(0, dtype=np.int64)
        columns = self.basis(section)
        product: np.ndarray | None = None
        for j in range(cut.size - 1):
            start = Section(y=ref.states[j], latch=ref.latches[j], contact=ref.contact[j])
            states, lat, run = self.carry(
                start, ref.t[j : j + 2], columns, np.full(columns.shape[1], -1)
            )
            if j == cut.size - 2:
                f = state_derivative(
                    self.model, run.final_state, t=crossing.time, latch=run.final_latch
                )
                states -= np.outer(f, self._dphi(states) / (f[: self.model.n_dof] @ self.row))
                ends = self.basis(section)
            else:
                ends = tangent_basis(
                    self.model, ref.states[j + 1], t=float(ref.t[j + 1]), time_scale=self.tau
                )
            piece = self.project_images(states, lat, ends, none)
            product = piece if product is None else piece @ product
            columns = ends
        assert product is not None
        return product


def _null_of(row: np.ndarray) -> np.ndarray:
    """Orthonormal basis of the vectors orthogonal to ``row``."""
    _, _, vt = np.linalg.svd(row[None, :])
    return vt[1:].T


def settle_turns(smap: CrankSection, start: Section, turns: int) -> Section:
    """The section state after ``turns`` returns of the map from ``start``."""
    sec = start
    for _ in range(turns):
        sec = image_section(smap, smap.cross(sec).run)
    return sec


def crank_section_orbit(
    model: Model,
    start: Section,
    *,
    turns: int,
    settle: int,
    tol: float,
    max_iterations: int,
    map_settings: dict,
) -> tuple[CrankSection, NewtonState]:
    """Newton shooting on the crank-angle section map of a motor-driven model from
    ``start`` (after ``settle`` returns); returns the map (its :attr:`schedule` the
    orbit's steps) and the solved state."""
    drive = model.scene.drive
    speed = abs(smap_speed(start.y, model))
    if speed <= 0.0:
        speed = drive.no_load_speed if drive.no_load_speed > 0.0 else 2.0 * math.pi
    first = CrankSection(model, return_time=2.0 * math.pi * turns / speed, period=turns,
                         **map_settings)  # fmt: skip
    sec = settle_turns(first, start, settle)
    # the velocities' scale from the settled return time
    smap = CrankSection(model, return_time=first.return_time, period=turns, **map_settings)
    smap.function_evaluations += first.function_evaluations
    solved = newton(smap, sec, tol, max_iterations)
    smap.settle_on(solved.section)
    if solved.jacobian_at is not solved.section:
        # the multipliers at the orbit's own state: the shooting's matrix may be from up
        # to 1e-5 of the length scale away, which moves them at the 1e-5 level
        solved.jacobian = None
    return smap, solved


def smap_speed(y: np.ndarray, model: Model) -> float:
    """The motor joint's relative rate (rad/s) in the state ``y``."""
    return float(crank_row(model) @ y[model.n_dof :])


def section_start(model: Model, y: np.ndarray, latch: np.ndarray | None = None) -> Section:
    """A section state from a state [q; q̇] (the latch of joints in contact held)."""
    held, contact = section_latch(model, y, latch)
    return Section(y=np.asarray(y, dtype=np.float64).copy(), latch=held, contact=contact)
