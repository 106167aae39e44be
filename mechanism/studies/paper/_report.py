"""The report's parts: figures, the tables beside the paper's, their notes, and
the run's facts and cost."""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd
import xarray as xr

import chaoskit
from chaoskit.reporting import plural

from .._plot import plot_bifurcation
from ._published import (
    COLUMNS,
    LABELS,
    NOT_AVAILABLE,
    PAPER_SAMPLES,
    PERIOD_150,
)
from ._settings import StudySettings
from ._summary import Stages, strobe_figure


def rods_of(trajectories: Mapping[str, xr.Dataset], settings: StudySettings) -> str:
    """The rods of the analysed series, per state when a flexible run fell back to rigid."""
    if not settings.flexible_rods:
        return "rigid"
    rigid = [s for s, traj in trajectories.items() if "rods_note" in traj.attrs]
    if not rigid:
        return "flexible"
    return "flexible (" + ", ".join(rigid) + ": rigid)"


def orbit_figure(orbits: Mapping[str, xr.Dataset], settings: StudySettings) -> Any:
    """The summary's orbit diagrams over crank speed, one panel per state."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0 * len(orbits), 4.0), layout="constrained")
    axes = fig.subplots(1, len(orbits), squeeze=False)[0]
    for ax, (state, ds) in zip(axes, orbits.items(), strict=False):
        plot_bifurcation(orbit_display(ds), axes=[ax])
        ax.set_title(state, fontsize=10)
    rods = "flexible" if settings.orbit_flexible_rods else "rigid (a reduction of --quick)"
    return chaoskit.ReportFigure.from_matplotlib(
        fig,
        caption="Orbit diagrams over crank speed before and after wear (worn at 150 rpm): "
        "journal-centre e_x once per revolution, "
        f"{plural(settings.orbit_revolutions - settings.orbit_discard_revolutions, 'revolution')}"
        f" per speed after {plural(settings.orbit_discard_revolutions, 'revolution')} of "
        f"transient, rods {rods}. "
        "A period-k motion gives k points above its speed, chaos a band.",
        name="orbit-before-after",
        section="Summary",
    )


#: Words for the scene keys the study sweeps, for axis labels.
_KEY_LABELS = {"drive.speed_rpm": "crank speed", "joints.C.clearance": "radial clearance at C"}


def orbit_display(ds: xr.Dataset) -> xr.Dataset:
    """An orbit diagram as the report draws it: journal displacements in mm (as in the
    stroboscopic maps beside it) and the swept parameter named in words."""
    out = ds.copy()
    parameter = str(ds.attrs.get("bifurcation_parameter", ""))
    if parameter in _KEY_LABELS and parameter in out.coords:
        out = out.assign_coords(
            {parameter: out[parameter].assign_attrs(long_name=_KEY_LABELS[parameter])}
        )
    for name in str(ds.attrs.get("bifurcation_variables", "")).split(","):
        if name in out.data_vars and out[name].attrs.get("units") == "m":
            out[name] = (out[name] * 1e3).assign_attrs({**ds[name].attrs, "units": "mm"})
    return out


def cost_section(stages: Stages) -> chaoskit.ReportSection:
    """Appendix: wall and CPU minutes of each stage of this run."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else (math.nan,) * 3
    table = chaoskit.ReportTable(
        caption="Cost of this run by stage: wall time and CPU time of the process and its "
        "workers (minutes). CPU time does not grow when other jobs share the cores; the "
        "wall time does.",
        data=stages.summary(),
        labels={"wall_min": "wall (min)", "cpu_min": "CPU (min)"},
        digits=3,
        section="Run: cost by stage",
    )
    return chaoskit.ReportSection(
        title="Run: cost by stage",
        items=(table,),
        text=f"{os.cpu_count()} cores; load average at the end of the run "
        f"{load[0]:.1f} (1 min), {load[2]:.1f} (15 min): a load above the core count means "
        "the cores were shared and the wall time is longer than on an idle machine.",
    )


def with_run_facts(
    rep: Any,
    *,
    wall: float,
    cpu: float,
    size: int,
    wear_info: list[str],
    unavailable: list[str],
) -> Any:
    """The summary with the run's facts: what is missing right under the answer; the wall
    and CPU time, the output size and the wear after the answer's tables and figures."""
    first = rep.sections[0]
    facts = (
        f"Run: wall time {wall / 60:.1f} min, output {size / 1e6:.1f} MB, CPU time "
        f"{cpu / 60:.1f} min on {os.cpu_count()} cores (by stage at the end). Wear: "
        + ("; ".join(wear_info) or "not run")
        + "."
    )
    text = first.text
    if unavailable:
        text += " NOT AVAILABLE: " + "; ".join(unavailable) + "."
    first = dataclasses.replace(first, text=text, footer=f"{first.footer} {facts}".strip())
    return dataclasses.replace(rep, sections=(first, *rep.sections[1:]))


