"""CPU cost and accuracy of the flexible ``paper`` scene: this checkout against a git revision.

The scene's default flexible rods (16 + 16 ANCF elements, fixed-step generalized-α at
T/10000) at 150 rpm. For each tree — this checkout and ``--baseline`` (a git revision,
exported with ``git archive`` into a temporary directory) — fresh processes run,
alternating between the trees so that both see the same machine load:

* ``record="sections"`` over ``--revolutions``: CPU time per revolution of the whole
  ``simulate`` call (``time.process_time``: the main run and its ideal companion, i.e. the
  cost on one core), the solver counters and the stroboscopic journal positions;
* ``record="full"`` over the first revolution: peak contact force, extreme axial strain of
  each rod and the journal trajectory (eccentricity on the T/10000 grid).

A third run, the baseline with the journal started 1e-12 m off centre, measures how far a
round-off-sized difference carries over the same horizon: the mechanism with friction
and impacts is chaotic, so two correct integrations agree only as long as such a
perturbation stays small, and a change of the code is judged against it.

Writes ``docs/benchmarks/flexible-cost.csv`` and prints the comparison. Run from the
repository root::

    python benchmarks/flexible_cost.py --baseline 897d698 [--revolutions 2] [--rounds 2]

or, against another checkout (which keeps its compiled cache between runs),
``--baseline-tree ../other-clone``.
With ``--main-only`` both trees run ``SectionsRecord(companion=False)``: the main run
alone, without the ideal companion's integration.

``--companion`` measures instead what the ideal companion's result (the slider of the
mechanism with ideal joints, from which the displacement and speed errors are taken)
costs and how far it moves with the model that gives it: the flexible ideal mechanism
at the scene's step T/10000, at T/5000 (what ``simulate`` runs) and T/2500, and the
rigid ideal mechanism (dopri5). CPU per revolution of ``record="sections"`` on the ideal
scene alone, and on the ``record="full"`` grid the largest slider position and speed
differences from the T/10000 companion and the errors of the clearance run measured
against each; writes ``docs/benchmarks/flexible-companion.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/flexible_cost.py --companion [--revolutions 2]

``--ideal-step`` compares, in one process and alternated over ``--rounds``, the scene's
``record="sections"`` run with its ideal companion at the main run's step and at
``FLEXIBLE_IDEAL_STEP`` times it (what ``simulate`` runs): CPU per revolution (the least
of the rounds), the companion's Newton iterations and, from ``record="metrics"`` runs,
the displacement and speed errors; writes ``docs/benchmarks/flexible-ideal-step.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/flexible_cost.py --ideal-step [--revolutions 1]

``--without-companion`` runs, in fresh processes of this checkout alternated over
``--rounds``, ``record=SectionsRecord(companion=True)`` and
``SectionsRecord(companion=False)``: CPU per revolution of each ``simulate`` call and
whether the two runs' stroboscopic journal positions are identical (the main run must
not depend on the companion), with their largest distance; writes
``docs/benchmarks/flexible-sections-companion.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/flexible_cost.py --without-companion \
        [--revolutions 2] [--rounds 3]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tarfile
import tempfile
import time
from io import BytesIO
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "benchmarks" / "flexible-cost.csv"
COMPANION_OUT = ROOT / "docs" / "benchmarks" / "flexible-companion.csv"
IDEAL_STEP_OUT = ROOT / "docs" / "benchmarks" / "flexible-ideal-step.csv"
SECTIONS_COMPANION_OUT = ROOT / "docs" / "benchmarks" / "flexible-sections-companion.csv"
PERTURBATION = 1e-12  # m, initial journal offset of the chaos reference


def _worker(out: str, revolutions: float, offset: float, companion: bool = True) -> None:
    import mechanism

    scene = mechanism.load_scene("paper")
    if offset:
        scene = scene.replace({"joints.C.initial_eccentricity": [offset, 0.0]})
    record = mechanism.SectionsRecord(companion=companion)
    mechanism.simulate(scene, revolutions=0.02, record=record)  # compile / load
    cpu = time.process_time()
    ds = mechanism.simulate(scene, revolutions=revolutions, record=record)
    cpu = time.process_time() - cpu
    full = mechanism.simulate(scene, revolutions=1.0, record="full")
    row = {
        "cpu_s_per_rev": cpu / revolutions,
        "steps_per_rev": ds.attrs["solver_steps"] / revolutions,
        "newton_per_rev": ds.attrs["solver_newton_iterations"] / revolutions,
        "jacobians_per_rev": ds.attrs["solver_jacobian_evaluations"] / revolutions,
        "companion_newton_per_rev": ds.attrs.get("ideal_solver_newton_iterations", 0) / revolutions,
        "peak_contact_force_N": float(full.contact_force.max()),
        "max_penetration_m": float(full.penetration.max()),
    }
    for i, rod in enumerate(full.rod.values):
        strain = full.strain.values[:, i]
        row[f"strain_max_{rod}"] = float(strain.max())
        row[f"strain_min_{rod}"] = float(strain.min())
    np.savez(
        out,
        strobe=np.stack([ds.eccentricity_x.values.ravel(), ds.eccentricity_y.values.ravel()]),
        orbit=np.stack([full.eccentricity_x.values.ravel(), full.eccentricity_y.values.ravel()]),
        slider=full.slider_position.values.ravel(),
        force=full.contact_force.values.ravel(),
    )
    print(json.dumps(row))


def _sections_worker(out: str, revolutions: float, companion: bool) -> None:
    """One ``record="sections"`` run of the paper scene with or without the companion."""
    import mechanism

    scene = mechanism.load_scene("paper")
    record = mechanism.SectionsRecord(companion=companion)
    mechanism.simulate(scene, revolutions=0.02, record=record)  # compile / load
    cpu = time.process_time()
    ds = mechanism.simulate(scene, revolutions=revolutions, record=record)
    cpu = time.process_time() - cpu
    row = {
        "companion": companion,
        "cpu_s_per_rev": cpu / revolutions,
        "newton_per_rev": ds.attrs["solver_newton_iterations"] / revolutions,
        "companion_newton_per_rev": ds.attrs.get("ideal_solver_newton_iterations", 0) / revolutions,
        "max_displacement_error_m": float(ds["max_displacement_error"]),
        "max_speed_error_m_s": float(ds["max_speed_error"]),
    }
    np.savez(out, strobe=np.stack([ds.eccentricity_x.values, ds.eccentricity_y.values]))
    print(json.dumps(row))


def _without_companion(revolutions: float, rounds: int) -> None:
    """The sections run with and without the companion, alternated (module docstring)."""
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    rows, strobes = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(rounds):
            for companion in (True, False):
                out = Path(tmp) / f"{companion}.npz"
                cmd = [sys.executable, str(Path(__file__).resolve()), "--sections-worker",
                       str(out), "--revolutions", str(revolutions),
                       "--with-companion", str(int(companion))]  # fmt: skip
                done = subprocess.run(
                    cmd, cwd=ROOT, env=env, check=True, capture_output=True, text=True
                )
                row = {"round": r, **json.loads(done.stdout.strip().splitlines()[-1])}
                strobes[companion] = np.load(out)["strobe"]
                rows.append(row)
                print(json.dumps(row), flush=True)
            same = strobes[True].shape == strobes[False].shape
            diff = np.hypot(*(strobes[True] - strobes[False])).max() if same else np.inf
            uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
            for row in rows[-2:]:
                row["strobe_points"] = strobes[True][0].size  # crossings x joints
                row["strobe_identical"] = bool(np.array_equal(strobes[True], strobes[False]))
                row["strobe_max_diff_m"] = float(diff)
                row["load"] = uptime.split("load average:")[-1].strip()
    _write(SECTIONS_COMPANION_OUT, rows)
    for companion in (True, False):
        cpu = [row["cpu_s_per_rev"] for row in rows if row["companion"] == companion]
        print(f"companion={companion}: CPU s/rev {' '.join(f'{c:.3f}' for c in cpu)}")
    print(f"strobe points identical: {' '.join(str(row['strobe_identical']) for row in rows[::2])}")
    print(f"written: {SECTIONS_COMPANION_OUT}")


def _companion(revolutions: float) -> None:
    """The ideal companion's result from the flexible ideal mechanism at three steps and
    from the rigid one, against the companion ``simulate`` runs (module docstring)."""
    import mechanism

    scene = mechanism.load_scene("paper")
    period = 60.0 / 150.0
    mechanism.simulate(scene, revolutions=0.02, record="sections")  # compile / load
    main = mechanism.simulate(scene, revolutions=revolutions, record="full")
    ideal = scene.replace({"effects.clearance": False})
    variants = {
        "flexible T/10000 (the main run's step)": ideal,
        "flexible T/5000 (simulate's companion)": ideal.replace({"solver.max_step": period / 5000}),
        "flexible T/2500": ideal.replace({"solver.max_step": period / 2500}),
        "rigid (dopri5)": ideal.replace({"effects.flexibility": False}),
    }
    rows, ref = [], None
    for name, variant in variants.items():
        mechanism.simulate(variant, revolutions=0.02, record="sections")
        cpu = time.process_time()
        mechanism.simulate(variant, revolutions=revolutions, record="sections")
        cpu = time.process_time() - cpu
        ds = mechanism.simulate(variant, revolutions=revolutions, record="full")
        x, v = ds.slider_position.values, ds.slider_velocity.values
        ref = (x, v) if ref is None else ref
        row = {
            "companion": name,
            "cpu_s_per_rev": cpu / revolutions,
            "steps_per_rev": ds.attrs["solver_steps"] / revolutions,
            "slider_position_diff_m": float(np.abs(x - ref[0]).max()),
            "slider_speed_diff_m_s": float(np.abs(v - ref[1]).max()),
            "max_displacement_error_m": float(np.abs(main.slider_position.values - x).max()),
            "max_speed_error_m_s": float(np.abs(main.slider_velocity.values - v).max()),
        }
        rows.append(row)
        print(json.dumps(row), flush=True)
    _write(COMPANION_OUT, rows)
    print(f"written: {COMPANION_OUT}")


def _ideal_step(revolutions: float, rounds: int) -> None:
    """The sections run with the ideal companion at the main run's step and at
    ``FLEXIBLE_IDEAL_STEP`` times it, alternated in one process (module docstring)."""
    import mechanism
    import mechanism.core._simulate as simulate_module

    scene = mechanism.load_scene("paper")
    factors = (1.0, simulate_module.FLEXIBLE_IDEAL_STEP)
    mechanism.simulate(scene, revolutions=0.02, record="sections")  # compile / load
    best = dict.fromkeys(factors, float("inf"))
    rows = {}
    try:
        for _ in range(rounds):
            for factor in factors:
                simulate_module.FLEXIBLE_IDEAL_STEP = factor
                cpu = time.process_time()
                ds = mechanism.simulate(scene, revolutions=revolutions, record="sections")
                best[factor] = min(best[factor], time.process_time() - cpu)
                rows[factor] = {
                    "companion_step": f"{factor:g} x main step",
                    "companion_newton_per_rev": ds.attrs["ideal_solver_newton_iterations"]
                    / revolutions,
                    "main_newton_per_rev": ds.attrs["solver_newton_iterations"] / revolutions,
                }
        for factor in factors:
            simulate_module.FLEXIBLE_IDEAL_STEP = factor
            metrics = mechanism.simulate(scene, revolutions=revolutions, record="metrics")
            rows[factor] |= {
                "cpu_s_per_rev": best[factor] / revolutions,
                "max_displacement_error_m": float(metrics["max_displacement_error"]),
                "max_speed_error_m_s": float(metrics["max_speed_error"]),
            }
            print(json.dumps(rows[factor]), flush=True)
    finally:
        simulate_module.FLEXIBLE_IDEAL_STEP = factors[1]
    _write(IDEAL_STEP_OUT, list(rows.values()))
    print(f"written: {IDEAL_STEP_OUT}")


def _write(path: Path, rows: list[dict]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fields = list(dict.fromkeys(k for row in rows for k in row))
    tmp_out = path.with_suffix(".csv.tmp")
    with tmp_out.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    tmp_out.replace(path)


def _export(revision: str, into: Path) -> Path:
    data = subprocess.run(
        ["git", "archive", revision], cwd=ROOT, check=True, capture_output=True
    ).stdout
    with tarfile.open(fileobj=BytesIO(data)) as tar:
        tar.extractall(into, filter="data")
    return into


def _run(
    tree: Path, out: Path, revolutions: float, offset: float = 0.0, companion: bool = True
) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_NUM_THREADS="1")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", str(out),
           "--revolutions", str(revolutions), "--offset", str(offset),
           "--with-companion", str(int(companion))]  # fmt: skip
    done = subprocess.run(cmd, cwd=tree, env=env, check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="main", help="git revision to compare with")
    parser.add_argument(
        "--baseline-tree", type=Path,
        help="a checkout to compare with instead of --baseline (its compiled cache is kept)",
    )  # fmt: skip
    parser.add_argument("--revolutions", type=float, default=2.0)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--offset", type=float, default=0.0, help=argparse.SUPPRESS)
    parser.add_argument(
        "--companion", action="store_true", help="measure the ideal companion's alternatives"
    )
    parser.add_argument(
        "--ideal-step", action="store_true",
        help="the sections run with the companion at the main step and at the default",
    )  # fmt: skip
    parser.add_argument(
        "--without-companion", action="store_true",
        help="the sections run with and without the ideal companion, alternated",
    )  # fmt: skip
    parser.add_argument(
        "--main-only", action="store_true",
        help="compare the trees on the sections run without its ideal companion",
    )  # fmt: skip
    parser.add_argument("--sections-worker", help=argparse.SUPPRESS)
    parser.add_argument("--with-companion", type=int, default=1, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.sections_worker:
        _sections_worker(args.sections_worker, args.revolutions, bool(args.with_companion))
        return
    if args.without_companion:
        _without_companion(args.revolutions, args.rounds)
        return
    if args.ideal_step:
        _ideal_step(args.revolutions, args.rounds)
        return
    if args.companion:
        _companion(args.revolutions)
        return
    if args.worker:
        _worker(args.worker, args.revolutions, args.offset, bool(args.with_companion))
        return
    with tempfile.TemporaryDirectory() as tmp:
        if args.baseline_tree is not None:
            base = args.baseline_tree.resolve()
        else:
            base = _export(args.baseline, Path(tmp) / "baseline")
        trees = {"baseline": base, "this": ROOT}
        rows = []
        files = {}
        for r in range(args.rounds):
            for name, tree in trees.items():
                files[name] = Path(tmp) / f"{name}.npz"
                run = _run(tree, files[name], args.revolutions, companion=not args.main_only)
                row = {"tree": name, "round": r, "companion": not args.main_only, **run}
                rows.append(row)
                print(json.dumps(row))
        files["perturbed"] = Path(tmp) / "perturbed.npz"
        row = {"tree": "baseline, journal 1e-12 m off", "round": 0,
               **_run(base, files["perturbed"], args.revolutions, PERTURBATION,
                      companion=not args.main_only)}  # fmt: skip
        rows.append(row)
        ref = np.load(files["baseline"])
        for name in ("this", "perturbed"):
            other = np.load(files[name])
            strobe = np.hypot(*(other["strobe"] - ref["strobe"]))
            orbit = np.hypot(*(other["orbit"] - ref["orbit"]))
            eccentricity = np.abs(np.hypot(*other["orbit"]) - np.hypot(*ref["orbit"]))
            for row in rows:
                if row["tree"].startswith(name if name == "this" else "baseline, journal"):
                    row["orbit_rev1_max_diff_m"] = float(orbit.max())
                    row["eccentricity_rev1_max_diff_m"] = float(eccentricity.max())
                    row["slider_rev1_max_diff_m"] = float(
                        np.abs(other["slider"] - ref["slider"]).max()
                    )
                    row["force_rev1_max_diff_N"] = float(
                        np.abs(other["force"] - ref["force"]).max()
                    )
                    row["strobe_diff_m"] = " ".join(f"{d:.2e}" for d in strobe)
        uptime = subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    for row in rows:
        row["load"] = uptime.split("load average:")[-1].strip()
    _write(OUT, rows)
    for name in ("baseline", "this"):
        cpu = [row["cpu_s_per_rev"] for row in rows if row["tree"] == name]
        print(f"{name}: CPU s/rev {' '.join(f'{c:.3f}' for c in cpu)}")
    print(f"written: {OUT} ({uptime})")


if __name__ == "__main__":
    main()
