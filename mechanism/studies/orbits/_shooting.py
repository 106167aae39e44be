"""Shooting on the stroboscopic map of a rigid scene: the map, its monodromy matrix and
the pure numerics of the Newton iteration.

The map takes the section state (a state [q; q̇] on the constraint manifold at a time
t ≡ 0 modulo the drive period T, with the latched impact velocities of the clearance
joints in contact) to the state k periods later. It is evaluated by
:func:`mechanism.core.integrate.integrate_tangent` with a zero deviation (the reference
alone); its Jacobian, in coordinates of the manifold's tangent space, by the same
function with a block of deviations, one per direction, carried in lock-step on one
reference run, so the tangent rules at contact entry and exit, on the friction ramp and
for the latch are those of :func:`mechanism.lyapunov_exponent`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from mechanism.core import SimulationError
from mechanism.core.integrate import (
    StepSettings,
    TangentIntegration,
    TangentSettings,
    deviation_size,
    integrate_tangent,
    project_state,
    section_latch,
    tangent_basis,
)
from mechanism.core.model import Model

#: no renormalisation inside a period: the deviation's growth is read at the stops
_NO_RENORMALIZATION = 2**62
#: a latch row of the monodromy matrix that differs from a unit row by less than this is
#: frozen (the contact lasts the whole period): only round-off of the growth read back
_FROZEN = 1e-9
#: deviations per tangent run of a Jacobian: None, all its columns in one block on one
#: reference run; 1, one run per column (the same numbers on a frozen step schedule, at
#: the cost of a reference run per column; kept for comparison)
COLUMNS_PER_RUN: int | None = None
#: how the Jacobian's tangent runs difference their deviations' rates
#: (:class:`mechanism.core.integrate.TangentSettings` ``difference``): the split
#: difference; the directional one (the exponent's default, a third of the cost) moved
#: the 30 rpm orbit's largest multiplier by 2.4 % and its reproduction from a start moved
#: by 1e-12 by 6 %, twice the 3 % of the split one (docs/periodic-orbits.md, Cost)
DIFFERENCE = "split"


@dataclass(frozen=True)
class Section:
    """A section state: [q; q̇] at t = 0 and the latch of the clearance joints."""

    y: np.ndarray
    latch: np.ndarray
    contact: np.ndarray


def angle_rows(dof_names: tuple[str, ...]) -> np.ndarray:
    """Boolean mask of the position rows of [q; q̇] that are angles (rad)."""
    n = len(dof_names)
    mask = np.zeros(2 * n, dtype=bool)
    mask[:n] = [name.endswith(".theta") for name in dof_names]
    return mask


def wrapped_difference(a: np.ndarray, b: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """a − b with the angle rows brought to (−π, π] (a crank turns 2π per period)."""
    diff = np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)
    diff[angles] -= 2.0 * math.pi * np.round(diff[angles] / (2.0 * math.pi))
    return diff


def newton_step(jacobian: np.ndarray, residual: np.ndarray) -> np.ndarray:
    """Solve (J − I) dz = −r for the correction of the section coordinates (least squares,
    so a (near-)singular J − I still gives the smallest correction)."""
    a = jacobian - np.eye(jacobian.shape[0])
    dz, *_ = np.linalg.lstsq(a, -residual, rcond=1e-13)
    return dz


def sorted_by_modulus(values: np.ndarray) -> np.ndarray:
    """Complex values, largest modulus first."""
    values = np.asarray(values, dtype=np.complex128)
    return values[np.argsort(-np.abs(values), kind="stable")]


class StroboscopicMap:
    """The k-fold stroboscopic map of a rigid model and its tangent-space Jacobian."""

    def __init__(
        self,
        model: Model,
        *,
        drive_period: float,
        period: int,
        rtol: float,
        atol: float,
        max_step: float,
        approach_floor: float,
        perturbation: float,
        clearance: float,
        deviation_rtol: float = 1e-4,
    ) -> None:
        self.model = model
        self.drive_period = drive_period
        self.period = period
        self.tau = drive_period / (2.0 * math.pi)
        self.clearance = clearance
        self.size = perturbation * clearance
        self.deviation_rtol = deviation_rtol
        self.angles = angle_rows(model.dof_names)
        steps = StepSettings(rtol=rtol, atol=atol, max_step=max_step, approach_floor=approach_floor)
        self.settings = TangentSettings(
            steps=steps, time_scale=self.tau, renormalize_every=_NO_RENORMALIZATION
        )
        self.evaluations = 0
        self.function_evaluations = 0
        self.schedule: np.ndarray | None = None
        #: record map evaluations on the frozen steps at every step (set by the Newton
        #: iteration near its round-off floor, where a trial is likely the orbit)
        self.record_images = False
        #: (section, schedule, run) of the last map evaluation recorded so
        self.last_image: tuple[Section, np.ndarray, TangentIntegration] | None = None

    @property
    def sections(self) -> np.ndarray:
        """Section times 0, T, …, kT (the map lands on each)."""
        return self.drive_period * np.arange(self.period + 1, dtype=np.float64)

    @property
    def stops(self) -> np.ndarray:
        """Stops of a map evaluation: the section times."""
        return self.sections

    def freeze_steps(self, section: Section, basis: np.ndarray) -> None:
        """Take the accepted steps of a run from ``section`` as the fixed step schedule of
        every later evaluation: the map is then a smooth function of the section state,
        which Newton needs below the tolerance's level (adaptive steps chosen anew make it
        jump by about rtol × the coordinates). The run carries a deviation along all the
        tangent directions with its own error control, so the steps resolve the
        linearised flow as well as the reference."""
        self.schedule = None
        d0 = self.freeze_direction(basis)
        settings = replace(self.settings, deviation_rtol=self.deviation_rtol)
        run = integrate_tangent(
            self.model, section.y, d0, self.sections, settings=settings,
            latch=(section.latch, section.contact), record_steps=True,
        )  # fmt: skip
        self.evaluations += 1
        self.function_evaluations += run.stats.function_evaluations
        if not run.stats.success:
            raise SimulationError(f"the integration failed: {run.stats.message}")
        self.schedule = run.step_times

    def freeze_direction(self, basis: np.ndarray) -> np.ndarray:
        """The deviation whose error control sets the frozen steps: the sum of the tangent
        basis's columns, each turned so that its largest component (in the scaled norm)
        is positive, at the perturbation's size.

        The basis is orthonormal up to the sign of each column, which the factorization
        may flip between two nearby states; unturned, the sum (and with it the steps and
        the multipliers computed on them, by a few per cent) would jump with it."""
        n = basis.shape[0] // 2
        scale = np.concatenate([np.ones(n), np.full(n, self.tau)])
        scaled = basis * scale[:, None]
        big = scaled[np.argmax(np.abs(scaled), axis=0), np.arange(basis.shape[1])]
        d0 = basis @ np.where(big < 0.0, -1.0, 1.0)
        return d0 * (self.size / deviation_size(self.model, d0, time_scale=self.tau))

    def freeze_pieces(
        self, starts: list[Section], times: np.ndarray, bases: list[np.ndarray]
    ) -> None:
        """As :meth:`freeze_steps`, piece by piece for multiple shooting: the steps of a
        run from ``starts[i]`` over ``times[i:i + 2]`` (with a deviation along all the
        tangent directions of ``bases[i]``), joined into one schedule."""
        self.schedule = None
        settings = replace(self.settings, deviation_rtol=self.deviation_rtol)
        pieces = []
        for i, (section, basis) in enumerate(zip(starts, bases, strict=True)):
            d0 = self.freeze_direction(basis)
            run = integrate_tangent(
                self.model, section.y, d0, times[i : i + 2], settings=settings,
                latch=(section.latch, section.contact), record_steps=True,
            )  # fmt: skip
            self.evaluations += 1
            self.function_evaluations += run.stats.function_evaluations
            if not run.stats.success:
                raise SimulationError(f"the integration failed: {run.stats.message}")
            pieces.append(run.step_times)
        self.schedule = np.unique(np.concatenate([*pieces, times]))

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
        """Integrate from ``section`` over ``stops`` (with a deviation ``d0``, else the
        reference alone); ``tangent``: the deviation's error also controls the steps;
        ``difference``: how the deviation's rate is differenced (default split)."""
        d = np.zeros_like(section.y) if d0 is None else d0
        settings = self.settings
        if tangent and self.schedule is None:
            settings = replace(settings, deviation_rtol=self.deviation_rtol)
        if difference is not None:
            settings = replace(settings, difference=difference)
        # with ``record_images``, a map evaluation on the frozen steps is recorded at every
        # step (the same bits, about a quarter more CPU): when its start turns out to be
        # the orbit, it is the orbit's record
        whole = (
            self.record_images
            and d0 is None
            and not record
            and self.schedule is not None
            and np.array_equal(stops, self.stops)
        )
        run = integrate_tangent(
            self.model, section.y, d, self.schedule if whole else stops, settings=settings,
            latch=(section.latch, section.contact), latch_deviation=latch_deviation,
            step_schedule=self.schedule, record_states=record or whole,
        )  # fmt: skip
        self.evaluations += 1
        self.function_evaluations += run.stats.function_evaluations
        if whole:
            self.last_image = (section, self.schedule, run)
            keep = np.searchsorted(run.t, stops)
            keep = keep[keep < run.t.size]
            run = replace(run, t=run.t[keep], log_growth=run.log_growth[keep])
        return run

    def recorded_image(self, section: Section) -> TangentIntegration:
        """The map's run from ``section`` recorded at every step of the frozen schedule:
        the last map evaluation's when it started there, else a new run."""
        last = self.last_image
        if (
            last is not None
            and last[0] is section
            and last[1] is self.schedule
            and last[2].stats.success
        ):
            return last[2]
        run = self.run(section, self.schedule, record=True)
        if not run.stats.success:
            raise SimulationError(f"the integration failed: {run.stats.message}")
        return run

    def residual(self, section: Section, end: TangentIntegration, active: np.ndarray) -> float:
        """Size of image − section, relative to the clearance: the mass-weighted norm of
        the state difference (that of the exponent, τ = T/2π) and τ × the difference of
        the latches that are unknowns (``active``)."""
        diff = wrapped_difference(end.final_state, section.y, self.angles)
        size = deviation_size(self.model, diff, time_scale=self.tau)
        dl = self.tau * (end.final_latch - section.latch)[active]
        return math.sqrt(size**2 + float(dl @ dl)) / self.clearance

    def distance(self, a: np.ndarray, b: np.ndarray) -> float:
        """Mass-weighted size of the state difference a − b over the clearance."""
        diff = wrapped_difference(a, b, self.angles)
        return deviation_size(self.model, diff, time_scale=self.tau) / self.clearance

    def coordinates(self, basis: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Coordinates of a state difference ``v`` on an orthonormal tangent basis."""
        n = v.size // 2
        scale2 = np.concatenate([np.ones(n), np.full(n, self.tau**2)])
        return basis.T @ (scale2 * v)

    def basis(self, section: Section) -> np.ndarray:
        """Orthonormal basis of the constraint manifold's tangent space at the section."""
        return tangent_basis(self.model, section.y, t=0.0, time_scale=self.tau)

    def reduced_residual(
        self, section: Section, end: TangentIntegration, basis: np.ndarray, latches: np.ndarray
    ) -> np.ndarray:
        """Image − section in tangent coordinates, then τ × latch differences of the joints
        ``latches``."""
        diff = wrapped_difference(end.final_state, section.y, self.angles)
        dl = self.tau * (end.final_latch - section.latch)[latches]
        return np.concatenate([self.coordinates(basis, diff), dl])

    def carry(
        self,
        section: Section,
        stops: np.ndarray,
        columns: np.ndarray,
        latch: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, TangentIntegration]:
        """Images of tangent vectors over ``stops`` from ``section`` as state and latch
        differences, by a block of deviations on one reference run
        (:data:`COLUMNS_PER_RUN`).

        Column c of ``columns`` (2n, k), scaled to the perturbation's size, starts with a
        unit τ × latch deviation of joint ``latch[c]`` (none for −1), scaled alike. Each
        is carried without rescaling inside the stops (the growth read at the last one
        restores its size); returns the images' state parts (2n, k), their latch parts
        (joints, k; m/s per unit of the column) and the (first) run, whose reference is
        that of a run without deviations on the same steps, bit for bit.
        """
        k = columns.shape[1]
        scales = np.array(
            [self.size / deviation_size(self.model, columns[:, c], time_scale=self.tau)
             for c in range(k)]
        )  # fmt: skip
        d0 = columns * scales
        dl = np.zeros((section.latch.size, k))
        for c in np.flatnonzero(latch >= 0):
            dl[latch[c], c] = scales[c] / self.tau
        width = k if COLUMNS_PER_RUN is None else COLUMNS_PER_RUN
        states = np.empty_like(d0)
        latches = np.empty_like(dl)
        first: TangentIntegration | None = None
        for lo in range(0, k, width):
            part = slice(lo, min(lo + width, k))
            one = part.stop - part.start == 1
            run = self.run(
                section, stops, d0=d0[:, lo] if one else d0[:, part],
                latch_deviation=dl[:, lo] if one else dl[:, part], tangent=True,
                difference=DIFFERENCE,
            )  # fmt: skip
            if not run.stats.success:
                raise SimulationError(f"the tangent run failed: {run.stats.message}")
            first = run if first is None else first
            dev = run.final_deviation.reshape(d0.shape[0], -1)
            dlat = run.final_latch_deviation.reshape(section.latch.size, part.stop - part.start)
            logs = np.atleast_1d(run.log_growth[-1])
            for i, c in enumerate(range(part.start, part.stop)):
                grow = math.exp(float(logs[i])) / scales[c]
                states[:, c] = dev[:, i] * grow
                latches[:, c] = dlat[:, i] * grow
        assert first is not None
        return states, latches, first

    def images(
        self,
        section: Section,
        stops: np.ndarray,
        columns: np.ndarray,
        latch: np.ndarray,
        basis: np.ndarray,
        latches: np.ndarray,
    ) -> tuple[np.ndarray, TangentIntegration]:
        """Images of tangent vectors over ``stops`` from ``section`` (:meth:`carry`) as
        rows of coordinates on ``basis``, then τ × the latches of the joints ``latches``
        (one column each); and the (first) run."""
        states, lat, run = self.carry(section, stops, columns, latch)
        return self.project_images(states, lat, basis, latches), run

    def project_images(
        self, states: np.ndarray, lat: np.ndarray, basis: np.ndarray, latches: np.ndarray
    ) -> np.ndarray:
        """State and latch differences (columns) as coordinates on ``basis``, then τ × the
        latches of the joints ``latches``."""
        out = np.empty((basis.shape[1] + latches.size, states.shape[1]))
        for c in range(states.shape[1]):
            # column by column, as the products have always been taken (the same bits)
            out[:, c] = np.concatenate(
                [self.coordinates(basis, states[:, c]), self.tau * lat[latches, c]]
            )
        return out

    def monodromy(self, section: Section, basis: np.ndarray, latches: np.ndarray) -> np.ndarray:
        """Jacobian of the map in tangent coordinates (and τ × latch of the joints
        ``latches``, indices of joints in contact at the section).

        One deviation per tangent direction, all in one block (:meth:`images`). A latch
        that the reference never renews (in contact at both ends, no contact entry in
        between) is frozen: its row and column are the unit ones, its multiplier exactly
        1. Another latch's column is the difference of the deviation with the latch
        deviation added to the first direction and that direction's (a deviation of the
        latch alone has no velocity part to carry the finite difference of its effect).
        """
        n_free = basis.shape[1]
        columns = np.concatenate([basis, np.repeat(basis[:, :1], latches.size, axis=1)], axis=1)
        latch = np.concatenate([np.full(n_free, -1), latches]).astype(np.int64)
        images, run = self.images(section, self.stops, columns, latch, basis, latches)
        jac = np.eye(n_free + latches.size)
        jac[:, :n_free] = images[:, :n_free]
        for pos, j in enumerate(latches):
            if run.stats.contact_events == 0 and run.final_contact[j] != 0:
                continue  # frozen: the unit row and column
            jac[:, n_free + pos] = images[:, n_free + pos] - images[:, 0]
        return jac

    def segmented(
        self, section: Section, segments: int, recorded: TangentIntegration | None = None
    ) -> np.ndarray:
        """Monodromy matrix on the tangent space (no latch) as the product of the Jacobians
        of ``segments`` consecutive pieces of the step schedule.

        Over a whole period every tangent deviation of a strongly contracting orbit turns
        into the dominant direction, and what the others carried is lost to round-off;
        piece by piece each Jacobian is better conditioned. For sections whose latches
        are all frozen (or absent). Each piece starts where the reference of the piece
        before ended: on the frozen steps that reference is the map's own, bit for bit,
        so no separate run finds the cuts (``recorded`` is accepted and not needed).
        """
        assert self.schedule is not None
        last = self.schedule.size - 1
        cut = np.unique(np.round(np.linspace(0, last, segments + 1)).astype(int))
        times = self.schedule[cut]
        # the end in the section's coordinates: the map's, so the product is its Jacobian
        first = self.basis(section)
        none = np.zeros(0, dtype=np.int64)
        start, cols = section, first
        product: np.ndarray | None = None
        for j in range(cut.size - 1):
            states, lat, run = self.carry(start, times[j : j + 2], cols, np.full(cols.shape[1], -1))
            end = Section(y=run.final_state, latch=run.final_latch, contact=run.final_contact)
            after = (
                first
                if j == cut.size - 2
                else tangent_basis(self.model, end.y, t=float(times[j + 1]), time_scale=self.tau)
            )
            piece = self.project_images(states, lat, after, none)
            product = piece if product is None else piece @ product
            start, cols = end, after
        assert product is not None
        return product

    def corrected(
        self, section: Section, basis: np.ndarray, latches: np.ndarray, dz: np.ndarray
    ) -> Section:
        """The section moved by tangent coordinates ``dz`` (then latch corrections), put
        back on the manifold; a joint's contact and latch follow the new state."""
        n_free = basis.shape[1]
        y = project_state(self.model, section.y + basis @ dz[:n_free], t=0.0)
        held = section.latch.copy()
        held[latches] += dz[n_free:] / self.tau
        latch, contact = section_latch(self.model, y, held)
        return Section(y=y, latch=latch, contact=contact)


def frozen_latches(jacobian: np.ndarray, n_free: int) -> np.ndarray:
    """Positions (among the latch columns) whose row is a unit row: the latch is frozen
    for the whole period, so its multiplier is exactly 1 with the latch as eigenvector."""
    out = []
    for j in range(n_free, jacobian.shape[0]):
        unit = np.zeros(jacobian.shape[1])
        unit[j] = 1.0
        if np.max(np.abs(jacobian[j] - unit)) < _FROZEN:
            out.append(j - n_free)
    return np.array(out, dtype=np.int64)
