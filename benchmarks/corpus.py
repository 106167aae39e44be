"""A labelled corpus of time series for the verdict: every label known from the equations.

Each :class:`Case` names a generator and its parameters, so cases are cheap to list and
build in worker processes. The label of a periodic window is not assumed: it is the
period of the generating state's recurrence (``true_period``), found from a clean run of
the equations. Everything except the ``dysts`` flows is generated here with numpy and
scipy, so the tests can build a stratified slice without the optional dependency.

Families
--------
``window``       periodic windows of the logistic and Hénon maps, the forced Duffing
                 oscillator, the driven damped pendulum and van der Pol's oscillator
``chaos``        chaotic maps and flows with known positive exponents
``dysts``        every chaotic flow of the ``dysts`` package (``bench`` extra)
``torus``        two- and three-frequency quasi-periodic signals, clean and with 1 % noise
``noise``        white, AR(1) (φ = 0.5, 0.9, 0.99), 1/f, and a random walk's increments
``noisy``        periodic and chaotic signals at 40, 20 and 10 dB SNR

A case is *decidable* unless it is a chaotic signal at 10 dB SNR: noise with a tenth of
the signal's variance hides the exponential divergence the exponents measure (Kantz &
Schreiber 2004, §6.2), so neither label nor "regular" can be earned there.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from chaoskit import systems

LENGTHS = (2000, 20000)
SNRS_DB = (40.0, 20.0, 10.0)


@dataclass(frozen=True)
class Case:
    """One labelled series: ``make()`` builds it, ``classify_kwargs`` say how to read it."""

    name: str
    family: str
    label: str  # periodic | quasi-periodic | chaotic | noise-like
    n: int
    builder: str
    params: dict[str, Any] = field(default_factory=dict)
    classify_kwargs: dict[str, Any] = field(default_factory=dict)
    period: int | None = None
    decidable: bool = True

    def make(self) -> np.ndarray:
        return np.ascontiguousarray(BUILDERS[self.builder](self.n, **self.params), dtype=float)

    @property
    def key(self) -> str:
        return f"{self.name} N={self.n}"

    def seed(self) -> int:
        return int(hashlib.sha256(self.key.encode()).hexdigest()[:8], 16)


# ----------------------------------------------------------------- generators


def _noise_like(x: np.ndarray, snr_db: float | None, seed: int) -> np.ndarray:
    if snr_db is None:
        return x
    g = np.random.default_rng(seed)
    return x + float(np.std(x)) * 10 ** (-snr_db / 20) * g.standard_normal(x.size)


def logistic(n: int, *, r: float, snr_db: float | None = None, seed: int = 0) -> np.ndarray:
    return _noise_like(systems.logistic(n, r=r, discard=5000), snr_db, seed)


def henon(n: int, *, a: float, b: float = 0.3, snr_db: float | None = None, seed: int = 0):
    x, y = 0.1, 0.1
    for _ in range(5000):
        x, y = 1 - a * x * x + y, b * x
    out = np.empty(n)
    for i in range(n):
        x, y = 1 - a * x * x + y, b * x
        out[i] = x
    return _noise_like(out, snr_db, seed)


def duffing(n: int, *, gamma: float, spp: int = 50, snr_db: float | None = None, seed: int = 0):
    _, state = systems.duffing(n, gamma=gamma, samples_per_period=spp, discard_periods=300)
    return _noise_like(state[:, 0], snr_db, seed)


def _pendulum_state(n: int, g: float, spp: int, q: float = 2.0, wd: float = 2.0 / 3.0):
    """Driven damped pendulum θ'' + θ'/q + sin θ = g cos ωd t (Baker & Gollub 1996)."""
    period = 2 * np.pi / wd
    t_skip = 300 * period
    t = t_skip + np.arange(n) * period / spp

    def rhs(time: float, s: np.ndarray) -> list[float]:
        return [s[1], -s[1] / q - math.sin(s[0]) + g * math.cos(wd * time)]

    sol = solve_ivp(rhs, (0.0, t[-1]), [0.2, 0.0], method="DOP853", t_eval=t,
                    rtol=1e-10, atol=1e-10)  # fmt: skip
    return sol.y.T


def pendulum(n: int, *, g: float, spp: int = 50, snr_db: float | None = None, seed: int = 0):
    # the angular velocity: bounded even when the pendulum turns over
    return _noise_like(_pendulum_state(n, g, spp)[:, 1], snr_db, seed)


def van_der_pol(n: int, *, mu: float, dt: float, snr_db: float | None = None, seed: int = 0):
    return _noise_like(systems.van_der_pol(n, dt=dt, mu=mu)[:, 0], snr_db, seed)


