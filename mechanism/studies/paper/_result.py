"""The reproduced study: :class:`PaperStudy`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

import chaoskit
from chaoskit.reporting import answer_table

from ._published import COLUMNS, LABELS
from ._settings import StudySettings


@dataclass(frozen=True, kw_only=True, eq=False)
class PaperStudy:
    """The reproduced study: our tables beside the paper's, and where the report is.

    Attributes
    ----------
    tables
        Our tables in the paper's units, keyed like :func:`paper_tables` (``"wear"``,
        ``"clearance"`` (150 rpm), ``"clearance_90rpm"``, ``"speed"``, ``"convergence"``,
        ``"chaos"``); a table whose building block is missing holds NaN.
    paper
        The paper's tables (:func:`paper_tables`).
    report_html, report_markdown
        The report files.
    output
        The output folder (sweep stores under ``runs/``).
    settings
        The :class:`StudySettings` used.
    quick
        Whether the quick reductions were used.
    unavailable
        One line per part this version could not run (empty when complete).
    wall_time
        Wall time of the whole study, s.
    output_size
        Bytes in the output folder at the end.
    motions
        ``{state: MotionVerdict}``: the verdict on the motion of each analysed state
        (the ``motions`` of :class:`chaoskit.Report`); :attr:`answer` tabulates it.
    wear_paths
        ``{(crank speed in rpm, clearance in m): WearLife}``: each wear path of the
        wear-life answer (:func:`mechanism.wear_life`), or the exception its run raised;
        empty when the settings leave the paths out.
    transition_claims
        The paper's claims on the transition to chaos judged on the wear paths, one row
        per claim (index: a few words of it): ``claim`` (the paper's words),
        ``agreement`` ("agree", "disagree" or "cannot tell") and ``why`` (one line).
    """

    tables: Mapping[str, pd.DataFrame]
    paper: Mapping[str, pd.DataFrame]
    report_html: Path
    report_markdown: Path | None
    output: Path
    settings: StudySettings
    quick: bool
    unavailable: tuple[str, ...] = ()
    wall_time: float = 0.0
    output_size: int = 0
    sweeps: Mapping[str, xr.Dataset] = field(default_factory=dict, repr=False)
    motions: Mapping[str, chaoskit.MotionVerdict] = field(default_factory=dict, repr=False)
    wear_paths: Mapping[tuple[float, float], Any] = field(default_factory=dict, repr=False)
    transition_claims: pd.DataFrame = field(default_factory=pd.DataFrame, repr=False)

    @property
    def answer(self) -> pd.DataFrame:
        """The answer, one row per state: motion verdict, confidence (two decimals), λ₁
        [95 %] and its source (``chaoskit.reporting.answer_table``)."""
        return answer_table(self.motions)

    @property
    def complete(self) -> bool:
        """True when every part of the study ran."""
        return not self.unavailable

    def to_dataset(self) -> xr.Dataset:
        """The response tables (ours and the paper's) as one labelled Dataset.

        Dimensions ``case`` (``"<table>: <row>"``) and ``quantity`` (``COLUMNS``);
        variables ``ours`` and ``paper`` in the paper's units (listed in ``units`` of
        ``quantity``).
        """
        cases, ours, theirs = [], [], []
        for name in ("wear", "clearance", "speed"):
            for row in self.paper[name].index:
                cases.append(f"{name}: {row}")
                ours.append(self.tables[name].reindex(columns=list(COLUMNS)).loc[row].to_numpy())
                theirs.append(self.paper[name].loc[row, list(COLUMNS)].to_numpy())
        coords = {
            "case": np.asarray(cases, dtype=str),
            "quantity": np.asarray(COLUMNS, dtype=str),
        }
        unit_text = "; ".join(f"{c}: {LABELS[c]}" for c in COLUMNS)
        return xr.Dataset(
            {
                "ours": (
                    ("case", "quantity"),
                    np.asarray(ours, dtype=np.float64),
                    {"units": "see quantity", "long_name": f"reproduced response ({unit_text})"},
                ),
                "paper": (
                    ("case", "quantity"),
                    np.asarray(theirs, dtype=np.float64),
                    {"units": "see quantity", "long_name": "published response (Jia et al. 2025)"},
                ),
            },
            coords=coords,
        )
