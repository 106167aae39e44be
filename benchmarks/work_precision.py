"""Work–precision study of the simulator: error against a tight reference versus wall time.

For each scene (the S3 clearance slider-crank with μ = 0.1 and the paper six-bar with rigid
rods), each contact law (Lankarani–Nikravesh, Hertz, Flores, Hu–Guo) and each integrator ×
tolerance, the run is compared with a reference of the same scene and law (dopri5,
rtol = atol = 1e-11, same output grid and step cap) on the common output grid:

* ``peak_force_rel_err`` — |max Fₙ − max Fₙ,ref| / max Fₙ,ref (peak contact force);
* ``slider_err_m`` — max |s − s_ref| (m, slider position);
* ``orbit_err_rel_c`` — max |e − e_ref| / c (journal orbit, fraction of the clearance);
* ``drift_m`` — max |Φ| (constraint violation);
* wall time of the whole ``mechanism.simulate`` call (s, includes the ideal companion and
  the Dataset) and the main run's solver counters.

Two step-cap settings are measured: ``cap = "output"`` (the scene default: the largest step
is the output step, so no impact is stepped over) for the tolerance sweep of every method,
and a step-cap sweep (``max_step`` = 1, 4, 16, 64 output steps) for dopri5 at the default
tolerance 1e-5. The element-count axis (4 … 24 ANCF elements per rod; peak contact force
and slider position against 24 elements at rtol 1e-8, over 5 % of a revolution) is measured
only when ``effects.flexibility = true`` runs on the paper scene; otherwise it is skipped and
the reason is printed and written to ``work-precision-elements.csv``. Rod strain is not an
output of ``mechanism.simulate`` yet, so it is not measured.

A conclusions table (``conclusions_study``) checks which settings keep what the paper scene
already gives without wear: the peak contact force and the arcs holding 80 % of the Archard
wear rate Fₙ|v_t| (over revolutions 2–4, 2–8 in the full run, against dopri5 at 1e-9).

Finally the analysis study ``benchmarks/mle_accuracy_vs_n.py`` is run (not duplicated) with
the same ``--quick`` flag.

Writes into ``docs/benchmarks/``: ``work-precision.csv``, ``work-precision-s3.png``,
``work-precision-paper.png``, ``work-precision-elements.csv``/``.png``,
``work-precision-conclusions.csv`` and
``mle-vs-n.csv``/``.png``
(with ``--quick`` the analysis tables go to ``docs/benchmarks/quick/`` so that the full-range
``mle-vs-n`` table is not replaced by a shorter one). Run from the repository root:

    python benchmarks/work_precision.py [--quick] [--skip-mle]

``--quick`` (about 5 minutes of CPU on the 2-core development machine, numba cache warm)
uses fewer tolerances, the implicit and scipy methods at fewer points and shorter windows.
Wall times on a shared machine are inflated by other jobs; compare them with each other.
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import mechanism

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "benchmarks"
LAWS = ("lankarani-nikravesh", "hertz", "flores", "hu-guo")
REF_TOL = 1e-11
FIELDS = [
    "scene",
    "law",
    "method",
    "tol",
    "cap",
    "max_step",
    "output_step",
    "t_end",
    "status",
    "wall_s",
    "solver_wall_s",
    "steps",
    "rejected",
    "fevals",
    "contact_events",
    "peak_force",
    "peak_force_rel_err",
    "slider_err_m",
    "orbit_err_rel_c",
    "drift_m",
    "max_penetration_rel_c",
]


@dataclass(frozen=True, kw_only=True)
class Case:
    """One scene of the study: its scene, clearance joint, window and output step."""

    name: str
    scene: mechanism.Scene
    joint: str
    t_end: float
    output_step: float

    def with_law(self, law: str, max_step: float | None = None) -> mechanism.Scene:
        changes: dict[str, object] = {f"joints.{self.joint}.contact.law": law}
        if max_step is not None:
            changes["solver.max_step"] = max_step
        return self.scene.replace(changes)


def _cases(quick: bool) -> list[Case]:
    s3 = mechanism.load_scene("slider-crank-clearance")  # μ = 0.1, 5000 rpm, c = 0.5 mm
    # rigid rods (explicitly: the built-in default is flexible), 150 rpm, c = 0.2 mm
    paper = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    s3_period = s3.drive.period
    paper_period = paper.drive.period
    return [
        # two revolutions: free flight, the first impacts and the onset of sliding contact
        Case(
            name="s3",
            scene=s3,
            joint="B",
            t_end=(1.0 if quick else 2.0) * s3_period,
            output_step=2e-6,
        ),
        # half a revolution of the paper scene (a quarter in --quick)
        Case(
            name="paper",
            scene=paper,
            joint="C",
            t_end=(0.25 if quick else 0.5) * paper_period,
            output_step=paper_period / 10000,
        ),
    ]


def _method_grid(quick: bool) -> list[tuple[str, float]]:
    if quick:
        grid = [("dopri5", t) for t in (1e-3, 1e-5, 1e-7, 1e-9)]
        grid += [("generalized-alpha", t) for t in (1e-3, 1e-5)]
        return grid
    grid = [("dopri5", 10.0**-k) for k in range(3, 10)]
    grid += [("generalized-alpha", 10.0**-k) for k in range(3, 8)]
    return grid


def _scipy_grid(quick: bool) -> list[tuple[str, float]]:
    # scipy steps the compiled right-hand side from Python: 10–100× slower, so only a few
    # points and only for the L-N law (the scene default)
    if quick:
        return [("LSODA", 1e-5)]
    return [(m, t) for m in ("LSODA", "DOP853", "Radau") for t in (1e-5, 1e-7)]


def _run(scene, case: Case, method: str, tol: float):
    t0 = time.perf_counter()
    ds = mechanism.simulate(
        scene,
        t_end=case.t_end,
        method=method,
        rtol=tol,
        atol=tol,
        output_step=case.output_step,
        throw=False,
    )
    return ds, time.perf_counter() - t0


def _errors(ds, ref, clearance: float) -> dict[str, float]:
    n = min(ds.sizes["time"], ref.sizes["time"])
    if ds.attrs["solver_status"] < 0 or n < ref.sizes["time"]:
        nan = float("nan")
        return {
            "peak_force_rel_err": nan,
            "slider_err_m": nan,
            "orbit_err_rel_c": nan,
            "drift_m": nan,
        }
    f = ds.contact_force.isel(joint=0).values
    f_ref = ref.contact_force.isel(joint=0).values
    ex = ds.eccentricity_x.isel(joint=0).values - ref.eccentricity_x.isel(joint=0).values
    ey = ds.eccentricity_y.isel(joint=0).values - ref.eccentricity_y.isel(joint=0).values
    return {
        "peak_force_rel_err": abs(f.max() - f_ref.max()) / f_ref.max(),
        "slider_err_m": float(np.abs(ds.slider_position.values - ref.slider_position.values).max()),
        "orbit_err_rel_c": float(np.hypot(ex, ey).max() / clearance),
        "drift_m": float(ds.constraint_violation.max()),
    }


def _row(case, law, method, tol, cap, max_step, ds, wall, ref) -> dict:
    clearance = case.scene.joints[case.joint].clearance
    row = {
        "scene": case.name,
        "law": law,
        "method": method,
        "tol": tol,
        "cap": cap,
        "max_step": max_step,
        "output_step": case.output_step,
        "t_end": case.t_end,
        "status": ds.attrs["solver_status"],
        "wall_s": wall,
        "solver_wall_s": ds.attrs["solver_wall_time"],
        "steps": ds.attrs["solver_steps"],
        "rejected": ds.attrs["solver_rejected_steps"],
        "fevals": ds.attrs["solver_function_evaluations"],
        "contact_events": ds.attrs["solver_contact_events"],
        "peak_force": float(ds.contact_force.max()) if ds.sizes["time"] else float("nan"),
        "max_penetration_rel_c": float(ds.penetration.max()) / clearance
        if ds.sizes["time"]
        else float("nan"),
    }
    row.update(_errors(ds, ref, clearance))
    return row


def _print(row: dict) -> None:
    print(
        f"{row['scene']:6s} {row['law']:19s} {row['method']:17s} tol={row['tol']:.0e} "
        f"cap={row['cap']:>6s} status={row['status']:2d} wall={row['wall_s']:7.2f}s "
        f"steps={row['steps']:7d}  dF={row['peak_force_rel_err']:.2e} "
        f"ds={row['slider_err_m']:.2e} m  de={row['orbit_err_rel_c']:.2e} c",
        flush=True,
    )


def simulator_study(quick: bool) -> list[dict]:
    """The integrator × tolerance × contact law × step cap table for both scenes."""
    rows: list[dict] = []
    for case in _cases(quick):
        for law in LAWS:
            scene = case.with_law(law)
            ref, ref_wall = _run(scene, case, "dopri5", REF_TOL)
            if ref.attrs["solver_status"] < 0:
                print(f"reference failed for {case.name}/{law}: {ref.attrs['solver_message']}")
                continue
            row = _row(case, law, "dopri5", REF_TOL, "output", case.output_step, ref, ref_wall, ref)
            row["cap"] = "ref"
            rows.append(row)
            grid = _method_grid(quick)
            if law == "lankarani-nikravesh":
                grid = grid + _scipy_grid(quick)
            for method, tol in grid:
                ds, wall = _run(scene, case, method, tol)
                rows.append(_row(case, law, method, tol, "output", case.output_step, ds, wall, ref))
                _print(rows[-1])
            if law == "lankarani-nikravesh":
                for factor in (4, 16, 64):
                    max_step = factor * case.output_step
                    ds, wall = _run(case.with_law(law, max_step), case, "dopri5", 1e-5)
                    rows.append(
                        _row(case, law, "dopri5", 1e-5, f"{factor}x", max_step, ds, wall, ref)
                    )
                    _print(rows[-1])
    return rows


def element_study(quick: bool) -> list[dict]:
    """Element count 4 … 24 per rod on the paper scene with flexible rods, if they run."""
    paper = mechanism.load_scene("paper")
    t_end = 0.05 * paper.drive.period
    # dopri5 pinned: the published rows measured the explicit step; the scene's "auto"
    # would now pick the fixed-step generalized-α for flexible rods
    probe = paper.replace({"effects.flexibility": True, "solver.method": "dopri5"})
    try:
        mechanism.simulate(probe, t_end=t_end / 10, output_step=t_end / 100)
    except Exception as exc:  # any failure means the axis cannot be measured
        reason = f"{type(exc).__name__}: {exc}"
        print(f"element-count axis skipped: flexible rods do not run ({reason})")
        return [{"elements": "", "status": "skipped", "reason": reason}]
    counts = (4, 8, 16) if quick else (4, 8, 12, 16, 20, 24)
    rows = []
    ref_scene = probe.replace({"bodies.rod3.elements": 24, "bodies.rod4.elements": 24})
    ref = mechanism.simulate(ref_scene, t_end=t_end, rtol=1e-8, atol=1e-8, throw=False)
    for count in counts:
        scene = probe.replace({"bodies.rod3.elements": count, "bodies.rod4.elements": count})
        t0 = time.perf_counter()
        ds = mechanism.simulate(scene, t_end=t_end, throw=False)
        wall = time.perf_counter() - t0
        f, f_ref = float(ds.contact_force.max()), float(ref.contact_force.max())
        rows.append(
            {
                "elements": count,
                "status": str(ds.attrs["solver_status"]),
                "reason": ds.attrs["solver_message"],
                "wall_s": wall,
                "steps": ds.attrs["solver_steps"],
                "peak_force": f,
                "peak_force_rel_err": abs(f - f_ref) / f_ref,
                "slider_err_m": float(
                    np.abs(ds.slider_position.values - ref.slider_position.values).max()
                ),
            }
        )
        print(rows[-1], flush=True)
    return rows


def _arcs(mask: np.ndarray) -> str:
    """1° regions as a list of arcs "a–b" (degrees, wrapping at 360)."""
    if mask.all():
        return "0-360"
    start = int(np.argmin(mask))  # begin the scan at a region outside every arc
    arcs, begin = [], None
    for k in range(361):
        i = (start + k) % 360
        if mask[i] and begin is None:
            begin = i
        elif not mask[i] and begin is not None:
            arcs.append(f"{begin}-{(i - 1) % 360 + 1}")
            begin = None
    return " ".join(arcs)


def _wear_rate_regions(ds, share: float = 0.8) -> tuple[np.ndarray, np.ndarray]:
    """Regions (1° in the bearing frame) holding ``share`` of the Archard wear rate Fₙ|v_t|."""
    fn = ds.contact_force.isel(joint=0).values
    vt = ds.sliding_velocity.isel(joint=0).values
    angle = np.degrees(np.mod(ds.contact_angle.isel(joint=0).values, 2 * np.pi))
    rate, _ = np.histogram(angle, bins=360, range=(0.0, 360.0), weights=fn * np.abs(vt))
    order = np.argsort(rate)[::-1]
    keep = order[: int(np.searchsorted(np.cumsum(rate[order]), share * rate.sum())) + 1]
    mask = np.zeros(360, dtype=bool)
    mask[keep] = True
    return mask, rate / rate.sum()


def conclusions_study(quick: bool) -> list[dict]:
    """Which settings keep the paper-scene conclusions the simulator can already give.

    The paper scene (rigid rods, unworn) over revolutions 2 … R (the first settles): the
    peak contact force of the second revolution and the median and maximum of the
    per-revolution peaks (the numerator and denominator of the paper's after/before-wear
    force ratio), and the arcs that hold 80 % of the Archard wear rate Fₙ|v_t| (where the
    wear concentrates), compared with dopri5 at rtol = atol = 1e-9 by their Jaccard overlap.
    """
    revolutions = 4 if quick else 8
    paper = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    period = paper.drive.period
    settings = [("dopri5", 1e-9, 1)]
    settings += [("dopri5", tol, 1) for tol in (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)]
    settings += [("dopri5", 1e-5, 4), ("dopri5", 1e-5, 16)]
    settings += [("generalized-alpha", tol, 1) for tol in (1e-4, 1e-5, 1e-6)]
    if not quick:
        settings += [("LSODA", 1e-5, 1), ("Radau", 1e-5, 1)]
    rows: list[dict] = []
    ref_mask = ref_force = None
    for method, tol, factor in settings:
        scene = paper
        if factor != 1:
            scene = paper.replace({"solver.max_step": factor * period / 10000})
        t0 = time.perf_counter()
        ds = mechanism.simulate(scene, revolutions=revolutions, method=method, rtol=tol, atol=tol)
        wall = time.perf_counter() - t0
        force_all = ds.contact_force.isel(joint=0).values[1:]
        peaks = force_all.reshape(revolutions, -1).max(axis=1)[1:]
        ds = ds.sel(time=slice(period, None))
        mask, share = _wear_rate_regions(ds)
        force = float(peaks[0])
        if ref_mask is None:
            ref_mask, ref_force, ref_median = mask, force, float(np.median(peaks))
        paper_arcs = np.zeros(360, dtype=bool)
        paper_arcs[75:132] = paper_arcs[252:310] = True
        rows.append(
            {
                "method": method,
                "tol": tol,
                "max_step_over_output": factor,
                "wall_s": wall,
                "revolutions": revolutions,
                "peak_force_rev2": force,
                "peak_force_rev2_rel_err": abs(force - ref_force) / ref_force,
                "median_rev_peak": float(np.median(peaks)),
                "median_rev_peak_rel_err": abs(float(np.median(peaks)) - ref_median) / ref_median,
                "max_rev_peak": float(peaks.max()),
                "min_rev_peak": float(peaks.min()),
                "wear_arcs_80pct_deg": _arcs(mask),
                "arc_jaccard_vs_ref": float((mask & ref_mask).sum() / (mask | ref_mask).sum()),
                "wear_rate_share_in_paper_arcs": float(share[paper_arcs].sum()),
            }
        )
        print(rows[-1], flush=True)
    return rows


def _write_csv(rows: list[dict], path: Path, fields: list[str]) -> None:
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: row.get(k, "") for k in fields})


def _plot(rows: list[dict], scene: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metrics = [
        ("peak_force_rel_err", "peak contact force, relative error"),
        ("slider_err_m", "slider position error (m)"),
        ("orbit_err_rel_c", "journal orbit error / clearance"),
    ]
    colours = {
        "dopri5": "C0",
        "generalized-alpha": "C1",
        "LSODA": "C2",
        "DOP853": "C3",
        "Radau": "C4",
    }
    styles = dict(zip(LAWS, ("-", "--", ":", "-."), strict=True))
    markers = dict(zip(LAWS, ("o", "s", "^", "v"), strict=True))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    sel = [r for r in rows if r["scene"] == scene and r["cap"] == "output"]
    for ax, (key, label) in zip(axes, metrics, strict=True):
        for law in LAWS:
            for method, colour in colours.items():
                pts = sorted(
                    (r["wall_s"], r[key], r["tol"])
                    for r in sel
                    if r["law"] == law and r["method"] == method and np.isfinite(r[key])
                )
                if not pts:
                    continue
                x, y, tol = zip(*pts, strict=True)
                y = np.maximum(np.asarray(y), 1e-16)
                ax.loglog(x, y, styles[law], marker=markers[law], color=colour, ms=4, lw=1)
                if law == "lankarani-nikravesh":
                    for xi, yi, ti in zip(x, y, tol, strict=True):
                        ax.annotate(f"{ti:.0e}", (xi, yi), fontsize=6, color=colour)
        capped = [r for r in rows if r["scene"] == scene and r["cap"].endswith("x")]
        if capped:
            ax.loglog(
                [r["wall_s"] for r in capped],
                [max(r[key], 1e-16) for r in capped],
                "k*",
                ms=7,
                label="dopri5 1e-5, max step 4/16/64 × output",
            )
        ax.set_xlabel("wall time of simulate (s, shared machine)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    handles = [plt.Line2D([], [], color=c, label=m) for m, c in colours.items()]
    handles += [
        plt.Line2D([], [], color="grey", ls=styles[law], marker=markers[law], label=law)
        for law in LAWS
    ]
    handles.append(plt.Line2D([], [], color="k", marker="*", ls="", label="dopri5 1e-5, step cap"))
    axes[0].legend(handles=handles, fontsize=7)
    fig.suptitle(f"work–precision, scene {scene} (reference dopri5 rtol = atol = {REF_TOL:g})")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_elements(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in rows if r["status"] == "0"]
    if not rows:
        return
    n = [r["elements"] for r in rows]
    fig, (ax_err, ax_time) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    ax_err.semilogy(n, [r["peak_force_rel_err"] for r in rows], "o-", label="peak contact force")
    ax_err.semilogy(n, [r["slider_err_m"] / 1e-3 for r in rows], "s--", label="slider (mm)")
    ax_err.set_xlabel("ANCF elements per rod")
    ax_err.set_ylabel("error vs 24 elements, rtol 1e-8")
    ax_err.legend()
    ax_time.plot(n, [r["wall_s"] for r in rows], "o-")
    ax_time.set_xlabel("ANCF elements per rod")
    ax_time.set_ylabel("wall time (s, shared machine)")
    for ax in (ax_err, ax_time):
        ax.grid(True, alpha=0.3)
    fig.suptitle("paper scene, flexible rods: element count (5 % of a revolution)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _mle_study(quick: bool) -> None:
    # a real import (benchmarks/ is on sys.path when this file runs as a script), so that
    # the study's worker function pickles into its fresh processes
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import mle_accuracy_vs_n as module

    if quick:
        # the committed mle-vs-n table is the full N range: keep it, write the quick one aside
        module.OUT = OUT / "quick"
        module.main(["--quick"])
    else:
        module.main([])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer points, shorter windows")
    parser.add_argument("--skip-mle", action="store_true", help="skip the analysis study")
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    # warm the compiled kernels so that the first timed run does not pay for compilation
    warm = mechanism.load_scene("slider-crank-clearance")
    for method in ("dopri5", "generalized-alpha", "LSODA"):
        mechanism.simulate(warm, t_end=1e-4, method=method)
    t0 = time.perf_counter()
    rows = simulator_study(args.quick)
    _write_csv(rows, OUT / "work-precision.csv", FIELDS)
    for scene in ("s3", "paper"):
        _plot(rows, scene, OUT / f"work-precision-{scene}.png")
    element_rows = element_study(args.quick)
    _write_csv(
        element_rows,
        OUT / "work-precision-elements.csv",
        [
            "elements",
            "status",
            "reason",
            "wall_s",
            "steps",
            "peak_force",
            "peak_force_rel_err",
            "slider_err_m",
        ],
    )
    _plot_elements(element_rows, OUT / "work-precision-elements.png")
    conclusion_rows = conclusions_study(args.quick)
    _write_csv(conclusion_rows, OUT / "work-precision-conclusions.csv", list(conclusion_rows[0]))
    print(f"simulator study: {time.perf_counter() - t0:.0f} s; wrote {OUT}/work-precision*")
    if not args.skip_mle:
        _mle_study(args.quick)


if __name__ == "__main__":
    main(sys.argv[1:])
