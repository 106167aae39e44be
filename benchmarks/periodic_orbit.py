"""CPU time and accuracy of one period-1 orbit of the rigid ``paper`` scene (30 rpm) with
its Floquet multipliers, against the map's integration tolerance.

For each tolerance (rtol = atol) :func:`mechanism.periodic_orbit` runs from the scene's
start (at most 5 settling periods) and the table records the process CPU time (one process,
``NUMBA_NUM_THREADS=1``, kernels compiled beforehand), the Newton iterations, the residual,
the largest multiplier and the exponent ln|μ_max|/T, single shooting at each tolerance and
multiple shooting over 8 segments at the default; it is written to
``docs/benchmarks/periodic-orbit.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/periodic_orbit.py [--rpm 30]

``--compare ROUNDS`` instead times the monodromy matrix's two ways of carrying its
columns, side by side in one process (interleaved rounds, the order alternating, so a
changing machine load falls on both alike): all columns in one block on one reference
run (the default), and one tangent run per column (the former way, the same numbers on
a frozen step schedule); written to ``docs/benchmarks/periodic-orbit-block.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/periodic_orbit.py --compare 3

``--stages`` prints where the CPU time of the default orbit (``periodic_orbit(scene)``,
30 rpm) goes: settling, freezing the steps, the map evaluations of the iteration, the
monodromy matrix's tangent runs, the orbit's record and its kinematics::

    NUMBA_NUM_THREADS=1 python benchmarks/periodic_orbit.py --stages
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

# the internal switch between the block and the per-column monodromy (comparison only)
from mechanism.studies.orbits import _shooting as shooting

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "periodic-orbit.csv"
COMPARE_OUT = OUT.with_name("periodic-orbit-block.csv")
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


def compare(rpm: float, rounds: int) -> list[dict]:
    """CPU of the default orbit with the block and with one run per column, interleaved."""
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    modes = {"block": None, "per column": 1}
    rows = []
    for r in range(rounds):
        order = list(modes) if r % 2 == 0 else list(modes)[::-1]
        for mode in order:
            shooting.COLUMNS_PER_RUN = modes[mode]
            try:
                cpu = time.process_time()
                orbit = mechanism.periodic_orbit(scene, settle=5)
                cpu = time.process_time() - cpu
            finally:
                shooting.COLUMNS_PER_RUN = None
            mu = orbit.largest_multiplier
            rows.append({
                "rpm": rpm, "round": r, "monodromy": mode, "cpu_s": round(cpu, 2),
                "function_evaluations": orbit.function_evaluations,
                "converged": orbit.converged, "residual": f"{orbit.residual:.2e}",
                "largest_multiplier": f"{mu.real:.10e}",
                "largest_multiplier_hex": float(mu.real).hex(),
            })  # fmt: skip
            print(rows[-1])
    return rows


def stages(rpm: float) -> dict[str, list[float]]:
    """CPU seconds and calls of the default orbit's stages (the map's methods timed)."""
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    spent: dict[str, list[float]] = {}
    cls = shooting.StroboscopicMap
    saved = {name: getattr(cls, name) for name in ("run", "freeze_steps", "carry")}
    active: list[str] = []

    def timed(name: str):
        inner = saved[name]

        def call(self, *args, **kw):
            label = name
            if name == "run":
                label = "map run, frozen steps" if self.schedule is not None else "map run"
                if kw.get("record"):
                    label = "record"
            if active:  # inside freeze_steps or carry: counted there
                return inner(self, *args, **kw)
            active.append(label)
            cpu = time.process_time()
            try:
                return inner(self, *args, **kw)
            finally:
                active.pop()
                row = spent.setdefault(label, [0.0, 0])
                row[0] += time.process_time() - cpu
                row[1] += 1

        return call

    for name in saved:
        setattr(cls, name, timed(name))
    try:
        cpu = time.process_time()
        orbit = mechanism.periodic_orbit(scene)
        spent["total"] = [time.process_time() - cpu, 1]
    finally:
        for name, inner in saved.items():
            setattr(cls, name, inner)
    spent["other (kinematics, bases, eigenvalues)"] = [
        spent["total"][0] - sum(v[0] for k, v in spent.items() if k != "total"),
        1,
    ]
    print(f"residual {orbit.residual:.2e}, |mu_max| {abs(orbit.largest_multiplier):.4e}")
    return spent


def _write(path: Path, rows: list[dict]) -> None:
    def write(target: Path) -> None:
        with target.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(path, write)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, default=30.0)
    parser.add_argument("--compare", type=int, default=0, metavar="ROUNDS")
    parser.add_argument("--stages", action="store_true")
    args = parser.parse_args()
    measure(args.rpm, 1e-8)  # compile the kernels outside the measurement
    if args.stages:
        for label, (cpu, calls) in stages(args.rpm).items():
            print(f"{label:40s} {cpu:6.2f} s  ({calls} calls)")
        return
    if args.compare > 0:
        rows = compare(args.rpm, args.compare)
        for mode in ("block", "per column"):
            cpu = [row["cpu_s"] for row in rows if row["monodromy"] == mode]
            print(f"{mode}: median CPU {np.median(cpu):.2f} s over {len(cpu)} rounds")
        _write(COMPARE_OUT, rows)
        return
    rows = [measure(args.rpm, tol) for tol in TOLERANCES]
    rows.append(measure(args.rpm, TOLERANCES[-1], segments=8))
    for row in rows:
        print(row)
    _write(OUT, rows)


if __name__ == "__main__":
    main()
