"""Cost and accuracy of the integrators on flexible (ANCF) scenes.

Writes ``docs/benchmarks/flexible-integrators.csv``: wall time, steps, right-hand sides
and the errors of the slider position and mid-span deflection against the S6 reference
(validation-targets S6), for each integrator, element count and step/tolerance; and
the paper scene with both rods flexible. Run from the repository root::

    python benchmarks/flexible_integrators.py [--quick]
    python benchmarks/flexible_integrators.py --paper-elements
    python benchmarks/flexible_integrators.py --rho-inf

The second form writes ``docs/benchmarks/paper-element-convergence.csv``: the default
paper scene re-meshed (both rods), 3 revolutions each, statistics over revolutions 2–3
(docs/ancf.md §9). The third writes ``docs/benchmarks/rho-inf.csv``: the numerical damping
ρ∞ of generalized-α against S6's slider error and wall time and against the paper
scene's friction chatter, peak force and wall time (docs/ancf.md §8).

Wall times are from a shared 2-core machine (JIT warmed up by a first short run).
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import numpy as np

import mechanism
from mechanism.core.record._metrics import friction_sign_flips

S6_X = 0.169737332842786
S6_W = 1.8932e-4
OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "flexible-integrators.csv"
ELEMENTS_OUT = OUT.with_name("paper-element-convergence.csv")
RHO_OUT = OUT.with_name("rho-inf.csv")


def s6_case(label, method, *, elements=16, t_end=0.1, rtol=1e-6, atol=1e-8, max_step=None):
    scene = mechanism.load_scene("flexible-slider-crank").replace({"bodies.rod.elements": elements})
    if max_step is not None:
        scene = scene.replace({"solver.max_step": max_step})
    mechanism.simulate(
        scene,
        t_end=min(t_end, 2e-4),
        method=method,
        rtol=rtol,
        atol=atol,
        output_step=1e-4,
        throw=False,
    )  # warm-up (JIT)
    start = time.perf_counter()
    ds = mechanism.simulate(
        scene, t_end=t_end, method=method, rtol=rtol, atol=atol, output_step=1e-4, throw=False
    )
    wall = time.perf_counter() - start
    a = ds.attrs
    row = dict(
        scene="flexible-slider-crank",
        integrator=label,
        elements=elements,
        rtol=rtol,
        atol=atol,
        step=max_step or "",
        t_end=float(ds.time[-1]),
        wall_s=round(wall, 3),
        wall_per_simulated_s=round(wall / float(ds.time[-1]), 2),
        steps=a["solver_steps"],
        rejected=a["solver_rejected_steps"],
        rhs=a["solver_function_evaluations"],
        jacobians=a["solver_jacobian_evaluations"],
        status=a["solver_status"],
        strain_extreme_ue=round(float(ds["strain_rod"]), 3),
    )
    if abs(float(ds.time[-1]) - 0.1) < 1e-9:
        row["slider_x_error_m"] = f"{float(ds.slider_position[-1]) - S6_X:.3e}"
        row["deflection_error_m"] = f"{float(ds.midspan_deflection.sel(rod='rod')[-1]) - S6_W:.3e}"
    return row


def paper_case(label, method, revolutions, *, max_step=None):
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": True})
    if max_step is not None:
        scene = scene.replace({"solver.max_step": max_step})
    mechanism.simulate(scene, revolutions=0.002, method=method, throw=False)
    start = time.perf_counter()
    ds = mechanism.simulate(scene, revolutions=revolutions, method=method, throw=False)
    wall = time.perf_counter() - start
    a = ds.attrs
    rev = float(ds.time[-1]) / float(a["drive_period"])
    return dict(
        scene="paper (flexible)",
        integrator=label,
        elements=16,
        rtol=a["rtol"],
        atol=a["atol"],
        step=max_step or a["max_step"],
        t_end=float(ds.time[-1]),
        wall_s=round(wall, 2),
        wall_per_revolution_s=round(wall / rev, 1),
        steps=a["solver_steps"],
        rejected=a["solver_rejected_steps"],
        rhs=a["solver_function_evaluations"],
        jacobians=a["solver_jacobian_evaluations"],
        status=a["solver_status"],
        strain_rod3_ue=round(float(ds["strain_rod3"]), 2),
        strain_rod4_ue=round(float(ds["strain_rod4"]), 2),
        contact_force_max_n=round(float(ds.contact_force.max()), 1),
    )


def _write_rows(path: Path, rows: list[dict]) -> None:
    """Write ``rows`` as CSV; the columns are the union of the rows' keys, in order."""
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)


