"""Step-size control of the rigid integrator: where its rejected steps go, and variants.

The Dormand–Prince loop of ``simulate`` (``mechanism.core.integrate._dopri_kernels``)
controls its step as Hairer's DOPRI5 does (PI controller, β = 0.04, safety 0.9, growth
≤ 10, no growth right after a rejection). This script runs the rigid ``paper`` scene and
the clearance slider-crank with that controller and with variants of it, side by side in
one process (alternated, the smallest CPU time of the repetitions), and writes
``docs/benchmarks/step-control.csv``:

* cost rows (``rtol`` = the scene's): accepted and rejected steps, right-hand sides and CPU
  time per revolution (per second for the slider-crank) of ``simulate`` with
  ``record=SectionsRecord(companion=False)``, on the unworn scene at 150 and 30 rpm and on
  the scene worn for 5000 cycles at 60 and 150 rpm (the bearing and journal wear depths
  the wear-life map ``docs/benchmarks/wear-life-speed.nc`` holds for that speed and
  checkpoint);
* accuracy rows (rtol = atol = 1e-5, 1e-6, 1e-7): the largest slider-position difference
  from a reference run (rtol = atol = 1e-9, the controller in use) over the first
  revolution at 30 rpm, and the time and the peak contact force of the first impact of
  the clearance slider-crank (μ = 0.1), located between the output samples, against its
  reference.

The variants run in a copy of the library's loop that takes the controller's parameters
(:func:`_advance`), swapped in for the library's entry point; the copy with the library's
parameters (``current``) reproduces the library's counts exactly, which the script checks
before it measures. The copy keeps its controller memory within one call of the loop (one
chunk of ``chunk_steps`` attempted steps), the library's kernel across calls. Run with

    NUMBA_NUM_THREADS=1 python benchmarks/step_control.py [--repeats 2]

Results and conclusions: ``docs/performance.md``, *Step control*.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import time
from pathlib import Path

import numpy as np
import xarray as xr

import mechanism
from chaoskit.contract import atomic_write
from mechanism.core._jit import njit_noalloc
from mechanism.core._status import (
    STATUS_OK,
    STATUS_RUNNING,
    STATUS_SINGULAR,
    STATUS_STEP_TOO_SMALL,
)
from mechanism.core.integrate import _dopri_kernels as dk
from mechanism.core.integrate._step_kernels import (
    DENSE_DOPRI5,
    EPS,
    after_step,
    chunk_end,
    entry_fraction,
    record_start,
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

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
CSV = OUT / "step-control.csv"
MAP = OUT / "wear-life-speed.nc"

# columns of a controller's parameter vector
P_EXPO, P_BETA, P_SAFETY, P_GROW, P_NO_GROWTH, P_REJECT, P_CAP, P_RELAX, P_GROW_AFTER = range(9)
REJECT_HAIRER, REJECT_ORDER, REJECT_ORDER_MEMORY = 0.0, 1.0, 2.0


def controller(beta=0.04, **options):
    """Parameter vector: Hairer's PI controller with ``beta``, changed by ``options``."""
    par = np.array([0.2 - 0.75 * beta, beta, 0.9, 10.0, 1.0, REJECT_HAIRER, 0.0, 0.0, 0.0])
    names = {
        "safety": P_SAFETY, "grow": P_GROW, "no_growth": P_NO_GROWTH, "reject": P_REJECT,
        "cap": P_CAP, "relax": P_RELAX, "grow_after": P_GROW_AFTER,
    }  # fmt: skip
    for key, value in options.items():
        par[names[key]] = value
    return par


#: name → (what differs from the controller in use, parameters)
CONTROLLERS = {
    "current": ("Hairer's DOPRI5: PI, beta 0.04, safety 0.9, growth <= 10", controller()),
    "pi-0.08": ("PI beta 0.08 (Gustafsson's PI.4.2: exponents 0.14, 0.08)", controller(0.08)),
    "pi-0.10": ("PI beta 0.10", controller(0.10)),
    "growth-5": ("growth <= 5 per step", controller(grow=5.0)),
    "growth-after-reject": ("the step may grow right after a rejection", controller(no_growth=0.0)),
    "stability-cap": (
        "step <= 3/rho, rho = |k7-k6|/|y7-y6| (Hairer's stiffness estimate)",
        controller(cap=3.0),
    ),
    "order-after-reject": (
        "2nd rejection in a row: h (0.9/e)^(1/p), p in [1, 5] from the two errors",
        controller(reject=REJECT_ORDER),
    ),
    "order-memory": (
        "as order-after-reject, p kept (back to 5 by 0.5 per accepted step) for the first "
        "rejection; growth <= 2 after a rejection, doubling per accepted step",
        controller(reject=REJECT_ORDER_MEMORY, relax=0.5, grow_after=2.0),
    ),
}
ACCURACY_CONTROLLERS = ["current", "pi-0.08", "order-after-reject", "order-memory"]
TOLERANCES = [1e-5, 1e-6, 1e-7]
FIELDS = [
    "case", "controller", "change", "rtol", "per", "accepted", "rejected", "rhs", "cpu_s", "error",
    "error_measure",
]  # fmt: skip