def lorenz(n: int, *, dt: float = 0.03, snr_db: float | None = None, seed: int = 0):
    return _noise_like(systems.lorenz(n, dt=dt)[:, 0], snr_db, seed)


def rossler(n: int, *, dt: float = 0.2, snr_db: float | None = None, seed: int = 0):
    return _noise_like(systems.rossler(n, dt=dt)[:, 0], snr_db, seed)


def torus(
    n: int, *, dt: float, form: str, snr_db: float | None = None, seed: int = 0
) -> np.ndarray:
    t = np.arange(n) * dt
    if form == "two sines":  # golden-mean frequency ratio
        x = np.sin(2 * np.pi * t) + 0.6 * np.sin(np.pi * (np.sqrt(5) - 1) * t)
    elif form == "two-torus in R3":  # (R + r cos θ2) cos θ1: lines at f1 and f1 ± f2
        x = (2.0 + np.cos(np.sqrt(2) * t)) * np.cos(t)
    elif form == "three sines":
        x = np.sin(t) + 0.6 * np.sin(np.sqrt(2) * t) + 0.3 * np.sin(np.sqrt(5) * t)
    elif form == "three-torus product":
        x = (2.0 + np.cos(np.sqrt(3) * t)) * (1.5 + np.cos(np.sqrt(7) / 2 * t)) * np.cos(t)
    else:
        raise ValueError(f"unknown torus form {form!r}")
    return _noise_like(x, snr_db, seed)


def noise(n: int, *, kind: str, seed: int = 0) -> np.ndarray:
    g = np.random.default_rng(seed)
    if kind == "white":
        return g.standard_normal(n)
    if kind.startswith("ar1"):
        phi = float(kind.split("=")[1])
        e = g.standard_normal(n + 2000)
        x = np.empty_like(e)
        x[0] = e[0]
        for i in range(1, e.size):
            x[i] = phi * x[i - 1] + e[i]
        return x[2000:]
    if kind == "1/f":  # spectral synthesis: |X(f)|² ∝ 1/f, random phases
        f = np.fft.rfftfreq(n)
        amp = np.zeros_like(f)
        amp[1:] = f[1:] ** -0.5
        spec = amp * np.exp(2j * np.pi * g.random(f.size)) * g.standard_normal(f.size)
        return np.fft.irfft(spec, n=n)
    if kind == "random-walk increments":  # ±1 steps of a simple random walk
        return np.diff(np.cumsum(g.choice([-1.0, 1.0], size=n + 1)))
    raise ValueError(f"unknown noise kind {kind!r}")


def dysts_flow(n: int, *, system: str, pts_per_period: int) -> np.ndarray:
    """First coordinate of a ``dysts`` flow (Gilpin 2021), ``n`` samples at
    ``pts_per_period`` per characteristic period, from the package's initial condition."""
    import warnings

    import dysts.flows

    model = getattr(dysts.flows, system)()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # dysts passes a Jacobian DOP853 does not use
        traj = model.make_trajectory(
            n,
            pts_per_period=pts_per_period,
            resample=True,
            method="DOP853",
            rtol=1e-9,
            atol=1e-9,
        )
    if traj is None:
        raise ValueError(f"{system} did not integrate")
    return np.asarray(traj)[:, 0]


def dysts_long(n: int, *, system: str, pts_per_period: int) -> np.ndarray:
    """The same flow from the estimator corpus's integration (:mod:`corpus_flows`: dysts'
    right-hand side, DOP853 at 1e-9 after 20 periods, ``pts_per_period`` per dysts period),
    which shares its cache: dysts' own ``make_trajectory`` needs minutes per long series."""
    from benchmarks import corpus_flows

    return corpus_flows.dysts_flow(system, n, pts_per_period=pts_per_period).x


BUILDERS = {
    "logistic": logistic,
    "henon": henon,
    "duffing": duffing,
    "pendulum": pendulum,
    "van_der_pol": van_der_pol,
    "lorenz": lorenz,
    "rossler": rossler,
    "torus": torus,
    "noise": noise,
    "dysts": dysts_flow,
    "dysts_long": dysts_long,
}


# ----------------------------------------------------------------- ground truth


def map_period(
    x: np.ndarray, max_period: int = 64, tol: float = 1e-7, scale: float | None = None
) -> int | None:
    """Smallest k with |x[n+k] − x[n]| ≤ tol · scale (default: the spread), or None."""
    scale = max(float(np.ptp(x)) if scale is None else scale, 1e-300)
    for k in range(1, max_period + 1):
        if np.max(np.abs(x[k:] - x[:-k])) <= tol * scale:
            return k
    return None


