"""Time and memory of nolds' sample entropy, DFA and R/S Hurst against the series length.

These numbers set ``chaoskit.complexity.MAX_SAMPLES`` (the limits checked before nolds is
called). Each case runs on white noise; the peak Python allocation is measured with
tracemalloc and the CPU time with ``time.process_time``. Writes
``docs/benchmarks/nolds-limits.csv``. Run from the repository root:

    python benchmarks/nolds_limits.py [--quick]
"""

from __future__ import annotations

import argparse
import csv
import time
import tracemalloc
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "nolds-limits.csv"


def main() -> None:
    import nolds

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the smallest length of each")
    args = parser.parse_args()
    cases = [
        ("sample_entropy", lambda x: nolds.sampen(x, emb_dim=2), [2000, 4000, 8000, 16000]),
        ("dfa", lambda x: nolds.dfa(x, fit_exp="poly"), [2500, 10_000, 40_000]),
        ("hurst_rs", lambda x: nolds.hurst_rs(x, fit="poly"), [10_000, 100_000, 1_000_000]),
    ]
    rng = np.random.default_rng(0)
    rows = []
    for name, func, lengths in cases:
        for n in lengths[:1] if args.quick else lengths:
            x = rng.standard_normal(n)
            tracemalloc.start()
            t0 = time.process_time()
            value = func(x)
            cpu = time.process_time() - t0
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            rows.append(
                [name, n, f"{value:.4f}", f"{cpu:.3f}", f"{peak / 1e6:.2f}", f"{peak / n:.0f}"]
            )
            print(*rows[-1], flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["measure", "n_samples", "value", "cpu_s", "peak_mb", "bytes_per_sample"])
        writer.writerows(rows)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
