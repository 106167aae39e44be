"""Compile time of a fresh install: which kernels a run compiles and where the time goes.

Each case runs in a child process with an empty numba cache (``NUMBA_CACHE_DIR`` set to a
new temporary folder), so every kernel it needs is compiled from its source. numba's event
API (``numba.core.event``) reports every compile of a dispatcher (``numba:compile``), every
compiler pass (``numba:run_pass``) and every hold of the LLVM lock (``numba:llvm_lock``:
LLVM's optimisation and machine-code generation). The events nest (a kernel's type
inference compiles the kernels it calls; lowering takes the LLVM lock), so each event's
*own* CPU time is its time less that of the events inside it; the table sums them per
kernel, per compiler pass and per kind. Times are CPU seconds of the child
(``time.process_time``), so a loaded machine inflates the wall time, not them.

Cases (``--case``, several allowed; default all):

* ``simulate``: ``mechanism.simulate`` of the rigid ``paper`` scene, one revolution,
  ``record="sections"``; then the same run over 10 revolutions once compiled (its CPU
  time per revolution is ``warm_call_cpu_s``: what a compile option costs at run time).
* ``lyapunov``: the same, then ``mechanism.lyapunov_exponent`` over 2 revolutions.
* ``wear``: the same as ``simulate`` with ``effects.wear = true``.
* ``flexible``: ``mechanism.simulate`` of the flexible ``paper`` scene, 0.05 revolutions.

Run with

    NUMBA_NUM_THREADS=1 python benchmarks/compile_time.py [--case simulate] [--csv FILE]

and ``--child CASE`` runs one case in this process (what the parent starts). A row per
case is appended to ``docs/benchmarks/compile-time.csv`` (``--csv`` to change).
``--kernels`` prints a table of every compiled dispatcher: the phase of the run that
compiled it first (``simulate``, or ``lyapunov`` for the exponent's own), its number of
signatures (``dispatcher.signatures``), its own CPU time, whether it has the wrappers for
calls from Python (``no``: a kernel of ``mechanism.core._jit.njit_inner``), and, for a
kernel compiled more than once, what its signatures differ in (argument by argument, the fields of a
named-tuple argument by field: array layout, readonly, integer width, ...).
``--json DIR`` writes the same per case to ``DIR/compile-CASE.json``.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

from numba.core import event

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "compile-time.csv"
#: the compiled run is timed over this many times the first call's revolutions (per 1)
WARM = 10.0
CASES = ("simulate", "lyapunov", "wear", "flexible")
FIELDS = [
    "date", "case", "import_cpu_s", "first_call_cpu_s", "warm_call_cpu_s", "compile_cpu_s",
    "kernels", "signatures", "type_inference_cpu_s", "llvm_cpu_s", "lowering_cpu_s",
    "other_passes_cpu_s", "load_start", "load_end", "top_kernels",
]  # fmt: skip


class Profile(event.Listener):
    """numba event listener: the own CPU time of every event (its time less that of the
    events inside it) per (kind, name), and per kernel being compiled (its passes and
    LLVM work included, the kernels it compiles in turn excluded)."""

    def __init__(self) -> None:
        self.stack: list[list[Any]] = []  # [(kind, name), start, own time so far]
        self.own: dict[tuple[str, str], float] = defaultdict(float)
        self.kernel: dict[str, float] = defaultdict(float)
        self.signatures: dict[str, set[str]] = defaultdict(set)
        self.dispatchers: dict[str, Any] = {}
        #: the phase of the run (``simulate``, ``lyapunov``) in which a kernel first compiled
        self.phase_of: dict[str, str] = {}
        self.phase = "simulate"
        self.compiling: list[str] = []
        self.last = time.process_time()

    def _credit(self, now: float) -> None:
        if self.compiling:
            self.kernel[self.compiling[-1]] += now - self.last
        if self.stack:
            self.stack[-1][2] += now - self.stack[-1][1]
            self.stack[-1][1] = now
        self.last = now

    def on_start(self, ev: Any) -> None:
        now = time.process_time()
        self._credit(now)
        name = ""
        if ev.kind == "numba:compile":
            disp = ev.data["dispatcher"]
            name = f"{disp.py_func.__module__}.{disp.py_func.__qualname__}"
            self.signatures[name].add(str(ev.data["args"]))
            self.dispatchers[name] = disp
            self.phase_of.setdefault(name, self.phase)
            self.compiling.append(name)
        elif ev.kind == "numba:run_pass":
            name = ev.data["name"].split(" [")[0]
        self.stack.append([(ev.kind, name), now, 0.0])

    def on_end(self, ev: Any) -> None:
        now = time.process_time()
        self._credit(now)
        key, _, own = self.stack.pop()
        self.own[key] += own
        if self.stack:
            self.stack[-1][1] = now
        if ev.kind == "numba:compile":
            self.compiling.pop()

    def install(self) -> None:
        for kind in ("numba:compile", "numba:run_pass", "numba:llvm_lock"):
            event.register(kind, self)


def _field_differences(a: Any, b: Any, where: str) -> list[str]:
    """Where two numba types differ: the fields of two named tuples of the same class one
    by one, else the two types whole."""
    if a == b:
        return []
    fields_a = getattr(a, "fields", None)
    if fields_a is not None and getattr(a, "instance_class", None) is getattr(
        b, "instance_class", False
    ):
        out = []
        for name, ta, tb in zip(fields_a, a.types, b.types, strict=True):
            out += _field_differences(ta, tb, f"{where}.{name}")
        return out
    return [f"{where}: {a} / {b}"]


def differences(signatures: list[tuple[Any, ...]]) -> str:
    """What the signatures of one dispatcher differ in (argument by argument, the fields of
    a named-tuple argument by field); empty with a single signature."""
    out: list[str] = []
    first = signatures[0] if signatures else ()
    for other in signatures[1:]:
        if len(other) != len(first):
            out.append(f"{len(first)} / {len(other)} arguments")
            continue
        for i, (a, b) in enumerate(zip(first, other, strict=True)):
            out += _field_differences(a, b, f"arg {i}")
    return "; ".join(dict.fromkeys(out))


def child(case: str) -> dict[str, Any]:
    """Run one case in this process (empty cache expected) and return its row."""
    profile = Profile()
    load_start = os.getloadavg()[0]
    t0 = time.process_time()
    import mechanism

    profile.install()
    t_import = time.process_time() - t0
    rigid = mechanism.load_scene("paper").replace({"effects.flexibility": False})

    def run(revolutions: float) -> None:
        if case == "flexible":
            mechanism.simulate(mechanism.load_scene("paper"), revolutions=0.05 * revolutions,
                               record="sections")  # fmt: skip
            return
        scene = rigid.replace({"effects.wear": True}) if case == "wear" else rigid
        mechanism.simulate(scene, revolutions=revolutions, record="sections")
        if case == "lyapunov":
            profile.phase = "lyapunov"
            mechanism.lyapunov_exponent(scene, revolutions=2 * revolutions, discard=0.5)

    t0 = time.process_time()
    run(1.0)
    first = time.process_time() - t0
    t0 = time.process_time()
    run(WARM)
    warm = (time.process_time() - t0) / WARM
    own = profile.own
    total = sum(v for (k, _), v in own.items())
    infer = sum(v for (k, n), v in own.items() if "type_inference" in n)
    llvm = own.get(("numba:llvm_lock", ""), 0.0)
    lowering = sum(v for (k, n), v in own.items() if "lowering" in n.lower())
    top = sorted(profile.kernel.items(), key=lambda kv: -kv[1])[:12]
    return {
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "case": case, "import_cpu_s": round(t_import, 2), "first_call_cpu_s": round(first, 2),
        "warm_call_cpu_s": round(warm, 4), "compile_cpu_s": round(total, 2),
        "kernels": len(profile.signatures),
        "signatures": sum(len(s) for s in profile.signatures.values()),
        "type_inference_cpu_s": round(infer, 2), "llvm_cpu_s": round(llvm, 2),
        "lowering_cpu_s": round(lowering, 2),
        "other_passes_cpu_s": round(total - infer - llvm - lowering, 2),
        "load_start": load_start, "load_end": os.getloadavg()[0],
        "top_kernels": "; ".join(f"{n.split('.', 2)[-1]} {v:.1f}" for n, v in top),
        "all_kernels": {n: [len(profile.dispatchers[n].signatures), round(profile.kernel[n], 2),
                            profile.phase_of[n],
                            differences(profile.dispatchers[n].signatures),
                            not profile.dispatchers[n].targetoptions.get("no_cpython_wrapper")]
                        for n in profile.signatures},
        "passes": {n: round(v, 2) for (k, n), v in sorted(own.items(), key=lambda kv: -kv[1])
                   if v > 0.2},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", action="append", choices=CASES)
    parser.add_argument("--child", choices=CASES, help=argparse.SUPPRESS)
    parser.add_argument("--csv", default=str(OUT))
    parser.add_argument(
        "--kernels", action="store_true",
        help="list every compiled kernel: phase, signatures, own CPU time, what differs",
    )  # fmt: skip
    parser.add_argument("--json", help="folder: write each case's row and kernel table there")
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args.child)))
        return
    for case in args.case or CASES:
        with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
            env = {**os.environ, "NUMBA_CACHE_DIR": cache, "NUMBA_NUM_THREADS": "1"}
            out = subprocess.run(
                [sys.executable, __file__, "--child", case], env=env, check=True,
                capture_output=True, text=True,
            )  # fmt: skip
        row = json.loads(out.stdout.strip().splitlines()[-1])
        kernels, passes = row.pop("all_kernels"), row.pop("passes")
        print(json.dumps(row, indent=1, ensure_ascii=False))
        print("passes (own CPU s):", passes)
        if args.kernels:
            print("| kernel | phase | signatures | own CPU s | wrappers | signatures differ in |")
            print("|---|---|---:|---:|---|---|")
            for name, (sigs, own, phase, diff, wrapped) in sorted(
                kernels.items(), key=lambda kv: (kv[1][2] != "simulate", -kv[1][1])
            ):
                short = name.removeprefix("mechanism.core.")
                wrappers = "yes" if wrapped else "no"
                print(f"| `{short}` | {phase} | {sigs} | {own:.2f} | {wrappers} | {diff} |")
        if args.json:
            folder = Path(args.json)
            folder.mkdir(parents=True, exist_ok=True)
            table = json.dumps({"row": row, "kernels": kernels}, indent=1)
            (folder / f"compile-{case}.json").write_text(table, encoding="utf-8")
        path = Path(args.csv)
        path.parent.mkdir(parents=True, exist_ok=True)
        new = not path.exists()
        with path.open("a", newline="", encoding="utf-8") as fh:
            writer = csv.DictWriter(fh, fieldnames=FIELDS)
            if new:
                writer.writeheader()
            writer.writerow(row)


if __name__ == "__main__":
    main()