def strobe_period(state: np.ndarray, spp: int, max_period: int = 64) -> int | None:
    """Smallest k for which the full state recurs after k drive periods (stroboscopic)."""
    strobe = state[::spp]
    scale = float(np.ptp(state[:, 0]))
    return map_period(strobe[:, 0], max_period, tol=1e-6, scale=scale)


def true_period(builder: str, params: dict[str, Any]) -> int | None:
    """The period of the generating state on a clean run of 20 000 samples (drive periods
    for forced systems, iterations for maps, maxima per period for van der Pol)."""
    clean = {k: v for k, v in params.items() if k not in ("snr_db", "seed")}
    if builder in ("logistic", "henon"):
        return map_period(BUILDERS[builder](20000, **clean))
    if builder == "duffing":
        spp = clean.get("spp", 50)
        _, st = systems.duffing(200 * spp, gamma=clean["gamma"], samples_per_period=spp,
                                discard_periods=300)  # fmt: skip
        return strobe_period(st, spp)
    if builder == "pendulum":
        spp = clean.get("spp", 50)
        st = _pendulum_state(200 * spp, clean["g"], spp)
        return strobe_period(np.column_stack([st[:, 1], np.cos(st[:, 0])]), spp)
    if builder == "van_der_pol":
        return 1  # a limit cycle with one maximum of x per period
    return None


# ----------------------------------------------------------------- the corpus

DUFFING_KW = {"drive_period": 2 * np.pi / 1.2, "dt": 2 * np.pi / 1.2 / 50}
PENDULUM_KW = {"drive_period": 3 * np.pi, "dt": 3 * np.pi / 50}
LOGISTIC_R = (3.2, 3.5, 3.55, 3.83, 3.74, 3.628)
HENON_A = (0.5, 0.95, 1.03, 1.25)
DUFFING_GAMMA = (0.2, 0.28, 0.29, 0.37, 0.65)
PENDULUM_G = (0.9, 1.07, 1.47, 1.35)
VDP = ((0.5, 0.2), (1.0, 0.2), (2.0, 0.2), (5.0, 0.3))
CHAOS = (
    ("logistic r=3.9", "logistic", {"r": 3.9}, {}),
    ("logistic r=4", "logistic", {"r": 4.0}, {}),
    ("henon a=1.4", "henon", {"a": 1.4}, {}),
    ("duffing gamma=0.5", "duffing", {"gamma": 0.5}, DUFFING_KW),
    ("pendulum g=1.5", "pendulum", {"g": 1.5}, PENDULUM_KW),
    ("lorenz", "lorenz", {"dt": 0.03}, {"dt": 0.03}),
    ("rossler", "rossler", {"dt": 0.2}, {"dt": 0.2}),
)
TORI = (("two sines", 0.05), ("two-torus in R3", 0.1), ("three sines", 0.1),
        ("three-torus product", 0.1))  # fmt: skip
NOISES = ("white", "ar1=0.5", "ar1=0.9", "ar1=0.99", "1/f", "random-walk increments")


def _forced(builder: str, params: dict[str, Any]) -> dict[str, Any]:
    if builder == "duffing":
        return dict(DUFFING_KW)
    if builder == "pendulum":
        return dict(PENDULUM_KW)
    if builder == "van_der_pol":
        return {"dt": params["dt"]}
    return {}


