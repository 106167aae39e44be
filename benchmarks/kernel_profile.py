"""Where a compiled run spends its time, kernel by kernel: samples of ``perf`` resolved
through ``gdb``.

A numba kernel is one opaque call to Python's profilers, and ``perf`` sees only the
addresses of code that numba generated in memory. This script runs a workload in a child
process (after a short warm-up call that loads or compiles every kernel it needs),
samples that process with ``perf record`` for ``--seconds``, and asks ``gdb``, attached to
the same still-running process, for the function at each sampled address (LLVM registers
the code it generates with gdb's JIT interface). Samples are summed by function; the
share of each function is its own time (callees not included).

Workloads (the ``paper`` scene at 150 rpm, c = 0.2 mm):

* ``flexible``: flexible rods at the fixed step T/10000, ``record=SectionsRecord(companion=False)``;
* ``flexible-worn``: the same on the bearing worn for 10 000 cycles at 150 rpm
  (one wear update, as the quick study predicts it);
* ``flexible-exponent``: :func:`mechanism.lyapunov_exponent` of the flexible scene (its
  reference at T/10000 and the perturbed copy taking the same steps);
* ``rigid``: rigid rods, error control at the scene's tolerance, ``record="sections"``;
* ``rigid-exponent``: :func:`mechanism.lyapunov_exponent` of the rigid scene.

Needs ``perf`` and ``gdb`` (``apt-get install linux-perf gdb`` or the distribution's
names) and permission to sample the child process. Writes
``docs/benchmarks/kernel-profile-<workload>.csv`` and prints the table::

    NUMBA_NUM_THREADS=1 python benchmarks/kernel_profile.py flexible [--seconds 20]
"""

from __future__ import annotations

import argparse
import collections
import csv
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WORKLOADS = ("flexible", "flexible-worn", "flexible-exponent", "rigid", "rigid-exponent")
_READY = "kernel-profile: ready"
# addresses resolved through gdb: the most frequent ones (the rest is a long tail)
_RESOLVE = 3000


def _workload(name: str) -> None:
    """Child process: warm up, say ready, then run the workload until killed."""
    import mechanism
    from mechanism.core import SectionsRecord

    scene = mechanism.load_scene("paper").replace({"joints.C.clearance": 2e-4})
    period = 60.0 / float(scene.drive.speed_rpm)
    if name.startswith("flexible"):
        scene = scene.replace({"effects.flexibility": True, "solver.max_step": period / 1e4})
        if name == "flexible-worn":
            scene = mechanism.predict_wear(
                scene,
                updates=1,
                cycles_per_update=1e4,
                max_depth_increment=1.0,
                settle_revolutions=1.0,
                output_step=period / 2500,
            ).worn_scene

        if name == "flexible-exponent":

            def run(revolutions: float) -> None:
                mechanism.lyapunov_exponent(scene, revolutions=revolutions + 0.1, discard=0.1)

        else:

            def run(revolutions: float) -> None:
                mechanism.simulate(
                    scene, revolutions=revolutions, record=SectionsRecord(companion=False)
                )

    elif name == "rigid":
        scene = scene.replace({"effects.flexibility": False})

        def run(revolutions: float) -> None:
            mechanism.simulate(scene, revolutions=10 * revolutions, record="sections")

    else:
        scene = scene.replace({"effects.flexibility": False})

        def run(revolutions: float) -> None:
            mechanism.lyapunov_exponent(scene, revolutions=revolutions + 1.0, discard=1.0)

    run(0.05)
    print(_READY, flush=True)
    while True:
        run(50.0)


def _function(symbol: str) -> str:
    """``package.module.function`` of a gdb symbol line (mangled or demangled)."""
    symbol = symbol.split(" in section ")[0]
    symbol = re.sub(r" \+ \d+$", "", symbol)
    if symbol.startswith("_ZN"):
        rest = symbol[3:]
        rest = rest.removeprefix("7cpython")
        parts = []
        while rest and rest[0].isdigit():
            digits = re.match(r"\d+", rest)
            assert digits is not None
            k = int(digits.group())
            start = len(digits.group())
            parts.append(rest[start : start + k])
            rest = rest[start + k :]
        return ".".join(parts) if parts else symbol[:80]
    head = symbol.split("[abi:")[0].split("(")[0]
    return head.replace("::", ".")


