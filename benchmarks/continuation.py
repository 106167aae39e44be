"""Continuation of the period-1 orbit of the rigid ``paper`` scene over crank speed: its
cost, its bifurcations, the route to chaos, and the accuracy of a located point against
the step and the shooting tolerance.

``sweep`` follows the orbit from ``--start`` to ``--stop`` rpm and, from a settled run
in every regular stretch of the orbit diagram (``mechanism.regular_stretches``), both
ways (process CPU time of one process, ``NUMBA_NUM_THREADS=1``, with the load average),
writes the Dataset to
``docs/benchmarks/continuation-speed.nc``, one cost row to
``docs/benchmarks/continuation-cost.csv``, the route against the chaotic windows of
``docs/benchmarks/bifurcation-speed-exponent.nc`` to stdout and the overlay figure to
``docs/benchmarks/continuation-speed.png``. ``accuracy`` repeats a short span with each
step and shooting tolerance and writes ``docs/benchmarks/continuation-accuracy.csv``: the
first located point and its distance to the finest run's. ``sweep`` also writes the
route of the paper study's report, ``mechanism/studies/paper/data/route_rigid.json``
(``paper`` rewrites it from the stored Dataset and ``docs/benchmarks/basins.csv``)::

    NUMBA_NUM_THREADS=1 python benchmarks/continuation.py sweep [--start 30 --stop 300]
    NUMBA_NUM_THREADS=1 python benchmarks/continuation.py accuracy --start 60 --stop 75
    python benchmarks/continuation.py paper
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import logging
import multiprocessing
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import xarray as xr

import mechanism
from chaoskit.contract import atomic_write

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs" / "benchmarks"
DIAGRAM = DOCS / "bifurcation-speed-exponent.nc"
BASINS = DOCS / "basins.csv"
PAPER_DATA = ROOT / "mechanism" / "studies" / "paper" / "data" / "route_rigid.json"
KEY = "drive.speed_rpm"
#: the crank speed of the paper's chaotic case, where coexisting motions are reported
COEXISTENCE_RPM = 150.0


def rigid_scene() -> mechanism.Scene:
    return mechanism.load_scene("paper").replace({"effects.flexibility": False})


def run(
    start: float, stop: float, step: float, locate: float, tol: float | None,
    seeds: list[float] | None = None,
):  # fmt: skip
    """One continuation: step control on the multipliers and the contact signature
    (grow by 1.5 while |mu_max| <= 0.5 and the signature holds, up to 4 steps), branch
    ends bracketed to ``locate`` (smallest step locate / 2), single shooting only."""
    settings = mechanism.ContinuationSettings(
        step=step, min_step=locate / 2, max_step=4 * step, locate_tolerance=locate,
        shooting_tolerance=tol, max_period=2, easy_iterations=1, max_iterations=8,
        segments=1, calm_modulus=0.5, reseed=False,
    )  # fmt: skip
    cpu = time.process_time()
    c = mechanism.continuation(
        rigid_scene(), parameter=KEY, span=(start, stop), settings=settings, seeds=seeds
    )
    return c, time.process_time() - cpu


def diagram_seeds(diagram: xr.Dataset, start: float, stop: float) -> list[float]:
    """One seed per regular stretch of the orbit diagram inside the span."""
    lo, hi = min(start, stop), max(start, stop)
    return [s for _, _, s in mechanism.regular_stretches(diagram) if lo <= s <= hi]


def write_csv(path: Path, rows: list[dict]) -> None:
    def write(target: Path) -> None:
        with target.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(path, write)


def _part(job: tuple) -> tuple:
    """One process's share of the sweep: (continuation, CPU s, wall s, load at its end)."""
    start, stop, step, locate, seeds = job
    wall0 = time.perf_counter()
    c, cpu = run(start, stop, step, locate, None, seeds)
    return c, cpu, time.perf_counter() - wall0, os.getloadavg()[0]


