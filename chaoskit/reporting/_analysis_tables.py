"""The analysis tables of a report: motion verdict, verdicts, chaos table and evidence.

Built from the analysed states of :func:`chaoskit.report` (one per trajectory);
the chaos table sets a reference (e.g. a paper's values) beside ours when one is given.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import pandas as pd

from .._selection import VariableSpec
from ._answer import CONFIDENCE_FORMAT, CONFIDENCE_NOTE, decided_by, plural
from ._content import ReportTable, format_number
from ._model import APPENDIX, MOTION
from ._states import State, sampling_step

__all__ = [
    "CHAOS_COLUMNS",
    "SET_ASIDE_MARK",
    "SET_ASIDE_NOTE",
    "analysis_tables",
    "set_aside_marks",
]

_LN2 = math.log(2.0)

#: Columns of the chaos table (see :func:`report`); the reference table uses these names.
CHAOS_COLUMNS = (
    "lag",
    "lag_time",
    "embedding_dim",
    "mle_wolf",
    "mle_wolf_low",
    "mle_wolf_high",
    "mle_wolf_bits",
    "mle_wolf_bits_low",
    "mle_wolf_bits_high",
    "mle_rosenstein",
    "mle_rosenstein_low",
    "mle_rosenstein_high",
    "mle_rosenstein_bits",
    "mle_rosenstein_bits_low",
    "mle_rosenstein_bits_high",
    "verdict",
    "confidence",
)
_VOTES = ("section", "rosenstein", "wolf", "zero_one", "surrogates")


def _chaos_frame(states: list[State], specs: list[VariableSpec]) -> pd.DataFrame:
    rows, keys = [], []
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            s = v.summary()
            row = {c: s.get(c, float("nan")) for c in CHAOS_COLUMNS if c in s}
            for method in ("wolf", "rosenstein"):
                res = getattr(v, method)
                factor = float(v.dt) / _LN2
                lo, hi = (float("nan"), float("nan")) if res is None else res.ci
                row[f"mle_{method}_bits_low"] = lo * factor
                row[f"mle_{method}_bits_high"] = hi * factor
            row["verdict"] = v.label
            keys.append((spec.alias, st.label))
            rows.append({c: row.get(c, float("nan")) for c in CHAOS_COLUMNS})
    index = pd.MultiIndex.from_tuples(keys, names=["variable", "state"])
    frame = pd.DataFrame(rows, index=index, columns=list(CHAOS_COLUMNS))
    return frame.astype({c: object for c in ("verdict",)})


#: Footnote of the estimates a verdict did not follow (see :func:`set_aside_marks`).
SET_ASIDE_MARK = "†"
SET_ASIDE_NOTE = (
    f"{SET_ASIDE_MARK} set aside: the verdict of this variable and state did not follow this "
    "estimate — it points the other way (clearly positive for a regular label, or not clearly "
    "positive for chaos) and the other evidence decided (votes in the appendix)."
)


def set_aside_marks(states: list[State], specs: list[VariableSpec]) -> dict[tuple[Any, str], str]:
    """Chaos-table cells of the exponents that the row's verdict voted against."""
    marks: dict[tuple[Any, str], str] = {}
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            if v.label == "undetermined":
                continue  # nothing was decided, so nothing was set aside
            for method in ("wolf", "rosenstein"):
                if v.votes.get(method) == "opposes":
                    for col in (f"mle_{method}", f"mle_{method}_bits"):
                        marks[((spec.alias, st.label), col)] = SET_ASIDE_MARK
    return marks


def _chaos_labels(kind: str) -> dict[str, str]:
    per = "1/iteration" if kind == "map" else "1/s"
    return {
        "lag": "lag (samples)",
        "lag_time": "lag (iterations)" if kind == "map" else "lag (s)",
        "embedding_dim": "embedding dimension",
        "mle_wolf": f"MLE Wolf ({per}) [95% CI]",
        "mle_wolf_bits": "MLE Wolf (bit/sample) [95% CI]",
        "mle_rosenstein": f"MLE Rosenstein ({per}) [95% CI]",
        "mle_rosenstein_bits": "MLE Rosenstein (bit/sample) [95% CI]",
        "verdict": "verdict",
        "confidence": "confidence",
    }


