"""Compiled time loops: Dormand–Prince 5(4) with dense output and generalized-α.

Both loops run inside numba; the Python layer (``_methods.py``) calls them in chunks, up
to the times of an optional progress bar and for at most ``StepControl.chunk_steps``
attempted steps per call, so that control returns to Python (where a pending Ctrl-C is
raised) however small the steps get. The trajectory does not depend on the chunking or on
what is recorded. A loop takes four typed tuples besides the model and its workspace:

* :class:`StepControl` — the settings of the run (end time, tolerances, step limits, the
  contact-entry test, the generalized-α parameters);
* :class:`LoopState` — what is carried from one chunk to the next: the state
  y = [q; q̇], its derivative (Dormand–Prince, first same as last) or acceleration
  (generalized-α), the pseudo-accelerations, ``step`` (float64[4], see each loop), the
  impact-velocity latch, the contact flags and the counters of ``mechanism.core.model._kernels``;
* :class:`Output` — what is recorded after every accepted step (see
  :func:`_after_step`): full samples on the output grid (one right-hand-side evaluation
  each), or light samples (crank angle, slider s and ṡ, and the eccentricity of each
  clearance joint, from the dense output, no evaluation), stroboscopic sections located
  on the dense output, and running response metrics at every accepted state;
* :class:`Jacobian` (generalized-α only) — the Jacobian buffers and column sets.

Status codes are those of :mod:`mechanism.core._status`.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np
from numba import njit

from mechanism.core._jit import njit_noalloc
from mechanism.core._status import (
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.bodies._ancf_kernels import (
    BEAM_F_DAMPING,
    beams_force_add,
    beams_jacobian_add,
)
from mechanism.core.contact._kernels import APPROACH_RATIO, FRICTION_NONE
from mechanism.core.joints._kernels import constraint_rows, update_point_rows, update_points
from mechanism.core.model._kernels import (
    CF_FLOOR,
    CF_V0,
    CF_V1,
    CJ_DELTA,
    CJ_DELTA_DOT,
    CJ_FN,
    CJ_PHI_B,
    CJ_VT,
    CNT_COLUMNS,
    CNT_FEV,
    CNT_JAC,
    CNT_NEWTON,
    CNT_REJECTED,
    CNT_STEPS,
    CW_WORN,
    _clearance_forces,
    _clearance_state,
    _solve,
    accelerations,
    approach_step,
    crank_angle,
    derived_outputs,
    entry_depth_ratio,
    journal_travel_ratio,
    light_outputs,
    project,
    rhs,
    update_latch,
)

__all__ = [
    "STATUS_MAX_STEPS",
    "STATUS_NONFINITE",
    "STATUS_OK",
    "STATUS_RUNNING",
    "STATUS_SINGULAR",
    "STATUS_STEP_TOO_SMALL",
    "Deviation",
    "Jacobian",
    "LoopState",
    "Output",
    "StepControl",
]

# what an Output records (bit flags of Output.mode)
REC_FULL = 1  # full samples on the output grid
REC_LIGHT = 2  # crank angle, slider s, ṡ and the eccentricities on the output grid
REC_SECTIONS = 4  # full samples where the crank angle passes phase + 2πk
REC_METRICS = 8  # running extremes at every accepted state after Output.t_window

# columns of Output.metrics (running extremes over the accepted states)
MET_FN = 0  # largest normal contact force of any clearance joint
MET_DELTA = 1  # largest δ = |e| − c
MET_TORQUE_MAX = 2  # driving torque −λ_drive, largest and smallest
MET_TORQUE_MIN = 3
MET_COLUMNS = 4
PEAK_SAMPLES = 8  # a long contact step is also sampled at up to 7 interior points

# columns of Output.strobe
STROBE_TARGET = 0  # next crank angle phase + 2πk to record
STROBE_DIRECTION = 1  # +1 or −1: the sense of rotation of the crank
STROBE_ANGLE = 2  # crank angle at the last accepted state
STROBE_COLUMNS = 3

# dense-output kinds
DENSE_DOPRI5 = 0  # rows: y₀, r₂…r₅ of Hairer's continuous extension
DENSE_HERMITE = 1  # rows: [q₀; q̇₀], [q₁; q̇₁], [q̇₀; q̈₀], [q̇₁; q̈₁] (cubic Hermite)


class StepControl(NamedTuple):
    """Settings of one integration (constant through the run)."""

    t_end: float
    rtol: float
    atol: float
    max_step: float
    max_steps: int  # attempted steps (accepted + rejected)
    projection: bool
    entry_depth: float  # reject steps entering contact deeper than this × clearance; 0: off
    entry_min_step: float  # below this step an entry is accepted rather than retried
    rho_inf: float  # generalized-α only (spectral radius at infinity)
    max_newton: int  # generalized-α only
    fixed_step: float  # generalized-α only: > 0 for the fixed-step scheme
    approach_floor: float  # > 0: steps bounded by the clearance joints' approach, not below this
    approach_fraction: float  # share of a journal's gap it may travel in one step
    chunk_steps: int  # attempted steps per call before returning to Python; ≤ 0: no limit


class LoopState(NamedTuple):
    """What one chunk of a loop hands to the next."""

    y: np.ndarray  # (2n,) [q; q̇], updated in place
    f: np.ndarray  # Dormand–Prince: f(t, y) (2n,); generalized-α: q̈ (n,)
    apse: np.ndarray  # generalized-α pseudo-accelerations (n,); empty for Dormand–Prince
    step: np.ndarray  # float64[4] (Dormand–Prince) or [5] (generalized-α), see each loop
    vimp: np.ndarray  # impact-velocity latch of each clearance joint
    contact: np.ndarray  # int64 contact flag of each clearance joint
    counters: np.ndarray  # int64[CNT_COLUMNS]


class Output(NamedTuple):
    """What a loop records after each accepted step (unused arrays have length 0)."""

    mode: int  # REC_* flags
    t_out: np.ndarray  # output grid (REC_FULL or REC_LIGHT)
    cursor: np.ndarray  # int64[2]: next grid sample, sections recorded
    rec: Any  # Recording of the grid samples (REC_FULL)
    light: np.ndarray  # (len(t_out), 3 + 2 n_cj) crank angle, s, ṡ, e_x, e_y (REC_LIGHT)
    sections: Any  # Recording of the section samples (REC_SECTIONS)
    strobe: np.ndarray  # float64[STROBE_COLUMNS]
    metrics: np.ndarray  # float64[MET_COLUMNS]
    t_window: float  # metrics count from this time on
    peak_step: float  # contact steps longer than this are also sampled inside (metrics)
    drive_row: int  # row of the drive constraint in λ, −1 without a drive


class Jacobian(NamedTuple):
    """Generalized-α Jacobian buffers: ∂q̈/∂q, ∂q̈/∂q̇, the column sets (differenced,
    analytic ANCF, clearance-contact) and the clearance-force linearisations that go
    with them. Everything a step reads from earlier steps lives here (or in
    ``LoopState``), so an integration split into pieces follows the same path as one
    call (:func:`jacobian_buffers`)."""

    kq: np.ndarray
    cv: np.ndarray
    fd_cols: np.ndarray
    an_cols: np.ndarray
    contact_cols: np.ndarray
    dq0: np.ndarray  # (nc, nc) clearance-force derivatives at the Jacobian's state
    dv0: np.ndarray
    basis: np.ndarray  # (nc, n) constrained response P M⁻¹ e_cc at the Jacobian's state
    dqi: np.ndarray  # (nc, nc) derivatives at the last re-linearised Newton iterate
    dvi: np.ndarray
    gt: np.ndarray  # (n_cj, nc) ∂v_t/∂q̇_cc of the last linearisation
    lin: np.ndarray  # (n_cj, LIN_COLUMNS) state of the last re-linearisation
    flags: np.ndarray  # int64[JF_COLUMNS]


JF_BASE_CONTACT = 0  # a joint touches at the Jacobian's state
JF_LIN_TOUCHING = 1  # a joint touches at the last re-linearisation
JF_FRESH = 2  # the Jacobian was refreshed whole for the current step
JF_STALE = 3  # the next refresh may keep the differenced ∂q̈/∂q̇ columns
JF_COLUMNS = 4


class Deviation(NamedTuple):
    """A perturbed copy of a generalized-α integration, kept as its deviation from the
    reference (the largest Lyapunov exponent of a flexible model, docs/mechanism-lyapunov.md).

    After each step the reference accepts, the copy takes the same step h from its own
    state, solving its own implicit equation with the reference's Newton matrix
    (:func:`_deviation_step`); the contact state is the reference's, each copy keeps its
    own impact-velocity latch (:func:`_deviation_latch`); every ``every`` accepted steps
    and at the end of every chunk the deviation is measured and rescaled
    (:func:`_deviation_renormalize`)."""

    d: np.ndarray  # (2n,) [δq; δq̇]
    dacc: np.ndarray  # (n,) δq̈, the deviation of the integrator's acceleration
    dapse: np.ndarray  # (n,) deviation of the pseudo-accelerations
    vimp: np.ndarray  # impact-velocity latch of the perturbed copy
    growth: np.ndarray  # float64[DEV_COLUMNS]
    counters: np.ndarray  # int64[CNT_COLUMNS]: the deviation's evaluations
    ws: Any  # workspace of the deviation's evaluations (the reference's is left alone)
    f0: np.ndarray  # (n,) q̈ at the reference's accepted state (scratch from here on)
    f1: np.ndarray  # (n,)
    fel: np.ndarray  # (n,) −(elastic + damping forces) of the beams at the reference state
    dx: np.ndarray  # (n,)
    res: np.ndarray  # (n,)
    dqn: np.ndarray  # (n,)
    dvn: np.ndarray  # (n,)
    yp: np.ndarray  # (2n,)
    scratch: np.ndarray  # (2n,)
    size: float  # size (m) the deviation is rescaled to
    tau2: float  # τ² (s²) of the deviation norm
    inv_mass: float  # 1 / total mass (1/kg)
    every: int  # accepted steps between renormalisations
    tol: float  # Newton test of the copy, relative to the deviation's size
    max_newton: int  # Newton iterations of the copy per step


DEV_LOG = 0  # Σ ln(|d| / size) over the renormalisations
DEV_COUNT = 1  # renormalisations done
DEV_LAST_T = 2  # time of the last renormalisation
DEV_SINCE = 3  # accepted steps since the last renormalisation
DEV_NEWTON = 4  # Newton iterations of the copy
DEV_UNCONVERGED = 5  # steps whose copy ended max_newton iterations above DEV_FLOOR
DEV_COLUMNS = 6
DEV_DEPTH = 5  # iterates the copy's Newton mixes (Anderson acceleration)
#: the beams' forces of the perturbed copy are differenced along its deviation at this
#: largest coordinate change (m): the axial stiffness turns an ulp of a slope into a force
#: far above the deviation's own (docs/mechanism-lyapunov.md §1)
DEV_REACH = 1e-7
#: a copy's Newton iteration that stops converging (at the round-off of its
#: coordinates) below this share of the deviation's size has converged; one that ends
#: its iterations above it counts as unconverged
DEV_FLOOR = 1e-3


def jacobian_buffers(
    n: int, n_cj: int, fd_cols: np.ndarray, an_cols: np.ndarray, contact_cols: np.ndarray
) -> Jacobian:
    """Empty :class:`Jacobian` (not yet valid) for ``n`` coordinates and ``n_cj``
    clearance joints."""
    nc = contact_cols.shape[0]
    return Jacobian(
        kq=np.zeros((n, n)), cv=np.zeros((n, n)), fd_cols=fd_cols, an_cols=an_cols,
        contact_cols=contact_cols, dq0=np.zeros((nc, nc)), dv0=np.zeros((nc, nc)),
        basis=np.zeros((nc, n)), dqi=np.zeros((nc, nc)), dvi=np.zeros((nc, nc)),
        gt=np.zeros((n_cj, nc)), lin=np.full((n_cj, LIN_COLUMNS), np.nan),
        flags=np.zeros(JF_COLUMNS, dtype=np.int64),
    )  # fmt: skip


# Dormand–Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Nørsett & Wanner, II.5)
C2 = 1.0 / 5.0
C3 = 3.0 / 10.0
C4 = 4.0 / 5.0
C5 = 8.0 / 9.0
A21 = 1.0 / 5.0
A31 = 3.0 / 40.0
A32 = 9.0 / 40.0
A41 = 44.0 / 45.0
A42 = -56.0 / 15.0
A43 = 32.0 / 9.0
A51 = 19372.0 / 6561.0
A52 = -25360.0 / 2187.0
A53 = 64448.0 / 6561.0
A54 = -212.0 / 729.0
A61 = 9017.0 / 3168.0
A62 = -355.0 / 33.0
A63 = 46732.0 / 5247.0
A64 = 49.0 / 176.0
A65 = -5103.0 / 18656.0
A71 = 35.0 / 384.0
A73 = 500.0 / 1113.0
A74 = 125.0 / 192.0
A75 = -2187.0 / 6784.0
A76 = 11.0 / 84.0
E1 = 71.0 / 57600.0
E3 = -71.0 / 16695.0
E4 = 71.0 / 1920.0
E5 = -17253.0 / 339200.0
E6 = 22.0 / 525.0
E7 = -1.0 / 40.0
# continuous extension of order 4 (Hairer's DOPRI5 dense output)
D1 = -12715105075.0 / 11282082432.0
D3 = 87487479700.0 / 32700410799.0
D4 = -10690763975.0 / 1880347072.0
D5 = 701980252875.0 / 199316789632.0
D6 = -1453857185.0 / 822651844.0
D7 = 69997945.0 / 29380423.0

_EPS = 2.220446049250313e-16
REFRESH_AFTER = 10


@njit_noalloc()
def record_sample(model, ws, rec, i, t, y, vimp, scratch, counters):
    """Write output sample ``i`` of state ``y`` at time ``t``: one right-hand-side
    evaluation gives q̈, λ and the contact quantities, from which the derived outputs
    (crank angle, slider kinematics, energy, constraint residual, joint reactions) follow."""
    n = model.n_dof
    status = rhs(model, ws, t, y, vimp, scratch, counters)
    rec.t[i] = t
    for k in range(n):
        rec.q[i, k] = y[k]
        rec.v[i, k] = y[n + k]
        rec.a[i, k] = scratch[n + k]
    for k in range(model.n_rows):
        rec.lam[i, k] = ws.lam[k]
    for j in range(ws.cj.shape[0]):
        for c in range(ws.cj.shape[1]):
            rec.cj[i, j, c] = ws.cj[j, c]
    derived_outputs(model, ws, y[:n], y[n:], scratch[n:], rec.out[i], rec.jf[i])
    return status


@njit(cache=True)
def record_batch(model, ws, rec, i0, times, states, vimp, counters):
    """Record ``times[k]`` / ``states[:, k]`` as output samples i0, i0 + 1, ..."""
    scratch = np.empty(states.shape[0])
    y = np.empty(states.shape[0])
    for k in range(times.shape[0]):
        for r in range(states.shape[0]):
            y[r] = states[r, k]
        status = record_sample(model, ws, rec, i0 + k, times[k], y, vimp, scratch, counters)
        if status != STATUS_OK:
            return status
    return STATUS_OK


@njit_noalloc()
def _dense_eval(kind, dense, th, h, yout):
    """The continuous extension of the last step at θ = (t − t₀)/h into ``yout``."""
    n2 = yout.shape[0]
    if kind == DENSE_DOPRI5:
        th1 = 1.0 - th
        for i in range(n2):
            yout[i] = dense[0, i] + th * (
                dense[1, i] + th1 * (dense[2, i] + th * (dense[3, i] + th1 * dense[4, i]))
            )
    else:
        h00 = (1.0 + 2.0 * th) * (1.0 - th) ** 2
        h10 = th * (1.0 - th) ** 2
        h01 = th * th * (3.0 - 2.0 * th)
        h11 = th * th * (th - 1.0)
        for i in range(n2):
            yout[i] = (
                h00 * dense[0, i]
                + h10 * h * dense[2, i]
                + h01 * dense[1, i]
                + (h11 * h * dense[3, i])
            )


@njit_noalloc()
def _crank_at(model, ws, kind, dense, th, h, yout):
    """Crank angle on the dense output at θ (the state is left in ``yout``)."""
    _dense_eval(kind, dense, th, h, yout)
    n = model.n_dof
    update_points(yout[:n], yout[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    return crank_angle(model, ws.pcf)


@njit(cache=True)
def _sections(model, ws, out, kind, dense, told, h, vimp, scratch, yout, counters):
    """Record a full sample wherever the crank angle passed the next strobe angle
    φ + 2πk during the step, located on the dense output by the Illinois method to
    round-off in the angle."""
    strobe = out.strobe
    sense = strobe[STROBE_DIRECTION]
    c_end = _crank_at(model, ws, kind, dense, 1.0, h, yout)
    lo = 0.0
    c_lo = strobe[STROBE_ANGLE]
    while sense * (c_end - strobe[STROBE_TARGET]) >= 0.0:
        target = strobe[STROBE_TARGET]
        a = lo
        fa = sense * (c_lo - target)
        b = 1.0
        fb = sense * (c_end - target)
        root = b
        side = 0
        tol = 4.0 * _EPS * max(1.0, abs(target))
        for _ in range(100):
            if fb <= tol or b - a <= _EPS:
                root = b
                break
            if fa == fb:
                root = b
                break
            c = (a * fb - b * fa) / (fb - fa)
            c = min(max(c, a), b)
            fc = sense * (_crank_at(model, ws, kind, dense, c, h, yout) - target)
            if fc >= 0.0:
                b = c
                fb = fc
                if side == 1:
                    fa *= 0.5
                side = 1
            else:
                a = c
                fa = fc
                if side == -1:
                    fb *= 0.5
                side = -1
            root = b
        _dense_eval(kind, dense, root, h, yout)
        i = out.cursor[1]
        if i < out.sections.t.shape[0]:
            record_sample(
                model, ws, out.sections, i, told + root * h, yout, vimp, scratch, counters
            )
            out.cursor[1] = i + 1
        strobe[STROBE_TARGET] = target + sense * 2.0 * math.pi
        lo = root
        c_lo = _crank_at(model, ws, kind, dense, lo, h, yout)
    strobe[STROBE_ANGLE] = c_end


@njit_noalloc()
def _metrics_from_workspace(met, ws, drive_row):
    """Update the running extremes from the workspace of the last evaluation."""
    for j in range(ws.cj.shape[0]):
        if ws.cj[j, CJ_FN] > met[MET_FN]:
            met[MET_FN] = ws.cj[j, CJ_FN]
        if ws.cj[j, CJ_DELTA] > met[MET_DELTA]:
            met[MET_DELTA] = ws.cj[j, CJ_DELTA]
    if drive_row >= 0:
        torque = -ws.lam[drive_row]
        if torque > met[MET_TORQUE_MAX]:
            met[MET_TORQUE_MAX] = torque
        if torque < met[MET_TORQUE_MIN]:
            met[MET_TORQUE_MIN] = torque


@njit_noalloc()
def _after_step(model, ws, out, kind, dense, told, t, h, vimp, contact, scratch, yout, counters):
    """Record what ``out`` asks for after an accepted step from ``told`` to ``t``.

    The metrics read the workspace as the step's last evaluation left it (the accepted
    state for Dormand–Prince, the last Newton iterate for generalized-α), so this runs
    before any sample overwrites it; samples come from the step's dense output.
    """
    mode = out.mode
    if mode & REC_METRICS and t >= out.t_window:
        met = out.metrics
        _metrics_from_workspace(met, ws, out.drive_row)
        touching = False
        for j in range(ws.cj.shape[0]):
            touching = touching or ws.cj[j, CJ_DELTA] > 0.0 or contact[j] != 0
        if touching and h > out.peak_step:
            # an impact peaks between accepted states: the equations of motion (for the
            # multipliers) on the dense output at interior points no farther apart than
            # peak_step, at most PEAK_SAMPLES − 1 of them
            n = model.n_dof
            parts = PEAK_SAMPLES
            if out.peak_step > 0.0:
                parts = min(PEAK_SAMPLES, math.ceil(h / out.peak_step))
            for s in range(1, parts):
                th = s / parts
                _dense_eval(kind, dense, th, h, yout)
                accelerations(model, ws, told + th * h, yout[:n], yout[n:], vimp, scratch[n:],
                              counters)  # fmt: skip
                _metrics_from_workspace(met, ws, out.drive_row)
    t_out = out.t_out
    cursor = out.cursor
    n_out = t_out.shape[0]
    while cursor[0] < n_out and t_out[cursor[0]] <= t:
        th = (t_out[cursor[0]] - told) / h
        _dense_eval(kind, dense, th, h, yout)
        if mode & REC_FULL:
            record_sample(model, ws, out.rec, cursor[0], t_out[cursor[0]], yout, vimp, scratch,
                          counters)  # fmt: skip
        else:
            light_outputs(model, ws, yout, out.light[cursor[0]])
        cursor[0] += 1
    if mode & REC_SECTIONS:
        _sections(model, ws, out, kind, dense, told, h, vimp, scratch, yout, counters)


@njit_noalloc()
def _wrms(err, y0, y1, rtol, atol):
    s = 0.0
    n = err.shape[0]
    for i in range(n):
        sk = atol + rtol * max(abs(y0[i]), abs(y1[i]))
        e = err[i] / sk
        s += e * e
    return math.sqrt(s / n)


@njit(cache=True)
def _initial_step(model, ws, t, y, f0, vimp, counters, rtol, atol, max_step):
    """Starting step size in the manner of Hairer's HINIT (order 5)."""
    n2 = y.shape[0]
    dnf = 0.0
    dny = 0.0
    for i in range(n2):
        sk = atol + rtol * abs(y[i])
        dnf += (f0[i] / sk) ** 2
        dny += (y[i] / sk) ** 2
    dnf /= n2
    dny /= n2
    if dnf <= 1e-10 or dny <= 1e-10:
        h = 1e-6
    else:
        h = 0.01 * math.sqrt(dny / dnf)
    h = min(h, max_step)
    y1 = np.empty(n2)
    f1 = np.empty(n2)
    for i in range(n2):
        y1[i] = y[i] + h * f0[i]
    rhs(model, ws, t + h, y1, vimp, f1, counters)
    der2 = 0.0
    for i in range(n2):
        sk = atol + rtol * abs(y[i])
        der2 += ((f1[i] - f0[i]) / sk) ** 2
    der2 = math.sqrt(der2 / n2) / h
    der12 = max(abs(der2), math.sqrt(dnf))
    if der12 <= 1e-15:
        h1 = max(1e-6, h * 1e-3)
    else:
        h1 = (0.01 / der12) ** 0.2
    return min(100.0 * h, h1, max_step)


