"""Accuracy against cost of the knobs of ``mechanism.lyapunov_exponent`` on the rigid paper
scene at 150 rpm: tolerance, the deviation's tolerance, renormalisation interval and
perturbation size, each varied alone from the defaults.

Each setting runs ``--revolutions`` drive periods (``--discard`` of them left out) and adds
one row to ``docs/benchmarks/lyapunov-knobs.csv`` (exponent, 95 % interval, steps, CPU
and wall time); rows already in the file are not re-run, so an interrupted run resumes::

    NUMBA_NUM_THREADS=1 python benchmarks/lyapunov_knobs.py --revolutions 52 --discard 2
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import mechanism

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "benchmarks" / "lyapunov-knobs.csv"
FIELDS = [
    "knob", "rtol", "deviation_rtol", "renormalize_every", "perturbation", "revolutions",
    "exponent", "ci_low", "ci_high", "per_period", "steps", "rejected_steps",
    "function_evaluations", "cpu_time", "wall_time",
]  # fmt: skip

DEFAULTS = {"rtol": 1e-8, "deviation_rtol": 1e-4, "renormalize_every": 1, "perturbation": 1e-7}
# (knob varied, settings); the first row is the reference setting (the defaults)
SETTINGS: list[tuple[str, dict]] = [
    ("reference", {}),
    ("rtol", {"rtol": 1e-5, "atol": 1e-5}),
    ("rtol", {"rtol": 1e-6, "atol": 1e-6}),
    ("rtol", {"rtol": 1e-7, "atol": 1e-7}),
    ("rtol", {"rtol": 1e-9, "atol": 1e-9}),
    ("deviation_rtol", {"deviation_rtol": 1e-3}),
    ("deviation_rtol", {"deviation_rtol": 1e-2}),
    ("deviation_rtol", {"deviation_rtol": 0.0}),
    ("renormalize_every", {"renormalize_every": 10}),
    ("renormalize_every", {"renormalize_every": 100}),
    ("perturbation", {"perturbation": 1e-9}),
    ("perturbation", {"perturbation": 1e-5}),
]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--revolutions", type=float, default=52.0)
    parser.add_argument("--discard", type=float, default=2.0)
    args = parser.parse_args()
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    done = set()
    if OUT.exists():
        with OUT.open() as fh:
            done = {tuple(r[f] for f in FIELDS[:5]) for r in csv.DictReader(fh)}
    else:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        with OUT.open("w", newline="") as fh:
            csv.DictWriter(fh, fieldnames=FIELDS).writeheader()
    for knob, kw in SETTINGS:
        settings = {**DEFAULTS, **kw}
        key = (
            knob, f"{settings['rtol']:g}", f"{settings['deviation_rtol']:g}",
            str(settings["renormalize_every"]), f"{settings['perturbation']:g}",
        )  # fmt: skip
        if key in done:
            continue
        start, cpu = time.perf_counter(), time.process_time()
        result = mechanism.lyapunov_exponent(
            scene,
            revolutions=args.revolutions,
            discard=args.discard,
            settings=mechanism.LyapunovSettings(**kw),
        )
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        stats = result.stats
        assert stats is not None
        row = dict(zip(FIELDS[:5], key, strict=True))
        row.update(
            revolutions=f"{args.revolutions:g}",
            exponent=f"{result.exponent:.4g}",
            ci_low=f"{result.ci[0]:.4g}",
            ci_high=f"{result.ci[1]:.4g}",
            per_period=f"{result.exponent_per_period:.4g}",
            steps=stats.steps,
            rejected_steps=stats.rejected_steps,
            function_evaluations=stats.function_evaluations,
            cpu_time=f"{cpu:.1f}",
            wall_time=f"{wall:.1f}",
        )
        with OUT.open("a", newline="") as fh:
            csv.DictWriter(fh, fieldnames=FIELDS).writerow(row)
        print(row, flush=True)


if __name__ == "__main__":
    main()
