"""Chaotic series with published largest Lyapunov exponents, for the corpus benchmarks.

Two sources, both importable without running anything:

* :func:`dysts_flow` — a chaotic flow of the ``dysts`` package (``pip install
  chaoskit[bench]``), integrated here from its right-hand side with SciPy's DOP853
  (rtol 1e-9, atol 1e-9) after a transient, sampled ``pts_per_period`` times per
  characteristic period (dysts' ``period``), and returned with dysts' published exponent
  ``maximum_lyapunov_estimated``. dysts' own ``make_trajectory`` (Radau at 1e-12) needs
  minutes per series here; an explicit high-order method at 1e-9 gives the same attractor.
  A flow "integrates cleanly" when the solver succeeds, every sample is finite and bounded,
  and the first coordinate still varies in the second half (no decay to a fixed point).
* :func:`maps` — five chaotic maps with exponents from the literature, each checked
  against the tangent-map (Jacobian-product) exponent of a long orbit in
  :func:`map_exponent`.

Series are cached as ``.npy`` files (atomic writes) in ``cache_dir`` so that reruns skip the
integration.
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

DEFAULT_CACHE = Path(tempfile.gettempdir()) / "chaoskit-corpus"
TRANSIENT_PERIODS = 20
RTOL = 1e-9
ATOL = 1e-9
BLOW_UP = 1e8


@dataclass(frozen=True)
class Series:
    """One scalar test series with its reference exponent (per unit of ``dt``)."""

    name: str
    kind: str  # "flow" or "map"
    x: np.ndarray
    dt: float
    mle: float
    periods: float  # characteristic periods (flows) or iterations (maps) covered


class IntegrationFailed(RuntimeError):
    """The flow did not integrate cleanly (solver failure, blow-up or decay)."""


def dysts_flow_names() -> list[str]:
    """Names of dysts' continuous systems with a positive published largest exponent."""
    import dysts.flows as flows
    from dysts.systems import get_attractor_list

    out = []
    for name in get_attractor_list("continuous"):
        lam = getattr(flows, name)().maximum_lyapunov_estimated
        if lam is not None and lam > 0:
            out.append(name)
    return out


def _atomic_save(path: Path, arr: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".npy")
    os.close(fd)
    np.save(tmp, arr)
    os.replace(tmp, path)


def _safe(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)


