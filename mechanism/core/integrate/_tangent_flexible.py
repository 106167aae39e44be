"""Reference trajectory and renormalised deviation on one generalized-α step sequence.

:func:`integrate_tangent_flexible` is :func:`~mechanism.core.integrate.integrate_tangent`
for a flexible model (ANCF beams), which is integrated by the implicit generalized-α
method: the reference runs in the compiled loop of :func:`GeneralizedAlpha.integrate
<mechanism.core.integrate.GeneralizedAlpha>` — the same code, the same steps, rejections
and Jacobian refreshes as :func:`mechanism.simulate` — and after each step it accepts, a
perturbed copy takes the same step with its own implicit solve
(:class:`~mechanism.core.integrate._tangent_kernels.Deviation`). docs/mechanism-lyapunov.md, §1.
"""

from __future__ import annotations

import dataclasses
import time
from typing import TYPE_CHECKING

import numpy as np

from chaoskit.contract import check_int, check_positive
from mechanism.core.bodies import beams_force_add
from mechanism.core.model import kernels as model_kernels

from . import _tangent_kernels as tangent_kernels
from ._methods import GeneralizedAlpha, RecordPlan, initial_latch
from ._tangent import TangentIntegration, TangentSettings, inverse_total_mass, progress_label

if TYPE_CHECKING:
    from collections.abc import Callable

    from mechanism.core.model import Model

__all__ = ["integrate_tangent_flexible"]

#: the copy's Newton iteration stops when its update is below this share of the
#: deviation's size (0.01 nats per drive period of ten thousand steps even if every
#: error had one sign), or earlier at the round-off of the copy's coordinates
#: (``_kernels.DEV_FLOOR``)
NEWTON_TOLERANCE = 1e-6
#: Newton iterations of the copy per step; a step that ends them with an update above
#: ``_kernels.DEV_FLOOR`` of the deviation's size is counted as unconverged
MAX_NEWTON = 12


def _check_flexible_settings(
    settings: TangentSettings, newton_tolerance: float, max_newton: int
) -> None:
    """Raise unless ``settings`` and the Newton options suit the generalized-α copy."""
    if not isinstance(settings, TangentSettings):
        raise TypeError(f"settings must be a TangentSettings; got {type(settings).__name__}.")
    if settings.steps.projection:
        raise ValueError(
            "settings.steps.projection must be False: the generalized-alpha copy is not projected."
        )
    if settings.deviation_rtol != 0.0:
        raise ValueError(
            "settings.deviation_rtol must be 0 on generalized-alpha steps (the reference "
            f"alone controls them); got {settings.deviation_rtol!r}."
        )
    if settings.difference != "split":
        raise ValueError(
            "settings.difference must be 'split' on generalized-alpha steps (the copy takes "
            f"its own implicit step); got {settings.difference!r}."
        )
    if settings.neutral_latch_after is not None:
        raise ValueError(
            "settings.neutral_latch_after must be None on generalized-alpha steps; got "
            f"{settings.neutral_latch_after!r}."
        )
    check_positive(newton_tolerance, name="newton_tolerance")
    check_int(max_newton, name="max_newton", minimum=1)


