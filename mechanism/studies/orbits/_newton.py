"""The Newton iteration of single shooting on the stroboscopic map (contraction first,
adaptive steps until the step schedule is frozen near the orbit) and the hand-over to
multiple shooting."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechanism.core import SimulationError
from mechanism.core.integrate import project_state, section_latch

from ._multiple import REFREEZE_ABOVE
from ._multiple import solve as multiple_shooting
from ._shooting import Section, StroboscopicMap, frozen_latches, newton_step

#: pieces of the period whose Jacobians make the final monodromy matrix (no renewed latch)
SEGMENTS = 8
#: before the first monodromy matrix the map is iterated (z <- P(z)) while each iteration
#: cuts the residual at least this much: an orbit that attracts that strongly converges at
#: the rate |mu_max| with no matrix, and costs one, at the converged state
CONTRACTION = 0.1
#: below this multiple of the shooting tolerance the residual is near the map's round-off
#: floor: a trial is then likely the orbit, and its run is recorded to serve as its record
NEAR_FLOOR = 100.0


def multiple(
    smap: StroboscopicMap,
    start: Section,
    segments: int,
    tol: float,
    max_iterations: int,
    done: int,
) -> NewtonState:
    """Multiple shooting from ``start`` (after ``done`` single-shooting iterations)."""
    result = multiple_shooting(smap, start, segments, tol, max_iterations)
    first = result.nodes.states[0]
    return NewtonState(
        section=first, residual=result.residual, iterations=done + result.iterations,
        jacobian=result.monodromy, jacobian_at=first, latches=result.latches,
        n_free=result.n_free,
    )  # fmt: skip


@dataclass
class NewtonState:
    """State of the Newton iteration."""

    section: Section
    residual: float
    iterations: int
    jacobian: np.ndarray | None = None
    jacobian_at: Section | None = None
    latches: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    n_free: int = 0


def run_ok(smap: StroboscopicMap, section: Section, stops: np.ndarray, **kw: Any) -> Any:
    run = smap.run(section, stops, **kw)
    if not run.stats.success:
        raise SimulationError(
            f"periodic orbit: the integration failed after t = {run.t[-1]:.6g} s: "
            f"{run.stats.message}"
        )
    return run


def refresh(smap: StroboscopicMap, state: NewtonState, end: Any) -> np.ndarray:
    """Recompute the monodromy matrix at the current section (``end``: the map's run from
    it); returns the basis."""
    sec = state.section
    basis = smap.basis(sec)
    state.latches = np.flatnonzero(sec.contact != 0)
    state.n_free = basis.shape[1]
    frozen = end.stats.contact_events == 0 and bool(np.all(end.final_contact[state.latches]))
    if frozen and smap.schedule is not None:
        # no latch renewed: the tangent block piece by piece (well conditioned), and the
        # latches' unit rows and columns
        block = smap.segmented(sec, SEGMENTS)
        jac = np.eye(state.n_free + state.latches.size)
        jac[: state.n_free, : state.n_free] = block
    else:
        jac = smap.monodromy(sec, basis, state.latches)
    state.jacobian = jac
    state.jacobian_at = sec
    return basis


def newton(
    smap: StroboscopicMap,
    start: Section,
    tol: float,
    max_iterations: int,
    *,
    end: Any = None,
) -> NewtonState:
    """Damped Newton on P(z) − z = 0 with the monodromy matrix reused while the residual
    falls fourfold per step (``end``: the map's run from ``start`` with adaptive steps,
    when the caller has it).

    Above ``REFREEZE_ABOVE`` of the clearance every run takes its own adaptive steps: a
    step schedule frozen from another start misplaces the steps around impacts that have
    moved, and the latched impact velocity (the approach speed at the last separated
    step) jumps with them. Below it the steps of a run from the current state are frozen
    and the map is smooth."""
    smap.schedule = None
    stops = smap.stops
    if end is None:
        end = run_ok(smap, start, stops)
    state = NewtonState(section=start, residual=smap.residual(start, end, start.contact != 0),
                    iterations=0)  # fmt: skip
    end = freeze_near(smap, state, end)
    end = contract(smap, state, end, tol, max_iterations)
    basis: np.ndarray | None = None
    fresh = False
    while state.residual > tol and state.iterations < max_iterations:
        if smap.schedule is None and state.residual <= REFREEZE_ABOVE:
            end, basis = freeze_near(smap, state, end), None
        sec = state.section
        if basis is None or not np.array_equal(sec.contact != 0, state.jacobian_at.contact != 0):
            basis, fresh = refresh(smap, state, end), True
        jac = state.jacobian
        frozen = frozen_latches(jac, state.n_free)
        keep = np.setdiff1d(np.arange(jac.shape[0]), state.n_free + frozen)
        r = smap.reduced_residual(sec, end, basis, state.latches)
        dz = np.zeros_like(r)
        dz[keep] = newton_step(jac[np.ix_(keep, keep)], r[keep])
        step = 1.0
        accepted = None
        # near the map's round-off floor halving only samples its noise
        near_floor = state.residual < NEAR_FLOOR * tol
        smap.record_images = near_floor
        for _ in range(3 if near_floor else 12):
            trial = smap.corrected(sec, basis, state.latches, step * dz)
            tend = smap.run(trial, stops)
            if tend.stats.success:
                trho = smap.residual(trial, tend, trial.contact != 0)
                if trho < (1.0 - 0.1 * step) * state.residual:
                    accepted = (trial, tend, trho)
                    break
            step *= 0.5
        state.iterations += 1
        if accepted is None:
            if fresh or near_floor:
                break  # no damped step helps: a fresh matrix, or the round-off floor
            basis = None  # retry with the matrix at this state
            continue
        # a fresh matrix only while far from the round-off floor of the map
        slow = accepted[2] > max(0.25 * state.residual, NEAR_FLOOR * tol)
        state.section, end, state.residual = accepted
        fresh = False
        if slow:
            basis = None
    smap.record_images = False
    return state


def freeze_near(smap: StroboscopicMap, state: NewtonState, end: Any) -> Any:
    """Freeze the step schedule at the current state once the residual is at most
    ``REFREEZE_ABOVE``; returns the map's run from it."""
    if smap.schedule is not None or state.residual > REFREEZE_ABOVE:
        return end
    sec = state.section
    smap.freeze_steps(sec, smap.basis(sec))
    end = run_ok(smap, sec, smap.stops)
    state.residual = smap.residual(sec, end, sec.contact != 0)
    return end


