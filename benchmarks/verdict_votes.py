"""Would correlation dimension (D2) saturation or RQA determinism earn a vote in the verdict?

For every series of the verdict corpus at one length, this computes next to the verdict
(read from a ``verdict_corpus.py`` CSV, whose lag and embedding dimension it reuses):

* D2 over embedding dimensions 1 … 8 (:func:`chaoskit.correlation_dimension`) and whether
  it saturates (the last two dimensions within 10 %);
* RQA determinism DET at a 5 % recurrence rate in the verdict's embedding
  (:func:`chaoskit.recurrence_analysis`, Theiler window one embedding span), and the same
  for one IAAFT surrogate of the series: the excess DET − DET_surrogate is determinism
  beyond what the linear correlations give.

Then it applies each candidate vote as a gate and prints the confusion matrix before and
after: *noise-like* needs D2 not saturated (resp. excess DET below ``DET_MARGIN``),
*chaotic* needs D2 saturated (resp. excess DET at least ``DET_MARGIN``); a label that
fails its gate becomes *undetermined*. Run after the corpus::

    python benchmarks/verdict_corpus.py --out /tmp/verdict.csv
    python benchmarks/verdict_votes.py /tmp/verdict.csv --n 2000
"""

from __future__ import annotations

import argparse
import csv
import multiprocessing
import os
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")


sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.corpus import corpus  # noqa: E402
from benchmarks.verdict_corpus import CACHE, LABELS, build  # noqa: E402

DET_MARGIN = 0.05
OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "verdict-votes.csv"
FIELDS = ["name", "n", "truth", "label", "decidable", "d2", "d2_saturated", "det",
          "det_surrogate", "det_excess", "seconds"]  # fmt: skip


def features(args: tuple[Any, dict[str, Any]]) -> dict[str, Any]:
    from chaoskit import correlation_dimension, recurrence_analysis
    from chaoskit.verdict._surrogates import iaaft_surrogates

    case, row = args
    out = {k: row[k] for k in ("name", "n", "truth", "label")}
    out["decidable"] = int(case.decidable)
    x = build(case, CACHE)
    lag, m = int(row["lag"] or 1), int(row["embedding_dim"] or 2)
    t0 = time.process_time()
    try:
        d2 = correlation_dimension(x, lag=lag)
        out.update(d2=round(float(d2.d2), 3), d2_saturated=int(d2.saturated))
    except ValueError as exc:
        out.update(d2="", d2_saturated="", note=str(exc))
    w = (m - 1) * lag + 1
    try:
        det = recurrence_analysis(x, embedding_dim=m, lag=lag, recurrence_rate=0.05,
                                  theiler_window=w).determinism  # fmt: skip
        s = iaaft_surrogates(x, n_surrogates=1, rng=case.seed())[0]
        det_s = recurrence_analysis(s, embedding_dim=m, lag=lag, recurrence_rate=0.05,
                                    theiler_window=w).determinism  # fmt: skip
        out.update(det=round(float(det), 4), det_surrogate=round(float(det_s), 4),
                   det_excess=round(float(det - det_s), 4))  # fmt: skip
    except ValueError:
        out.update(det="", det_surrogate="", det_excess="")
    out["seconds"] = round(time.process_time() - t0, 2)
    return out


def gate(rows: list[dict[str, Any]], vote: str) -> list[str]:
    labels = []
    for r in rows:
        lab = r["label"]
        if vote == "d2" and r["d2_saturated"] != "":
            sat = int(r["d2_saturated"])
            if (lab == "noise-like" and sat) or (lab == "chaotic" and not sat):
                lab = "undetermined"
        if vote == "det" and r["det_excess"] != "":
            excess = float(r["det_excess"]) >= DET_MARGIN
            if (lab == "noise-like" and excess) or (lab == "chaotic" and not excess):
                lab = "undetermined"
        labels.append(lab)
    return labels


def matrix(rows: list[dict[str, Any]], labels: list[str], title: str) -> str:
    truths = ("periodic", "quasi-periodic", "chaotic", "noise-like")
    out = [f"**{title}**", "", "| truth \\ verdict | " + " | ".join(LABELS) + " |",
           "|---" * (len(LABELS) + 1) + "|"]  # fmt: skip
    for t in truths:
        c = Counter(lab for r, lab in zip(rows, labels, strict=True) if r["truth"] == t)
        out.append(f"| {t} | " + " | ".join(str(c[lab]) for lab in LABELS) + " |")
    dec = [(r, lab) for r, lab in zip(rows, labels, strict=True) if int(r["decidable"])]
    ok = sum(r["truth"] == lab for r, lab in dec)
    false_chaos = sum(lab == "chaotic" and r["truth"] != "chaotic" for r, lab in dec)
    out += ["", f"correct where decidable: {ok}/{len(dec)} = {100 * ok / len(dec):.1f} %; "
            f"non-chaotic called chaotic: {false_chaos}"]  # fmt: skip
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("verdicts", type=Path, help="CSV written by verdict_corpus.py")
    parser.add_argument("--n", type=int, default=2000, help="series length (default 2000)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    with open(args.verdicts, encoding="utf-8") as fh:
        done = {(r["name"], int(r["n"])): r for r in csv.DictReader(fh) if r["status"] == "ok"}
    jobs = [(c, done[(c.name, c.n)]) for c in corpus() if (c.name, c.n) in done
            and c.n == args.n]  # fmt: skip
    with multiprocessing.get_context("fork").Pool(args.workers) as pool:
        rows = list(pool.imap(features, jobs))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, suffix=".csv", delete=False,
                                     newline="", encoding="utf-8") as fh:  # fmt: skip
        writer = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(fh.name, args.out)
    print(matrix(rows, [r["label"] for r in rows], "the verdict as it is"))
    for vote in ("d2", "det"):
        print()
        print(matrix(rows, gate(rows, vote), f"with the {vote} vote as a gate"))
    cpu = sum(float(r["seconds"]) for r in rows)
    print(f"\n{len(rows)} series, {cpu:.0f} s of CPU for D2, RQA and one surrogate's RQA")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