def dysts_states(
    name: str, n: int, *, pts_per_period: int, max_seconds: float = 60.0
) -> tuple[np.ndarray, float, float]:
    """Every coordinate of dysts flow ``name``: an ``(n, d)`` array at ``pts_per_period``
    samples per period, its sampling interval and dysts' published exponent.

    Raises :class:`IntegrationFailed` when the flow does not integrate cleanly, including
    when the integration takes longer than ``max_seconds`` of wall time (stiff systems).
    """
    import dysts.flows as flows
    from scipy.integrate import solve_ivp

    model = getattr(flows, name)()
    period = float(model.period)
    dt = period / pts_per_period
    lam = float(model.maximum_lyapunov_estimated)
    ic = np.asarray(model.ic, dtype=np.float64).ravel()
    t0 = TRANSIENT_PERIODS * period
    t_eval = t0 + dt * np.arange(n)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        return np.asarray(model.rhs(y, t), dtype=np.float64)

    deadline = time.monotonic() + max_seconds

    def escape(t: float, y: np.ndarray) -> float:
        if time.monotonic() > deadline:
            return -1.0
        return BLOW_UP - float(np.max(np.abs(y)))

    escape.terminal = True  # type: ignore[attr-defined]
    with np.errstate(all="ignore"):
        try:
            sol = solve_ivp(
                rhs,
                (0.0, t_eval[-1]),
                ic,
                method="DOP853",
                t_eval=t_eval,
                rtol=RTOL,
                atol=ATOL,
                events=escape,
            )
        except Exception as exc:  # the right-hand side itself failed
            raise IntegrationFailed(f"{name}: {type(exc).__name__}: {exc}") from None
    if sol.status != 0 or sol.y.shape[1] != n:
        why = "too stiff (wall-time limit)" if time.monotonic() > deadline else sol.message
        raise IntegrationFailed(f"{name}: solver stopped ({why})")
    states = np.ascontiguousarray(sol.y.T, dtype=np.float64)
    if not np.isfinite(states).all():
        raise IntegrationFailed(f"{name}: non-finite samples")
    half = states[n // 2 :, 0]
    if not half.std() > 1e-6 * (np.abs(half).max() + 1e-300):
        raise IntegrationFailed(f"{name}: decays to a fixed point")
    return states, dt, lam


def dysts_flow(
    name: str,
    n: int,
    *,
    pts_per_period: int,
    cache_dir: Path | None = DEFAULT_CACHE,
    max_seconds: float = 60.0,
) -> Series:
    """First coordinate of dysts flow ``name``: ``n`` samples, ``pts_per_period`` per period
    (:func:`dysts_states`), cached."""
    import dysts.flows as flows

    model = getattr(flows, name)()
    dt = float(model.period) / pts_per_period
    lam = float(model.maximum_lyapunov_estimated)
    path = None
    if cache_dir is not None:
        path = Path(cache_dir) / f"{_safe(name)}-{n}-{pts_per_period}.npy"
        if path.exists():
            return Series(name, "flow", np.load(path), dt, lam, n / pts_per_period)
    states, dt, lam = dysts_states(name, n, pts_per_period=pts_per_period, max_seconds=max_seconds)
    x = np.ascontiguousarray(states[:, 0])
    if path is not None:
        _atomic_save(path, x)
    return Series(name, "flow", x, dt, lam, n / pts_per_period)


def tangent_exponent(
    name: str,
    *,
    periods: int = 200,
    cache_dir: Path | None = DEFAULT_CACHE,
    max_seconds: float = 120.0,
) -> float:
    """Largest exponent of dysts flow ``name`` from its variational equation (Benettin).

    The tangent vector ``v`` follows ``v' = J(x) v`` with the Jacobian–vector product taken
    by central differences of dysts' right-hand side (step 1e-6 (1 + ‖x‖), so every flow
    works, with or without an analytic Jacobian); it is renormalised once per period and the
    exponent is the mean log growth over ``periods`` periods after the transient used by
    :func:`dysts_flow` — the span of the N = 20,000 series, i.e. the finite-time exponent
    no estimator can beat. NaN when the integration fails or exceeds ``max_seconds``.
    """
    import dysts.flows as flows
    from scipy.integrate import solve_ivp

    path = None
    if cache_dir is not None:
        path = Path(cache_dir) / f"{_safe(name)}-tangent-{periods}.npy"
        if path.exists():
            return float(np.load(path))
    model = getattr(flows, name)()
    period = float(model.period)
    y = np.asarray(model.ic, dtype=np.float64).ravel()
    dim = y.size
    deadline = time.monotonic() + max_seconds

    def f(t: float, x: np.ndarray) -> np.ndarray:
        return np.asarray(model.rhs(x, t), dtype=np.float64)

    def rhs(t: float, z: np.ndarray) -> np.ndarray:
        x, v = z[:dim], z[dim:]
        h = 1e-6 * (1.0 + float(np.linalg.norm(x)))
        return np.concatenate([f(t, x), (f(t, x + h * v) - f(t, x - h * v)) / (2.0 * h)])

    def stop(t: float, z: np.ndarray) -> float:
        return -1.0 if time.monotonic() > deadline else 1.0

    stop.terminal = True  # type: ignore[attr-defined]
    lam = float("nan")
    with np.errstate(all="ignore"):
        try:
            sol = solve_ivp(
                f,
                (0.0, TRANSIENT_PERIODS * period),
                y,
                method="DOP853",
                rtol=RTOL,
                atol=ATOL,
                events=stop,
            )
            ok = sol.status == 0
            z = np.concatenate([sol.y[:, -1], np.ones(dim) / np.sqrt(dim)])
            t, total = TRANSIENT_PERIODS * period, 0.0
            for _ in range(periods if ok else 0):
                sol = solve_ivp(
                    rhs, (t, t + period), z, method="DOP853", rtol=RTOL, atol=ATOL, events=stop
                )
                if sol.status != 0:
                    ok = False
                    break
                z, t = sol.y[:, -1].copy(), t + period
                norm = float(np.linalg.norm(z[dim:]))
                if not (np.isfinite(norm) and norm > 0):
                    ok = False
                    break
                total += np.log(norm)
                z[dim:] /= norm
            if ok:
                lam = total / (periods * period)
        except Exception:
            lam = float("nan")
    if path is not None:
        _atomic_save(path, np.asarray(lam))
    return lam


# -- maps: (name, published exponent, source) ------------------------------------------------
MAP_REFERENCES = {
    "logistic": (float(np.log(2.0)), "r = 4: ln 2 (exact)"),
    "henon": (0.41922, "a = 1.4, b = 0.3: Sprott, Chaos and Time-Series Analysis (2003)"),
    "lozi": (0.47023, "a = 1.7, b = 0.5: Sprott (2003)"),
    "ikeda": (0.50754, "u = 0.9: Sprott (2003)"),
    "tent": (float(np.log(1.99)), "slope 1.99: ln 1.99 (exact)"),
}


def _iterate(name: str, n: int, discard: int = 1000) -> np.ndarray:
    """``n`` states (rows) of map ``name`` after ``discard`` iterations."""
    total = n + discard
    out = np.empty((total, 2))
    if name == "logistic":
        s = np.array([0.4, 0.0])
    elif name == "tent":
        s = np.array([0.3141, 0.0])
    else:
        s = np.array([0.1, 0.1])
    for i in range(total):
        x, y = s
        if name == "logistic":
            s = np.array([4.0 * x * (1.0 - x), 0.0])
        elif name == "tent":
            s = np.array([1.99 * min(x, 1.0 - x), 0.0])
        elif name == "henon":
            s = np.array([1.0 - 1.4 * x * x + y, 0.3 * x])
        elif name == "lozi":
            s = np.array([1.0 - 1.7 * abs(x) + y, 0.5 * x])
        else:  # ikeda
            t = 0.4 - 6.0 / (1.0 + x * x + y * y)
            s = np.array(
                [1.0 + 0.9 * (x * np.cos(t) - y * np.sin(t)), 0.9 * (x * np.sin(t) + y * np.cos(t))]
            )
        out[i] = s
    return out[discard:]


def _jacobian(name: str, x: float, y: float) -> np.ndarray:
    if name == "logistic":
        return np.array([[4.0 - 8.0 * x, 0.0], [0.0, 0.0]])
    if name == "tent":
        return np.array([[1.99 if x < 0.5 else -1.99, 0.0], [0.0, 0.0]])
    if name == "henon":
        return np.array([[-2.8 * x, 1.0], [0.3, 0.0]])
    if name == "lozi":
        return np.array([[-1.7 * np.sign(x), 1.0], [0.5, 0.0]])
    r2 = 1.0 + x * x + y * y
    t = 0.4 - 6.0 / r2
    dt_dx, dt_dy = 12.0 * x / r2**2, 12.0 * y / r2**2
    c, s = np.cos(t), np.sin(t)
    gx = -x * s - y * c  # d(x cos t − y sin t)/dt
    gy = x * c - y * s  # d(x sin t + y cos t)/dt
    return 0.9 * np.array([[c + gx * dt_dx, -s + gx * dt_dy], [s + gy * dt_dx, c + gy * dt_dy]])


def map_exponent(name: str, n: int = 200_000) -> float:
    """Largest exponent of map ``name`` from the tangent map along an ``n``-step orbit."""
    states = _iterate(name, n)
    v = np.array([1.0, 0.3])
    total = 0.0
    for x, y in states:
        v = _jacobian(name, x, y) @ v
        norm = float(np.hypot(v[0], v[1]))
        total += np.log(norm)
        v /= norm
    return total / n


def maps(n: int) -> list[Series]:
    """First coordinate of every map in :data:`MAP_REFERENCES`, ``n`` iterations each."""
    return [
        Series(name, "map", np.ascontiguousarray(_iterate(name, n)[:, 0]), 1.0, lam, float(n))
        for name, (lam, _) in MAP_REFERENCES.items()
    ]
