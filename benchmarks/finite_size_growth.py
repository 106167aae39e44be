"""Separation rate at each scale of the separation, rigid ``paper`` scene at 150 rpm, before
and after wear (first-passage times; docs/mechanism-lyapunov.md §4).

``mechanism.lyapunov_exponent`` measures the growth of an infinitesimal deviation (linear up
to about 2e-8 m in the worn press); the data-driven estimators follow neighbours of a delay
embedding 1e-7 m apart and more. Here a reference run of ``--transient`` drive periods
reaches the attractor; from ``--pairs`` of its states, spread over the following
revolutions, two copies start ``--offset`` metres apart (a random direction tangent to the
constraints, in the mass-weighted norm of ``lyapunov_exponent``) and are integrated
independently by the scene's Dormand–Prince at rtol = atol = ``--rtol`` for ``--horizon``
drive periods. The separation of their journal centres, |Δe(t)| (what the data-driven
estimators see), is read on a T/``--samples`` grid; for the scales δ_j = ``--smallest``·2^j
the first time each pair's separation reaches δ_j gives

    λ(δ_j) = ln 2 / ⟨t(δ_{j+1}) − t(δ_j)⟩        (mean over the pairs that reach both)

(the finite-size rate of Aurell, Boffetta, Crisanti, Paladin & Vulpiani 1996). First
passages count growth only: where the separation also shrinks between impacts, the
small-scale limit lies above the largest Lyapunov exponent. It drives the compiled
integrator directly (internal API: ``simulate`` starts from the scene's initial state
only). The worn state is ``docs/benchmarks/worn-150rpm.toml`` (the profile of ``mechanism
paper --quick``). Writes ``docs/benchmarks/finite-size-growth.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/finite_size_growth.py
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

import mechanism
from chaoskit.contract import atomic_write
from mechanism.core import default_step, step_limits
from mechanism.core.integrate import Dopri5, StepSettings, initial_deviation
from mechanism.core.model import assemble, initial_state

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "benchmarks" / "finite-size-growth.csv"
WORN = ROOT / "docs" / "benchmarks" / "worn-150rpm.toml"
FIELDS = ["state", "scale_m", "rate_per_s", "pairs", "mean_time_s", "cpu_s"]


def separations(
    scene: mechanism.Scene, *, pairs: int, transient: float, horizon: float, offset: float,
    samples: int, tol: float, seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Times (s, from each pair's start) and journal separations (m, one row per pair)."""
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    tau = period / (2.0 * math.pi)
    model = assemble(scene)
    method = Dopri5()
    max_step, floor = step_limits(model, method, default_step(scene, transient * period))
    kw = {"steps": StepSettings(rtol=tol, atol=tol, max_step=max_step, approach_floor=floor)}
    q0, v0 = initial_state(model)
    # the starts: after the transient, every 1 + 1/pairs revolutions (different phases)
    starts = transient * period + np.arange(pairs) * period * (1.0 + 1.0 / pairs)
    ref = method.integrate(model, np.concatenate([q0, v0]), np.r_[0.0, starts], **kw)
    grid = np.arange(round(horizon * samples) + 1) * period / samples
    out = np.full((pairs, grid.size), np.nan)
    for k, t0 in enumerate(starts):
        ya = np.concatenate([ref.recording.q[k + 1], ref.recording.v[k + 1]])
        d0 = initial_deviation(model, ya, t0=t0, size=offset, time_scale=tau, seed=seed + k)
        a, b = (method.integrate(model, y0, t0 + grid, **kw).recording for y0 in (ya, ya + d0))
        n = min(a.t.size, b.t.size)
        de = b.cj[:n, 0, :2] - a.cj[:n, 0, :2]  # e_x, e_y of the clearance joint
        out[k, :n] = np.hypot(de[:, 0], de[:, 1])
    return grid, out


def passage_times(t: np.ndarray, d: np.ndarray, scales: np.ndarray) -> np.ndarray:
    """First time the separation reaches each scale (NaN where it never does), linear in
    ln d between the grid points."""
    out = np.full(scales.size, np.nan)
    running = np.maximum.accumulate(d)
    for j, s in enumerate(scales):
        i = int(np.searchsorted(running, s))
        if i >= d.size:
            continue
        if i == 0 or d[i - 1] <= 0.0:
            out[j] = t[i]
            continue
        lo, hi = math.log(d[i - 1]), math.log(d[i])
        w = (math.log(s) - lo) / (hi - lo) if hi > lo else 1.0
        out[j] = t[i - 1] + min(max(w, 0.0), 1.0) * (t[i] - t[i - 1])
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--pairs", type=int, default=16)
    parser.add_argument("--transient", type=float, default=5.0, help="drive periods")
    parser.add_argument("--horizon", type=float, default=1.5, help="drive periods per pair")
    parser.add_argument("--offset", type=float, default=1e-10, help="initial separation (m)")
    parser.add_argument("--smallest", type=float, default=1e-9, help="smallest scale (m)")
    parser.add_argument("--samples", type=int, default=4000, help="grid points per period")
    parser.add_argument("--rtol", type=float, default=1e-9)
    args = parser.parse_args()
    rigid = {"effects.flexibility": False}
    states = {
        "before wear": mechanism.load_scene("paper").replace(rigid),
        "after wear": mechanism.load_scene(WORN).replace(rigid),
    }
    clearance = 2e-4
    scales = args.smallest * 2.0 ** np.arange(int(math.log2(clearance / args.smallest)) + 1)
    rows = []
    for state, scene in states.items():
        cpu = time.process_time()
        t, d = separations(
            scene, pairs=args.pairs, transient=args.transient, horizon=args.horizon,
            offset=args.offset, samples=args.samples, tol=args.rtol,
        )  # fmt: skip
        cpu = time.process_time() - cpu
        p = np.array([passage_times(t, row[np.isfinite(row)], scales) for row in d])
        for j in range(scales.size - 1):
            dt = p[:, j + 1] - p[:, j]
            dt = dt[np.isfinite(dt)]
            if dt.size == 0:
                continue
            mean = float(dt.mean())
            rows.append({
                "state": state, "scale_m": f"{scales[j]:.3e}",
                "rate_per_s": f"{math.log(2.0) / mean:.4g}" if mean > 0.0 else "inf",
                "pairs": dt.size, "mean_time_s": f"{mean:.4e}", "cpu_s": f"{cpu:.1f}",
            })  # fmt: skip
            print(rows[-1], flush=True)

    def write(path: Path) -> None:
        with path.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=FIELDS)
            writer.writeheader()
            writer.writerows(rows)

    atomic_write(OUT, write)


if __name__ == "__main__":
    main()
