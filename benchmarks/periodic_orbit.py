"""CPU time and accuracy of one period-1 orbit of the rigid ``paper`` scene (30 rpm) with
its Floquet multipliers, against the map's integration tolerance.

For each tolerance (rtol = atol) :func:`mechanism.periodic_orbit` runs from the scene's
start (5 settling periods) and the table records the process CPU time (one process,
``NUMBA_NUM_THREADS=1``, kernels compiled beforehand), the Newton iterations, the residual,
the largest multiplier and the exponent ln|μ_max|/T, single shooting at each tolerance and
multiple shooting over 8 segments at the default; it is written to
``docs/benchmarks/periodic-orbit.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/periodic_orbit.py [--rpm 30]
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

import mechanism
from chaoskit.contract import atomic_write

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "periodic-orbit.csv"
TOLERANCES = (1e-8, 1e-9, 1e-10)


def _position_gap(orbit: mechanism.PeriodicOrbit) -> float:
    """Largest |end − start| (m) of the recorded period over the non-angle coordinates:
    the positions' share of the residual."""
    gap = orbit.position[-1] - orbit.section_state[: len(orbit.dof_names)]
    lengths = np.array([not n.endswith(".theta") for n in orbit.dof_names])
    return float(np.max(np.abs(gap[lengths])))


def measure(rpm: float, tol: float, segments: int | None = None) -> dict:
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    cpu = time.process_time()
    orbit = mechanism.periodic_orbit(scene, settle=5, rtol=tol, atol=tol, segments=segments)
    cpu = time.process_time() - cpu
    mu = abs(orbit.largest_multiplier)
    return {
        "rpm": rpm,
        "rtol": tol,
        "shooting": f"{orbit.shooting} ({orbit.segments})",
        "cpu_s": round(cpu, 2),
        "iterations": orbit.iterations,
        "converged": orbit.converged,
        "residual": f"{orbit.residual:.2e}",
        "position_gap_over_clearance": f"{_position_gap(orbit) / orbit.clearance:.1e}",
        "largest_multiplier": f"{mu:.4e}",
        "exponent_per_s": round(math.log(mu) / orbit.drive_period, 4),
        "function_evaluations": orbit.function_evaluations,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, default=30.0)
    args = parser.parse_args()
    measure(args.rpm, 1e-8)  # compile the kernels outside the measurement
    rows = [measure(args.rpm, tol) for tol in TOLERANCES]
    rows.append(measure(args.rpm, TOLERANCES[-1], segments=8))
    for row in rows:
        print(row)

    def write(path: Path) -> None:
        with path.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(OUT, write)


if __name__ == "__main__":
    main()
