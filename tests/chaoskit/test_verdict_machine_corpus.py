"""The published machine corpus meets its targets.

``docs/benchmarks/machine-corpus.csv`` is written by ``benchmarks/machine_corpus.py``
(the project's own scenes observed as a rig would, truths from the equations); the
numbers asserted here are those published in docs/verdict.md, "The machine corpus".
"""

from __future__ import annotations

import csv
from pathlib import Path

MACHINE_CSV = Path(__file__).resolve().parents[2] / "docs" / "benchmarks" / "machine-corpus.csv"


def test_machine_corpus_targets() -> None:
    """The published machine corpus (written by ``benchmarks/machine_corpus.py``) meets its
    targets: no regular series called chaotic, at least 97 % right at confidence ≥ 0.9,
    and the decidable series right up to 10 % noise as published in docs/verdict.md
    (102 of 116; the target of 90 % is not met yet)."""
    with open(MACHINE_CSV, encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 167
    regular = [r for r in rows if r["truth"] == "periodic"]
    assert len(regular) == 99
    assert not any(r["called_chaotic"] == "True" for r in regular)
    scored = [r for r in rows if r["decidable"] == "True"]
    confident = [
        r for r in scored if r["label"] != "undetermined" and float(r["confidence"]) >= 0.9
    ]
    right = sum(r["correct"] == "True" for r in confident)
    assert right >= 0.97 * len(confident) and len(confident) == 64
    upto10 = [r for r in scored if r["noise_pct"] == "" or int(r["noise_pct"]) <= 10]
    assert len(upto10) == 116
    assert sum(r["correct"] == "True" for r in upto10) >= 102
