"""Time of the measures toolbox beside its peers, as ratios measured in one run.

* D2 on Lorenz x (dt = 0.01), N = 50 000, embedding dimensions 1–5, lag 10, Theiler
  window 50, 100 radii from 1/1000 of the range to the range, maximum norm, at most
  ``P`` pairs per radius, against TISEAN 3.0.1 ``d2`` with the same settings
  (``-M1,5 -d10 -t50 -#100 -N P``) for P = 1000 (TISEAN's default) and 20 000 (ours). TISEAN
  is not shipped with chaoskit: build it from its source and give the path of ``d2`` in
  the ``TISEAN_D2`` environment variable (its row is skipped otherwise). Its time is
  the wall time of the process, which includes reading the 50 000-line input (≈ 10 ms).
  The correlation sums of both are compared where both hold ≥ 1000 pairs.
* D2 against ``nolds.corr_dim`` on N = 5000 (every pair, Euclidean norm, nolds' radii).
* RQA on Lorenz x, N = 20 000, m = 3, lag 10, maximum norm, ε = 2 (RR ≈ 3 %), against
  pyunicorn's ``RecurrencePlot`` (dense matrix) computing RR, DET, L, L_max, ENTR, LAM,
  TT, V_max; the numbers of both are compared (pyunicorn's main diagonal removed for the
  vertical-line measures, see tests/chaoskit/test_recurrence.py).

Best of ``--repeat`` wall times after a warm-up call (numba compiled). Writes
``docs/benchmarks/measures-vs-peers.csv``. Run from the repository root:

    TISEAN_D2=/path/to/d2 python benchmarks/measures_vs_peers.py
"""

from __future__ import annotations

import argparse
import csv
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "measures-vs-peers.csv"


