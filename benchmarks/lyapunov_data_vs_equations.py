"""Data-driven exponents (Wolf, Rosenstein) of the journal eccentricity against the exponent
from the equations, for the rigid paper scene at 150 rpm before and after wear.

Writes ``docs/benchmarks/lyapunov-data-vs-equations.csv`` (the table of
``docs/mechanism-lyapunov.md`` §5). Each piece is cached in ``--work`` so an interrupted
run resumes::

    python benchmarks/lyapunov_data_vs_equations.py --revolutions 220 --discard 20 \
        --work /tmp/lyap-d4 [--only equations-before]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import time
from pathlib import Path

import numpy as np
import xarray as xr

import chaoskit
import mechanism
from chaoskit.contract import write_netcdf

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "benchmarks" / "lyapunov-data-vs-equations.csv"
#: paper-matching worn state (docs/wear.md: peak-force ratio 2.51 after 4000 cycles)
WEAR = {"updates": 4, "cycles_per_update": 1000.0, "settle_revolutions": 2.0}
#: samples per drive period of the series handed to the data-driven estimators
SAMPLES_PER_PERIOD = 200


def scenes(work: Path, only: str | None) -> dict[str, mechanism.Scene]:
    before = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    if only is not None and only.endswith("before"):
        return {"before wear": before}
    path = work / "worn-scene.toml"
    if not path.exists():
        pred = mechanism.predict_wear(before, **WEAR)
        mechanism.save_scene(pred.worn_scene, path)
    return {"before wear": before, "after wear": mechanism.load_scene(path)}


def equations(scene: mechanism.Scene, path: Path, revolutions: float, discard: float) -> dict:
    if not path.exists():
        result = mechanism.lyapunov_exponent(
            scene, revolutions=revolutions, discard=discard, progress=True
        )
        write_netcdf(result.to_dataset(), path)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        a = dict(ds.attrs)
    return {
        "method": "equations (Benettin, full state)",
        "exponent": a["exponent"],
        "ci_low": a["ci_low"],
        "ci_high": a["ci_high"],
        "rtol": a["setting_rtol"],
        "verdict": "chaotic" if a["ci_low"] > 0 else ("regular" if a["ci_high"] < 0 else "—"),
        "wall_time": a["solver_wall_time"],
    }


def data_driven(
    scene: mechanism.Scene, path: Path, revolutions: float, discard: float, tol: float
) -> list[dict]:
    period = float(scene.drive.period)
    if not path.exists():
        start = time.perf_counter()
        # the grid only samples: the step is bounded as in the default run (T/10000)
        run = scene.replace({"solver.max_step": period / 1e4})
        ds = mechanism.simulate(
            run, revolutions=revolutions, rtol=tol, atol=tol, output_step=period / 1000
        )
        ecc = ds["eccentricity_x"].sel(joint="C").where(ds.time >= discard * period, drop=True)
        step = 1000 // SAMPLES_PER_PERIOD
        keep = ecc.isel(time=slice(0, None, step)).to_dataset(name="eccentricity_x")
        keep.attrs["simulate_wall_time"] = time.perf_counter() - start
        write_netcdf(keep, path)
    cached = path.with_suffix(".json")
    if cached.exists():
        return list(json.loads(cached.read_text()))
    with xr.open_dataset(path, engine="h5netcdf") as keep:
        x = keep["eccentricity_x"].values
        sim_wall = float(keep.attrs["simulate_wall_time"])
    dt = period / SAMPLES_PER_PERIOD
    start = time.perf_counter()
    verdict = chaoskit.classify(x, dt=dt, drive_period=period, rng=0)
    wall = time.perf_counter() - start
    rows = []
    for name, res in (("Wolf", verdict.wolf), ("Rosenstein", verdict.rosenstein)):
        rows.append(
            {
                "method": f"{name} on eccentricity x (rtol {tol:g})",
                "exponent": res.mle if res is not None else math.nan,
                "ci_low": res.ci[0] if res is not None else math.nan,
                "ci_high": res.ci[1] if res is not None else math.nan,
                "rtol": tol,
                "verdict": verdict.label,
                "wall_time": sim_wall + wall,
                "embedding_dim": verdict.embedding_dim,
                "lag": verdict.lag,
                "classify_wall_time": wall,
            }
        )
    cached.write_text(json.dumps(rows, default=float))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--revolutions", type=float, default=220.0)
    parser.add_argument("--discard", type=float, default=20.0)
    parser.add_argument("--work", type=Path, default=Path("lyapunov-d4"))
    parser.add_argument("--only", default=None, help="e.g. equations-before, data-after")
    args = parser.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    rows = []
    for state, scene in scenes(args.work, args.only).items():
        tag = state.split()[0]
        period = float(scene.drive.period)
        if args.only in (None, f"equations-{tag}"):
            row = equations(
                scene, args.work / f"equations-{tag}.nc", args.revolutions, args.discard
            )
            rows.append({"state": state, **row})
        if args.only in (None, f"data-{tag}"):
            for tol in (1e-8,):
                path = args.work / f"eccentricity-{tag}-{tol:g}.nc"
                for row in data_driven(scene, path, args.revolutions, args.discard, tol):
                    rows.append({"state": state, **row})
        for row in rows:
            row.setdefault("per_period", row["exponent"] * period)
    if args.only is not None:
        return
    fields = ["state", "method", "exponent", "ci_low", "ci_high", "per_period", "rtol"]
    fields += ["verdict", "embedding_dim", "lag", "wall_time"]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _fmt(row.get(k, "")) for k in fields})
    print(OUT.read_text())


def _fmt(value: object) -> object:
    if isinstance(value, float | np.floating):
        return f"{float(value):.4g}"
    return value


if __name__ == "__main__":
    main()
