"""What an integrator takes and returns: the :class:`Integrator` interface, the
:class:`RecordPlan` of what a run records, and its result (:class:`Integration`: the raw
output arrays of :class:`Recording` and the :class:`SolverStats`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, NamedTuple

import numpy as np

from mechanism.core._status import MESSAGES
from mechanism.core.model import kernels as model_kernels

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = [
    "FULL",
    "Integration",
    "Integrator",
    "RecordPlan",
    "Recording",
    "SolverStats",
    "StepSettings",
    "solver_stats",
]


class Recording(NamedTuple):
    """Raw output arrays on the output grid (filled by the compiled loops)."""

    t: np.ndarray  # (N,)
    q: np.ndarray  # (N, n) positions
    v: np.ndarray  # (N, n) velocities
    a: np.ndarray  # (N, n) accelerations
    lam: np.ndarray  # (N, m) Lagrange multipliers
    cj: np.ndarray  # (N, n_cj, CJ_COLUMNS) clearance-joint kinematics and forces
    out: np.ndarray  # (N, OUT_COLUMNS) crank angle, slider s/ṡ/s̈, energy, max|Φ|
    jf: np.ndarray  # (N, n_ideal_joints, 2) reaction force on each ideal joint's bodies[1]

    @classmethod
    def empty(cls, model: Model, n_out: int) -> Recording:
        n = model.n_dof
        return cls(
            t=np.zeros(n_out),
            q=np.zeros((n_out, n)),
            v=np.zeros((n_out, n)),
            a=np.zeros((n_out, n)),
            lam=np.zeros((n_out, model.n_rows)),
            cj=np.zeros((n_out, model.kernel.cj_i.shape[0], model_kernels.CJ_COLUMNS)),
            out=np.zeros((n_out, model_kernels.OUT_COLUMNS)),
            jf=np.zeros((n_out, model.kernel.jt_i.shape[0], 2)),
        )

    def head(self, count: int) -> Recording:
        """The first ``count`` samples."""
        return Recording(*(a[:count] for a in self))


@dataclass(frozen=True, kw_only=True)
class SolverStats:
    """What an integration cost and whether it succeeded.

    Attributes
    ----------
    method : str
        Integrator name.
    status : int
        0 success; negative: failure (see ``message``).
    message : str
    steps, rejected_steps, function_evaluations, jacobian_evaluations, newton_iterations
        Solver work (right-hand-side evaluations made only to record outputs are not
        counted).
    contact_events : int
        Transitions separated → contact of any clearance joint among accepted states.
    contact_evaluations : int
        Calls of the contact law made by the solver.
    wall_time : float
        Seconds spent in the integrator.
    """

    method: str
    status: int
    message: str
    steps: int = 0
    rejected_steps: int = 0
    function_evaluations: int = 0
    jacobian_evaluations: int = 0
    newton_iterations: int = 0
    contact_events: int = 0
    contact_evaluations: int = 0
    wall_time: float = 0.0

    @property
    def success(self) -> bool:
        return self.status == 0

    def as_attrs(self, prefix: str = "solver_") -> dict[str, Any]:
        """Flat attributes for a Dataset (``solver_steps``, ...)."""
        return {
            f"{prefix}method": self.method,
            f"{prefix}status": int(self.status),
            f"{prefix}message": self.message,
            f"{prefix}steps": int(self.steps),
            f"{prefix}rejected_steps": int(self.rejected_steps),
            f"{prefix}function_evaluations": int(self.function_evaluations),
            f"{prefix}jacobian_evaluations": int(self.jacobian_evaluations),
            f"{prefix}newton_iterations": int(self.newton_iterations),
            f"{prefix}contact_events": int(self.contact_events),
            f"{prefix}contact_evaluations": int(self.contact_evaluations),
            f"{prefix}wall_time": float(self.wall_time),
        }


@dataclass(frozen=True, kw_only=True)
class RecordPlan:
    """What an integration records besides its statistics.

    Parameters
    ----------
    grid : {"full", "light"}
        On the output grid: full samples (state, accelerations, multipliers, contact
        quantities and derived outputs; one right-hand-side evaluation each) or light
        samples (crank angle, slider position and velocity from the dense output alone).
    sections : int
        Capacity of the stroboscopic recording (0: none): a full sample wherever the
        crank angle passes ``phase`` + 2πk, located on the integrator's dense output.
    phase : float
        Strobe phase (rad).
    discard : float
        Crank revolutions from the start before the first section.
    metrics_from : float or None
        Time (s) from which running extremes (peak contact force, deepest penetration,
        driving torque) are taken at every accepted state; None: none.
    peak_step : float
        A step during which a clearance joint touches is also evaluated at interior
        points of its dense output no farther apart than this (at most 7), since an
        impact peaks between accepted states (s; default: every such step, 7 points).
    """

    grid: Literal["full", "light"] = "full"
    sections: int = 0
    phase: float = 0.0
    discard: float = 0.0
    metrics_from: float | None = None
    peak_step: float = 0.0


FULL = RecordPlan()


@dataclass(frozen=True, kw_only=True)
class StepSettings:
    """How an integration steps: its tolerances and step limits, built once per run.

    Parameters
    ----------
    rtol, atol : float
        Relative and absolute tolerance (> 0) of the local error; a fixed-step
        generalized-α run uses them for its Newton convergence test.
    max_step : float
        Largest step (s, > 0; ``math.inf``: unbounded).
    approach_floor : float
        With a value (s) > 0 each step is also bounded by the approach of the clearance
        joints — no separated journal travels more than ``APPROACH_FRACTION`` of its gap
        to the wall — but never below the floor (the model kernels' ``approach_step``);
        the scipy methods, whose step control has no such hook, take the floor as their
        largest step. 0: no approach bound.
    projection : bool
        Project the state onto the constraints after each accepted step
        (``solver.projection`` of the scene).
    step_budget : float
        A run whose attempted steps, extrapolated from its progress after each return of
        a compiled loop, exceed this is stopped early with the status of the step cap (the
        compiled integrators; default none: a run whose forecast exceeds the integrator's
        ``max_steps`` is stopped early all the same).

    Examples
    --------
    >>> StepSettings(rtol=1e-8, atol=1e-8, max_step=1e-3).approach_floor
    0.0
    >>> StepSettings(rtol=0.0, atol=1e-8, max_step=1e-3)
    Traceback (most recent call last):
    ...
    ValueError: rtol must be a number > 0; got 0.0.
    """

    rtol: float
    atol: float
    max_step: float
    approach_floor: float = 0.0
    projection: bool = False
    step_budget: float = math.inf

    def __post_init__(self) -> None:
        for name in ("rtol", "atol", "max_step", "step_budget"):
            value = getattr(self, name)
            if isinstance(value, bool) or not (isinstance(value, int | float) and value > 0):
                raise ValueError(f"{name} must be a number > 0; got {value!r}.")
        floor = self.approach_floor
        if isinstance(floor, bool) or not (isinstance(floor, int | float) and floor >= 0):
            raise ValueError(f"approach_floor must be a number >= 0 (s); got {floor!r}.")


@dataclass(frozen=True, kw_only=True)
class Integration:
    """Result of an integrator run: the recorded samples (possibly fewer than requested
    when the run failed) and the statistics.

    ``recording`` holds the full grid samples (empty with a light plan), ``light`` the
    light grid samples (N, 3 + 2 × clearance joints: crank angle, slider s, ṡ, then e_x,
    e_y of each clearance joint), ``sections`` the section samples
    and ``metrics`` the running extremes (``mechanism.core.integrate.kernels.MET_*``).
    ``final_step`` is the step size (s) the integrator would have tried next (NaN when
    not known) and ``final_contact`` the clearance joints in contact at ``final_time``
    (one flag per joint of ``Model.clearance_joints``), so that a failure can say what
    held the step down."""

    recording: Recording
    stats: SolverStats
    final_state: np.ndarray
    final_time: float = math.nan
    light: np.ndarray | None = None
    sections: Recording | None = None
    metrics: np.ndarray | None = None
    final_step: float = math.nan
    final_contact: np.ndarray | None = None


def solver_stats(
    method: str, status: int, counters: np.ndarray, wall: float, msg: str = ""
) -> SolverStats:
    """The :class:`SolverStats` of a finished run from its status code and kernel counters
    (``msg`` overrides the status code's standard message)."""
    return SolverStats(
        method=method,
        status=int(status),
        message=msg or MESSAGES.get(int(status), f"status {status}"),
        steps=int(counters[model_kernels.CNT_STEPS]),
        rejected_steps=int(counters[model_kernels.CNT_REJECTED]),
        function_evaluations=int(counters[model_kernels.CNT_FEV]),
        jacobian_evaluations=int(counters[model_kernels.CNT_JAC]),
        newton_iterations=int(counters[model_kernels.CNT_NEWTON]),
        contact_events=int(counters[model_kernels.CNT_CONTACT_EVENTS]),
        contact_evaluations=int(counters[model_kernels.CNT_CONTACT_EVALS]),
        wall_time=wall,
    )


class Integrator:
    """Base of the integrator strategies (see the subclasses)."""

    name: str = "integrator"

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
        """Integrate ``model`` from ``y0`` over the grid ``t_out``.

        Parameters
        ----------
        model : mechanism.core.model.Model
            The assembled mechanism.
        y0 : numpy.ndarray
            Consistent initial state (positions, then velocities).
        t_out : numpy.ndarray
            Uniform output grid (s); the run goes from its first to its last time.
        steps : StepSettings
            Tolerances and step limits.
        record : RecordPlan
            What the run records besides its statistics (default: full samples).
        progress : bool
            Show a progress bar labelled ``label``.
        label : str
            Name of the run in the progress bar.

        Returns
        -------
        Integration
        """
        raise NotImplementedError
