"""Where the time goes: solver counters, compiled vs Python time, and compile cost.

For each run it measures the process CPU time, the counters the integrators return
(accepted and rejected steps, right-hand-side evaluations, Jacobians, Newton iterations,
contact-law calls and contact events — ``ds.attrs["solver_*"]`` or
``SceneLyapunov.stats``), and a cProfile of the run split into time inside compiled
kernels (numba dispatchers) and Python between them:

* the rigid and the flexible ``paper`` scene at 150 rpm: ``simulate(record="full")``,
  ``simulate(record="sections")`` and ``lyapunov_exponent``, per revolution;
* the clearance slider-crank (μ = 0.1, 5000 rpm) for 0.2 s;
* Simeon's flexible slider-crank (16 elements) for 0.1 s;
* ``lyapunov_rosenstein`` on Lorenz x, N = 50 000, all reference points;
* a fresh install (``--compile``): first calls in a child process whose numba cache is an
  empty folder (``NUMBA_CACHE_DIR``), minus the same calls warm;
* the exponent's cost: ``lyapunov_exponent`` against ``simulate(record="sections")`` of
  the same revolutions, side by side in one process and alternated ``--repeats`` times
  (the least CPU time of each kept, so the machine's load falls on both alike), for the
  rigid paper scene with the directional and the split difference of the deviation, and
  for the flexible one; with the exponent and its interval (``--exponent-cost-only`` runs
  this part alone and writes ``docs/benchmarks/exponent-cost.csv``).

Writes ``docs/benchmarks/profiles.csv`` and prints the tables. Run from the repository
root (about 3 minutes of CPU, plus about 3 for ``--compile``):

    NUMBA_NUM_THREADS=1 python benchmarks/profiles.py [--compile] [--out FILE]
"""

from __future__ import annotations

import argparse
import cProfile
import csv
import math
import os
import pstats
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mechanism
from chaoskit import lyapunov_rosenstein, systems
from chaoskit.contract import atomic_write

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "profiles.csv"
#: where ``--exponent-cost-only`` writes by default
OUT_EXPONENT = OUT.with_name("exponent-cost.csv")
COUNTERS = (
    "steps",
    "rejected_steps",
    "function_evaluations",
    "jacobian_evaluations",
    "newton_iterations",
    "contact_evaluations",
    "contact_events",
)


def _paper(flexible: bool):
    scene = mechanism.load_scene("paper")
    return scene if flexible else scene.replace({"effects.flexibility": False})


def _clearance():
    return mechanism.load_scene("slider-crank-clearance").replace(
        {"joints.B.friction.coefficient": 0.1}
    )


def _compiled_time(stats: pstats.Stats) -> tuple[float, list[tuple[str, float]]]:
    """Time spent in compiled code and the five largest Python entries (own time).

    A numba dispatcher call is a C call that cProfile lists as a built-in; its own time is
    the kernel's time. Everything else is Python (numpy included)."""
    compiled = 0.0
    python: list[tuple[str, float]] = []
    for (fname, line, func), (_, _, tottime, _, _) in stats.stats.items():  # type: ignore[attr-defined]
        if fname == "~" and ("Dispatcher" in func or "_compile_for_args" in func):
            compiled += tottime
        elif "_kernels" in fname or ("numba" in fname and "dispatcher" in fname):
            compiled += tottime
        else:
            python.append((f"{Path(fname).name}:{line}({func})", tottime))
    python.sort(key=lambda t: -t[1])
    return compiled, python[:5]


def profile(name: str, func, per: float, unit: str) -> dict:
    """Run ``func`` under cProfile; CPU time (process) and the split."""
    prof = cProfile.Profile()
    cpu = time.process_time()
    prof.enable()
    out = func()
    prof.disable()
    cpu = time.process_time() - cpu
    stats = pstats.Stats(prof)
    total = sum(v[2] for v in stats.stats.values())  # type: ignore[attr-defined]
    compiled, top = _compiled_time(stats)
    row = {
        "run": name,
        "unit": unit,
        "cpu_s": cpu,
        "cpu_s_per_unit": cpu / per,
        "compiled_share": compiled / total if total > 0 else float("nan"),
        "python_top": "; ".join(f"{n} {t:.3f}s" for n, t in top[:3]),
    }
    counters = _counters(out)
    for key in COUNTERS:
        if key in counters:
            row[f"{key}_per_unit"] = counters[key] / per
    if counters.get("wall_time"):
        row["solver_wall_s"] = counters["wall_time"]
    print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
    return row


