"""Coexisting motions of the rigid ``paper`` scene: the basins of an 8 × 8 grid of initial
journal eccentricities of joint C (at rest relative to the bearing, within 0.9 of the
clearance) at one crank speed, with the process CPU time; written to
``docs/benchmarks/basins.csv`` (one row per motion found)::

    NUMBA_NUM_THREADS=1 python benchmarks/basins.py [--rpm 150] [--points 8]
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

import mechanism
from chaoskit.contract import atomic_write

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "basins.csv"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rpm", type=float, default=150.0)
    parser.add_argument("--points", type=int, default=8)
    parser.add_argument("--revolutions", type=int, default=24)
    parser.add_argument("--discard", type=int, default=12)
    args = parser.parse_args()
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": args.rpm}
    )
    cpu = time.process_time()
    result = mechanism.basins(
        scene, points=args.points, revolutions=args.revolutions, discard=args.discard
    )
    cpu = time.process_time() - cpu
    labels, counts = np.unique(result.label, return_counts=True)
    rows = [
        {
            "rpm": args.rpm,
            "grid": f"{args.points}x{args.points}",
            "revolutions": args.revolutions,
            "discard": args.discard,
            "motion": str(label),
            "initial_states": int(count),
            "cpu_s": round(cpu, 1),
        }
        for label, count in zip(labels, counts, strict=True)
    ]
    for row in rows:
        print(row)
    print("coexisting:", result.coexisting)

    def write(path: Path) -> None:
        with path.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(OUT, write)


if __name__ == "__main__":
    main()
