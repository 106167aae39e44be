"""Rosenstein and Kantz beside TISEAN 3.0.1 ``lyap_r`` and ``lyap_k``: CPU time and curves.

Cases: Lorenz x (dt = 0.01) with N = 10 000 and 50 000, Hénon x with N = 50 000. Each is
run twice:

* **same work** — the same embedding dimension, lag, Theiler window, horizon and radii,
  every reference point (``max_points`` and ``max_neighbors`` unbounded on our side), our
  Euclidean nearest sample (``neighbor="sample"``, ``distance="euclidean"``) and a fixed
  fit window (TISEAN prints the curve only; its slope is fitted here over the same window);
* **defaults** — ``lyap_r file`` / ``lyap_k file`` (m = 2, lag 1, no Theiler window, 10 or
  50 steps) against ``lyapunov_rosenstein(x, dt=dt)`` / ``lyapunov_kantz(x, dt=dt)``
  (which also estimate the lag, the dimension, the Theiler window, the horizon and the fit
  window, and compute the interval).

Both run in this process tree in interleaved rounds: TISEAN's CPU time is that of the
child (``resource.getrusage(RUSAGE_CHILDREN)``, reading its input file included), ours the
process CPU time (``time.process_time``) after a warm-up call, so compiling is excluded;
the compile time of a fresh install is measured separately in a child process with an
empty numba cache (``--compile``). The median of ``--rounds`` rounds is reported.

Curves: TISEAN's ``lyap_r`` curve is the mean ln distance in units of the data range, ours
in units of the standard deviation, so they differ by the constant ln(range / std); after
removing it they must agree within 0.02 nats at every horizon (the reference sets differ
by TISEAN's last ``theiler_window`` points, and zero distances are dropped by TISEAN), and
the fitted slopes within 1 %. ``lyap_k`` finds neighbours in the Euclidean norm and
averages squared distances (ln of the RMS distance), ours the maximum norm and distances
(ln of the mean): the slopes over the fit window must agree within 10 %. Kantz's same
work is also run on TISEAN's definition (``definition="rms"``): then every
radius's curve must agree with ``lyap_k``'s within 10⁻⁴ nats after the unit offset
(``lyap_k`` prints six digits).

Results: every speed-up of the kernels must keep our estimates. ``BEFORE`` holds the
exponent and interval of each row as computed before the last round of speed-ups (on the
series whose SHA-256 prefix is in ``SERIES``); when the series are bit-identical (same
machine arithmetic) each estimate must agree within ``RESULT_TOL`` relative, else the
check is skipped with a note (a chaotic series depends on the rounding of its integrator).

TISEAN is not shipped with chaoskit: build it from its source (``./configure && make`` in
``source_c``) and give the programs in ``TISEAN_LYAP_R`` and ``TISEAN_LYAP_K``; rows
whose program is missing are skipped. Writes ``docs/benchmarks/lyapunov-vs-tisean.csv``.
Run from the repository root:

    TISEAN_LYAP_R=/path/lyap_r TISEAN_LYAP_K=/path/lyap_k python benchmarks/lyapunov_vs_tisean.py
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from chaoskit import lyapunov_kantz, lyapunov_rosenstein, systems
from chaoskit.contract import atomic_write

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "lyapunov-vs-tisean.csv"
CURVE_TOL = 0.02  # nats, lyap_r curve against ours after removing the unit offset
SLOPE_TOL_R = 0.01  # relative, lyap_r
SLOPE_TOL_K = 0.10  # relative, lyap_k (other norm and mean)
RESULT_TOL = 1e-12  # relative, our estimates against BEFORE
CURVE_TOL_K = 1e-4  # nats, lyap_k curve against ours on TISEAN's definition (it prints 6 digits)
TISEAN_DEFINITION = "Euclidean ball, ln RMS"
#: SHA-256 prefix of each case's series when BEFORE was computed
SERIES = {
    "Lorenz x N=10000": "f8744cd2890631e0",
    "Lorenz x N=50000": "058b47ba8c2ea44a",
    "Henon x N=50000": "698af7bbaeeabcc7",
}
#: (mle, ci low, ci high) before the speed-ups of the neighbour search (kernels inlined,
#: cells sorted), the divergence curve (horizons on a step of 2 or 3 built over their span),
#: the interval's batch sums and Kantz's fused distance pass (the TISEAN-definition rows: their
#: values when the option was added)
BEFORE = {
    ("rosenstein", "Lorenz x N=10000", "same work"): (
        1.0340769520312452,
        0.24933053023119345,
        1.8188233738312969,
    ),
    ("rosenstein", "Lorenz x N=10000", "defaults"): (
        0.9717487116680739,
        0.21403297429369483,
        1.729464449042453,
    ),
    ("kantz", "Lorenz x N=10000", "same work"): (
        1.3036364269709313,
        0.05303336358449906,
        2.5542394903573635,
    ),
    ("kantz", "Lorenz x N=10000", "defaults"): (
        1.058728154817303,
        0.08224364820787611,
        2.03521266142673,
    ),
    ("rosenstein", "Lorenz x N=50000", "same work"): (
        0.9730618407300292,
        0.2424524226276744,
        1.703671258832384,
    ),
    ("rosenstein", "Lorenz x N=50000", "defaults"): (
        0.8867014472554894,
        0.2196675970873755,
        1.5572398215360117,
    ),
    ("kantz", "Lorenz x N=50000", "same work"): (
        1.2049829272121444,
        0.11083445509475864,
        2.2991313993295304,
    ),
    ("kantz", "Lorenz x N=50000", "defaults"): (
        0.9460349554041753,
        0.07981200091588525,
        1.8122579098924652,
    ),
    ("rosenstein", "Henon x N=50000", "same work"): (
        0.4181090828225908,
        0.39701681695120494,
        0.43920134869397665,
    ),
    ("rosenstein", "Henon x N=50000", "defaults"): (
        0.41797400861464085,
        0.3963091854526813,
        0.4396388317766004,
    ),
    ("kantz", "Henon x N=50000", "same work"): (
        0.4250599575427061,
        0.4028655946133524,
        0.44725432047205976,
    ),
    ("kantz", "Henon x N=50000", "defaults"): (
        0.42426845687988707,
        0.39998113693644627,
        0.4479348906581768,
    ),
    # TISEAN's definition (Euclidean balls, ln of the RMS distance), when it was added
    ("kantz", "Lorenz x N=10000", "same work, " + TISEAN_DEFINITION): (
        1.321604641650683,
        0.050425673459925546,
        2.5927836098414403,
    ),
    ("kantz", "Lorenz x N=50000", "same work, " + TISEAN_DEFINITION): (
        1.1969762287797583,
        0.10082339521686379,
        2.293129062342653,
    ),
    ("kantz", "Henon x N=50000", "same work, " + TISEAN_DEFINITION): (
        0.42719580757082687,
        0.40338848196977223,
        0.4510031331718815,
    ),
}


@dataclass(frozen=True)
class Case:
    name: str
    x: np.ndarray
    dt: float
    m: int
    lag: int
    w: int
    steps: int
    fit: tuple[int, int]
    k_steps: int
    k_fit: tuple[int, int]


def cases() -> list[Case]:
    lor10 = systems.lorenz(10_000, dt=0.01)[:, 0]
    lor50 = systems.lorenz(50_000, dt=0.01)[:, 0]
    hen50 = systems.henon(50_000)[:, 0]
    return [
        Case("Lorenz x N=10000", lor10, 0.01, 3, 10, 100, 300, (20, 200), 200, (20, 150)),
        Case("Lorenz x N=50000", lor50, 0.01, 3, 10, 100, 300, (20, 250), 200, (20, 150)),
        Case("Henon x N=50000", hen50, 1.0, 2, 1, 1, 25, (1, 12), 20, (1, 8)),
    ]


def series_hash(x: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(x, dtype=np.float64).tobytes()).hexdigest()[:16]


def check_before(estimator: str, case: Case, label: str, res) -> str:
    """Compare an estimate with ``BEFORE`` (asserting agreement); returns a note."""
    kind = "defaults" if label == "defaults" else "same work"
    if label.endswith(TISEAN_DEFINITION):
        kind = "same work, " + TISEAN_DEFINITION
    key = (estimator, case.name, kind)
    if key not in BEFORE:
        return "no earlier value"
    if series_hash(case.x) != SERIES[case.name]:
        return "before-check skipped: the series differs from the one BEFORE was computed on"
    got = (res.mle, *res.ci)
    dev = max(abs(g / b - 1.0) for g, b in zip(got, BEFORE[key], strict=True))
    assert dev <= RESULT_TOL, f"{key}: estimate moved by {dev:.3g} relative since BEFORE"
    return f"same as before within {dev:.1g}"


def child_cpu() -> float:
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def run_tisean(cmd: list[str]) -> float:
    t0 = child_cpu()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return child_cpu() - t0


def run_ours(func) -> tuple[float, object]:
    t0 = time.process_time()
    out = func()
    return time.process_time() - t0, out


def radii(x: np.ndarray) -> np.ndarray:
    """TISEAN's default radii: range/1000 … range/100, five in geometric progression."""
    span = float(np.ptp(x))
    return np.geomspace(span / 1000.0, span / 100.0, 5)


