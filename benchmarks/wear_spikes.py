"""Contact-force spikes after wear: diagnosis and the peak-force ratio protocol.

Not a pytest-benchmark file: a script that reproduces the numbers of ``docs/wear.md`` §5
and ``docs/contact-and-wear.md`` §2 ("sustained contact").

``spike``  grows the paper scene's wear (``predict_wear``, blocks of 1000 cycles), simulates
the worn scene for 8 revolutions with each approach-speed rule and prints the samples around
the largest contact force: penetration δ, its rate δ̇, the local stiffness K_n, the elastic
force K_n δⁿ and the approach speed δ̇⁻ the force implies,
δ̇⁻ = χ̂ δ̇ K_n δⁿ / (F − K_n δⁿ) (the latch is not an output, but the force law is known).

``ratios`` runs the protocol of ``docs/wear.md`` §5 with one rule: ``predict_wear(paper,
updates=N, cycles_per_update=1000, settle_revolutions=2)``, then every state's scene
simulated for 8 revolutions and compared with the unworn one over revolutions 2–8.

Usage (one CPU-heavy process at a time)::

    python benchmarks/wear_spikes.py spike --cycles 2000
    python benchmarks/wear_spikes.py ratios --updates 8 --rule latched -o latched.json
    python benchmarks/wear_spikes.py ratios --updates 8 --rule bounded -o bounded.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from typing import Any

import numpy as np
import xarray as xr

import mechanism
from mechanism.core.contact import _kernels as ck
from mechanism.core.contact import contact_parameters
from mechanism.core.scene import ClearanceRevolute, Scene
from mechanism.core.wear import WornProfile

REVOLUTIONS = 8.0
#: The measurements used rigid rods 3 and 4; the built-in paper scene is flexible by default.
RIGID_RODS = {"effects.flexibility": False}
JOINT = "C"


def with_rule(scene: Scene, rule: str) -> Scene:
    """``scene`` with every clearance joint's ``contact.approach_speed`` set to ``rule``."""
    joints = dict(scene.joints)
    for name, joint in joints.items():
        if isinstance(joint, ClearanceRevolute):
            contact = dataclasses.replace(joint.contact, approach_speed=rule)
            joints[name] = dataclasses.replace(joint, contact=contact)
    return dataclasses.replace(scene, joints=joints)


def with_depth(scene: Scene, depth: np.ndarray) -> Scene:
    """``scene`` whose joint ``C`` carries ``depth`` = [bearing, journal] (m per region)."""
    joint = scene.joints[JOINT]
    assert isinstance(joint, ClearanceRevolute)
    profile = WornProfile.from_joint(joint).with_depth(
        bearing_depth=depth[0], journal_depth=depth[1]
    )
    return dataclasses.replace(scene, joints={**scene.joints, JOINT: profile.apply_to(joint)})


def force_breakdown(ds: xr.Dataset, scene: Scene) -> dict[str, np.ndarray]:
    """Per-sample elastic force K_n δⁿ and the approach speed δ̇⁻ implied by the force."""
    joint = scene.joints[JOINT]
    assert isinstance(joint, ClearanceRevolute)
    p = contact_parameters(joint)
    chi = ck.hysteresis_factor(p.law_code, p.restitution)
    force = ds.contact_force.sel(joint=JOINT).values
    delta = ds.penetration.sel(joint=JOINT).values
    rate = ds.penetration_velocity.sel(joint=JOINT).values
    phi_b = ds.contact_angle.sel(joint=JOINT).values
    phi_j = ds.contact_angle_journal.sel(joint=JOINT).values
    profile = WornProfile.from_joint(joint)
    if p.form is None:
        kn = np.full(force.shape, p.stiffness)
    else:
        kn = np.asarray(
            profile.local_stiffness(
                phi_b,
                phi_j,
                effective_modulus=p.effective_modulus,
                form=p.form,  # type: ignore[arg-type]
                radius_ratio_limit=joint.wear.radius_ratio_limit,
            )
        )
    elastic = kn * np.maximum(delta, 0.0) ** p.exponent
    with np.errstate(divide="ignore", invalid="ignore"):
        implied = np.where(
            (force > 0.0) & (np.abs(force - elastic) > 1e-9 * elastic),
            chi * rate * elastic / (force - elastic),
            np.nan,
        )
        ratio = np.where(elastic > 0.0, force / elastic, np.nan)
    return {
        "time": ds.time.values,
        "force": force,
        "delta": delta,
        "rate": rate,
        "stiffness": kn,
        "elastic": elastic,
        "implied_speed": implied,
        "ratio": ratio,
        "angle": np.degrees(phi_b),
    }