def write_csv(path: Path, fields: list[str], rows: list[dict]) -> None:
    """Rows as CSV, floats to 4 significant digits (also used by measures_accuracy.py)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields)
        writer.writeheader()
        for row in rows:
            writer.writerow(
                {k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()}
            )


def _best(func, repeat: int) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _read_c2(path: Path, dims: int) -> list[np.ndarray]:
    blocks: list[list[list[float]]] = []
    for line in path.read_text().splitlines():
        if line.startswith("#dim="):
            blocks.append([])
        elif line.strip() and not line.startswith("#") and blocks:
            blocks[-1].append([float(v) for v in line.split()])
    return [np.array(b) for b in blocks[:dims]]


def d2_vs_tisean(rows: list, repeat: int) -> None:
    from chaoskit import correlation_dimension, systems

    x = systems.lorenz(50_000, dt=0.01)[:, 0]
    d2_bin = os.environ.get("TISEAN_D2")
    span = float(np.ptp(x))
    radii = np.geomspace(span / 1000.0, span, 100)
    correlation_dimension(x[:2000], embedding_dims=[1, 2], lag=10)  # warm-up
    for pairs in (1000, 20_000):
        kw = dict(embedding_dims=[1, 2, 3, 4, 5], lag=10, theiler_window=50, radii=radii)
        ours_t, ours = _best(
            lambda kw=kw, pairs=pairs: correlation_dimension(x, pairs_per_radius=pairs, **kw),
            repeat,
        )
        row = {
            "case": f"D2 Lorenz N=50000 m=1..5 pairs={pairs}",
            "ours_s": ours_t,
            "ours_value": ours.d2,
        }
        if d2_bin and Path(d2_bin).exists():
            with tempfile.TemporaryDirectory() as tmp:
                data = Path(tmp) / "lorenz.dat"
                np.savetxt(data, x)
                cmd = [d2_bin, str(data), "-M1,5", "-d10", "-t50", "-#100", f"-N{pairs}"]
                cmd += [f"-r{span / 1000.0}", f"-R{span}", "-o", str(Path(tmp) / "out"), "-V0"]
                peer_t, _ = _best(lambda cmd=cmd: subprocess.run(cmd, check=True), repeat)
                c2 = _read_c2(Path(tmp) / "out.c2", 5)
            # TISEAN lists radii from the largest down; compare where both hold enough pairs
            rel = []
            for m, block in enumerate(c2):
                eps, csum = block[:, 0], block[:, 1]
                ours_c = np.interp(np.log(eps), np.log(ours.radius), ours.correlation_sum[m])
                ours_p = np.interp(np.log(eps), np.log(ours.radius), ours.pairs[m])
                ok = (ours_p >= 1000) & (csum > 0) & (eps <= span * 0.5)
                rel.extend(np.abs(ours_c[ok] / csum[ok] - 1.0))
            row |= {
                "peer": "TISEAN d2",
                "peer_s": peer_t,
                "ratio": ours_t / peer_t,
                "agreement": f"median |C/C_TISEAN - 1| = {np.median(rel):.3f}",
            }
        else:
            row |= {"peer": "TISEAN d2 (not built: set TISEAN_D2)"}
        rows.append(row)
        print(row, flush=True)


def d2_vs_nolds(rows: list, repeat: int) -> None:
    import nolds

    from chaoskit import correlation_dimension, systems

    x = systems.lorenz(5000, dt=0.02)[:, 0]
    sd = np.std(x, ddof=1)
    rvals = nolds.logarithmic_r(0.1 * sd, 0.5 * sd, 1.03)
    kw = dict(embedding_dims=[5], lag=5, theiler_window=0, radii=rvals, norm="euclidean")
    ours_t, ours = _best(lambda: correlation_dimension(x, pairs_per_radius=None, **kw), repeat)
    peer_t, peer = _best(
        lambda: nolds.corr_dim(x, 5, lag=5, rvals=rvals, fit="poly", debug_data=True), 1
    )
    pts = x.size - 4 * 5
    theirs = np.exp(peer[1][1])
    same = (2 * ours.pairs[0] + pts) / (pts * (pts - 1))
    rows.append(
        {
            "case": "correlation sums Lorenz N=5000 m=5 (every pair)",
            "ours_s": ours_t,
            "peer": "nolds.corr_dim",
            "peer_s": peer_t,
            "ratio": ours_t / peer_t,
            "agreement": f"max rel. difference of C = {np.max(np.abs(same / theirs - 1)):.1e}",
        }
    )
    print(rows[-1], flush=True)


def rqa_vs_pyunicorn(rows: list, repeat: int) -> None:
    from chaoskit import recurrence_analysis, systems

    x = systems.lorenz(20_000, dt=0.01)[:, 0]
    kw = dict(embedding_dim=3, lag=10, threshold=2.0, norm="chebyshev")
    recurrence_analysis(x[:1000], **kw)
    ours_t, ours = _best(lambda: recurrence_analysis(x, **kw), repeat)
    row = {"case": "RQA Lorenz N=20000 m=3 eps=2", "ours_s": ours_t, "ours_value": ours.determinism}
    try:
        from pyunicorn.timeseries import RecurrencePlot
    except ImportError:
        rows.append(row | {"peer": "pyunicorn (not installed)"})
        return

    def peer() -> dict:
        rp = RecurrencePlot(x, metric="supremum", threshold=2.0, dim=3, tau=10, silence_level=3)
        n = rp.N
        out = {
            "RR": (rp.recurrence_matrix().sum() - n) / (n * n - n),
            "DET": rp.determinism(),
            "L": rp.average_diaglength(),
            "L_max": rp.max_diaglength(),
            "ENTR": rp.diag_entropy(),
        }
        rp.recurrence_matrix()[np.diag_indices(n)] = 0
        return out | {
            "LAM": rp.laminarity(),
            "TT": rp.trapping_time(),
            "V_max": rp.max_vertlength(),
        }

    peer_t, theirs = _best(peer, 1)
    mine = ours.measures()
    worst = max(abs(mine[k] / theirs[k] - 1.0) for k in theirs)
    rows.append(
        row
        | {
            "peer": "pyunicorn RecurrencePlot",
            "peer_s": peer_t,
            "ratio": ours_t / peer_t,
            "agreement": f"max rel. difference over 8 measures = {worst:.1e}",
        }
    )
    print(rows[-1], flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    rows: list[dict] = []
    d2_vs_tisean(rows, args.repeat)
    d2_vs_nolds(rows, args.repeat)
    rqa_vs_pyunicorn(rows, args.repeat)
    fields = ["case", "ours_s", "ours_value", "peer", "peer_s", "ratio", "agreement"]
    write_csv(OUT, fields, rows)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
