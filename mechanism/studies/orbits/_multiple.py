"""Multiple shooting on the stroboscopic map: the orbit period split into segments at
fixed times, the states at the segment starts as unknowns and the continuity defects as
residuals.

Over one whole period the map of an unstable impacting orbit is too sensitive for Newton
(one-period growth of several hundred, and the impact sequence changes between the
iterates); over a segment of 1/m of it each linearisation holds across more of the
impact sequence and the Newton system stays well conditioned. The monodromy matrix is the
product of the segment Jacobians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechanism.core import SimulationError
from mechanism.core.integrate import (
    TangentIntegration,
    deviation_size,
    project_state,
    section_latch,
    tangent_basis,
)

from ._shooting import Section, StroboscopicMap, wrapped_difference

#: residual (share of the clearance) above which every run chooses its own steps (so
#: its steps follow its impacts: a schedule frozen from another start misplaces them and
#: the latched impact velocity jumps); below it the steps of the nodes' runs are frozen,
#: and the map is a smooth function of the nodes
REFREEZE_ABOVE = 1e-5
#: first trust radius per segment (share of the clearance): a journal moves within it
TRUST_RADIUS = 0.1


@dataclass
class Nodes:
    """Segment starts: the section state at ``times[i]`` for i < m (node m is node 0 one
    orbit period later)."""

    times: np.ndarray
    states: list[Section]

    @property
    def count(self) -> int:
        return len(self.states)

    def active(self, i: int) -> np.ndarray:
        """Joints whose latch is an unknown at node i (in contact there)."""
        return np.flatnonzero(self.states[i % self.count].contact != 0)


@dataclass
class MultipleResult:
    """Outcome of the multiple-shooting Newton iteration."""

    nodes: Nodes
    residual: float
    iterations: int
    monodromy: np.ndarray
    latches: np.ndarray
    n_free: int


def _run(smap: StroboscopicMap, nodes: Nodes, i: int, **kw: object) -> TangentIntegration:
    run = smap.run(nodes.states[i], nodes.times[i : i + 2], **kw)  # type: ignore[arg-type]
    if not run.stats.success:
        raise SimulationError(
            f"periodic orbit: the integration of segment {i} failed after "
            f"t = {run.t[-1]:.6g} s: {run.stats.message}"
        )
    return run


def _basis(smap: StroboscopicMap, nodes: Nodes, i: int) -> np.ndarray:
    i %= nodes.count
    return tangent_basis(
        smap.model, nodes.states[i].y, t=float(nodes.times[i]), time_scale=smap.tau
    )


def initial_nodes(smap: StroboscopicMap, start: Section, segments: int) -> Nodes:
    """Nodes along a run from ``start`` (the trajectory itself is the first guess)."""
    times = smap.period * smap.drive_period * np.arange(segments + 1) / segments
    run = smap.run(start, times, record=True)
    if not run.stats.success:
        raise SimulationError(f"periodic orbit: the integration failed: {run.stats.message}")
    states = []
    for i in range(segments):
        y = project_state(smap.model, run.states[i], t=float(times[i]))
        latch, contact = section_latch(smap.model, y, run.latches[i])
        states.append(Section(y=y, latch=latch, contact=contact))
    return Nodes(times=times, states=states)


def defects(
    smap: StroboscopicMap, nodes: Nodes
) -> tuple[list[np.ndarray], list[np.ndarray], float, float]:
    """The defects in the next node's coordinates (tangent basis, then τ × the latches
    of the joints in contact there), the nodes' bases, and two sizes of all defects over
    the clearance (root sums of squares): in those coordinates (the metric of the Newton
    system, so a trust-region step that shrinks its model shrinks it, which decides the
    steps) and mass-weighted as the single-shooting residual (which decides convergence
    and is reported)."""
    bases = [_basis(smap, nodes, i) for i in range(nodes.count)]
    rhs, total = [], 0.0
    for i in range(nodes.count):
        end = _run(smap, nodes, i)
        nxt = nodes.states[(i + 1) % nodes.count]
        rhs.append(_reduced_defect(smap, nodes, i, end, bases[(i + 1) % nodes.count]))
        diff = wrapped_difference(end.final_state, nxt.y, smap.angles)
        dl = smap.tau * (end.final_latch - nxt.latch)[nodes.active(i + 1)]
        total += deviation_size(smap.model, diff, time_scale=smap.tau) ** 2 + float(dl @ dl)
    size = float(np.linalg.norm(np.concatenate(rhs))) / smap.clearance
    return rhs, bases, size, math.sqrt(total) / smap.clearance


def _reduced_defect(
    smap: StroboscopicMap, nodes: Nodes, i: int, end: TangentIntegration, basis: np.ndarray
) -> np.ndarray:
    nxt = nodes.states[(i + 1) % nodes.count]
    diff = wrapped_difference(end.final_state, nxt.y, smap.angles)
    dl = smap.tau * (end.final_latch - nxt.latch)[nodes.active(i + 1)]
    return np.concatenate([smap.coordinates(basis, diff), dl])


def segment_jacobian(
    smap: StroboscopicMap, nodes: Nodes, i: int, start: np.ndarray, end: np.ndarray
) -> np.ndarray:
    """Jacobian of segment i: from (tangent coordinates on ``start``, τ × latches of the
    joints in contact at node i) to (coordinates on ``end``, τ × latches of the joints in
    contact at node i + 1).

    One deviation per tangent direction over the segment, unrescaled, all in one block
    on one reference run (:meth:`StroboscopicMap.images`); a latch column is the
    deviation with the latch deviation added to the first direction minus that
    direction's (a deviation of the latch alone has no velocity part to carry the finite
    difference of its effect)."""
    into = nodes.active(i + 1)
    held = nodes.active(i)
    n_free = start.shape[1]
    columns = np.concatenate([start, np.repeat(start[:, :1], held.size, axis=1)], axis=1)
    latch = np.concatenate([np.full(n_free, -1), held]).astype(np.int64)
    try:
        images, _ = smap.images(nodes.states[i], nodes.times[i : i + 2], columns, latch, end, into)
    except SimulationError as exc:
        raise SimulationError(f"periodic orbit: segment {i}: {exc}") from None
    images[:, n_free:] -= images[:, :1]
    return images


def _jacobians(smap: StroboscopicMap, nodes: Nodes) -> tuple[list[np.ndarray], list[np.ndarray]]:
    bases = [_basis(smap, nodes, i) for i in range(nodes.count)]
    jacs = [
        segment_jacobian(smap, nodes, i, bases[i], bases[(i + 1) % nodes.count])
        for i in range(nodes.count)
    ]
    return jacs, bases


def newton_system(
    jacs: list[np.ndarray], rhs: list[np.ndarray]
) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """The cyclic block-bidiagonal system J_i δz_i − δz_{i+1} = −d_i (δz_m = δz_0) as one
    dense matrix, its right-hand side and the column offset of each node."""
    m = len(jacs)
    cols = [j.shape[1] for j in jacs]
    offsets = [0, *np.cumsum(cols).tolist()]
    rows = [j.shape[0] for j in jacs]
    a = np.zeros((sum(rows), offsets[-1]))
    r0 = 0
    for i, jac in enumerate(jacs):
        nxt = (i + 1) % m
        if rows[i] != cols[nxt]:
            raise ValueError("segment Jacobian does not match the next node's unknowns.")
        a[r0 : r0 + rows[i], offsets[i] : offsets[i] + cols[i]] += jac
        a[r0 : r0 + rows[i], offsets[nxt] : offsets[nxt] + cols[nxt]] -= np.eye(rows[i])
        r0 += rows[i]
    return a, -np.concatenate(rhs), offsets


def _corrected(
    smap: StroboscopicMap, nodes: Nodes, bases: list[np.ndarray], dz: np.ndarray, offsets: list[int]
) -> Nodes:
    states = []
    for i, sec in enumerate(nodes.states):
        step = dz[offsets[i] : offsets[i + 1]]
        n_free = bases[i].shape[1]
        t = float(nodes.times[i])
        y = project_state(smap.model, sec.y + bases[i] @ step[:n_free], t=t)
        held = sec.latch.copy()
        held[nodes.active(i)] += step[n_free:] / smap.tau
        latch, contact = section_latch(smap.model, y, held)
        states.append(Section(y=y, latch=latch, contact=contact))
    return Nodes(times=nodes.times, states=states)


def _pattern(nodes: Nodes) -> tuple[bytes, ...]:
    return tuple((s.contact != 0).tobytes() for s in nodes.states)


def trust_step(a: np.ndarray, b: np.ndarray, radius: float) -> np.ndarray:
    """The least-squares Newton step of A dz = b, or, when it is longer than ``radius``,
    the Levenberg–Marquardt step of that length (λ by bisection on the SVD)."""
    u, sv, vt = np.linalg.svd(a, full_matrices=False)
    ub = u.T @ b
    keep = sv > 1e-13 * sv[0]
    full = vt[keep].T @ (ub[keep] / sv[keep])
    if np.linalg.norm(full) <= radius:
        return full

    def step(lam: float) -> np.ndarray:
        return vt.T @ (sv * ub / (sv**2 + lam))

    lo, hi = 0.0, float(sv[0] ** 2) * 1e6
    for _ in range(60):
        mid = math.sqrt(max(lo, 1e-300) * hi) if lo > 0.0 else hi * 1e-12
        if np.linalg.norm(step(mid)) > radius:
            lo = mid
        else:
            hi = mid
        if lo > 0.0 and hi / lo < 1.01:
            break
    return step(hi)


def solve(
    smap: StroboscopicMap, start: Section, segments: int, tol: float, max_iterations: int
) -> MultipleResult:
    """Newton on the continuity defects of ``segments`` segments in a trust region
    (Levenberg–Marquardt steps of at most ``radius``, widened after good steps and
    narrowed after refused ones). While the defect is above ``REFREEZE_ABOVE`` every run
    takes its own adaptive steps; below it the steps of the nodes' runs are frozen. The
    segment Jacobians are reused while the defect falls fourfold."""
    smap.schedule = None
    nodes = initial_nodes(smap, start, segments)
    rhs, bases, rho, mass = defects(smap, nodes)
    iterations = 0
    jacs: list[np.ndarray] | None = None
    pattern: tuple[bytes, ...] = ()
    radius = TRUST_RADIUS * smap.clearance * math.sqrt(segments)
    fresh = False
    while iterations < max_iterations and mass > tol:
        if smap.schedule is None and mass <= REFREEZE_ABOVE:
            _freeze(smap, nodes)
            rhs, bases, rho, mass = defects(smap, nodes)
            jacs = None
        if jacs is None or _pattern(nodes) != pattern:
            jacs, _ = _jacobians(smap, nodes)
            pattern, fresh = _pattern(nodes), True
        a, b, offsets = newton_system(jacs, rhs)
        near_floor = mass < 100.0 * tol
        accepted = None
        for _ in range(3 if near_floor else 10):
            dz = trust_step(a, b, radius)
            trial = _corrected(smap, nodes, bases, dz, offsets)
            try:
                result = defects(smap, trial)
            except SimulationError:
                result = None
            if result is not None and (result[2] < 0.95 * rho or (near_floor and result[3] < mass)):
                accepted = (trial, result)
                if result[2] < 0.5 * rho:
                    radius = max(radius, 2.0 * float(np.linalg.norm(dz)))
                break
            radius = 0.25 * min(radius, float(np.linalg.norm(dz)))
        iterations += 1
        if accepted is None:
            if fresh or near_floor:
                break
            jacs = None
            continue
        nodes, (rhs, bases, new_rho, mass) = accepted
        slow = new_rho > max(0.25 * rho, 100.0 * tol)
        rho = new_rho
        fresh = False
        if slow:
            jacs = None
    jacs, bases = _jacobians(smap, nodes)
    product = jacs[0]
    for jac in jacs[1:]:
        product = jac @ product
    return MultipleResult(
        nodes=nodes,
        residual=mass,
        iterations=iterations,
        monodromy=product,
        latches=nodes.active(0),
        n_free=bases[0].shape[1],
    )


def _freeze(smap: StroboscopicMap, nodes: Nodes) -> None:
    bases = [_basis(smap, nodes, i) for i in range(nodes.count)]
    smap.freeze_pieces(nodes.states, nodes.times, bases)