@njit(cache=True)
def dopri5_start(model, ws, t, y, k1, vimp, step, counters, rtol, atol, max_step):
    """Evaluate k1 = f(t, y) and the starting step into ``step`` (a ``LoopState.step``);
    returns a status. (Positional, as the tangent integration also calls it.)"""
    status = rhs(model, ws, t, y, vimp, k1, counters)
    if status != STATUS_OK:
        return status
    step[0] = t
    if step[1] <= 0.0:
        step[1] = _initial_step(model, ws, t, y, k1, vimp, counters, rtol, atol, max_step)
    step[2] = 1e-4
    step[3] = 0.0
    return STATUS_RUNNING


@njit(cache=True, nogil=True)
def dopri5_advance(model, ws, loop, out, ctl, t_stop):
    """Advance the Dormand–Prince 5(4) integration until ``t ≥ t_stop`` (or ``ctl.t_end``).

    Step-size control as in Hairer's DOPRI5 (PI controller, β = 0.04, safety 0.9, growth
    limited to [0.2, 10]); error norm ‖e/(atol + rtol·max(|y|, |y_new|))‖_rms. With
    ``ctl.entry_depth`` > 0 a step that passes the error test but takes a separated
    clearance joint deeper than ``entry_depth`` × clearance is retried shorter, as in the
    generalized-α loop, so no impact is stepped over whatever the output grid.
    ``loop.step`` = [t, h, facold, last step rejected]. Returns ``STATUS_RUNNING`` when
    ``t_stop`` is reached before ``t_end`` or after ``ctl.chunk_steps`` attempted steps
    (then ``loop.step[0]`` < ``t_stop``; the next call continues bit for bit),
    ``STATUS_OK`` at ``t_end``, or a failure status.
    """
    y = loop.y
    k1 = loop.f
    vimp = loop.vimp
    contact = loop.contact
    counters = loop.counters
    t_end = ctl.t_end
    rtol = ctl.rtol
    atol = ctl.atol
    max_step = ctl.max_step
    n2 = y.shape[0]
    k2 = np.empty(n2)
    k3 = np.empty(n2)
    k4 = np.empty(n2)
    k5 = np.empty(n2)
    k6 = np.empty(n2)
    k7 = np.empty(n2)
    ytmp = np.empty(n2)
    ynew = np.empty(n2)
    err = np.empty(n2)
    dense = np.empty((5, n2))
    yout = np.empty(n2)
    scratch = np.empty(n2)
    out_counters = np.zeros(counters.shape[0], dtype=np.int64)
    beta = 0.04
    expo1 = 0.2 - beta * 0.75
    t = loop.step[0]
    h = loop.step[1]
    facold = loop.step[2]
    last_rejected = loop.step[3] > 0.0
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while True:
        if t >= t_end:
            status = STATUS_OK
            break
        if t >= t_stop:
            break
        if counters[CNT_STEPS] + counters[CNT_REJECTED] >= ctl.max_steps:
            status = STATUS_MAX_STEPS
            break
        if 0 < ctl.chunk_steps <= counters[CNT_STEPS] + counters[CNT_REJECTED] - attempted:
            break  # back to Python, which checks for Ctrl-C and calls again
        h = min(h, max_step)
        if ctl.approach_floor > 0.0:
            near = approach_step(model, ws, y, k1[n2 // 2 :], ctl.approach_fraction)
            h = min(h, max(ctl.approach_floor, near))
        if t + 1.01 * h >= t_end:
            h = t_end - t
        if h < 10.0 * _EPS * max(abs(t), 1e-300) or h <= 0.0:
            status = STATUS_STEP_TOO_SMALL
            break
        st = STATUS_OK
        for i in range(n2):
            ytmp[i] = y[i] + h * A21 * k1[i]
        st = min(st, rhs(model, ws, t + C2 * h, ytmp, vimp, k2, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i])
        st = min(st, rhs(model, ws, t + C3 * h, ytmp, vimp, k3, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i])
        st = min(st, rhs(model, ws, t + C4 * h, ytmp, vimp, k4, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i])
        st = min(st, rhs(model, ws, t + C5 * h, ytmp, vimp, k5, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (
                A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]
            )
        st = min(st, rhs(model, ws, t + h, ytmp, vimp, k6, counters))
        for i in range(n2):
            ynew[i] = y[i] + h * (
                A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]
            )
        st = min(st, rhs(model, ws, t + h, ynew, vimp, k7, counters))
        if st != STATUS_OK:
            # a singular or non-finite stage: the configuration cannot be continued
            status = STATUS_SINGULAR
            break
        for i in range(n2):
            err[i] = h * (
                E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]
            )
        e = _wrms(err, y, ynew, rtol, atol)
        if not math.isfinite(e):
            counters[CNT_REJECTED] += 1
            h *= 0.1
            last_rejected = True
            continue
        fac11 = e**expo1
        if e <= 1.0 and ctl.entry_depth > 0.0:
            r_end = entry_depth_ratio(model, ws, ynew, contact)
            if r_end > ctl.entry_depth and h > ctl.entry_min_step:
                counters[CNT_REJECTED] += 1
                h *= _entry_fraction(model, ws, y, contact, ctl.entry_depth, r_end)
                last_rejected = True
                continue
        if e <= 1.0:
            # dense-output coefficients before y is overwritten
            for i in range(n2):
                d = ynew[i] - y[i]
                b = h * k1[i] - d
                dense[0, i] = y[i]
                dense[1, i] = d
                dense[2, i] = b
                dense[3, i] = d - h * k7[i] - b
                dense[4, i] = h * (
                    D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]
                )
            told = t
            t = t + h
            if t_end - t < 4.0 * _EPS * max(abs(t_end), 1.0):
                t = t_end
            _after_step(model, ws, out, DENSE_DOPRI5, dense, told, t, h, vimp, contact, scratch,
                        yout, out_counters)  # fmt: skip
            for i in range(n2):
                y[i] = ynew[i]
                k1[i] = k7[i]
            counters[CNT_STEPS] += 1
            update_latch(model, ws, y, vimp, contact, counters)
            if ctl.projection:
                if not project(model, ws, t, y, 1e-12, 5):
                    status = STATUS_SINGULAR
                    break
                rhs(model, ws, t, y, vimp, k1, counters)
            fac = fac11 / facold**beta
            fac = max(0.1, min(5.0, fac / 0.9))
            hnew = h / fac
            facold = max(e, 1e-4)
            if last_rejected:
                hnew = min(hnew, h)
            last_rejected = False
            h = hnew
        else:
            counters[CNT_REJECTED] += 1
            h = h / min(5.0, fac11 / 0.9)
            last_rejected = True
    loop.step[0] = t
    loop.step[1] = h
    loop.step[2] = facold
    loop.step[3] = 1.0 if last_rejected else 0.0
    return status