def integrate_tangent_flexible(
    model: Model,
    y0: np.ndarray,
    d0: np.ndarray,
    t_stops: np.ndarray,
    *,
    method: GeneralizedAlpha,
    settings: TangentSettings,
    newton_tolerance: float = NEWTON_TOLERANCE,
    max_newton: int = MAX_NEWTON,
    until: Callable[[np.ndarray, np.ndarray], bool] | None = None,
    progress: bool | str = False,
) -> TangentIntegration:
    """Integrate ``y0`` by ``method`` from ``t_stops[0]`` and its deviation ``d0`` along.

    Parameters
    ----------
    model
        Assembled mechanism (flexible or not: any model the generalized-α method runs).
    y0, d0
        Initial state [q; q̇] and deviation; the deviation's acceleration is that of the
        perturbed state, a(y0 + d0) − a(y0), and so is its pseudo-acceleration (the
        integrator starts its own from the acceleration).
    t_stops
        Increasing times (s); the first is the start, the last the end. The growth is
        read at the first accepted step at or after each (the steps are the reference's,
        which does not land on them), and the deviation is renormalised there.
    method
        The generalized-α integrator of the reference (as :func:`mechanism.simulate`
        resolves it).
    settings
        ``settings.steps``: the reference's step control, as for ``method.integrate``
        (without projection); ``time_scale`` and ``renormalize_every`` of the deviation.
        The Dormand–Prince-only options (``deviation_rtol``, ``neutral_latch_after``,
        ``difference``) must be left at their defaults.
    newton_tolerance, max_newton
        The copy's Newton test (relative to the deviation's size, > 0) and iteration
        limit (≥ 1).
    until
        Called at every stop before the last with the times and log growths read so far
        (as the result's ``t`` and ``log_growth``); a true return ends the run there, a
        successful run with fewer rows than ``t_stops`` (its steps are those the whole
        run would take only where the step control does not look at the end time).
    progress
        Show a progress bar: True, or its label (default ``"lyapunov"``).

    Returns
    -------
    TangentIntegration
        ``t`` holds the times reached at the stops; ``stats`` are the reference's (its
        ``function_evaluations`` count both copies); fewer rows when the run failed or
        ``until`` ended it.

    Raises
    ------
    ValueError
        On projection, a Dormand–Prince-only option or a bad Newton setting.
    """
    _check_flexible_settings(settings, newton_tolerance, max_newton)
    renormalize_every, time_scale = settings.renormalize_every, settings.time_scale
    km = model.kernel
    n = model.n_dof
    stops = np.ascontiguousarray(t_stops, dtype=np.float64)
    y = np.ascontiguousarray(y0, dtype=np.float64).copy()
    d = np.ascontiguousarray(d0, dtype=np.float64).copy()
    tau2 = float(time_scale) ** 2
    inv_mass = inverse_total_mass(model)
    size = float(tangent_kernels.deviation_size(km, d, tau2, inv_mass))
    counters_d = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    vimp, _ = initial_latch(model, y)
    t0 = float(stops[0])
    dev = tangent_kernels.Deviation(
        d=d, dacc=np.zeros(n), dapse=np.zeros(n), vimp=vimp.copy(),
        growth=np.zeros(tangent_kernels.DEV_COLUMNS), counters=counters_d, ws=model.workspace(),
        f0=np.zeros(n), f1=np.zeros(n), fel=np.zeros(n),
        dx=np.zeros(n), res=np.zeros(n), dqn=np.zeros(n), dvn=np.zeros(n),
        yp=np.zeros(2 * n), scratch=np.zeros(2 * n),
        hx=np.zeros((tangent_kernels.DEV_DEPTH, n)), hf=np.zeros((tangent_kernels.DEV_DEPTH, n)),
        xprev=np.zeros(n), fprev=np.zeros(n), size=size, tau2=tau2,
        inv_mass=inv_mass, every=int(renormalize_every), tol=float(newton_tolerance),
        max_newton=int(max_newton),
    )  # fmt: skip
    # the copy starts with its own acceleration, a(y0 + d0) − a(y0), and so do its
    # pseudo-accelerations (the integrator starts its own from the acceleration)
    beams_force_add(km.beam_i, km.beam_f, y[:n], y[n:], -1.0, dev.fel, dev.ws.beam)
    zero = np.zeros(n)
    tangent_kernels.copy_accelerations(km, dev, t0, y[:n], y[n:], zero, zero, vimp, dev.f0)
    tangent_kernels.copy_accelerations(km, dev, t0, y[:n], y[n:], d[:n], d[n:], vimp, dev.f1)
    dev.dacc[:] = dev.f1 - dev.f0
    dev.dapse[:] = dev.dacc
    times = [t0]
    logs = [0.0]

    def read(t: float) -> bool:
        times.append(t)
        logs.append(float(dev.growth[tangent_kernels.DEV_LOG]))
        return until is not None and t < stops[-1] and bool(until(np.array(times), np.array(logs)))

    start = time.perf_counter()
    run = method._advance(
        model, y, stops, steps=settings.steps, progress=bool(progress),
        label=progress_label(progress), record=RecordPlan(grid="light"), deviation=dev,
        stops=stops[1:], on_stop=read,
    )  # fmt: skip
    wall = time.perf_counter() - start
    stats = dataclasses.replace(
        run.stats,
        function_evaluations=run.stats.function_evaluations
        + int(counters_d[model_kernels.CNT_FEV]),
        wall_time=wall,
    )
    return TangentIntegration(
        t=np.array(times),
        log_growth=np.array(logs),
        renormalizations=int(dev.growth[tangent_kernels.DEV_COUNT]),
        stats=stats,
        final_state=run.final_state,
        final_deviation=d,
        newton_iterations=int(dev.growth[tangent_kernels.DEV_NEWTON]),
        unconverged_steps=int(dev.growth[tangent_kernels.DEV_UNCONVERGED]),
    )
