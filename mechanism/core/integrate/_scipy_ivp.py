"""scipy's ``solve_ivp`` solvers as an integrator strategy (:class:`ScipyIVP`): a
cross-check of the compiled integrators, one Python callback per right-hand side."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechanism.core._status import STATUS_SINGULAR, STATUS_STEP_TOO_SMALL
from mechanism.core.model import kernels as model_kernels

from . import _step_kernels as step_kernels
from ._driver import ProgressBar, initial_latch
from ._interface import (
    FULL,
    Integration,
    Integrator,
    Recording,
    RecordPlan,
    StepSettings,
    solver_stats,
)

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = ["ScipyIVP", "ScipyMethodName"]

ScipyMethodName = Literal["RK45", "DOP853", "Radau", "BDF", "LSODA"]


@dataclass(frozen=True, kw_only=True)
class ScipyIVP(Integrator):
    """A :mod:`scipy.integrate` ``OdeSolver`` stepping the compiled right-hand side.

    Parameters
    ----------
    method : {"RK45", "DOP853", "Radau", "BDF", "LSODA"}
        The scipy solver class. The impact-velocity latch is updated between accepted
        steps; outputs come from the solver's dense output. Each right-hand-side call
        crosses from Python into numba, so this path is a cross-check, not the fast path.
    """

    method: ScipyMethodName = "RK45"
    name: str = field(default="", init=False)

    def __post_init__(self) -> None:
        if self.method not in ("RK45", "DOP853", "Radau", "BDF", "LSODA"):
            raise ValueError(
                f"method must be one of 'RK45', 'DOP853', 'Radau', 'BDF', 'LSODA'; "
                f"got {self.method!r}."
            )
        object.__setattr__(self, "name", self.method)

    def integrate(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        steps: StepSettings,
        record: RecordPlan = FULL,
        progress: bool = False,
        label: str = "simulate",
    ) -> Integration:
        import scipy.integrate as si

        if record != FULL:
            raise ValueError(
                f"the scipy method {self.method!r} records the full trajectory only; use "
                "'dopri5' or a generalized-α method for metrics or sections."
            )
        km = model.kernel
        ws = model.workspace()
        rec = Recording.empty(model, t_out.size)
        counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        vimp, contact = initial_latch(model, y)
        status_box = [0]

        def fun(t: float, yy: np.ndarray) -> np.ndarray:
            out = np.empty_like(yy)
            st = model_kernels.rhs(
                km, ws, t, np.ascontiguousarray(yy, dtype=np.float64), vimp, out, counters
            )
            if st != 0:
                status_box[0] = int(st)
            return out

        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        solver_cls = getattr(si, self.method)
        options: dict[str, Any] = {"rtol": steps.rtol, "atol": steps.atol}
        max_step = steps.max_step
        if steps.approach_floor > 0.0:
            # scipy's step control has no approach bound: the floor is the largest step
            max_step = min(max_step, steps.approach_floor)
        if math.isfinite(max_step):
            options["max_step"] = max_step
        start = time.perf_counter()
        solver = solver_cls(fun, t0, y, t_end, **options)
        step_kernels.record_sample(km, ws, rec, 0, t0, y, vimp, np.empty_like(y), counters.copy())
        cursor = 1
        bar = ProgressBar(progress, t0, t_end, label)
        status = 0
        message = ""
        out_counters = np.zeros_like(counters)
        try:
            while solver.status == "running":
                msg = solver.step()
                if solver.status == "failed":
                    status = STATUS_STEP_TOO_SMALL
                    message = str(msg)
                    break
                if status_box[0] != 0:
                    status = STATUS_SINGULAR
                    break
                counters[model_kernels.CNT_STEPS] += 1
                stop = int(np.searchsorted(t_out, solver.t, side="right"))
                if stop > cursor:
                    dense = solver.dense_output()
                    times = np.ascontiguousarray(t_out[cursor:stop])
                    states = np.ascontiguousarray(np.atleast_2d(dense(times)).reshape(y.size, -1))
                    step_kernels.record_batch(
                        km, ws, rec, cursor, times, states, vimp, out_counters
                    )
                    cursor = stop
                yy = np.ascontiguousarray(solver.y, dtype=np.float64)
                model_kernels.update_latch(km, ws, yy, vimp, contact, counters, False)
                bar.update(solver.t)
        finally:
            bar.close()
        wall = time.perf_counter() - start
        counters[model_kernels.CNT_JAC] += int(getattr(solver, "njev", 0))
        return Integration(
            recording=rec.head(cursor) if status != 0 else rec,
            stats=solver_stats(self.name, status, counters, wall, message),
            final_state=np.asarray(solver.y, dtype=np.float64),
            final_time=float(solver.t),
            final_step=float(solver.step_size) if solver.step_size is not None else math.nan,
            final_contact=contact.copy(),
        )
