"""Integrators as strategy objects.

Each integrator takes an assembled :class:`~mechanism.core.model.Model`, a consistent
initial state and a uniform output grid, and returns an :class:`Integration`: the raw
output arrays (``Recording``) and :class:`SolverStats`.

* :class:`Dopri5` — Dormand–Prince 5(4) with dense output, the whole time loop compiled
  (the MATLAB ``ode45`` scheme; default).
* :class:`ScipyIVP` (``_scipy_ivp.py``) — scipy's ``RK45``, ``DOP853``, ``Radau``,
  ``BDF``, ``LSODA`` stepping the compiled right-hand side from Python (one Python
  callback per evaluation: slower; a cross-check).
* :class:`GeneralizedAlpha` — implicit generalized-α (Chung & Hulbert 1993) with Newton
  iterations on a hybrid (finite-difference + analytic ANCF) Jacobian whose clearance-contact
  columns are re-linearised at every iterate (semi-smooth Newton), and step rejection on
  deep contact entry, for stiff contact and  stiff axial modes.

The interface and its result types are in ``_interface.py``; the Python side of the
compiled loops (chunked calls, interruption, progress, step forecast) in ``_driver.py``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np

from mechanism.core._status import STATUS_OK, STATUS_RUNNING
from mechanism.core.joints import ANGLE_RIGID, ANGLE_SLOPE, POINT_LINEAR, POINT_RIGID
from mechanism.core.model import kernels as model_kernels

from . import _dopri_kernels as dopri_kernels
from . import _genalpha_kernels as genalpha_kernels
from . import _step_kernels as step_kernels
from . import _tangent_kernels as tangent_kernels

# the ``name as name`` imports: the tangent loops (``_tangent``, ``_tangent_flexible``)
# import these from here; and numba's cache index names the types of compiled arguments
# by the module that defined them and is unpickled whole before its freshness is checked:
# ``Recording`` was defined here, so an index written by an older source (another
# process) must still find it here
from ._driver import APPROACH_FRACTION as APPROACH_FRACTION
from ._driver import (
    CHUNK_STEPS,
    ProgressBar,
    StepForecast,
    advance_to,
    check_chunk_steps,
    initial_latch,
    interruptions,
    loop_output,
    loop_result,
    progress_chunks,
    step_control,
)
from ._interface import FULL, Integration, Integrator, RecordPlan, StepSettings
from ._interface import Recording as Recording
from ._interface import SolverStats as SolverStats
from ._interface import solver_stats as solver_stats
from ._scipy_ivp import ScipyIVP

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = ["METHODS", "Dopri5", "GeneralizedAlpha", "resolve_method"]


@dataclass(frozen=True, kw_only=True)
class Dopri5(Integrator):
    """Compiled adaptive Dormand–Prince 5(4) with 4th-order dense output.

    Parameters
    ----------
    contact_entry_depth : float
        With a value > 0, a step that passes the error test but takes a separated clearance
        joint deeper than this fraction of its radial clearance is retried with the step
        at which the penetration, interpolated from the start of the step, is half of it
        (as in :class:`GeneralizedAlpha`). Off by default: the error test already sees the
        contact force in the stages of a step that enters contact, and on the hard cases
        the check changed the latched impact velocity more than it helped (the peak force
        of the 1 µm slider-crank moved by 0.65 % between step caps T/4000 and T/8000 with
        it, 0.02 % without).
    max_steps : int
        Upper bound on attempted steps (accepted + rejected).
    chunk_steps : int, optional
        Attempted steps per call of the compiled loop (≥ 1; default 5 000): between calls
        Python runs, so Ctrl-C stops even a run held at tiny steps. The results do not
        depend on it.

    Notes
    -----
    Hairer's DOPRI5 step control (PI, β = 0.04) and continuous extension; the impact
    velocity latch is updated between accepted steps. Reference: J. R. Dormand,
    P. J. Prince, J. Comput. Appl. Math. 6 (1980) 19–26; E. Hairer, S. P. Nørsett,
    G. Wanner, *Solving Ordinary Differential Equations I*, §II.5–6.
    """

    contact_entry_depth: float = 0.0
    max_steps: int = 200_000_000
    chunk_steps: int = CHUNK_STEPS["dopri5"]
    name: str = field(default="dopri5", init=False)

    def __post_init__(self) -> None:
        if not float(self.contact_entry_depth) >= 0.0:
            raise ValueError(f"contact_entry_depth must be ≥ 0; got {self.contact_entry_depth!r}.")
        check_chunk_steps(self.chunk_steps)

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
        km = model.kernel
        ws = model.workspace()
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
        vimp, contact = initial_latch(model, y)
        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        # step = [t, h, facold, −1]: the loop's first call starts the run (k1 and the
        # initial step), so the whole run is one compiled entry point
        loop = step_kernels.LoopState(
            y=y, f=np.zeros_like(y), apse=np.zeros(0), step=np.array([t0, 0.0, 0.0, -1.0]),
            vimp=vimp, contact=contact, counters=counters,
            work=np.zeros((dopri_kernels.DOPRI_WORK_ROWS, y.size)),
            tally=np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64),
        )  # fmt: skip
        ctl = step_control(self, t0, t_end, steps)
        out = loop_output(model, ws, y, vimp, t_out, record, in_kernel=True)
        since = interruptions()
        start = time.perf_counter()
        forecast = StepForecast(
            t0=t0, t_end=t_end, max_steps=self.max_steps, counters=counters,
            budget=steps.step_budget,
        )  # fmt: skip
        status = STATUS_RUNNING
        bar = ProgressBar(progress, t0, t_end, label)
        try:
            for t_stop in progress_chunks(t0, t_end, progress):
                status = advance_to(
                    lambda stop: dopri_kernels.dopri5_advance(km, ws, loop, out, ctl, stop),
                    loop.step, t_stop, bar, since, forecast,
                )  # fmt: skip
                if status != STATUS_RUNNING:
                    break
        finally:
            bar.close()
        wall = time.perf_counter() - start
        return loop_result(
            self.name, out, status, counters, wall, y, loop.step[0], loop, forecast.message
        )


def _jacobian_columns(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """(finite-difference columns, analytic columns) of the generalized-α Jacobian.

    A node of an ANCF beam that no point of the point table reads (no joint, contact or
    output touches it) enters q̈ only through its elastic and damping forces, whose
    Jacobian the element provides; every other coordinate is differenced.
    """
    km = model.kernel
    n = model.n_dof
    node_start = np.full(n, -1, dtype=np.int64)  # first coordinate of the node of a beam DOF
    for o, ne in km.beam_i[:, :2]:
        idx = np.arange(o, o + 4 * (ne + 1))
        node_start[idx] = o + 4 * ((idx - o) // 4)
    analytic = node_start >= 0
    for row in km.pt_i:
        for d in (row[1], row[3], *row[4:8]):
            if d >= 0 and node_start[d] >= 0:
                analytic[node_start[d] : node_start[d] + 4] = False
    cols = np.arange(n, dtype=np.int64)
    return np.ascontiguousarray(cols[~analytic]), np.ascontiguousarray(cols[analytic])


def _contact_columns(model: Model) -> np.ndarray:
    """The coordinates the clearance joints' bearing and journal points read (position,
    and the angle that sets the friction moment and the worn-profile region)."""
    km = model.kernel
    cols: set[int] = set()
    for point in km.cj_i[:, :2].ravel():
        kind, base, angle_kind, slope, *ds = (int(x) for x in km.pt_i[point])
        if kind == POINT_RIGID:
            cols.update((base, base + 1, base + 2))
        elif kind == POINT_LINEAR:
            for d in ds:
                if d >= 0:
                    cols.update((d, d + 1))
        if angle_kind == ANGLE_RIGID:
            cols.add(base + 2)
        elif angle_kind == ANGLE_SLOPE:
            cols.update((slope, slope + 1))
    return np.array(sorted(cols), dtype=np.int64)


@dataclass(frozen=True, kw_only=True)
class GeneralizedAlpha(Integrator):
    """Implicit generalized-α integrator for stiff contact (Chung & Hulbert 1993).

    Parameters
    ----------
    rho_inf : float
        Spectral radius at infinite frequency, in [0, 1]: 1 keeps all energy
        (trapezoidal), smaller values damp the unresolved high-frequency content.
    max_newton : int
        Newton iterations per step before the Jacobian is refreshed or the step is
        reduced.
    contact_entry_depth : float
        A step from a separated state is rejected when it ends deeper than this fraction
        of the radial clearance and retried with the step at which the penetration,
        interpolated from the start of the step, is half of it, so every impact starts
        with a short step; a step below 1e-6 × the maximum step is accepted (a worn
        profile can make the penetration jump). 0 disables the check.
    max_steps : int
        Upper bound on attempted steps.
    chunk_steps : int, optional
        Attempted steps per call of the compiled loop (≥ 1; default 1 000): between calls
        Python runs, so Ctrl-C stops even a run held at tiny steps. The results do not
        depend on it.
    step : float or "max_step", optional
        Fixed step (s), or ``"max_step"`` for the run's maximum step (``solver.max_step``,
        else the output step of a scene with clearance joints): no local error control
        or the output spacing when that is unbounded (the tolerances still set the
        Newton convergence test); a step whose Newton
        iteration fails, or that enters contact too deep, is retried with a fraction of
        it. For flexible (ANCF) bodies, whose stiff axial modes an error-controlled step
        would have to resolve (docs/ancf.md §8). Default: adaptive. The method name
        ``"generalized-alpha-fixed"`` is ``GeneralizedAlpha(step="max_step")``.

    Notes
    -----
    Second order; the local error estimate compares the acceleration change over the
    step (``e_q = h²|β − 1/6| Δq̈``, ``e_v = h(|γ − ½| + 1/12) Δq̈``). J. Chung, G. M. Hulbert,
    J. Appl. Mech. 60 (1993) 371–375; M. Arnold, O. Brüls, Multibody Syst. Dyn. 18 (2007)
    185–202.
    """

    rho_inf: float = 0.8
    max_newton: int = 8
    contact_entry_depth: float = 0.01
    max_steps: int = 200_000_000
    chunk_steps: int = CHUNK_STEPS["generalized-alpha"]
    step: float | Literal["max_step"] | None = None
    name: str = field(default="generalized-alpha", init=False)

    def __post_init__(self) -> None:
        if not 0.0 <= float(self.rho_inf) <= 1.0:
            raise ValueError(f"rho_inf must be in [0, 1]; got {self.rho_inf!r}.")
        if int(self.max_newton) < 1:
            raise ValueError(f"max_newton must be ≥ 1; got {self.max_newton!r}.")
        if not float(self.contact_entry_depth) >= 0.0:
            raise ValueError(f"contact_entry_depth must be ≥ 0; got {self.contact_entry_depth!r}.")
        if self.step is not None and self.step != "max_step":
            if not (isinstance(self.step, int | float) and math.isfinite(self.step)):
                raise ValueError(
                    f"step must be a number > 0 (s), 'max_step' or None; got {self.step!r}."
                )
            if not self.step > 0.0:
                raise ValueError(f"step must be > 0 (s); got {self.step!r}.")
        check_chunk_steps(self.chunk_steps)

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
        return self._advance(
            model, y0, t_out, steps=steps, record=record, progress=progress, label=label
        )

    def _advance(
        self,
        model: Model,
        y0: np.ndarray,
        t_out: np.ndarray,
        *,
        steps: StepSettings,
        record: RecordPlan = FULL,
        progress: bool = False,
        label: str = "simulate",
        deviation: tangent_kernels.Deviation | None = None,
        stops: np.ndarray | None = None,
        on_stop: Callable[[float], bool] | None = None,
    ) -> Integration:
        """:meth:`integrate`, optionally carrying a :class:`~._kernels.Deviation` along
        (the largest Lyapunov exponent): the loop then stops at every time of ``stops``
        (the first accepted step at or after it; the steps do not depend on the stops)
        and calls ``on_stop`` with the time reached; a true return ends the run there."""
        km = model.kernel
        n = model.n_dof
        ws = model.workspace()
        y = np.ascontiguousarray(y0, dtype=np.float64).copy()
        counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
        vimp, contact = initial_latch(model, y)
        t0 = float(t_out[0])
        t_end = float(t_out[-1])
        out = loop_output(model, ws, y, vimp, t_out, record)
        since = interruptions()
        start = time.perf_counter()
        acc = np.zeros(n)
        t_now = t0
        loop = None
        forecast = StepForecast(
            t0=t0, t_end=t_end, max_steps=self.max_steps, counters=counters,
            budget=steps.step_budget,
        )  # fmt: skip
        max_step = steps.max_step
        status = model_kernels.accelerations(km, ws, t0, y[:n], y[n:], vimp, acc, counters)
        if status == STATUS_OK:
            status = STATUS_RUNNING
            fd_cols, an_cols = _jacobian_columns(model)
            jac = genalpha_kernels.jacobian_buffers(
                n, vimp.shape[0], fd_cols, an_cols, _contact_columns(model)
            )
            if self.step == "max_step":
                # an unbounded run (e.g. the ideal companion) steps at the output spacing
                fixed = float(max_step)
                if not math.isfinite(fixed):
                    fixed = float(t_out[1] - t_out[0]) if t_out.size > 1 else t_end - t0
            else:
                fixed = 0.0 if self.step is None else float(self.step)
            if fixed > 0.0:
                max_step = min(max_step, fixed)
                h0 = max_step
            else:
                h0 = min(max_step, 1e-3 * (t_end - t0), 1e-4)
            ctl = step_control(self, t0, t_end, steps, max_step=max_step, fixed_step=fixed)
            loop = step_kernels.LoopState(
                y=y, f=acc, apse=acc.copy(), step=np.array([t0, h0, 0.0, 0.0, 0.0, -1.0, 0.0]),
                vimp=vimp, contact=contact, counters=counters, work=np.zeros((0, 0)),
                tally=np.zeros(0, dtype=np.int64),
            )  # fmt: skip
            bar = ProgressBar(progress, t0, t_end, label)
            chunks = (
                progress_chunks(t0, t_end, progress) if stops is None else [float(x) for x in stops]
            )
            try:
                for t_stop in chunks:
                    status = advance_to(
                        lambda stop: genalpha_kernels.genalpha_advance(
                            km, ws, loop, out, ctl, jac, stop, deviation
                        ),
                        loop.step, t_stop, bar, since, forecast,
                    )  # fmt: skip
                    if on_stop is not None and status in (STATUS_RUNNING, STATUS_OK):
                        if on_stop(float(loop.step[0])):
                            status = STATUS_OK
                    if status != STATUS_RUNNING:
                        break
            finally:
                bar.close()
            t_now = float(loop.step[0])
        wall = time.perf_counter() - start
        return loop_result(self.name, out, status, counters, wall, y, t_now, loop, forecast.message)


METHODS: tuple[str, ...] = (
    "auto",
    "dopri5",
    "RK45",
    "DOP853",
    "Radau",
    "BDF",
    "LSODA",
    "generalized-alpha",
    "generalized-alpha-fixed",
)


def resolve_method(method: str | Integrator, model: Model | None = None) -> Integrator:
    """Turn a method name (see ``METHODS``) or an :class:`Integrator` into a strategy.

    ``"auto"`` picks by the assembled ``model``: the fixed-step generalized-α
    (``GeneralizedAlpha(step="max_step")``, as ``"generalized-alpha-fixed"``) when it has
    ANCF beam coordinates, whose axial modes (kHz to 0.1 MHz) hold every error-controlled
    method at their period (docs/ancf.md §8), and :class:`Dopri5` (the MATLAB ``ode45``
    scheme of the paper) for a rigid model.

    Parameters
    ----------
    method : str or Integrator
        A name of ``METHODS`` or an integrator object (returned unchanged).
    model : mechanism.core.model.Model, optional
        The assembled mechanism; required by ``"auto"``. Its ``solver.rho_inf`` sets the
        numerical damping of the generalized-α methods (0.8 without a model).

    Examples
    --------
    >>> resolve_method("Radau").name
    'Radau'
    >>> resolve_method(GeneralizedAlpha(rho_inf=0.5)).name
    'generalized-alpha'
    >>> import mechanism
    >>> from mechanism.core.model._assemble import assemble
    >>> rigid = assemble(mechanism.load_scene("slider-crank"))
    >>> resolve_method("auto", rigid).name
    'dopri5'
    >>> flexible = assemble(mechanism.load_scene("flexible-slider-crank"))
    >>> resolve_method("auto", flexible).step
    'max_step'
    """
    if isinstance(method, Integrator):
        return method
    # the scene's numerical damping for the generalized-α methods (default 0.8)
    rho_inf = 0.8 if model is None else float(model.scene.solver.rho_inf)
    if method == "auto":
        if model is None:
            raise ValueError("method 'auto' needs the assembled model to choose an integrator.")
        has_beams = model.kernel.beam_i.shape[0] > 0
        return GeneralizedAlpha(rho_inf=rho_inf, step="max_step") if has_beams else Dopri5()
    if method == "dopri5":
        return Dopri5()
    if method == "generalized-alpha":
        return GeneralizedAlpha(rho_inf=rho_inf)
    if method == "generalized-alpha-fixed":
        return GeneralizedAlpha(rho_inf=rho_inf, step="max_step")
    if method in ("RK45", "DOP853", "Radau", "BDF", "LSODA"):
        return ScipyIVP(method=method)  # type: ignore[arg-type]
    raise ValueError(f"method must be one of {list(METHODS)} or an Integrator; got {method!r}.")