def _chaos_intervals() -> dict[str, tuple[str, str]]:
    out = {}
    for method in ("wolf", "rosenstein"):
        for suffix in ("", "_bits"):
            base = f"mle_{method}{suffix}"
            out[base] = (f"{base}_low", f"{base}_high")
    return out


def _evidence_frame(states: list[State], specs: list[VariableSpec]) -> pd.DataFrame:
    rows, keys = [], []
    for spec in specs:
        for st in states:
            v = st.verdicts[spec.alias]
            s = v.summary()
            row: dict[str, Any] = {
                "verdict": v.label,
                "period": s["period"],
                "confidence": s["confidence"],
            }
            for name in _VOTES:
                row[f"vote_{name}"] = v.votes.get(name, "missing")
            row.update(
                zero_one_k=s["zero_one_k"],
                surrogate_p_value=s["surrogate_p_value"],
                section_structure=s["section_structure"],
                section_points=s["section_points"],
                n_samples=s["n_samples"],
                dt=s["dt"],
                reason=v.reason,
            )
            rows.append(row)
            keys.append((spec.alias, st.label))
    index = pd.MultiIndex.from_tuples(keys, names=["variable", "state"])
    return pd.DataFrame(rows, index=index).astype(object)


_EVIDENCE_LABELS = {
    "period": "period k",
    "vote_section": "section",
    "vote_rosenstein": "Rosenstein",
    "vote_wolf": "Wolf",
    "vote_zero_one": "0-1 test",
    "vote_surrogates": "surrogates",
    "zero_one_k": "0-1 K",
    "surrogate_p_value": "surrogate p",
    "section_structure": "section structure",
    "section_points": "section points",
    "n_samples": "samples",
    "dt": "dt",
}


def _motion_table(states: list[State], kind: str) -> ReportTable:
    """One row per state: the motion verdict and the joint evidence it rests on."""
    rows, index = [], []
    for st in states:
        mv = st.motion
        if mv is None:
            continue
        row = mv.summary()
        rows.append(
            {
                "verdict": mv.label if mv.period is None else f"{mv.label} (period {mv.period})",
                "confidence": mv.confidence,
                "section": _joint_section_text(
                    row["motion_section_structure"], row["motion_section_points"]
                ),
                "mle": row["motion_mle"],
                "mle_low": row["motion_mle_low"],
                "mle_high": row["motion_mle_high"],
                "equations": row["motion_mle_equations"],
                "equations_low": row["motion_mle_equations_low"],
                "equations_high": row["motion_mle_equations_high"],
                "set_aside": ", ".join((*mv.drive_variables, *mv.constant_variables)) or "—",
                "why": decided_by(mv),
            }
        )
        index.append(st.label)
    unit = "1/iteration" if kind == "map" else "1/s"
    return ReportTable(
        caption="The motion verdict: one label per state from all its analysed variables "
        "together — their joint section, the largest exponent of their mixed delay "
        "embedding, the exponent from the equations of motion when given, and each "
        "variable's verdict (docs/verdict.md). Variables that follow the drive alone are set "
        'aside; "why" names the evidence that decided.',
        data=pd.DataFrame(rows, index=pd.Index(index, name="state")),
        labels={
            "verdict": "motion verdict",
            "confidence": "confidence",
            "section": "joint section",
            "mle": f"joint MLE ({unit})",
            "equations": f"equations MLE ({unit})",
            "set_aside": "set aside",
            "why": "why",
        },
        intervals={
            "mle": ("mle_low", "mle_high"),
            "equations": ("equations_low", "equations_high"),
        },
        digits=3,
        formats={"confidence": CONFIDENCE_FORMAT},
        notes=CONFIDENCE_NOTE,
        section=MOTION,
    )