def merged(parts: list[mechanism.Continuation]) -> mechanism.Continuation:
    """The continuations of the processes as one (branch indices shifted)."""
    branches, bifs = [], []
    for c in parts:
        offset = len(branches)
        branches.extend(c.branches)
        bifs.extend(dataclasses.replace(b, branch=b.branch + offset) for b in c.bifurcations)
    first = parts[0]
    return dataclasses.replace(
        first, branches=tuple(branches), bifurcations=tuple(bifs),
        orbit_solves=sum(c.orbit_solves for c in parts),
        cpu_time=sum(c.cpu_time for c in parts),
    )  # fmt: skip


def sweep(args: argparse.Namespace) -> None:
    """The span in two processes: below ``--split`` from ``--start`` up (and its seeds),
    above it from ``--stop`` down (and its seeds), each running ``--overlap`` rpm past
    the split so the branches from the seeds next to it reach their ends."""
    diagram = xr.open_dataset(DIAGRAM)
    seeds = diagram_seeds(diagram, args.start, args.stop)
    low = [s for s in seeds if s <= args.split]
    high = [s for s in seeds if s > args.split]
    jobs = [(args.start, args.split + args.overlap, args.step, args.locate, low)]
    if args.stop > args.split:
        jobs.append((args.stop, args.split - args.overlap, args.step, args.locate, high))
    print("parts:", jobs, flush=True)
    load0, wall0 = os.getloadavg()[0], time.perf_counter()
    with ProcessPoolExecutor(len(jobs), mp_context=multiprocessing.get_context("fork")) as pool:
        results = list(pool.map(_part, jobs))
    wall, load1 = time.perf_counter() - wall0, os.getloadavg()[0]
    c = merged([r[0] for r in results])
    cpu = sum(r[1] for r in results)
    ds = c.to_dataset()
    ds.attrs["seeds"] = ", ".join(f"{s:.6g}" for s in seeds)
    ds.attrs["processes"] = len(jobs)
    atomic_write(DOCS / "continuation-speed.nc", lambda p: ds.to_netcdf(p))
    rows = []
    for (start, stop, *_), (part, part_cpu, part_wall, part_load) in zip(
        jobs, results, strict=True
    ):
        rows.append({
            "part": f"{start:g}-{stop:g} rpm", "seeds": len(_[-1]),
            "cpu_s": round(part_cpu, 1), "wall_s": round(part_wall, 1),
            "load_start": round(load0, 1), "load_end": round(part_load, 1),
            "orbit_solves": part.orbit_solves,
            "points": sum(len(b.points) for b in part.branches),
            "branches": len(part.branches), "bifurcations": len(part.bifurcations),
        })  # fmt: skip
    rows.append({
        "part": f"total {args.start:g}-{args.stop:g} rpm (step {args.step:g}, locate "
        f"{args.locate:g})", "seeds": len(seeds), "cpu_s": round(cpu, 1),
        "wall_s": round(wall, 1), "load_start": round(load0, 1), "load_end": round(load1, 1),
        "orbit_solves": c.orbit_solves, "points": sum(len(b.points) for b in c.branches),
        "branches": len(c.branches), "bifurcations": len(c.bifurcations),
    })  # fmt: skip
    write_csv(DOCS / "continuation-cost.csv", rows)
    for row in rows:
        print(row)
    cost = {"date": time.strftime("%Y-%m-%d"), "cpu_s": round(cpu, 1),
            "orbit_solves": c.orbit_solves, "processes": len(jobs)}  # fmt: skip
    write_paper_data(paper_data(c, diagram, cost))
    for b in c.branches:
        print(f"branch period {b.period} {b.origin}: {b.parameter[0]:.2f}-{b.parameter[-1]:.2f} "
              f"rpm, {len(b.points)} points, end: {b.end}")  # fmt: skip
    for bif in c.bifurcations:
        where = "end of branch" if bif.branch_end else "on branch"
        print(f"{bif.kind} ({where} {bif.branch}) at {bif.parameter:.3f} rpm {bif.bracket}: "
              f"{bif.explanation}")  # fmt: skip
    r = mechanism.route(c, diagram)
    print("\n".join(r.lines()))
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        axes = mechanism.plot_bifurcation(diagram, continuation=c)
        axes[0].figure.savefig(DOCS / "continuation-speed.png", dpi=160)