def _counters(out) -> dict:
    stats = getattr(out, "stats", None)
    if stats is not None:
        return {k: getattr(stats, k) for k in (*COUNTERS, "wall_time") if hasattr(stats, k)}
    attrs = getattr(out, "attrs", {})
    return {k: attrs[f"solver_{k}"] for k in (*COUNTERS, "wall_time") if f"solver_{k}" in attrs}


def scene_rows(revs_rigid: float, revs_flex: float, exp_revs: float) -> list[dict]:
    rows = []
    for flexible, revs in ((False, revs_rigid), (True, revs_flex)):
        label = "flexible" if flexible else "rigid"
        scene = _paper(flexible)
        for record in ("full", "sections"):
            mechanism.simulate(scene, revolutions=0.02, record=record)  # compile / load
            rows.append(
                profile(
                    f"paper {label} simulate record={record}",
                    lambda scene=scene, revs=revs, record=record: mechanism.simulate(
                        scene, revolutions=revs, record=record
                    ),
                    revs,
                    "revolution",
                )
            )
        mechanism.lyapunov_exponent(scene, revolutions=0.2)  # compile / load
        rows.append(
            profile(
                f"paper {label} lyapunov_exponent",
                lambda scene=scene: mechanism.lyapunov_exponent(scene, revolutions=exp_revs),
                exp_revs,
                "revolution",
            )
        )
    return rows


def _exponent_row(name: str, out, cpu: float, revs: float, sections_cpu: float) -> dict:
    stats = out.stats
    attempted = stats.steps + stats.rejected_steps
    row = {
        "run": name,
        "unit": "revolution",
        "cpu_s_per_unit": cpu / revs,
        "cpu_over_sections": cpu / sections_cpu,
        "exponent": out.exponent,
        "ci_low": out.ci[0],
        "ci_high": out.ci[1],
        "steps_per_unit": stats.steps / revs,
        "rejected_steps_per_unit": stats.rejected_steps / revs,
        "function_evaluations_per_unit": stats.function_evaluations / revs,
        "function_evaluations_per_attempted_step": stats.function_evaluations / attempted,
    }
    print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
    return row


def exponent_cost_rows(revs_rigid: float, revs_flex: float, repeats: int) -> list[dict]:
    """``lyapunov_exponent`` against a sections run of the same revolutions, in one
    process: the least CPU time of ``repeats`` alternated runs of each."""
    rigid = _paper(False)
    cases = [
        ("rigid", rigid, revs_rigid, "directional", mechanism.LyapunovSettings()),
        ("rigid", rigid, revs_rigid, "split", mechanism.LyapunovSettings(difference="split")),
        ("flexible", _paper(True), revs_flex, "copy", mechanism.LyapunovSettings()),
    ]
    rows = []
    for label in ("rigid", "flexible"):
        mine = [c for c in cases if c[0] == label]
        scene, revs = mine[0][1], mine[0][2]
        mechanism.simulate(scene, revolutions=0.02, record="sections")  # compile / load
        for case in mine:
            mechanism.lyapunov_exponent(scene, revolutions=0.02, settings=case[4])
        best = {"sections": math.inf} | {c[3]: math.inf for c in mine}
        results = {}
        for _ in range(repeats):
            cpu = time.process_time()
            ds = mechanism.simulate(scene, revolutions=revs, record="sections")
            best["sections"] = min(best["sections"], time.process_time() - cpu)
            for case in mine:
                cpu = time.process_time()
                results[case[3]] = mechanism.lyapunov_exponent(
                    scene, revolutions=revs, settings=case[4]
                )
                best[case[3]] = min(best[case[3]], time.process_time() - cpu)
        row = {
            "run": f"exponent cost: paper {label} simulate record=sections",
            "unit": "revolution",
            "cpu_s_per_unit": best["sections"] / revs,
            "cpu_over_sections": 1.0,
        }
        row |= {f"{k}_per_unit": v / revs for k, v in _counters(ds).items() if k in COUNTERS}
        print(row, flush=True)
        rows.append(row)
        for case in mine:
            name = f"exponent cost: paper {label} lyapunov_exponent difference={case[3]}"
            rows.append(_exponent_row(name, results[case[3]], best[case[3]], revs,
                                      best["sections"]))  # fmt: skip
    return rows


