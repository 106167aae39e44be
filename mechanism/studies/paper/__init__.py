"""The paper's study by one call: is the press chaotic before and after wear, and the tables.

:func:`run_paper_study` answers the question of Jia, Meng, Jiang, Kang (Lubricants 2025,
13(3), 130) with the reconstructed ``paper`` scene (docs/paper-model.md) and writes a
report (HTML + Markdown, :func:`chaoskit.report`) that opens with the answer — the
wear-life answer (cycles to chaos of five wear paths over speed and clearance, beside the
paper's claims on the transition to chaos), then the verdict of each state with its
confidence and the largest Lyapunov exponent from the equations and from the data, beside
the paper's values and claims — followed by every published table beside ours. The
published numbers are data (``data/paper_tables.toml`` in this package,
:func:`paper_tables`, :func:`paper_claims`).

The study is built from the public pieces, nothing is computed a second way:

* sweeps (:func:`mechanism.sweep`) give every response row — clearance × speed (90 and
  150 rpm) before wear, and each speed after wear on the scene worn at that speed — with
  the metrics of docs/paper-model.md §7 (``peak_contact_force``, ``max_penetration``,
  ...);
* :func:`mechanism.predict_wear` gives the worn scene at 30, 90 and 150 rpm;
* :func:`mechanism.element_convergence` gives the rod-strain convergence table;
* :func:`mechanism.lyapunov_exponent` gives the exponent from the equations (on the
  series' model, and with rigid rods beside it unless the settings leave that out);
* :func:`mechanism.bifurcation` gives the orbit diagrams over crank speed;
* :func:`mechanism.wear_life` gives the wear paths and their cycles to chaos;
* :func:`chaoskit.report` analyses the journal-centre motion before and after wear (the
  chaos table) and assembles the page.

A part that fails is reported in the page as "not available", never skipped in silence.
See ``docs/paper-study.md``.

Modules, one concern each: ``_published`` (the paper's data and the study's fixed
design), ``_settings`` (:class:`StudySettings`), ``_runs`` (the single computations, pool
tasks), ``_schedule`` (backends, the pool's queue, stores, stage costs), ``_study`` (the
stages in order), ``_tables`` (our tables), ``_report`` and ``_summary`` (the report's
parts), ``_claims`` (the transition claims judged on the wear paths), ``_wear_paths``
(the report's wear-life answer), ``_route`` (the report's route to chaos over crank
speed, from a stored continuation) and ``_result`` (:class:`PaperStudy`).
"""

from __future__ import annotations

from ._published import COLUMNS, LABELS, paper_claims, paper_tables, paper_wear_zones
from ._result import PaperStudy
from ._settings import StudySettings
from ._study import run_paper_study
from ._summary import process_tree_cpu_time

__all__ = [
    "COLUMNS",
    "LABELS",
    "PaperStudy",
    "StudySettings",
    "paper_claims",
    "paper_tables",
    "paper_wear_zones",
    "process_tree_cpu_time",
    "run_paper_study",
]
