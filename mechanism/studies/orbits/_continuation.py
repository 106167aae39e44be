"""Continuation of fixed points of a parameterised map and the bifurcations along them.

Pure numerics, no scene: the map x ↦ P(x, p) is a callable returning
(P(x, p) − x, ∂P/∂x, ∂P/∂p or ``None``). Branches are followed by natural-parameter
continuation with step control and, where Newton at fixed p fails (a fold), by
pseudo-arclength continuation; bifurcations are read from sign changes of test
functions of the multipliers (eigenvalues of ∂P/∂x) between consecutive points and
located by bisection. The engine (:class:`Follower`) only needs a corrector at fixed p,
so the scene-level continuation (``_scene.py``) runs on it with periodic-orbit shooting
as the corrector.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Protocol

import numpy as np

from chaoskit.contract import check_int, check_positive

__all__ = [
    "BIFURCATION_KINDS",
    "BifurcationPoint",
    "ContinuationBranch",
    "ContinuationPoint",
    "ContinuationSettings",
    "Follower",
    "Solved",
    "test_functions",
]

#: the labels a bifurcation point can carry
BIFURCATION_KINDS = ("period-doubling", "fold", "neimark-sacker", "grazing", "end")
#: at the end of a branch, a multiplier within this distance of +1 (−1) names a fold
#: (period doubling) that the corrector could not pass
END_CRITICAL = 0.2
#: halvings of the step below ``min_step`` allowed at a branch end that its last points
#: do not name yet: points closer to the end give the grazing margin's trend
END_REFINEMENTS = 3

MapFunction = Callable[[np.ndarray, float], tuple[np.ndarray, np.ndarray, np.ndarray | None]]


@dataclass(frozen=True, kw_only=True)
class ContinuationSettings:
    """Step control, bifurcation location and branch switching of a continuation.

    Attributes
    ----------
    step : float
        First step of the parameter (its units, > 0; the sign follows the span).
    min_step, max_step : float
        Smallest and largest step size (> 0): a corrector failure halves the step; below
        ``min_step`` the branch ends (or turns to pseudo-arclength where available).
    growth : float
        Factor (≥ 1) on the step after a point that converged in at most
        ``easy_iterations`` Newton iterations.
    easy_iterations : int
        Newton iterations (≥ 1) at or below which a point counts as easy.
    locate_tolerance : float
        Width (parameter units, > 0) of the bracket a bifurcation is bisected down to.
    newton_tolerance : float
        Size of P(x, p) − x (max norm, > 0) at which a fixed point of a map given as a
        callable is converged (scene continuations use the shooting tolerance of
        :func:`mechanism.periodic_orbit` instead).
    max_iterations : int
        Newton iterations per point (≥ 1; for a scene, ``max_iterations`` of
        :func:`mechanism.periodic_orbit`).
    max_points : int
        Points per branch at most (≥ 2).
    arclength : bool
        Turn to pseudo-arclength continuation when Newton at fixed p fails below
        ``min_step`` (maps given as callables; goes around folds).
    switch_branches : bool
        At a located period doubling, start and follow the branch of twice the period.
    max_period : int
        Largest period (in map iterations, ≥ 1) a switched branch may have.
    switch_offset : float or None
        ε of the period-2 guess x* ± ε v (v the critical eigenvector); default
        ``sqrt(step) * (1 + max(abs(x*)))``.
    shooting_tolerance : float or None
        Scene continuations: ``tol`` of :func:`mechanism.periodic_orbit` (default its
        own).
    reseed : bool
        Scene continuations: when a period-1 branch ends before the end of the span,
        start a new one further on (every ``max_step``) from a run of the scene settled
        for 40 periods, and follow it.
    segments : int or None
        Scene continuations: ``segments`` of :func:`mechanism.periodic_orbit` (1: single
        shooting only, so a value where the branch has ended fails after
        ``max_iterations`` instead of going on to multiple shooting; default its own).
    calm_modulus : float or None
        Step control on the multipliers: the step also grows (by ``growth``) after a
        point whose ``|μ_max|`` is at most this (> 0), whose contact-mode signature is
        that of the point before and with no bifurcation between them, however many
        Newton iterations it took; such a stretch is far from any crossing of the unit
        circle and from any grazing. ``None``: growth on easy points only.
    """

    step: float = 0.01
    min_step: float = 1e-6
    max_step: float = 0.05
    growth: float = 1.5
    easy_iterations: int = 3
    locate_tolerance: float = 1e-9
    newton_tolerance: float = 1e-12
    max_iterations: int = 20
    max_points: int = 2000
    arclength: bool = True
    switch_branches: bool = True
    max_period: int = 4
    switch_offset: float | None = None
    shooting_tolerance: float | None = None
    reseed: bool = True
    segments: int | None = None
    calm_modulus: float | None = None

    def __post_init__(self) -> None:
        for name in ("step", "min_step", "max_step", "locate_tolerance", "newton_tolerance"):
            check_positive(getattr(self, name), name=name)
        if self.min_step > self.max_step:
            raise ValueError(
                f"min_step must be at most max_step; got {self.min_step!r} > {self.max_step!r}."
            )
        if not (math.isfinite(self.growth) and self.growth >= 1.0):
            raise ValueError(f"growth must be a finite number >= 1; got {self.growth!r}.")
        check_int(self.easy_iterations, name="easy_iterations", minimum=1)
        check_int(self.max_iterations, name="max_iterations", minimum=1)
        check_int(self.max_points, name="max_points", minimum=2)
        check_int(self.max_period, name="max_period", minimum=1)
        if self.segments is not None:
            check_int(self.segments, name="segments", minimum=1, maximum=64)
        for name in ("switch_offset", "shooting_tolerance", "calm_modulus"):
            if getattr(self, name) is not None:
                check_positive(getattr(self, name), name=name)


@dataclass(frozen=True, kw_only=True)
class ContinuationPoint:
    """One converged fixed point of a branch.

    Attributes
    ----------
    parameter : float
        Parameter value (its units).
    state : numpy.ndarray
        The fixed point (for a scene: the orbit's section state [q; q̇], SI).
    multipliers : numpy.ndarray
        Eigenvalues of ∂P/∂x (complex, largest modulus first); for a scene the Floquet
        multipliers without the neutral latch directions.
    stable : bool
        Every multiplier strictly inside the unit circle.
    residual : float
        Size of P(x, p) − x at the point (for a scene: share of the clearance).
    signature : tuple of str
        Contact-mode signature of a scene's orbit (joint and mode of each contact phase in
        time order; empty for a map given as a callable).
    eccentricity : numpy.ndarray
        (k, joints): ``|e|`` of each clearance joint at the orbit's k section times (m), the
        orbit diagram's variable; empty for a map given as a callable.
    margin : float
        Grazing margin of a scene's orbit, 0 at a grazing: for a journal in contact the
        whole period its smallest contact force over the mean, otherwise the smallest
        interior extreme of the penetration inside a phase (a free flight closest to
        touching) over the clearance (``mechanism.studies.orbits`` ``grazing_margin``).
        NaN without one, and for a map given as a callable.
    """

    parameter: float
    state: np.ndarray
    multipliers: np.ndarray
    stable: bool
    residual: float
    signature: tuple[str, ...] = ()
    eccentricity: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    margin: float = math.nan


@dataclass(frozen=True, kw_only=True)
class ContinuationBranch:
    """A followed branch of fixed points of the period-fold map.

    Attributes
    ----------
    period : int
        Map iterations (drive periods for a scene) per point of the branch.
    points : tuple of ContinuationPoint
        In the order followed.
    origin : str
        ``"start"`` or how the branch was reached (e.g. the period doubling it was
        switched to at).
    end : str
        Why the branch stopped.
    """

    period: int
    points: tuple[ContinuationPoint, ...]
    origin: str = "start"
    end: str = ""

    @property
    def parameter(self) -> np.ndarray:
        """Parameter values of the points."""
        return np.array([p.parameter for p in self.points], dtype=np.float64)

    @property
    def stable(self) -> np.ndarray:
        """Stability flags of the points."""
        return np.array([p.stable for p in self.points], dtype=bool)

    @property
    def largest_modulus(self) -> np.ndarray:
        """``|μ_max|`` of the points (0 for a point without multipliers)."""
        return np.array(
            [float(np.abs(p.multipliers[0])) if p.multipliers.size else 0.0 for p in self.points]
        )


@dataclass(frozen=True, kw_only=True)
class BifurcationPoint:
    """A located bifurcation (or grazing) on a branch.

    Attributes
    ----------
    kind : str
        ``"period-doubling"`` (a real multiplier crosses −1), ``"fold"`` (+1),
        ``"neimark-sacker"`` (a complex pair crosses the unit circle), ``"grazing"``
        (the orbit's contact-mode signature changes: a contact phase appears or
        vanishes) or, at the end of a branch that the corrector cannot continue,
        ``"end"`` when none of these is recognised there.
    parameter : float
        Located value (zero of the test function in the final bracket; its middle for a
        grazing).
    bracket : tuple of float
        (low, high): the last bracket, width at most the locate tolerance unless the
        corrector failed inside it.
    branch : int
        Index of the branch it lies on.
    period : int
        Period of that branch.
    multipliers_before, multipliers_after : numpy.ndarray
        Multipliers at the bracket's ends, in the direction followed.
    signature_before, signature_after : tuple of str
        Contact-mode signatures at the bracket's ends.
    explanation : str
        One line on what happens there.
    state : numpy.ndarray
        The fixed point at ``parameter`` (interpolated in the final bracket; at a branch
        end, the last converged one).
    branch_end : bool
        The branch ends here: the corrector failed past the last converged point at every
        step down to the smallest, so ``bracket`` is (last converged value, first failed
        one), ``multipliers_after`` is empty and ``kind`` is read from the trend of the
        last points (the grazing margin extrapolated to 0 inside twice the bracket, or a
        multiplier within 0.2 of +1 or −1).
    """

    kind: str
    parameter: float
    bracket: tuple[float, float]
    branch: int
    period: int
    multipliers_before: np.ndarray
    multipliers_after: np.ndarray
    signature_before: tuple[str, ...] = ()
    signature_after: tuple[str, ...] = ()
    explanation: str = ""
    state: np.ndarray = field(default_factory=lambda: np.zeros(0))
    branch_end: bool = False


@dataclass
class Solved:
    """A corrected point with what the engine needs besides the public point."""

    point: ContinuationPoint
    iterations: int
    jacobian: np.ndarray | None = None
    payload: Any = None
    tangent: np.ndarray | None = field(default=None, repr=False)


class Corrector(Protocol):
    """What :class:`Follower` needs: a fixed point at a fixed parameter value."""

    def at(self, parameter: float, guess: Solved) -> Solved | None: ...


def test_functions(mu: np.ndarray) -> dict[str, float]:
    """Test functions whose sign changes mark a crossing: ∏(μ+1) period doubling,
    ∏(μ−1) fold, ∏_{i<j}(μ_i μ_j − 1) a pair whose product crosses 1 (Neimark–Sacker)."""
    mu = np.asarray(mu, dtype=np.complex128)
    if mu.size == 0:
        return {"period-doubling": 1.0, "fold": 1.0, "neimark-sacker": 1.0}
    pairs = np.outer(mu, mu)[np.triu_indices(mu.size, 1)] - 1.0
    return {
        "period-doubling": float(np.prod(mu + 1.0).real),
        "fold": float(np.prod(mu - 1.0).real),
        "neimark-sacker": float(np.prod(pairs).real) if pairs.size else 1.0,
    }


def _explain(kind: str, before: np.ndarray, after: np.ndarray, period: int) -> str:
    """One line on a located bifurcation."""
    b = _critical(kind, before)
    a = _critical(kind, after)
    gain = "loses" if abs(a) > abs(b) else "gains"
    orbit = f"period-{period} orbit"
    if kind == "period-doubling":
        return (f"a real multiplier crosses -1 ({_fmt(b)} -> {_fmt(a)}): the {orbit} {gain} "
                f"stability and a period-{2 * period} orbit branches off")  # fmt: skip
    if kind == "fold":
        return (f"a real multiplier crosses +1 ({_fmt(b)} -> {_fmt(a)}): two {orbit}s meet "
                "and turn back (saddle-node)")  # fmt: skip
    return (
        f"a complex pair crosses the unit circle (|mu| {abs(b):.6g} -> {abs(a):.6g}, angle "
        f"{abs(np.angle(a)):.3g} rad): the {orbit} {gain} stability to a torus"
    )


def _fmt(z: complex) -> str:
    return f"{z.real:.6g}" if abs(z.imag) <= 1e-12 * max(abs(z), 1.0) else f"{z:.6g}"


def _critical(kind: str, mu: np.ndarray) -> complex:
    """The multiplier nearest to where ``kind`` crosses."""
    mu = np.asarray(mu, dtype=np.complex128)
    if mu.size == 0:
        return complex(0.0)
    if kind == "period-doubling":
        return complex(mu[np.argmin(np.abs(mu + 1.0))])
    if kind == "fold":
        return complex(mu[np.argmin(np.abs(mu - 1.0))])
    complex_ones = mu[np.abs(mu.imag) > 1e-9 * np.maximum(np.abs(mu), 1.0)]
    pool = complex_ones if complex_ones.size else mu
    return complex(pool[np.argmin(np.abs(np.abs(pool) - 1.0))])


def _is_neimark_sacker(mu: np.ndarray) -> bool:
    """The multiplier nearest the unit circle is one of a complex pair."""
    mu = np.asarray(mu, dtype=np.complex128)
    if mu.size < 2:
        return False
    near = mu[np.argmin(np.abs(np.abs(mu) - 1.0))]
    return bool(abs(near.imag) > 1e-6 * max(abs(near), 1.0))


class Follower:
    """Follows one branch with a corrector at fixed p, detects and locates bifurcations.

    ``chord`` (optional) corrects on the hyperplane through a predicted (x, p)
    perpendicular to a direction: pseudo-arclength, used around folds and to bisect
    between points that a fixed p cannot (both sides of a fold). ``stop_when``
    (optional) is asked after every new point and ends the branch there when it returns
    a reason (e.g. the point lies on a branch followed before).
    """

    def __init__(
        self,
        corrector: Corrector,
        settings: ContinuationSettings,
        *,
        chord: Callable[[np.ndarray, np.ndarray, Solved], Solved | None] | None = None,
        on_point: Callable[[Solved], None] | None = None,
        stop_when: Callable[[Solved], str | None] | None = None,
    ) -> None:
        self.corrector = corrector
        self.settings = settings
        self.chord = chord
        self.on_point = on_point
        self.stop_when = stop_when
        #: (located point, bracket end before, bracket end after) of every located point
        self.brackets: list[tuple[BifurcationPoint, Solved, Solved]] = []

    # -- following ------------------------------------------------------------------
    def follow(
        self,
        start: Solved,
        stop: float,
        *,
        period: int,
        branch: int,
        origin: str = "start",
        targets: list[float] | None = None,
    ) -> tuple[ContinuationBranch, list[BifurcationPoint], list[Solved]]:
        """Points from ``start`` towards ``stop`` (through each of ``targets`` on the
        way), with the bifurcations between them."""
        s = self.settings
        waypoints = list(targets or [])
        points = [start]
        found: list[BifurcationPoint] = []
        p0 = start.point.parameter
        direction = 1.0 if stop >= p0 else -1.0
        lo, hi = min(p0, stop), max(p0, stop)
        h = min(s.step, s.max_step)
        arclength = False
        end = "reached the end of the span"
        failed = math.nan
        refinements = END_REFINEMENTS
        while len(points) < s.max_points:
            last = points[-1]
            if not arclength:
                p_next = last.point.parameter + direction * h
                while waypoints and direction * (waypoints[0] - last.point.parameter) <= 0:
                    waypoints.pop(0)
                cap = waypoints[0] if waypoints else stop
                if direction * (p_next - cap) > 0:
                    p_next = cap
                guess = _predict(points, p_next)
                new = self.corrector.at(p_next, guess)
            else:
                new = self._arclength_step(points, h, direction)
            if new is None:
                if not arclength:
                    failed = p_next
                h *= 0.5
                if h < s.min_step:
                    if (not arclength and refinements > 0 and math.isfinite(failed)
                            and _end_kind([x.point for x in points[-3:]], failed, period)[0]
                            == "end"):  # fmt: skip
                        # unnamed yet: closer to the end before giving up
                        refinements -= 1
                        continue
                    if self.chord is not None and s.arclength and not arclength:
                        arclength, h = True, max(4.0 * s.min_step, s.step * 0.25)
                        continue
                    end = "the corrector failed below the smallest step"
                    if not arclength and math.isfinite(failed):
                        found.append(branch_end(points, failed, branch=branch, period=period))
                    break
                continue
            points.append(new)
            if self.on_point is not None:
                self.on_point(new)
            located = self._detect(points[-2], new, branch=branch, period=period)
            found.extend(located)
            if new.iterations <= s.easy_iterations or (not located and _calm(points[-2], new, s)):
                h = min(h * s.growth, s.max_step)
            p = new.point.parameter
            reason = self.stop_when(new) if self.stop_when is not None else None
            if reason:
                end = reason
                break
            if not arclength and p == stop:
                break
            if arclength and not (lo - 1e-12 <= p <= hi + 1e-12):
                end = "left the span"
                break
        else:
            end = "reached max_points"
        branch_obj = ContinuationBranch(
            period=period, points=tuple(x.point for x in points), origin=origin, end=end
        )
        return branch_obj, found, points

    def _arclength_step(self, points: list[Solved], h: float, direction: float) -> Solved | None:
        """One pseudo-arclength step of length h along the secant (or the tangent)."""
        last = points[-1]
        y_last = _augmented(last)
        if len(points) >= 2:
            t = y_last - _augmented(points[-2])
        elif last.tangent is not None:
            t = last.tangent.copy()
        else:
            t = np.zeros_like(y_last)
            t[-1] = direction
        norm = float(np.linalg.norm(t))
        if norm == 0.0:
            return None
        t /= norm
        assert self.chord is not None
        return self.chord(y_last + h * t, t, last)

    # -- detection and location -----------------------------------------------------
    def _detect(self, a: Solved, b: Solved, *, branch: int, period: int) -> list[BifurcationPoint]:
        out: list[BifurcationPoint] = []
        graze: tuple[Solved, Solved] | None = None
        if a.point.signature != b.point.signature:
            located_graze, g_lo, g_hi = self._locate_grazing(a, b, branch=branch, period=period)
            out.append(located_graze)
            graze = (g_lo, g_hi)
        fa, fb = test_functions(a.point.multipliers), test_functions(b.point.multipliers)
        for kind in ("fold", "period-doubling", "neimark-sacker"):
            if not _changes(fa[kind], fb[kind]):
                continue
            if kind == "neimark-sacker" and (
                not _is_neimark_sacker(a.point.multipliers)
                and not _is_neimark_sacker(b.point.multipliers)
            ):
                continue  # a real pair whose product crosses 1: a saddle, no torus
            lo, hi = a, b
            if graze is not None:
                # the sign changes across the grazing (a jump, reported as the grazing)
                # or on one side of it: bisect only that side
                f_lo = test_functions(graze[0].point.multipliers)[kind]
                f_hi = test_functions(graze[1].point.multipliers)[kind]
                if _changes(fa[kind], f_lo):
                    hi = graze[0]
                elif _changes(f_hi, fb[kind]):
                    lo = graze[1]
                else:
                    continue
            located = self._locate(lo, hi, kind, branch=branch, period=period)
            if located is not None and not any(
                g.kind == "grazing" and g.bracket[0] <= located.parameter <= g.bracket[1]
                for g in out
            ):
                out.append(located)
        return out

    def _between(self, a: Solved, b: Solved, theta: float) -> Solved | None:
        """The corrected point at fraction ``theta`` of the way from a to b."""
        ya, yb = _augmented(a), _augmented(b)
        pa, pb = a.point.parameter, b.point.parameter
        if self.chord is not None:
            t = yb - ya
            norm = float(np.linalg.norm(t))
            if norm > 0.0:
                return self.chord(ya + theta * t, t / norm, a)
        guess = _interpolated(a, b, theta)
        return self.corrector.at(pa + theta * (pb - pa), guess)

    def _locate(
        self, a: Solved, b: Solved, kind: str, *, branch: int, period: int
    ) -> BifurcationPoint | None:
        """Bisection on the sign of the test function of ``kind`` between a and b."""
        tol = self.settings.locate_tolerance
        fa = test_functions(a.point.multipliers)[kind]
        fb = test_functions(b.point.multipliers)[kind]
        lo, hi = a, b
        for _ in range(200):
            if _width(lo, hi) <= tol:
                break
            mid = self._between(lo, hi, 0.5)
            if mid is None:
                break
            fm = test_functions(mid.point.multipliers)[kind]
            if (fm > 0) == (fa > 0):
                lo, fa = mid, fm
            else:
                hi, fb = mid, fm
        if kind == "neimark-sacker" and not (
            _is_neimark_sacker(lo.point.multipliers) or _is_neimark_sacker(hi.point.multipliers)
        ):
            return None
        pl, ph = lo.point.parameter, hi.point.parameter
        if lo.point.signature != hi.point.signature:
            return None  # a jump of the multipliers at a grazing, reported as the grazing
        # the test function's zero by linear interpolation in the final bracket
        theta = fa / (fa - fb) if fa != fb else 0.5
        value = pl + (ph - pl) * theta
        if kind == "fold":
            # p is stationary at a fold: the extreme of the bracket's ends is closest
            pa, pb = a.point.parameter, b.point.parameter
            if max(pl, ph) > max(pa, pb):
                value = max(pl, ph)
            elif min(pl, ph) < min(pa, pb):
                value = min(pl, ph)
        located = BifurcationPoint(
            kind=kind,
            parameter=float(value),
            bracket=(float(min(pl, ph)), float(max(pl, ph))),
            branch=branch,
            period=period,
            multipliers_before=lo.point.multipliers,
            multipliers_after=hi.point.multipliers,
            signature_before=lo.point.signature,
            signature_after=hi.point.signature,
            explanation=_explain(kind, lo.point.multipliers, hi.point.multipliers, period),
            state=(1.0 - theta) * lo.point.state + theta * hi.point.state,
        )
        self.brackets.append((located, lo, hi))
        return located

    def _locate_grazing(
        self, a: Solved, b: Solved, *, branch: int, period: int
    ) -> tuple[BifurcationPoint, Solved, Solved]:
        """Bisection on the contact-mode signature between a and b."""
        tol = self.settings.locate_tolerance
        lo, hi = a, b
        for _ in range(200):
            if _width(lo, hi) <= tol:
                break
            mid = self._between(lo, hi, 0.5)
            if mid is None:
                break
            if mid.point.signature == lo.point.signature:
                lo = mid
            else:
                hi = mid
        pl, ph = lo.point.parameter, hi.point.parameter
        located = BifurcationPoint(
            kind="grazing",
            parameter=0.5 * (pl + ph),
            bracket=(float(min(pl, ph)), float(max(pl, ph))),
            branch=branch,
            period=period,
            multipliers_before=lo.point.multipliers,
            multipliers_after=hi.point.multipliers,
            signature_before=lo.point.signature,
            signature_after=hi.point.signature,
            explanation=_explain_grazing(lo.point, hi.point, period),
            state=0.5 * (lo.point.state + hi.point.state),
        )
        return located, lo, hi


def branch_end(
    points: list[Solved], failed: float, *, branch: int, period: int
) -> BifurcationPoint:
    """The end of a branch between its last converged point and the first value the
    corrector failed at, named from the trend of the last points (``BifurcationPoint``,
    ``branch_end``)."""
    last = points[-1].point
    pl = float(last.parameter)
    kind, why = _end_kind([x.point for x in points[-3:]], failed, period)
    return BifurcationPoint(
        kind=kind, parameter=0.5 * (pl + failed), bracket=(min(pl, failed), max(pl, failed)),
        branch=branch, period=period, multipliers_before=last.multipliers,
        multipliers_after=np.zeros(0, dtype=np.complex128),
        signature_before=last.signature, explanation=why, state=last.state.copy(),
        branch_end=True,
    )  # fmt: skip


def _end_kind(last: list[ContinuationPoint], failed: float, period: int) -> tuple[str, str]:
    """(kind, one line) of a branch end from its last points (oldest first)."""
    point = last[-1]
    p = point.parameter
    orbit = f"period-{period} orbit"
    past = f"nothing converges from {p:.6g} to {failed:.6g}"
    if len(last) >= 2 and math.isfinite(point.margin) and math.isfinite(last[-2].margin):
        m0, m1 = last[-2].margin, point.margin
        p0 = last[-2].parameter
        if m1 < m0:
            zero = p + (p - p0) * m1 / (m0 - m1)
            if (zero - p) * (failed - p) > 0 and abs(zero - p) <= 2.0 * abs(failed - p):
                return "grazing", (
                    f"the {orbit} grazes: its grazing margin falls from {m0:.3g} to "
                    f"{m1:.3g} ({p0:.6g} -> {p:.6g}) and reaches 0 near "
                    f"{zero:.6g}; {past}"
                )
    mu = np.asarray(point.multipliers, dtype=np.complex128)
    if mu.size:
        near_one = complex(mu[np.argmin(np.abs(mu - 1.0))])
        near_minus = complex(mu[np.argmin(np.abs(mu + 1.0))])
        if abs(near_one - 1.0) < END_CRITICAL:
            return "fold", (
                f"a real multiplier approaches +1 ({_fmt(near_one)}): the {orbit} meets "
                f"another and turns back (saddle-node); {past}"
            )
        if abs(near_minus + 1.0) < END_CRITICAL:
            return "period-doubling", (
                f"a real multiplier approaches -1 ({_fmt(near_minus)}): the {orbit} doubles; {past}"
            )
    top = float(np.abs(mu[0])) if mu.size else 0.0
    return "end", (
        f"the {orbit} ends abruptly (|mu_max| {top:.3g}, no multiplier near +-1, no "
        f"grazing margin closing): {past}"
    )


def _calm(a: Solved, b: Solved, s: ContinuationSettings) -> bool:
    """Step control on the multipliers: b is far inside the unit circle and has a's
    contact-mode signature."""
    mu = b.point.multipliers
    return (
        s.calm_modulus is not None
        and a.point.signature == b.point.signature
        and (float(np.max(np.abs(mu))) if mu.size else 0.0) <= s.calm_modulus
    )


def _changes(f0: float, f1: float) -> bool:
    """Whether a test function changes sign (a zero counts as no change)."""
    return f0 != 0.0 and f1 != 0.0 and (f0 > 0) != (f1 > 0)


def _explain_grazing(lo: ContinuationPoint, hi: ContinuationPoint, period: int) -> str:
    before, after = set(lo.signature), set(hi.signature)
    gained = sorted(after - before)
    lost = sorted(before - after)
    change = "a contact phase appears" if len(hi.signature) > len(lo.signature) else (
        "a contact phase vanishes" if len(hi.signature) < len(lo.signature)
        else "the contact modes change")  # fmt: skip
    what = "; ".join(
        ([f"new: {', '.join(gained)}"] if gained else [])
        + ([f"gone: {', '.join(lost)}"] if lost else [])
    )
    mb = float(np.abs(lo.multipliers[0])) if lo.multipliers.size else 0.0
    ma = float(np.abs(hi.multipliers[0])) if hi.multipliers.size else 0.0
    stability = ""
    if lo.stable != hi.stable:
        stability = (
            f", stability {'lost' if lo.stable else 'gained'} across it (|mu_max| "
            f"{mb:.3g} -> {ma:.3g})"
        )
    return f"the period-{period} orbit grazes: {change} ({what or 'reordered'}){stability}"


def _width(lo: Solved, hi: Solved) -> float:
    """Size of a bracket: its parameter width, or its length in (x, p) (around a fold,
    where p hardly changes)."""
    dp = abs(hi.point.parameter - lo.point.parameter)
    if lo.tangent is None:
        return dp
    return max(dp, float(np.linalg.norm(_augmented(hi) - _augmented(lo))))


def _augmented(s: Solved) -> np.ndarray:
    return np.append(np.asarray(s.point.state, dtype=np.float64), s.point.parameter)


def _interpolated(a: Solved, b: Solved, theta: float) -> Solved:
    state = (1.0 - theta) * a.point.state + theta * b.point.state
    p = (1.0 - theta) * a.point.parameter + theta * b.point.parameter
    return Solved(point=replace(a.point, state=state, parameter=p), iterations=0,
                  payload=a.payload)  # fmt: skip


def _predict(points: list[Solved], p_next: float) -> Solved:
    """Secant predictor in p from the last two points (the last point alone at first)."""
    last = points[-1]
    if len(points) < 2:
        return last
    prev = points[-2]
    dp = last.point.parameter - prev.point.parameter
    if dp == 0.0:
        return last
    slope = (last.point.state - prev.point.state) / dp
    state = last.point.state + slope * (p_next - last.point.parameter)
    return Solved(point=replace(last.point, state=state), iterations=0, payload=last.payload)
