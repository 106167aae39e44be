"""Orbit diagrams of the rigid ``paper`` scene over crank speed and over clearance.

The speed diagram is the performance target of the bifurcation study: 60 speeds from 30 to
300 rpm, 100 revolutions kept after 20 discarded, on the 2-core machine in ≤ 10 min (≤ 20
min with the exponent at every value). The clearance diagram spans 0.05–0.5 mm at 150 rpm.
Each run writes its Dataset and figure into ``docs/benchmarks/`` and prints wall time and
the CPU time of the points (each point's ``wall_time`` in its summary is the time its worker
spent on it). Run with

    python benchmarks/bifurcation_paper.py speed [--values 30:300:60] [--workers 2]
    python benchmarks/bifurcation_paper.py clearance [--values 5e-5:5e-4:46]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib
import xarray as xr

import mechanism
from mechanism.studies._sweep_store import write_netcdf

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
KEYS = {"speed": "drive.speed_rpm", "clearance": "joints.C.clearance"}
DEFAULT_VALUES = {"speed": "30:300:60", "clearance": "5e-5:5e-4:46"}


def _point_cpu_seconds(store: Path) -> dict[float, float]:
    """CPU seconds of each value's simulation (``solver_cpu_time`` of its summary)."""
    out = {}
    for path in (store / "points").glob("*.summary.nc"):
        with xr.open_dataset(path, engine="h5netcdf") as summary:
            value = float(next(iter(json.loads(summary.attrs["params"]).values())))
            out[value] = float(summary.attrs.get("solver_cpu_time", float("nan")))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", choices=sorted(KEYS))
    parser.add_argument("--values", default=None)
    parser.add_argument("--revolutions", type=float, default=120.0)
    parser.add_argument("--discard", type=float, default=20.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--store", type=Path, default=None)
    parser.add_argument("--exponent", action="store_true", help="also the exponent at every value")
    args = parser.parse_args()
    from mechanism.studies._bifurcation import parse_values

    values = parse_values(args.values or DEFAULT_VALUES[args.sweep])
    name = f"bifurcation-{args.sweep}" + ("-exponent" if args.exponent else "")
    store = args.store or Path(f"{name}-store")
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    start = time.perf_counter()
    ds = mechanism.bifurcation(
        scene,
        parameter=KEYS[args.sweep],
        values=values,
        revolutions=args.revolutions,
        discard=args.discard,
        n_workers=args.workers,
        store=store,
        exponent=args.exponent,
        progress=True,
    )
    wall = time.perf_counter() - start
    cpu = _point_cpu_seconds(store)
    busy = sum(cpu.values())
    ok = int((ds.status.values == "ok").sum())
    print(
        f"{len(values)} values ({ok} ok), {args.revolutions:g} revolutions each "
        f"({args.discard:g} discarded): wall {wall:.0f} s, CPU of the points {busy:.0f} s "
        f"({busy / len(values) / args.revolutions:.3f} s per revolution; on 2 free cores "
        f"{busy / 2 / 60:.1f} min)"
    )
    for value in sorted(cpu):
        print(f"  {value:10.4g}  {cpu[value] / args.revolutions:.3f} s CPU per revolution")
    OUT.mkdir(parents=True, exist_ok=True)
    write_netcdf(ds, OUT / f"{name}.nc")
    matplotlib.use("Agg")
    axes = mechanism.plot_bifurcation(ds)
    axes[0].set_title(
        f"rigid paper scene, {len(values)} values, strobes at revolutions "
        f"{args.discard:g}–{args.revolutions:g}; {busy:.0f} s CPU "
        f"({busy / len(values) / args.revolutions:.3f} s per revolution)",
        fontsize=9,
    )
    axes[0].figure.savefig(OUT / f"{name}.png", dpi=160, bbox_inches="tight")
    print(f"written: {OUT / f'{name}.png'}")


if __name__ == "__main__":
    main()
