"""The machine corpus: the project's own scenes, observed as a rig would, with known truth.

One command (simulated series and the truths are cached between runs)::

    python benchmarks/machine_corpus.py

writes ``docs/benchmarks/machine-corpus.csv`` (one row per series), the noise-tolerance
figure ``docs/benchmarks/machine-corpus-noise.png`` and prints the tables published in
``docs/verdict.md`` ("The machine corpus") and ``docs/measured-data.md``.

**Truth, from the equations.** Each regime (a built-in scene at one crank speed) is
*periodic* when :func:`mechanism.periodic_orbit` converges (shooting residual below its
tolerance) to an orbit whose Floquet multipliers all lie inside the unit circle and the
exponent of the equations (:func:`mechanism.lyapunov_exponent`) is not clearly positive;
*chaotic* when that exponent's 95 % interval lies above zero with λ₁T ≥ 0.1 per drive
period and no stable orbit was found; anything else is *undecidable* and kept out of the
scores.

**Observation.** 100 drive periods after 20 discarded, at T/100 (N = 10 000), of

* ``journal_x``: the eccentricity x of the clearance joint's journal (a proximity probe), m;
* ``housing_acc``: the acceleration of the bearing housing, taken as the x component of
  the contact force the journal puts into the bearing (normal force along the
  eccentricity, friction along the tangent; the bearing does not rotate in these scenes)
  over an effective housing mass of ``HOUSING_MASS`` (a stiffly mounted housing; the
  scale does not change a verdict), m s⁻²;
* ``slider_position``: the output slider's position (a displacement transducer), m;

plus the crank angle (the rig's encoder), used as ``phase_variable``. Added measurement
noise of 0, 1, 5, 10, 20 % of the clean series' standard deviation, white Gaussian or
coloured (AR(1), φ = 0.9, scaled to the same standard deviation), then a data logger's
quantisation: 16 bits (both noise kinds) or 12 bits (no noise, and 10 % white noise) over
the series' range
widened by 10 % on each side.

**Decidable rows.** A chaotic motion is not chaotic in every observable to every
resolution: the slider of a press follows the drive to a few parts in a thousand. For a
chaotic regime each observable's *chaotic part* is measured on the clean series: the RMS
of its departure from its mean cycle over its standard deviation. A chaotic row is
decidable when that part exceeds both the added noise level and the verdict's stated
resolution (``VerdictRule.cluster_tol``, 5 % of the spread: below it the rule calls a
tight stroboscopic cluster a periodic orbit plus noise, by design). Rows of periodic
regimes are all decidable. The undecidable rows are listed with their labels, not scored.

Each estimator's own answer is also recorded (``est_*``: "chaotic", "regular" or empty
when it does not decide) for the noise-tolerance figure.

``--evidence`` prints instead the range of every piece of evidence the verdict computed
on the rows it calls periodic from one tight stroboscopic cluster, chaotic truths against
periodic ones (``docs/verdict.md``, "What the remaining misses need"); it classifies
every row again (minutes).
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import math
import os
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402

import chaoskit  # noqa: E402
import mechanism  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "benchmarks" / "machine-corpus.csv"
FIGURE = REPO / "docs" / "benchmarks" / "machine-corpus-noise.png"
CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "chaoskit-corpus"
KEPT = 100  # drive periods observed
DISCARDED = 20  # drive periods of transient dropped (the 250 rpm transient lasts 0-13)
PER_PERIOD = 100  # samples per drive period
HOUSING_MASS = 10.0  # kg, effective mass of the bearing housing
LEVELS = (0.0, 0.01, 0.05, 0.10, 0.20)
OBSERVABLES = ("journal_x", "housing_acc", "slider_position")
UNITS = {"journal_x": "m", "housing_acc": "m s-2", "slider_position": "m"}
LONG_NAMES = {
    "journal_x": "journal eccentricity x (proximity probe)",
    "housing_acc": "bearing housing acceleration x (contact force / housing mass)",
    "slider_position": "slider position (displacement transducer)",
}
SPECTRUM_ANSWER = {"periodic": "regular", "quasi-periodic": "regular", "broadband": "chaotic"}
SECTION_ANSWER = {"clusters": "regular", "closed-curve": "regular", "scattered": "chaotic"}
ESTIMATORS = ("lines", "rosenstein", "wolf", "zero_one", "surrogates", "cycle_test",
              "cycle_spread", "section")  # fmt: skip
FIELDS = [
    "regime", "scene", "rpm", "truth", "truth_reason", "observable", "noise_kind",
    "noise_pct", "bits", "n", "chaotic_part", "decidable", "label", "period", "confidence",
    "correct", "called_chaotic", *(f"est_{e}" for e in ESTIMATORS), "reason", "cpu_s",
]  # fmt: skip


@dataclass(frozen=True)
class Regime:
    """A built-in scene at one crank speed."""

    name: str
    scene: str
    rpm: float
    rigid: bool = True
    shift: float = 0.0  # the crank's start, in revolutions (rounding-robustness checks)

    def build(self) -> mechanism.Scene:
        changes: dict[str, Any] = {"drive.speed_rpm": self.rpm}
        if self.shift:
            changes["drive.initial_angle"] = 2 * math.pi * self.shift
        if self.rigid:
            changes["effects.flexibility"] = False
        return mechanism.load_scene(self.scene).replace(changes)

    @property
    def period(self) -> float:
        return 60.0 / self.rpm


#: Every regime whose truth the equations decide is scored: the rigid paper scene at 30
#: and 250 rpm (stable period-1 orbits), 150 and 90 rpm (chaotic; at 90 rpm the journal's
#: chaos lives in the impacts' timing) and the clearance slider-crank at 5000 rpm (a stable
#: period-1 orbit).
REGIMES = (
    Regime("paper 30 rpm", "paper", 30.0),
    Regime("paper 250 rpm", "paper", 250.0),
    Regime("paper 150 rpm", "paper", 150.0),
    Regime("paper 90 rpm", "paper", 90.0),
    Regime("slider-crank-clearance 5000 rpm", "slider-crank-clearance", 5000.0),
)
#: Regimes defined but not in the default run (``--extra`` adds them).
EXTRA: tuple[Regime, ...] = ()


def _atomic_json(path: Path, obj: Any) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=path.parent, suffix=".json", delete=False) as fh:
        json.dump(obj, fh, indent=1)
    os.replace(fh.name, path)


def _key(regime: Regime, what: str) -> str:
    fields = (regime.scene, regime.rpm, regime.rigid, regime.shift, what, mechanism.__version__)
    return hashlib.sha256(repr(fields).encode()).hexdigest()[:16]


# ----------------------------------------------------------------- truth


def truth(regime: Regime, cache: Path) -> dict[str, Any]:
    """The regime decided by the equations: the stable orbit and the exponent."""
    path = cache / "machine" / f"truth-{_key(regime, 'truth')}.json"
    if path.is_file():
        return json.loads(path.read_text(encoding="utf-8"))
    scene = regime.build()
    t0 = time.process_time()
    try:
        orbit = mechanism.periodic_orbit(scene, settle=DISCARDED)
        mult = np.abs(np.asarray(orbit.multipliers))
        orbit_info = {
            "converged": bool(orbit.converged),
            "residual": float(orbit.residual),
            "largest_multiplier": float(mult.max()) if mult.size else float("nan"),
            "stable": bool(orbit.converged and mult.size and mult.max() < 1.0),
        }
    except Exception as exc:  # a failed shooting is evidence against a stable orbit
        orbit_info = {"converged": False, "error": f"{type(exc).__name__}: {exc}"[:200],
                      "stable": False, "largest_multiplier": float("nan"),
                      "residual": float("nan")}  # fmt: skip
    t1 = time.process_time()
    lyap = mechanism.lyapunov_exponent(scene, revolutions=60, discard=DISCARDED)
    t2 = time.process_time()
    lo, hi = (float(c) for c in lyap.ci)
    growth = float(lyap.exponent) * regime.period
    positive = lo > 0.0 and growth >= 0.1
    if orbit_info["stable"] and not positive:
        label = "periodic"
        why = (f"stable period-1 orbit, |mu|max {orbit_info['largest_multiplier']:.3g}; "
               f"lambda1 {lyap.exponent:.3g} 1/s [{lo:.3g}, {hi:.3g}]")  # fmt: skip
    elif positive and not orbit_info["stable"]:
        label = "chaotic"
        why = (f"lambda1 {lyap.exponent:.3g} 1/s [{lo:.3g}, {hi:.3g}], "
               f"{growth:.2f} per drive period; no stable period-1 orbit")  # fmt: skip
    else:
        label = "undecidable"
        why = (f"lambda1 {lyap.exponent:.3g} 1/s [{lo:.3g}, {hi:.3g}]; period-1 orbit "
               f"{'stable' if orbit_info['stable'] else 'not found stable'}")  # fmt: skip
    out = {"label": label, "reason": why, "orbit": orbit_info,
           "exponent": float(lyap.exponent), "ci": [lo, hi], "growth_per_period": growth,
           "cpu_orbit_s": t1 - t0, "cpu_exponent_s": t2 - t1}  # fmt: skip
    _atomic_json(path, out)
    return out


# ----------------------------------------------------------------- observation


def observe(regime: Regime, cache: Path) -> xr.Dataset:
    """The clean observables and the crank angle, KEPT periods after DISCARDED, at T/100."""
    path = cache / "machine" / f"series-{_key(regime, 'series')}.nc"
    if path.is_file():
        with xr.open_dataset(path) as ds:
            return ds.load()
    period = regime.period
    traj = mechanism.simulate(regime.build(), revolutions=KEPT + DISCARDED,
                              output_step=period / PER_PERIOD)  # fmt: skip
    traj = traj.isel(time=slice(DISCARDED * PER_PERIOD, (KEPT + DISCARDED) * PER_PERIOD))
    traj = traj.isel(joint=0, drop=True)
    ds = xr.Dataset(
        {
            "journal_x": traj["eccentricity_x"],
            # the bearing takes +Fn along the eccentricity and -Ft along the tangent
            "housing_acc": (
                traj["contact_force"] * np.cos(traj["contact_angle"])
                + traj["friction_force"] * np.sin(traj["contact_angle"])
            )
            / HOUSING_MASS,
            "slider_position": traj["slider_position"],
            "crank_angle": traj["crank_angle"],
        }
    )
    for name in OBSERVABLES:
        ds[name].attrs = {"units": UNITS[name], "long_name": LONG_NAMES[name]}
    ds["crank_angle"].attrs = {"units": "rad", "long_name": "crank angle (encoder)"}
    ds = ds.drop_vars([c for c in ds.coords if c != "time"])
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".nc", delete=False) as fh:
        tmp = fh.name
    ds.to_netcdf(tmp)
    os.replace(tmp, path)
    return ds


def chaotic_part(x: np.ndarray) -> float:
    """RMS departure of a clean series from its mean cycle, over its standard deviation."""
    cycles = x[: (x.size // PER_PERIOD) * PER_PERIOD].reshape(-1, PER_PERIOD)
    return float(np.sqrt(np.mean((cycles - cycles.mean(axis=0)) ** 2)) / x.std())


def measurement_noise(n: int, kind: str, seed: int) -> np.ndarray:
    """Unit-variance measurement noise: white Gaussian, or AR(1) with phi = 0.9."""
    g = np.random.default_rng(seed)
    e = g.standard_normal(n)
    if kind == "white":
        return e
    phi = 0.9
    out = np.empty(n)
    out[0] = e[0]
    for i in range(1, n):
        out[i] = phi * out[i - 1] + math.sqrt(1 - phi * phi) * e[i]
    return out


def quantise(x: np.ndarray, bits: int) -> np.ndarray:
    """A logger's quantisation over the series' range widened by 10 % on each side."""
    lo, hi = float(x.min()), float(x.max())
    span = hi - lo
    lo, hi = lo - 0.1 * span, hi + 0.1 * span
    lsb = (hi - lo) / 2**bits
    return lo + np.round((x - lo) / lsb) * lsb


def recorded(clean: xr.Dataset, name: str, kind: str, level: float, bits: int,
             seed: int) -> xr.Dataset:  # fmt: skip
    """What the logger stores: ``name`` plus noise, quantised, beside the crank angle."""
    x = clean[name].values
    noisy = x + level * x.std() * measurement_noise(x.size, kind, seed)
    out = clean[[name, "crank_angle"]].copy()
    out[name] = (("time",), quantise(noisy, bits), clean[name].attrs)
    return out


def row_seed(tag: str) -> int:
    """The noise seed of one corpus row, from its tag ``regime|observable|kind|level|bits``."""
    return int(hashlib.sha256(tag.encode()).hexdigest()[:8], 16)


def cases() -> list[tuple[str, float, int]]:
    """(noise kind, level, bits) of every recorded variant of one observable."""
    out = [("white", 0.0, 16)]
    out += [(k, lev, 16) for k in ("white", "ar1") for lev in LEVELS[1:]]
    out += [("white", lev, 12) for lev in (0.0, 0.10)]
    return out


# ----------------------------------------------------------------- verdicts


def estimator_answers(v: chaoskit.Verdict) -> dict[str, str]:
    """Each estimator's own answer, "chaotic" or "regular" ("" when it does not decide).

    The IAAFT surrogate test asks another question (linear noise or not): its answer is
    "deterministic" when it rejects, which is right for every row of this corpus."""
    rule = v.rule
    lines = "" if v.lines is None else v.lines.kind
    k = None if v.zero_one is None else float(v.zero_one.k)
    st = None if v.structure is None else v.structure.kind
    spread = v.cycle_spread

    def positive(flag: bool | None) -> str:
        return "" if flag is None else ("chaotic" if flag else "regular")

    def two_way(flag: bool, yes: str, no: str) -> str:
        return yes if flag else no

    zero_one = ""
    if k is not None and k >= rule.zero_one_chaotic:
        zero_one = "chaotic"
    elif k is not None and k <= rule.zero_one_regular:
        zero_one = "regular"
    sur, cyc = v.surrogates, v.surrogates_cycle
    return {
        "lines": SPECTRUM_ANSWER.get(lines, ""),
        "rosenstein": positive(v.rosenstein_positive),
        "wolf": positive(v.wolf_positive),
        "zero_one": zero_one,
        "surrogates": "" if sur is None else two_way(sur.rejected, "deterministic", "noise"),
        "cycle_test": "" if cyc is None else two_way(cyc.rejected, "chaotic", "regular"),
        "cycle_spread": ""
        if not np.isfinite(spread)
        else two_way(spread > rule.cluster_tol, "chaotic", "regular"),
        "section": SECTION_ANSWER.get(st or "", ""),
    }


def run_regime(regime: Regime, cache: Path, tr: dict[str, Any]) -> list[dict[str, Any]]:
    """The corpus rows of one regime (cached: they depend on the series, the truth and
    chaoskit's version)."""
    key = _key(regime, f"rows {chaoskit.__version__} {tr['label']} {cases()}")
    path = cache / "machine" / f"rows-{key}.json"
    if path.is_file():
        rows = json.loads(path.read_text(encoding="utf-8"))
    else:
        rows = _classify_regime(regime, cache, tr)
        _atomic_json(path, rows)
    for row in rows:
        row["truth_reason"] = tr["reason"]
    return rows


def variants(
    regime: Regime, cache: Path, tr: dict[str, Any]
) -> Iterator[tuple[str, str, tuple[str, float, int], float, bool, xr.Dataset]]:
    """Every recorded series of one regime: (tag, observable, (kind, level, bits), chaotic
    part, decidable, the recorded Dataset)."""
    clean = observe(regime, cache)
    tol = chaoskit.VerdictRule().cluster_tol
    for name in OBSERVABLES:
        part = chaotic_part(clean[name].values)
        for kind, level, bits in cases():
            tag = f"{regime.name}|{name}|{kind}|{level}|{bits}"
            data = recorded(clean, name, kind, level, bits, row_seed(tag))
            decidable = tr["label"] == "periodic" or (
                tr["label"] == "chaotic" and part > max(level, tol)
            )
            yield tag, name, (kind, level, bits), part, decidable, data


def _classify_regime(regime: Regime, cache: Path, tr: dict[str, Any]) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    for tag, name, (kind, level, bits), part, decidable, data in variants(regime, cache, tr):
        row: dict[str, Any] = {
            "regime": regime.name, "scene": regime.scene, "rpm": regime.rpm,
            "truth": tr["label"], "truth_reason": tr["reason"], "observable": name,
            "noise_kind": kind if level else "none", "noise_pct": round(100 * level),
            "bits": bits, "n": data.sizes["time"], "chaotic_part": round(part, 4),
            "decidable": decidable,
        }  # fmt: skip
        t0 = time.process_time()
        v = chaoskit.classify(data, variable=name, phase_variable="crank_angle", rng=0)
        row.update(
            label=v.label, period="" if v.period is None else v.period,
            confidence=round(float(v.confidence), 3), correct=v.label == tr["label"],
            called_chaotic=v.label == "chaotic",
            **{f"est_{e}": a for e, a in estimator_answers(v).items()},
            reason=v.reason[:200], cpu_s=round(time.process_time() - t0, 2),
        )  # fmt: skip
        rows.append(row)
        print(f"{tag}: {v.label} ({v.confidence:.2f})", file=sys.stderr, flush=True)
    return rows


def shipped_rows() -> list[dict[str, Any]]:
    """The project's shipped probe file (synthetic: the 150 rpm journal plus sensor noise
    and a 12-bit converter) as a rig file; its truth is that of the 150 rpm regime."""
    path = REPO / "data" / "measured-journal.csv"
    ds = chaoskit.load_trajectory(path, time="t_s")
    rows = []
    for name in ("probe_x_um", "probe_y_um"):
        t0 = time.process_time()
        v = chaoskit.classify(ds, variable=name, drive_period=0.4, rng=0)
        rows.append({"regime": "shipped data/measured-journal.csv", "scene": "paper",
                     "rpm": 150.0, "truth": "chaotic", "truth_reason": "the 150 rpm regime",
                     "observable": name, "noise_kind": "white", "noise_pct": "",
                     "bits": 12, "n": ds.sizes["time"], "chaotic_part": "",
                     "decidable": True, "label": v.label,
                     "period": "" if v.period is None else v.period,
                     "confidence": round(float(v.confidence), 3),
                     "correct": v.label == "chaotic", "called_chaotic": v.label == "chaotic",
                     **{f"est_{e}": a for e, a in estimator_answers(v).items()},
                     "reason": v.reason[:200],
                     "cpu_s": round(time.process_time() - t0, 2)})  # fmt: skip
    return rows


# ----------------------------------------------------------------- tight clusters

#: The groups ``--evidence`` compares: chaotic rows the rule calls periodic from one tight
#: stroboscopic cluster, against the periodic rows with a tight cluster (all of them, and
#: those whose departure from the mean cycle depends on the phase: the ``phase`` vote).
GROUPS = ("chaotic, called periodic", "periodic, phase against", "periodic, tight cluster")


def evidence(v: chaoskit.Verdict, x: np.ndarray) -> dict[str, float]:
    """What the verdict computed on a forced series, as numbers: exponents (and their lower
    95 % bounds) times the drive period; Kantz's, which the verdict runs only as a
    referee, is computed here for every row; ``positive`` counts the clearly positive
    estimates of the three."""
    nan = float("nan")
    per = v.characteristic_time
    try:
        kantz = chaoskit.lyapunov_kantz(x, embedding_dim=v.embedding_dim, lag=v.lag, dt=v.dt)
    except (ValueError, np.linalg.LinAlgError):
        kantz = None
    out: dict[str, float] = {}
    positive = 0
    for name, res in (("rosenstein", v.rosenstein), ("wolf", v.wolf), ("kantz", kantz)):
        lam, low = (nan, nan) if res is None else (float(res.mle), float(res.ci[0]))
        out[name], out[f"{name}_low"] = lam * per, low * per
        positive += bool(low > 0 and lam * per >= v.rule.min_growth)
    out["positive"] = positive
    sur, cyc = v.surrogates, v.surrogates_cycle
    st = v.structure
    out.update(
        zero_one_k=nan if v.zero_one is None else float(v.zero_one.k),
        surrogate_p=nan if sur is None else sur.p_value,
        surrogate_effect=nan if sur is None else sur.effect,
        cycle_p=nan if cyc is None else cyc.p_value,
        cycle_effect=nan if cyc is None else cyc.effect,
        phase_spread=v.phase_spread,
        cluster_radius=nan if st is None else float(st.cluster_radius),
        line_residual=nan if v.lines is None else float(v.lines.residual_fraction),
        noise_level=v.noise_level,
    )
    return out


def evidence_rows(
    regimes: list[Regime], cache: Path, truths: dict[str, dict[str, Any]]
) -> dict[str, list[dict[str, float]]]:
    """The evidence of every row in one of ``GROUPS`` (classified again: the cached rows
    keep only the labels)."""
    groups: dict[str, list[dict[str, float]]] = {g: [] for g in GROUPS}
    for regime in regimes:
        tr = truths[regime.name]
        for tag, name, _case, _part, decidable, data in variants(regime, cache, tr):
            v = chaoskit.classify(data, variable=name, phase_variable="crank_angle", rng=0)
            tight = v.structure is not None and v.structure.kind == "clusters"
            if not (tight and decidable and v.label == "periodic"):
                continue
            ev = evidence(v, data[name].values)
            if tr["label"] == "chaotic":
                groups[GROUPS[0]].append(ev)
            elif tr["label"] == "periodic":
                groups[GROUPS[2]].append(ev)
                if v.votes.get("phase") == "opposes":
                    groups[GROUPS[1]].append(ev)
            print(f"{tag}: evidence", file=sys.stderr, flush=True)
    return groups


def evidence_table(groups: dict[str, list[dict[str, float]]]) -> str:
    """The range of each piece of evidence in each group."""
    lines = ["| evidence | " + " | ".join(f"{g} ({len(r)})" for g, r in groups.items()) + " |",
             "|---|" + "---|" * len(groups)]  # fmt: skip
    first = next((r for r in groups.values() if r), [])
    for key in first[0] if first else ():
        cells = []
        for rows in groups.values():
            vals = [r[key] for r in rows if np.isfinite(r[key])]
            cells.append(f"{min(vals):.3g} – {max(vals):.3g}" if vals else "—")
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    counts = [f"{sum(r['positive'] >= 2 for r in rows)}/{len(rows)}" for rows in groups.values()]
    lines.append("| two or three clearly positive | " + " | ".join(counts) + " |")
    return "\n".join(lines)


# ----------------------------------------------------------------- tables


def _flag(r: dict[str, Any], key: str) -> bool:
    return str(r[key]) in ("True", "1")


def _pct(a: int, b: int) -> str:
    return f"{a}/{b} = {100 * a / b:.0f} %" if b else "—"


def summarize(rows: list[dict[str, Any]], truths: dict[str, dict[str, Any]]) -> str:
    lines = ["Truth of each regime, from the equations:", "",
             "| regime | truth | why |", "|---|---|---|"]  # fmt: skip
    for name, tr in truths.items():
        lines.append(f"| {name} | {tr['label']} | {tr['reason']} |")
    scored = [r for r in rows if _flag(r, "decidable") and r["truth"] in ("periodic", "chaotic")]
    labels = ["periodic", "chaotic", "quasi-periodic", "noise-like", "undetermined"]
    lines += ["", "Confusion of the decidable rows (per noise level and kind; 16 and 12 bits "
              "pooled):", "",
              "| truth | noise | kind | rows | " + " | ".join(labels) + " | right |",
              "|---|---|---|---|" + "---|" * (len(labels) + 1)]  # fmt: skip
    for truth_label in ("periodic", "chaotic"):
        for lev in sorted({int(r["noise_pct"]) for r in scored if r["noise_pct"] != ""}):
            for kind in ("none", "white", "ar1"):
                sub = [r for r in scored if r["truth"] == truth_label and r["noise_kind"] == kind
                       and r["noise_pct"] != "" and int(r["noise_pct"]) == lev]  # fmt: skip
                if not sub:
                    continue
                c = Counter(r["label"] for r in sub)
                right = sum(_flag(r, "correct") for r in sub)
                lines.append(f"| {truth_label} | {lev} % | {kind} | {len(sub)} | "
                             + " | ".join(str(c.get(lab, 0)) for lab in labels)
                             + f" | {_pct(right, len(sub))} |")  # fmt: skip
    regular = [r for r in rows if r["truth"] == "periodic"]
    wrong_chaos = [r for r in regular if _flag(r, "called_chaotic")]
    upto10 = [r for r in scored if r["noise_pct"] == "" or int(r["noise_pct"]) <= 10]
    at20 = [r for r in scored if str(r["noise_pct"]) == "20"]
    lines += ["", "Targets:", "",
              f"* regular series called chaotic: {len(wrong_chaos)} of {len(regular)}",
              f"* decidable series right up to 10 % noise: "
              f"{_pct(sum(_flag(r, 'correct') for r in upto10), len(upto10))}",
              f"* decidable series right at 20 %: "
              f"{_pct(sum(_flag(r, 'correct') for r in at20), len(at20))}"]  # fmt: skip
    lines += ["", "Calibration (decidable rows with a decided label):", "",
              "| confidence | verdicts | right |", "|---|---|---|"]  # fmt: skip
    for lo, hi in ((0.9, 1.01), (0.75, 0.9), (0.5, 0.75), (0.0, 0.5)):
        sub = [r for r in scored if r["label"] != "undetermined" and r["confidence"] != ""
               and lo <= float(r["confidence"]) < hi]  # fmt: skip
        lines.append(f"| {lo:.2f}–{min(hi, 1.0):.2f} | {len(sub)} | "
                     f"{_pct(sum(_flag(r, 'correct') for r in sub), len(sub))} |")  # fmt: skip
    lines += ["", "By observable (decidable rows, all noise levels):", "",
              "| regime | observable | chaotic part | rows | right | labels |",
              "|---|---|---|---|---|---|"]  # fmt: skip
    for reg in dict.fromkeys(r["regime"] for r in rows):
        for obs in dict.fromkeys(r["observable"] for r in rows if r["regime"] == reg):
            allr = [r for r in rows if r["regime"] == reg and r["observable"] == obs]
            sub = [r for r in allr if _flag(r, "decidable")]
            c = Counter(r["label"] for r in allr)
            lines.append(f"| {reg} | {obs} | {allr[0]['chaotic_part']} | "
                         f"{len(sub)} of {len(allr)} | "
                         f"{_pct(sum(_flag(r, 'correct') for r in sub), len(sub))} | "
                         + ", ".join(f"{k} {n}" for k, n in c.most_common()) + " |")  # fmt: skip
    cpu = sum(float(r["cpu_s"]) for r in rows)
    lines += ["", f"classify CPU time: {cpu:.0f} s over {len(rows)} series."]
    return "\n".join(lines)


def figure(rows: list[dict[str, Any]], path: Path) -> None:
    """Right-rate of each estimator and of the verdict against the noise level."""
    scored = [r for r in rows if _flag(r, "decidable") and r["noise_pct"] != ""
              and r["truth"] in ("periodic", "chaotic")]  # fmt: skip
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax, truth_label in zip(axes, ("periodic", "chaotic"), strict=True):
        sub = [r for r in scored if r["truth"] == truth_label]
        levels = sorted({int(r["noise_pct"]) for r in sub})
        want = "regular" if truth_label == "periodic" else "chaotic"
        for est in (*ESTIMATORS, "verdict"):
            rate = []
            for lev in levels:
                at = [r for r in sub if int(r["noise_pct"]) == lev]
                if est == "verdict":
                    ok = sum(_flag(r, "correct") for r in at)
                elif est == "surrogates":
                    ok = sum(r["est_surrogates"] == "deterministic" for r in at)
                else:
                    ok = sum(r[f"est_{est}"] == want for r in at)
                rate.append(ok / len(at) if at else np.nan)
            style = dict(lw=3, color="k") if est == "verdict" else dict(lw=1.3, marker="o", ms=3)
            ax.plot(levels, rate, label=est, **style)
        ax.set_title(f"{truth_label} regimes ({len(sub)} series)")
        ax.set_xlabel("measurement noise, % of the standard deviation")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction right")
    axes[1].legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".png", delete=False) as fh:
        tmp = fh.name
    fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    os.replace(tmp, path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT, help="CSV written (atomically)")
    parser.add_argument("--cache", type=Path, default=CACHE, help="where series are kept")
    parser.add_argument("--only", help="run only the regimes whose name contains this")
    parser.add_argument("--extra", action="store_true", help="also the EXTRA regimes")
    parser.add_argument("--truth-only", action="store_true", help="decide the truths only")
    parser.add_argument("--summarize", type=Path, help="only print the tables of a CSV")
    parser.add_argument("--evidence", action="store_true",
                        help="only print the evidence of the rows called periodic from a "
                        "tight cluster (classifies again; minutes)")  # fmt: skip
    args = parser.parse_args(argv)
    every = REGIMES + (EXTRA if args.extra else ())
    regimes = [r for r in every if not args.only or args.only in r.name]
    truths = {}
    for regime in regimes:
        truths[regime.name] = truth(regime, args.cache)
        print(f"truth {regime.name}: {truths[regime.name]}", file=sys.stderr, flush=True)
    if args.truth_only:
        return 0
    if args.evidence:
        print(evidence_table(evidence_rows(regimes, args.cache, truths)))
        return 0
    if args.summarize is not None:
        with open(args.summarize, encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
        print(summarize(rows, truths))
        figure(rows, FIGURE)
        return 0
    t0 = time.process_time()
    rows: list[dict[str, Any]] = []
    for regime in regimes:
        rows += run_regime(regime, args.cache, truths[regime.name])
    rows += shipped_rows()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=args.out.parent, suffix=".csv", delete=False,
                                     newline="", encoding="utf-8") as fh:  # fmt: skip
        writer = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(fh.name, args.out)
    strings = [{k: str(v) for k, v in r.items()} for r in rows]
    print(summarize(strings, truths))
    figure(strings, FIGURE)
    print(f"\nCPU {time.process_time() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