def spike_summary(ds: xr.Dataset, scene: Scene, discard: float = 1.0) -> dict[str, Any]:
    """The largest contact force after ``discard`` revolutions and how it is made up."""
    b = force_breakdown(ds, scene)
    late = b["time"] >= discard * scene.drive.period
    i = int(np.argmax(np.where(late, b["force"], 0.0)))
    in_contact = late & (b["delta"] > 0.0)
    return {
        "peak_force": float(b["force"][i]),
        "revolution": float(b["time"][i] / scene.drive.period),
        "penetration": float(b["delta"][i]),
        "rate": float(b["rate"][i]),
        "elastic": float(b["elastic"][i]),
        "force_over_elastic": float(b["ratio"][i]),
        "implied_speed": float(b["implied_speed"][i]),
        "max_force_over_elastic": float(np.nanmax(b["ratio"][in_contact])),
        "max_penetration": float(b["delta"][late].max()),
    }


def spike(cycles: int) -> None:
    scene = mechanism.load_scene("paper").replace(RIGID_RODS)
    updates = max(1, round(cycles / 1000))
    pred = mechanism.predict_wear(
        with_rule(scene, "latched"),
        updates=updates,
        cycles_per_update=1000.0,
        settle_revolutions=2.0,
    )
    worn = pred.worn_scene
    print(f"worn state: {pred.cycles[-1]:.0f} cycles (grown with the latched rule)")
    for rule in ("latched", "bounded"):
        s = with_rule(worn, rule)
        t0 = time.perf_counter()
        ds = mechanism.simulate(s, revolutions=REVOLUTIONS)
        wall = time.perf_counter() - t0
        summary = spike_summary(ds, s)
        print(f"\n{rule} ({wall:.1f} s): " + json.dumps(summary, indent=None))
        b = force_breakdown(ds, s)
        late = b["time"] >= s.drive.period
        i = int(np.argmax(np.where(late, b["force"], 0.0)))
        j = i
        while j > 0 and b["delta"][j] > 0.0:
            j -= 1
        print("  sample  t (s)  δ (µm)  δ̇ (mm/s)  angle (°)  K_n  F (N)  K_nδⁿ (N)  δ̇⁻ (mm/s)")
        for q in range(max(j - 2, 0), min(i + 3, b["time"].size)):
            print(
                f"  {q:6d} {b['time'][q]:.6f} {b['delta'][q] * 1e6:8.3f} {b['rate'][q] * 1e3:9.2f}"
                f" {b['angle'][q]:8.2f} {b['stiffness'][q]:.3e} {b['force'][q]:9.1f}"
                f" {b['elastic'][q]:9.1f} {b['implied_speed'][q] * 1e3:9.3f}"
            )


def ratios(updates: int, rule: str, output: str | None) -> None:
    scene = with_rule(mechanism.load_scene("paper").replace(RIGID_RODS), rule)
    t0 = time.perf_counter()
    pred = mechanism.predict_wear(
        scene, updates=updates, cycles_per_update=1000.0, settle_revolutions=2.0
    )
    print(f"predict_wear: {time.perf_counter() - t0:.1f} s")
    depth = pred.to_dataset()["wear_depth"].sel(joint=JOINT).values  # (update, surface, angle)
    before = mechanism.simulate(scene, revolutions=REVOLUTIONS)
    rows = []
    for u in range(updates + 1):
        state = with_depth(scene, depth[u]) if u else scene
        t0 = time.perf_counter()
        after = mechanism.simulate(state, revolutions=REVOLUTIONS) if u else before
        wall = time.perf_counter() - t0
        table = mechanism.compare_wear(before, after, discard_revolutions=1.0).table
        summary = spike_summary(after, state)
        row = {
            "cycles": float(pred.cycles[u]),
            "bearing_depth_um": float(depth[u, 0].max() * 1e6),
            "journal_depth_um": float(depth[u, 1].max() * 1e6),
            "peak_force_kN": float(table.loc["peak_contact_force", "after"]) / 1e3,
            "ratio": float(table.loc["peak_contact_force", "ratio"]),
            "max_penetration_mm": float(table.loc["max_penetration", "after"]) * 1e3,
            "penetration_ratio": float(table.loc["max_penetration", "ratio"]),
            "peak_force_over_elastic": summary["force_over_elastic"],
            "max_force_over_elastic": summary["max_force_over_elastic"],
            "wall_s": wall,
        }
        rows.append(row)
        print(json.dumps(row))
    if output:
        with open(output, "w") as fh:
            json.dump({"rule": rule, "rows": rows}, fh, indent=1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p_spike = sub.add_parser("spike", help="diagnose the largest force of a worn state")
    p_spike.add_argument("--cycles", type=int, default=2000)
    p_ratio = sub.add_parser("ratios", help="peak-force ratio over wear (docs/wear.md §5)")
    p_ratio.add_argument("--updates", type=int, default=8)
    p_ratio.add_argument("--rule", choices=("latched", "bounded"), default="bounded")
    p_ratio.add_argument("-o", "--output", default=None)
    args = parser.parse_args()
    if args.command == "spike":
        spike(args.cycles)
    else:
        ratios(args.updates, args.rule, args.output)


if __name__ == "__main__":
    main()