def read_ros(path: Path) -> tuple[np.ndarray, np.ndarray]:
    data = np.loadtxt(path, ndmin=2)
    return data[:, 0].astype(int), data[:, 1]


def read_lyap(path: Path, index: int) -> tuple[np.ndarray, np.ndarray]:
    """Curve of the ``index``-th radius of a ``lyap_k`` output."""
    blocks: list[list[list[float]]] = []
    for line in path.read_text().splitlines():
        if line.startswith("#epsilon"):
            blocks.append([])
        elif line.strip() and blocks:
            blocks[-1].append([float(v) for v in line.split()])
    block = np.array(blocks[index])
    return block[:, 0].astype(int), block[:, 1]


def lyap_k_curve_deviation(path: Path, res, index: int) -> float:
    """Largest deviation of the ``index``-th radius's ``lyap_k`` curve from ours, after
    removing their mean difference (TISEAN's unit is the range, ours the std)."""
    k, y = read_lyap(path, index)
    ours_y = np.interp(k, res.horizon, res.curves[index])
    offset = float(np.mean(ours_y - y))
    return float(np.max(np.abs(ours_y - y - offset)))


def slope(k: np.ndarray, y: np.ndarray, fit: tuple[int, int]) -> float:
    sel = (k >= fit[0]) & (k <= fit[1])
    return float(np.polyfit(k[sel], y[sel], 1)[0])


