"""One verdict per motion, measured: per-variable disagreement and the motion verdict's accuracy.

One command (series are cached between runs)::

    pip install -e ".[bench]"          # dysts, for its chaotic flows
    python benchmarks/motion_corpus.py

writes ``docs/benchmarks/motion-corpus.csv`` (one row per system) and prints the tables
published in ``docs/verdict.md``. Every system is observed through all its coordinates:

* every chaotic flow of ``dysts`` that integrates cleanly, all coordinates (at most
  ``MAX_COORDS``), 100 characteristic periods at 20 points per period (N = 2000);
* maps with both coordinates: Hénon at a = 1.4 (chaotic) and in its periodic windows;
* flows generated here (N = 3000): forced Duffing (x, ẋ) and the driven pendulum
  (ω, sin θ) in periodic windows and chaotic, van der Pol (x, ẋ), Lorenz and Rössler
  (x, y, z); the same chaotic motions seen through a coordinate that follows the drive
  (the Duffing position beside cos ωt) or a nearly periodic one (Rössler's x beside the
  cosine of its phase angle);
* two- and three-frequency tori through two or three coordinates, clean and with 1 % noise;
* noise: pairs of independent series (white, AR(1), 1/f);
* noisy motions at 20 dB SNR (each coordinate).

``classify`` (per variable) and ``classify_motion`` run with their defaults and a seed per
system. "Best single variable" is the coordinate position (first, second, ...) whose
verdicts are most often right; "any variable" counts a system as right when at least one of
its variables is (an oracle no user has).
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import os
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks import corpus as vc  # noqa: E402
from chaoskit import classify_motion, systems  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "benchmarks" / "motion-corpus.csv"
CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "chaoskit-corpus"
N_GENERATED = 3000
N_DYSTS = 2000
MAX_COORDS = 6
FIELDS = [
    "name", "family", "truth", "true_period", "n", "k", "status", "variable_labels",
    "variable_confidences", "disagree", "confident_contradiction", "label", "period",
    "confidence", "correct", "first_correct", "any_correct", "variable_correct",
    "drive_variables", "reason", "needs", "cpu_s",
]  # fmt: skip


@dataclass(frozen=True)
class System:
    """One labelled motion observed through several variables."""

    name: str
    family: str
    truth: str
    builder: str
    params: dict[str, Any] = field(default_factory=dict)
    kwargs: dict[str, Any] = field(default_factory=dict)
    period: int | None = None

    def seed(self) -> int:
        return int(hashlib.sha256(self.name.encode()).hexdigest()[:8], 16)


# ----------------------------------------------------------------- generators


def _noisy(states: np.ndarray, snr_db: float | None, seed: int) -> np.ndarray:
    if snr_db is None:
        return states
    g = np.random.default_rng(seed)
    scale = states.std(axis=0) * 10 ** (-snr_db / 20)
    return states + scale * g.standard_normal(states.shape)


def henon(n: int, *, a: float) -> np.ndarray:
    x, y = 0.1, 0.1
    for _ in range(5000):
        x, y = 1 - a * x * x + y, 0.3 * x
    out = np.empty((n, 2))
    for i in range(n):
        x, y = 1 - a * x * x + y, 0.3 * x
        out[i] = x, y
    return out


def duffing(n: int, *, gamma: float, snr_db: float | None = None, drive: bool = False):
    t, st = systems.duffing(n, gamma=gamma, samples_per_period=50, discard_periods=300)
    if drive:
        return np.column_stack([st[:, 0], np.cos(1.2 * t)])
    return _noisy(st, snr_db, 7)


def pendulum(n: int, *, g: float) -> np.ndarray:
    st = vc._pendulum_state(n, g, 50)
    return np.column_stack([st[:, 1], np.sin(st[:, 0])])


def van_der_pol(n: int, *, mu: float, dt: float) -> np.ndarray:
    return systems.van_der_pol(n, dt=dt, mu=mu)


def lorenz(n: int, *, snr_db: float | None = None) -> np.ndarray:
    return _noisy(systems.lorenz(n, dt=0.03), snr_db, 7)


def rossler(n: int, *, phase: bool = False) -> np.ndarray:
    st = systems.rossler(n, dt=0.2)
    if phase:  # x beside the cosine of the phase angle: nearly periodic
        return np.column_stack([st[:, 0], np.cos(np.arctan2(st[:, 1], st[:, 0]))])
    return st


def torus(n: int, *, form: str, dt: float, snr_db: float | None = None) -> np.ndarray:
    t = np.arange(n) * dt
    if form == "two sines":
        w2 = np.pi * (np.sqrt(5) - 1)
        st = np.column_stack([np.sin(2 * np.pi * t) + 0.6 * np.sin(w2 * t),
                              np.cos(2 * np.pi * t) + 0.6 * np.cos(w2 * t)])  # fmt: skip
    elif form == "two-torus in R3":
        r = 2.0 + np.cos(np.sqrt(2) * t)
        st = np.column_stack([r * np.cos(t), r * np.sin(t), np.sin(np.sqrt(2) * t)])
    elif form == "three sines":
        st = np.column_stack([
            np.sin(t) + 0.6 * np.sin(np.sqrt(2) * t) + 0.3 * np.sin(np.sqrt(5) * t),
            np.cos(t) + 0.6 * np.cos(np.sqrt(2) * t) + 0.3 * np.cos(np.sqrt(5) * t),
        ])  # fmt: skip
    else:
        raise ValueError(f"unknown torus form {form!r}")
    return _noisy(st, snr_db, 7)


def noise_pair(n: int, *, kinds: tuple[str, str], seed: int) -> np.ndarray:
    return np.column_stack([vc.noise(n, kind=k, seed=seed + j) for j, k in enumerate(kinds)])


def dysts_system(n: int, *, system: str) -> np.ndarray:
    from benchmarks.corpus_flows import dysts_states

    states, _, _ = dysts_states(system, n, pts_per_period=20)
    return states[:, :MAX_COORDS]


BUILDERS = {
    "henon": henon, "duffing": duffing, "pendulum": pendulum, "van_der_pol": van_der_pol,
    "lorenz": lorenz, "rossler": rossler, "torus": torus, "noise": noise_pair,
    "dysts": dysts_system,
}  # fmt: skip


# ----------------------------------------------------------------- the corpus

DUFFING = vc.DUFFING_KW
PENDULUM = vc.PENDULUM_KW


def generated() -> list[System]:
    out: list[System] = []
    period_028 = vc.true_period("duffing", {"gamma": 0.28})
    for a in vc.HENON_A:
        k = vc.true_period("henon", {"a": a})
        if k is not None and k <= 8:
            out.append(System(f"henon a={a} (x, y)", "map", "periodic", "henon", {"a": a},
                              {}, k))  # fmt: skip
    out.append(System("henon a=1.4 (x, y)", "map", "chaotic", "henon", {"a": 1.4}))
    for g in vc.DUFFING_GAMMA:
        k = vc.true_period("duffing", {"gamma": g})
        if k is not None and k <= 8:
            out.append(System(f"duffing gamma={g} (x, v)", "window", "periodic", "duffing",
                              {"gamma": g}, DUFFING, k))  # fmt: skip
    for g in vc.PENDULUM_G:
        k = vc.true_period("pendulum", {"g": g})
        if k is not None and k <= 8:
            out.append(System(f"pendulum g={g} (omega, sin theta)", "window", "periodic",
                              "pendulum", {"g": g}, PENDULUM, k))  # fmt: skip
    for mu, dt in vc.VDP:
        out.append(System(f"van der Pol mu={mu} (x, v)", "window", "periodic", "van_der_pol",
                          {"mu": mu, "dt": dt}, {"dt": dt}, 1))  # fmt: skip
    out += [
        System("duffing gamma=0.5 (x, v)", "chaos", "chaotic", "duffing", {"gamma": 0.5}, DUFFING),
        System("pendulum g=1.5 (omega, sin theta)", "chaos", "chaotic", "pendulum", {"g": 1.5},
               PENDULUM),
        System("lorenz (x, y, z)", "chaos", "chaotic", "lorenz", {}, {"dt": 0.03}),
        System("rossler (x, y, z)", "chaos", "chaotic", "rossler", {}, {"dt": 0.2}),
        System("duffing gamma=0.5 (x, cos wt)", "mixed", "chaotic", "duffing",
               {"gamma": 0.5, "drive": True}, DUFFING),
        System("duffing gamma=0.5 (x, cos wt), no drive period", "mixed", "chaotic", "duffing",
               {"gamma": 0.5, "drive": True}, {"dt": DUFFING["dt"]}),
        System("rossler (x, cos phase)", "mixed", "chaotic", "rossler", {"phase": True},
               {"dt": 0.2}),
        System("lorenz (x, y, z) at 20 dB", "noisy", "chaotic", "lorenz", {"snr_db": 20.0},
               {"dt": 0.03}),
        System("duffing gamma=0.5 (x, v) at 20 dB", "noisy", "chaotic", "duffing",
               {"gamma": 0.5, "snr_db": 20.0}, DUFFING),
        System("duffing gamma=0.28 (x, v) at 20 dB", "noisy", "periodic", "duffing",
               {"gamma": 0.28, "snr_db": 20.0}, DUFFING, period_028),
    ]  # fmt: skip
    for form, dt in (("two sines", 0.05), ("two-torus in R3", 0.1), ("three sines", 0.1)):
        for snr in (None, 40.0):
            tag = "" if snr is None else " + 1% noise"
            out.append(System(f"torus {form}{tag}", "torus", "quasi-periodic", "torus",
                              {"form": form, "dt": dt, "snr_db": snr}, {"dt": dt}))  # fmt: skip
    for kinds in (("white", "white"), ("ar1=0.5", "ar1=0.9"), ("1/f", "white")):
        for seed in (0, 1):
            kw = {} if seed == 0 else {"dt": 0.01}
            name = f"noise {kinds[0]} + {kinds[1]} seed={seed}"
            params = {"kinds": kinds, "seed": seed}
            out.append(System(name, "noise", "noise-like", "noise", params, kw))
    return out


def dysts_systems() -> list[System]:
    from benchmarks.corpus_flows import dysts_flow_names

    return [System(f"dysts {s}", "dysts", "chaotic", "dysts", {"system": s}, {"dt": 1.0})
            for s in dysts_flow_names()]  # fmt: skip


# ----------------------------------------------------------------- running


def build(system: System, n: int, cache: Path) -> np.ndarray:
    key = hashlib.sha256(repr((system.builder, sorted(system.params.items()), n)).encode())
    path = cache / "motion" / f"{key.hexdigest()[:20]}.npy"
    if path.is_file():
        return np.load(path)
    x = np.ascontiguousarray(BUILDERS[system.builder](n, **system.params), dtype=float)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".npy", delete=False) as fh:
        np.save(fh, x)
    os.replace(fh.name, path)
    return x


def _right(label: str, truth: str) -> bool:
    return label == truth


def run(system: System, cache: Path) -> dict[str, Any]:
    n = N_DYSTS if system.family == "dysts" else N_GENERATED
    row: dict[str, Any] = {"name": system.name, "family": system.family, "truth": system.truth,
                           "true_period": system.period or "", "n": n}  # fmt: skip
    try:
        states = build(system, n, cache)
    except Exception as exc:
        row["status"] = f"skipped: {type(exc).__name__}: {exc}"[:200]
        return row
    t0 = time.process_time()
    try:
        mv = classify_motion(states, rng=system.seed(), **system.kwargs)
    except Exception as exc:
        row["status"] = f"failed: {type(exc).__name__}: {exc}"[:200]
        return row
    cpu = time.process_time() - t0
    labels = {k: v.label for k, v in mv.variables.items()}
    confs = {k: v.confidence for k, v in mv.variables.items()}
    voting = {k: labels[k] for k in mv.voting}
    confident = {lab for k, lab in voting.items() if lab != "undetermined" and confs[k] >= 0.5}
    correct = [_right(lab, system.truth) for lab in labels.values()]
    row.update(
        status="ok",
        k=len(labels),
        variable_labels=";".join(labels.values()),
        variable_confidences=";".join(f"{c:.2f}" for c in confs.values()),
        disagree=len(set(voting.values())) > 1,
        confident_contradiction=len(confident) > 1,
        label=mv.label,
        period="" if mv.period is None else mv.period,
        confidence=round(mv.confidence, 3),
        correct=_right(mv.label, system.truth),
        first_correct=correct[0],
        any_correct=any(correct),
        variable_correct=";".join(str(int(c)) for c in correct),
        drive_variables=";".join(mv.drive_variables),
        reason=mv.reason[:300],
        needs="; ".join(mv.needs)[:300],
        cpu_s=round(cpu, 2),
    )
    return row


def _pct(a: int, b: int) -> str:
    return f"{a}/{b} = {100 * a / b:.1f} %" if b else "—"


def summarize(rows: list[dict[str, Any]]) -> str:
    ok = [r for r in rows if r.get("status") == "ok"]

    def flag(r: dict[str, Any], key: str) -> bool:
        return str(r[key]) in ("True", "1")

    lines = ["| family | systems | variables disagree | confident contradiction | "
             "first variable right | best single position right | any variable right | "
             "motion right | motion undetermined | motion confident (≥ 0.5) and wrong |",
             "|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    families = [*sorted({r["family"] for r in ok}), "all"]
    for fam in families:
        sub = [r for r in ok if fam in ("all", r["family"])]
        if not sub:
            continue
        by_pos: Counter[int] = Counter()
        n_pos: Counter[int] = Counter()
        for r in sub:
            for j, c in enumerate(str(r["variable_correct"]).split(";")):
                by_pos[j] += c == "1"
                n_pos[j] += 1
        best = max(n_pos, key=lambda j: (by_pos[j] / n_pos[j], -j))
        wrong_conf = sum(
            1 for r in sub
            if not flag(r, "correct") and r["label"] != "undetermined"
            and float(r["confidence"]) >= 0.5
        )  # fmt: skip
        lines.append(
            f"| {fam} | {len(sub)} | {sum(flag(r, 'disagree') for r in sub)} | "
            f"{sum(flag(r, 'confident_contradiction') for r in sub)} | "
            f"{_pct(sum(flag(r, 'first_correct') for r in sub), len(sub))} | "
            f"{_pct(by_pos[best], n_pos[best])} (variable {best + 1}) | "
            f"{_pct(sum(flag(r, 'any_correct') for r in sub), len(sub))} | "
            f"{_pct(sum(flag(r, 'correct') for r in sub), len(sub))} | "
            f"{sum(r['label'] == 'undetermined' for r in sub)} | {wrong_conf} |"
        )
    resolved = [r for r in ok if flag(r, "disagree")]
    lines += ["", "Systems whose variables disagree, and the motion verdict:", "",
              "| system | truth | variables | motion | confidence | reason |",
              "|---|---|---|---|---|---|"]  # fmt: skip
    for r in resolved:
        lines.append(
            f"| {r['name']} | {r['truth']} | {r['variable_labels'].replace(';', ', ')} | "
            f"{r['label']} | {r['confidence']} | {r['reason'][:160]} |"
        )
    cpu = sum(float(r["cpu_s"]) for r in ok)
    lines += ["", f"classify_motion CPU time: {cpu:.0f} s over {len(ok)} systems "
              f"({len(rows) - len(ok)} skipped or failed)."]  # fmt: skip
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-dysts", action="store_true", help="skip the dysts flows")
    parser.add_argument("--out", type=Path, default=OUT, help="CSV written (atomically)")
    parser.add_argument("--cache", type=Path, default=CACHE, help="where series are kept")
    parser.add_argument("--summarize", type=Path, help="only print the tables of a CSV")
    args = parser.parse_args(argv)
    if args.summarize is not None:
        with open(args.summarize, encoding="utf-8") as fh:
            print(summarize(list(csv.DictReader(fh))))
        return 0
    cases = generated() + ([] if args.no_dysts else dysts_systems())
    t0, c0 = time.perf_counter(), time.process_time()
    rows: list[dict[str, Any]] = []
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, suffix=".csv", delete=False,
                                     newline="", encoding="utf-8") as fh:  # fmt: skip
        writer = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        for i, system in enumerate(cases, 1):
            row = run(system, args.cache)
            rows.append(row)
            writer.writerow(row)
            fh.flush()
            print(f"[{i}/{len(cases)}] {system.name}: {row.get('label') or row['status']}",
                  file=sys.stderr, flush=True)  # fmt: skip
    os.replace(fh.name, args.out)
    print(summarize([{k: str(v) for k, v in r.items()} for r in rows]))
    print(f"\nwall {time.perf_counter() - t0:.0f} s, CPU {time.process_time() - c0:.0f} s "
          "(building the series included)")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