@njit_noalloc()
def _entry_fraction(model, ws, y, contact, entry_depth, r_end):
    """Fraction of a step that entered contact too deep to retry with: the step at which
    the penetration, interpolated linearly from the start of the step, is half the
    allowed entry depth, so one retry lands inside the contact (a fixed fraction could
    approach a slowly closing gap, a worn flank, in ever shorter steps)."""
    r_start = entry_depth_ratio(model, ws, y, contact)
    frac = 0.3
    if r_start < 0.5 * entry_depth:
        frac = (0.5 * entry_depth - r_start) / (r_end - r_start)
    return min(0.9, max(0.01, frac))


# --------------------------------------------------------------------------- generalized-α


@njit(cache=True, error_model="numpy")
def _lu_factor(a, piv):
    """In-place LU factorisation with partial pivoting; False if singular.

    On return ``a`` holds the factors *transposed* (row j of ``a`` is column j of L below
    the diagonal and of U above it), the layout :func:`_lu_solve` reads along rows.
    """
    n = a.shape[0]
    row = np.empty(n)
    for k in range(n):
        p = k
        big = abs(a[k, k])
        for i in range(k + 1, n):
            if abs(a[i, k]) > big:
                big = abs(a[i, k])
                p = i
        if not big > 0.0:
            return False
        piv[k] = p
        if p != k:
            for j in range(n):
                tmp = a[k, j]
                a[k, j] = a[p, j]
                a[p, j] = tmp
        inv = 1.0 / a[k, k]
        # the pivot row in a separate buffer: the update loop then reads and writes
        # different arrays, which the compiler vectorises
        m = n - k - 1
        for j in range(m):
            row[j] = a[k, k + 1 + j]
        for i in range(k + 1, n):
            a[i, k] *= inv
            f = a[i, k]
            if f != 0.0:
                ai = a[i, k + 1 :]
                for j in range(m):
                    ai[j] -= f * row[j]
    for i in range(n):
        for j in range(i + 1, n):
            tmp = a[i, j]
            a[i, j] = a[j, i]
            a[j, i] = tmp
    return True


