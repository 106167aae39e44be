"""The verdict on a labelled corpus: confusion matrix, runtime and every miss with its reason.

One command (on two idle cores: 17 min the first time, which builds and caches every
series, about 8 min afterwards)::

    pip install -e ".[bench]"          # dysts, for its chaotic flows
    python benchmarks/verdict_corpus.py

writes ``docs/benchmarks/verdict-corpus.csv`` (one row per series) and prints the tables
published in ``docs/verdict.md``. ``--no-dysts`` runs the part generated here only;
``--workers`` sets the processes (default 2). The corpus is described in
``benchmarks/corpus.py``; ``classify`` runs with its defaults and a seed per series.
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing
import os
import signal
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one process per core: threads would only contend

import numpy as np  # noqa: E402  (after the thread settings)

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.corpus import Case, cache_path, corpus  # noqa: E402
from chaoskit.contract import atomic_write  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "benchmarks" / "verdict-corpus.csv"
CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "chaoskit-corpus"
BUILD_TIMEOUT = 90  # s: a dysts flow that takes longer does not "integrate cleanly"
LABELS = ("periodic", "quasi-periodic", "chaotic", "noise-like", "equilibrium", "undetermined")
REGULAR = ("periodic", "quasi-periodic", "equilibrium")

FIELDS = [
    "name", "family", "n", "truth", "true_period", "decidable", "status", "label", "period",
    "confidence", "correct", "lines", "section", "needs", "reason", "n_cycles", "lag",
    "embedding_dim", "noise_level", "rosenstein_growth", "wolf_growth", "kantz_growth",
    "zero_one_k",
    "surrogate_p", "surrogate_effect", "build_s", "classify_s", "classify_cpu_s",
]  # fmt: skip


class _Timeout(Exception):
    pass


def _alarm(signum: int, frame: Any) -> None:
    raise _Timeout


class _BuiltBefore(Exception):
    """A series whose build failed in an earlier run (the reason is the message)."""


def _failure_path(case: Case, cache: Path) -> Path:
    return cache_path(case, cache).with_suffix(".failed")


def build(case: Case, cache: Path) -> np.ndarray:
    """The series, from the cache when built before (written atomically). A build that
    failed before is not retried: its reason is kept beside the cache entry (``.failed``;
    delete that file to retry), which saves the minutes a flow that times out costs."""
    path = cache_path(case, cache)
    if path.is_file():
        return np.load(path)
    failed = _failure_path(case, cache)
    if failed.is_file():
        raise _BuiltBefore(failed.read_text(encoding="utf-8").strip())
    x = case.make()
    cache.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=cache, suffix=".npy", delete=False) as fh:
        np.save(fh, x)
    os.replace(fh.name, path)
    return x


def _remember_failure(case: Case, cache: Path, problem: str) -> None:
    atomic_write(_failure_path(case, cache), lambda tmp: tmp.write_text(problem + "\n"))


def _clean(x: np.ndarray) -> str | None:
    if x.size == 0 or not np.all(np.isfinite(x)):
        return "not finite"
    half = x[x.size // 2 :]
    if float(np.std(half)) <= 1e-9 * max(float(np.abs(half).max()), 1e-300):
        return "settles to a fixed point"
    return None


def run_case(args: tuple[Case, str]) -> dict[str, Any]:
    from chaoskit import classify

    case, cache = args
    row: dict[str, Any] = {
        "name": case.name, "family": case.family, "n": case.n, "truth": case.label,
        "true_period": "" if case.period is None else case.period,
        "decidable": int(case.decidable),
    }  # fmt: skip
    t0 = time.perf_counter()
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(BUILD_TIMEOUT)
    try:
        x = build(case, Path(cache))
        problem = _clean(x)
    except _BuiltBefore as exc:
        problem = f"{exc} (in an earlier run)"
    except _Timeout:
        problem = f"integration took more than {BUILD_TIMEOUT} s"
        _remember_failure(case, Path(cache), problem)
    except Exception as exc:  # a generator failing is data: the flow did not integrate
        problem = f"{type(exc).__name__}: {exc}"[:200]
        _remember_failure(case, Path(cache), problem)
    finally:
        signal.alarm(0)
    row["build_s"] = round(time.perf_counter() - t0, 2)
    if problem is not None:
        row.update(status=f"skipped: {problem}", label="", correct="")
        return row
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        v = classify(x, rng=case.seed(), **case.classify_kwargs)
    except Exception as exc:
        row.update(status=f"error: {type(exc).__name__}: {exc}"[:200], label="", correct="")
        row["classify_s"] = round(time.perf_counter() - t0, 2)
        return row
    # wall time, and the CPU time that does not depend on what else runs on the machine
    row["classify_s"] = round(time.perf_counter() - t0, 2)
    row["classify_cpu_s"] = round(time.process_time() - c0, 2)
    row.update(
        status="ok",
        label=v.label,
        period="" if v.period is None else v.period,
        confidence=round(float(v.confidence), 3),
        correct=int(v.label == case.label),
        lines="" if v.lines is None else v.lines.kind,
        section="" if v.structure is None else v.structure.kind,
        needs="; ".join(v.needs),
        reason=v.reason,
        **_evidence(v),
    )
    return row


def _evidence(v: Any) -> dict[str, Any]:
    """The numbers behind the votes: where a miss comes from, read off the CSV."""

    def growth(res: Any) -> Any:  # λ₁T, the growth per characteristic time
        return "" if res is None else round(float(res.mle * v.characteristic_time), 4)

    s = v.surrogates
    return {
        "n_cycles": round(float(v.n_cycles), 1),
        "lag": v.lag,
        "embedding_dim": v.embedding_dim,
        "noise_level": round(float(v.noise_level), 4),
        "rosenstein_growth": growth(v.rosenstein),
        "wolf_growth": growth(v.wolf),
        "kantz_growth": growth(v.kantz),  # the referee, when it ran
        "zero_one_k": "" if v.zero_one is None else round(float(v.zero_one.k), 3),
        "surrogate_p": "" if s is None else round(float(s.p_value), 3),
        "surrogate_effect": "" if s is None else round(float(s.effect), 4),
    }


def summarize(rows: list[dict[str, Any]]) -> str:
    """The Markdown tables of docs/verdict.md: confusion matrix, targets, misses."""
    ok = [r for r in rows if r["status"] == "ok"]
    skipped = [r for r in rows if r["status"] != "ok"]
    truths = ("periodic", "quasi-periodic", "chaotic", "noise-like")
    out = ["| truth \\ verdict | " + " | ".join(LABELS) + " | n |",
           "|---" * (len(LABELS) + 2) + "|"]  # fmt: skip
    for t in truths:
        c = Counter(r["label"] for r in ok if r["truth"] == t)
        out.append(f"| {t} | " + " | ".join(str(c[lab]) for lab in LABELS)
                   + f" | {sum(c.values())} |")  # fmt: skip
    dec = [r for r in ok if int(r["decidable"])]

    def pct(a: int, b: int) -> str:
        return f"{a}/{b} = {100 * a / b:.1f} %" if b else "—"

    def targets(sel: list[dict[str, Any]]) -> list[tuple[str, str, bool | None]]:
        correct = sum(int(r["correct"]) for r in sel)
        und = sum(r["label"] == "undetermined" for r in sel)
        non_chaotic = [r for r in sel if r["truth"] != "chaotic"]
        false_chaos = [r for r in non_chaotic if r["label"] == "chaotic"]
        chaotic = [r for r in sel if r["truth"] == "chaotic"]
        chaos_regular = [r for r in chaotic if r["label"] in REGULAR]
        confident = [
            r for r in sel if r["label"] != "undetermined" and float(r["confidence"]) >= 0.9
        ]
        conf_ok = sum(int(r["correct"]) for r in confident)
        hits = [r for r in sel if r["truth"] == "periodic" and r["label"] == "periodic"]
        period_ok = sum(str(r["period"]) == str(r["true_period"]) for r in hits)
        return [
            (f"{pct(correct, len(sel))} ({und} undetermined)", "", correct >= 0.95 * len(sel)),
            (pct(len(false_chaos), len(non_chaotic)), "", not false_chaos),
            (pct(len(chaos_regular), len(chaotic)), "", len(chaos_regular) <= 0.02 * len(chaotic)),
            (pct(conf_ok, len(confident)), "", conf_ok >= 0.97 * len(confident)),
            (pct(period_ok, len(hits)), "", None),
        ]

    names = (
        "≥ 95 % correct",
        "no periodic, quasi-periodic or noise series called chaotic",
        "≤ 2 % of chaotic series called regular",
        "≥ 97 % correct among confidence ≥ 0.9",
        "period right when periodic is right",
    )
    out += [
        "",
        "| target | decidable rows | met | all rows | met |",
        "|---|---|---|---|---|",
    ]
    for name, (d, _, dm), (a, _, am) in zip(names, targets(dec), targets(ok), strict=True):

        def yes(m: bool | None) -> str:
            return "—" if m is None else ("yes" if m else "no")

        out.append(f"| {name} | {d} | {yes(dm)} | {a} | {yes(am)} |")
    out += ["", "| family | N | correct where decidable | labels (decidable rows) |",
            "|---|---|---|---|"]  # fmt: skip
    for fam in sorted({r["family"] for r in ok}):
        for n in sorted({int(r["n"]) for r in ok}):
            sel = [r for r in dec if r["family"] == fam and int(r["n"]) == n]
            if sel:
                c = Counter(r["label"] for r in sel)
                labs = ", ".join(f"{c[lab]} {lab}" for lab in LABELS if c[lab])
                good = sum(int(r["correct"]) for r in sel)
                out.append(f"| {fam} | {n} | {pct(good, len(sel))} | {labs} |")
    build = sum(float(r["build_s"] or 0) for r in rows)
    cls = sum(float(r.get("classify_s") or 0) for r in ok)
    cpu = [float(r.get("classify_cpu_s") or 0) for r in ok]
    median = float(np.median(cpu)) if ok else float("nan")
    out += ["", f"{len(rows)} series, {len(ok)} classified, {len(skipped)} skipped. "
            f"classify: {sum(cpu):.0f} s of CPU in all (median {median:.2f} s, largest "
            f"{max(cpu, default=0):.1f} s per series), {cls:.0f} s of wall time in the "
            f"workers; building the series: {build:.0f} s of wall time."]  # fmt: skip
    misses = [r for r in ok if not int(r["correct"])]
    out += ["", "| series | N | truth | verdict | confidence | decidable | reason |",
            "|---|---|---|---|---|---|---|"]  # fmt: skip
    for r in sorted(misses, key=lambda r: (r["family"], r["name"], int(r["n"]))):
        out.append(f"| {r['name']} | {r['n']} | {r['truth']} | {r['label']} | "
                   f"{r['confidence']} | {'yes' if int(r['decidable']) else 'no'} | "
                   f"{r['reason']} |")  # fmt: skip
    if skipped:
        out += ["", "Skipped: " + "; ".join(f"{r['name']} N={r['n']} ({r['status']})"
                                            for r in skipped)]  # fmt: skip
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-dysts", action="store_true", help="skip the dysts flows")
    parser.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    parser.add_argument("--out", type=Path, default=OUT, help="CSV written (atomically)")
    parser.add_argument("--cache", type=Path, default=CACHE, help="where series are kept")
    parser.add_argument("--summarize", type=Path, help="only print the tables of a CSV")
    parser.add_argument("--only-n", type=int, help="run only the series of this length")
    parser.add_argument("--only-family", help="run only this family (e.g. dysts)")
    parser.add_argument(
        "--rerun-undetermined",
        type=Path,
        help="re-classify only the undetermined and failed rows of this CSV, keep the rest",
    )
    parser.add_argument(
        "--rerun-unbacked",
        type=Path,
        help="re-classify the rows of this CSV whose label the line analysis does not back "
        "(undetermined, failed, regular from the section alone) and the forced series",
    )
    args = parser.parse_args(argv)
    if args.summarize is not None:
        with open(args.summarize, encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
        print(summarize(rows))
        return 0
    if args.workers < 1:
        parser.error("--workers must be >= 1")
    cases = corpus(with_dysts=not args.no_dysts)
    if args.only_n is not None:
        cases = [c for c in cases if c.n == args.only_n]
    if args.only_family is not None:
        cases = [c for c in cases if c.family == args.only_family]
    kept: list[dict[str, Any]] = []
    if args.rerun_undetermined is not None:
        with open(args.rerun_undetermined, encoding="utf-8") as fh:
            old = list(csv.DictReader(fh))
        redo = {(r["name"], int(r["n"])) for r in old if r["label"] in ("undetermined", "")}
        kept = [r for r in old if (r["name"], int(r["n"])) not in redo]
        cases = [c for c in cases if (c.name, c.n) in redo]
    if args.rerun_unbacked is not None:
        with open(args.rerun_unbacked, encoding="utf-8") as fh:
            old = list(csv.DictReader(fh))
        forced = {(c.name, c.n) for c in cases if "drive_period" in c.classify_kwargs}

        def backed(r: dict[str, Any]) -> bool:
            lab, lines = r["label"], r["lines"]
            return (lab == lines or (lab == "chaotic" and lines in ("broadband", "unresolved"))
                    or (lab == "noise-like" and lines == "broadband"))  # fmt: skip

        redo = {(r["name"], int(r["n"])) for r in old
                if not backed(r) or (r["name"], int(r["n"])) in forced}  # fmt: skip
        kept = [r for r in old if (r["name"], int(r["n"])) not in redo]
        cases = [c for c in cases if (c.name, c.n) in redo]
    # the series generated here first, then the dysts flows, shorter before longer: a run
    # cut short still holds every family
    cases.sort(key=lambda c: (c.family == "dysts", c.n if c.family == "dysts" else 0))
    t0 = time.perf_counter()
    rows: list[dict[str, Any]] = []
    ctx = multiprocessing.get_context("fork")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    # rows are written as they come (a partial run keeps its results), then moved in place
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, suffix=".csv", delete=False,
                                     newline="", encoding="utf-8") as fh:  # fmt: skip
        writer = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        with ctx.Pool(args.workers, maxtasksperchild=20) as pool:
            jobs = [(c, str(args.cache)) for c in cases]
            for i, row in enumerate(pool.imap_unordered(run_case, jobs), 1):
                rows.append(row)
                writer.writerow(row)
                fh.flush()
                result = row.get("label") or row["status"]
                print(f"[{i}/{len(cases)}] {row['name']} N={row['n']}: {result}",
                      file=sys.stderr, flush=True)  # fmt: skip
    wall = time.perf_counter() - t0
    rows += kept
    rows.sort(key=lambda r: (r["family"], r["name"], int(r["n"])))
    with open(fh.name, "w", newline="", encoding="utf-8") as sorted_fh:
        writer = csv.DictWriter(sorted_fh, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(fh.name, args.out)
    print(summarize(rows))
    print(f"\nwall time {wall:.0f} s with {args.workers} worker(s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