def timed_rounds(rounds: int, ours, theirs) -> tuple[float, float, object]:
    """Median CPU times of interleaved rounds (order alternating) and our last result."""
    t_ours, t_theirs, out = [], [], None
    for r in range(rounds):
        if r % 2:
            t_theirs.append(theirs())
        dt_, out = run_ours(ours)
        t_ours.append(dt_)
        if not r % 2:
            t_theirs.append(theirs())
    return float(np.median(t_ours)), float(np.median(t_theirs)), out


def rosenstein_rows(case: Case, lyap_r: str | None, tmp: Path, rounds: int) -> list[dict]:
    data = tmp / "x.dat"
    np.savetxt(data, case.x)
    kw = dict(
        dt=case.dt,
        embedding_dim=case.m,
        lag=case.lag,
        theiler_window=case.w,
        max_horizon=case.steps,
        fit_range=case.fit,
        max_points=10**9,
        neighbor="sample",
        distance="euclidean",
    )
    rows = []
    for label, ours, cmd in (
        (
            f"m={case.m} lag={case.lag} w={case.w} k<={case.steps} fit={case.fit}",
            lambda: lyapunov_rosenstein(case.x, **kw),
            [f"-m{case.m}", f"-d{case.lag}", f"-t{case.w}", f"-s{case.steps}"],
        ),
        ("defaults", lambda: lyapunov_rosenstein(case.x, dt=case.dt), []),
    ):
        row = {"estimator": "rosenstein", "case": case.name, "settings": label}
        if not lyap_r:
            t, res = run_ours(ours)
            before = check_before("rosenstein", case, label, res)
            rows.append(
                row
                | {
                    "ours_cpu_s": t,
                    "peer": "lyap_r (not built: set TISEAN_LYAP_R)",
                    "before": before,
                }
            )
            continue
        out = tmp / "x.ros"
        full = [lyap_r, str(data), *cmd, "-o", str(out), "-V0"]
        t_ours, t_theirs, res = timed_rounds(rounds, ours, lambda full=full: run_tisean(full))
        row |= {
            "ours_cpu_s": t_ours,
            "peer": "TISEAN lyap_r",
            "peer_cpu_s": t_theirs,
            "ratio": t_ours / t_theirs,
            "ours_mle": res.mle,
            "before": check_before("rosenstein", case, label, res),
        }
        if cmd:
            k, y = read_ros(out)
            ours_y = np.interp(k, res.horizon, res.curve)
            offset = float(np.mean(ours_y - y))
            dev = float(np.max(np.abs(ours_y - y - offset)))
            s_theirs = slope(k, y, case.fit) / case.dt
            rel = abs(res.mle / s_theirs - 1.0)
            row |= {
                "peer_mle": s_theirs,
                "agreement": f"curve max dev {dev:.2g} nats, slope rel. diff {rel:.2g}",
            }
            assert dev < CURVE_TOL, f"{case.name}: lyap_r curve deviates by {dev:.3g} nats"
            assert rel < SLOPE_TOL_R, f"{case.name}: lyap_r slope differs by {rel:.3g}"
        rows.append(row)
        print(row, flush=True)
    return rows


