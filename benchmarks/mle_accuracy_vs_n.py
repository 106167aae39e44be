"""Accuracy and cost of the largest-Lyapunov-exponent estimators against series length.

Writes ``docs/benchmarks/mle-vs-n.csv`` and ``docs/benchmarks/mle-vs-n.png``: relative error
of the exponent and wall time for N = 10^3 … 10^6 on Lorenz x (dt = 0.01, λ1 = 0.9056) and
Hénon x (λ1 = 0.4192), for ``lyapunov_rosenstein`` and ``lyapunov_wolf`` with defaults
(only ``dt`` given) and for ``nolds.lyap_r`` where its N×N distance matrix fits in memory
(N ≤ 10^4), given the same embedding, Theiler window and fit range as our Rosenstein run.
Also the time of FNN (m = 1…10) and of the MI curve (lags 0…100) against N. Wall and CPU
time are both recorded; the figure shows CPU time, which other jobs on a shared machine
disturb less.

Every case runs in a fresh process (so the peak resident memory is its own) after a small
warm-up call that loads the compiled kernels. Run from the repository root:

    python benchmarks/mle_accuracy_vs_n.py [--quick]
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing as mp
import resource
import sys
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
TRUE = {"lorenz": 0.9056, "henon": 0.4192}
DT = {"lorenz": 0.01, "henon": 1.0}
NS = [1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000]
LIMITS = {  # largest N per (method, system): nolds builds an N×N matrix
    ("nolds", "lorenz"): 10_000,
    ("nolds", "henon"): 10_000,
}


def _series(system: str, n: int) -> np.ndarray:
    from chaoskit import systems

    return systems.lorenz(n)[:, 0] if system == "lorenz" else systems.henon(n)[:, 0]


def _run(task: tuple[str, str, int], queue) -> None:
    method, system, n = task
    import chaoskit as ck

    dt = DT[system]
    x = _series(system, n)
    row: dict = {"system": system, "method": method, "n": n}
    if method in ("rosenstein", "wolf", "nolds"):
        func = ck.lyapunov_wolf if method == "wolf" else ck.lyapunov_rosenstein
        func(_series(system, 2000), dt=dt)  # warm-up: load compiled kernels
        ref = ck.lyapunov_rosenstein(x, dt=dt) if method == "nolds" else None
        t0, c0 = time.perf_counter(), time.process_time()
        if method == "nolds":
            import nolds

            a, b = ref.fit_range
            mle = float(
                nolds.lyap_r(
                    x,
                    emb_dim=ref.embedding_dim,
                    lag=ref.lag,
                    min_tsep=ref.theiler_window,
                    tau=dt,
                    trajectory_len=b + 1,
                    fit="poly",
                    fit_offset=a,
                )
            )
            ci, res = (np.nan, np.nan), ref
        else:
            res = func(x, dt=dt)
            mle, ci = res.mle, res.ci
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        row.update(
            mle=mle,
            rel_error=mle / TRUE[system] - 1.0,
            ci_low=ci[0],
            ci_high=ci[1],
            lag=res.lag,
            embedding_dim=res.embedding_dim,
            theiler_window=res.theiler_window,
            fit_start=res.fit_range[0],
            fit_stop=res.fit_range[1],
            fit_found=res.fit_found,
        )
    elif method == "fnn_m1-10":
        ck.false_nearest_neighbors(x[:2000], lag=17, max_dim=3)
        t0, c0 = time.perf_counter(), time.process_time()
        res = ck.false_nearest_neighbors(x, lag=17, max_dim=10)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        row.update(embedding_dim=res.embedding_dim)
    else:  # mi_lag0-100
        ck.mutual_information(x[:2000], max_lag=10)
        t0, c0 = time.perf_counter(), time.process_time()
        ck.mutual_information(x, max_lag=100)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    row["wall_s"] = wall
    row["cpu_s"] = cpu
    row["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    queue.put(row)


def _in_fresh_process(task) -> dict:
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_run, args=(task, queue))
    proc.start()
    row = queue.get()
    proc.join()
    return row


def _plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_err, ax_time) = plt.subplots(1, 2, figsize=(11, 4.2))
    styles = {"rosenstein": "o-", "wolf": "s-", "nolds": "^--"}
    for system, color in (("lorenz", "C0"), ("henon", "C1")):
        for method, style in styles.items():
            sel = [r for r in rows if r["system"] == system and r["method"] == method]
            if not sel:
                continue
            n = [r["n"] for r in sel]
            ax_err.plot(
                n,
                [100 * abs(r["rel_error"]) for r in sel],
                style,
                color=color,
                label=f"{method}, {system}",
                alpha=0.85,
            )
            ax_time.plot(
                n,
                [r["cpu_s"] for r in sel],
                style,
                color=color,
                label=f"{method}, {system}",
                alpha=0.85,
            )
    for method, style in (("fnn_m1-10", "k:"), ("mi_lag0-100", "k-.")):
        sel = [r for r in rows if r["method"] == method]
        ax_time.plot([r["n"] for r in sel], [r["cpu_s"] for r in sel], style, label=method)
    ax_err.axhline(5, color="0.5", lw=0.8)
    ax_err.set(
        xscale="log",
        yscale="log",
        xlabel="N (samples)",
        ylabel="|relative error| of λ1 (%)",
        title="accuracy (defaults, only dt given)",
    )
    ax_time.set(
        xscale="log",
        yscale="log",
        xlabel="N (samples)",
        ylabel="CPU time (s)",
        title="cost (CPU time, one core)",
    )
    ax_err.legend(fontsize=7)
    ax_time.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="N up to 10^4 only")
    args = parser.parse_args(argv)
    ns = [n for n in NS if n <= 10_000] if args.quick else NS
    tasks = []
    for n in ns:
        for system in ("lorenz", "henon"):
            for method in ("rosenstein", "wolf", "nolds"):
                if n <= LIMITS.get((method, system), 10**9):
                    tasks.append((method, system, n))
        tasks.append(("fnn_m1-10", "lorenz", n))
        tasks.append(("mi_lag0-100", "lorenz", n))
    rows = []
    for task in tasks:
        row = _in_fresh_process(task)
        rows.append(row)
        err = row.get("rel_error", float("nan"))
        print(
            f"{task[0]:12s} {task[1]:7s} N={task[2]:>8d}  err={100 * err:+7.2f}%  "
            f"t={row['wall_s']:8.3f}s cpu={row['cpu_s']:8.3f}s  rss={row['peak_rss_mb']:7.0f} MB",
            flush=True,
        )
    OUT.mkdir(parents=True, exist_ok=True)
    fields = [
        "system",
        "method",
        "n",
        "mle",
        "rel_error",
        "ci_low",
        "ci_high",
        "wall_s",
        "cpu_s",
        "peak_rss_mb",
        "lag",
        "embedding_dim",
        "theiler_window",
        "fit_start",
        "fit_stop",
        "fit_found",
    ]
    with open(OUT / "mle-vs-n.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: row.get(k, "") for k in fields})
    _plot(rows, OUT / "mle-vs-n.png")
    print(f"wrote {OUT / 'mle-vs-n.csv'} and {OUT / 'mle-vs-n.png'}")


if __name__ == "__main__":
    main(sys.argv[1:])