def main(quick: bool) -> None:
    ga = "generalized-alpha-fixed"
    rows = []
    for elements in (4, 8, 16, 24):
        rows.append(s6_case("generalized-alpha fixed", ga, elements=elements, max_step=1e-4))
    for step in (5e-5, 2e-5):
        rows.append(s6_case("generalized-alpha fixed", ga, max_step=step))
    rows.append(s6_case("dopri5", "dopri5", t_end=0.01))
    rows.append(
        s6_case(
            "generalized-alpha adaptive", "generalized-alpha", t_end=0.002, rtol=1e-5, atol=1e-6
        )
    )
    rows.append(s6_case("Radau (scipy)", "Radau", t_end=0.002, rtol=1e-5, atol=1e-6))
    rows.append(s6_case("BDF (scipy)", "BDF", t_end=0.002, rtol=1e-5, atol=1e-6))
    if not quick:
        rows.append(s6_case("generalized-alpha fixed", ga, t_end=1.0, max_step=1e-4))
        rows.append(paper_case("generalized-alpha fixed", ga, 0.1))
        rows.append(paper_case("dopri5", "dopri5", 0.005))
    _write_rows(OUT, rows)
    for row in rows:
        print(row)


def paper_elements(elements=(4, 8, 12, 16, 20, 24), revolutions=3.0) -> list[dict]:
    """Element study of the default paper scene: per element count (both rods), the
    wall time, solver counts and, over revolutions 2..``revolutions`` (the start transient
    excluded), each rod's extreme, 99th-percentile and RMS |axial strain| over time and
    stations (µε) and the contact force's 99th percentile and peak (N)."""
    base = mechanism.load_scene("paper")
    mechanism.simulate(base, revolutions=0.002)  # warm-up (JIT)
    rows = []
    for ne in elements:
        scene = base.replace({"bodies.rod3.elements": ne, "bodies.rod4.elements": ne})
        start = time.perf_counter()
        ds = mechanism.simulate(scene, revolutions=revolutions, throw=False)
        wall = time.perf_counter() - start
        a = ds.attrs
        late = ds.sel(time=slice(float(a["drive_period"]), None))
        row = dict(
            elements=ne,
            revolutions=round(float(ds.time[-1]) / float(a["drive_period"]), 3),
            status=a["solver_status"],
            wall_s=round(wall, 1),
            steps=a["solver_steps"],
            rejected=a["solver_rejected_steps"],
            jacobians=a["solver_jacobian_evaluations"],
        )
        for rod in ("rod3", "rod4"):
            eps = 1e6 * np.abs(late.strain.sel(rod=rod).values)
            row[f"{rod}_extreme_ue"] = round(float(eps.max()), 2)
            row[f"{rod}_p99_ue"] = round(float(np.percentile(eps, 99)), 2)
            row[f"{rod}_rms_ue"] = round(float(np.sqrt(np.mean(eps**2))), 3)
        force = late.contact_force.values
        row["contact_force_p99_n"] = round(float(np.percentile(force, 99)), 0)
        row["contact_force_max_n"] = round(float(force.max()), 0)
        row["penetration_max_m"] = f"{float(late.penetration.max()):.3e}"
        rows.append(row)
        print(row, flush=True)
    _write_rows(ELEMENTS_OUT, rows)
    return rows


def rho_inf_study(values=(0.9, 0.8, 0.7, 0.6, 0.5, 0.3, 0.0)) -> list[dict]:
    """ρ∞ against accuracy and cost: S6 (16 elements, h = 1e-4 s) slider error at 0.1 s and
    wall time for 1 s; the default paper scene over one revolution: wall time, Newton
    counts, friction sign flips, peak contact force and rod 3's extreme strain."""
    s6 = mechanism.load_scene("flexible-slider-crank")
    paper = mechanism.load_scene("paper")
    mechanism.simulate(s6, t_end=2e-4)  # warm-up (JIT)
    mechanism.simulate(paper, revolutions=0.002)
    rows = []
    for rho in values:
        row: dict = {"rho_inf": rho}
        scene = s6.replace({"solver.rho_inf": rho})
        start = time.perf_counter()
        ds = mechanism.simulate(scene, t_end=1.0, throw=False)
        row["s6_wall_s"] = round(time.perf_counter() - start, 3)
        row["s6_status"] = ds.attrs["solver_status"]
        x = float(ds.slider_position.sel(time=0.1, method="nearest"))
        row["s6_slider_x_error_m"] = f"{x - S6_X:.3e}"
        row["s6_newton_iterations"] = ds.attrs["solver_newton_iterations"]
        scene = paper.replace({"solver.rho_inf": rho})
        start = time.perf_counter()
        ds = mechanism.simulate(scene, revolutions=1.0, throw=False)
        row["paper_wall_s"] = round(time.perf_counter() - start, 3)
        row["paper_status"] = ds.attrs["solver_status"]
        row["paper_newton_iterations"] = ds.attrs["solver_newton_iterations"]
        row["paper_jacobians"] = ds.attrs["solver_jacobian_evaluations"]
        flips, longest = friction_sign_flips(ds)
        row["paper_friction_sign_flips"] = flips
        row["paper_longest_flip_run"] = longest
        row["paper_contact_force_max_n"] = round(float(ds.contact_force.max()), 1)
        row["paper_strain_rod3_ue"] = round(float(ds["strain_rod3"]), 3)
        rows.append(row)
        print(row, flush=True)
    _write_rows(RHO_OUT, rows)
    return rows


if __name__ == "__main__":
    if "--rho-inf" in sys.argv:
        rho_inf_study()
    elif "--paper-elements" in sys.argv:
        paper_elements()
    else:
        main("--quick" in sys.argv)
