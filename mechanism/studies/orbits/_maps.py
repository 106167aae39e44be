"""Fixed points of a map given as a callable: Newton at fixed p and on a chord
(pseudo-arclength), the k-fold map by the chain rule, and the switch to the doubled
branch at a period doubling; :func:`continue_map` runs them on the engine of
``_continuation``."""

from __future__ import annotations

import math

import numpy as np

from chaoskit.contract import check_int

from ._continuation import (
    BifurcationPoint,
    ContinuationBranch,
    ContinuationPoint,
    ContinuationSettings,
    Follower,
    MapFunction,
    Solved,
)

__all__ = ["MapCorrector", "continue_map"]


class MapCorrector:
    """Newton on P(x, p) − x = 0 for a map given as a callable, at fixed p or on a chord
    (pseudo-arclength)."""

    def __init__(
        self,
        func: MapFunction,
        period: int,
        settings: ContinuationSettings,
        *,
        distinct_from: int = 0,
    ) -> None:
        self.func = func
        self.period = period
        self.settings = settings
        self.evaluations = 0
        # a doubled branch must not fall back onto the branch it came from: a point that
        # is also a fixed point of the ``distinct_from``-fold map is rejected
        self.distinct_from = distinct_from

    def _fallen_back(self, x: np.ndarray, p: float) -> bool:
        if not self.distinct_from:
            return False
        half = MapCorrector(self.func, self.distinct_from, self.settings)
        r, _, _ = half.evaluate(x, p)
        self.evaluations += half.evaluations
        return bool(np.max(np.abs(r)) <= 1e-6 * (1.0 + np.max(np.abs(x))))

    def evaluate(self, x: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(P^k(x) − x, ∂P^k/∂x, ∂P^k/∂p) of the k-fold map (chain rule)."""
        y = np.asarray(x, dtype=np.float64)
        n = y.size
        jac = np.eye(n)
        dp = np.zeros(n)
        for _ in range(self.period):
            r, j, pp = self.func(y, p)
            self.evaluations += 1
            r = np.asarray(r, dtype=np.float64).reshape(n)
            j = np.asarray(j, dtype=np.float64).reshape(n, n)
            if pp is None:
                h = 1e-7 * max(1.0, abs(p))
                r2, _, _ = self.func(y, p + h)
                self.evaluations += 1
                pp = (np.asarray(r2, dtype=np.float64).reshape(n) - r) / h
            pp = np.asarray(pp, dtype=np.float64).reshape(n)
            dp = j @ dp + pp
            jac = j @ jac
            y = y + r
        return y - np.asarray(x, dtype=np.float64), jac, dp

    def _point(self, x: np.ndarray, p: float, it: int) -> Solved | None:
        r, jac, dp = self.evaluate(x, p)
        if not np.all(np.isfinite(jac)) or self._fallen_back(x, p):
            return None
        mu = np.linalg.eigvals(jac)
        mu = mu[np.argsort(-np.abs(mu), kind="stable")]
        tangent = _null_tangent(jac, dp)
        return Solved(
            point=ContinuationPoint(
                parameter=float(p), state=np.asarray(x, dtype=np.float64).copy(),
                multipliers=mu.astype(np.complex128), stable=bool(np.all(np.abs(mu) < 1.0)),
                residual=float(np.max(np.abs(r))) if r.size else 0.0,
            ),
            iterations=it, jacobian=jac, tangent=tangent,
        )  # fmt: skip

    def at(self, parameter: float, guess: Solved) -> Solved | None:
        x = np.asarray(guess.point.state, dtype=np.float64).copy()
        tol = self.settings.newton_tolerance
        for it in range(self.settings.max_iterations + 1):
            r, jac, _ = self.evaluate(x, parameter)
            if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
                return None
            if np.max(np.abs(r)) <= tol * (1.0 + np.max(np.abs(x))):
                return self._point(x, parameter, it)
            try:
                dx = np.linalg.solve(jac - np.eye(x.size), -r)
            except np.linalg.LinAlgError:
                return None
            x = x + dx
        return None

    def chord(self, y_pred: np.ndarray, t: np.ndarray, start: Solved) -> Solved | None:
        """Newton on [P(x, p) − x; t·(y − y_pred)] = 0 (pseudo-arclength)."""
        y = np.asarray(y_pred, dtype=np.float64).copy()
        n = y.size - 1
        tol = self.settings.newton_tolerance
        for it in range(self.settings.max_iterations + 1):
            r, jac, dp = self.evaluate(y[:n], float(y[n]))
            if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
                return None
            g = np.append(r, float(t @ (y - y_pred)))
            if np.max(np.abs(g)) <= tol * (1.0 + np.max(np.abs(y))):
                return self._point(y[:n], float(y[n]), it)
            a = np.zeros((n + 1, n + 1))
            a[:n, :n] = jac - np.eye(n)
            a[:n, n] = dp
            a[n] = t
            try:
                y = y - np.linalg.solve(a, g)
            except np.linalg.LinAlgError:
                return None
        return None


def _null_tangent(jac: np.ndarray, dp: np.ndarray) -> np.ndarray:
    """Unit null vector of [∂P/∂x − I, ∂P/∂p] (the branch's tangent in (x, p))."""
    n = jac.shape[0]
    a = np.hstack([jac - np.eye(n), dp[:, None]])
    _, _, vt = np.linalg.svd(a)
    return vt[-1]


def _critical_vector(jac: np.ndarray) -> np.ndarray:
    """Real eigenvector of ∂P/∂x for the multiplier nearest −1 (unit length)."""
    values, vectors = np.linalg.eig(jac)
    v = np.real(vectors[:, int(np.argmin(np.abs(values + 1.0)))])
    return v / max(float(np.linalg.norm(v)), 1e-300)


def continue_map(
    func: MapFunction,
    x0: np.ndarray,
    span: tuple[float, float],
    *,
    period: int = 1,
    settings: ContinuationSettings | None = None,
) -> tuple[tuple[ContinuationBranch, ...], tuple[BifurcationPoint, ...]]:
    """Follow fixed points of x ↦ P(x, p) over a parameter span and locate bifurcations.

    Natural-parameter continuation (secant predictor; the step halves when Newton fails
    and grows after an easy point), then pseudo-arclength where Newton at fixed p fails
    below the smallest step (around a fold). Between consecutive points the sign
    changes of ∏(μ+1), ∏(μ−1) and ∏_{i<j}(μ_i μ_j − 1) over the multipliers μ (the
    eigenvalues of ∂P/∂x) mark a period doubling, a fold and a Neimark–Sacker
    bifurcation; each is bisected down to ``settings.locate_tolerance``. At a period
    doubling the branch of twice the period is started from x* ± ε v (v the critical
    eigenvector) on the 2-fold map just past the bifurcation and followed too, up to
    ``settings.max_period``.

    Parameters
    ----------
    func : callable
        ``func(x, p)`` returning (P(x, p) − x, ∂P/∂x, ∂P/∂p), the last may be ``None``
        (then a forward difference of the residual in p).
    x0 : numpy.ndarray
        A guess of a fixed point of the ``period``-fold map at ``span[0]``.
    span : tuple of float
        (start, stop) of the parameter.
    period : int
        Map iterations per point of the first branch (≥ 1).
    settings : ContinuationSettings, optional
        Steps, tolerances and branch switching (defaults: :class:`mechanism.ContinuationSettings`).

    Returns
    -------
    tuple
        (branches, bifurcations): the branches followed (the first from ``x0``) and the
        located points, in the order found.

    Raises
    ------
    ValueError
        On a bad span or period, or when Newton does not converge from ``x0``.
    """
    settings = ContinuationSettings() if settings is None else settings
    period = check_int(period, name="period", minimum=1)
    start, stop = (float(v) for v in span)
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise ValueError(f"span must be two different finite values; got {span!r}.")
    x0 = np.atleast_1d(np.asarray(x0, dtype=np.float64))
    corrector = MapCorrector(func, period, settings)
    seed = Solved(
        point=ContinuationPoint(parameter=start, state=x0, multipliers=np.zeros(0, complex),
                                stable=False, residual=math.inf),
        iterations=0,
    )  # fmt: skip
    first = corrector.at(start, seed)
    if first is None:
        raise ValueError(
            f"x0 is not close enough to a fixed point of the {period}-fold map at p = {start:g}: "
            "Newton did not converge."
        )
    branches: list[ContinuationBranch] = []
    found: list[BifurcationPoint] = []
    queue: list[tuple[Solved, int, str, MapCorrector]] = [(first, period, "start", corrector)]
    while queue:
        seed_point, k, origin, corr = queue.pop(0)
        follower = Follower(corr, settings, chord=corr.chord)
        branch, located, _ = follower.follow(
            seed_point, stop, period=k, branch=len(branches), origin=origin
        )
        branches.append(branch)
        found.extend(located)
        if not settings.switch_branches or 2 * k > settings.max_period:
            continue
        for bif in located:
            if bif.kind != "period-doubling":
                continue
            switched = _switch_period_doubling(func, corr, bif, stop, settings)
            if switched is not None:
                queue.append(
                    (switched[0], 2 * k, f"period doubling at {bif.parameter:.10g}", switched[1])
                )
    return tuple(branches), tuple(found)


def _switch_period_doubling(
    func: MapFunction,
    corr: MapCorrector,
    bif: BifurcationPoint,
    stop: float,
    settings: ContinuationSettings,
) -> tuple[Solved, MapCorrector] | None:
    """A point of the doubled branch just past a period doubling, from x* ± ε v."""
    base = corr.at(bif.parameter, _seed_state(bif.state, bif.parameter))
    if base is None or base.jacobian is None:
        return None
    v = _critical_vector(base.jacobian)
    doubled = MapCorrector(func, 2 * corr.period, settings, distinct_from=corr.period)
    direction = 1.0 if stop >= bif.parameter else -1.0
    # one step past the bifurcation: the doubled orbit is then ~√step away from x*
    delta = settings.step
    x_star = base.point.state
    eps0 = settings.switch_offset or math.sqrt(delta) * (1.0 + float(np.max(np.abs(x_star))))
    for side in (direction, -direction):
        p = bif.parameter + side * delta
        for eps in (eps0, 0.1 * eps0, 10.0 * eps0):
            for sign in (1.0, -1.0):
                guess = _seed_state(x_star + sign * eps * v, p)
                got = doubled.at(p, guess)
                if got is not None:
                    return got, doubled
    return None


def _seed_state(x: np.ndarray, p: float) -> Solved:
    return Solved(
        point=ContinuationPoint(parameter=float(p), state=np.asarray(x, dtype=np.float64),
                                multipliers=np.zeros(0, complex), stable=False,
                                residual=math.inf),
        iterations=0,
    )  # fmt: skip
