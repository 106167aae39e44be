"""Shared pieces of the compiled time loops (Dormand–Prince in ``_dopri_kernels.py``,
generalized-α in ``_genalpha_kernels.py``): the typed tuples they carry and what they
record after every accepted step.

Both loops run inside numba; the Python layer (``_driver.py``) calls them in chunks, up
to the times of an optional progress bar and for at most ``StepControl.chunk_steps``
attempted steps per call, so that control returns to Python (where a pending Ctrl-C is
raised) however small the steps get. The trajectory does not depend on the chunking or on
what is recorded. A loop takes these typed tuples besides the model and its workspace:

* :class:`StepControl` — the settings of the run (end time, tolerances, step limits, the
  contact-entry test, the generalized-α parameters);
* :class:`LoopState` — what is carried from one chunk to the next: the state
  y = [q; q̇], its derivative (Dormand–Prince, first same as last) or acceleration
  (generalized-α), the pseudo-accelerations, ``step`` (float64[4], see each loop), the
  impact-velocity latch, the contact flags and the counters of ``mechanism.core.model``;
* :class:`Output` — what is recorded after every accepted step (see
  :func:`after_step`): full samples on the output grid (one right-hand-side evaluation
  each), or light samples (crank angle, slider s and ṡ, and the eccentricity of each
  clearance joint, from the dense output, no evaluation), stroboscopic sections located
  on the dense output, and running response metrics at every accepted state.

Status codes are those of :mod:`mechanism.core._status`.
"""

from __future__ import annotations

import math
from typing import (
    Any,
    NamedTuple,
)

import numpy as np
from numba import (
    njit,
)

from mechanism.core._jit import (
    njit_inner,
    njit_noalloc,
)
from mechanism.core._status import (
    STATUS_MAX_STEPS,
    STATUS_OK,
    STATUS_RUNNING,
)
from mechanism.core.joints import (
    update_points,
)
from mechanism.core.model import (
    CJ_DELTA,
    CJ_FN,
    CNT_REJECTED,
    CNT_STEPS,
    accelerations,
    crank_angle,
    derived_outputs,
    entry_depth_ratio,
    light_outputs,
    rhs,
)

__all__ = ["LoopState", "Output", "StepControl"]

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
STROBE_PHASE = 3  # φ of the strobe angles φ + 2πk (for the first target, record_start)
STROBE_SHIFT = 4  # ±2π × the revolutions discarded before the first section (the same)
STROBE_COLUMNS = 5

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
    #: Dormand–Prince: (DOPRI_WORK_ROWS, 2n) scratch (stages, dense output, samples), so
    #: that the loop allocates nothing and compiles without reference counting; (0, 0)
    #: for generalized-α
    work: np.ndarray
    #: int64[CNT_COLUMNS]: the evaluations of the recorded samples (not the run's count)
    tally: np.ndarray


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


EPS = 2.220446049250313e-16


@njit_noalloc(inline="always")
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


@njit_inner()
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


