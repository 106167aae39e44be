"""Orbit diagrams of the rigid ``paper`` scene over crank speed and over clearance.

The speed diagram is the performance target of the bifurcation study: 60 speeds from 30 to
300 rpm, 100 revolutions kept after 20 discarded, on the 2-core machine in ≤ 10 min (≤ 20
min with the exponent at every value). The clearance diagram spans 0.05–0.5 mm at 150 rpm.
Each run writes its Dataset and figure into ``docs/benchmarks/`` and adds a row to
``docs/benchmarks/bifurcation-cost.csv``: wall time, CPU time of the worker processes
(measured while they live, so it is the whole cost of the values computed in this run:
simulation, exponent and the sweep's bookkeeping), the CPU time of the simulations and of
the exponents summed over every value of the store (``solver_cpu_time`` and
``solver_exponent_cpu_time`` of each value, whichever run of a resumed store computed it),
and the load average at the start, sampled every 10 s during the run (mean and
largest) and at the end. Run with

    NUMBA_NUM_THREADS=1 python benchmarks/bifurcation_paper.py speed [--exponent]
    NUMBA_NUM_THREADS=1 python benchmarks/bifurcation_paper.py speed --exponent \
        --exponent-revolutions 30 --exponent-discard 10   # the exponent over fewer

With fewer exponent revolutions than the points' the run is compared, value by value, with
the stored diagram whose exponent kept all of them (``bifurcation-speed-exponent.nc``): the
difference of the exponents, the width of the intervals, and whether each value is read the
same way (interval above 0, or reaching 0 or below); the comparison is printed and added to
``docs/benchmarks/bifurcation-exponent-accuracy.csv``.
    NUMBA_NUM_THREADS=1 python benchmarks/bifurcation_paper.py clearance --values 5e-5:5e-4:46
    python benchmarks/bifurcation_paper.py speed --replot   # figure from the stored Dataset
"""

from __future__ import annotations

import argparse
import csv
import datetime
import io
import json
import logging
import os
import threading
import time
from pathlib import Path

import matplotlib
import numpy as np
import xarray as xr

import mechanism
from chaoskit.contract import atomic_write, write_netcdf
from mechanism.studies.paper import process_tree_cpu_time

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
COST = OUT / "bifurcation-cost.csv"
ACCURACY = OUT / "bifurcation-exponent-accuracy.csv"
KEYS = {"speed": "drive.speed_rpm", "clearance": "joints.C.clearance"}
DEFAULT_VALUES = {"speed": "30:300:60", "clearance": "5e-5:5e-4:46"}
COST_FIELDS = [
    "date", "sweep", "values", "revolutions", "discard", "exponent", "exponent_revolutions",
    "exponent_discard", "workers", "ok",
    "wall_s", "worker_cpu_s", "simulation_cpu_s", "exponent_cpu_s", "cpu_s_per_revolution",
    "load_start", "load_mean", "load_max", "load_end",
]  # fmt: skip


def _point_cpu_seconds(store: Path, key: str) -> dict[float, float]:
    """CPU seconds of each value's simulation (``key`` = ``solver_cpu_time``) or exponent
    (``solver_exponent_cpu_time``) from its summary; 0 where not recorded."""
    out = {}
    for path in (store / "points").glob("*.summary.nc"):
        with xr.open_dataset(path, engine="h5netcdf") as summary:
            value = float(next(iter(json.loads(summary.attrs["params"]).values())))
            out[value] = float(summary.attrs.get(key, 0.0))
    return out


class _LoadSampler:
    """The 1-minute load average every ``every`` seconds in a background thread."""

    def __init__(self, every: float = 10.0) -> None:
        self.samples = [os.getloadavg()[0]]
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(every,), daemon=True)
        self._thread.start()

    def _run(self, every: float) -> None:
        while not self._stop.wait(every):
            self.samples.append(os.getloadavg()[0])

    def stop(self) -> list[float]:
        self._stop.set()
        self._thread.join()
        self.samples.append(os.getloadavg()[0])
        return self.samples


