"""What the integration tolerance does to an orbit diagram of the rigid ``paper`` scene.

At the scene's own tolerance (rtol = atol = 1e-5, the paper's solver setting) the error
the step control accepts on positions is 10 µm, 5 % of the 0.2 mm clearance: a regular
orbit's stroboscopic points then scatter by micrometres, and the scatter looks like a thin
chaotic band. For a few crank speeds and tolerances this measures the spread of the
journal eccentricity |e| over the kept strobes (max − min) and the CPU time per revolution
(one process, ``NUMBA_NUM_THREADS=1``), and writes ``docs/benchmarks/orbit-tolerance.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/orbit_tolerance.py [--revolutions 60] [--discard 20]
"""

from __future__ import annotations

import argparse
import csv
import os
import tempfile
import time
from pathlib import Path

import numpy as np

import mechanism

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "orbit-tolerance.csv"
SPEEDS = (30.0, 60.0, 90.0, 150.0, 250.0)
TOLERANCES = (None, 1e-6, 1e-7, 1e-8)


def measure(rpm: float, tol: float | None, revolutions: float, discard: float) -> dict:
    scene = mechanism.load_scene("paper").replace(
        {"effects.flexibility": False, "drive.speed_rpm": rpm}
    )
    cpu = time.process_time()
    ds = mechanism.simulate(
        scene,
        revolutions=revolutions,
        record=mechanism.SectionsRecord(discard=discard),
        rtol=tol,
        atol=tol,
    )
    cpu = time.process_time() - cpu
    e = np.hypot(
        ds["eccentricity_x"].isel(joint=0).values, ds["eccentricity_y"].isel(joint=0).values
    )
    return {
        "speed_rpm": rpm,
        "rtol_atol": scene.solver.rtol if tol is None else tol,
        "strobes": int(e.size),
        "spread_um": float(np.ptp(e) * 1e6),
        "mean_e_um": float(np.mean(e) * 1e6),
        "cpu_s_per_rev": cpu / revolutions,
        "steps_per_rev": ds.attrs["solver_steps"] / revolutions,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=60.0)
    parser.add_argument("--discard", type=float, default=20.0)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    mechanism.simulate(  # compile before timing
        mechanism.load_scene("paper").replace({"effects.flexibility": False}), revolutions=0.2
    )
    rows = []
    for rpm in SPEEDS:
        for tol in TOLERANCES:
            row = measure(rpm, tol, args.revolutions, args.discard)
            rows.append(row)
            print(
                f"{rpm:5.0f} rpm  tol {row['rtol_atol']:.0e}  spread {row['spread_um']:9.4f} µm  "
                f"{row['cpu_s_per_rev']:.3f} s/rev  {row['steps_per_rev']:.0f} steps/rev",
                flush=True,
            )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, delete=False, newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(fh.name, args.out)


if __name__ == "__main__":
    main()
