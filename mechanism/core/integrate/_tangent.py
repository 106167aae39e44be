"""Reference trajectory and renormalised deviation on one step sequence (Python layer).

:func:`integrate_tangent` drives the compiled loop of ``_tangent_kernels``: it advances a
state and a deviation of fixed size by the same Dormand–Prince steps (its rate the
derivative of the right-hand side along it, by finite differences of that size),
renormalising the deviation every few accepted steps, and returns the accumulated log growth at the
requested stop times. The largest Lyapunov exponent of a scene
(:func:`mechanism.lyapunov_exponent`) is built on it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mechanism.core.joints._kernels import PC_X, PC_Y, update_points
from mechanism.core.model import _kernels as k

from . import _kernels as ik
from . import _tangent_kernels as tk
from ._methods import (
    APPROACH_FRACTION,
    CHUNK_STEPS,
    SolverStats,
    _check_chunk_steps,
    _initial_latch,
    _Progress,
    _stats,
    advance_to,
    interruptions,
)

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = [
    "TangentIntegration",
    "deviation_size",
    "initial_deviation",
    "integrate_tangent",
    "length_scale",
]


@dataclass(frozen=True, kw_only=True)
class TangentIntegration:
    """Log growth of a renormalised deviation along a reference trajectory.

    Attributes
    ----------
    t : numpy.ndarray
        Times (s) at which the growth was read: the requested stops reached (the last
        step before each stop is shortened to land on it; the deviation is renormalised
        there).
    log_growth : numpy.ndarray
        Σ ln(|d|/size) from the start up to each ``t`` (natural log, dimensionless).
    renormalizations : int
        Renormalisations done.
    stats : SolverStats
        Reference integration cost; ``function_evaluations`` counts both copies.
    final_state, final_deviation : numpy.ndarray
    newton_iterations, unconverged_steps : int
        Generalized-α only: the perturbed copy's Newton iterations, and the steps whose
        copy ended its iterations with an update above 1e-3 of the deviation's size (0
        for Dormand–Prince).
    """

    t: np.ndarray
    log_growth: np.ndarray
    renormalizations: int
    stats: SolverStats
    final_state: np.ndarray
    final_deviation: np.ndarray
    newton_iterations: int = 0
    unconverged_steps: int = 0


def _inv_mass(model: Model) -> float:
    """1 / total mass: of the rigid bodies from their x-coordinates; with ANCF beams uᵀMu
    for the unit translation u along x (1 on every body's and node's x-coordinate)."""
    if not model.beams:
        mass = sum(float(model.kernel.mass[o, o]) for o in model.body_offsets)
        return 1.0 / mass
    u = np.array([1.0 if name.endswith(".x") else 0.0 for name in model.dof_names])
    return 1.0 / float(u @ model.kernel.mass @ u)


def deviation_size(model: Model, d: np.ndarray, *, time_scale: float) -> float:
    """Mass-weighted size (m) √((δqᵀMδq + τ²δq̇ᵀMδq̇)/m_total) of a state deviation ``d``."""
    d = np.ascontiguousarray(d, dtype=np.float64)
    return float(ik.deviation_size(model.kernel, d, time_scale**2, _inv_mass(model)))


def length_scale(model: Model, y0: np.ndarray) -> float:
    """Length (m) a deviation size is relative to: the smallest radial clearance of the
    active clearance joints, else the mechanism's size (largest extent of its points at
    state ``y0``)."""
    if model.clearance_joints:
        return float(np.min(model.kernel.cj_f[:, k.CF_C]))
    ws = model.workspace()
    n = model.n_dof
    y = np.ascontiguousarray(y0, dtype=np.float64)
    update_points(y[:n], y[n:], model.kernel.pt_i, model.kernel.pt_f, ws.pci, ws.pcf)
    xy = ws.pcf[:, [PC_X, PC_Y]]
    span = float(np.max(np.ptp(xy, axis=0))) if xy.shape[0] > 1 else 0.0
    return span if span > 0.0 else 1.0


def _check_rigid(model: Model) -> None:
    if model.beams:
        raise ValueError(
            "integrate_tangent needs a rigid model: flexible (ANCF) bodies are integrated "
            "with generalized-alpha; use integrate_tangent_flexible."
        )


def initial_deviation(
    model: Model, y0: np.ndarray, *, t0: float, size: float, time_scale: float, seed: int = 0
) -> np.ndarray:
    """A random deviation of ``y0`` tangent to the constraint manifold, of the given size.

    Raises
    ------
    ValueError
        When the constraints leave the scene no degree of freedom (its motion is
        prescribed, so no deviation exists).
    """
    free = model.n_dof - model.n_rows
    if free <= 0:
        raise ValueError(
            f"the scene has no degree of freedom ({model.n_dof} coordinates, "
            f"{model.n_rows} constraint equations): its motion is prescribed by the drive, "
            "so it has no Lyapunov exponent; give it a clearance joint or a free body."
        )
    y = np.ascontiguousarray(y0, dtype=np.float64)
    d = np.random.default_rng(seed).standard_normal(y.size)
    ws, ws2 = model.workspace(), model.workspace()
    if not tk.project_tangent(model.kernel, ws, ws2, float(t0), y, d, np.empty(y.size)):
        raise ValueError("the constraint Jacobian is singular at the initial state.")
    r = ik.deviation_size(model.kernel, d, time_scale**2, _inv_mass(model))
    return np.ascontiguousarray(d * (size / r))


def integrate_tangent(
    model: Model,
    y0: np.ndarray,
    d0: np.ndarray,
    t_stops: np.ndarray,
    *,
    rtol: float,
    atol: float,
    max_step: float,
    renormalize_every: int,
    time_scale: float,
    approach_floor: float = 0.0,
    projection: bool = False,
    deviation_rtol: float = 0.0,
    max_steps: int = 200_000_000,
    chunk_steps: int = CHUNK_STEPS["tangent"],
    progress: bool = False,
    label: str = "lyapunov",
) -> TangentIntegration:
    """Integrate ``y0`` from ``t_stops[0]`` and its deviation ``d0`` to ``t_stops[-1]``.

    Parameters
    ----------
    model
        Assembled rigid mechanism.
    y0, d0
        Initial state [q; q̇] and deviation (its size, :func:`deviation_size`, is kept at
        every renormalisation).
    t_stops
        Increasing times (s); the first is the start. The growth is read at each.
    rtol, atol, max_step, approach_floor
        Step control of the reference, as :class:`~mechanism.integrate.Dopri5`
        (``approach_floor`` > 0: the clearance joints' approach bounds the step, never
        below it).
    renormalize_every
        Accepted steps between renormalisations (also done at every stop).
    deviation_rtol
        > 0: a step is also rejected when the deviation's error estimate exceeds this
        fraction of its size (mass-weighted norm); 0: the reference's error alone decides,
        and the steps are those of ``simulate`` at the same settings.
    time_scale
        τ (s) of the deviation norm.
    max_steps
        Upper bound on attempted steps.
    chunk_steps
        Attempted steps per call of the compiled loop (≥ 1): between calls Python runs, so
        Ctrl-C stops even a run held at tiny steps. The results do not depend on it.

    Returns
    -------
    TangentIntegration
        Fewer rows than ``t_stops`` when the run failed (``stats.status`` < 0).
    """
    _check_rigid(model)
    _check_chunk_steps(chunk_steps)
    km = model.kernel
    ws, ws2 = model.workspace(), model.workspace()
    stops = np.ascontiguousarray(t_stops, dtype=np.float64)
    y = np.ascontiguousarray(y0, dtype=np.float64).copy()
    d = np.ascontiguousarray(d0, dtype=np.float64).copy()
    tau2 = float(time_scale) ** 2
    inv_mass = _inv_mass(model)
    size = float(ik.deviation_size(km, d, tau2, inv_mass))
    k1 = np.zeros_like(y)
    kd1 = np.zeros_like(y)
    state = np.zeros(5)
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    counters_p = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    growth = np.zeros(tk.GROWTH_COLUMNS)
    vimp, contact = _initial_latch(model, y)
    dvimp = np.zeros_like(vimp)  # deviation of the latched impact velocities (m/s)
    t0, t_end = float(stops[0]), float(stops[-1])
    times = [t0]
    logs = [0.0]
    since = interruptions()
    start = time.perf_counter()
    status = k.rhs(km, ws, t0, y, vimp, k1, counters)
    if status == k.STATUS_OK:
        state[0] = t0
        state[1] = ik._initial_step(km, ws, t0, y, k1, vimp, counters, rtol, atol, max_step)
        state[2] = 1e-4
        status = ik.STATUS_RUNNING
    if status == ik.STATUS_RUNNING:
        status = tk.tangent_start(
            km, ws, t0, y, d, k1, kd1, vimp, dvimp, counters, counters_p, size,
            float(time_scale), inv_mass,
        )  # fmt: skip
    bar = _Progress(progress, t0, t_end, label)
    try:
        for t_stop in stops[1:]:
            if status != ik.STATUS_RUNNING:
                break
            status = advance_to(
                lambda stop: tk.tangent_advance(
                    km, ws, ws2, y, d, k1, kd1, state, vimp, dvimp, contact, counters,
                    counters_p, growth, stop, t_end, rtol, atol, max_step, projection,
                    max_steps, int(renormalize_every), size, tau2, inv_mass,
                    float(approach_floor), APPROACH_FRACTION, float(deviation_rtol),
                    int(chunk_steps),
                ),
                state, float(t_stop), bar, since,
            )  # fmt: skip
            if status in (ik.STATUS_RUNNING, 0):
                times.append(float(state[0]))
                logs.append(float(growth[tk.GROWTH_LOG]))
    finally:
        bar.close()
    wall = time.perf_counter() - start
    if status == ik.STATUS_RUNNING:
        status = 0
    counters[k.CNT_FEV] += counters_p[k.CNT_FEV]
    stats = _stats("dopri5", status, counters, wall)
    return TangentIntegration(
        t=np.array(times),
        log_growth=np.array(logs),
        renormalizations=int(growth[tk.GROWTH_COUNT]),
        stats=stats,
        final_state=y,
        final_deviation=d,
    )