def from_dataset(ds: xr.Dataset) -> mechanism.Continuation:
    """A continuation back from its stored Dataset (``to_dataset``): the points and the
    located points with the moduli of their multipliers, enough for ``route``."""
    branches = []
    for i in range(int(ds["branch"].max()) + 1 if ds.sizes["point"] else 0):
        rows = np.flatnonzero(ds["branch"].values == i)
        points = tuple(
            mechanism.ContinuationPoint(
                parameter=float(ds["parameter"].values[j]),
                state=ds["section_state"].values[j],
                multipliers=_finite(ds["multiplier_real"].values[j]
                                    + 1j * ds["multiplier_imag"].values[j]),
                stable=bool(ds["stable"].values[j]), residual=float(ds["residual"].values[j]),
                signature=tuple(str(ds["signature"].values[j]).split(" | ")),
                margin=float(ds["grazing_margin"].values[j]),
            )
            for j in rows
        )  # fmt: skip
        branches.append(
            mechanism.ContinuationBranch(period=int(ds["period"].values[rows[0]]), points=points)
        )
    bifs = tuple(
        mechanism.BifurcationPoint(
            kind=str(ds["bifurcation_kind"].values[b]),
            parameter=float(ds["bifurcation_parameter"].values[b]),
            bracket=(float(ds["bifurcation_low"].values[b]),
                     float(ds["bifurcation_high"].values[b])),
            branch=int(ds["bifurcation_branch"].values[b]),
            period=branches[int(ds["bifurcation_branch"].values[b])].period,
            multipliers_before=_finite(ds["modulus_before"].values[b]),
            multipliers_after=_finite(ds["modulus_after"].values[b]),
            explanation=str(ds["bifurcation_explanation"].values[b]),
            branch_end=bool(ds["bifurcation_branch_end"].values[b]),
        )
        for b in range(ds.sizes.get("bifurcation", 0))
    )  # fmt: skip
    return mechanism.Continuation(
        parameter=str(ds.attrs["continuation_parameter"]), units=str(ds.attrs["parameter_units"]),
        scene_name=str(ds.attrs["scene_name"]), branches=tuple(branches), bifurcations=bifs,
        settings=mechanism.ContinuationSettings(locate_tolerance=float(
            ds.attrs["locate_tolerance"])),
        orbit_solves=int(ds.attrs["orbit_solves"]), cpu_time=float(ds.attrs["cpu_time"]),
    )  # fmt: skip


def _finite(values: np.ndarray) -> np.ndarray:
    values = np.asarray(values)
    return values[np.isfinite(values)]


def _edge(b: mechanism.BifurcationPoint | None) -> dict | None:
    if b is None:
        return None
    return {
        "kind": b.kind, "rpm": round(b.parameter, 4),
        "bracket_rpm": [round(b.bracket[0], 4), round(b.bracket[1], 4)],
        "period": b.period, "branch_end": bool(b.branch_end), "explanation": b.explanation,
    }  # fmt: skip