def table_notes(
    settings: StudySettings,
    unavailable: list[str],
    *,
    has_wear: bool,
    wear_info: Sequence[str] = (),
) -> dict[str, str]:
    """The note under each table (keyed like the tables, and ``"chaos"``): the run's
    conditions, why ours differs from the paper, and what is not available."""
    rigid = (
        "Rods 3 and 4 are rigid bars in this run (StudySettings.flexible_rods = false), so "
        "there are no rod strains. "
        if not settings.flexible_rods
        else ""
    )
    common = (
        "Why ours differs (docs/paper-model.md, “Reconstruction choices”): the geometry is a "
        "reconstruction with the clearance at C; the contact stiffness is the value the "
        "paper's own numbers imply (K = 1.31e10 N/m^1.5); v0/v1 of the friction law are "
        "assumed; the paper's displacement error is about 10× larger than the geometric "
        "bound of a 0.5 mm clearance. "
        + rigid
        + f"Metrics over revolutions {settings.discard_revolutions:g}–{settings.revolutions:g}, "
        f"output step T/{settings.samples_per_revolution}."
    )
    missing_wear = (
        f"{NOT_AVAILABLE}: the wear prediction (mechanism.predict_wear) — no after-wear row. "
        if not has_wear
        else ""
    )
    cycles = settings.wear_updates * settings.wear_cycles_per_update
    worn = (
        f"Each speed is worn at its own speed for {cycles:,.0f} crank cycles "
        f"({plural(settings.wear_updates, 'update')} × {settings.wear_cycles_per_update:,.0f}; "
        "the paper "
        "gives no cycle count: docs/paper-model.md, “Amount of wear”). "
        + ("; ".join(wear_info) + ". " if wear_info else "")
    )
    return {
        "wear": missing_wear + "150 rpm, c = 0.2 mm. Ratios compare magnitudes (|after| / "
        "|before|). " + worn + common,
        "clearance": "Before wear, 150 rpm: the table's conditions are not printed "
        "(docs/paper-model.md, “Clearance size”). The difference compares magnitudes. " + common,
        "clearance_90rpm": "Before wear, 90 rpm: the other reading of the table's unprinted "
        "conditions (the paper's 0.2 mm row is close to its 90 rpm row). " + common,
        "speed": (
            "After wear, c = 0.2 mm. " + worn
            if has_wear
            else f"{NOT_AVAILABLE}: wear prediction; no after-wear rows. "
        )
        + common,
        "convergence": "Signed extreme axial strain (µε) over the nodes and element "
        "mid-points of each rod (mechanism.element_convergence), flexible rods, before wear, "
        "150 rpm, c = 0.2 mm, over the first "
        f"{plural(settings.convergence_revolutions, 'revolution')} (the first impact of the "
        "concentric start is the largest of a "
        f"revolution), output step T/{settings.samples_per_revolution}. Our strain follows "
        "our contact force (rod 3 carries the joint force axially, docs/paper-model.md, "
        "“Clearance joint location”). "
        + next((f"{NOT_AVAILABLE}: {u}." for u in unavailable if "convergence" in u), ""),
        "chaos": "Series: journal-centre eccentricity x (X) and y (Y) of joint C "
        "(docs/paper-model.md, “Analysed series”), 150 rpm, c = 0.2 mm, "
        f"{plural(settings.chaos_revolutions, 'revolution')} after the first "
        f"{plural(settings.discard_revolutions, 'revolution')}, "
        f"{'flexible' if settings.flexible_rods else 'rigid'} rods, integration "
        "step T/10000. The "
        "paper samples at T/10000 (4e-5 s): its lag and bits per sample refer to that step; "
        "ours refer to the analysed step stated in the caption, so compare lag time (s) and "
        "the MLE in 1/s (the paper's values converted with λ = bits·ln2/Δt). Only the sign "
        "of the MLE is physically meaningful (docs/paper-model.md §8)."
        + ("" if has_wear else f" {NOT_AVAILABLE}: wear prediction — no after-wear rows."),
    }


def _magnitude_ratio(a: float, b: float) -> float:
    return abs(a) / abs(b) if math.isfinite(a) and math.isfinite(b) and b != 0.0 else math.nan


def wear_comparison(ours: pd.DataFrame, paper: pd.DataFrame) -> pd.DataFrame:
    """Before | after | ratio for ours and the paper, one row per quantity."""
    rows = {}
    for col in COLUMNS:
        row: dict[str, float] = {}
        for name, frame in (("ours", ours), ("paper", paper)):
            before = (
                float(frame.at["before wear", col]) if "before wear" in frame.index else math.nan
            )
            after = float(frame.at["after wear", col]) if "after wear" in frame.index else math.nan
            row[f"{name}_before"] = before
            row[f"{name}_after"] = after
            row[f"{name}_ratio"] = _magnitude_ratio(after, before)
        rows[LABELS[col]] = row
    return pd.DataFrame.from_dict(rows, orient="index").rename_axis("quantity")