@njit_noalloc(inline="always")
def _rejected_step(par, h, e, fac11, last_rejected, e_prev, h_prev, p_mem):
    """(h, p_mem) after a rejected step of error ``e`` (``e_prev``, ``h_prev``: the
    rejected step before it at the same time, when ``last_rejected``)."""
    safety = par[P_SAFETY]
    rule = par[P_REJECT]
    again = last_rejected and e_prev > 0.0 and h_prev > h and e < e_prev
    if rule == REJECT_HAIRER or (rule == REJECT_ORDER and not again):
        return h / min(5.0, fac11 / safety), p_mem
    p = p_mem if rule == REJECT_ORDER_MEMORY else 5.0
    if again:
        # the order the error shows between two tries: near 1 where a stiff contact or
        # friction term, not the method's truncation error, sets it
        p = min(5.0, max(1.0, math.log(e_prev / e) / math.log(h_prev / h)))
    return h * max(0.1, min(0.9, safety * e ** (-1.0 / p))), p


@njit_noalloc(nogil=True)
def _advance(model, ws, loop, out, ctl, t_stop, par):
    """``dk.dopri5_advance`` with the step-size controller of ``par`` (see
    :func:`controller`); the integration, the contact-entry test and the recording are
    the library's."""
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
    work = loop.work
    k2, k3, k4, k5, k6, k7 = work[0], work[1], work[2], work[3], work[4], work[5]
    ytmp, ynew, err, dense, yout, scratch = (
        work[6],
        work[7],
        work[8],
        work[9:14],
        work[14],
        work[15],
    )
    if loop.step[3] < 0.0:
        record_start(model, ws, out, loop.step[0], y, vimp, scratch, loop.tally)
        started = dk.dopri5_start(model, ws, loop.step[0], y, k1, vimp, loop.step, counters,
                                  rtol, atol, max_step, work[16], work[17])  # fmt: skip
        if started != STATUS_RUNNING:
            return started
    beta = par[P_BETA]
    expo1 = par[P_EXPO]
    safety = par[P_SAFETY]
    e_prev, h_prev, p_mem, grow = -1.0, 0.0, 5.0, par[P_GROW]
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
            ytmp[i] = y[i] + h * dk.A21 * k1[i]
        st = min(st, rhs(model, ws, t + dk.C2 * h, ytmp, vimp, k2, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (dk.A31 * k1[i] + dk.A32 * k2[i])
        st = min(st, rhs(model, ws, t + dk.C3 * h, ytmp, vimp, k3, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (dk.A41 * k1[i] + dk.A42 * k2[i] + dk.A43 * k3[i])
        st = min(st, rhs(model, ws, t + dk.C4 * h, ytmp, vimp, k4, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (dk.A51 * k1[i] + dk.A52 * k2[i] + dk.A53 * k3[i] + dk.A54 * k4[i])
        st = min(st, rhs(model, ws, t + dk.C5 * h, ytmp, vimp, k5, counters))
        for i in range(n2):
            ytmp[i] = y[i] + h * (
                dk.A61 * k1[i] + dk.A62 * k2[i] + dk.A63 * k3[i] + dk.A64 * k4[i]
                + dk.A65 * k5[i]
            )  # fmt: skip
        st = min(st, rhs(model, ws, t + h, ytmp, vimp, k6, counters))
        for i in range(n2):
            ynew[i] = y[i] + h * (
                dk.A71 * k1[i] + dk.A73 * k3[i] + dk.A74 * k4[i] + dk.A75 * k5[i]
                + dk.A76 * k6[i]
            )  # fmt: skip
        st = min(st, rhs(model, ws, t + h, ynew, vimp, k7, counters))
        if st != STATUS_OK:
            status = STATUS_SINGULAR
            break
        for i in range(n2):
            err[i] = h * (
                dk.E1 * k1[i] + dk.E3 * k3[i] + dk.E4 * k4[i] + dk.E5 * k5[i] + dk.E6 * k6[i]
                + dk.E7 * k7[i]
            )  # fmt: skip
        e = dk.wrms(err, y, ynew, rtol, atol)
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
        # Hairer's stiffness estimate |λ| ≈ |k7 − k6| / |y7 − y6| (ytmp: the 6th stage)
        num = 0.0
        den = 0.0
        for i in range(n2):
            num += (k7[i] - k6[i]) ** 2
            den += (ynew[i] - ytmp[i]) ** 2
        rho = math.sqrt(num / den) if den > 0.0 else 0.0
        if e <= 1.0:
            for i in range(n2):
                d = ynew[i] - y[i]
                b = h * k1[i] - d
                dense[0, i] = y[i]
                dense[1, i] = d
                dense[2, i] = b
                dense[3, i] = d - h * k7[i] - b
                dense[4, i] = h * (
                    dk.D1 * k1[i] + dk.D3 * k3[i] + dk.D4 * k4[i] + dk.D5 * k5[i]
                    + dk.D6 * k6[i] + dk.D7 * k7[i]
                )  # fmt: skip
            told = t
            t = t + h
            if t_end - t < 4.0 * EPS * max(abs(t_end), 1.0):
                t = t_end
            after_step(model, ws, out, DENSE_DOPRI5, dense, told, t, h, vimp, contact, scratch,
                       yout, loop.tally)  # fmt: skip
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
            fac = max(1.0 / grow, min(5.0, fac / safety))
            hnew = h / fac
            if par[P_NO_GROWTH] > 0.0 and last_rejected:
                hnew = min(hnew, h)
            if par[P_CAP] > 0.0 and rho > 0.0:
                hnew = min(hnew, max(par[P_CAP] / rho, 0.2 * h))
            grow = min(par[P_GROW], 2.0 * grow)
            p_mem = min(5.0, p_mem + par[P_RELAX])
            h = hnew
            facold = max(e, 1e-4)
            last_rejected = False
        else:
            counters[CNT_REJECTED] += 1
            h_rej = h
            h, p_mem = _rejected_step(par, h, e, fac11, last_rejected, e_prev, h_prev, p_mem)
            if par[P_GROW_AFTER] > 0.0:
                grow = par[P_GROW_AFTER]
            e_prev = e
            h_prev = h_rej
            last_rejected = True
    loop.step[0] = t
    loop.step[1] = h
    loop.step[2] = facold
    loop.step[3] = 1.0 if last_rejected else 0.0
    return status


LIBRARY = dk.dopri5_advance


def use(name: str | None) -> None:
    """Run ``simulate`` with controller ``name`` (None: the library's kernel)."""
    if name is None:
        dk.dopri5_advance = LIBRARY
        return
    par = CONTROLLERS[name][1]
    dk.dopri5_advance = lambda km, ws, loop, out, ctl, stop: _advance(
        km, ws, loop, out, ctl, stop, par
    )


def rigid_paper(rpm: float, worn_cycles: float = 0.0) -> mechanism.Scene:
    """The rigid ``paper`` scene at ``rpm``, worn as the wear-life map's path at that
    speed was at ``worn_cycles`` (0: unworn)."""
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    if worn_cycles <= 0.0:
        return scene
    with xr.open_dataset(MAP) as life:
        depth = life.wear_depth.sel(value=rpm, checkpoint=worn_cycles, joint="C").values
    return scene.replace({
        "effects.wear": True,
        "joints.C.wear.bearing_profile": [float(x) for x in depth[0]],
        "joints.C.wear.journal_profile": [float(x) for x in depth[1]],
    })  # fmt: skip


def slider_crank() -> mechanism.Scene:
    return mechanism.load_scene("slider-crank-clearance").replace(
        {"joints.B.friction.coefficient": 0.1}
    )


SECTIONS = mechanism.SectionsRecord(companion=False)
COST_CASES = {
    "paper 150 rpm unworn": (lambda: rigid_paper(150.0), {"revolutions": 6}),
    "paper 30 rpm unworn": (lambda: rigid_paper(30.0), {"revolutions": 4}),
    "paper 60 rpm worn 5000 cycles": (lambda: rigid_paper(60.0, 5000.0), {"revolutions": 3}),
    "paper 150 rpm worn 5000 cycles": (lambda: rigid_paper(150.0, 5000.0), {"revolutions": 4}),
    "slider-crank clearance": (slider_crank, {"t_end": 0.05}),
}


def _per(ds: xr.Dataset, span: dict) -> tuple[str, float]:
    if "revolutions" in span:
        return "revolution", float(span["revolutions"])
    return "s", float(span["t_end"])


def _row(case, name, ds, span, cpu, error="", measure="") -> dict:
    """A row of the table: the counters of ``ds`` and ``cpu`` per revolution or second."""
    per, n = _per(ds, span)
    a = ds.attrs
    return {
        "case": case, "controller": name, "change": CONTROLLERS[name][0], "rtol": a["rtol"],
        "per": per, "accepted": a["solver_steps"] / n,
        "rejected": a["solver_rejected_steps"] / n, "rhs": a["solver_function_evaluations"] / n,
        "cpu_s": cpu / n, "error": error, "error_measure": measure,
    }  # fmt: skip


def cost_rows(repeats: int) -> list[dict]:
    scenes = {case: (make(), span) for case, (make, span) in COST_CASES.items()}
    # the copy with the library's parameters must take the library's steps
    scene, span = scenes["paper 150 rpm unworn"]
    counts = []
    for name in (None, "current"):
        use(name)
        ds = mechanism.simulate(scene, record=SECTIONS, revolutions=1)
        counts.append((ds.attrs["solver_steps"], ds.attrs["solver_rejected_steps"]))
    if counts[0] != counts[1]:
        raise SystemExit(f"the loop's copy differs from the library's: {counts}")
    found: dict[tuple[str, str], list] = {}
    for _ in range(repeats):
        for name in CONTROLLERS:
            use(name)
            for case, (scene, span) in scenes.items():
                start = time.process_time()
                ds = mechanism.simulate(scene, record=SECTIONS, **span)
                cpu = time.process_time() - start
                row = found.setdefault((case, name), [ds, []])
                row[1].append(cpu)
    use(None)
    rows = []
    for (case, name), (ds, cpus) in found.items():
        rows.append(_row(case, name, ds, scenes[case][1], min(cpus)))
    return rows


def _first_impact(ds: xr.Dataset, clearance: float) -> tuple[float, float]:
    """Time and peak contact force of the first impact, between the output samples: the
    time where |e| − c crosses zero (linear), the peak of the parabola through the largest
    sample and its neighbours."""
    t = ds.time.values
    ecc = ds.isel(joint=0)
    depth = np.hypot(ecc.eccentricity_x.values, ecc.eccentricity_y.values) - clearance
    force = ds.contact_force.isel(joint=0).values
    first = int(np.argmax(depth > 0.0))
    hit = t[first - 1] + (t[first] - t[first - 1]) * (-depth[first - 1]) / (
        depth[first] - depth[first - 1]
    )
    after = first + int(np.argmax(force[first:] <= 0.0))
    k = first + int(np.argmax(force[first:after]))
    f0, f1, f2 = force[k - 1], force[k], force[k + 1]
    curve = f0 - 2.0 * f1 + f2
    peak = f1 - 0.125 * (f2 - f0) ** 2 / curve if curve < 0.0 else f1
    return float(hit), float(peak)


def accuracy_rows(repeats: int) -> list[dict]:
    paper, crank = rigid_paper(30.0), slider_crank()
    use(None)
    ref = mechanism.simulate(paper, revolutions=1, rtol=1e-9, atol=1e-9)
    clearance = crank.joints["B"].clearance
    reference = mechanism.simulate(crank, t_end=0.01, rtol=1e-9, atol=1e-9)
    hit_ref, peak_ref = _first_impact(reference, clearance)
    rows = []
    for tol in TOLERANCES:
        for name in ACCURACY_CONTROLLERS:
            use(name)
            for case, scene, span in (("paper 30 rpm unworn, revolution 1", paper,
                                       {"revolutions": 1}),
                                      ("slider-crank clearance, first impact", crank,
                                       {"t_end": 0.01})):  # fmt: skip
                cpus = []
                for _ in range(repeats):
                    start = time.process_time()
                    ds = mechanism.simulate(scene, rtol=tol, atol=tol, **span)
                    cpus.append(time.process_time() - start)
                if "revolutions" in span:
                    error = float(abs(ds.slider_position - ref.slider_position).max())
                    rows.append(_row(case, name, ds, span, min(cpus), f"{error:.3e}",
                                     "max |slider position - reference| (m)"))  # fmt: skip
                    continue
                hit, peak = _first_impact(ds, clearance)
                rows.append(_row(case, name, ds, span, min(cpus), f"{abs(hit - hit_ref):.3e}",
                                 "|time - reference| (s), first impact"))  # fmt: skip
                rows.append(_row(case, name, ds, span, min(cpus),
                                 f"{abs(peak - peak_ref) / peak_ref:.3e}",
                                 "|peak force - reference| / reference, first impact"))  # fmt: skip
    use(None)
    return rows


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=2, help="timed runs per cell (min)")
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error(f"--repeats must be ≥ 1; got {args.repeats}")
    mechanism.simulate(rigid_paper(150.0), revolutions=0.02, record=SECTIONS)  # compile
    use("current")
    mechanism.simulate(rigid_paper(150.0), revolutions=0.02, record=SECTIONS)
    rows = cost_rows(args.repeats) + accuracy_rows(args.repeats)
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=FIELDS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _fmt(v) for k, v in row.items()})
    body = text.getvalue()
    atomic_write(CSV, lambda tmp: tmp.write_text(body, encoding="utf-8"))
    print(body)


if __name__ == "__main__":
    main()