def paper_data(c: mechanism.Continuation, diagram: xr.Dataset, cost: dict) -> dict:
    """The stored route of the paper study's report (mechanism/studies/paper/_route.py)."""
    r = mechanism.route(c, diagram)
    closings = r.closings or (None,) * len(r.windows)
    windows = [
        {"rpm": [round(lo, 2), round(hi, 2)], "onset": _edge(on), "closing": _edge(cl),
         "stable_inside": [[round(a, 2), round(b, 2)] for a, b in inside]}
        for (lo, hi), on, cl, inside in zip(r.windows, r.onsets, closings, r.inside,
                                            strict=True)
    ]  # fmt: skip
    stable = []
    for i, b in enumerate(c.branches):
        ps = b.parameter
        on = [p for p in b.points if p.stable]
        if on and min(p.parameter for p in on) <= COEXISTENCE_RPM <= max(p.parameter for p in on):
            stable.append(f"period {b.period} (branch {i}, {ps.min():.1f} - {ps.max():.1f} rpm)")
    coexistence = {"rpm": COEXISTENCE_RPM, "stable_orbits_followed": stable, "basins": None}
    if BASINS.exists():
        with BASINS.open() as fh:
            rows = [row for row in csv.DictReader(fh)
                    if float(row["rpm"]) == COEXISTENCE_RPM]  # fmt: skip
        if rows:
            counts = {row["motion"]: int(row["initial_states"]) for row in rows}
            inside = sum(n for m, n in counts.items() if m != "outside")
            coexistence["basins"] = {
                "grid": rows[0]["grid"], "revolutions": int(rows[0]["revolutions"]),
                "starts": inside, "extent": 0.9, "max_period": 4,
                "undetermined": counts.get("undetermined", 0),
                "periodic": inside - counts.get("undetermined", 0),
                "cpu_s": float(rows[0]["cpu_s"]),
            }  # fmt: skip
    p = c.branches[0].parameter if c.branches else np.zeros(1)
    return {
        "scene": "paper, effects.flexibility = false, radial clearance 0.2 mm",
        "span_rpm": [float(np.min(p)), float(max(b.parameter.max() for b in c.branches))],
        "locate_rpm": float(c.settings.locate_tolerance),
        "windows": windows,
        "branches": [
            {
                "period": b.period,
                "from_rpm": round(float(b.parameter[0]), 3),
                "to_rpm": round(float(b.parameter[-1]), 3),
                "points": len(b.points),
                "stable_points": int(b.stable.sum()),
                "origin": b.origin,
                "end": b.end,
            }
            for b in c.branches
        ],
        "coexistence": coexistence,
        "cost": cost,
        "recompute": "NUMBA_NUM_THREADS=1 python benchmarks/continuation.py sweep --start 30 "
        "--stop 300 --step 2 --locate 0.5 --figure",
    }


def write_paper_data(data: dict) -> None:
    text = json.dumps(data, indent=1, ensure_ascii=False) + "\n"
    atomic_write(PAPER_DATA, lambda path: path.write_text(text, encoding="utf-8"))


def paper(args: argparse.Namespace) -> None:
    """The paper report's stored route from the stored continuation and cost row."""
    ds = xr.load_dataset(DOCS / "continuation-speed.nc")
    with (DOCS / "continuation-cost.csv").open() as fh:
        row = list(csv.DictReader(fh))[-1]  # the total
    written = (DOCS / "continuation-speed.nc").stat().st_mtime
    cost = {"date": time.strftime("%Y-%m-%d", time.gmtime(written)),
            "cpu_s": float(row["cpu_s"]), "orbit_solves": int(row["orbit_solves"]),
            "processes": int(ds.attrs.get("processes", 1))}  # fmt: skip
    data = paper_data(from_dataset(ds), xr.open_dataset(DIAGRAM), cost)
    write_paper_data(data)
    print(json.dumps(data["windows"], indent=1))


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
    parser.add_argument("mode", choices=("sweep", "accuracy", "paper"))
    parser.add_argument("--start", type=float, default=30.0)
    parser.add_argument("--stop", type=float, default=300.0)
    parser.add_argument("--step", type=float, default=2.0)
    parser.add_argument("--locate", type=float, default=0.5)
    parser.add_argument("--figure", action="store_true")
    parser.add_argument("--split", type=float, default=147.0)
    parser.add_argument("--overlap", type=float, default=15.0)
    args = parser.parse_args()
    logging.basicConfig(
        level=logging.INFO, stream=sys.stderr, format="%(asctime)s %(process)d %(message)s"
    )
    if args.mode == "paper":
        paper(args)
        return
    # compile the kernels outside the measurement (a stable orbit: quick)
    mechanism.periodic_orbit(rigid_scene().replace({KEY: 30.0}), settle=2, max_iterations=1)
    (sweep if args.mode == "sweep" else accuracy)(args)


if __name__ == "__main__":
    main()
