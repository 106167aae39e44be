"""The paper's study by one call: is the press chaotic before and after wear, and the tables.

:func:`run_paper_study` answers the question of Jia, Meng, Jiang, Kang (Lubricants 2025,
13(3), 130) with the reconstructed ``paper`` scene (docs/paper-model.md) and writes a
report (HTML + Markdown, :func:`chaoskit.report`) that opens with the answer — the verdict
of each state with its confidence and the largest Lyapunov exponent from the equations and
from the data, beside the paper's values and claims — followed by every published table
beside ours. The published numbers are data (``mechanism/studies/data/paper_tables.toml``,
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
* :func:`chaoskit.report` analyses the journal-centre motion before and after wear (the
  chaos table) and assembles the page.

A part that fails is reported in the page as "not available", never skipped in silence.
See ``docs/paper-study.md``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import os
import shlex
import sys
import threading
import time
import tomllib
from collections.abc import Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

import chaoskit
from chaoskit.reporting import answer_table, plural
from mechanism.core import SimulationError, WornProfile, load_scene, simulate
from mechanism.core.scene import ClearanceRevolute

from ._bifurcation import ORBIT_TOLERANCE, bifurcation
from ._convergence import element_convergence
from ._lyapunov import lyapunov_exponent
from ._paper_summary import Stages, strobe_figure, summary_section
from ._plot import plot_bifurcation
from ._sweep import Analysis, dask_client, register_grid_transform, sweep
from ._wear_prediction import predict_wear
from ._wear_report import wear_profile_section

__all__ = ["PaperStudy", "StudySettings", "paper_claims", "paper_tables", "run_paper_study"]

_DATA = Path(__file__).parent / "data" / "paper_tables.toml"

#: Response columns of the paper's tables, in print order.
COLUMNS: tuple[str, ...] = (
    "displacement_error",
    "speed_error",
    "contact_force",
    "embedding_depth",
    "rod3_strain",
    "rod4_strain",
    "driving_torque",
)
LABELS: dict[str, str] = {
    "displacement_error": "displacement error (mm)",
    "speed_error": "speed error (m/s)",
    "contact_force": "contact force (kN)",
    "embedding_depth": "embedding depth (mm)",
    "rod3_strain": "strain of rod 3 (µε)",
    "rod4_strain": "strain of rod 4 (µε)",
    "driving_torque": "driving torque (N m)",
}
# paper column -> (sweep metric, factor from SI to the paper's unit)
_FROM_SWEEP: dict[str, tuple[str, float]] = {
    "displacement_error": ("max_displacement_error", 1e3),
    "speed_error": ("max_speed_error", 1.0),
    "contact_force": ("peak_contact_force", 1e-3),
    "embedding_depth": ("max_penetration", 1e3),
    "driving_torque": ("driving_torque_extreme", 1.0),
}
_RODS = {"rod3_strain": "rod3", "rod4_strain": "rod4"}
_MICRO = 1e6
_CLEARANCES = (1e-4, 2e-4, 5e-4)
_SPEEDS = (30, 90, 150)
#: the before-wear sweep's speeds: those of its tables (clearance at 150 and at 90 rpm, the
#: before-wear row at 150); a 30 rpm point costs five 150 rpm ones and no table used it
_BEFORE_SPEEDS = (90, 150)
_DEFAULT_CLEARANCE = 2e-4
_PAPER_SAMPLES = 10_000  # the paper's step is T/10000 (its parameter table)
#: Largest integration step of every run of the study (s): the paper's T/10000 at 150 rpm,
#: at every speed. The flexible rods run the fixed-step generalized-α at this step; T/10000
#: at 30 rpm (2e-4 s) diverged on the profile worn at 30 rpm (penetration far beyond the
#: clearance, singular constraint Jacobian after 0.99 s) where 1e-4 s ran, and the sweeps'
#: output grid (T/2500 in --quick) must not become the step (docs/paper-model.md,
#: "Integration step").
_STEP = 0.4 / _PAPER_SAMPLES
_SPR = "samples_per_revolution"
#: what the chaos runs record: the drive's phase and the journal centre (no full state)
_CHAOS_VARIABLES = ("crank_angle", "eccentricity_x", "eccentricity_y")
_NOT_AVAILABLE = "NOT AVAILABLE IN THIS VERSION"


# --------------------------------------------------------------------------- the paper's data


def paper_tables() -> dict[str, pd.DataFrame]:
    """The published tables of the seed paper as DataFrames, in the paper's units.

    Keys: ``"convergence"`` (index ``elements``; rod strains in µε), ``"wear"`` (rows
    "before wear", "after wear"), ``"clearance"`` (rows "0.1 mm", "0.2 mm", "0.5 mm"),
    ``"speed"`` (rows "30 rpm", "90 rpm", "150 rpm") — the response tables with the columns
    of :data:`COLUMNS` (mm, m/s, kN, mm, µε, µε, N m) — and ``"chaos"`` (index
    ``(variable, state)``; ``lag`` in samples of T/10000, ``embedding_dim``,
    ``mle_wolf_bits`` in bits per sample). Read from ``mechanism/studies/data/paper_tables.toml``.

    Examples
    --------
    >>> import mechanism
    >>> t = mechanism.paper_tables()
    >>> float(t["wear"].loc["after wear", "contact_force"])
    23.33
    >>> int(t["chaos"].loc[("Y", "after wear"), "lag"])
    12
    """
    with _DATA.open("rb") as fh:
        raw = tomllib.load(fh)
    out: dict[str, pd.DataFrame] = {}
    conv = raw["convergence"]
    out["convergence"] = pd.DataFrame(
        {"rod3_strain": conv["rod3_strain"], "rod4_strain": conv["rod4_strain"]},
        index=pd.Index(conv["elements"], name="elements"),
    )
    for name, index_name in (("wear", "state"), ("clearance", "clearance"), ("speed", "speed")):
        table = raw[name]
        out[name] = pd.DataFrame(
            [table[row] for row in table["rows"]],
            index=pd.Index(table["rows"], name=index_name),
            columns=table["columns"],
        )
    chaos = raw["chaos"]
    out["chaos"] = pd.DataFrame(
        {k: chaos[k] for k in ("lag", "embedding_dim", "mle_wolf_bits")},
        index=pd.MultiIndex.from_arrays(
            [chaos["variables"], chaos["states"]], names=["variable", "state"]
        ),
    )
    return out


def paper_claims() -> dict[str, dict[str, str]]:
    """The paper's claim about the motion of each state (before, after wear).

    ``{state: {"motion": "chaotic" | "not chaotic", "text": one line}}``, read from the
    ``[claims]`` table of ``mechanism/studies/data/paper_tables.toml``.
    """
    with _DATA.open("rb") as fh:
        raw = tomllib.load(fh)["claims"]
    return {
        state: {"motion": str(motion), "text": str(text)}
        for state, motion, text in zip(raw["states"], raw["motion"], raw["text"], strict=True)
    }


def paper_wear_zones() -> list[tuple[float, float]]:
    """The paper's concentrated wear arcs in degrees: [(75, 132), (252, 310)]."""
    with _DATA.open("rb") as fh:
        zones = tomllib.load(fh)["wear"]["wear_zones_deg"]
    return [(float(a), float(b)) for a, b in zones]