def _joint_section_text(structure: str, points: float) -> str:
    """``"clusters (198 points)"``; ``"none"`` when there is no joint section."""
    if not math.isfinite(points):
        return str(structure)
    return f"{structure} ({plural(int(points), 'point')})"


def _overview_frame(states: list[State], specs: list[VariableSpec]) -> pd.DataFrame:
    data = {}
    for st in states:
        col = []
        for spec in specs:
            v = st.verdicts[spec.alias]
            text = v.label if v.period is None else f"{v.label} (period {v.period})"
            col.append(text)
        data[st.label] = col
    return pd.DataFrame(data, index=pd.Index([s.alias for s in specs], name="variable"))


def analysis_tables(
    states: list[State],
    specs: list[VariableSpec],
    put: Callable[..., None],
    texts: dict[str, str],
    *,
    kind: str,
    motion: bool,
    chaos_reference: pd.DataFrame | None,
    reference_name: str,
    chaos_notes: str,
) -> None:
    """Put the motion verdict, verdicts, chaos and evidence tables; the chaos section text."""
    if motion:
        put(_motion_table(states, kind), MOTION)
    described = "; ".join(
        f"{s.alias} = {s.spec} ({states[0].view[s.alias].attrs.get('long_name', s.name)}, "
        f"{states[0].view[s.alias].attrs.get('units', '')})"
        for s in specs
    )
    put(
        ReportTable(
            caption=f"Verdict per variable and state. Variables: {described}.",
            data=_overview_frame(states, specs),
        ),
        "Verdicts",
    )
    texts["Chaos identification"] = (
        "Delay τ from the delay curve, embedding dimension m from false nearest neighbours, "
        "largest Lyapunov exponent (MLE) by Wolf's and Rosenstein's methods with 95 % "
        "intervals, in "
        + ("1/iteration" if kind == "map" else "1/s (natural log)")
        + " and in bits per sample (λ·Δt/ln 2, the unit of Wolf's program and of most "
        "papers). The verdict combines all evidence (docs/verdict.md)."
    )
    frame = _chaos_frame(states, specs)
    ref = None
    if chaos_reference is not None:
        if not isinstance(chaos_reference, pd.DataFrame):
            raise ValueError("chaos_reference must be a pandas DataFrame.")
        unknown = [c for c in chaos_reference.columns if c not in CHAOS_COLUMNS]
        if unknown:
            raise ValueError(
                f"chaos_reference has columns {unknown} that the chaos table does not have; "
                f"use {list(CHAOS_COLUMNS)}."
            )
        if chaos_reference.index.nlevels != 2:
            raise ValueError("chaos_reference must be indexed by (variable, state).")
        ref = chaos_reference
    dts = sorted({format_number(sampling_step(st.view)) for st in states})
    marks = set_aside_marks(states, specs)
    notes = " ".join(
        n
        for n in (chaos_notes, SET_ASIDE_NOTE if marks else "", "" if motion else CONFIDENCE_NOTE)
        if n
    )
    put(
        ReportTable(
            caption=(
                "Chaos table: embedding and largest Lyapunov exponent per variable and state "
                f"(analysed sampling interval Δt = {', '.join(dts)} "
                + ("iterations" if kind == "map" else "s")
                + ")."
            ),
            data=frame,
            reference=ref,
            reference_name=reference_name,
            intervals=_chaos_intervals(),
            labels=_chaos_labels(kind),
            # beside a reference, one row per quantity keeps the table at five columns
            layout="long" if ref is not None else "wide",
            formats={"confidence": CONFIDENCE_FORMAT},
            marks=marks,
            notes=notes,
            section="Chaos identification",
        )
    )
    put(
        ReportTable(
            caption=(
                "Evidence behind each verdict: how each test voted (supports / opposes / "
                "neutral / missing), the 0-1 test's K, the surrogate test's p-value, the "
                "structure of the section set, and the rule that fired."
            ),
            data=_evidence_frame(states, specs),
            labels=_EVIDENCE_LABELS,
            formats={"confidence": CONFIDENCE_FORMAT},
            layout="long",
            section=APPENDIX,
        )
    )
