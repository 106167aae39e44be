"""Cost of what a run records: full trajectory, wear variables, metrics only, sections only.

Measures, for the ``paper`` scene at 150 rpm, the CPU time per revolution of
``mechanism.simulate`` (process CPU time: the main run and its ideal companion together,
i.e. the cost on one core; wall time on a shared machine says little) in each record mode,
with rigid rods and with the default flexible rods, and the memory a long section-only run
holds (peak of Python-tracked allocations, numpy included). Goals (the performance targets
of the record modes):

* rigid, sections only: ≤ 0.1 s per revolution on one core (also measured with the
  default output step as a fixed step limit, against the default approach bound);
* flexible (16 + 16 ANCF elements), sections only: ≤ 1.0 s per revolution on one core;
* 1000 revolutions, sections only: < 200 MB.

Writes ``docs/benchmarks/record-modes.csv`` and prints the table. Run with
``python benchmarks/record_modes.py [--revolutions 20] [--flexible-revolutions 1]
[--memory-revolutions 1000]``.
"""

from __future__ import annotations

import argparse
import csv
import time
import tracemalloc
from pathlib import Path

import mechanism

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "record-modes.csv"


def _scene(flexible: bool):
    scene = mechanism.load_scene("paper")
    return scene if flexible else scene.replace({"effects.flexibility": False})


def _cost(scene, revolutions: float, record: str) -> dict:
    mechanism.simulate(scene, revolutions=0.05, record="full")  # compile / load
    cpu, wall = time.process_time(), time.perf_counter()
    ds = mechanism.simulate(scene, revolutions=revolutions, record=record)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    assert ds.attrs["solver_status"] == 0
    return {
        "cpu_s_per_rev": cpu / revolutions,
        "wall_s_per_rev": wall / revolutions,
        "steps_per_rev": ds.attrs["solver_steps"] / revolutions,
        "rejected_per_rev": ds.attrs["solver_rejected_steps"] / revolutions,
        "peak_contact_force_N": float(
            ds["peak_contact_force"] if "peak_contact_force" in ds else ds.contact_force.max()
        ),
    }


def _memory(revolutions: float) -> float:
    scene = _scene(False)
    mechanism.simulate(scene, revolutions=1, record="sections")
    tracemalloc.start()
    ds = mechanism.simulate(scene, revolutions=revolutions, record="sections")
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert ds.sizes["crossing"] == int(revolutions) + 1
    return peak / 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=20.0)
    parser.add_argument("--flexible-revolutions", type=float, default=1.0)
    parser.add_argument("--memory-revolutions", type=float, default=1000.0)
    args = parser.parse_args()
    rows = []
    for flexible, revs in ((False, args.revolutions), (True, args.flexible_revolutions)):
        for record in ("full", "wear", "metrics", "sections"):
            row = {"rods": "flexible" if flexible else "rigid", "record": record}
            row["revolutions"] = revs
            row.update(_cost(_scene(flexible), revs, record))
            rows.append(row)
            print({k: round(v, 4) if isinstance(v, float) else v for k, v in row.items()})
        if not flexible:
            # the default output step as a fixed limit, against the default approach bound
            scene = _scene(False)
            fixed = scene.replace({"solver.max_step": scene.drive.period / 10000})
            row = {"rods": "rigid", "record": "sections, fixed T/10000 limit"}
            row["revolutions"] = revs
            row.update(_cost(fixed, revs, "sections"))
            rows.append(row)
            print({k: round(v, 4) if isinstance(v, float) else v for k, v in row.items()})
    peak = _memory(args.memory_revolutions)
    rows.append(
        {"rods": "rigid", "record": "sections", "revolutions": args.memory_revolutions,
         "peak_memory_MB": peak}
    )  # fmt: skip
    print(f"{args.memory_revolutions:g} revolutions, sections only: peak {peak:.1f} MB")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fields = sorted(
        {k for row in rows for k in row}, key=lambda k: (k not in ("rods", "record"), k)
    )
    with OUT.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    print(f"written: {OUT}")


if __name__ == "__main__":
    main()