def image_section(smap: StroboscopicMap, end: Any) -> Section:
    """The section state a run ends at (angles back by whole turns, on the manifold)."""
    y = end.final_state.copy()
    y[smap.angles] -= 2.0 * math.pi * np.round(y[smap.angles] / (2.0 * math.pi))
    y = project_state(smap.model, y, t=0.0)
    latch, contact = section_latch(smap.model, y, end.final_latch)
    return Section(y=y, latch=latch, contact=contact)


def contract(
    smap: StroboscopicMap, state: NewtonState, end: Any, tol: float, max_iterations: int
) -> Any:
    """Iterate the map (z <- P(z)) while each iteration cuts the residual by at least
    ``CONTRACTION``; returns the run from the last accepted state. A strongly attracting
    orbit converges so at the rate of its largest multiplier without a monodromy matrix;
    elsewhere the first trial is refused and Newton starts where it would have."""
    stops = smap.stops
    while state.residual > tol and state.iterations < max_iterations:
        trial = image_section(smap, end)
        smap.record_images = state.residual < NEAR_FLOOR * tol
        tend = smap.run(trial, stops)
        if not tend.stats.success:
            break
        trho = smap.residual(trial, tend, trial.contact != 0)
        if not trho < state.residual:
            break
        slow = trho > CONTRACTION * state.residual
        state.section, end, state.residual = trial, tend, trho
        state.iterations += 1
        end = freeze_near(smap, state, end)
        if slow:
            break
    return end