@njit(cache=True, error_model="numpy")
def _lu_solve(lt, piv, b):
    """Solve A x = b in place from :func:`_lu_factor`'s transposed factors, column by
    column (contiguous rows of ``lt``)."""
    n = lt.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = b[k]
            b[k] = b[p]
            b[p] = tmp
    # the updates run over slices (no bounds read per element): the compiler vectorises
    # them, 2.6× faster on 145 × 145 than indexing the rows
    for j in range(n):
        bj = b[j]
        col = lt[j, j + 1 :]
        rest = b[j + 1 :]
        for i in range(n - j - 1):
            rest[i] -= col[i] * bj
    for j in range(n - 1, -1, -1):
        bj = b[j] / lt[j, j]
        b[j] = bj
        col = lt[j, :j]
        rest = b[:j]
        for i in range(j):
            rest[i] -= col[i] * bj


@njit(cache=True)
def _fd_jacobian(model, ws, t, q, v, vimp, kq, cv, counters):
    """Forward-difference ∂q̈/∂q and ∂q̈/∂q̇ (2n + 1 evaluations).

    The base value is evaluated here: the integrator's q̈ is a Newton iterate, accurate only
    to the tolerance, and its error divided by the tiny increments would swamp the
    Jacobian.
    """
    n = q.shape[0]
    qp = q.copy()
    vp = v.copy()
    f0 = np.empty(n)
    f1 = np.empty(n)
    accelerations(model, ws, t, q, v, vimp, f0, counters)
    for j in range(n):
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        accelerations(model, ws, t, qp, v, vimp, f1, counters)
        qp[j] = q[j]
        for i in range(n):
            kq[i, j] = (f1[i] - f0[i]) / eps
    for j in range(n):
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        accelerations(model, ws, t, q, vp, vimp, f1, counters)
        vp[j] = v[j]
        for i in range(n):
            cv[i, j] = (f1[i] - f0[i]) / eps
    counters[CNT_JAC] += 1


@njit(cache=True, error_model="numpy")
def _project(model, ws, x, out, y, u):
    """out = P M⁻¹ x, P = I − W S⁻¹Φq (the constrained response to a generalized force).

    Reads W = M⁻¹Φqᵀ, Φq and the Cholesky factor of S = Φq M⁻¹Φqᵀ (lower triangle) left in
    ``ws`` by the last :func:`accelerations` call; ``y`` (n) and ``u`` (m) are scratch.
    """
    n = out.shape[0]
    m = model.n_rows
    for i in range(n):
        acc = 0.0
        for l in range(model.blk_lo[i], model.blk_hi[i]):
            acc += model.minv[i, l] * x[l]
        y[i] = acc
    for k in range(m):
        acc = 0.0
        for i in range(n):
            acc += ws.phiq[k, i] * y[i]
        u[k] = acc
    for i in range(m):
        acc = u[i]
        for k in range(i):
            acc -= ws.s[i, k] * u[k]
        u[i] = acc / ws.s[i, i]
    for i in range(m - 1, -1, -1):
        acc = u[i]
        for k in range(i + 1, m):
            acc -= ws.s[k, i] * u[k]
        u[i] = acc / ws.s[i, i]
    for i in range(n):
        acc = y[i]
        for k in range(m):
            acc -= ws.w[i, k] * u[k]
        out[i] = acc


@njit(cache=True, error_model="numpy")
def _projected_columns(model, ws, kbuf, cols, out):
    """out[:, j] = −P M⁻¹ kbuf[:, j] for j in ``cols`` (see :func:`_project`), all columns
    at once, row by row so that the innermost loop runs along the columns.

    Plain loops, not BLAS: the products are small (the mass blocks, the m constraint rows
    with their zeros skipped), and a threaded BLAS would spin its threads on the other
    cores between calls and change the sums' order with the machine's core count."""
    n = out.shape[0]
    m = model.n_rows
    nk = cols.shape[0]
    y = np.zeros((n, nk))
    i = 0
    while i < n:
        lo = model.blk_lo[i]
        hi = model.blk_hi[i]
        for r in range(lo, hi):
            for l in range(lo, hi):
                a = model.minv[r, l]
                if a != 0.0:
                    for c in range(nk):
                        y[r, c] -= a * kbuf[l, cols[c]]
        i = hi
    if m == 0:
        for i in range(n):
            for c in range(nk):
                out[i, cols[c]] = y[i, c]
        return
    u = np.zeros((m, nk))
    for r in range(m):
        for i in range(n):
            a = ws.phiq[r, i]
            if a != 0.0:
                for c in range(nk):
                    u[r, c] += a * y[i, c]
    for c in range(nk):
        for r in range(m):
            acc = u[r, c]
            for k in range(r):
                acc -= ws.s[r, k] * u[k, c]
            u[r, c] = acc / ws.s[r, r]
        for r in range(m - 1, -1, -1):
            acc = u[r, c]
            for k in range(r + 1, m):
                acc -= ws.s[k, r] * u[k, c]
            u[r, c] = acc / ws.s[r, r]
    for i in range(n):
        for c in range(nk):
            acc = y[i, c]
            for r in range(m):
                acc -= ws.w[i, r] * u[r, c]
            out[i, cols[c]] = acc


@njit(cache=True, error_model="numpy")
def _contact_force(model, q, v, vimp, rows, pci, pcf, gen, cj, scratch_counters):
    """Generalized forces of the clearance joints alone at (q, q̇) into ``gen``; only the
    bearing and journal points ``rows`` of the point cache are refreshed (the clearance
    forces read no other point)."""
    gen[:] = 0.0
    update_point_rows(q, v, model.pt_i, model.pt_f, pci, pcf, rows)
    _clearance_forces(model, pci, pcf, vimp, gen, cj, scratch_counters)


@njit(cache=True)
def _contact_rows(model):
    """The point-table rows of the clearance joints' bearings and journals."""
    n_cj = model.cj_i.shape[0]
    rows = np.empty(2 * n_cj, dtype=np.int64)
    for j in range(n_cj):
        rows[2 * j] = model.cj_i[j, 0]
        rows[2 * j + 1] = model.cj_i[j, 1]
    return rows


@njit(cache=True, error_model="numpy")
def _contact_derivatives(model, ws, q, v, vimp, cc, dq, dv, gt, cs):
    """Derivatives of the clearance-joint forces with respect to the coordinates ``cc``
    they read (bearing and journal points): ``dq[a, c] = ∂Q_cc[a]/∂q_cc[c]``,
    ``dv[a, c] = ∂Q_cc[a]/∂q̇_cc[c]`` and ``gt[j, c] = ∂v_t/∂q̇_cc[c]`` of joint j, by
    forward differences of the contact law alone (2·len(cc) + 1 contact evaluations; the
    generalized contact force is nonzero only on ``cc``). Returns whether any clearance
    joint is in contact at (q, q̇); zeros when none is. ``cs`` holds the scratch
    (:func:`_contact_scratch`), so the call allocates nothing.
    """
    rows, pci, pcf, cj0, cj, cnt, g0, g1, qp, vp = cs
    nc = cc.shape[0]
    n_cj = ws.cj.shape[0]
    _contact_force(model, q, v, vimp, rows, pci, pcf, g0, cj0, cnt)
    touching = False
    for j in range(n_cj):
        if cj0[j, CJ_DELTA] > 0.0:
            touching = True
    if not touching:
        dq[:, :] = 0.0
        dv[:, :] = 0.0
        return False
    qp[:] = q
    vp[:] = v
    for c in range(nc):
        j = cc[c]
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        _contact_force(model, qp, v, vimp, rows, pci, pcf, g1, cj, cnt)
        qp[j] = q[j]
        for a in range(nc):
            dq[a, c] = (g1[cc[a]] - g0[cc[a]]) / eps
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        _contact_force(model, q, vp, vimp, rows, pci, pcf, g1, cj, cnt)
        vp[j] = v[j]
        for a in range(nc):
            dv[a, c] = (g1[cc[a]] - g0[cc[a]]) / eps
        for jj in range(n_cj):
            gt[jj, c] = (cj[jj, CJ_VT] - cj0[jj, CJ_VT]) / eps
    return True


