"""How far the rigid-rod wear path is from the flexible-rod one: ``mechanism.wear_life``
of the ``paper`` scene at 150 rpm, c = 0.2 mm, with rigid rods and with flexible rods.

Both paths run the same wear (cycles, checkpoints, averaged revolutions, increment cap)
and the same analysis at every checkpoint; the rigid one at the error control's step, the
flexible one (16 + 16 ANCF elements, fixed-step generalized-α) at the paper study's step
T/10000. Each path runs in its own process (the two in parallel), and the script prints,
per checkpoint and rod model, the largest bearing and journal wear depth, λ₁ from the
equations with its 95 % interval, the motion verdict with its confidence, and each path's
CPU time (``time.process_time`` of its process: the cost on one core, which does not
grow with the machine's load). With ``--csv PATH`` the rows are also written there.

Run from the repository root (the defaults: the quick settings' 10 000 cycles of the
paper study's wear paths, with two checkpoints, 5 000 and 10 000, and 4 averaged
revolutions)::

    python benchmarks/wear_life_rigid_vs_flexible.py [--cycles 10000] [--checkpoints 5000 10000]
        [--averaged 4] [--csv rows.csv]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from typing import Any

import numpy as np

import mechanism

STEP = 0.4 / 10_000  # s: the paper study's integration step of flexible rods (T/10000 at 150 rpm)


def run_path(
    flexible: bool, cycles: float, checkpoints: list[float], averaged: int
) -> list[dict[str, Any]]:
    """One wear path (in a worker process): a row per analysed state."""
    scene = mechanism.load_scene("paper").replace(
        {
            "drive.speed_rpm": 150.0,
            "joints.C.clearance": 2e-4,
            "effects.flexibility": flexible,
            "solver.max_step": STEP if flexible else None,
        }
    )
    cpu = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mechanism.SimulationWarning)
        life = mechanism.wear_life(
            scene, cycles=cycles, checkpoints=checkpoints, averaged_revolutions=averaged
        )
    cpu = time.process_time() - cpu
    ds = life.to_dataset()
    depth = ds["max_wear_depth"].max("joint")
    rows = []
    for i, n in enumerate(life.checkpoints):
        rows.append(
            {
                "rods": "flexible" if flexible else "rigid",
                "cycles": float(n),
                "bearing_um": float(depth.sel(surface="bearing").values[i]) * 1e6,
                "journal_um": float(depth.sel(surface="journal").values[i]) * 1e6,
                "lambda": float(ds["lyapunov_exponent"].values[i]),
                "lambda_low": float(ds["lyapunov_ci_low"].values[i]),
                "lambda_high": float(ds["lyapunov_ci_high"].values[i]),
                "motion": str(ds["motion"].values[i]),
                "confidence": float(ds["motion_confidence"].values[i]),
                "status": life.status,
                "cycles_to_chaos": -1.0 if life.cycles_to_chaos is None else life.cycles_to_chaos,
                "path_cpu_s": cpu,
            }
        )
    return rows


def _table(rows: list[dict[str, Any]]) -> str:
    head = (
        "| rods | cycles | bearing / journal depth (µm) | λ₁ [95 %] (1/s) | motion (confidence) "
        "| path CPU (s) |\n|---|---:|---|---|---|---:|"
    )
    lines = [head]
    for r in rows:
        lam = (
            "not computed"
            if math.isnan(r["lambda"])
            else f"{r['lambda']:.3g} [{r['lambda_low']:.3g}, {r['lambda_high']:.3g}]"
        )
        lines.append(
            f"| {r['rods']} | {r['cycles']:,.0f} | {r['bearing_um']:.3g} / {r['journal_um']:.3g} "
            f"| {lam} | {r['motion']} ({r['confidence']:.2f}) | {r['path_cpu_s']:.0f} |"
        )
    return "\n".join(lines)


def _differences(rows: list[dict[str, Any]]) -> str:
    """Per checkpoint both paths reached: rigid − flexible depth, relative."""
    by = {(r["rods"], r["cycles"]): r for r in rows}
    out = []
    for n in sorted({r["cycles"] for r in rows}):
        rigid, flexible = by.get(("rigid", n)), by.get(("flexible", n))
        if rigid is None or flexible is None or n == 0.0:
            continue
        parts = []
        for surface in ("bearing_um", "journal_um"):
            ref = flexible[surface]
            rel = (rigid[surface] - ref) / ref if ref > 0 else np.nan
            parts.append(f"{surface.split('_')[0]} {100 * rel:+.0f} %")
        same = "same" if rigid["motion"] == flexible["motion"] else "different"
        out.append(
            f"{n:,.0f} cycles: rigid against flexible depth {', '.join(parts)}; {same} verdict"
        )
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cycles", type=float, default=10_000.0)
    parser.add_argument("--checkpoints", type=float, nargs="+", default=[5_000.0, 10_000.0])
    parser.add_argument("--averaged", type=int, default=4)
    parser.add_argument("--csv", default=None, help="also write the rows to this CSV file")
    args = parser.parse_args()
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=2, mp_context=get_context("spawn")) as pool:
        futures = [
            pool.submit(run_path, flexible, args.cycles, args.checkpoints, args.averaged)
            for flexible in (True, False)
        ]
        rows = [row for future in futures for row in future.result()]
    rows.sort(key=lambda r: (r["cycles"], r["rods"]))
    load = os.getloadavg()
    print(_table(rows))
    print(_differences(rows))
    print(
        f"wall {time.perf_counter() - t0:.0f} s, load average {load[0]:.1f} (1 min), "
        f"{load[2]:.1f} (15 min) on {os.cpu_count()} cores"
    )
    if args.csv:
        with open(args.csv, "w", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
