"""Reference dynamical systems with known largest Lyapunov exponents.

Used for examples, tests and benchmarks. Maps return one sample per iteration; flows are
integrated with a compiled classical Runge–Kutta scheme at ``dt / substeps`` and sampled every
``dt`` after a transient of ``discard`` samples.

========================  ===========================  =====================
system                    parameters                   λ1 (natural log)
========================  ===========================  =====================
logistic map              r = 4                        ln 2 per iteration
Hénon map                 a = 1.4, b = 0.3             0.419 per iteration
Lorenz                    σ = 10, ρ = 28, β = 8/3      0.9056 per time unit
Rössler                   a = b = 0.2, c = 5.7         0.0714 per time unit
========================  ===========================  =====================
"""

from __future__ import annotations

import numpy as np

from . import _systems_kernels as _k
from ._validate import check_int, check_positive

__all__ = [
    "duffing",
    "henon",
    "logistic",
    "lorenz",
    "rossler",
    "torus",
    "van_der_pol",
]


def logistic(n: int, *, r: float = 4.0, x0: float = 0.4, discard: int = 1000) -> np.ndarray:
    """Iterate x ← r x (1 − x) and return ``n`` values after ``discard`` transients."""
    n = check_int(n, name="n", minimum=1)
    return _k.logistic(n, float(r), float(x0), check_int(discard, name="discard", minimum=0))


def henon(
    n: int, *, a: float = 1.4, b: float = 0.3, x0: float = 0.1, y0: float = 0.1, discard: int = 1000
) -> np.ndarray:
    """Iterate the Hénon map; returns an ``(n, 2)`` array of (x, y)."""
    n = check_int(n, name="n", minimum=1)
    return _k.henon(n, float(a), float(b), float(x0), float(y0), int(discard))


def _flow(kind: int, p, s0, n, dt, discard, substeps, t0=0.0) -> np.ndarray:
    n = check_int(n, name="n", minimum=1)
    dt = check_positive(dt, name="dt")
    discard = check_int(discard, name="discard", minimum=0)
    substeps = check_int(substeps, name="substeps", minimum=1)
    out = _k.rk4_sample(
        kind, np.asarray(p, float), np.asarray(s0, float), t0, dt, substeps, n + discard
    )
    return out[discard:]


def lorenz(
    n: int,
    *,
    dt: float = 0.01,
    sigma: float = 10.0,
    rho: float = 28.0,
    beta: float = 8.0 / 3.0,
    initial=(1.0, 1.0, 1.0),
    discard: int = 5000,
    substeps: int = 10,
) -> np.ndarray:
    """Lorenz system sampled every ``dt``; returns an ``(n, 3)`` array of (x, y, z)."""
    return _flow(0, (sigma, rho, beta), initial, n, dt, discard, substeps)


def rossler(
    n: int,
    *,
    dt: float = 0.05,
    a: float = 0.2,
    b: float = 0.2,
    c: float = 5.7,
    initial=(1.0, 1.0, 0.0),
    discard: int = 5000,
    substeps: int = 10,
) -> np.ndarray:
    """Rössler system sampled every ``dt``; returns an ``(n, 3)`` array of (x, y, z)."""
    return _flow(1, (a, b, c), initial, n, dt, discard, substeps)


def duffing(
    n: int,
    *,
    gamma: float = 0.5,
    delta: float = 0.3,
    alpha: float = -1.0,
    beta: float = 1.0,
    omega: float = 1.2,
    samples_per_period: int = 100,
    initial=(1.0, 0.0),
    discard_periods: int = 100,
    substeps: int = 10,
) -> tuple[np.ndarray, np.ndarray]:
    """Forced Duffing oscillator x'' + δx' + αx + βx³ = γ cos ωt.

    Sampled ``samples_per_period`` times per forcing period after ``discard_periods`` periods.
    Returns ``(t, state)`` with ``state`` of shape ``(n, 2)`` (x, x').
    """
    spp = check_int(samples_per_period, name="samples_per_period", minimum=4)
    dt = 2.0 * np.pi / float(omega) / spp
    discard = check_int(discard_periods, name="discard_periods", minimum=0) * spp
    state = _flow(2, (delta, alpha, beta, gamma, omega), initial, n, dt, discard, substeps)
    t = (np.arange(n) + discard) * dt
    return t, state


def van_der_pol(
    n: int,
    *,
    dt: float = 0.05,
    mu: float = 1.0,
    initial=(2.0, 0.0),
    discard: int = 2000,
    substeps: int = 10,
) -> np.ndarray:
    """Van der Pol oscillator (a limit cycle); returns an ``(n, 2)`` array of (x, x')."""
    return _flow(3, (mu,), initial, n, dt, discard, substeps)


def torus(
    n: int,
    *,
    dt: float = 0.05,
    f1: float = 1.0,
    f2: float = (np.sqrt(5.0) - 1.0) / 2.0,
    amplitudes=(1.0, 0.6),
) -> np.ndarray:
    """Two-frequency quasi-periodic signal a1 sin 2πf1 t + a2 sin 2πf2 t (irrational ratio)."""
    n = check_int(n, name="n", minimum=1)
    t = np.arange(n) * check_positive(dt, name="dt")
    return amplitudes[0] * np.sin(2 * np.pi * f1 * t) + amplitudes[1] * np.sin(2 * np.pi * f2 * t)