def other_rows() -> list[dict]:
    rows = []
    s3 = _clearance()
    mechanism.simulate(s3, t_end=1e-3)
    rows.append(
        profile(
            "slider-crank-clearance mu=0.1 simulate",
            lambda: mechanism.simulate(s3, t_end=0.2, output_step=1e-4),
            0.2,
            "simulated second",
        )
    )
    s6 = mechanism.load_scene("flexible-slider-crank")
    mechanism.simulate(s6, t_end=1e-3)
    rows.append(
        profile(
            "flexible-slider-crank (Simeon) simulate",
            lambda: mechanism.simulate(s6, t_end=0.1),
            0.1,
            "simulated second",
        )
    )
    x = systems.lorenz(50_000, dt=0.01)[:, 0]
    kw = dict(
        dt=0.01,
        embedding_dim=3,
        lag=10,
        theiler_window=100,
        max_horizon=300,
        fit_range=(20, 250),
        max_points=10**9,
        neighbor="sample",
        distance="euclidean",
    )
    lyapunov_rosenstein(x[:5000], **kw)
    rows.append(
        profile(
            "lyapunov_rosenstein Lorenz x N=50000 all references",
            lambda: lyapunov_rosenstein(x, **kw),
            1.0,
            "call",
        )
    )
    return rows


_COMPILE = """
import time, mechanism
from chaoskit import lyapunov_rosenstein, systems
scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
x = systems.lorenz(10_000, dt=0.01)[:, 0]
for name, f in (
    ("simulate rigid paper 0.02 rev", lambda: mechanism.simulate(scene, revolutions=0.02)),
    ("lyapunov_exponent rigid paper 0.05 rev",
     lambda: mechanism.lyapunov_exponent(scene, revolutions=0.05)),
    ("lyapunov_rosenstein defaults", lambda: lyapunov_rosenstein(x, dt=0.01)),
):
    c, w = time.process_time(), time.perf_counter(); f()
    c1, w1 = time.process_time() - c, time.perf_counter() - w
    c, w = time.process_time(), time.perf_counter(); f()
    print(name, "|", c1 - (time.process_time() - c), "|", w1 - (time.perf_counter() - w))
"""


def compile_rows() -> list[dict]:
    with tempfile.TemporaryDirectory() as cache:
        env = os.environ | {"NUMBA_CACHE_DIR": cache}
        out = subprocess.run(
            [sys.executable, "-c", _COMPILE], env=env, check=True, capture_output=True, text=True
        ).stdout
    rows = []
    for line in out.splitlines():
        name, cpu, wall = (v.strip() for v in line.split("|"))
        rows.append(
            {
                "run": f"fresh install: first {name}",
                "unit": "first call minus warm call",
                "cpu_s": float(cpu),
                "wall_s": float(wall),
            }
        )
        print(rows[-1], flush=True)
    return rows


def write_rows(path: Path, rows: list[dict]) -> None:
    fields: list[str] = []
    for row in rows:
        fields += [k for k in row if k not in fields]

    def writer(tmp: Path) -> None:
        with tmp.open("w", newline="") as fh:
            out = csv.DictWriter(fh, fieldnames=fields)
            out.writeheader()
            for row in rows:
                out.writerow(
                    {k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()}
                )

    atomic_write(path, writer)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=float, default=3.0, help="rigid paper scene")
    parser.add_argument("--flexible-revolutions", type=float, default=0.5)
    parser.add_argument("--exponent-revolutions", type=float, default=1.0)
    parser.add_argument("--compile", action="store_true", help="also time a fresh install")
    parser.add_argument("--repeats", type=int, default=3, help="runs of each in the exponent cost")
    parser.add_argument(
        "--exponent-cost-only", action="store_true", help="only the exponent's cost"
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help=f"CSV to write (default {OUT.name}, or {OUT_EXPONENT.name} with --exponent-cost-only)",
    )
    args = parser.parse_args()
    for name in ("revolutions", "flexible_revolutions", "exponent_revolutions"):
        if getattr(args, name) <= 0:
            parser.error(f"--{name.replace('_', '-')} must be > 0")
    if args.repeats < 1:
        parser.error("--repeats must be >= 1")
    rows = exponent_cost_rows(args.revolutions, args.flexible_revolutions, args.repeats)
    if not args.exponent_cost_only:
        rows += scene_rows(args.revolutions, args.flexible_revolutions, args.exponent_revolutions)
        rows += other_rows()
    if args.compile:
        rows += compile_rows()
    out = args.out or (OUT_EXPONENT if args.exponent_cost_only else OUT)
    write_rows(out, rows)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
