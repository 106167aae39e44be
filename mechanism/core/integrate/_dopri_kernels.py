"""Compiled Dormand–Prince 5(4) loop with dense output (the default integrator).

:func:`dopri5_advance` is the one entry point of a run: its first call (``loop.step[3]``
< 0) records the initial state, evaluates k1 = f(t₀, y₀) and the starting step
(:func:`dopri5_start`), every call advances a chunk of steps. The typed tuples it takes
and the recording after every accepted step are in ``_step_kernels.py``. The Butcher
tableau and :func:`wrms` are shared with the tangent integration of
``_tangent_kernels.py``.

Why one entry point: numba links the code of every kernel a kernel calls into its own
module and optimises and emits the whole module again, once per compiled kernel, and
gives every kernel wrappers for calls from Python. The start, the initial step and the
recording are therefore inlined at numba's IR level (``inline="always"``) rather than
compiled as kernels of their own (``docs/performance.md``, *Compiling*);
:func:`initial_step` stays a kernel for the tangent integration, which calls it from
Python.
"""

from __future__ import annotations

import math

import numpy as np
from numba import (
    njit,
)

from mechanism.core._jit import (
    njit_inner,
    njit_noalloc,
)
from mechanism.core._status import (
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.model import (
    CNT_REJECTED,
    CNT_STEPS,
    approach_step,
    entry_depth_ratio,
    project,
    rhs,
    update_latch,
)

from ._step_kernels import (
    DENSE_DOPRI5,
    EPS,
    after_step,
    chunk_end,
    entry_fraction,
    next_step_size,
    record_start,
)

__all__: list[str] = []


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


@njit_inner()
def wrms(err, y0, y1, rtol, atol):
    """Weighted RMS norm of the error estimate ``err``, each component scaled by
    ``atol + rtol·max(|y0|, |y1|)`` (≤ 1 accepts the step)."""
    s = 0.0
    n = err.shape[0]
    for i in range(n):
        sk = atol + rtol * max(abs(y0[i]), abs(y1[i]))
        e = err[i] / sk
        s += e * e
    return math.sqrt(s / n)


#: rows of ``LoopState.work`` of the Dormand–Prince loop: stages k2…k7, the stage state,
#: the new state, the error, the five rows of the dense output, the sample state and its
#: derivative, and the two states of the initial step
DOPRI_WORK_ROWS = 18


@njit(cache=True)
def initial_step(model, ws, t, y, f0, vimp, counters, rtol, atol, max_step):
    """Starting step size in the manner of Hairer's HINIT (order 5)."""
    n2 = y.shape[0]
    return _initial_step(model, ws, t, y, f0, vimp, counters, rtol, atol, max_step,
                         np.empty(n2), np.empty(n2))  # fmt: skip


@njit_noalloc(inline="always")
def _initial_step(model, ws, t, y, f0, vimp, counters, rtol, atol, max_step, y1, f1):
    """:func:`initial_step` with its two scratch states ``y1``, ``f1`` given."""
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


@njit_noalloc(inline="always")
def dopri5_start(model, ws, t, y, k1, vimp, step, counters, rtol, atol, max_step, y1, f1):
    """Evaluate k1 = f(t, y) and the starting step into ``step`` (a ``LoopState.step``);
    returns a status. Inlined into :func:`dopri5_advance`, which calls it on its first
    call."""
    status = rhs(model, ws, t, y, vimp, k1, counters)
    if status != STATUS_OK:
        return status
    step[0] = t
    if step[1] <= 0.0:
        step[1] = _initial_step(model, ws, t, y, k1, vimp, counters, rtol, atol, max_step, y1,
                                f1)  # fmt: skip
    step[2] = 1e-4
    step[3] = 0.0
    return STATUS_RUNNING


@njit_noalloc(nogil=True)
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

    Compiled without reference counting: it allocates nothing, its scratch is
    ``loop.work`` (``DOPRI_WORK_ROWS`` × 2n). The first call of a run (``loop.step`` =
    [t₀, h₀ or 0, ·, −1]) starts it first: the samples of the initial state
    (``_step_kernels.record_start``; the Output comes from ``loop_output(...,
    in_kernel=True)``), then k1 = f(t₀, y₀) into ``loop.f`` and, unless h₀ > 0, the
    starting step of :func:`initial_step`; a failure there is returned before any step.
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
    # scratch from the caller (LoopState.work), so that the loop allocates nothing
    work = loop.work
    k2 = work[0]
    k3 = work[1]
    k4 = work[2]
    k5 = work[3]
    k6 = work[4]
    k7 = work[5]
    ytmp = work[6]
    ynew = work[7]
    err = work[8]
    dense = work[9:14]
    yout = work[14]
    scratch = work[15]
    out_counters = loop.tally
    if loop.step[3] < 0.0:
        # the run's first call: the start's samples, then k1 and the first step
        record_start(model, ws, out, loop.step[0], y, vimp, scratch, out_counters)
        started = dopri5_start(model, ws, loop.step[0], y, k1, vimp, loop.step, counters,
                               rtol, atol, max_step, work[16], work[17])  # fmt: skip
        if started != STATUS_RUNNING:
            return started
    beta = 0.04
    expo1 = 0.2 - beta * 0.75
    t = loop.step[0]
    h = loop.step[1]
    facold = loop.step[2]
    last_rejected = loop.step[3] > 0.0
    attempted = counters[CNT_STEPS] + counters[CNT_REJECTED]
    status = STATUS_RUNNING
    while True:
        stop, status = chunk_end(
            t, t_end, t_stop, counters, ctl.max_steps, ctl.chunk_steps, attempted
        )
        if stop:
            break
        h = min(h, max_step)
        if ctl.approach_floor > 0.0:
            near = approach_step(model, ws, y, k1[n2 // 2 :], ctl.approach_fraction)
            h = min(h, max(ctl.approach_floor, near))
        if t + 1.01 * h >= t_end:
            h = t_end - t
        if h < 10.0 * EPS * max(abs(t), 1e-300) or h <= 0.0:
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
        e = wrms(err, y, ynew, rtol, atol)
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
                h *= entry_fraction(model, ws, y, contact, ctl.entry_depth, r_end)
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
            if t_end - t < 4.0 * EPS * max(abs(t_end), 1.0):
                t = t_end
            after_step(model, ws, out, DENSE_DOPRI5, dense, told, t, h, vimp, contact, scratch,
                        yout, out_counters)  # fmt: skip
            for i in range(n2):
                y[i] = ynew[i]
                k1[i] = k7[i]
            counters[CNT_STEPS] += 1
            # np.bool_: a plain bool, as the generalized-α loop and the Python start pass
            # (a literal False would compile another signature)
            update_latch(model, ws, y, vimp, contact, counters, np.bool_(False))
            if ctl.projection:
                if not project(model, ws, t, y, 1e-12, 5):
                    status = STATUS_SINGULAR
                    break
                rhs(model, ws, t, y, vimp, k1, counters)
            h, facold, last_rejected = next_step_size(
                True, e, h, fac11, facold, beta, last_rejected
            )
        else:
            counters[CNT_REJECTED] += 1
            h, facold, last_rejected = next_step_size(
                False, e, h, fac11, facold, beta, last_rejected
            )
    loop.step[0] = t
    loop.step[1] = h
    loop.step[2] = facold
    loop.step[3] = 1.0 if last_rejected else 0.0
    return status