def kantz_rows(case: Case, lyap_k: str | None, tmp: Path, rounds: int) -> list[dict]:
    data = tmp / "x.dat"
    np.savetxt(data, case.x)
    eps = radii(case.x)
    kw = dict(
        dt=case.dt,
        embedding_dim=case.m,
        lag=case.lag,
        theiler_window=case.w,
        max_horizon=case.k_steps,
        fit_range=case.k_fit,
        epsilon=eps,
        max_points=10**9,
        max_neighbors=10**9,
        distance="euclidean",
    )
    same = [
        f"-M{case.m}",
        f"-m{case.m}",
        f"-d{case.lag}",
        f"-t{case.w}",
        f"-s{case.k_steps}",
        f"-r{eps[0]}",
        f"-R{eps[-1]}",
        "-#5",
    ]
    rows = []
    settings = f"m={case.m} lag={case.lag} w={case.w} k<={case.k_steps} fit={case.k_fit} 5 radii"
    for label, ours, cmd in (
        (settings, lambda: lyapunov_kantz(case.x, **kw), same),
        (
            f"{settings}, {TISEAN_DEFINITION}",
            lambda: lyapunov_kantz(case.x, **kw, definition="rms"),
            same,
        ),
        ("defaults", lambda: lyapunov_kantz(case.x, dt=case.dt), []),
    ):
        row = {"estimator": "kantz", "case": case.name, "settings": label}
        if not lyap_k:
            t, res = run_ours(ours)
            before = check_before("kantz", case, label, res)
            rows.append(
                row
                | {
                    "ours_cpu_s": t,
                    "peer": "lyap_k (not built: set TISEAN_LYAP_K)",
                    "before": before,
                }
            )
            continue
        out = tmp / "x.lyap"
        full = [lyap_k, str(data), *cmd, "-o", str(out), "-V0"]
        t_ours, t_theirs, res = timed_rounds(rounds, ours, lambda full=full: run_tisean(full))
        row |= {
            "ours_cpu_s": t_ours,
            "peer": "TISEAN lyap_k",
            "peer_cpu_s": t_theirs,
            "ratio": t_ours / t_theirs,
            "ours_mle": res.mle,
            "before": check_before("kantz", case, label, res),
        }
        if cmd:
            e = res.epsilon_index
            k, y = read_lyap(out, e)
            s_theirs = slope(k, y, case.k_fit) / case.dt
            rel = abs(res.mle / s_theirs - 1.0)
            note = f"slope rel. diff {rel:.2g} (radius {e})"
            if label.endswith(TISEAN_DEFINITION):
                # the same quantity: every radius's curve, after the unit offset
                dev = max(lyap_k_curve_deviation(out, res, i) for i in range(eps.size))
                note = f"curve max dev {dev:.2g} nats (5 radii), " + note
                assert dev < CURVE_TOL_K, f"{case.name}: lyap_k curve deviates by {dev:.3g}"
            row |= {"peer_mle": s_theirs, "agreement": note}
            assert rel < SLOPE_TOL_K, f"{case.name}: lyap_k slope differs by {rel:.3g}"
        rows.append(row)
        print(row, flush=True)
    return rows