def _sample(pid: int, seconds: float, workdir: Path) -> collections.Counter[str]:
    data = workdir / "perf.data"
    subprocess.run(
        ["perf", "record", "-F", "1999", "-p", str(pid), "-o", str(data), "--", "sleep",
         str(seconds)],
        check=True, capture_output=True,
    )  # fmt: skip
    script = subprocess.run(
        ["perf", "script", "-i", str(data), "-F", "ip,sym,dso"],
        check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    by_ip: collections.Counter[str] = collections.Counter()
    named: dict[str, str] = {}
    for line in script.splitlines():
        fields = line.split(None, 1)
        if not fields:
            continue
        ip = fields[0]
        by_ip[ip] += 1
        rest = fields[1] if len(fields) > 1 else ""
        if "[unknown]" not in rest and "JIT" not in rest:
            named[ip] = rest.rsplit(" (", 1)[0].strip() or "?"
    unresolved = [ip for ip, _ in by_ip.most_common() if ip not in named][:_RESOLVE]
    commands = workdir / "gdb.cmd"
    commands.write_text("".join(f"info symbol 0x{ip}\n" for ip in unresolved))
    out = subprocess.run(
        ["gdb", "-p", str(pid), "-batch", "-x", str(commands)],
        capture_output=True, text=True, check=False,
    ).stdout  # fmt: skip
    answers = [
        line for line in out.splitlines() if " in section " in line or "No symbol matches" in line
    ]
    for ip, answer in zip(unresolved, answers, strict=False):
        named[ip] = "?" if "No symbol" in answer else _function(answer)
    totals: collections.Counter[str] = collections.Counter()
    for ip, count in by_ip.items():
        totals[named.get(ip, "(unresolved tail)")] += count
    return totals


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("workload", choices=WORKLOADS)
    parser.add_argument("--seconds", type=float, default=20.0, help="sampling time (s)")
    parser.add_argument("--top", type=int, default=25, help="rows printed")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _workload(args.workload)
        return 0
    missing = [tool for tool in ("perf", "gdb") if shutil.which(tool) is None]
    if missing:
        print(f"kernel_profile: needs {' and '.join(missing)} on PATH", file=sys.stderr)
        return 2
    if not args.seconds > 0:
        print("kernel_profile: --seconds must be > 0", file=sys.stderr)
        return 2
    child = subprocess.Popen(
        [sys.executable, __file__, args.workload, "--child"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
        env={**os.environ, "NUMBA_NUM_THREADS": os.environ.get("NUMBA_NUM_THREADS", "1")},
    )  # fmt: skip
    try:
        assert child.stdout is not None
        for line in child.stdout:
            if _READY in line:
                break
        else:
            print("kernel_profile: the workload ended before it was ready", file=sys.stderr)
            return 1
        time.sleep(1.0)
        with tempfile.TemporaryDirectory() as tmp:
            totals = _sample(child.pid, args.seconds, Path(tmp))
    finally:
        child.send_signal(signal.SIGKILL)
        child.wait()
    total = sum(totals.values())
    rows = [(name, count, count / total) for name, count in totals.most_common()]
    out = ROOT / "docs" / "benchmarks" / f"kernel-profile-{args.workload}.csv"
    tmp_out = out.with_suffix(".csv.tmp")
    with tmp_out.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["function", "samples", "share"])
        for name, count, share in rows:
            writer.writerow([name, count, f"{share:.4f}"])
    tmp_out.replace(out)
    print(f"{total} samples over {args.seconds:g} s of {args.workload}")
    for name, count, share in rows[: args.top]:
        print(f"{100 * share:6.1f} %  {count:7d}  {name}")
    print(f"written: {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
