"""The report's wear-life answer: the five wear paths' cycles to chaos and the paper's
transition claims judged on them, the first thing the summary says."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd

import chaoskit
from chaoskit.reporting import CONFIDENCE_FORMAT, CONFIDENCE_NOTE, format_confidence, plural

from ._claims import ClaimVerdict, PathOutcome, cycles_text, path_label, path_outcome
from ._published import WEAR_PATHS
from ._schedule import wear_path_cost
from ._settings import StudySettings


def wear_paths_design(settings: StudySettings) -> str:
    """One sentence on how the paths were run (rods, cycles, checkpoints, analysis)."""
    if settings.wear_path_flexible_rods:
        rods = "flexible rods (ANCF, step T/10000 at 150 rpm)"
    else:
        flexible = sum(wear_path_cost(rpm, settings, flexible=True) for rpm, _ in WEAR_PATHS)
        rigid = sum(wear_path_cost(rpm, settings) for rpm, _ in WEAR_PATHS)
        rods = (
            f"rigid rods: flexible ones would cost an estimated {flexible / 60:.0f} min of "
            f"CPU for the five paths, rigid ones {rigid / 60:.0f} (docs/paper-study.md, "
            "“Wear-life answer”)"
        )
    points = ", ".join(cycles_text(n) for n in settings.wear_path_checkpoints)
    return (
        f"{rods}; wear up to {cycles_text(settings.wear_path_cycles)} crank cycles, analysed "
        f"unworn and at {points}"
        + (
            f" and {cycles_text(settings.wear_path_cycles)}"
            if settings.wear_path_checkpoints[-1] < settings.wear_path_cycles
            else ""
        )
        + f" cycles ({plural(settings.wear_path_analysis_revolutions, 'revolution')} each, "
        f"the exponent from the equations over "
        f"{plural(settings.wear_path_lyapunov_revolutions, 'revolution')}); wear per cycle "
        f"averaged over {plural(settings.wear_path_averaged_revolutions, 'revolution')}"
    )


def wear_life_opening(
    outcomes: Mapping[tuple[float, float], PathOutcome],
    verdicts: Sequence[ClaimVerdict],
    settings: StudySettings,
) -> str:
    """The summary's first sentences: each claim with agree / disagree / cannot tell and
    why, then each path's cycles to chaos with its confidence."""
    claims = " ".join(f"{v.line[:1].upper()}{v.line[1:]}." for v in verdicts)
    parts = []
    for o in (outcomes[p] for p in WEAR_PATHS if p in outcomes):
        sure = format_confidence(o.confidence) if math.isfinite(o.confidence) else ""
        parts.append(f"{o.label}: {o.answer}" + (f" (confidence {sure})" if sure else ""))
    paths = "; ".join(parts)
    rods = "flexible" if settings.wear_path_flexible_rods else "rigid"
    return (
        f"Wear life against the paper's claims on the transition to chaos. {claims} "
        f"Cycles to chaos per wear path ({rods} rods, {cycles_text(settings.wear_path_cycles)} "
        f"cycles): {paths}."
    )


def claims_frame(verdicts: Sequence[ClaimVerdict]) -> pd.DataFrame:
    """The judged claims, one row per claim (index: its few words): ``claim`` (the
    paper's words, quoted), ``agreement`` and ``why``."""
    return pd.DataFrame(
        {
            "claim": [f"“{v.claim.quote}”" for v in verdicts],
            "agreement": [v.agreement for v in verdicts],
            "why": [v.why for v in verdicts],
        },
        index=pd.Index([v.claim.short for v in verdicts], name="paper's claim"),
    )


def wear_life_tables(
    outcomes: Mapping[tuple[float, float], PathOutcome],
    verdicts: Sequence[ClaimVerdict],
    settings: StudySettings,
) -> tuple[chaoskit.ReportTable, chaoskit.ReportTable]:
    """The claims table (the paper's words, agreement, why) and the paths table (cycles
    to chaos, confidence, λ₁, wear depth, the motion at each checkpoint)."""
    claims = claims_frame(verdicts)
    rows, labels = [], []
    for key in WEAR_PATHS:
        o = outcomes.get(key)
        if o is None:
            continue
        labels.append(path_label(*key))
        rows.append(
            {
                "answer": o.answer,
                "confidence": o.confidence,
                "lam": o.exponent[0],
                "lam_low": o.exponent[1],
                "lam_high": o.exponent[2],
                "depth": o.depths[-1] * 1e6 if o.depths else math.nan,
                "motions": " → ".join(o.motions) or "—",
            }
        )
    paths = pd.DataFrame(rows, index=pd.Index(labels, name="wear path"))
    rods = "flexible" if settings.wear_path_flexible_rods else "rigid"
    return (
        chaoskit.ReportTable(
            caption="The wear life against the paper's claims on the transition to chaos: "
            "agree, disagree or cannot tell, and why (the wear paths of the next table).",
            data=claims,
            labels={"claim": "the paper's words", "agreement": "agreement", "why": "why"},
            notes="A path turns chaotic at the first checkpoint whose exponent from the "
            "equations has its 95 % interval above zero and whose motion verdict is chaotic "
            "(mechanism.wear_life); “not within N cycles” means no checkpoint up to N was. "
            "A path that ended early (a worn state outside what the wear model represents) "
            "or failed cannot tell, and the reason is given.",
            section="Summary",
        ),
        chaoskit.ReportTable(
            caption=f"Cycles to chaos of each wear path ({rods} rods): the answer, the "
            "motion verdict's confidence and λ₁ [95 %] at the deciding checkpoint (the "
            "chaotic one, else the last), the largest wear depth at the last checkpoint and "
            "the motion verdict at each checkpoint.",
            data=paths,
            labels={
                "answer": "cycles to chaos",
                "confidence": "confidence",
                "lam": "λ₁ (1/s)",
                "depth": "wear depth (µm)",
                "motions": "motion at each checkpoint",
            },
            intervals={"lam": ("lam_low", "lam_high")},
            formats={"confidence": CONFIDENCE_FORMAT},
            digits=3,
            notes=f"{wear_paths_design(settings)[:1].upper()}{wear_paths_design(settings)[1:]}. "
            + CONFIDENCE_NOTE,
            section="Summary",
        ),
    )


def outcomes_of(results: Mapping[tuple[float, float], Any]) -> dict[tuple[float, float], Any]:
    """``{(rpm, clearance): PathOutcome}`` from each path's WearLife or exception."""
    return {key: path_outcome(*key, life) for key, life in results.items()}
