"""The Lyapunov estimators with defaults on a public corpus of chaotic flows and maps.

Every chaotic flow of ``dysts`` that integrates cleanly (see :mod:`corpus_flows`), first
coordinate, at two lengths from one integration:

* N = 20,000 samples at 100 per characteristic period (200 periods);
* N = 2,000 samples at 20 per period (100 periods; every fifth sample of the same run);

plus five maps with published exponents at both lengths. On each series
``lyapunov_rosenstein``, ``lyapunov_kantz`` and ``lyapunov_wolf`` run with defaults (only
``dt`` given), and ``nolds.lyap_r`` with its defaults at N = 2,000 (its N×N distance
matrix does not fit in memory at 20,000 on this machine class). The reference is dysts'
``maximum_lyapunov_estimated`` (flows) or the published value (maps).

Writes ``docs/benchmarks/estimator-corpus.csv`` (one row per series and method) and
``docs/benchmarks/estimator-corpus-summary.csv`` (median relative error, fraction within
20 %, 95 % interval coverage, per method, length and kind) and prints the summary as a
Markdown table. Run from the repository root (needs ``pip install chaoskit[bench]``):

    python benchmarks/estimator_corpus.py [--processes 2] [--quick]

Integrated series are cached (``--cache-dir``, default in the system temporary folder), so a
second run only re-runs the estimators.
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing as mp
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import corpus_flows

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks"
LONG, SHORT = 20_000, 2_000
PTS_LONG, DECIMATE = 100, 5
METHODS = ("rosenstein", "kantz", "wolf", "nolds")
NOLDS_MAX_N = 2_000
AGREE = 0.2  # dysts' published and the tangent exponent within 20 %: a trusted reference
QUICK_FLOWS = ("Lorenz", "Rossler", "Chua", "Duffing", "Halvorsen", "SprottB")
FIELDS = [
    "name",
    "kind",
    "n",
    "method",
    "true",
    "tangent",
    "estimate",
    "rel_error",
    "rel_error_tangent",
    "ci_low",
    "ci_high",
    "covered",
    "covered_tangent",
    "fit_found",
    "seconds",
    "note",
]


def _estimate(method: str, x: np.ndarray, dt: float) -> tuple[float, float, float, bool]:
    import chaoskit as ck

    if method == "nolds":
        import nolds

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            lam = float(nolds.lyap_r(x)) / dt
        return lam, np.nan, np.nan, True
    func = {
        "rosenstein": ck.lyapunov_rosenstein,
        "kantz": ck.lyapunov_kantz,
        "wolf": ck.lyapunov_wolf,
    }[method]
    res = func(x, dt=dt)
    return res.mle, res.ci[0], res.ci[1], res.fit_found


def _rows_for(series: corpus_flows.Series, tangent: float, methods: tuple[str, ...]) -> list[dict]:
    rows = []
    for method in methods:
        row = {"name": series.name, "kind": series.kind, "n": series.x.size, "method": method}
        row["true"] = series.mle
        row["tangent"] = tangent
        if method == "nolds" and series.x.size > NOLDS_MAX_N:
            continue
        t0 = time.perf_counter()
        try:
            lam, lo, hi, found = _estimate(method, series.x, series.dt)
            row.update(
                estimate=lam,
                rel_error=lam / series.mle - 1.0,
                rel_error_tangent=lam / tangent - 1.0 if tangent > 0 else np.nan,
                ci_low=lo,
                ci_high=hi,
                covered="" if method == "nolds" else int(lo <= series.mle <= hi),
                covered_tangent="" if method == "nolds" else int(lo <= tangent <= hi),
                fit_found=int(found),
                note="",
            )
        except Exception as exc:  # a failure is data here
            row.update(note=f"{type(exc).__name__}: {exc}"[:200])
        row["seconds"] = round(time.perf_counter() - t0, 3)
        rows.append(row)
    return rows


def _flow_task(args: tuple[str, str | None, tuple[str, ...]]) -> list[dict]:
    name, cache, methods = args
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    try:
        long = corpus_flows.dysts_flow(
            name, LONG, pts_per_period=PTS_LONG, cache_dir=Path(cache) if cache else None
        )
    except corpus_flows.IntegrationFailed as exc:
        return [
            {"name": name, "kind": "flow", "n": LONG, "method": "integration", "note": str(exc)}
        ]
    tangent = corpus_flows.tangent_exponent(name, cache_dir=Path(cache) if cache else None)
    short = corpus_flows.Series(
        name,
        "flow",
        np.ascontiguousarray(long.x[::DECIMATE][:SHORT]),
        long.dt * DECIMATE,
        long.mle,
        SHORT / (PTS_LONG / DECIMATE),
    )
    rows = []
    for s in (short, long):
        if np.ptp(s.x) == 0.0:
            continue
        rows.extend(_rows_for(s, tangent, methods))
    return rows


def _map_task(args: tuple[str, int, tuple[str, ...]]) -> list[dict]:
    name, n, methods = args
    series = next(s for s in corpus_flows.maps(n) if s.name == name)
    return _rows_for(series, corpus_flows.map_exponent(name), methods)


def _run_task(task: tuple) -> list[dict]:
    func, arg = task
    return func(arg)


def _summary(rows: list[dict]) -> list[dict]:
    """Per reference, method, length and kind: median |relative error|, shares, coverage."""
    out = []
    done = [r for r in rows if r["method"] in METHODS and r.get("note") == ""]
    for r in done:
        # series whose two references agree within 20 %: the tangent value, else excluded
        agree = (
            abs(float(r["true"]) / float(r["tangent"]) - 1.0) <= AGREE if r["tangent"] else False
        )
        r["agreed"] = float(r["tangent"]) if agree else np.nan
    for ref, err_key, cov_key, ref_key in (
        ("dysts", "rel_error", "covered", "true"),
        ("tangent", "rel_error_tangent", "covered_tangent", "tangent"),
        ("agreed", "rel_error_tangent", "covered_tangent", "agreed"),
    ):
        for method in METHODS:
            for n in (SHORT, LONG):
                for kind in ("flow", "map", "all"):
                    sel = [
                        r
                        for r in done
                        if r["method"] == method
                        and r["n"] == n
                        and (kind == "all" or r["kind"] == kind)
                        and np.isfinite(r[ref_key])
                        and r[ref_key] > 0
                    ]
                    if not sel:
                        continue
                    err = np.abs([r[err_key] for r in sel])
                    cov = [r[cov_key] for r in sel if r[cov_key] != ""]
                    out.append(
                        {
                            "reference": ref,
                            "method": method,
                            "n": n,
                            "kind": kind,
                            "series": len(sel),
                            "median_abs_rel_error": float(np.median(err)),
                            "within_20pct": float(np.mean(err <= 0.2)),
                            "within_5pct": float(np.mean(err <= 0.05)),
                            "ci_coverage": float(np.mean(cov)) if cov else np.nan,
                        }
                    )
    return out


def _write_csv(path: Path, rows: list[dict], fields: list[str]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".csv")
    with os.fdopen(fd, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, path)


def _print_summary(summary: list[dict]) -> None:
    print(
        "| reference | method | N | kind | series | median abs rel. error | within 20 % "
        "| within 5 % | 95 % CI coverage |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for s in summary:
        cov = "—" if np.isnan(s["ci_coverage"]) else f"{100 * s['ci_coverage']:.0f} %"
        print(
            f"| {s['reference']} | {s['method']} | {s['n']} | {s['kind']} | {s['series']} | "
            f"{100 * s['median_abs_rel_error']:.1f} % | {100 * s['within_20pct']:.0f} % | "
            f"{100 * s['within_5pct']:.0f} % | {cov} |"
        )


def _read_rows(path: Path) -> list[dict]:
    """The rows of a results CSV, with numbers as the summary expects them."""
    with path.open() as fh:
        rows: list[dict] = []
        for r in csv.DictReader(fh):
            for key in ("n",):
                r[key] = int(r[key])
            for key in ("true", "tangent", "rel_error", "rel_error_tangent"):
                r[key] = float(r[key]) if r.get(key) not in (None, "") else np.nan
            for key in ("covered", "covered_tangent"):
                r[key] = int(r[key]) if r.get(key) not in (None, "") else ""
            rows.append(r)
    return rows


def _resummarize(path: Path) -> int:
    rows = _read_rows(path)
    summary = _summary(rows)
    _write_csv(path.with_name(path.stem + "-summary.csv"), summary, list(summary[0]))
    _print_summary(summary)
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--processes", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--quick", action="store_true", help="six flows and the maps only")
    parser.add_argument(
        "--cache-dir", default=str(corpus_flows.DEFAULT_CACHE), help="integrated-series cache"
    )
    parser.add_argument("--out", default=str(OUT), help="output folder for the CSV files")
    parser.add_argument(
        "--summarize", metavar="CSV", help="only rewrite the summary of an existing results CSV"
    )
    parser.add_argument(
        "--methods", default=",".join(METHODS), help="comma-separated subset of " + str(METHODS)
    )
    parser.add_argument(
        "--keep-from",
        metavar="CSV",
        help="copy the rows of the methods not run from this results CSV (e.g. nolds')",
    )
    args = parser.parse_args(argv)
    if args.summarize:
        return _resummarize(Path(args.summarize))
    run = [m.strip() for m in args.methods.split(",") if m.strip()]
    if not run or any(m not in METHODS for m in run):
        parser.error(f"--methods must name some of {', '.join(METHODS)}")
    if args.processes < 1:
        parser.error("--processes must be >= 1")
    names = corpus_flows.dysts_flow_names()
    if args.quick:
        names = [n for n in names if n in QUICK_FLOWS]
    cached = {n for n in names if (Path(args.cache_dir) / f"{n}-tangent-200.npy").exists()}
    names.sort(key=lambda n: n not in cached)  # cached reference exponents first
    methods = tuple(run)
    tasks: list = [
        (_map_task, (m, n, methods)) for m in corpus_flows.MAP_REFERENCES for n in (SHORT, LONG)
    ]
    tasks += [(_flow_task, (n, args.cache_dir, methods)) for n in names]
    t0 = time.perf_counter()
    rows: list[dict] = []
    if args.keep_from:
        # integration failures are found again by this run; keeping them would repeat them
        kept = _read_rows(Path(args.keep_from))
        rows += [r for r in kept if r["method"] not in (*run, "integration")]
    out = Path(args.out)
    suffix = "-quick" if args.quick else ""
    summary: list[dict] = []
    with mp.get_context("spawn").Pool(args.processes, maxtasksperchild=10) as pool:
        # results are written after every finished group, so an interrupted run leaves
        # consistent tables of the groups done so far
        for i, group in enumerate(pool.imap_unordered(_run_task, tasks), 1):
            rows.extend(group)
            _write_csv(out / f"estimator-corpus{suffix}.csv", rows, FIELDS)
            summary = _summary(rows)
            if summary:
                _write_csv(out / f"estimator-corpus{suffix}-summary.csv", summary, list(summary[0]))
            print(f"\r{i}/{len(tasks)} series groups done", end="", file=sys.stderr)
    wall = time.perf_counter() - t0
    print(file=sys.stderr)
    failed = [r for r in rows if r["method"] == "integration"]
    broken = [r for r in rows if r["method"] in METHODS and r.get("note")]
    for r in failed + broken:
        print(f"not used: {r['name']} N={r['n']} {r['method']}: {r['note']}")
    print(f"{len(names) - len(failed)} of {len(names)} flows integrated cleanly; wall {wall:.0f} s")
    _print_summary(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
