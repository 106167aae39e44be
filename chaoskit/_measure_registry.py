"""The registry of further measures (D2, RQA, Lyapunov spectrum, SampEn, DFA, Hurst) as one
step of an analysis: their names, how each runs, its table columns and its figure.

Used by ``chaoskit analyze --measures`` and by :func:`chaoskit.report` (``measures=``).
Each measure runs with the delay and embedding dimension the verdict chose; series longer
than a measure's limit are cut to their last samples, and the table says so.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import pandas as pd

from . import plot
from .complexity import MAX_SAMPLES, detrended_fluctuation, hurst_exponent, sample_entropy
from .dimension import correlation_dimension
from .lyapunov import lyapunov_spectrum
from .recurrence import recurrence_analysis

__all__ = ["MEASURES", "compute_measures", "measure_figures", "measures_row", "parse_measures"]

MEASURES = ("d2", "rqa", "spectrum", "sampen", "dfa", "hurst")
RQA_MAX_SAMPLES = 10_000  # RQA at RR = 5 %: 5·10⁶ recurrences, well inside memory

LABELS = {
    "d2": "D2",
    "d2_low": "D2 low",
    "d2_high": "D2 high",
    "d2_saturated": "D2 saturated",
    "rqa_rr": "RR",
    "rqa_det": "DET",
    "rqa_lam": "LAM",
    "rqa_l_mean": "L mean",
    "rqa_entr": "ENTR (nat)",
    "rqa_tt": "TT",
    "lambda_1": "λ1",
    "lambda_2": "λ2",
    "lambda_sum": "Σλ",
    "spurious": "λ unconfirmed",
    "sample_entropy": "SampEn (nat)",
    "dfa_alpha": "DFA α",
    "hurst": "Hurst H",
}


def parse_measures(text: str | Sequence[str] | None) -> tuple[str, ...]:
    """``"d2,rqa"`` (or ``"all"``, or a sequence of names) as a validated tuple."""
    if text is None:
        return ()
    items = text.split(",") if isinstance(text, str) else list(text)
    names = [s.strip().lower() for s in items if s.strip()]
    if names == ["all"]:
        return MEASURES
    bad = [n for n in names if n not in MEASURES]
    if bad:
        raise ValueError(
            f"measures must be a comma-separated subset of {', '.join(MEASURES)} (or all); "
            f"got {', '.join(bad)}."
        )
    return tuple(dict.fromkeys(names))


def _tail(x: np.ndarray, limit: int) -> np.ndarray:
    return x[-limit:] if x.size > limit else x


def compute_measures(
    x: Any,
    names: Sequence[str],
    *,
    dt: float,
    lag: int | None,
    embedding_dim: int | None,
    units: str = "1",
    rng: int = 0,
) -> dict[str, Any]:
    """Run each named measure; a measure that cannot run gives its error message instead."""
    arr = np.asarray(getattr(x, "values", x), dtype=np.float64).ravel()
    lag = lag or None
    m = max(2, min(int(embedding_dim or 3), 11))
    runs: dict[str, Callable[[], Any]] = {
        "d2": lambda: correlation_dimension(arr, lag=lag, units=units, rng=rng),
        "rqa": lambda: recurrence_analysis(
            _tail(arr, RQA_MAX_SAMPLES),
            embedding_dim=m,
            lag=lag or 1,
            recurrence_rate=0.05,
            theiler_window=1,
            units=units,
            rng=rng,
        ),
        "spectrum": lambda: lyapunov_spectrum(arr, embedding_dim=m, lag=lag, dt=dt),
        "sampen": lambda: sample_entropy(_tail(arr, MAX_SAMPLES["sample_entropy"])),
        "dfa": lambda: detrended_fluctuation(_tail(arr, MAX_SAMPLES["dfa"])),
        "hurst": lambda: hurst_exponent(_tail(arr, MAX_SAMPLES["hurst_rs"])),
    }
    out: dict[str, Any] = {}
    for name in names:
        try:
            out[name] = runs[name]()
        except ValueError as exc:
            out[name] = str(exc)
    return out


_COLUMNS: dict[str, tuple[tuple[str, Callable[[Any], float]], ...]] = {
    "d2": (
        ("d2", lambda r: r.d2),
        ("d2_low", lambda r: r.interval[0]),
        ("d2_high", lambda r: r.interval[1]),
        ("d2_saturated", lambda r: float(r.saturated)),
    ),
    "rqa": (
        ("rqa_rr", lambda r: r.recurrence_rate),
        ("rqa_det", lambda r: r.determinism),
        ("rqa_lam", lambda r: r.laminarity),
        ("rqa_l_mean", lambda r: r.mean_diagonal),
        ("rqa_entr", lambda r: r.entropy),
        ("rqa_tt", lambda r: r.trapping_time),
    ),
    "spectrum": (
        ("lambda_1", lambda r: r.exponents[0]),
        ("lambda_2", lambda r: r.exponents[1]),
        ("lambda_sum", lambda r: r.sum_exponents),
        ("spurious", lambda r: float(r.spurious.sum())),
    ),
    "sampen": (("sample_entropy", lambda r: r.value),),
    "dfa": (("dfa_alpha", lambda r: r.value),),
    "hurst": (("hurst", lambda r: r.value),),
}

#: (figure kind, caption, name of the chaoskit.plot function) per measure with a figure
_FIGURES = {
    "d2": (
        "local_slopes",
        "local slopes of the correlation sum, one line per embedding dimension",
        "local_slopes",
    ),
    "rqa": ("recurrence_plot", "recurrence plot at a 5 % recurrence rate", "recurrence_plot"),
    "spectrum": (
        "lyapunov_spectrum",
        "running estimates of the Lyapunov spectrum",
        "lyapunov_spectrum",
    ),
}


def measures_row(results: dict[str, Any]) -> dict[str, float]:
    """Flat numbers for a table row (NaN where a measure failed)."""
    row: dict[str, float] = {}
    for name, res in results.items():
        for key, get in _COLUMNS[name]:
            row[key] = float("nan") if isinstance(res, str) else float(get(res))
    return row


def _drawer(func: Callable[..., Any], result: Any) -> Callable[[Any], Any]:
    def draw(ax: Any) -> Any:
        return func(result, ax=ax)

    return draw


def measure_figures(results: dict[str, Any]) -> list[tuple[str, str, Callable[[Any], Any]]]:
    """``(kind, caption, draw(ax))`` for each measure that has a figure and succeeded."""
    figs: list[tuple[str, str, Callable[[Any], Any]]] = []
    for name, res in results.items():
        if name in _FIGURES and not isinstance(res, str):
            kind, caption, func = _FIGURES[name]
            figs.append((kind, caption, _drawer(getattr(plot, func), res)))
    return figs


def measures_for_verdicts(
    ds: Any, verdicts: dict[str, Any], names: Sequence[str], *, rng: int = 0
) -> dict[str, dict[str, Any]]:
    """The measures of every classified variable of a trajectory (skips equilibria)."""
    out: dict[str, dict[str, Any]] = {}
    for name, verdict in verdicts.items():
        if verdict.label == "equilibrium":
            continue
        var = ds[name]
        out[name] = compute_measures(
            var.values,
            names,
            dt=verdict.dt,
            lag=verdict.lag,
            embedding_dim=verdict.embedding_dim,
            units=str(var.attrs.get("units", "1")),
            rng=rng,
        )
    return out


def measures_text(results: dict[str, dict[str, Any]]) -> str:
    """A fixed-width table of the measures, one row per variable, with failures listed."""
    frame = pd.DataFrame({name: measures_row(res) for name, res in results.items()}).T
    frame = frame.rename(columns=LABELS)
    lines = [frame.to_string(float_format=lambda v: f"{v:.4g}", na_rep="—")]
    for name, res in results.items():
        for measure, value in res.items():
            if isinstance(value, str):
                lines.append(f"{name} {measure}: {value}")
    lines.append(
        f"(RQA on the last {RQA_MAX_SAMPLES} samples at most, embedding of the verdict, "
        "RR = 5 %; SampEn and DFA on at most their length limits.)"
    )
    return "\n".join(lines)