def windows(lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    """Periodic windows, each labelled with the period of its clean recurrence."""
    specs: list[tuple[str, str, dict[str, Any]]] = []
    specs += [(f"logistic r={r}", "logistic", {"r": r}) for r in LOGISTIC_R]
    specs += [(f"henon a={a}", "henon", {"a": a}) for a in HENON_A]
    specs += [(f"duffing gamma={g}", "duffing", {"gamma": g}) for g in DUFFING_GAMMA]
    specs += [(f"pendulum g={g}", "pendulum", {"g": g}) for g in PENDULUM_G]
    specs += [(f"van der Pol mu={m}", "van_der_pol", {"mu": m, "dt": dt}) for m, dt in VDP]
    cases = []
    for name, builder, params in specs:
        k = true_period(builder, params)
        if k is None or k > 8:
            continue  # not a periodic window after all: not in the corpus
        for n in lengths:
            cases.append(Case(name, "window", "periodic", n, builder, params,
                              _forced(builder, params), period=k))  # fmt: skip
    return cases


def chaos(lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    return [Case(name, "chaos", "chaotic", n, b, p, kw) for name, b, p, kw in CHAOS
            for n in lengths]  # fmt: skip


def tori(lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    cases = []
    for form, dt in TORI:
        for snr in (None, 40.0):
            tag = "" if snr is None else " + 1% noise"
            for n in lengths:
                cases.append(Case(f"torus {form}{tag}", "torus", "quasi-periodic", n, "torus",
                                  {"dt": dt, "form": form, "snr_db": snr}, {"dt": dt}))  # fmt: skip
    return cases


def noises(lengths: tuple[int, ...] = LENGTHS, seeds: tuple[int, ...] = (0, 1)) -> list[Case]:
    cases = []
    for kind in NOISES:
        for seed in seeds:
            kw = {} if seed % 2 == 0 else {"dt": 0.01}  # an array, and a sampled signal
            for n in lengths:
                cases.append(Case(f"{kind} seed={seed}", "noise", "noise-like", n, "noise",
                                  {"kind": kind, "seed": seed}, kw))  # fmt: skip
    return cases


NOISY_PERIODIC = (
    ("logistic r=3.5", "logistic", {"r": 3.5}, {}, 4),
    ("van der Pol mu=1", "van_der_pol", {"mu": 1.0, "dt": 0.2}, {"dt": 0.2}, 1),
    ("duffing gamma=0.28", "duffing", {"gamma": 0.28}, DUFFING_KW, 2),
)
NOISY_CHAOTIC = CHAOS[:1] + CHAOS[2:]


def noisy(lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    cases = []
    for snr in SNRS_DB:
        for name, b, p, kw, k in NOISY_PERIODIC:
            for n in lengths:
                cases.append(Case(f"{name} at {snr:g} dB", "noisy", "periodic", n, b,
                                  {**p, "snr_db": snr, "seed": 7}, kw, period=k))  # fmt: skip
        for name, b, p, kw in NOISY_CHAOTIC:
            for n in lengths:
                cases.append(Case(f"{name} at {snr:g} dB", "noisy", "chaotic", n, b,
                                  {**p, "snr_db": snr, "seed": 7}, kw,
                                  decidable=snr > 10.0))  # fmt: skip
    return cases


TANGENT_CSV = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "estimator-corpus.csv"
MIN_GROWTH = 0.1  # the verdict's resolution: λ₁T ≥ 0.1 nats per characteristic time


def dysts_growth() -> dict[str, float]:
    """λ₁T of each dysts flow from the equations: the tangent exponent of the estimator
    corpus (variational equations over 200 periods, ``estimator-corpus.csv``) times dysts'
    ``period``. Flows without a tangent reference are absent."""
    import csv

    import dysts.flows

    out: dict[str, float] = {}
    if not TANGENT_CSV.is_file():
        return out
    with open(TANGENT_CSV, encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            if row["kind"] == "flow" and row["method"] == "wolf" and row["n"] == "20000":
                if row["tangent"] not in ("", "nan"):
                    period = float(getattr(dysts.flows, row["name"])().period)
                    out[row["name"]] = float(row["tangent"]) * period
    return out


def dysts_cases(lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    """Every chaotic flow of ``dysts`` (first coordinate): 100 characteristic periods at
    N = 2000 (20 points per period, dysts' ``make_trajectory``), 200 at N = 20000 (100
    points per period, integrated as in the estimator corpus, :func:`dysts_long`)."""
    from dysts.systems import get_attractor_list

    growth = dysts_growth()
    cases = []
    for system in get_attractor_list():
        # dysts labels every flow chaotic from its own estimate; the equations say otherwise
        # for some (Torus: λ₁ = 0) and others separate by less than the verdict resolves
        decidable = growth.get(system, MIN_GROWTH) >= MIN_GROWTH
        for n in lengths:
            ppp, builder = (20, "dysts") if n <= 2000 else (100, "dysts_long")
            cases.append(Case(f"dysts {system}", "dysts", "chaotic", n, builder,
                              {"system": system, "pts_per_period": ppp}, {"dt": 1.0},
                              decidable=decidable))  # fmt: skip
    return cases


def corpus(*, with_dysts: bool = True, lengths: tuple[int, ...] = LENGTHS) -> list[Case]:
    """Every case (``with_dysts=False``: only those generated here)."""
    cases = windows(lengths) + chaos(lengths) + tori(lengths) + noises(lengths)
    cases += noisy(lengths)
    if with_dysts:
        cases += dysts_cases(lengths)
    return cases


def cache_path(case: Case, root: Path) -> Path:
    """Where a built series is kept between runs (name sanitised to a hash)."""
    digest = hashlib.sha256(repr((case.builder, sorted(case.params.items()), case.n)).encode())
    return root / f"{digest.hexdigest()[:20]}.npy"