# --------------------------------------------------------------------------- settings


@dataclass(frozen=True, kw_only=True)
class StudySettings:
    """How much of the study is run: the paper's settings or documented reductions.

    Parameters
    ----------
    revolutions
        Crank revolutions simulated per response point (peaks need ≥ 3; the paper's
        simulation length is not printed: docs/paper-model.md, “Simulation length”).
    discard_revolutions
        Transient dropped before metrics and chaos analysis (revolutions).
    samples_per_revolution
        Output samples per crank revolution of the response points; the output step is
        T / this. The paper: 10 000.
    flexible_rods
        Rods 3 and 4 as ANCF beams (the paper, and the default everywhere) or rigid bars.
    wear_updates, wear_cycles_per_update, wear_max_depth_increment, wear_settle_revolutions
        Cycle extrapolation of :func:`mechanism.predict_wear` (docs/paper-model.md §6): the
        number of profile updates and the crank cycles per update set the amount of wear
        (the cycle count is stated in the report); the cap on one update's depth increment
        (fraction of the clearance) is a safety limit only; the revolutions settled before
        the measured cycle. Each speed of the speed table is worn at its own speed. The
        paper's settings and the quick ones wear the same 10 000 cycles, in 5 updates and
        in 1.
    elements
        ANCF elements per rod for the convergence table (paper: 4 … 24).
    convergence_revolutions
        Revolutions per run of the convergence table.
    chaos_revolutions
        Revolutions analysed per state (before, after wear) after the transient, ≥ 200:
        fewer drive periods cannot separate periodic, quasi-periodic and chaotic motion.
    chaos_samples_per_revolution
        Output samples per revolution of the analysed series; the integration step stays
        the paper's T/10000.
    exponent_revolutions
        Revolutions of :func:`mechanism.lyapunov_exponent` per state, on the model of the
        analysed series.
    rigid_rod_exponent
        With flexible rods, also the exponent of each state with rigid rods (a check that
        the answer does not hang on the rod model; the quick settings leave it out).
    orbit_speeds, orbit_revolutions, orbit_discard_revolutions, orbit_flexible_rods
        The orbit diagrams over crank speed before and after wear
        (:func:`mechanism.bifurcation`): speeds (rpm), revolutions per speed, transient,
        and whether the rods are flexible there.
    n_surrogates
        Surrogates per series of the verdict's surrogate test (at least 19: with fewer
        the test cannot reach its 5 % level).
    max_samples
        At most this many samples of each analysed series (plain stride); None: all.
    """

    revolutions: float = 11.0
    discard_revolutions: float = 1.0
    samples_per_revolution: int = _PAPER_SAMPLES
    flexible_rods: bool = True
    wear_updates: int = 5
    wear_cycles_per_update: float = 2.0e3
    wear_max_depth_increment: float = 1.0
    wear_settle_revolutions: float = 2.0
    elements: tuple[int, ...] = (4, 8, 12, 16, 20, 24)
    convergence_revolutions: float = 1.0
    chaos_revolutions: float = 200.0
    chaos_samples_per_revolution: int = 2000
    exponent_revolutions: float = 100.0
    rigid_rod_exponent: bool = True
    orbit_speeds: tuple[float, ...] = tuple(float(v) for v in range(30, 151, 15))
    orbit_revolutions: float = 30.0
    orbit_discard_revolutions: float = 15.0
    orbit_flexible_rods: bool = True
    n_surrogates: int = 19
    max_samples: int | None = 400_000

    def __post_init__(self) -> None:
        def number(name: str, low: float, *, integer: bool = False) -> None:
            v = getattr(self, name)
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            if not ok or v < low or (integer and int(v) != v):
                kind = "an integer" if integer else "a number"
                raise ValueError(f"StudySettings.{name} must be {kind} >= {low:g}; got {v!r}.")

        number("revolutions", 1.0)
        number("discard_revolutions", 0.0)
        number("samples_per_revolution", 100, integer=True)
        number("wear_updates", 1, integer=True)
        number("wear_cycles_per_update", 0.0)
        number("wear_settle_revolutions", 0.0)
        number("wear_max_depth_increment", 1e-6)
        number("convergence_revolutions", 0.01)
        number("chaos_revolutions", 1.0)
        number("chaos_samples_per_revolution", 100, integer=True)
        number("exponent_revolutions", 1.0)
        number("orbit_revolutions", 1.0)
        number("orbit_discard_revolutions", 0.0)
        # the surrogate test's rank test needs 1/alpha - 1 surrogates to reach alpha = 0.05
        number("n_surrogates", 19, integer=True)
        if self.wear_max_depth_increment > 1.0:
            raise ValueError(
                "StudySettings.wear_max_depth_increment must be in (0, 1] (a fraction of the "
                f"clearance); got {self.wear_max_depth_increment:g}."
            )
        if self.revolutions <= self.discard_revolutions:
            raise ValueError(
                f"StudySettings.revolutions ({self.revolutions:g}) must exceed "
                f"discard_revolutions ({self.discard_revolutions:g})."
            )
        if self.orbit_revolutions <= self.orbit_discard_revolutions:
            raise ValueError(
                f"StudySettings.orbit_revolutions ({self.orbit_revolutions:g}) must exceed "
                f"orbit_discard_revolutions ({self.orbit_discard_revolutions:g})."
            )
        if self.max_samples is not None:
            number("max_samples", 200, integer=True)
        elements = tuple(int(e) for e in self.elements)
        if not elements or any(e < 1 for e in elements):
            raise ValueError(f"StudySettings.elements must be integers >= 1; got {self.elements}.")
        speeds = tuple(float(v) for v in self.orbit_speeds)
        if any(not math.isfinite(v) or v <= 0 for v in speeds):
            raise ValueError(
                f"StudySettings.orbit_speeds must be positive speeds in rpm; got {speeds}."
            )
        object.__setattr__(self, "elements", elements)
        object.__setattr__(self, "orbit_speeds", speeds)
        object.__setattr__(self, "flexible_rods", bool(self.flexible_rods))
        object.__setattr__(self, "orbit_flexible_rods", bool(self.orbit_flexible_rods))
        object.__setattr__(self, "rigid_rod_exponent", bool(self.rigid_rod_exponent))

    @classmethod
    def paper(cls) -> StudySettings:
        """The paper's settings (T/10000, flexible rods, 4 … 24 elements, 200 revolutions)."""
        return cls()

    @classmethod
    def quick(cls) -> StudySettings:
        """The documented reductions of ``mechanism paper --quick`` (``docs/paper-study.md``).

        Flexible rods and the 200 analysed revolutions per state are kept; the response
        points run 4 revolutions with output T/2500, the wear 1 update of 10 000 cycles,
        the convergence table 3 meshes over the first impact, the analysed series at most
        100 000 samples, the exponent from the equations 10 revolutions (flexible rods
        only), and the orbit diagrams rigid rods at 5 speeds.
        """
        return cls(
            revolutions=4.0,
            discard_revolutions=1.0,
            samples_per_revolution=2500,
            flexible_rods=True,
            wear_updates=1,
            wear_cycles_per_update=1.0e4,
            wear_max_depth_increment=1.0,
            wear_settle_revolutions=1.0,
            elements=(4, 8, 16),
            convergence_revolutions=0.15,
            chaos_revolutions=200.0,
            chaos_samples_per_revolution=1000,
            exponent_revolutions=10.0,
            rigid_rod_exponent=False,
            orbit_speeds=(30.0, 60.0, 90.0, 120.0, 150.0),
            orbit_revolutions=30.0,
            orbit_discard_revolutions=10.0,
            orbit_flexible_rods=False,
            n_surrogates=19,
            max_samples=100_000,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready form (listed in the report's parameters)."""
        d = dataclasses.asdict(self)
        d["elements"] = list(self.elements)
        d["orbit_speeds"] = list(self.orbit_speeds)
        return d


def _output_step_transform(scene: Any, samples: Any) -> Any:
    """Grid key ``samples_per_revolution``: output step T/samples at the point's own speed."""
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    return scene.replace({"solver.output_step": period / int(samples)})


register_grid_transform(
    _SPR,
    _output_step_transform,
    long_name="output samples per crank revolution",
    units="1",
    overwrite=True,
)


# --------------------------------------------------------------------------- the result


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
        (:attr:`chaoskit.Report.motions`); :attr:`answer` tabulates it.
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

    @property
    def answer(self) -> pd.DataFrame:
        """The answer, one row per state: motion verdict, confidence (two decimals), λ₁
        [95 %] and its source (:func:`chaoskit.reporting.answer_table`)."""
        return answer_table(self.motions)

    @property
    def complete(self) -> bool:
        """True when every part of the study ran."""
        return not self.unavailable

    def to_dataset(self) -> xr.Dataset:
        """The response tables (ours and the paper's) as one labelled Dataset.

        Dimensions ``case`` (``"<table>: <row>"``) and ``quantity`` (:data:`COLUMNS`);
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


# --------------------------------------------------------------------------- helpers


def _metrics_row(point: xr.Dataset) -> dict[str, float]:
    """One sweep point's metrics in the paper's units (rod strains in µε, NaN if rigid)."""
    row: dict[str, float] = {}
    for col, (name, factor) in _FROM_SWEEP.items():
        row[col] = float(point[name].values) * factor if name in point else math.nan
    for col, rod in _RODS.items():
        value = math.nan
        if "rod_strain_extreme" in point and "rod" in point["rod_strain_extreme"].dims:
            rods = [str(r) for r in point["rod"].values]
            if rod in rods:
                value = float(point["rod_strain_extreme"].sel(rod=rod).values) * _MICRO
        row[col] = value
    return row


def _frame(rows: Mapping[str, Mapping[str, float]], index_name: str) -> pd.DataFrame:
    return pd.DataFrame(
        [dict(r) for r in rows.values()],
        index=pd.Index(list(rows), name=index_name),
        columns=list(COLUMNS),
    )


def _point(ds: xr.Dataset, **sel: Any) -> xr.Dataset:
    return ds.sel({k: v for k, v in sel.items() if k in ds.dims})


def _speed_label(rpm: float) -> str:
    return f"{rpm:g} rpm"


def _clearance_label(c: float) -> str:
    return f"{c * 1e3:g} mm"


def _store_name(kind: str, settings: StudySettings, quick: bool) -> str:
    digest = hashlib.sha1(json.dumps(settings.to_dict(), sort_keys=True).encode()).hexdigest()
    return f"{kind}-{'quick' if quick else 'paper'}-{digest[:8]}"


def _predict_worn(scene: Any, settings: StudySettings) -> tuple[Any, xr.Dataset | None, str]:
    """The worn scene from :func:`mechanism.predict_wear` (module level: runs in a pool)."""
    prediction = predict_wear(
        scene,
        updates=settings.wear_updates,
        cycles_per_update=settings.wear_cycles_per_update,
        max_depth_increment=settings.wear_max_depth_increment,
        settle_revolutions=settings.wear_settle_revolutions,
        output_step=60.0 / abs(float(scene.drive.speed_rpm)) / settings.samples_per_revolution,
    )
    worn = prediction.worn_scene
    profile = None
    rpm = float(scene.drive.speed_rpm)
    info = ""
    try:
        joint = worn.joints["C"]
        if not isinstance(joint, ClearanceRevolute):
            raise TypeError("the paper scene's joint C must be a clearance_revolute joint")
        profile = WornProfile.from_joint(joint).to_dataset()
        capped = (
            f"; {plural(prediction.reduced_updates, 'update')} worn in sub-updates of at most "
            f"{settings.wear_max_depth_increment:g} of the clearance each"
            if prediction.reduced_updates
            else ""
        )
        info = (
            f"{rpm:g} rpm: {float(prediction.cycles[-1]):,.0f} crank cycles in "
            f"{plural(prediction.updates, 'update')}{capped}; largest wear depth: bearing "
            f"{float(np.max(joint.wear.bearing_profile)) * 1e6:.3g} µm, journal "
            f"{float(np.max(joint.wear.journal_profile or [0.0])) * 1e6:.3g} µm"
        )
    except Exception as exc:  # the profile is a figure; the study goes on without it
        info = f"{rpm:g} rpm: wear profile unavailable: {type(exc).__name__}: {exc}"
    return worn, profile, info


def _chaos_run(scene: Any, settings: StudySettings) -> xr.Dataset:
    """The analysed series of one state: ≥ 200 revolutions after the transient at the
    paper's step T/10000, output every T/``chaos_samples_per_revolution`` (runs in a pool).

    Only the journal-centre eccentricity and the crank angle are recorded (``simulate(...,
    variables=...)``): no full state on the grid and no ideal companion, so the run holds
    a few arrays of the grid's length and costs the integration of the worn mechanism
    alone.
    """
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    step = min(scene.solver.max_step or math.inf, period / _PAPER_SAMPLES)
    revolutions = settings.discard_revolutions + settings.chaos_revolutions

    def run(sc: Any) -> xr.Dataset:
        return simulate(
            sc.replace({"solver.max_step": step}),
            revolutions=revolutions,
            output_step=period / settings.chaos_samples_per_revolution,
            variables=_CHAOS_VARIABLES,
        )

    # The worn profile's narrow grooves can throw the journal of the fixed-step flexible
    # model across the bearing (docs/paper-model.md, "Rods of the long runs"): a run that
    # stops, or whose journal leaves the bearing, is replaced by the rigid-rod run of the
    # same state, and the report says so.
    try:
        ds = run(scene)
    except SimulationError as exc:
        if not scene.effects.flexibility:
            raise
        why = (
            f"the run with flexible rods stopped after {exc.time / period:.0f} of "
            f"{revolutions:g} revolutions ({exc})"
        )
    else:
        room = _bearing_room(scene)
        reach = float(np.max(np.hypot(ds["eccentricity_x"], ds["eccentricity_y"])))
        if not scene.effects.flexibility or reach <= room:
            return ds
        why = (
            f"the journal of the run with flexible rods left the bearing (eccentricity up "
            f"to {reach * 1e3:.3g} mm, the worn bearing leaves {room * 1e3:.3g} mm)"
        )
    ds = run(scene.replace({"effects.flexibility": False}))
    ds.attrs["rods_note"] = f"{why}; its series are from rigid rods"
    return ds


def _bearing_room(scene: Any) -> float:
    """Largest eccentricity (m) a journal of joint C can reach without leaving its worn
    bearing: the clearance, the deepest bearing and journal wear, and half a clearance
    more for the contact's own penetration."""
    joint = scene.joints["C"]
    c = float(joint.clearance)
    worn = 0.0
    if joint.wear is not None:
        for profile in (joint.wear.bearing_profile, joint.wear.journal_profile):
            if profile is not None and len(profile):
                worn += float(np.max(profile))
    return 1.5 * c + worn


def chaos_analysis_options(settings: StudySettings) -> dict[str, Any]:
    """The :func:`chaoskit.report` options of the study's chaos analysis of one state's
    series from :func:`_chaos_run` (the journal centre of joint C as ``X`` and ``Y``, the
    crank angle as the drive's phase, the transient dropped)."""
    return {
        "variables": {"X": "eccentricity_x[joint=C]", "Y": "eccentricity_y[joint=C]"},
        "phase_variable": "crank_angle",
        "discard": settings.discard_revolutions * 60.0 / 150.0,
        "max_samples": settings.max_samples,
        "n_surrogates": settings.n_surrogates,
        "rng": 0,
        # journal displacements in mm in every figure, as in the stroboscopic maps
        "display_units": {"X": "mm", "Y": "mm"},
    }


def _equation_exponent(scene: Any, settings: StudySettings, *, rigid: bool = False) -> Any:
    """:func:`mechanism.lyapunov_exponent` of a state (pool task): on the model of the
    analysed series (flexible rods when ``settings.flexible_rods``, at the long runs' step
    T/10000), or on the rigid-rod model with ``rigid``."""
    if rigid or not settings.flexible_rods:
        model = scene.replace({"effects.flexibility": False})
    else:
        period = 60.0 / abs(float(scene.drive.speed_rpm))
        step = min(scene.solver.max_step or math.inf, period / _PAPER_SAMPLES)
        model = scene.replace({"effects.flexibility": True, "solver.max_step": step})
    return lyapunov_exponent(
        model,
        revolutions=settings.discard_revolutions + settings.exponent_revolutions,
        discard=settings.discard_revolutions,
    )


def _convergence_run(scene: Any, elements: int, settings: StudySettings) -> list[float]:
    """Extreme strains (µε) of rods 3 and 4 with ``elements`` per rod."""
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    # the scene's "auto" method runs flexible rods with the fixed-step generalized-α at
    # max_step: keep that step at the paper's T/10000 even when the output grid is coarser
    step = min(scene.solver.max_step or math.inf, period / _PAPER_SAMPLES)
    result = element_convergence(
        scene.replace({"solver.max_step": step}),
        rods=tuple(_RODS.values()),
        elements=(int(elements),),
        revolutions=settings.convergence_revolutions,
        output_step=period / settings.samples_per_revolution,
    )
    rods = list(result.rods)
    # element_convergence already reports micro-strain
    return [
        float(result.strain[0, rods.index(rod)]) if rod in rods else math.nan
        for rod in _RODS.values()
    ]


def _compile_kernels(part: str, *, rigid_exponent: bool = True) -> float:
    """Run each compiled path of the study once on a tiny problem (pool task), so that
    numba compiles it and writes its cache; returns the CPU seconds spent.

    On a fresh install every worker process would otherwise compile the same kernels at
    the same time (about two minutes of CPU each); compiled once here, in the pool's two
    processes in parallel, the others load them from the cache. ``part`` is
    ``"flexible"`` (the generalized-α runs: full record, the chaos runs' series, wear) or
    ``"rigid"`` (sections, the rigid exponent when ``rigid_exponent``, the analysis, and
    last the flexible exponent, so that the two parts take about the same time).
    """
    cpu = time.process_time()
    scene = load_scene("paper").replace({"effects.flexibility": True, "solver.max_step": _STEP})
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    if part == "flexible":
        simulate(scene, revolutions=0.01, output_step=period / 2500)
        simulate(
            scene,
            revolutions=0.01,
            output_step=period / 1000,
            variables=_CHAOS_VARIABLES,
        )
        predict_wear(
            scene,
            updates=1,
            cycles_per_update=1.0,
            settle_revolutions=0.0,
            output_step=period / 2500,
        )
    else:
        rigid = scene.replace({"effects.flexibility": False, "solver.max_step": None})
        simulate(
            rigid, revolutions=0.2, record="sections", rtol=ORBIT_TOLERANCE, atol=ORBIT_TOLERANCE
        )
        if rigid_exponent:
            lyapunov_exponent(rigid, revolutions=0.2, discard=0.1)
        t = np.arange(4000) * 0.05
        chaoskit.classify(np.sin(t) + 0.5 * np.sin(np.sqrt(2.0) * t), dt=0.05)
        lyapunov_exponent(scene, revolutions=0.02, discard=0.01)
    return time.process_time() - cpu


def _session_client(client: Any, n_workers: int | None, n_tasks: int) -> Any:
    """A context manager giving the backend of the sweeps (one cluster for the study)."""
    if client == "serial":
        return contextlib.nullcontext("serial")
    return dask_client(client, n_workers, n_tasks)


def _pool(client: Any, n_workers: int | None) -> Any:
    """Processes for the long compiled runs (wear, chaos, exponents), or this process.

    A long compiled run holds the GIL, so on a dask worker it misses the heartbeats and is
    restarted; separate processes run them in parallel without that limit.
    """
    if client == "serial":
        return contextlib.nullcontext(None)
    workers = n_workers or min(os.cpu_count() or 1, 2)
    return ProcessPoolExecutor(max_workers=max(1, workers), mp_context=get_context("spawn"))


def _submit(pool: Any, fn: Any, *args: Any, **kwargs: Any) -> Any:
    if pool is None:
        done: Future[Any] = Future()
        try:
            done.set_result(fn(*args, **kwargs))
        except Exception as exc:
            done.set_exception(exc)
        return done
    return pool.submit(fn, *args, **kwargs)


def _folder_size(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def _drop_trajectories(store: Path) -> None:
    """Remove a sweep store's point trajectories, keep its summaries (the metrics)."""
    for path in (store / "points").glob("*.nc"):
        if not path.name.endswith(".summary.nc"):
            path.unlink(missing_ok=True)


def _stage_weights(settings: StudySettings, n_conv: int) -> dict[str, float]:
    """Prior wall time of each stage, in CPU seconds of one core (for the time left).

    Calibrated on the quick settings (CPU seconds per revolution at 150 rpm; a slower
    speed v costs 150/v times as much, the step being fixed in time): a flexible response
    point with its ideal companion 1.55 at the output grid T/2500 (2.6 at T/10000; rigid
    0.25); a rigid orbit revolution 0.08 before wear and 0.29 after (0.18 on average;
    flexible 1.2, on the paper settings); a convergence run 2 per revolution; a flexible
    chaos run 0.70 before and 1.19 after wear; a flexible exponent 2.8 (rigid 1.3). The
    long runs (wear, chaos runs, exponents) run in the pool beside the sweeps and the
    orbit diagrams, and the four processes share the two cores: a dask stage takes about
    its own CPU time in wall time, the pool doing as much meanwhile, and the long-runs
    stage is what the pool has left, on two cores. The analysis runs on one core.
    """
    flex = (1.2 + 0.35 * settings.samples_per_revolution / 2500) if settings.flexible_rods else 0.25
    speeds = sum(150.0 / v for v in _SPEEDS)
    before_speeds = sum(150.0 / v for v in _BEFORE_SPEEDS)
    orbit = (1.2 if settings.orbit_flexible_rods else 0.18) * sum(
        150.0 / v for v in settings.orbit_speeds
    )
    long_run = settings.discard_revolutions + settings.chaos_revolutions
    dask = {
        "before-wear sweep": len(_CLEARANCES) * settings.revolutions * before_speeds * flex,
        "after-wear sweeps": settings.revolutions * speeds * flex,
        "orbit diagrams over speed": 2 * settings.orbit_revolutions * orbit,
    }
    exponent = (
        (2.8 + (1.3 if settings.rigid_rod_exponent else 0.0)) if settings.flexible_rods else 1.3
    )
    pool = (
        0.5 * (settings.wear_updates + 1) * (settings.wear_settle_revolutions + 1) * speeds * flex
        + 2 * long_run * (0.95 if settings.flexible_rods else 0.2)
        + 2 * (settings.discard_revolutions + settings.exponent_revolutions) * exponent
    )
    samples = min(
        long_run * settings.chaos_samples_per_revolution, settings.max_samples or math.inf
    )
    return {
        # left out of the estimate: minutes on a fresh install, seconds with the cache
        "compiling the kernels (first run only)": 0.0,
        "before-wear sweep": dask["before-wear sweep"],
        # done in the pool while the before-wear sweep runs
        "wear prediction at 30, 90, 150 rpm": 0.0,
        "after-wear sweeps": dask["after-wear sweeps"],
        "element convergence": n_conv * settings.convergence_revolutions * 2.0,
        "orbit diagrams over speed": dask["orbit diagrams over speed"],
        "long runs for the chaos analysis and exponents": max(pool - sum(dask.values()), 0.0) / 2.0,
        "chaos analysis and report": 4 * (8.0 + 0.04e-3 * samples),
    }


class _LongRuns:
    """The study's long compiled runs in the process pool, in the order that finishes
    first: the three wear predictions (short; the after-wear sweeps wait for them) at once;
    as soon as the profile worn at 150 rpm exists, the after-wear chaos run (the longest
    run) first, then the before-wear chaos run, the two exponents and, when asked for, the
    rigid-rod ones. The pool's two processes then finish within a short run of each other
    (measured on the quick settings: 240 s of CPU for the after-wear chaos run against
    141 + 62 + 54 s for the rest).

    With no pool (``client="serial"``) everything runs here, in that order.
    """

    def __init__(self, pool: Any, base_scene: Any, settings: StudySettings) -> None:
        self._pool = pool
        self._settings = settings
        before = wear_scene_of(base_scene)
        # the wear predictions are short, and the after-wear sweeps wait for them
        self._wear = {
            float(rpm): _submit(pool, _predict_worn, _at_speed(base_scene, rpm), settings)
            for rpm in sorted(_SPEEDS, reverse=True)
        }
        self._states: dict[str, list[Any]] = {}
        self._queue = threading.Thread(
            target=self._then, args=(before,), name="paper-long-runs", daemon=True
        )
        if pool is None:
            self._then(before)
        else:
            self._queue.start()

    def _then(self, before: Any) -> None:
        pool, settings = self._pool, self._settings
        try:
            worn = self._wear[150.0].result()[0]
        except Exception:
            worn = None
        scenes = {"before wear": before, "after wear": worn}
        order = [s for s in ("after wear", "before wear") if scenes[s] is not None]
        runs: dict[str, list[Any]] = {s: [] for s in order}
        for state in order:
            runs[state].append(_submit(pool, _chaos_run, scenes[state], settings))
        for state in order:
            runs[state].append(_submit(pool, _equation_exponent, scenes[state], settings))
        # the rigid-rod model's exponent beside the flexible one
        rigid = settings.flexible_rods and settings.rigid_rod_exponent
        for state in order:
            runs[state].append(
                _submit(pool, _equation_exponent, scenes[state], settings, rigid=True)
                if rigid
                else None
            )
        self._states = {s: runs[s] for s in ("before wear", "after wear") if s in runs}
        self._scenes = scenes

    def rigid_exponent(self, state: str) -> Future[Any]:
        """The rigid-rod exponent of ``state``: the queued one, or queued now (a series
        that fell back to rigid rods is judged with it even when the settings leave it
        out)."""
        self._queued()
        queued = self._states[state][2]
        if queued is not None:
            return queued
        scene = self._scenes[state]
        return _submit(self._pool, _equation_exponent, scene, self._settings, rigid=True)

    def _queued(self) -> None:
        if self._queue.is_alive():
            self._queue.join()

    def wear(self) -> dict[float, Future[Any]]:
        """The wear predictions by speed (rpm), in increasing speed."""
        return {rpm: self._wear[rpm] for rpm in sorted(self._wear)}

    def states(self) -> dict[str, tuple[Future[Any], Future[Any], Future[Any] | None]]:
        """(chaos run, exponent on the series' model, rigid-rod exponent or None when the
        series are rigid) of each state whose scene exists."""
        self._queued()
        return {state: (f[0], f[1], f[2]) for state, f in self._states.items() if len(f) == 3}


def _at_speed(scene: Any, rpm: float) -> Any:
    return scene.replace({"drive.speed_rpm": rpm})


# --------------------------------------------------------------------------- the study


def run_paper_study(
    output: str | Path,
    *,
    quick: bool = False,
    client: Any = None,
    n_workers: int | None = None,
    scene: Any = "paper",
    progress: bool = False,
    keep_trajectories: bool = False,
    command: str | None = None,
    _settings: StudySettings | Mapping[str, Any] | None = None,
) -> PaperStudy:
    """Run the whole study of the paper and write its report, the answer first.

    What runs (the model: docs/paper-model.md; the stages: docs/paper-study.md):

    1. **before wear**: a sweep of the ``paper`` scene over clearance c ∈ {0.1, 0.2, 0.5} mm
       × crank speed {30, 90, 150} rpm — the clearance table (150 rpm, and 90 rpm because
       the paper does not print that table's conditions: docs/paper-model.md, “Clearance
       size”) and the before-wear row;
    2. **wear**: :func:`mechanism.predict_wear` at 30, 90 and 150 rpm, c = 0.2 mm, each
       speed worn at its own speed as the paper did; the amount is set by the cycles;
    3. **after wear**: each worn scene at its speed — the speed table and the after-wear
       row (150 rpm);
    4. **chaos**: per state (before, after wear at 150 rpm) a run of
       ``chaos_revolutions`` revolutions after the transient at T/10000 with flexible rods,
       analysed by :func:`chaoskit.report` (verdict, delay, embedding, Wolf and Rosenstein
       exponents), beside :func:`mechanism.lyapunov_exponent` of the same model (and of
       the rigid-rod one);
    5. **element convergence**: :func:`mechanism.element_convergence`;
    6. **orbit diagrams** over crank speed before and after wear
       (:func:`mechanism.bifurcation`).

    The report opens with a summary: the verdict of each state with its confidence, the
    exponents in 1/s and bits per sample, and the paper's values and claims beside ours.

    Parameters
    ----------
    output
        Folder for ``report.html``, ``report.md`` (+ figures) and the sweep stores
        (``runs/``).
    quick
        Use :meth:`StudySettings.quick` (documented reductions) instead of
        :meth:`StudySettings.paper`.
    client, n_workers
        Backend of the sweeps, as in :func:`mechanism.sweep` (``"serial"`` runs everything
        in this process; None: a ``LocalCluster``); ``n_workers`` also sizes the process
        pool of the long runs.
    scene
        Base scene (default the built-in ``paper``: reconstructed geometry, clearance at C).
    progress
        Print each stage with the elapsed time and an estimate of the time left.
    keep_trajectories
        Keep the trajectories of the sweep points and of the chaos runs (``runs/`` and
        ``trajectories/``, hundreds of MB); by default only their metrics are kept and a
        re-run recomputes the points.
    command
        Command line recorded in the report's provenance.

    Returns
    -------
    PaperStudy

    Examples
    --------
    >>> import mechanism
    >>> if __name__ == "__main__":  # doctest: +SKIP
    ...     study = mechanism.run_paper_study("results", quick=True)
    ...     print(study.tables["wear"])
    """
    t0 = time.perf_counter()
    if _settings is None:
        settings = StudySettings.quick() if quick else StudySettings.paper()
    elif isinstance(_settings, StudySettings):
        settings = _settings
    else:
        base = StudySettings.quick() if quick else StudySettings.paper()
        settings = dataclasses.replace(base, **dict(_settings))
    out = Path(output).resolve()
    runs = out / "runs"
    runs.mkdir(parents=True, exist_ok=True)
    base_scene = load_scene(scene)
    base_scene = base_scene.replace(
        {
            "effects.flexibility": settings.flexible_rods,
            "joints.C.clearance": _DEFAULT_CLEARANCE,
            "solver.max_step": _STEP,
        }
    )
    paper = paper_tables()
    claims = paper_claims()
    unavailable: list[str] = []
    stages = Stages(_stage_weights(settings, len(settings.elements)), enabled=progress)
    analysis = Analysis(variables=(), discard_revolutions=settings.discard_revolutions)
    spr = [settings.samples_per_revolution]
    period = 60.0 / 150.0
    before_store = runs / _store_name("before", settings, quick)
    stores = [before_store]

    with contextlib.ExitStack() as context:
        pool = context.enter_context(_pool(client, n_workers))
        if pool is not None:
            # compile once, in the pool's processes, before the workers start
            with stages.stage("compiling the kernels (first run only)"):
                rigid_exponent = settings.rigid_rod_exponent or not settings.flexible_rods
                for future in [
                    _submit(pool, _compile_kernels, p, rigid_exponent=rigid_exponent)
                    for p in ("flexible", "rigid")
                ]:
                    # a speed-up only: a path that fails here fails again, with its
                    # message, in the run that needs it
                    with contextlib.suppress(Exception):
                        future.result()
        backend = context.enter_context(
            _session_client(client, n_workers, len(_CLEARANCES) * len(_BEFORE_SPEEDS))
        )
        # The long compiled runs go to the pool first, the longest chain (the wear at
        # 150 rpm, then the after-wear chaos run) at its head; the sweeps and orbit
        # diagrams run on dask meanwhile, and the results are collected when needed.
        long_runs = _LongRuns(pool, base_scene, settings)
        with stages.stage("before-wear sweep"):
            before = sweep(
                base_scene,
                grid={
                    "joints.C.clearance": list(_CLEARANCES),
                    "drive.speed_rpm": list(_BEFORE_SPEEDS),
                    _SPR: spr,
                },
                revolutions=settings.revolutions,
                analysis=analysis,
                client=backend,
                store=before_store,
                progress=False,
            ).isel({_SPR: 0}, drop=True)
        worn: dict[float, Any] = {}
        profiles: dict[str, xr.Dataset] = {}
        wear_info: list[str] = []
        with stages.stage("wear prediction at 30, 90, 150 rpm"):
            for rpm, future in long_runs.wear().items():
                try:
                    worn[rpm], profile, info = future.result()
                except Exception as exc:
                    unavailable.append(
                        f"wear prediction at {rpm:g} rpm failed: {type(exc).__name__}: {exc}"
                    )
                    continue
                wear_info.append(info)
                if profile is not None:
                    profiles[f"worn at {rpm:g} rpm"] = profile
        after: dict[float, xr.Dataset] = {}
        with stages.stage("after-wear sweeps"):
            for speed in _SPEEDS:
                if speed not in worn:
                    continue
                store = runs / _store_name(f"after-{speed:g}rpm", settings, quick)
                stores.append(store)
                after[speed] = sweep(
                    worn[speed],
                    grid={"drive.speed_rpm": [speed], _SPR: spr},
                    revolutions=settings.revolutions,
                    analysis=analysis,
                    client=backend,
                    store=store,
                    progress=False,
                ).isel({_SPR: 0, "drive.speed_rpm": 0}, drop=True)
        state_scenes = {"before wear": wear_scene_of(base_scene)}
        if 150 in worn:
            state_scenes["after wear"] = worn[150]
        conv_rows: dict[int, list[float]] = {}
        conv_errors: list[str] = []
        with stages.stage("element convergence"):
            conv_scene = wear_scene_of(base_scene).replace({"effects.flexibility": True})
            for n in settings.elements:
                try:
                    conv_rows[n] = _convergence_run(conv_scene, n, settings)
                except Exception as exc:
                    conv_errors.append(f"{n} elements: {type(exc).__name__}: {exc}")
        orbits: dict[str, xr.Dataset] = {}
        with stages.stage("orbit diagrams over speed"):
            for state, sc in state_scenes.items():
                store = runs / _store_name(f"orbit-{state.replace(' ', '-')}", settings, quick)
                stores.append(store)
                try:
                    orbits[state] = bifurcation(
                        sc.replace(
                            {
                                "effects.flexibility": settings.orbit_flexible_rods,
                                # rigid rods: the error control and the approach limit
                                # resolve the impacts; the study's step cap is for the
                                # fixed-step generalized-α of flexible rods
                                "solver.max_step": sc.solver.max_step
                                if settings.orbit_flexible_rods
                                else None,
                            }
                        ),
                        parameter="drive.speed_rpm",
                        values=list(settings.orbit_speeds),
                        revolutions=settings.orbit_revolutions,
                        discard=settings.orbit_discard_revolutions,
                        variables=("eccentricity_x",),
                        client=backend,
                        store=store,
                    )
                except Exception as exc:
                    unavailable.append(f"orbit diagram {state}: {type(exc).__name__}: {exc}")
        trajectories: dict[str, xr.Dataset] = {}
        equations: dict[str, Any] = {}
        rigid_equations: dict[str, Any] = {}
        with stages.stage("long runs for the chaos analysis and exponents"):
            for state, futures in long_runs.states().items():
                chaos_future, exponent_future, rigid_future = futures
                try:
                    trajectories[state] = chaos_future.result()
                except Exception as exc:
                    unavailable.append(f"chaos run {state} failed: {type(exc).__name__}: {exc}")
                for store, future, model in (
                    (equations, exponent_future, "the series' model"),
                    (rigid_equations, rigid_future, "rigid rods"),
                ):
                    if future is None:
                        continue
                    try:
                        store[state] = future.result()
                    except Exception as exc:
                        store[state] = None
                        unavailable.append(
                            f"exponent from the equations ({model}), {state}: "
                            f"{type(exc).__name__}: {exc}"
                        )
                # series that fell back to rigid rods are judged with the rigid exponent
                if "rods_note" in getattr(trajectories.get(state), "attrs", {}):
                    if rigid_future is not None:  # collected above, its failure noted
                        equations[state] = rigid_equations.pop(state, None)
                    else:
                        try:
                            equations[state] = long_runs.rigid_exponent(state).result()
                        except Exception as exc:
                            equations[state] = None
                            unavailable.append(
                                f"exponent from the equations (rigid rods), {state}: "
                                f"{type(exc).__name__}: {exc}"
                            )

    # ---- tables (ours, in the paper's units)
    c0 = _DEFAULT_CLEARANCE
    tables: dict[str, pd.DataFrame] = {}
    rows = {
        "before wear": _metrics_row(
            _point(before, **{"joints.C.clearance": c0, "drive.speed_rpm": 150})
        )
    }
    if 150 in after:
        rows["after wear"] = _metrics_row(after[150])
    tables["wear"] = _frame(rows, "state")
    for rpm, key in ((150, "clearance"), (90, "clearance_90rpm")):
        tables[key] = _frame(
            {
                _clearance_label(c): _metrics_row(
                    _point(before, **{"joints.C.clearance": c, "drive.speed_rpm": rpm})
                )
                for c in _CLEARANCES
            },
            "clearance",
        )
    tables["speed"] = _frame(
        {
            _speed_label(v): _metrics_row(after[v])
            if v in after
            else dict.fromkeys(COLUMNS, math.nan)
            for v in _SPEEDS
        },
        "speed",
    )
    elements = sorted(set(settings.elements) | {int(e) for e in paper["convergence"].index})
    tables["convergence"] = pd.DataFrame(
        [conv_rows.get(n, [math.nan] * len(_RODS)) for n in elements],
        index=pd.Index(elements, name="elements"),
        columns=list(_RODS),
    )
    if conv_errors:
        unavailable.append("element convergence failed: " + "; ".join(conv_errors))

    # ---- chaos analysis and the report
    with stages.stage("chaos analysis and report"):
        dt_paper = period / _PAPER_SAMPLES
        chaos_ref = paper["chaos"].copy()
        chaos_ref["lag_time"] = chaos_ref["lag"] * dt_paper
        chaos_ref["mle_wolf"] = chaos_ref["mle_wolf_bits"] * math.log(2.0) / dt_paper
        chaos_ref = chaos_ref[
            [s in trajectories for s in chaos_ref.index.get_level_values("state")]
        ]
        notes = _table_notes(settings, unavailable, has_wear=150 in after, wear_info=wear_info)
        report_tables = _report_tables(tables, paper, notes, has_after=150 in after)
        if command is None:
            command = " ".join(shlex.quote(a) for a in sys.argv) if sys.argv else "run_paper_study"
        analysis_options = chaos_analysis_options(settings) if trajectories else {}
        rep = chaoskit.report(
            trajectories or None,
            exponents={s: e for s, e in equations.items() if e is not None and s in trajectories},
            **analysis_options,
            chaos_reference=chaos_ref if trajectories else None,
            reference_name="paper",
            chaos_notes=notes["chaos"],
            tables=report_tables,
            parameters={"quick": quick, "settings": settings.to_dict()},
            title="Is the six-bar press with a worn clearance joint chaotic? Jia et al. (2025) "
            "reproduced" + (" (quick settings)" if quick else ""),
            command=command,
        )
        chaos = rep.table("Chaos table").data if trajectories else pd.DataFrame()
        tables["chaos"] = chaos
        headline: list[chaoskit.ReportFigure] = []
        if trajectories:
            # the points the motion verdict counted: one source for the figure and tables
            fig = strobe_figure(
                trajectories, motions=rep.motions, discard=analysis_options["discard"]
            )
            headline.append(
                chaoskit.ReportFigure.from_matplotlib(
                    fig,
                    caption="Stroboscopic maps of the journal centre of joint C (once per crank "
                    f"revolution over the {plural(settings.chaos_revolutions, 'revolution')} "
                    f"after the transient, {_rods_of(trajectories, settings)} rods, "
                    "150 rpm, c = 0.2 mm): before and after wear. The points are those of "
                    "the joint section the motion verdict counts (its “joint section” "
                    "column), the initial state and the transient left out.",
                    name="strobe-before-after",
                    section="Summary",
                )
            )
        if orbits:
            headline.append(_orbit_figure(orbits, settings))
        wall_so_far = time.perf_counter() - t0
        rods_notes = "".join(
            f" {state.capitalize()}: {traj.attrs['rods_note']}."
            for state, traj in trajectories.items()
            if "rods_note" in traj.attrs
        )
        settings_text = (
            f"Settings: {'quick' if quick else 'paper'}; chaos from "
            f"{plural(settings.chaos_revolutions, 'revolution')} per state after "
            f"{plural(settings.discard_revolutions, 'revolution')} of transient, integration "
            f"step T/{_PAPER_SAMPLES} (T = {period:g} s at 150 rpm), series sampled at T/"
            f"{settings.chaos_samples_per_revolution}; rods "
            f"{'flexible (ANCF)' if settings.flexible_rods else 'rigid'}; the bearing of "
            "each speed's row is worn at that speed for "
            f"{settings.wear_updates * settings.wear_cycles_per_update:,.0f} crank "
            f"cycles.{rods_notes} Wall time {wall_so_far / 60:.1f} min until the report. The "
            "model and every reconstruction choice: docs/paper-model.md."
        )
        summary = summary_section(
            states=[s for s in ("before wear", "after wear") if s in state_scenes],
            motions=rep.motions,
            chaos=chaos,
            paper_chaos=paper["chaos"],
            claims=claims,
            equations=equations,
            rigid_equations=rigid_equations,
            paper_step=dt_paper,
            settings_text=settings_text,
            figures=headline,
            series_rods=_rods_of(trajectories, settings),
        )
        sections = [summary]
        if profiles:
            sections.append(
                wear_profile_section(
                    profiles, sectors=paper_wear_zones(), sector_label="paper's wear zones"
                )
            )
        rep = dataclasses.replace(rep, sections=(*sections, *rep.sections))
        if keep_trajectories:
            folder = out / "trajectories"
            folder.mkdir(exist_ok=True)
            for state, traj in trajectories.items():
                chaoskit.save_trajectory(traj, folder / f"{state.replace(' ', '-')}.nc")
        else:
            for store in stores:
                _drop_trajectories(store)
        rep.write(out / "report.html")
    stages.report()
    wall = time.perf_counter() - t0
    size = _folder_size(out)
    cpu = float(stages.summary().at["total", "cpu_min"]) * 60.0
    rep = _with_run_facts(
        rep, wall=wall, cpu=cpu, size=size, wear_info=wear_info, unavailable=unavailable
    )
    rep = dataclasses.replace(rep, sections=(*rep.sections, _cost_section(stages)))
    rep.write(out / "report.html")
    return PaperStudy(
        tables=tables,
        paper=paper,
        report_html=out / "report.html",
        report_markdown=out / "report.md",
        output=out,
        settings=settings,
        quick=quick,
        unavailable=tuple(unavailable),
        wall_time=time.perf_counter() - t0,
        output_size=_folder_size(out),
        sweeps={"before": before, **{f"after {k:g} rpm": v for k, v in after.items()}},
        motions=dict(rep.motions),
    )


def _rods_of(trajectories: Mapping[str, xr.Dataset], settings: StudySettings) -> str:
    """The rods of the analysed series, per state when a flexible run fell back to rigid."""
    if not settings.flexible_rods:
        return "rigid"
    rigid = [s for s, traj in trajectories.items() if "rods_note" in traj.attrs]
    if not rigid:
        return "flexible"
    return "flexible (" + ", ".join(rigid) + ": rigid)"


def wear_scene_of(scene: Any) -> Any:
    """The before-wear state of the chaos analysis: 150 rpm, c = 0.2 mm."""
    return scene.replace({"drive.speed_rpm": 150, "joints.C.clearance": _DEFAULT_CLEARANCE})


def _orbit_figure(orbits: Mapping[str, xr.Dataset], settings: StudySettings) -> Any:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0 * len(orbits), 4.0), layout="constrained")
    axes = fig.subplots(1, len(orbits), squeeze=False)[0]
    for ax, (state, ds) in zip(axes, orbits.items(), strict=False):
        plot_bifurcation(_orbit_display(ds), axes=[ax])
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


def _orbit_display(ds: xr.Dataset) -> xr.Dataset:
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


def _cost_section(stages: Stages) -> chaoskit.ReportSection:
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


def _with_run_facts(
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


def _table_notes(
    settings: StudySettings,
    unavailable: list[str],
    *,
    has_wear: bool,
    wear_info: Sequence[str] = (),
) -> dict[str, str]:
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
        f"{_NOT_AVAILABLE}: the wear prediction (mechanism.predict_wear) — no after-wear row. "
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
            else f"{_NOT_AVAILABLE}: wear prediction; no after-wear rows. "
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
        + next((f"{_NOT_AVAILABLE}: {u}." for u in unavailable if "convergence" in u), ""),
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
        + ("" if has_wear else f" {_NOT_AVAILABLE}: wear prediction — no after-wear rows."),
    }


def _magnitude_ratio(a: float, b: float) -> float:
    return abs(a) / abs(b) if math.isfinite(a) and math.isfinite(b) and b != 0.0 else math.nan


def _wear_comparison(ours: pd.DataFrame, paper: pd.DataFrame) -> pd.DataFrame:
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


def _report_tables(
    tables: Mapping[str, pd.DataFrame],
    paper: Mapping[str, pd.DataFrame],
    notes: Mapping[str, str],
    *,
    has_after: bool,
) -> list[Any]:
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
        data=_wear_comparison(tables["wear"], paper["wear"]),
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
