"""Wear paths of the rigid ``paper`` scene over crank speed: cycles to chaos per speed.

The performance target of :func:`mechanism.wear_life_map`: the ``paper`` scene with
``effects.flexibility = false`` (``wear_life`` switches ``effects.wear`` on itself) at 30,
60, 90, 120 and 150 rpm, one wear path each up to 40 000 cycles with 8 checkpoints (every
5 000 cycles), the exponent from the equations and the motion verdict at each, on 2
workers: ≤ 10 min on two idle cores. The run writes the map
(``docs/benchmarks/wear-life-speed.nc``), its figures (``docs/benchmarks/wear-life-*.png``)
and the report (``docs/benchmarks/wear-life-speed.md``), and adds a row to
``docs/benchmarks/wear-life-cost.csv``: wall time, the CPU time of the paths (summed over
the paths' tasks; whichever run of a resumed store computed them) and the load average at
the start, sampled every 10 s during the run (mean and largest) and at the end.
``docs/benchmarks/wear-life-paths.csv`` is rewritten with one row per path: how far it
went, its CPU and wall time and where its CPU went (the simulations, averaging their wear,
the exponent, the verdict: the path's ``phase_cpu_*`` attributes). Run with

    NUMBA_NUM_THREADS=1 python benchmarks/wear_life.py [--store FOLDER] [--workers 2]
    python benchmarks/wear_life.py --replot       # map, tables, figures, report from the store

(``--replot`` runs here, serially, any path the store does not hold yet.)
"""

from __future__ import annotations

import argparse
import csv
import datetime
import io
import os
import tempfile
import threading
import time
from pathlib import Path

import matplotlib
import xarray as xr

import mechanism
from chaoskit.contract import atomic_write

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
MAP = OUT / "wear-life-speed.nc"
COST = OUT / "wear-life-cost.csv"
PATHS = OUT / "wear-life-paths.csv"
# slowest first: a slower path costs more (longer revolutions with more impacts each,
# docs/wear.md §7) and the paths start in this order, so the longest starts first (the
# 30 rpm path is estimated at more than the other four together)
SPEEDS = [30.0, 60.0, 90.0, 120.0, 150.0]
CYCLES = 40000.0
CHECKPOINTS = [5000.0 * k for k in range(1, 9)]
FIELDS = [
    "date", "values", "cycles", "checkpoints", "workers", "complete", "wall_s", "path_cpu_s",
    "load_start", "load_mean", "load_max", "load_end",
]  # fmt: skip
#: the phases of a path's CPU time (its ``phase_cpu_*`` attributes)
PHASES = ["runs", "wear", "exponent", "verdict", "total"]


class LoadSampler(threading.Thread):
    """The 1-minute load average every ``every`` seconds while the run lasts."""

    def __init__(self, every: float = 10.0) -> None:
        super().__init__(daemon=True)
        # not ``_stop``: that name is a method of threading.Thread, which join() calls
        self.every, self.samples, self._done = every, [os.getloadavg()[0]], threading.Event()

    def run(self) -> None:
        while not self._done.wait(self.every):
            self.samples.append(os.getloadavg()[0])

    def stop(self) -> None:
        self._done.set()
        self.join()


def scene() -> mechanism.Scene:
    return mechanism.load_scene("paper").replace({"effects.flexibility": False})


def write_map(life: mechanism.WearLifeMap) -> xr.Dataset:
    """The map as NetCDF (``wear-life-speed.nc``), written atomically; returns its Dataset."""
    ds = life.to_dataset()
    buffer = io.BytesIO(ds.to_netcdf(engine="h5netcdf"))
    atomic_write(MAP, lambda p: p.write_bytes(buffer.getvalue()))
    return ds


def path_rows(life: mechanism.WearLifeMap) -> list[dict[str, object]]:
    """One row per path: status, checkpoints reached, CPU and wall time, CPU by phase."""
    rows = []
    for value, path, cpu, wall in zip(
        life.values, life.paths, life.cpu_times, life.wall_times, strict=True
    ):
        attrs = {} if path is None else path.dataset.attrs
        reached = float(path.checkpoints[-1]) if path is not None and path.checkpoints.size else 0
        row = {
            "value": value, "status": attrs.get("status", "failed"), "reached_cycles": reached,
            "states": 0 if path is None else int(path.checkpoints.size),
            "cycles_to_chaos": "" if path is None or path.cycles_to_chaos is None
            else path.cycles_to_chaos,
            "cpu_s": round(cpu, 1), "wall_s": round(wall, 1),
        }  # fmt: skip
        for phase in PHASES:
            row[f"{phase}_cpu_s"] = round(float(attrs.get(f"phase_cpu_{phase}", "nan")), 1)
        rows.append(row)
    return rows


def write_paths(life: mechanism.WearLifeMap) -> None:
    """``wear-life-paths.csv``: :func:`path_rows` of every path, rewritten atomically."""
    buffer = io.StringIO()
    rows = path_rows(life)
    writer = csv.DictWriter(buffer, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    atomic_write(PATHS, lambda p: p.write_text(buffer.getvalue(), encoding="utf-8"))


def write_outputs(life: mechanism.WearLifeMap) -> None:
    """The per-path table, the figures (PNG) and the report (Markdown twin, figures as
    files) into docs."""
    write_paths(life)
    matplotlib.use("Agg")
    rep = mechanism.wear_life_report(life, title="Wear paths of the rigid paper scene over speed")
    for fig in rep.figures:
        atomic_write(OUT / f"wear-life-speed-{fig.name}.png", lambda p, f=fig: p.write_bytes(f.png))
    rep.write(OUT / "wear-life-speed.html")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--store", default=str(Path(tempfile.gettempdir()) / "wear-life-speed"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--replot", action="store_true")
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    if args.replot:
        life = mechanism.wear_life_map(
            scene(), parameter="drive.speed_rpm", values=SPEEDS, cycles=CYCLES,
            checkpoints=CHECKPOINTS, store=args.store, scheduler="serial",
        )  # fmt: skip
        write_map(life)
        write_outputs(life)
        return
    sampler = LoadSampler()
    sampler.start()
    start = time.perf_counter()
    life = mechanism.wear_life_map(
        scene(), parameter="drive.speed_rpm", values=SPEEDS, cycles=CYCLES,
        checkpoints=CHECKPOINTS, store=args.store, workers=args.workers, progress=True,
    )  # fmt: skip
    wall = time.perf_counter() - start
    sampler.stop()
    ds = write_map(life)
    loads = sampler.samples
    row = {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "values": ",".join(f"{v:g}" for v in SPEEDS), "cycles": CYCLES,
        "checkpoints": len(CHECKPOINTS), "workers": args.workers,
        "complete": sum(s == "complete" for s in life.statuses), "wall_s": round(wall, 1),
        "path_cpu_s": round(float(ds["cpu_time"].sum()), 1), "load_start": loads[0],
        "load_mean": round(sum(loads) / len(loads), 2), "load_max": max(loads),
        "load_end": os.getloadavg()[0],
    }  # fmt: skip
    new = not COST.exists()
    with COST.open("a", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=FIELDS)
        if new:
            writer.writeheader()
        writer.writerow(row)
    print(life.summary())
    print(row)
    for value, cpu, wall_time in zip(life.values, life.cpu_times, life.wall_times, strict=True):
        print(f"  {value:g} rpm: CPU {cpu:.0f} s, wall {wall_time:.0f} s")
    for path_row in path_rows(life):
        print("  " + ", ".join(f"{k} {v}" for k, v in path_row.items()))
    write_outputs(life)


if __name__ == "__main__":
    main()