# Largest relative journal travel per accepted generalized-α step, in nominal radial
# clearances (docs/simulator.md, "Fixed-step generalized-α on worn profiles")
TRAVEL_LIMIT = 0.5


# A linearisation of the clearance forces is reused while every quantity that sets it
# has moved by less than this fraction of its scale (docs/ancf.md §8)
RELINEARISE = 0.01
LIN_DELTA = 0  # δ, δ̇, v_t, φ_b and the latched impact speed at the last linearisation
LIN_DELTA_DOT = 1
LIN_VT = 2
LIN_PHI = 3
LIN_VIMP = 4
LIN_COLUMNS = 5


@njit(cache=True)
def _linearisation_holds(model, cj, vimp, lin):
    """Whether the clearance-force derivatives taken at the state ``lin`` recorded still
    hold at the state of ``cj`` (the last evaluation) to about ``RELINEARISE``: the same
    joints touch with the same latched impact speed, and per touching joint δ, the
    contact angle and δ̇ moved by less than that fraction of δ, of a radian and of
    |δ̇| + the impact speed, and v_t stayed on the same flat side of a regularised friction
    law (|v_t| ≥ v1, one sign) or moved by less than the fraction of v0. Worn joints, whose
    stiffness jumps between profile regions, are always re-linearised."""
    for j in range(cj.shape[0]):
        d = cj[j, CJ_DELTA]
        dr = lin[j, LIN_DELTA]
        if not (d > 0.0) == (dr > 0.0) or not vimp[j] == lin[j, LIN_VIMP]:
            return False
        if not d > 0.0:
            continue
        if model.cw_i[j, CW_WORN] != 0:
            return False
        if abs(d - dr) > RELINEARISE * dr:
            return False
        if abs(cj[j, CJ_PHI_B] - lin[j, LIN_PHI]) > RELINEARISE:
            return False
        dd = cj[j, CJ_DELTA_DOT]
        ddr = lin[j, LIN_DELTA_DOT]
        if abs(dd - ddr) > RELINEARISE * (abs(ddr) + vimp[j]):
            return False
        if model.cj_i[j, 3] != FRICTION_NONE:
            vt = cj[j, CJ_VT]
            vtr = lin[j, LIN_VT]
            v0 = model.cj_f[j, CF_V0]
            v1 = model.cj_f[j, CF_V1]
            sliding = min(abs(vt), abs(vtr)) >= v1 and vt * vtr > 0.0
            if not sliding and abs(vt - vtr) > RELINEARISE * v0:
                return False
    return True


@njit(cache=True)
def _record_linearisation(cj, vimp, lin):
    for j in range(cj.shape[0]):
        lin[j, LIN_DELTA] = cj[j, CJ_DELTA]
        lin[j, LIN_DELTA_DOT] = cj[j, CJ_DELTA_DOT]
        lin[j, LIN_VT] = cj[j, CJ_VT]
        lin[j, LIN_PHI] = cj[j, CJ_PHI_B]
        lin[j, LIN_VIMP] = vimp[j]


@njit(cache=True)
def _contact_scratch(model, ws):
    """Scratch of :func:`_contact_derivatives`, allocated once per integration call."""
    n = model.n_dof
    return (
        _contact_rows(model), ws.pci.copy(), ws.pcf.copy(), ws.cj.copy(), ws.cj.copy(),
        np.zeros(CNT_COLUMNS, dtype=np.int64), np.empty(n), np.empty(n), np.empty(n),
        np.empty(n),
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _response_basis(model, ws, cc, basis):
    """``basis[a] = P M⁻¹ e_cc[a]``: the constrained acceleration response to a unit
    generalized force on coordinate cc[a] (factors of the last :func:`accelerations`)."""
    n = basis.shape[1]
    e = np.zeros(n)
    y = np.empty(n)
    u = np.empty(model.n_rows)
    for a in range(cc.shape[0]):
        e[cc[a]] = 1.0
        _project(model, ws, e, basis[a], y, u)
        e[cc[a]] = 0.0


@njit(cache=True, error_model="numpy")
def _contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, w, dx):
    """Solve (J₀ + Y Δ Eᵀ) dx = r in place (``dx`` holds r) by Sherman–Morrison–Woodbury:
    J₀ = LU(``jm``, ``piv``), ``zb`` = rows of J₀⁻¹Y, Δ (``delta``, nc × nc) the change of
    the contact-force derivatives and E the selection of the columns ``cc``. Returns False
    if the small capacitance matrix is singular."""
    n = dx.shape[0]
    nc = cc.shape[0]
    _lu_solve(jm, piv, dx)
    # (I + Eᵀ Z Δ) w = Eᵀ y, Z = J₀⁻¹Y; then dx = y − Z Δ w
    for a in range(nc):
        for b in range(nc):
            acc = 0.0
            for c in range(nc):
                acc += zb[c, cc[a]] * delta[c, b]
            sm[a, b] = acc
        sm[a, a] += 1.0
        w[a] = dx[cc[a]]
    if not _lu_factor(sm, spiv):
        return False
    _lu_solve(sm, spiv, w)
    for c in range(nc):
        acc = 0.0
        for b in range(nc):
            acc += delta[c, b] * w[b]
        for i in range(n):
            dx[i] -= zb[c, i] * acc
    return True


@njit(cache=True, error_model="numpy")
def _hybrid_jacobian(
    model, ws, t, q, v, vimp, kq, cv, fd_cols, an_cols, counters, velocity_columns=True
):
    """∂q̈/∂q and ∂q̈/∂q̇: forward differences for the columns ``fd_cols`` and, for the
    interior ANCF coordinates ``an_cols`` (no joint or contact point reads them, so they
    enter q̈ only through Q = −F_e − F_d), the exact −P M⁻¹ ∂F/∂q from the analytic
    element Jacobian (docs/ancf.md §8): 2·len(fd_cols) + 1 evaluations instead of 2n + 1.
    With ``velocity_columns`` False the differenced columns of ∂q̈/∂q̇ are left as they
    are (len(fd_cols) + 1 evaluations).
    """
    n = q.shape[0]
    f0 = np.empty(n)
    f1 = np.empty(n)
    accelerations(model, ws, t, q, v, vimp, f0, counters)
    if an_cols.shape[0] > 0:
        kbuf = np.zeros((n, n))
        beams_jacobian_add(model.beam_i, model.beam_f, q, 1.0, 0.0, kbuf)
        _projected_columns(model, ws, kbuf, an_cols, kq)
        damped = False
        for b in range(model.beam_f.shape[0]):
            if model.beam_f[b, BEAM_F_DAMPING] > 0.0:
                damped = True
        if damped:
            kbuf[:, :] = 0.0
            beams_jacobian_add(model.beam_i, model.beam_f, q, 0.0, 1.0, kbuf)
            _projected_columns(model, ws, kbuf, an_cols, cv)
        else:
            # undamped beams: interior velocities do not enter q̈ at all
            for i in range(n):
                for c in range(an_cols.shape[0]):
                    cv[i, an_cols[c]] = 0.0
    qp = q.copy()
    vp = v.copy()
    for c in range(fd_cols.shape[0]):
        j = fd_cols[c]
        eps = 1.4901161193847656e-08 * max(abs(q[j]), 1e-2)
        qp[j] = q[j] + eps
        accelerations(model, ws, t, qp, v, vimp, f1, counters)
        qp[j] = q[j]
        for i in range(n):
            kq[i, j] = (f1[i] - f0[i]) / eps
    if not velocity_columns:
        counters[CNT_JAC] += 1
        return
    for c in range(fd_cols.shape[0]):
        j = fd_cols[c]
        eps = 1.4901161193847656e-08 * max(abs(v[j]), 1e-1)
        vp[j] = v[j] + eps
        accelerations(model, ws, t, q, vp, vimp, f1, counters)
        vp[j] = v[j]
        for i in range(n):
            cv[i, j] = (f1[i] - f0[i]) / eps
    counters[CNT_JAC] += 1