def _figure(ds: xr.Dataset, name: str) -> None:
    matplotlib.use("Agg")
    axes = mechanism.plot_bifurcation(ds)
    cost = ds.attrs.get("benchmark_cost", "")
    axes[0].set_title(
        f"rigid paper scene, {ds.sizes[ds.attrs['bifurcation_parameter']]} values, strobes "
        f"after {ds.attrs.get('benchmark_discard', 0):g} of "
        f"{ds.attrs.get('benchmark_revolutions', 0):g} revolutions; {cost}",
        fontsize=8,
    )
    axes[0].figure.savefig(OUT / f"{name}.png", dpi=160, bbox_inches="tight")
    print(f"written: {OUT / f'{name}.png'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", choices=sorted(KEYS))
    parser.add_argument("--values", default=None)
    parser.add_argument("--revolutions", type=float, default=120.0)
    parser.add_argument("--discard", type=float, default=20.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--store", type=Path, default=None)
    parser.add_argument("--exponent", action="store_true", help="also the exponent at every value")
    parser.add_argument("--exponent-revolutions", type=float, default=None)
    parser.add_argument("--exponent-discard", type=float, default=None)
    parser.add_argument("--replot", action="store_true", help="redraw from the stored Dataset")
    args = parser.parse_args()
    args.exponent |= args.exponent_revolutions is not None or args.exponent_discard is not None
    name = f"bifurcation-{args.sweep}" + ("-exponent" if args.exponent else "")
    if args.exponent_revolutions is not None:
        name += f"-{args.exponent_revolutions:g}"
    if args.replot:
        with xr.open_dataset(OUT / f"{name}.nc", engine="h5netcdf") as stored:
            _figure(stored.load(), name)
        return
    from distributed import Client, LocalCluster

    from mechanism.studies._orbit_diagram import parse_values

    values = parse_values(args.values or DEFAULT_VALUES[args.sweep])
    store = args.store or Path(f"{name}-store")
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    with (
        LocalCluster(
            n_workers=args.workers, threads_per_worker=1, processes=True,
            dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR,
        ) as cluster,
        Client(cluster) as client,
    ):  # fmt: skip
        cpu0 = process_tree_cpu_time()
        load = _LoadSampler()
        start = time.perf_counter()
        ds = mechanism.bifurcation(
            scene,
            parameter=KEYS[args.sweep],
            values=values,
            revolutions=args.revolutions,
            discard=args.discard,
            client=client,
            store=store,
            exponent=args.exponent,
            settings=mechanism.BifurcationSettings(
                exponent_revolutions=args.exponent_revolutions,
                exponent_discard=args.exponent_discard,
            ),
            progress=True,
        )
        wall = time.perf_counter() - start
        cpu = process_tree_cpu_time() - cpu0  # the workers are still alive: all of it
        loads = load.stop()
    # per value, whatever run of a resumed store computed it
    sim = sum(_point_cpu_seconds(store, "solver_cpu_time").values())
    exp = sum(_point_cpu_seconds(store, "solver_exponent_cpu_time").values())
    ok = int((ds.status.values == "ok").sum())
    kept = args.exponent_revolutions or args.revolutions - args.discard
    discarded = args.discard if args.exponent_discard is None else args.exponent_discard
    revs = len(values) * args.revolutions
    row = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M"),
        "sweep": args.sweep,
        "values": args.values or DEFAULT_VALUES[args.sweep],
        "revolutions": f"{args.revolutions:g}",
        "discard": f"{args.discard:g}",
        "exponent": int(args.exponent),
        "exponent_revolutions": "" if not args.exponent else f"{kept:g}",
        "exponent_discard": "" if not args.exponent else f"{discarded:g}",
        "workers": args.workers,
        "ok": ok,
        "wall_s": f"{wall:.0f}",
        "worker_cpu_s": f"{cpu:.0f}",
        "simulation_cpu_s": f"{sim:.0f}",
        "exponent_cpu_s": f"{exp:.0f}",
        "cpu_s_per_revolution": f"{cpu / revs:.4f}",
        "load_start": f"{loads[0]:.1f}",
        "load_mean": f"{sum(loads) / len(loads):.1f}",
        "load_max": f"{max(loads):.1f}",
        "load_end": f"{loads[-1]:.1f}",
    }
    print(row)
    print(
        f"{len(values)} values ({ok} ok), {args.revolutions:g} revolutions each "
        f"({args.discard:g} discarded): wall {wall / 60:.1f} min, CPU of the workers "
        f"{cpu / 60:.1f} min ({cpu / revs:.3f} s per revolution; on 2 free cores "
        f"{cpu / 2 / 60:.1f} min); per value (all runs of the store): simulations "
        f"{sim / 60:.1f} min, exponents {exp / 60:.1f} min"
    )
    _append(COST, COST_FIELDS, row)
    ds.attrs.update(
        benchmark_revolutions=args.revolutions,
        benchmark_discard=args.discard,
        benchmark_cost=(
            f"wall {wall / 60:.1f} min, CPU {cpu / 60:.1f} min on {args.workers} workers "
            f"(load {row['load_mean']})"
        ),
    )
    OUT.mkdir(parents=True, exist_ok=True)
    write_netcdf(ds, OUT / f"{name}.nc")
    _figure(ds, name)
    reference = OUT / f"bifurcation-{args.sweep}-exponent.nc"
    if args.exponent_revolutions is not None and reference.exists():
        with xr.open_dataset(reference, engine="h5netcdf") as full:
            _compare(ds, full.load(), args, kept, discarded, cpu)