def report_tables(
    tables: Mapping[str, pd.DataFrame],
    paper: Mapping[str, pd.DataFrame],
    notes: Mapping[str, str],
    *,
    has_after: bool,
) -> list[Any]:
    """The report's response tables, each beside the paper's with its note."""

    def table(key: str, caption: str, *, reference: str | None = None, **options: Any) -> Any:
        # a table's data, its published values and its notes share one key
        return chaoskit.ReportTable(
            caption=caption,
            data=tables[key],
            reference=paper[reference or key],
            reference_name="paper",
            labels=LABELS,
            notes=notes[key],
            **options,
        )

    side = {"before": "before", "after": "after", "ratio": "ratio after/before"}
    wear = chaoskit.ReportTable(
        caption="Before and after wear, 150 rpm (paper Table: before/after wear): ours and "
        "the paper's, each with the ratio after / before.",
        data=wear_comparison(tables["wear"], paper["wear"]),
        labels={f"{who}_{k}": f"{who} {v}" for who in ("ours", "paper") for k, v in side.items()},
        notes=notes["wear"],
    )
    return [
        wear,
        table(
            "clearance",
            "Clearance size, before wear, 150 rpm (paper Table: clearance size).",
            layout="long",
        ),
        table(
            "clearance_90rpm",
            "Clearance size, before wear, 90 rpm (the other reading; paper Table: clearance size).",
            reference="clearance",
            layout="long",
        ),
        table(
            "speed",
            "Driving speed, after wear, each speed worn at its own speed (paper Table: "
            "driving speed)."
            if has_after
            else "Driving speed — wear prediction not available (paper Table: driving speed, "
            "after wear).",
            layout="long",
        ),
        table(
            "convergence",
            "Element convergence: rod strains (µε) before wear, 150 rpm, against "
            "ANCF elements per rod (paper Table: element convergence).",
            section="Element convergence",
        ),
    ]


def chaos_reference(
    paper: Mapping[str, pd.DataFrame], trajectories: Mapping[str, xr.Dataset]
) -> pd.DataFrame:
    """The paper's chaos table for the analysed states, with its lag in seconds and its
    Wolf exponent in 1/s (from bits per sample at the paper's step T/10000, 150 rpm)."""
    dt_paper = PERIOD_150 / PAPER_SAMPLES
    reference = paper["chaos"].copy()
    reference["lag_time"] = reference["lag"] * dt_paper
    reference["mle_wolf"] = reference["mle_wolf_bits"] * math.log(2.0) / dt_paper
    return reference[[s in trajectories for s in reference.index.get_level_values("state")]]


def strobe_headline(
    trajectories: Mapping[str, xr.Dataset], rep: Any, settings: StudySettings, discard: float
) -> chaoskit.ReportFigure:
    """The summary's stroboscopic maps before and after wear: the points the motion
    verdict counted (one source for the figure and the tables)."""
    fig = strobe_figure(trajectories, motions=rep.motions, discard=discard)
    return chaoskit.ReportFigure.from_matplotlib(
        fig,
        caption="Stroboscopic maps of the journal centre of joint C (once per crank "
        f"revolution over the {plural(settings.chaos_revolutions, 'revolution')} "
        f"after the transient, {rods_of(trajectories, settings)} rods, "
        "150 rpm, c = 0.2 mm): before and after wear. The points are those of "
        "the joint section the motion verdict counts (its “joint section” "
        "column), the initial state and the transient left out.",
        name="strobe-before-after",
        section="Summary",
    )


def settings_text(
    settings: StudySettings,
    *,
    quick: bool,
    trajectories: Mapping[str, xr.Dataset],
    wall_so_far: float,
) -> str:
    """The summary's paragraph on the settings of this run (and its wall time so far, s)."""
    rods_notes = "".join(
        f" {state.capitalize()}: {traj.attrs['rods_note']}."
        for state, traj in trajectories.items()
        if "rods_note" in traj.attrs
    )
    return (
        f"Settings: {'quick' if quick else 'paper'}; chaos from "
        f"{plural(settings.chaos_revolutions, 'revolution')} per state after "
        f"{plural(settings.discard_revolutions, 'revolution')} of transient, integration "
        f"step T/{PAPER_SAMPLES} (T = {PERIOD_150:g} s at 150 rpm), series sampled at T/"
        f"{settings.chaos_samples_per_revolution}; rods "
        f"{'flexible (ANCF)' if settings.flexible_rods else 'rigid'}; the bearing of "
        "each speed's row is worn at that speed for "
        f"{settings.wear_updates * settings.wear_cycles_per_update:,.0f} crank "
        f"cycles.{rods_notes} Wall time {wall_so_far / 60:.1f} min until the report. The "
        "model and every reconstruction choice: docs/paper-model.md."
    )