@njit_noalloc(inline="always")
def _crank_at(model, ws, kind, dense, th, h, yout):
    """Crank angle on the dense output at θ (the state is left in ``yout``)."""
    _dense_eval(kind, dense, th, h, yout)
    n = model.n_dof
    update_points(yout[:n], yout[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
    return crank_angle(model, ws.pcf)


@njit(cache=True, inline="always")
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
        tol = 4.0 * EPS * max(1.0, abs(target))
        for _ in range(100):
            if fb <= tol or b - a <= EPS:
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


@njit_noalloc(inline="always")
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


@njit_noalloc(inline="always")
def after_step(model, ws, out, kind, dense, told, t, h, vimp, contact, scratch, yout, counters):
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


@njit_noalloc(inline="always")
def record_start(model, ws, out, t0, y, vimp, scratch, counters):
    """Record what ``out`` asks for at the initial state ``y`` at ``t0``: the first grid
    sample, and the first strobe angle φ + 2πk at or after ``out.strobe[STROBE_SHIFT]``
    (± the discarded revolutions) from the initial crank angle, with a section at ``t0``
    when the initial crank angle is one. ``counters`` receive the evaluations of the
    samples (pass others than the run's to keep them out of its count). What
    ``_driver.loop_output`` records from Python, here inside the loop's first call so that
    no recording kernel is called from Python (each such kernel compiles on its own, with
    everything it calls)."""
    mode = out.mode
    if mode & REC_FULL:
        record_sample(model, ws, out.rec, 0, t0, y, vimp, scratch, counters)
    else:
        light_outputs(model, ws, y, out.light[0])
    out.cursor[0] = 1
    if mode & REC_SECTIONS:
        strobe = out.strobe
        n = model.n_dof
        update_points(y[:n], y[n:], model.pt_i, model.pt_f, ws.pci, ws.pcf)
        start = crank_angle(model, ws.pcf)  # as light_outputs
        sense = strobe[STROBE_DIRECTION]
        phase = strobe[STROBE_PHASE]
        two_pi = 2.0 * math.pi
        first = start + strobe[STROBE_SHIFT] - phase
        if sense > 0:
            turns = math.ceil(first / two_pi - 1e-9)
        else:
            turns = math.floor(first / two_pi + 1e-9)
        target = phase + two_pi * turns
        if abs(target - start) <= 1e-9:
            record_sample(model, ws, out.sections, 0, t0, y, vimp, scratch, counters)
            out.cursor[1] = 1
            target += sense * two_pi
        strobe[STROBE_TARGET] = target
        strobe[STROBE_ANGLE] = start


@njit_noalloc(inline="always")
def entry_fraction(model, ws, y, contact, entry_depth, r_end):
    """Fraction of a step that entered contact too deep to retry with: the step at which
    the penetration, interpolated linearly from the start of the step, is half the
    allowed entry depth, so one retry lands inside the contact (a fixed fraction could
    approach a slowly closing gap, a worn flank, in ever shorter steps)."""
    r_start = entry_depth_ratio(model, ws, y, contact)
    frac = 0.3
    if r_start < 0.5 * entry_depth:
        frac = (0.5 * entry_depth - r_start) / (r_end - r_start)
    return min(0.9, max(0.01, frac))


@njit_noalloc(inline="always")
def chunk_end(t, t_end, t_stop, counters, max_steps, chunk_steps, attempted):  # type: ignore[no-untyped-def]
    """Whether a compiled loop stops before its next step, and with which status.

    (True, ``STATUS_OK``) at the end of the interval; (True, ``STATUS_RUNNING``) at a stop
    time or after ``chunk_steps`` attempted steps of this call (back to Python, which
    checks for Ctrl-C and calls again); (True, ``STATUS_MAX_STEPS``) at the step cap;
    (False, ``STATUS_RUNNING``) to go on. ``attempted``: steps attempted before this call.
    """
    if t >= t_end:
        return True, STATUS_OK
    if t >= t_stop:
        return True, STATUS_RUNNING
    done = counters[CNT_STEPS] + counters[CNT_REJECTED]
    if done >= max_steps:
        return True, STATUS_MAX_STEPS
    if 0 < chunk_steps <= done - attempted:
        return True, STATUS_RUNNING
    return False, STATUS_RUNNING


@njit_noalloc(inline="always")
def next_step_size(accepted, e, h, fac11, facold, beta, last_rejected):  # type: ignore[no-untyped-def]
    """(h, facold, last_rejected) after a step of the stabilised (PI) step-size control of
    Hairer, Nørsett & Wanner (Solving ODEs I, §II.4, DOPRI5): ``e`` the error norm,
    ``fac11`` = e**(0.2 − 0.75·beta); after a rejection the step may not grow."""
    if accepted:
        fac = fac11 / facold**beta
        fac = max(0.1, min(5.0, fac / 0.9))
        hnew = h / fac
        if last_rejected:
            hnew = min(hnew, h)
        return hnew, max(e, 1e-4), False
    return h / min(5.0, fac11 / 0.9), facold, True
