"""Accuracy against cost of the flexible exponent's Newton test: the perturbed copy's
``newton_tolerance`` of :func:`mechanism.core.integrate.integrate_tangent_flexible`.

The flexible ``paper`` scene (ANCF rods, generalized-α at T/10000) at 150 rpm (chaotic)
and 30 rpm (regular), the deviation set up as :func:`mechanism.lyapunov_exponent` sets it
(ε = 1e-7 of the length scale, seed 0, τ = T/2π). The growth is read at every revolution;
each revolution after ``--discard`` gives one exponent, and the row holds their mean and
95 % Student interval, the copy's Newton iterations per step, its unconverged steps and
the CPU time per revolution (``time.process_time``, after a warm-up that compiles).
Rows are appended to ``docs/benchmarks/copy-tolerance.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/copy_tolerance.py [--rpm 150 --rpm 30]
        [--tolerance 1e-6 --tolerance 3e-4 ...] [--revolutions 6 --discard 1]
"""

from __future__ import annotations

import argparse
import csv
import datetime
import math
import time
from pathlib import Path

import numpy as np
from scipy import stats

import mechanism
from mechanism.core import default_step, drive_period, step_limits
from mechanism.core.integrate import (
    StepSettings,
    TangentSettings,
    initial_deviation,
    integrate_tangent_flexible,
    length_scale,
    resolve_method,
)
from mechanism.core.model import assemble, initial_state

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "copy-tolerance.csv"
FIELDS = [
    "date", "rpm", "newton_tolerance", "revolutions", "discard", "exponent", "ci_low",
    "ci_high", "newton_per_step", "unconverged_steps", "steps", "cpu_s_per_revolution",
]  # fmt: skip
PERTURBATION = 1e-7


def run(rpm: float, tolerance: float, revolutions: int, discard: int) -> dict:
    """One exponent of the flexible paper scene at ``rpm`` with the copy's Newton test at
    ``tolerance``."""
    scene = mechanism.load_scene("paper").replace({"drive.speed_rpm": rpm})
    model = assemble(scene)
    method = resolve_method(scene.solver.method, model)
    period = drive_period(scene)
    t_end = revolutions * period
    max_step, floor = step_limits(model, method, default_step(scene, t_end))
    q0, v0 = initial_state(model)
    y0 = np.concatenate([q0, v0])
    tau = period / (2.0 * math.pi)
    size = PERTURBATION * length_scale(model, y0)
    d0 = initial_deviation(model, y0, t0=0.0, size=size, time_scale=tau, seed=0)
    steps = StepSettings(
        rtol=scene.solver.rtol, atol=scene.solver.atol, max_step=max_step, approach_floor=floor
    )
    cpu = time.process_time()
    out = integrate_tangent_flexible(
        model, y0, d0, period * np.arange(revolutions + 1), method=method,
        settings=TangentSettings(steps=steps, time_scale=tau), newton_tolerance=tolerance,
    )  # fmt: skip
    cpu = time.process_time() - cpu
    rates = np.diff(out.log_growth)[discard:] / np.diff(out.t)[discard:]
    half = stats.t.ppf(0.975, rates.size - 1) * rates.std(ddof=1) / math.sqrt(rates.size)
    return {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "rpm": rpm, "newton_tolerance": tolerance, "revolutions": revolutions,
        "discard": discard, "exponent": round(float(rates.mean()), 4),
        "ci_low": round(float(rates.mean() - half), 4),
        "ci_high": round(float(rates.mean() + half), 4),
        "newton_per_step": round(out.newton_iterations / out.stats.steps, 3),
        "unconverged_steps": out.unconverged_steps, "steps": out.stats.steps,
        "cpu_s_per_revolution": round(cpu / revolutions, 4),
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, action="append")
    parser.add_argument("--tolerance", type=float, action="append")
    parser.add_argument("--revolutions", type=int, default=6)
    parser.add_argument("--discard", type=int, default=1)
    parser.add_argument("--csv", default=str(OUT))
    args = parser.parse_args()
    if args.revolutions - args.discard < 2:
        parser.error("--revolutions must exceed --discard by at least 2")
    run(150.0, 3e-4, 1, 0)  # compile / load the kernels
    path = Path(args.csv)
    new = not path.exists()
    for rpm in args.rpm or [150.0, 30.0]:
        for tolerance in args.tolerance or [1e-6, 1e-4, 3e-4, 1e-3]:
            row = run(rpm, tolerance, args.revolutions, args.discard)
            print(row, flush=True)
            with path.open("a", newline="") as fh:
                writer = csv.DictWriter(fh, fieldnames=FIELDS)
                if new:
                    writer.writeheader()
                    new = False
                writer.writerow(row)


if __name__ == "__main__":
    main()
