"""The answer first: the paper study's summary, headline figures and stage progress.

:func:`summary_section` turns the per-state verdicts, the exponents from the data (Wolf,
Rosenstein) and from the equations (:func:`mechanism.lyapunov_exponent`, rigid model) and
the paper's values and claims into the report's opening section; :class:`Stages` prints
progress for every stage of the study with an estimate of the time left. The model and its
reconstruction choices are described in ``docs/paper-model.md``.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
from collections.abc import Iterator, Mapping, Sequence
from typing import Any, TextIO

import numpy as np
import pandas as pd
import psutil
import xarray as xr

import chaoskit
from chaoskit.reporting import (
    CONFIDENCE_FORMAT,
    CONFIDENCE_NOTE,
    decided_by,
    format_confidence,
    plural,
)

__all__ = [
    "Stages",
    "motion_verdict",
    "process_tree_cpu_time",
    "strobe_figure",
    "strobe_points",
    "summary_section",
]

_LN2 = math.log(2.0)
#: Verdict labels that mean "regular" when a claim says "not chaotic".
_REGULAR = ("periodic", "quasi-periodic", "equilibrium")
#: Footnote of the exponents that point the other way from the state's motion verdict.
SET_ASIDE = "†"
SET_ASIDE_NOTE = (
    f"{SET_ASIDE} set aside: the estimate points the other way from the state's motion "
    "verdict (clearly positive for a regular motion, or not clearly positive for chaos), "
    'which the other evidence decided (Table 1, "why"). '
)


# --------------------------------------------------------------------------- progress


def process_tree_cpu_time() -> float:
    """CPU seconds (user + system) used so far by this process and all its descendants.

    Counts the live descendants (dask workers, process pools) and the children already
    waited for. A descendant that ends and is reaped by a process other than this one or a
    live descendant is lost, so the figure is a lower bound on a shared machine: unlike
    wall time it does not grow when other jobs take the cores.
    """
    own = os.times()
    total = own.user + own.system + own.children_user + own.children_system
    with contextlib.suppress(psutil.Error):
        for child in psutil.Process().children(recursive=True):
            with contextlib.suppress(psutil.Error):
                t = child.cpu_times()
                total += t.user + t.system + t.children_user + t.children_system
    return float(total)


class Stages:
    """Progress of a multi-stage job: each stage's start with elapsed time and time left.

    The estimate of the time left scales the prior costs (``weights``, any unit) of the
    stages still to run by the measured cost of the stages done so far, so it improves as
    the job goes on. Each stage's wall time (``times``) and CPU time of the process tree
    (``cpu_times``, :func:`process_tree_cpu_time`) are kept; :meth:`summary` lists them.

    Parameters
    ----------
    weights
        ``{stage name: prior cost}`` in run order. A stage of prior cost 0 is timed and
        listed but left out of the estimate (its cost is not proportional to the others').
    enabled
        Print (to ``stream``) or stay silent.
    """

    def __init__(
        self, weights: Mapping[str, float], *, enabled: bool = True, stream: TextIO | None = None
    ) -> None:
        self._weights = {str(k): max(float(v), 0.0) for k, v in weights.items()}
        self._enabled = bool(enabled)
        self._stream = stream
        self._t0 = time.perf_counter()
        self._done_weight = 0.0
        self._done_time = 0.0
        self.times: dict[str, float] = {}
        self.cpu_times: dict[str, float] = {}

    def _left(self, name: str) -> float | None:
        names = list(self._weights)
        rest = sum(self._weights[n] for n in names[names.index(name) :] if n not in self.times)
        if self._done_weight <= 0.0:
            return None
        return rest * self._done_time / self._done_weight

    @staticmethod
    def _clock(seconds: float) -> str:
        minutes, s = divmod(round(seconds), 60)
        return f"{minutes} min {s:02d} s" if minutes else f"{s} s"

    @contextlib.contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Time one stage (a name of ``weights``) and print its start line."""
        if name not in self._weights:
            raise ValueError(f"unknown stage {name!r}; stages: {list(self._weights)}.")
        if self._enabled:
            k = list(self._weights).index(name) + 1
            left = self._left(name)
            eta = "estimating time left" if left is None else f"about {self._clock(left)} left"
            elapsed = self._clock(time.perf_counter() - self._t0)
            print(
                f"[{k}/{len(self._weights)}] {name} (elapsed {elapsed}, {eta})",
                file=self._stream or sys.stderr,
                flush=True,
            )
        t = time.perf_counter()
        cpu = process_tree_cpu_time()
        try:
            yield
        finally:
            spent = time.perf_counter() - t
            self.cpu_times[name] = process_tree_cpu_time() - cpu
            self.times[name] = spent
            if self._weights[name] > 0.0:
                self._done_time += spent
                self._done_weight += self._weights[name]

    def summary(self) -> pd.DataFrame:
        """Wall and CPU minutes of each stage run so far, with a total row."""
        names = [n for n in self._weights if n in self.times]
        frame = pd.DataFrame(
            {
                "wall_min": [self.times[n] / 60.0 for n in names],
                "cpu_min": [self.cpu_times[n] / 60.0 for n in names],
            },
            index=pd.Index(names, name="stage"),
        )
        frame.loc["total"] = frame.sum()
        return frame

    def report(self) -> None:
        """Print :meth:`summary` (when enabled), one line per stage."""
        if not self._enabled:
            return
        stream = self._stream or sys.stderr
        for name, row in self.summary().iterrows():
            print(
                f"  {name}: wall {row['wall_min']:.1f} min, CPU {row['cpu_min']:.1f} min",
                file=stream,
                flush=True,
            )


# --------------------------------------------------------------------------- verdicts


def motion_verdict(
    series: xr.Dataset,
    *,
    variables: Sequence[str] | None = ("X", "Y"),
    drive_period: float | None = None,
    phase_variable: str | None = "crank_angle",
    exponent: Any = None,
    n_surrogates: int = 19,
    rng: Any = 0,
) -> chaoskit.MotionVerdict:
    """The verdict of one state's motion: :func:`chaoskit.classify_motion` of its series.

    ``series`` holds the state's analysed series (by default ``X`` and ``Y``, the journal
    centre of joint C, and the crank angle as the drive's phase); ``exponent`` is the
    largest exponent from the equations of motion of the same state
    (:func:`mechanism.lyapunov_exponent`), a vote beside the data. The study's report
    computes the same verdict for every state (:func:`chaoskit.report` with
    ``exponents=``) and its summary shows it.
    """
    return chaoskit.classify_motion(
        series,
        variables=variables,
        drive_period=drive_period,
        phase_variable=phase_variable,
        exponent=exponent,
        n_surrogates=n_surrogates,
        rng=rng,
    )


def _agrees(ours: str, claim: str) -> str:
    if ours in ("undetermined", "noise-like"):
        return "cannot tell"
    if claim == "chaotic":
        return "agree" if ours == "chaotic" else "disagree"
    return "agree" if ours in _REGULAR else "disagree"


# --------------------------------------------------------------------------- the section


def _model_of(result: Any) -> str:
    """The model a :func:`mechanism.lyapunov_exponent` result ran: "flexible" or "rigid"."""
    settings = getattr(result, "settings", None) or {}
    return str(settings.get("model", "rigid"))


def _ci(result: Any) -> tuple[float, float, float]:
    if result is None:
        return (math.nan, math.nan, math.nan)
    lo, hi = result.ci
    return (float(result.exponent), float(lo), float(hi))


def summary_section(
    *,
    states: Sequence[str],
    motions: Mapping[str, chaoskit.MotionVerdict],
    chaos: pd.DataFrame,
    paper_chaos: pd.DataFrame,
    claims: Mapping[str, Mapping[str, str]],
    equations: Mapping[str, Any],
    paper_step: float,
    settings_text: str,
    figures: Sequence[chaoskit.ReportFigure] = (),
    series_rods: str = "flexible",
    rigid_equations: Mapping[str, Any] | None = None,
) -> chaoskit.ReportSection:
    """The report's opening section: verdict per state, exponents, the paper beside ours.

    Parameters
    ----------
    states
        State labels in print order (``"before wear"``, ``"after wear"``).
    motions
        ``{state: MotionVerdict}``: one verdict per state from all its series and the
        equations' exponent (``chaoskit.Report.motions``, or :func:`motion_verdict`).
    chaos
        Our chaos table (index ``(variable, state)``; ``mle_wolf``, ``mle_rosenstein`` and
        their ``_low``/``_high`` bounds in 1/s).
    paper_chaos
        The paper's chaos table (``mle_wolf_bits`` in bits per sample of ``paper_step``).
    claims
        ``{state: {"motion": "chaotic" | "not chaotic", "text": ...}}``: the paper's claim.
    equations
        ``{state: SceneLyapunov or None}`` from :func:`mechanism.lyapunov_exponent` on the
        model of the analysed series.
    paper_step
        The paper's sampling step (s): bits per sample are λ·Δt/ln 2 at this Δt.
    settings_text
        One sentence on what was simulated (revolutions, step, rods); printed after the
        tables and figures (the section opens with the answer in one sentence).
    figures
        Headline figures shown under the tables.
    series_rods
        What rods the analysed series come from (printed in the captions).
    rigid_equations
        ``{state: SceneLyapunov}`` of the rigid-rod model, shown beside a flexible one.
    """
    to_bits = paper_step / _LN2
    answer, opening = _answer(states, motions, claims)

    exponents = _exponent_rows(
        states=states,
        chaos=chaos,
        paper_chaos=paper_chaos,
        equations=equations,
        rigid_equations=rigid_equations or {},
        claims=claims,
        to_bits=to_bits,
    )
    marks = _set_aside(exponents, motions)
    tables = (
        chaoskit.ReportTable(
            caption="The answer: the motion of the journal centre before and after wear, our "
            "verdict and its confidence beside the paper's claim.",
            data=answer,
            labels={
                "verdict": "our verdict",
                "confidence": "confidence",
                "paper": "paper's claim",
                "agreement": "agreement",
                "why": "why",
            },
            formats={"confidence": CONFIDENCE_FORMAT},
            notes='"why" names the evidence that decided our verdict over the evidence it '
            "overruled (all of it: the motion verdict's table and the appendix). "
            + CONFIDENCE_NOTE,
            section="Summary",
        ),
        _exponent_table(
            exponents,
            marks,
            rigid=bool(rigid_equations),
            series_rods=series_rods,
            paper_step=paper_step,
        ),
    )
    return chaoskit.ReportSection(
        title="Summary", items=(*tables, *figures), text=opening, footer=settings_text
    )


def _answer(
    states: Sequence[str],
    motions: Mapping[str, chaoskit.MotionVerdict],
    claims: Mapping[str, Mapping[str, str]],
) -> tuple[pd.DataFrame, str]:
    """The answer table (verdict, confidence, the paper's claim, agreement, why) and the
    section's opening sentence."""
    answer_rows = []
    for state in states:
        mv = motions.get(state)
        claim = claims.get(state, {})
        ours = mv.label if mv is not None else "not run"
        agree = _agrees(ours, claim.get("motion", "")) if mv is not None else "—"
        why = "this state was not simulated"
        if mv is not None:
            # one line: the evidence that decided over the evidence it overruled
            aside = [r for r in mv.reasons if r.startswith("set aside")]
            why = "; ".join([decided_by(mv), *aside])
        answer_rows.append(
            {
                "verdict": ours,
                "confidence": mv.confidence if mv is not None else math.nan,
                "paper": claim.get("motion", "—"),
                "agreement": agree,
                "why": f"ours: {why}; paper: {claim.get('text', '—')}",
            }
        )
    answer = pd.DataFrame(answer_rows, index=pd.Index(list(states), name="state"))
    opening = " ".join(
        f"{state[:1].upper()}{state[1:]}: {row['verdict']}"
        + (
            f" (confidence {format_confidence(row['confidence'])})"
            if math.isfinite(row["confidence"])
            else ""
        )
        + f"; the paper: {row['paper']} ({row['agreement']})."
        for state, row in zip(states, answer_rows, strict=True)
    )
    return answer, opening


def _exponent_table(
    exponents: pd.DataFrame,
    marks: Mapping[tuple[Any, str], str],
    *,
    rigid: bool,
    series_rods: str,
    paper_step: float,
) -> chaoskit.ReportTable:
    """The summary's table of the largest exponent per state, from the equations and the
    data, beside the paper's."""
    return chaoskit.ReportTable(
        caption="Largest Lyapunov exponent [95 % interval] of each state: from the "
        "equations of motion (of the model of the series"
        + (", and of the same state with rigid rods" if rigid else "")
        + ") and from the journal-centre series X and Y by Wolf's and "
        "Rosenstein's methods "
        f"({series_rods} rods), in 1/s and in bits per sample of the paper's step "
        f"Δt = {paper_step:.3g} s, beside the paper's Wolf values.",
        data=exponents,
        labels={
            "per_s": "λ (1/s)",
            "bits": "λ (bit/sample)",
            "paper_bits": "paper (bit/sample)",
            "sign": "sign vs paper",
        },
        intervals={
            "per_s": ("per_s_low", "per_s_high"),
            "bits": ("bits_low", "bits_high"),
        },
        digits=3,
        marks=marks,
        notes=(SET_ASIDE_NOTE if marks else "")
        + "Positive means nearby motions separate (chaos); an interval that contains 0 "
        "does not decide; an unbounded interval means the estimator found no "
        "straight scaling region. The exponent from the equations follows an "
        "infinitesimal perturbation of the full state (docs/mechanism-lyapunov.md) and is "
        "compared with the paper's claim; the data estimators run on the series "
        f"({series_rods} rods) and are compared with the paper's value of the same "
        "series. The data see separation only from the distance of the series' nearest "
        "neighbours up, so an exponent set by the growth of perturbations far below that "
        "scale (at impacts) shows in the equations only. Only signs are compared: our "
        "step, series length and model differ (docs/paper-model.md).",
        section="Summary",
    )


def _says_chaotic(row: pd.Series, verdict: Any, estimate: str) -> bool | None:
    """Whether one exponent row points to chaos: the verdict's own call on that estimator
    ("clearly positive") when the series' verdict has it, else its interval above 0."""
    method, _, series = estimate.partition(", ")
    v = getattr(verdict, "variables", {}).get(series) if series else None
    flag = getattr(v, f"{method.lower()}_positive", None) if v is not None else None
    if flag is not None:
        return bool(flag)
    low = float(row["per_s_low"])
    if math.isnan(low):
        return None if math.isnan(float(row["per_s"])) else bool(row["per_s"] > 0.0)
    return low > 0.0


def _set_aside(exponents: pd.DataFrame, motions: Mapping[str, Any]) -> dict[tuple[Any, str], str]:
    """Exponent cells that point the other way from their state's decided verdict."""
    marks: dict[tuple[Any, str], str] = {}
    for (state, estimate), row in exponents.iterrows():
        mv = motions.get(state)
        label = getattr(mv, "label", "undetermined")
        if label not in (*_REGULAR, "chaotic"):
            continue  # undetermined (nothing decided) or noise-like
        chaotic = _says_chaotic(row, mv, str(estimate))
        if chaotic is not None and chaotic != (label == "chaotic"):
            for col in ("per_s", "bits"):
                marks[((state, estimate), col)] = SET_ASIDE
    return marks


def _claim_agreement(estimate: tuple[float, float, float], claim: str) -> str:
    """Does λ (value, low, high) agree with the paper's claim ("chaotic": λ > 0)?"""
    if not math.isfinite(estimate[0]) or claim not in ("chaotic", "not chaotic"):
        return "—"
    side = _sign_word(*estimate)
    if claim == "chaotic":
        return {1: "agrees with claim", 0: "cannot tell", -1: "contradicts claim"}[side]
    return "contradicts claim" if side == 1 else "agrees with claim"


def _sign_word(ours: float, low: float, high: float) -> int:
    """+1 or −1 when the 95 % interval (or, without one, the value) lies on one side of
    zero; 0 when it contains zero or is missing."""
    if math.isnan(low) or math.isnan(high):
        return int(np.sign(ours)) if math.isfinite(ours) else 0
    return 1 if low > 0.0 else (-1 if high < 0.0 else 0)


def _exponent_rows(
    *,
    states: Sequence[str],
    chaos: pd.DataFrame,
    paper_chaos: pd.DataFrame,
    equations: Mapping[str, Any],
    rigid_equations: Mapping[str, Any],
    claims: Mapping[str, Mapping[str, str]],
    to_bits: float,
) -> pd.DataFrame:
    """One row per (state, estimate): λ in 1/s and bits per sample with intervals, the
    paper's Wolf value of the same series and whether the signs agree (for the equations'
    exponent: whether its sign agrees with the paper's claim, chaotic meaning λ > 0)."""
    series = sorted({str(v) for v in chaos.index.get_level_values("variable")}) or ["X", "Y"]
    rows, keys = [], []
    for state in states:
        claim_sign = {
            s: float(paper_chaos.at[(s, state), "mle_wolf_bits"])
            for s in series
            if (s, state) in paper_chaos.index
        }
        estimates: list[tuple[str, tuple[float, float, float], float]] = []
        for result in (equations.get(state), rigid_equations.get(state)):
            if result is None and keys and keys[-1][0] == state:
                continue  # no rigid-rod companion
            eq = _ci(result)
            rows.append(
                {
                    "per_s": eq[0],
                    "per_s_low": eq[1],
                    "per_s_high": eq[2],
                    "bits": eq[0] * to_bits,
                    "bits_low": eq[1] * to_bits,
                    "bits_high": eq[2] * to_bits,
                    "paper_bits": math.nan,
                    "sign": _claim_agreement(eq, claims.get(state, {}).get("motion", "")),
                }
            )
            keys.append((state, f"equations ({_model_of(result)} rods)"))
        for method in ("wolf", "rosenstein"):
            for name in series:
                key = (name, state)
                values = tuple(
                    float(chaos.at[key, f"mle_{method}{suffix}"])
                    if key in chaos.index and f"mle_{method}{suffix}" in chaos.columns
                    else math.nan
                    for suffix in ("", "_low", "_high")
                )
                estimates.append(
                    (
                        f"{method.capitalize()}, {name}",
                        (values[0], values[1], values[2]),
                        claim_sign.get(name, math.nan),
                    )
                )
        for label, (value, low, high), theirs in estimates:
            ours = _sign_word(value, low, high)
            if not math.isfinite(theirs) or not math.isfinite(value):
                sign = "—"
            elif ours == 0:
                sign = "cannot tell"
            else:
                sign = "agree" if ours == int(np.sign(theirs)) else "disagree"
            rows.append(
                {
                    "per_s": value,
                    "per_s_low": low,
                    "per_s_high": high,
                    "bits": value * to_bits,
                    "bits_low": low * to_bits,
                    "bits_high": high * to_bits,
                    "paper_bits": theirs,
                    "sign": sign,
                }
            )
            keys.append((state, label))
    return pd.DataFrame(
        rows, index=pd.MultiIndex.from_tuples(keys, names=["state", "estimate"])
    ).astype({"sign": object})


def strobe_points(
    trajectory: xr.Dataset, *, joint: str = "C", motion: Any = None, discard: float = 0.0
) -> xr.Dataset:
    """The stroboscopic points (e_x, e_y once per crank revolution, m) a figure shows.

    With ``motion`` (the state's :class:`chaoskit.MotionVerdict`) exactly the points of its
    joint section: the instants the verdict counted (its "joint section" points), after
    the transient and never the initial state. Without one, the points after ``discard``
    (s), the first sample excluded: the initial state is a strobe instant of the crank
    angle (0 at t = 0) but no point of the motion.
    """
    view = trajectory[["eccentricity_x", "eccentricity_y", "crank_angle"]]
    if "joint" in view.dims:
        view = view.sel(joint=joint, drop=True)
    points = chaoskit.stroboscopic_map(
        view, phase_variable="crank_angle", coords=["eccentricity_x", "eccentricity_y"]
    )
    t = np.asarray(points["time"].values, dtype=np.float64)
    section = getattr(motion, "section", None)
    if section is not None and "time" in section.coords and t.size:
        wanted = np.asarray(section["time"].values, dtype=np.float64)
        spacing = float(np.median(np.diff(t))) if t.size > 1 else math.inf
        nearest = np.abs(t[:, None] - wanted[None, :]).argmin(axis=0)
        close = np.abs(t[nearest] - wanted) <= 0.25 * spacing
        return points.isel(crossing=np.unique(nearest[close]))
    start = float(view["time"].values[0])
    slack = 1e-9  # s: a strobe instant found on a sample, up to rounding, is on it
    keep = (t >= start + discard - slack) & (t > start + slack)
    return points.isel(crossing=np.flatnonzero(keep))


def strobe_figure(
    trajectories: Mapping[str, xr.Dataset],
    *,
    joint: str = "C",
    motions: Mapping[str, Any] | None = None,
    discard: float = 0.0,
) -> Any:
    """Stroboscopic maps (e_x, e_y once per crank revolution, mm) of each state, side by
    side: the points of :func:`strobe_points` (those of each state's motion verdict when
    ``motions`` has it), their number in each panel's title."""
    from matplotlib.figure import Figure

    n = max(len(trajectories), 1)
    fig = Figure(figsize=(4.2 * n, 4.0), layout="constrained")
    axes = fig.subplots(1, n, squeeze=False)[0]
    for ax, (state, traj) in zip(axes, trajectories.items(), strict=False):
        motion = (motions or {}).get(state)
        points = strobe_points(traj, joint=joint, motion=motion, discard=discard)
        x = np.asarray(points["eccentricity_x"].values) * 1e3
        y = np.asarray(points["eccentricity_y"].values) * 1e3
        ax.plot(x, y, ".", ms=3, color="C0" if "before" in state else "C3", rasterized=True)
        ax.set_title(f"{state}: {plural(x.size, 'point')}", fontsize=10)
        ax.set_xlabel("journal-centre e_x (mm)")
        ax.set_ylabel("journal-centre e_y (mm)")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    return fig
