"""Continuation of the period-1 orbit of the rigid ``paper`` scene over crank speed: its
cost, its bifurcations, the route to chaos, and the accuracy of a located point against
the step and the shooting tolerance.

``sweep`` follows the orbit from ``--start`` to ``--stop`` rpm (process CPU time of one
process, ``NUMBA_NUM_THREADS=1``), writes the Dataset to
``docs/benchmarks/continuation-speed.nc``, one cost row to
``docs/benchmarks/continuation-cost.csv``, the route against the chaotic windows of
``docs/benchmarks/bifurcation-speed-exponent.nc`` to stdout and the overlay figure to
``docs/benchmarks/continuation-speed.png``. ``accuracy`` repeats a short span with each
step and shooting tolerance and writes ``docs/benchmarks/continuation-accuracy.csv``: the
first located point and its distance to the finest run's::

    NUMBA_NUM_THREADS=1 python benchmarks/continuation.py sweep [--start 30 --stop 300]
    NUMBA_NUM_THREADS=1 python benchmarks/continuation.py accuracy --start 60 --stop 75
"""

from __future__ import annotations

import argparse
import csv
import logging
import sys
import time
from pathlib import Path

import xarray as xr

import mechanism
from chaoskit.contract import atomic_write

DOCS = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
DIAGRAM = DOCS / "bifurcation-speed-exponent.nc"
KEY = "drive.speed_rpm"


def rigid_scene() -> mechanism.Scene:
    return mechanism.load_scene("paper").replace({"effects.flexibility": False})


def run(start: float, stop: float, step: float, locate: float, tol: float | None):
    settings = mechanism.ContinuationSettings(
        step=step, min_step=step / 64, max_step=4 * step, locate_tolerance=locate,
        shooting_tolerance=tol, max_period=2, easy_iterations=5, max_iterations=8,
        segments=1,
    )  # fmt: skip
    cpu = time.process_time()
    c = mechanism.continuation(rigid_scene(), parameter=KEY, span=(start, stop), settings=settings)
    return c, time.process_time() - cpu


def write_csv(path: Path, rows: list[dict]) -> None:
    def write(target: Path) -> None:
        with target.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(path, write)


def sweep(args: argparse.Namespace) -> None:
    c, cpu = run(args.start, args.stop, args.step, args.locate, None)
    ds = c.to_dataset()
    atomic_write(DOCS / "continuation-speed.nc", lambda p: ds.to_netcdf(p))
    points = sum(len(b.points) for b in c.branches)
    row = {
        "start_rpm": args.start, "stop_rpm": args.stop, "step_rpm": args.step,
        "locate_rpm": args.locate, "cpu_s": round(cpu, 1), "orbit_solves": c.orbit_solves,
        "points": points, "branches": len(c.branches), "bifurcations": len(c.bifurcations),
    }  # fmt: skip
    write_csv(DOCS / "continuation-cost.csv", [row])
    print(row)
    for b in c.branches:
        print(f"branch period {b.period} {b.origin}: {b.parameter[0]:.2f}-{b.parameter[-1]:.2f} "
              f"rpm, {len(b.points)} points, end: {b.end}")  # fmt: skip
    for bif in c.bifurcations:
        where = "end of branch" if bif.branch_end else "on branch"
        print(f"{bif.kind} ({where} {bif.branch}) at {bif.parameter:.3f} rpm {bif.bracket}: "
              f"{bif.explanation}")  # fmt: skip
    diagram = xr.open_dataset(DIAGRAM)
    r = mechanism.route(c, diagram)
    print("\n".join(r.lines()))
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        axes = mechanism.plot_bifurcation(diagram, continuation=c)
        axes[0].figure.savefig(DOCS / "continuation-speed.png", dpi=160)


def accuracy(args: argparse.Namespace) -> None:
    rows = []
    runs = [(s, t) for t in (1e-7, 1e-9) for s in (4.0, 2.0, 1.0)]
    results = []
    for step, tol in runs:
        c, cpu = run(args.start, args.stop, step, args.locate, tol)
        first = c.first_loss_of_stability()
        results.append((step, tol, c, cpu, first))
        print(step, tol, round(cpu, 1), c.orbit_solves, first and (first.kind, first.parameter),
              file=sys.stderr, flush=True)  # fmt: skip
    ref = results[-1][4]
    for step, tol, c, cpu, first in results:
        rows.append({
            "step_rpm": step, "shooting_tol": tol, "locate_rpm": args.locate,
            "cpu_s": round(cpu, 1), "orbit_solves": c.orbit_solves,
            "first_loss": first.kind if first else "",
            "located_rpm": round(first.parameter, 4) if first else "",
            "bracket_rpm": f"{first.bracket[0]:.4f}-{first.bracket[1]:.4f}" if first else "",
            "error_vs_finest_rpm": (round(abs(first.parameter - ref.parameter), 4)
                                    if first and ref else ""),
        })  # fmt: skip
    write_csv(DOCS / "continuation-accuracy.csv", rows)
    for row in rows:
        print(row)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=("sweep", "accuracy"))
    parser.add_argument("--start", type=float, default=30.0)
    parser.add_argument("--stop", type=float, default=300.0)
    parser.add_argument("--step", type=float, default=2.0)
    parser.add_argument("--locate", type=float, default=0.5)
    parser.add_argument("--figure", action="store_true")
    args = parser.parse_args()
    logging.basicConfig(level=logging.INFO, stream=sys.stderr, format="%(asctime)s %(message)s")
    # compile the kernels outside the measurement (a stable orbit: quick)
    mechanism.periodic_orbit(rigid_scene().replace({KEY: 30.0}), settle=2, max_iterations=1)
    (sweep if args.mode == "sweep" else accuracy)(args)


if __name__ == "__main__":
    main()
