"""Accuracy of the measures toolbox against known values and nolds, for docs/estimators.md.

* D2 (defaults, lag 1 for maps) on Hénon x, the logistic map, Lorenz x (dt = 0.01) and a
  two-frequency torus (dt = 0.37) for N = 5000, 20 000 and 100 000, against the published
  values (Grassberger & Procaccia 1983) and 2 for the torus.
* Lyapunov spectrum: Hénon x (m = 2, lag 1) and Lorenz x (m = 4, lag 8, step 10,
  dt = 0.01) against the known spectra, and ``nolds.lyap_e`` on the same series (Hénon:
  ``emb_dim = matrix_dim = 2``; Lorenz: ``matrix_dim = 4``, ``emb_dim = 25`` so that its
  matrix coordinates are 8 samples apart, ``min_tsep = 100``, N = 10 000 because it is
  O(N²)).

Writes ``docs/benchmarks/measures-accuracy.csv``. Run from the repository root:

    python benchmarks/measures_accuracy.py
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "measures-accuracy.csv"


def main() -> None:
    import nolds
    from measures_vs_peers import write_csv

    from chaoskit import correlation_dimension, lyapunov_spectrum, systems

    rows: list[dict] = []
    series = {
        "henon": (lambda n: systems.henon(n)[:, 0], 1, 1.21),
        "logistic": (lambda n: systems.logistic(n), 1, 1.0),
        "lorenz": (lambda n: systems.lorenz(n, dt=0.01)[:, 0], None, 2.05),
        "torus": (lambda n: systems.torus(n, dt=0.37), None, 2.0),
    }
    for name, (make, lag, expected) in series.items():
        for n in (5000, 20_000, 100_000):
            t0 = time.perf_counter()
            res = correlation_dimension(make(n), lag=lag)
            rows.append(
                {
                    "measure": "D2",
                    "case": f"{name} N={n}",
                    "expected": expected,
                    "ours": res.d2,
                    "ours_error_pct": 100 * (res.d2 / expected - 1),
                    "detail": f"[{res.interval[0]:.3f}, {res.interval[1]:.3f}] "
                    f"saturated={res.saturated} found={res.scaling_found}",
                    "seconds": time.perf_counter() - t0,
                }
            )
            print(rows[-1], flush=True)
    h = systems.henon(10_000)[:, 0]
    henon_kw = dict(embedding_dim=2, lag=1)
    henon_nolds = dict(emb_dim=2, matrix_dim=2, min_tsep=2)
    cases = [
        ("henon λ1", h, henon_kw, 0.419, 0, henon_nolds),
        ("henon λ1+λ2", h, henon_kw, np.log(0.3), "sum", henon_nolds),
    ]
    x50 = systems.lorenz(50_000, dt=0.01)[:, 0]
    x10 = x50[:10_000]
    lorenz_kw = dict(embedding_dim=4, lag=8, dt=0.01, step=10)
    nolds_kw = dict(emb_dim=25, matrix_dim=4, min_tsep=100, tau=0.01)
    for label, x in (("N=50000", x50), ("N=10000", x10)):
        cases.append(
            (f"lorenz λ1 {label}", x, lorenz_kw, 0.9056, 0, nolds_kw if x is x10 else None)
        )
        cases.append((f"lorenz λ2 {label}", x, lorenz_kw, 0.0, 1, nolds_kw if x is x10 else None))
    cache: dict = {}
    for label, x, kw, expected, which, nkw in cases:
        key = (id(x), tuple(sorted(kw.items())))
        if key not in cache:
            t0 = time.perf_counter()
            cache[key] = (lyapunov_spectrum(x, **kw), time.perf_counter() - t0)
        res, seconds = cache[key]
        pick = (lambda v: float(np.sum(v))) if which == "sum" else (lambda v, w=which: float(v[w]))
        ours = pick(res.exponents)
        row = {
            "measure": "Lyapunov spectrum",
            "case": label,
            "expected": expected,
            "ours": ours,
            "ours_error_pct": 100 * (ours / expected - 1) if expected else float("nan"),
            "detail": f"spectrum {np.round(res.exponents, 3).tolist()} spurious "
            f"{res.spurious.astype(int).tolist()}",
            "seconds": seconds,
        }
        if nkw is not None:
            nkey = (id(x), tuple(sorted(nkw.items())))
            if nkey not in cache:
                t0 = time.perf_counter()
                cache[nkey] = (np.sort(nolds.lyap_e(x, **nkw))[::-1], time.perf_counter() - t0)
            theirs, nsec = cache[nkey]
            row |= {"nolds": pick(theirs), "nolds_seconds": nsec}
        rows.append(row)
        print(row, flush=True)
    fields = ["measure", "case", "expected", "ours", "ours_error_pct", "nolds", "detail"]
    write_csv(OUT, [*fields, "seconds", "nolds_seconds"], rows)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