_COMPILE = """
import time, numpy as np
from chaoskit import lyapunov_kantz, lyapunov_rosenstein, systems
x = systems.lorenz(10_000, dt=0.01)[:, 0]
for f in (lyapunov_rosenstein, lyapunov_kantz):
    t0 = time.process_time(); f(x, dt=0.01); first = time.process_time() - t0
    t0 = time.process_time(); f(x, dt=0.01); warm = time.process_time() - t0
    print(f.__name__, first - warm)
"""


def compile_rows() -> list[dict]:
    """First call minus a warm call, in a child with an empty numba cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = os.environ | {"NUMBA_CACHE_DIR": cache}
        out = subprocess.run(
            [sys.executable, "-c", _COMPILE], env=env, check=True, capture_output=True, text=True
        ).stdout
    rows = []
    for line in out.splitlines():
        name, value = line.split()
        rows.append(
            {
                "estimator": name.removeprefix("lyapunov_"),
                "case": "compile (fresh numba cache)",
                "settings": "defaults, Lorenz x N=10000, first call minus warm call",
                "ours_cpu_s": float(value),
            }
        )
        print(rows[-1], flush=True)
    return rows


FIELDS = [
    "estimator",
    "case",
    "settings",
    "ours_cpu_s",
    "peer",
    "peer_cpu_s",
    "ratio",
    "ours_mle",
    "peer_mle",
    "agreement",
    "before",
]


def write_rows(path: Path, rows: list[dict]) -> None:
    def writer(tmp: Path) -> None:
        with tmp.open("w", newline="") as fh:
            out = csv.DictWriter(fh, fieldnames=FIELDS)
            out.writeheader()
            for row in rows:
                out.writerow(
                    {k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()}
                )

    atomic_write(path, writer)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5, help="interleaved rounds (median)")
    parser.add_argument("--compile", action="store_true", help="also time a fresh compile")
    parser.add_argument("--out", type=Path, default=OUT, help="CSV to write")
    args = parser.parse_args()
    if args.rounds < 1:
        parser.error("--rounds must be >= 1")
    lyap_r = os.environ.get("TISEAN_LYAP_R")
    lyap_k = os.environ.get("TISEAN_LYAP_K")
    lyap_r = lyap_r if lyap_r and Path(lyap_r).exists() else None
    lyap_k = lyap_k if lyap_k and Path(lyap_k).exists() else None
    warm = systems.lorenz(3000, dt=0.01)[:, 0]
    lyapunov_rosenstein(warm, dt=0.01)
    lyapunov_kantz(warm, dt=0.01)
    lyapunov_rosenstein(
        warm[:2000],
        embedding_dim=3,
        lag=10,
        theiler_window=100,
        max_horizon=50,
        fit_range=(5, 40),
        neighbor="sample",
        distance="euclidean",
    )
    rows: list[dict] = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in cases():
            rows += rosenstein_rows(case, lyap_r, Path(tmp), args.rounds)
            rows += kantz_rows(case, lyap_k, Path(tmp), args.rounds)
    if args.compile:
        rows += compile_rows()
    write_rows(args.out, rows)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