def _append(path: Path, fields: list[str], row: dict[str, object]) -> None:
    """Add a row to a CSV file, atomically; older rows get blanks in new columns."""
    rows: list[dict[str, object]] = []
    if path.exists():
        with path.open(newline="") as fh:
            rows = list(csv.DictReader(fh))
    rows.append(row)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=fields, restval="")
    writer.writeheader()
    writer.writerows(rows)
    text = buffer.getvalue()
    atomic_write(path, lambda tmp: tmp.write_text(text))


def _reading(ds: xr.Dataset) -> np.ndarray:
    """Per value: "chaotic" when the exponent's interval lies above 0, "regular" otherwise."""
    return np.where(ds["lyapunov_exponent_low"].values > 0.0, "chaotic", "regular")


def _compare(
    ds: xr.Dataset, full: xr.Dataset, args: argparse.Namespace, kept: float,
    discarded: float, cpu: float,
) -> None:  # fmt: skip
    """The exponent over fewer revolutions against the stored one over all of them."""
    key = KEYS[args.sweep]
    full = full.sel({key: ds[key].values}, method="nearest")
    ok = (ds.status.values == "ok") & (full.status.values == "ok")
    lam, ref = ds.lyapunov_exponent.values[ok], full.lyapunov_exponent.values[ok]
    width = (ds.lyapunov_exponent_high - ds.lyapunov_exponent_low).values[ok]
    ref_width = (full.lyapunov_exponent_high - full.lyapunov_exponent_low).values[ok]
    same = _reading(ds)[ok] == _reading(full)[ok]
    inside = (ref >= ds.lyapunov_exponent_low.values[ok]) & (
        ref <= ds.lyapunov_exponent_high.values[ok]
    )
    row = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M"),
        "sweep": args.sweep,
        "values": int(ok.sum()),
        "exponent_revolutions": f"{kept:g}",
        "exponent_discard": f"{discarded:g}",
        "reference_revolutions": f"{full.lyapunov_exponent.attrs.get('revolutions_kept', 100):g}",
        "same_reading": int(same.sum()),
        "reference_inside_interval": int(inside.sum()),
        "median_abs_difference": f"{np.median(np.abs(lam - ref)):.3g}",
        "median_width_ratio": f"{np.median(width / np.maximum(ref_width, 1e-12)):.3g}",
        "worker_cpu_s": f"{cpu:.0f}",
        "differently_read": " ".join(f"{v:.4g}" for v in ds[key].values[ok][~same]),
    }
    print(row)
    _append(ACCURACY, list(row), row)


if __name__ == "__main__":
    main()
