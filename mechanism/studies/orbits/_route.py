"""``mechanism.route``: the sequence of bifurcations from regular motion to chaos, read
from a continuation and the chaotic windows of an orbit diagram."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from ._continuation import BifurcationPoint
from ._scene import Continuation

__all__ = ["RouteToChaos", "chaotic_windows", "regular_stretches", "route"]

#: an orbit diagram's value between two chaotic ones whose exponent estimate is above
#: this (1/s) while its 95 % interval reaches below 0 is undecided and does not split a
#: chaotic window; a periodic orbit's estimate is about 1e-5 (its neutral latch)
UNDECIDED_EXPONENT = 0.1


@dataclass(frozen=True, kw_only=True)
class RouteToChaos:
    """How the followed orbits reach the chaotic windows.

    Attributes
    ----------
    parameter : str
        The scene key.
    units : str
    steps : tuple of str
        The route in order: stable stretches of each branch, the bifurcation that ends
        each, and the window it opens.
    windows : tuple of tuple of float
        Chaotic windows (low, high), in the direction followed.
    onsets : tuple of BifurcationPoint or None
        Per window, the last located bifurcation at or before its start (within
        ``slack``) and after the previous window; ``None`` when none was located there.
        Points on branches followed towards lower values are left out when a branch
        followed upwards has one there.
    closings : tuple of BifurcationPoint or None
        Per window, what ends the regular motion above it going down: the first located
        loss of stability (else located point) met going down from the next window to
        the window's start, on a branch followed towards lower values (e.g. from a seed
        in the regular stretch above); inside the window when a stable orbit outlives
        the orbit diagram's chaos there. ``None`` when no such branch was followed.
    inside : tuple of tuple of (float, float)
        Per window, the part of it covered by each run of consecutive stable points of a
        followed branch: stable periodic orbits beside the orbit diagram's chaos (which
        is the motion from the scene's start).
    slack : float
        How far past a window's first chaotic value its onset may lie (half the orbit
        diagram's spacing there; 0 for windows given as pairs).
    """

    parameter: str
    units: str
    steps: tuple[str, ...]
    windows: tuple[tuple[float, float], ...]
    onsets: tuple[BifurcationPoint | None, ...]
    slack: float = 0.0
    closings: tuple[BifurcationPoint | None, ...] = ()
    inside: tuple[tuple[tuple[float, float], ...], ...] = ()

    def lines(self) -> list[str]:
        """The route, then the onset (and, where followed, the closing from above) of
        every window, one line each."""
        out = list(self.steps)
        closings = self.closings or (None,) * len(self.windows)
        for (lo, hi), onset, closing in zip(self.windows, self.onsets, closings, strict=True):
            window = f"chaotic window {_v(lo)}–{_v(hi)} {self.units}"
            if onset is None:
                text = f"{window}: no located bifurcation of the followed branches opens it"
            else:
                text = f"{window}: opened by the {_named(onset, self.units)}"
            for a, b in dict(zip(self.windows, self.inside, strict=False)).get((lo, hi), ()):
                text += f"; a stable orbit followed inside it over {_v(a)}–{_v(b)} {self.units}"
            if closing is not None:
                text += (
                    f"; from above, the regular motion ends in the {_named(closing, self.units)}"
                )
                if closing.parameter < hi - self.slack:
                    text += " inside the window: a stable orbit there beside the diagram's chaos"
            out.append(text)
        return out

    def summary(self) -> str:
        """The route as one paragraph (the steps joined by semicolons)."""
        return "; ".join(self.steps) + "."


def _v(x: float) -> str:
    return f"{x:.4g}"


def _named(b: BifurcationPoint, units: str) -> str:
    """'grazing at 64.47 rpm [64.44, 64.51] (end of the period-1 branch)'."""
    where = "end of the" if b.branch_end else "on the"
    return (
        f"{b.kind} at {_v(b.parameter)} {units} [{b.bracket[0]:.4g}, {b.bracket[1]:.4g}] "
        f"({where} period-{b.period} branch {b.branch})"
    )


def chaotic_windows(diagram: xr.Dataset) -> tuple[list[tuple[float, float]], float]:
    """Chaotic windows of a :func:`mechanism.bifurcation` Dataset with the exponent:
    runs of consecutive values whose 95 % interval of λ₁ lies above 0, and half the
    largest spacing of the values (the resolution of a window's edge). Values between
    two such runs that are all undecided (interval reaching below 0, estimate above
    ``UNDECIDED_EXPONENT``) do not split the window."""
    name = str(diagram.attrs.get("bifurcation_parameter", ""))
    if name not in diagram.dims or "lyapunov_exponent_low" not in diagram:
        raise ValueError(
            "windows must be a mechanism.bifurcation Dataset with the exponent "
            "(exponent=True) or a list of (low, high) chaotic windows."
        )
    p = np.asarray(diagram[name].values, dtype=np.float64)
    low = np.asarray(diagram["lyapunov_exponent_low"].values, dtype=np.float64)
    order = np.argsort(p)
    p, chaotic = p[order], np.nan_to_num(low[order], nan=-1.0) > 0
    if "lyapunov_exponent" in diagram:
        estimate = np.nan_to_num(
            np.asarray(diagram["lyapunov_exponent"].values, dtype=np.float64)[order], nan=-1.0
        )
        undecided = ~chaotic & (estimate > UNDECIDED_EXPONENT)
    else:
        undecided = np.zeros_like(chaotic)
    out: list[tuple[float, float]] = []
    i = 0
    while i < p.size:
        if chaotic[i]:
            j = i
            while True:
                k = j + 1
                while k < p.size and undecided[k]:
                    k += 1
                if k < p.size and chaotic[k]:
                    j = k
                else:
                    break
            out.append((float(p[i]), float(p[j])))
            i = j + 1
        else:
            i += 1
    spacing = float(np.max(np.diff(p))) if p.size > 1 else 0.0
    return out, 0.5 * spacing


def regular_stretches(diagram: xr.Dataset) -> list[tuple[float, float, float]]:
    """The stretches of an orbit diagram between its chaotic windows
    (runs of values whose 95 % interval of λ₁ lies above 0, undecided values between
    two such runs bridged): (first value, last value, seed) of every run of values
    outside the windows, in increasing order, the seed being the run's value of lowest
    exponent estimate (the most strongly attracting motion): where
    :func:`mechanism.continuation` ``seeds`` start branches."""
    wins, _ = chaotic_windows(diagram)
    name = str(diagram.attrs.get("bifurcation_parameter", ""))
    order = np.argsort(np.asarray(diagram[name].values, dtype=np.float64))
    p = np.asarray(diagram[name].values, dtype=np.float64)[order]
    lam = np.nan_to_num(
        np.asarray(diagram["lyapunov_exponent"].values, dtype=np.float64)[order], nan=np.inf
    )
    inside = np.zeros(p.size, dtype=bool)
    for lo, hi in wins:
        inside |= (p >= lo) & (p <= hi)
    out: list[tuple[float, float, float]] = []
    i = 0
    while i < p.size:
        if inside[i]:
            i += 1
            continue
        j = i
        while j + 1 < p.size and not inside[j + 1]:
            j += 1
        run = p[i : j + 1]
        seed = float(run[np.argmin(lam[i : j + 1])])
        out.append((float(run[0]), float(run[-1]), seed))
        i = j + 1
    return out


def _given_windows(windows: Any) -> tuple[list[tuple[float, float]], float]:
    if isinstance(windows, xr.Dataset):
        return chaotic_windows(windows)
    out: list[tuple[float, float]] = []
    try:
        for pair in windows:
            lo, hi = (float(v) for v in pair)
            if not (math.isfinite(lo) and math.isfinite(hi)):
                raise ValueError
            out.append((min(lo, hi), max(lo, hi)))
    except (TypeError, ValueError):
        raise ValueError(
            f"windows must be a mechanism.bifurcation Dataset with the exponent or a list "
            f"of (low, high) pairs of finite numbers; got {windows!r}."
        ) from None
    return out, 0.0


def route(
    continuation: Continuation, windows: xr.Dataset | Sequence[tuple[float, float]]
) -> RouteToChaos:
    """The sequence of bifurcations from the regular regime to the first chaotic window.

    Walks the first branch from the start of the continuation: its stable stretch, the
    located point where it loses stability, the branch switched to there (at a period
    doubling) and so on, until a loss of stability reaches the first chaotic window
    (its start within ``slack``) or the branches end. Every window is then given the
    last located bifurcation at or before its start.

    Parameters
    ----------
    continuation : Continuation
        From :func:`mechanism.continuation`.
    windows : xarray.Dataset or sequence of (float, float)
        A :func:`mechanism.bifurcation` Dataset with the exponent (a window is a run of
        values whose 95 % interval of λ₁ lies above 0), or the chaotic windows as
        (low, high) pairs in the parameter's units.

    Returns
    -------
    RouteToChaos

    Raises
    ------
    ValueError
        On windows of another form or a continuation without branches.
    """
    if not continuation.branches or not continuation.branches[0].points:
        raise ValueError("the continuation has no branch to follow.")
    wins, slack = _given_windows(windows)
    first = continuation.branches[0]
    p0 = first.points[0].parameter
    direction = 1.0 if first.points[-1].parameter >= p0 else -1.0
    # windows in the direction followed, from the start on
    wins = sorted(
        (w for w in wins if direction * ((w[1] if direction > 0 else w[0]) - p0) >= 0),
        key=lambda w: direction * (w[0] if direction > 0 else w[1]),
    )
    units = continuation.units
    steps = _walk(continuation, wins, slack, direction)
    onsets = [_onset(continuation, wins, i, slack, direction, p0) for i in range(len(wins))]
    closings = [_closing(continuation, wins, i, slack) for i in range(len(wins))]
    inside = [_stable_inside(continuation, w) for w in wins]
    return RouteToChaos(
        parameter=continuation.parameter, units=units, steps=tuple(steps),
        windows=tuple(wins), onsets=tuple(onsets), slack=slack, closings=tuple(closings),
        inside=tuple(inside),
    )  # fmt: skip


def _stable_inside(c: Continuation, window: tuple[float, float]) -> tuple[tuple[float, float], ...]:
    """Per branch, the part of the window covered by a run of its consecutive stable
    points (a branch stable on both sides of a one-value window runs through it)."""
    lo, hi = min(window), max(window)
    out = []
    for b in c.branches:
        ps, stable = b.parameter, b.stable
        i = 0
        while i < ps.size:
            if not stable[i]:
                i += 1
                continue
            j = i
            while j + 1 < ps.size and stable[j + 1]:
                j += 1
            a, z = float(np.min(ps[i : j + 1])), float(np.max(ps[i : j + 1]))
            if a <= hi and z >= lo:
                out.append((max(a, lo), min(z, hi)))
            i = j + 1
    return tuple(out)


def _branch_direction(c: Continuation, index: int) -> float:
    """+1 for a branch followed towards higher values, −1 lower, 0 a single point."""
    ps = c.branches[index].parameter
    return float(np.sign(ps[-1] - ps[0])) if ps.size > 1 else 0.0


def _is_loss(b: BifurcationPoint) -> bool:
    before = bool(np.all(np.abs(b.multipliers_before) < 1.0))
    after = bool(np.all(np.abs(b.multipliers_after) < 1.0))
    return before and (b.branch_end or not after)


def _closing(
    c: Continuation, wins: list[tuple[float, float]], i: int, slack: float
) -> BifurcationPoint | None:
    """The first located loss of stability (else any located point) met going down from
    the next window (in increasing order) to the start of window i, on branches followed
    downwards: where the regular motion above the window ends, inside the window when a
    stable orbit outlives the orbit diagram's chaos there."""
    lo_w, hi_w = min(wins[i]), max(wins[i])
    above = [min(w) for w in wins if min(w) > hi_w]
    ceiling = min(above) if above else math.inf
    candidates = [
        b for b in c.bifurcations
        if _branch_direction(c, b.branch) < 0 and lo_w - slack < b.parameter <= ceiling + slack
    ]  # fmt: skip
    losses = [b for b in candidates if _is_loss(b)] or candidates
    return max(losses, key=lambda b: b.parameter) if losses else None


def _entry(w: tuple[float, float], direction: float) -> float:
    return w[0] if direction > 0 else w[1]


def _losses(c: Continuation, branch: int, direction: float) -> list[BifurcationPoint]:
    """Located points on ``branch`` where the orbit loses stability, in the direction
    followed."""
    out = []
    for bif in c.bifurcations:
        if bif.branch != branch:
            continue
        before = bool(np.all(np.abs(bif.multipliers_before) < 1.0))
        after = bool(np.all(np.abs(bif.multipliers_after) < 1.0))
        if before and (bif.branch_end or not after):
            out.append(bif)
    return sorted(out, key=lambda b: direction * b.parameter)


def _walk(
    c: Continuation, wins: list[tuple[float, float]], slack: float, direction: float
) -> list[str]:
    units = c.units
    steps: list[str] = []
    branch = 0
    target = _entry(wins[0], direction) if wins else None
    while True:
        b = c.branches[branch]
        start = b.points[0].parameter
        losses = _losses(c, branch, direction)
        stable = [p for p in b.points if p.stable]
        if not losses:
            last = stable[-1].parameter if stable else start
            steps.append(
                f"period-{b.period} {'stable' if stable else 'unstable'} "
                f"{_v(start)}–{_v(last)} {units} ({b.end})"
            )
            break
        loss = losses[0]
        steps.append(f"period-{b.period} stable {_v(start)}–{_v(loss.parameter)} {units}")
        text = f"{loss.kind} at {_v(loss.parameter)} {units}"
        if target is not None and direction * (loss.parameter - target) >= -slack - 1e-12:
            lo, hi = wins[0]
            steps.append(f"{text} opens the chaotic window {_v(lo)}–{_v(hi)} {units}")
            break
        steps.append(text)
        children = [
            i for i, x in enumerate(c.branches)
            if x.origin.startswith("period doubling") and x.period == 2 * b.period
            and abs(x.points[0].parameter - loss.parameter) <= 2 * c.settings.step + 1e-12
        ]  # fmt: skip
        if loss.kind != "period-doubling" or not children:
            if target is not None:
                lo, hi = wins[0]
                steps.append(
                    f"no stable orbit followed beyond it; the chaotic window "
                    f"{_v(lo)}–{_v(hi)} {units} follows"
                )
            break
        branch = children[0]
    return steps


def _onset(
    c: Continuation,
    wins: list[tuple[float, float]],
    i: int,
    slack: float,
    direction: float,
    p0: float,
) -> BifurcationPoint | None:
    entry = _entry(wins[i], direction)
    after = (wins[i - 1][1] if direction > 0 else wins[i - 1][0]) if i > 0 else p0
    candidates = [
        b for b in c.bifurcations
        if direction * (b.parameter - after) >= -slack
        and direction * (b.parameter - entry) <= slack + 1e-12
    ]  # fmt: skip
    # going the way of the first branch: points of branches followed that way first
    ahead = [b for b in candidates if _branch_direction(c, b.branch) != -direction]
    candidates = ahead or candidates
    if not candidates:
        return None
    return max(candidates, key=lambda b: direction * b.parameter)