@njit_noalloc()
def _copy_accelerations(model, dev, t, q, v, dq, dv, vimp, acc):
    """q̈ of the state (q + δq, q̇ + δq̇) into ``acc``, as :func:`accelerations` solves it,
    except that the beams' elastic and damping forces are the reference's (``dev.fel``, at
    (q, q̇)) plus their central difference along (δq, δq̇) at a change of ``DEV_REACH``.

    Evaluated directly at a deviation of 1e-13 m, the rods' axial stiffness (1e9–1e10 N/m
    per element) turns the round-off of the perturbed slopes (an ulp, 2e-16) into forces
    larger than the deviation's own; the forces are smooth, so their increment is taken
    at a larger scale instead. Everything else (constraints, contact, friction) is
    evaluated at the perturbed state. With δq = δq̇ = 0 it is the reference's q̈ by the
    same arithmetic. Returns a status."""
    ws = dev.ws
    n = q.shape[0]
    yp = dev.yp
    sc = dev.scratch
    big = 0.0
    for i in range(n):
        yp[i] = q[i] + dq[i]
        yp[n + i] = v[i] + dv[i]
        big = max(big, abs(dq[i]), abs(dv[i]))
    dev.counters[CNT_FEV] += 1
    update_points(yp[:n], yp[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    ws.phiq[:, :] = 0.0
    constraint_rows(
        t, model.con_i, model.con_f, model.drive_i, model.drive_f, model.spline_x,
        model.spline_c, ws.pci, ws.pcf, ws.phi, ws.phiq, ws.phit, ws.gam,
    )  # fmt: skip
    gen = ws.gen
    for i in range(n):
        gen[i] = model.gravity_force[i] + dev.fel[i]
    if model.beam_i.shape[0] > 0 and big > 0.0:
        step = DEV_REACH / big
        for i in range(n):
            sc[i] = q[i] + step * dq[i]
            sc[n + i] = v[i] + step * dv[i]
        beams_force_add(model.beam_i, model.beam_f, sc[:n], sc[n:], -0.5 / step, gen)
        for i in range(n):
            sc[i] = q[i] - step * dq[i]
            sc[n + i] = v[i] - step * dv[i]
        beams_force_add(model.beam_i, model.beam_f, sc[:n], sc[n:], 0.5 / step, gen)
    if model.cj_i.shape[0] > 0:
        _clearance_forces(model, ws.pci, ws.pcf, vimp, gen, ws.cj, dev.counters)
    return _solve(
        model.minv, model.blk_lo, model.blk_hi, model.alpha, model.beta, ws.phi, ws.phiq,
        ws.phit, ws.gam, gen, yp[n:], ws.a0, ws.w, ws.s, ws.lam, ws.nz_n, ws.nz_j, acc,
    )  # fmt: skip


@njit(cache=True, error_model="numpy")
def _deviation_step(model, dev, t, h, qn, vn, vimp, am, af, gm, bt, cq, cvv, jm, piv, cc, zb,
                    dq0, dv0, base_contact, cs, sm, spiv, wv):  # fmt: skip
    """Advance the deviation ``dev`` over the step of size ``h`` the reference just
    accepted, ending at time ``t`` in the state (``qn``, ``vn``).

    The perturbed copy takes the same generalized-α step from its own state: its
    acceleration x + δx solves its implicit equation, written as one for δx,

        δx = a(t, qn + δqn(δx), vn + δvn(δx); copy's latch) − a(t, qn, vn; reference's latch),

    with δqn, δvn the predictor and corrector of the method applied to δq, δq̇, δq̈ and
    the pseudo-accelerations' deviation. The difference form shares the reference's own
    Newton residual (its iterate solves its equation only to the tolerance, far more than
    the deviation's size) with the copy. Newton with the reference's iteration matrix
    (the LU factors ``jm`` at h, frozen at the Jacobian's state) whose clearance-contact
    columns are re-linearised at the accepted state (the Sherman–Morrison–Woodbury
    correction of the reference's loop; the reference's own last linearisation may lie
    before its last update, on the other side of a friction ramp whose slope is a
    damper of 1e8 1/s), from the last step's δq̈, until the update is below ``dev.tol``
    of the deviation's size. Returns a status.
    """
    n = qn.shape[0]
    d = dev.d
    dacc = dev.dacc
    dapse = dev.dapse
    f0 = dev.f0
    f1 = dev.f1
    dx = dev.dx
    r = dev.res
    dqn = dev.dqn
    dvn = dev.dvn
    growth = dev.growth
    tau2 = dev.tau2
    c0 = (1.0 - af) / (1.0 - am)
    c1 = af / (1.0 - am)
    c2 = -am / (1.0 - am)
    fel = dev.fel
    for i in range(n):
        fel[i] = 0.0
        dqn[i] = 0.0
    if model.beam_i.shape[0] > 0:
        beams_force_add(model.beam_i, model.beam_f, qn, vn, -1.0, fel)
    st = _copy_accelerations(model, dev, t, qn, vn, dqn, dqn, vimp, f0)
    if st != STATUS_OK:
        return st
    nc = cc.shape[0]
    smw = False
    delta = np.zeros((nc, nc))
    if nc > 0:
        dqc = np.zeros((nc, nc))
        dvc = np.zeros((nc, nc))
        gtc = np.zeros((dev.vimp.shape[0], nc))
        touching = _contact_derivatives(model, dev.ws, qn, vn, vimp, cc, dqc, dvc, gtc, cs)
        smw = touching or base_contact
        if smw:
            for a in range(nc):
                for b in range(nc):
                    delta[a, b] = -cq * (dqc[a, b] - dq0[a, b]) - cvv * (dvc[a, b] - dv0[a, b])
    for i in range(n):
        dx[i] = dacc[i]
    converged = False
    prev = np.inf
    conv = np.inf
    # Anderson mixing of the last DEV_DEPTH iterates: the frozen matrix contracts some
    # directions slowly (the reference tolerates a contraction up to 0.9), which the
    # copy, held to 1e-6 of its size, cannot; mixing removes a few such directions
    hx = np.zeros((DEV_DEPTH, n))
    hf = np.zeros((DEV_DEPTH, n))
    xprev = np.zeros(n)
    fprev = np.zeros(n)
    stored = 0
    for it in range(dev.max_newton):
        for i in range(n):
            da = c0 * dx[i] + c1 * dacc[i] + c2 * dapse[i]
            dqn[i] = d[i] + h * d[n + i] + h * h * ((0.5 - bt) * dapse[i] + bt * da)
            dvn[i] = d[n + i] + h * ((1.0 - gm) * dapse[i] + gm * da)
        st = _copy_accelerations(model, dev, t, qn, vn, dqn, dvn, dev.vimp, f1)
        if st != STATUS_OK:
            return st
        for i in range(n):
            r[i] = f1[i] - f0[i] - dx[i]
        if smw:
            if not _contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, wv, r):
                return STATUS_SINGULAR
        else:
            _lu_solve(jm, piv, r)
        num = 0.0
        den = 0.0
        for i in range(n):
            num += (cq * r[i]) ** 2 + tau2 * (cvv * r[i]) ** 2
            den += dqn[i] ** 2 + tau2 * dvn[i] ** 2
        growth[DEV_NEWTON] += 1.0
        if not math.isfinite(num):
            return STATUS_NONFINITE
        conv = math.sqrt(num / den) if den > 0.0 else 0.0
        # the copy's coordinates carry the round-off of the reference's (an ulp of q
        # against a deviation of 1e-13 m), so its equation holds only to about 1e-6 of
        # the deviation: an update below DEV_FLOOR that no longer halves has reached it
        if conv <= dev.tol or (conv <= DEV_FLOOR and conv >= 0.5 * prev):
            for i in range(n):
                dx[i] += r[i]
            converged = True
            break
        prev = conv
        if it > 0:
            slot = (it - 1) % DEV_DEPTH
            for i in range(n):
                hx[slot, i] = dx[i] - xprev[i]
                hf[slot, i] = r[i] - fprev[i]
            stored = min(stored + 1, DEV_DEPTH)
        for i in range(n):
            xprev[i] = dx[i]
            fprev[i] = r[i]
        mixed = False
        if stored > 0:
            a = np.zeros((stored, stored))
            g = np.zeros(stored)
            apiv = np.zeros(stored, dtype=np.int64)
            trace = 0.0
            for u in range(stored):
                for w in range(stored):
                    acc = 0.0
                    for i in range(n):
                        acc += hf[u, i] * hf[w, i]
                    a[u, w] = acc
                acc = 0.0
                for i in range(n):
                    acc += hf[u, i] * r[i]
                g[u] = acc
                trace += a[u, u]
            for u in range(stored):
                a[u, u] += 1e-12 * trace
            if trace > 0.0 and _lu_factor(a, apiv):
                _lu_solve(a, apiv, g)
                for i in range(n):
                    acc = dx[i] + r[i]
                    for u in range(stored):
                        acc -= g[u] * (hx[u, i] + hf[u, i])
                    dx[i] = acc
                mixed = True
        if not mixed:
            for i in range(n):
                dx[i] += r[i]
    if not converged and conv > DEV_FLOOR:
        growth[DEV_UNCONVERGED] += 1.0
    for i in range(n):
        da = c0 * dx[i] + c1 * dacc[i] + c2 * dapse[i]
        dq_new = d[i] + h * d[n + i] + h * h * ((0.5 - bt) * dapse[i] + bt * da)
        dv_new = d[n + i] + h * ((1.0 - gm) * dapse[i] + gm * da)
        d[i] = dq_new
        d[n + i] = dv_new
        dapse[i] = da
        dacc[i] = dx[i]
    return STATUS_OK


@njit_noalloc()
def _deviation_latch(model, dev, y, contact, carry_worn):
    """The perturbed copy's impact-velocity latch after an accepted step: the reference
    decides contact (``contact``, already updated); a joint it sees separated tracks the
    copy's own approach speed at y + d, floored as :func:`update_latch` does; one in
    contact keeps the copy's latched value, raised from the copy's own δ̇ as
    :func:`update_latch` raises it with ``carry_worn`` on a worn joint."""
    ncj = model.cj_i.shape[0]
    if ncj == 0:
        return
    n = model.n_dof
    yp = dev.yp
    for i in range(2 * n):
        yp[i] = y[i] + dev.d[i]
    ws = dev.ws
    for j in range(ncj):
        carry = carry_worn and model.cw_i[j, CW_WORN] != 0
        if contact[j] != 0 and not carry:
            continue
        update_point_rows(yp[:n], yp[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf, model.cj_i[j, :2])
        _, ddot, _ = _clearance_state(model, ws, yp, j)
        if contact[j] != 0:
            if ddot > APPROACH_RATIO * dev.vimp[j]:
                dev.vimp[j] = ddot / APPROACH_RATIO
            continue
        floor = model.cj_f[j, CF_FLOOR]
        dev.vimp[j] = ddot if ddot > floor else floor


@njit_noalloc()
def deviation_size(model, d, tau2, inv_mass):
    """√((δqᵀMδq + τ² δq̇ᵀMδq̇)/m): the mass-weighted size (m) of a deviation, in the
    rigid and the generalized-α tangent integrations alike.

    With m the total mass, a rigid translation of the whole mechanism by δ has size δ and
    a velocity deviation counts as the displacement it makes in the time τ.
    """
    n = model.n_dof
    s = 0.0
    for i in range(n):
        xq = 0.0
        xv = 0.0
        for j in range(model.blk_lo[i], model.blk_hi[i]):
            xq += model.mass[i, j] * d[j]
            xv += model.mass[i, j] * d[n + j]
        s += d[i] * xq + tau2 * d[n + i] * xv
    return math.sqrt(max(s, 0.0) * inv_mass)


@njit_noalloc()
def _deviation_renormalize(model, dev, t, vimp):
    """Add ln(|d|/size) to the growth and rescale the deviation — (δq, δq̇), and with them
    δq̈, the pseudo-accelerations' deviation and the difference of the copy's latched
    impact velocities from the reference's ``vimp``, so the copy stays a consistent
    generalized-α state — to ``dev.size``. Unlike the rigid case the deviation is not
    projected onto the constraints' tangent space: a mass-orthogonal correction moves
    the rods' end nodes against their interior nodes and excites the stiff axial modes
    (docs/mechanism-lyapunov.md §1). Returns a status."""
    n = model.n_dof
    d = dev.d
    growth = dev.growth
    size = deviation_size(model, d, dev.tau2, dev.inv_mass)
    if not (size > 0.0 and math.isfinite(size)):
        return STATUS_NONFINITE
    growth[DEV_LOG] += math.log(size / dev.size)
    growth[DEV_COUNT] += 1.0
    growth[DEV_LAST_T] = t
    growth[DEV_SINCE] = 0.0
    f = dev.size / size
    for i in range(2 * n):
        d[i] *= f
    for i in range(n):
        dev.dacc[i] *= f
        dev.dapse[i] *= f
    # the copy's latched impact velocities are part of its state: their difference from
    # the reference's is rescaled with the rest
    for j in range(vimp.shape[0]):
        dev.vimp[j] = vimp[j] + f * (dev.vimp[j] - vimp[j])
    return STATUS_OK


@njit(cache=True, error_model="numpy", nogil=True)
def genalpha_advance(model, ws, loop, out, ctl, jac, t_stop, dev):
    """Advance a variable-step generalized-α integration (Chung & Hulbert 1993) of
    q̈ = a(t, q, q̇) until ``t ≥ t_stop`` (or ``t_end``).

    Parameters αm = (2ρ∞ − 1)/(ρ∞ + 1), αf = ρ∞/(ρ∞ + 1), γ = ½ + αf − αm,
    β = ¼(γ + ½)² (Arnold & Brüls 2007 form with pseudo-accelerations ``apse``). Each step
    solves R(x) = x − a(t + h, q(x), q̇(x)) for x = q̈ₙ₊₁ by modified Newton on
    J = I − c_q ∂a/∂q − c_v ∂a/∂q̇ (:func:`_hybrid_jacobian`; refreshed when Newton stalls,
    when the Newton iterations beyond two per step since the last refresh exceed
    ``REFRESH_AFTER``, and — in models
    without contact columns — when a clearance joint changes between contact and
    separation; convergence from the observed contraction rate, at least two
    iterations). The step is rejected when Newton fails,
    when the local error estimate e_q = h²|β − 1/6| Δq̈, e_v = h(|γ − ½| + 1/12) Δq̈
    exceeds the tolerance, or when a
    separated clearance joint would enter contact deeper than ``entry_depth`` × clearance
    (so that every impact starts with a short step and a well-defined approach speed; the
    retry interpolates the entry time, and steps below 1e-6 × ``max_step`` are accepted).

    With ``fixed_step`` > 0 the error test is skipped and every step after an accepted
    one is ``fixed_step`` (pass ``max_step`` ≤ ``fixed_step``): the fixed-step scheme of
    structural dynamics, whose numerical damping (ρ∞ < 1) removes unresolved stiff modes
    that would otherwise hold an error-controlled step at their period (ANCF axial
    modes, docs/ancf.md §8).

    Clearance-joint forces are stiff and only piecewise smooth (contact onset, the
    stick–slip ramp of regularised friction acting on a light journal), so a Jacobian
    taken at the start of the step can be useless at its end. The columns ``cc`` that
    those forces read (the bearing and journal coordinates) are therefore re-linearised
    at every Newton iterate that touches (:func:`_contact_derivatives`, a few contact-law
    evaluations; kept while the contact state moved by less than ``RELINEARISE`` since,
    :func:`_linearisation_holds`), and the change, mapped by the constrained response
    P M⁻¹ frozen at the Jacobian's state, enters the factorised matrix as a rank-len(cc)
    Sherman–Morrison–Woodbury correction (:func:`_contact_newton_solve`): a semi-smooth
    Newton iteration at O(n·len(cc)) extra work per iterate.

    ``state`` = [t, h, Jacobian valid, Newton iterations beyond two per step since the
    last refresh, last Newton iterate left the admissible configurations]; the contact
    linearisations and refresh flags live in ``jac``, so calls that stop at successive
    ``t_stop``, or after ``ctl.chunk_steps`` attempted steps, follow the path of one call
    bit for bit. Returns 1 (``t_stop`` reached, or the step budget spent with
    ``state[0]`` < ``t_stop``), 0 (done) or a negative failure status.

    ``dev`` is None, or a :class:`Deviation` that follows the run: after every accepted
    step the perturbed copy takes the same step (:func:`_deviation_step`), its latch
    follows the reference's contact state, and it is renormalised every ``dev.every``
    accepted steps and at the step that reaches ``t_stop`` or ``t_end``. The reference's
    steps, counters and state do not depend on it (with None the deviation's code is
    compiled out).
    """
    y = loop.y
    acc = loop.f
    apse = loop.apse
    state = loop.step
    vimp = loop.vimp
    contact = loop.contact
    counters = loop.counters
    kq = jac.kq
    cv = jac.cv
    fd_cols = jac.fd_cols
    an_cols = jac.an_cols
    cc = jac.contact_cols
    t_end = ctl.t_end
    rtol = ctl.rtol
    atol = ctl.atol
    max_step = ctl.max_step
    rho_inf = ctl.rho_inf
    max_newton = ctl.max_newton
    entry_depth = ctl.entry_depth
    projection = ctl.projection
    fixed_step = ctl.fixed_step
    n = model.n_dof
    n2 = 2 * n
    q = y[:n]
    v = y[n:]
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gm = 0.5 + af - am
    bt = 0.25 * (gm + 0.5) ** 2
    x = np.empty(n)
    f = np.empty(n)
    dx = np.empty(n)
    anew = np.empty(n)
    qn = np.empty(n)
    vn = np.empty(n)
    jm = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    yout = np.empty(n2)
    scratch = np.empty(n2)
    dense = np.empty((4, n2))
    out_counters = np.zeros(counters.shape[0], dtype=np.int64)
    was = np.zeros(contact.shape[0], dtype=contact.dtype)
    nc = cc.shape[0]
    dq0 = jac.dq0
    dv0 = jac.dv0
    dqi = jac.dqi
    dvi = jac.dvi
    basis = jac.basis
    gt = jac.gt
    lin = jac.lin
    flags = jac.flags
    delta = np.zeros((nc, nc))
    zb = np.zeros((nc, n))
    sm = np.zeros((nc, nc))
    spiv = np.empty(nc, dtype=np.int64)
    wv = np.empty(nc)
    cs = _contact_scratch(model, ws)
    lin_touching = flags[JF_LIN_TOUCHING] != 0
    base_contact = flags[JF_BASE_CONTACT] != 0
    t = state[0]
    h = state[1]
    jac_valid = state[2] > 0.0
    # the LU factors are rebuilt from kq, cv and h, bit for bit
    h_lu = -1.0
    fresh = flags[JF_FRESH] != 0
    excess = int(state[3])
    stale = flags[JF_STALE] != 0
    singular_iterate = state[4] > 0.0
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while True:
        if t >= t_end:
            status = STATUS_OK
            break
        if t >= t_stop:
            break
        if counters[CNT_STEPS] + counters[CNT_REJECTED] >= ctl.max_steps:
            status = STATUS_MAX_STEPS
            break
        if 0 < ctl.chunk_steps <= counters[CNT_STEPS] + counters[CNT_REJECTED] - attempted:
            break  # back to Python, which checks for Ctrl-C and calls again
        h = min(h, max_step)
        if ctl.approach_floor > 0.0:
            near = approach_step(model, ws, y, acc, ctl.approach_fraction)
            h = min(h, max(ctl.approach_floor, near))
        if t + 1.01 * h >= t_end:
            h = t_end - t
        if h < 10.0 * _EPS * max(abs(t), 1e-300) or h <= 0.0:
            status = STATUS_SINGULAR if singular_iterate else STATUS_STEP_TOO_SMALL
            break
        if not jac_valid:
            _hybrid_jacobian(
                model, ws, t, q, v, vimp, kq, cv, fd_cols, an_cols, counters, not stale
            )
            if nc > 0:
                accelerations(model, ws, t, q, v, vimp, f, counters)
                base_contact = _contact_derivatives(model, ws, q, v, vimp, cc, dq0, dv0, gt, cs)
                _response_basis(model, ws, cc, basis)
            jac_valid = True
            # only a complete refresh makes a Newton failure a reason to shorten the step
            fresh = not stale
            stale = False
            excess = 0
            h_lu = -1.0
        cq = h * h * bt * (1.0 - af) / (1.0 - am)
        cvv = h * gm * (1.0 - af) / (1.0 - am)
        if h != h_lu:
            for i in range(n):
                for j in range(n):
                    jm[i, j] = -cq * kq[i, j] - cvv * cv[i, j]
                jm[i, i] += 1.0
            if not _lu_factor(jm, piv):
                status = STATUS_SINGULAR
                break
            for c in range(nc):
                for i in range(n):
                    zb[c, i] = basis[c, i]
                _lu_solve(jm, piv, zb[c])
            h_lu = h
        for i in range(n):
            x[i] = acc[i]
        converged = False
        iters = 0
        prev = np.inf
        st = STATUS_OK
        for it in range(max_newton):
            for i in range(n):
                anew[i] = ((1.0 - af) * x[i] + af * acc[i] - am * apse[i]) / (1.0 - am)
                qn[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * apse[i] + bt * anew[i])
                vn[i] = v[i] + h * ((1.0 - gm) * apse[i] + gm * anew[i])
            st = accelerations(model, ws, t + h, qn, vn, vimp, f, counters)
            counters[CNT_NEWTON] += 1
            if st != STATUS_OK:
                break
            for i in range(n):
                dx[i] = f[i] - x[i]
            touching = False
            if nc > 0:
                # ws.cj holds the clearance state at this iterate (the evaluation above)
                if _linearisation_holds(model, ws.cj, vimp, lin):
                    touching = lin_touching
                else:
                    touching = _contact_derivatives(model, ws, qn, vn, vimp, cc, dqi, dvi, gt, cs)
                    _record_linearisation(ws.cj, vimp, lin)
                    lin_touching = touching
            if touching or base_contact:
                for a in range(nc):
                    for b in range(nc):
                        delta[a, b] = -cq * (dqi[a, b] - dq0[a, b]) - cvv * (dvi[a, b] - dv0[a, b])
                if not _contact_newton_solve(jm, piv, cc, zb, delta, sm, spiv, wv, dx):
                    break
            else:
                _lu_solve(jm, piv, dx)
            scale = 1.0
            if touching:
                # Regularised friction is flat while sliding and in its dead zone and steep
                # in the narrow ramp between: a full update from a flat piece overshoots (to
                # the opposite sliding direction, or out of the dead zone) and Newton
                # oscillates. Such an update is shortened to land in the middle of the ramp,
                # whose own tangent the contact derivatives capture; convergence is still
                # judged on the full update.
                for j in range(contact.shape[0]):
                    v0 = model.cj_f[j, CF_V0]
                    v1 = model.cj_f[j, CF_V1]
                    vt = ws.cj[j, CJ_VT]
                    if ws.cj[j, CJ_DELTA] <= 0.0 or model.cj_i[j, 3] == FRICTION_NONE:
                        continue
                    dvt = 0.0
                    for c in range(nc):
                        dvt += gt[j, c] * cvv * dx[cc[c]]
                    vnew = vt + dvt
                    target = np.nan
                    leaves = vt * vnew < 0.0 or abs(vnew) < v0  # into or across the dead zone
                    if abs(vt) > v1 and leaves:
                        target = 0.5 * (v0 + v1) * (1.0 if vt > 0.0 else -1.0)
                    elif abs(vt) >= v0 and leaves:
                        target = 0.5 * v0 * (1.0 if vt > 0.0 else -1.0)
                    elif abs(vt) < v0 and abs(vnew) > v1:
                        target = 0.5 * (v0 + v1) * (1.0 if vnew > 0.0 else -1.0)
                    if math.isfinite(target) and dvt != 0.0:
                        r = (target - vt) / dvt
                        if 0.0 < r < scale:
                            scale = r
            # the size of the full Newton update measures convergence, damped or not
            sq = 0.0
            for i in range(n):
                sk_q = atol + rtol * abs(q[i])
                sk_v = atol + rtol * abs(v[i])
                sq += (cq * dx[i] / sk_q) ** 2 + (cvv * dx[i] / sk_v) ** 2
            conv = math.sqrt(sq / n2)
            iters = it + 1
            for i in range(n):
                x[i] += scale * dx[i]
            if not math.isfinite(conv):
                break
            # Convergence from the observed contraction rate θ (Hairer & Wanner IV.8): a
            # stale Jacobian can make the first update small while the residual is not,
            # so at least two iterations are always taken.
            if scale < 1.0:
                # a shortened update says nothing about the contraction: start afresh
                prev = np.inf
                continue
            if it >= 1:
                if conv <= 1e-12 * (1.0 + prev) or prev <= 0.0:
                    converged = True
                    break
                theta = conv / prev
                if theta >= 0.9:
                    break
                if theta / (1.0 - theta) * conv < 0.03:
                    converged = True
                    break
            prev = conv
        # A Newton iterate may leave the admissible configurations (a wild first update
        # on a stiff contact): that is a failed iteration, handled like any other — the
        # step is retried smaller, and only a step that shrinks to nothing reports it.
        singular_iterate = st == STATUS_SINGULAR
        if not converged:
            if not fresh:
                jac_valid = False
                continue
            counters[CNT_REJECTED] += 1
            h *= 0.25
            continue
        for i in range(n):
            anew[i] = ((1.0 - af) * x[i] + af * acc[i] - am * apse[i]) / (1.0 - am)
            qn[i] = q[i] + h * v[i] + h * h * ((0.5 - bt) * apse[i] + bt * anew[i])
            vn[i] = v[i] + h * ((1.0 - gm) * apse[i] + gm * anew[i])
        # local error estimate from the change of acceleration over the step
        ce_q = h * h * abs(bt - 1.0 / 6.0)
        ce_v = h * (abs(gm - 0.5) + 1.0 / 12.0)
        sq = 0.0
        for i in range(n):
            da = x[i] - acc[i]
            sk_q = atol + rtol * max(abs(q[i]), abs(qn[i]))
            sk_v = atol + rtol * max(abs(v[i]), abs(vn[i]))
            sq += (ce_q * da / sk_q) ** 2 + (ce_v * da / sk_v) ** 2
        e = math.sqrt(sq / n2)
        for i in range(n):
            yout[i] = qn[i]
            yout[n + i] = vn[i]
        if entry_depth > 0.0:
            r_end = entry_depth_ratio(model, ws, yout, contact)
            # A penetration that does not vanish with the step is a jump of the surface
            # (a worn profile between regions), not an impact to resolve: below
            # ``ctl.entry_min_step`` (1e-6 × max_step) the entry is accepted rather than
            # retried forever.
            if r_end > entry_depth and h > ctl.entry_min_step:
                counters[CNT_REJECTED] += 1
                h *= _entry_fraction(model, ws, y, contact, entry_depth, r_end)
                continue
        if nc > 0 and h > ctl.entry_min_step:
            # A journal that moves more than TRAVEL_LIMIT clearances in one step has jumped
            # over its impacts (thrown off a worn flank it can cross the whole bearing and
            # end inside the opposite wall while the contact latch still says "touching",
            # which the entry test does not see): retried with a step that moves it a
            # quarter of that.
            travel = journal_travel_ratio(model, ws, y, yout)
            if travel > TRAVEL_LIMIT:
                counters[CNT_REJECTED] += 1
                h *= max(0.01, 0.25 * TRAVEL_LIMIT / travel)
                continue
        if fixed_step <= 0.0 and not e <= 1.0:
            counters[CNT_REJECTED] += 1
            h *= max(0.2, 0.9 * e ** (-1.0 / 3.0)) if math.isfinite(e) else 0.2
            continue
        # A stale Jacobian shows as Newton iterations beyond the two every step takes
        # (the rods turn, and their axial stiffness turns with them): refresh it once
        # those extra iterations since the last refresh exceed REFRESH_AFTER, which
        # amortises a refresh over the steps it speeds up (docs/ancf.md §8).
        if iters > 2:
            excess += iters - 2
        if excess > REFRESH_AFTER and not fresh:
            jac_valid = False
            # Staleness is the rotation of the stiffness, i.e. of ∂q̈/∂q; the differenced
            # ∂q̈/∂q̇ columns (constraint stabilisation, ∝ h·2α in J) barely change and are
            # kept, which halves the refresh. Clearance joints' velocity derivatives
            # enter the contact correction against the Jacobian's state: refreshed whole.
            stale = nc == 0
        fresh = False
        told = t
        t = t + h
        if t_end - t < 4.0 * _EPS * max(abs(t_end), 1.0):
            t = t_end
        for i in range(n):
            dense[0, i] = q[i]
            dense[0, n + i] = v[i]
            dense[1, i] = qn[i]
            dense[1, n + i] = vn[i]
            dense[2, i] = v[i]
            dense[2, n + i] = acc[i]
            dense[3, i] = vn[i]
            dense[3, n + i] = x[i]
        _after_step(model, ws, out, DENSE_HERMITE, dense, told, t, h, vimp, contact, scratch,
                    yout, out_counters)  # fmt: skip
        if dev is not None:
            dst = _deviation_step(model, dev, t, h, qn, vn, vimp, am, af, gm, bt, cq, cvv, jm,
                                  piv, cc, zb, dq0, dv0, base_contact, cs, sm, spiv,
                                  wv)  # fmt: skip
        for i in range(n):
            q[i] = qn[i]
            v[i] = vn[i]
            apse[i] = anew[i]
            acc[i] = x[i]
        counters[CNT_STEPS] += 1
        changed = False
        for j in range(contact.shape[0]):
            was[j] = contact[j]
        update_latch(model, ws, y, vimp, contact, counters, fixed_step > 0.0)
        for j in range(contact.shape[0]):
            if was[j] != contact[j]:
                changed = True
        if changed and nc == 0:
            # contact stiffness appears or vanishes: the Jacobian is no longer useful
            jac_valid = False
        if projection:
            if not project(model, ws, t, y, 1e-12, 5):
                status = STATUS_SINGULAR
                break
            accelerations(model, ws, t, q, v, vimp, acc, counters)
        if dev is not None:
            if dst != STATUS_OK:
                status = STATUS_SINGULAR if dst == STATUS_SINGULAR else STATUS_NONFINITE
                break
            _deviation_latch(model, dev, y, contact, fixed_step > 0.0)
            dev.growth[DEV_SINCE] += 1.0
            if dev.growth[DEV_SINCE] >= dev.every or t >= t_stop or t >= t_end:
                dst = _deviation_renormalize(model, dev, t, vimp)
                if dst != STATUS_OK:
                    status = STATUS_NONFINITE
                    break
        if fixed_step > 0.0:
            h = fixed_step
        else:
            grow = 2.0 if e < 1e-10 else min(2.0, max(0.2, 0.9 * e ** (-1.0 / 3.0)))
            h *= grow
    state[0] = t
    state[1] = h
    state[2] = 1.0 if jac_valid else 0.0
    state[3] = float(excess)
    state[4] = 1.0 if singular_iterate else 0.0
    flags[JF_BASE_CONTACT] = 1 if base_contact else 0
    flags[JF_LIN_TOUCHING] = 1 if lin_touching else 0
    flags[JF_FRESH] = 1 if fresh else 0
    flags[JF_STALE] = 1 if stale else 0
    return status
