"""The run of the paper study: its stages in order, then the tables and the report.

:func:`run_paper_study` is the sequence; each stage is one function over :class:`_Run`,
which holds what the stages share (settings, output folders, the progress stages, the
sweeps' backend and what could not be run).
"""

from __future__ import annotations

import contextlib
import dataclasses
import shlex
import sys
import time
from collections.abc import Mapping
from concurrent.futures import BrokenExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pandas as pd
import xarray as xr

import chaoskit
from mechanism.core import load_scene

from .._orbit_diagram import bifurcation
from .._wear_report import wear_profile_section
from ..sweep import Analysis, sweep
from ._claims import judge_claims, path_label
from ._published import (
    BEFORE_SPEEDS,
    CLEARANCES,
    DEFAULT_CLEARANCE,
    PAPER_SAMPLES,
    PERIOD_150,
    SPEEDS,
    SPR,
    STEP,
    TRANSITION_CLAIMS,
    paper_claims,
    paper_tables,
    paper_wear_zones,
)
from ._report import (
    chaos_reference,
    cost_section,
    orbit_figure,
    report_tables,
    rods_of,
    settings_text,
    strobe_headline,
    table_notes,
    with_run_facts,
)
from ._result import PaperStudy
from ._route import route_section
from ._runs import chaos_analysis_options, compile_kernels, convergence_run, wear_scene_of
from ._schedule import (
    WEAR_PATHS_STAGE,
    LongRuns,
    drop_trajectories,
    folder_size,
    process_pool,
    session_client,
    stage_weights,
    store_name,
    submit,
)
from ._settings import StudySettings
from ._summary import Stages, summary_section
from ._tables import response_tables
from ._wear_paths import claims_frame, outcomes_of, wear_life_opening, wear_life_tables


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
    settings: StudySettings | Mapping[str, Any] | None = None,
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
       (:func:`mechanism.bifurcation`);
    7. **wear paths**: :func:`mechanism.wear_life` at 30, 90 and 150 rpm (c = 0.2 mm) and
       at c = 0.1, 0.2 and 0.5 mm (150 rpm), five paths, each one task of the pool.

    The report opens with a summary: first the wear-life answer — each wear path's cycles
    to chaos (or "not within N cycles") with its confidence, beside the paper's claims on
    the transition to chaos, each with agree / disagree / cannot tell and one line of
    why — then the verdict of each state with its confidence, the exponents in 1/s and
    bits per sample, and the paper's values and claims beside ours.

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
    settings
        How much is run: a :class:`StudySettings` (used as given; ``quick`` then only
        names the run), or a mapping of fields that replace those of the ``quick`` or paper
        settings, e.g. ``{"revolutions": 3.0}``. Default: :meth:`StudySettings.quick` with
        ``quick``, else :meth:`StudySettings.paper`.

    Returns
    -------
    PaperStudy

    Examples
    --------
    >>> import mechanism
    >>> if __name__ == "__main__":  # doctest: +SKIP
    ...     study = mechanism.run_paper_study("results", quick=True)
    ...     print(study.tables["wear"])
    ...     fewer = {"elements": (4, 8)}  # the quick settings, fewer convergence runs
    ...     study = mechanism.run_paper_study("results-2", quick=True, settings=fewer)
    """
    t0 = time.perf_counter()
    run = _Run.start(
        output,
        settings=_resolve_settings(settings, quick=quick),
        quick=quick,
        scene=scene,
        progress=progress,
    )
    with contextlib.ExitStack() as context:
        pool = context.enter_context(process_pool(client, n_workers))
        if pool is not None:
            _compile_in_pool(run, pool)
        run.backend = context.enter_context(
            session_client(client, n_workers, len(CLEARANCES) * len(BEFORE_SPEEDS))
        )
        # The long compiled runs go to the pool first, the longest chain (the wear at
        # 150 rpm, then the after-wear chaos run) at its head; the sweeps and orbit
        # diagrams run on dask meanwhile, and the results are collected when needed.
        long_runs = LongRuns(pool, run.base_scene, run.settings)
        results = _run_stages(run, long_runs)
        tables = response_tables(
            before=results.before,
            after=results.after,
            convergence=results.convergence,
            elements=run.settings.elements,
            paper=run.paper,
        )
        if results.convergence_errors:
            run.unavailable.append(
                "element convergence failed: " + "; ".join(results.convergence_errors)
            )
        with run.stages.stage("chaos analysis and report"):
            # the states' verdicts are tasks of the pool, one per state; a pool that lost a
            # worker gives way to this process (the same verdicts: each state has its stream)
            try:
                rep = _report(run, results, tables, command=command, t0=t0, executor=pool)
            except BrokenExecutor:
                rep = _report(run, results, tables, command=command, t0=t0, executor=None)
            _keep_or_drop_trajectories(run, results.trajectories, keep=keep_trajectories)
            rep.write(run.out / "report.html")
    return _finish(run, results, tables, rep, t0=t0)


def _resolve_settings(
    settings: StudySettings | Mapping[str, Any] | None, *, quick: bool
) -> StudySettings:
    """The settings of the run: as given, or the quick/paper ones with ``settings``'s
    fields replaced."""
    if isinstance(settings, StudySettings):
        return settings
    base = StudySettings.quick() if quick else StudySettings.paper()
    if settings is None:
        return base
    if not isinstance(settings, Mapping):
        raise TypeError(
            "settings must be a mechanism.StudySettings or a mapping of its fields; "
            f"got {type(settings).__name__}."
        )
    return dataclasses.replace(base, **dict(settings))


@dataclass(kw_only=True, eq=False)
class _Run:
    """What the stages of one study share."""

    settings: StudySettings
    quick: bool
    out: Path
    runs: Path
    base_scene: Any
    stages: Stages
    analysis: Analysis
    paper: dict[str, pd.DataFrame]
    backend: Any = None
    stores: list[Path] = field(default_factory=list)
    unavailable: list[str] = field(default_factory=list)

    @classmethod
    def start(
        cls,
        output: str | Path,
        *,
        settings: StudySettings,
        quick: bool,
        scene: Any,
        progress: bool,
    ) -> _Run:
        """Create the output folders and the study's base scene (c = 0.2 mm, the study's
        step, the settings' rods)."""
        out = Path(output).resolve()
        runs = out / "runs"
        runs.mkdir(parents=True, exist_ok=True)
        base_scene = load_scene(scene).replace(
            {
                "effects.flexibility": settings.flexible_rods,
                "joints.C.clearance": DEFAULT_CLEARANCE,
                "solver.max_step": STEP,
            }
        )
        return cls(
            settings=settings,
            quick=quick,
            out=out,
            runs=runs,
            base_scene=base_scene,
            stages=Stages(stage_weights(settings, len(settings.elements)), enabled=progress),
            analysis=Analysis(variables=(), discard_revolutions=settings.discard_revolutions),
            paper=paper_tables(),
        )

    def store(self, kind: str) -> Path:
        """A new sweep store of this study (its trajectories are dropped at the end)."""
        path = self.runs / store_name(kind, self.settings, self.quick)
        self.stores.append(path)
        return path


@dataclass(kw_only=True, eq=False)
class _Results:
    """What the stages computed."""

    before: xr.Dataset
    after: dict[float, xr.Dataset]
    profiles: dict[str, xr.Dataset]
    wear_info: list[str]
    state_scenes: dict[str, Any]
    convergence: dict[int, list[float]]
    convergence_errors: list[str]
    orbits: dict[str, xr.Dataset]
    trajectories: dict[str, xr.Dataset]
    equations: dict[str, Any]
    rigid_equations: dict[str, Any]
    wear_paths: dict[tuple[float, float], Any]


def _compile_in_pool(run: _Run, pool: Any) -> None:
    """Compile the kernels once, in the pool's processes, before the workers start."""
    with run.stages.stage("compiling the kernels (first run only)"):
        settings = run.settings
        rigid_exponent = (
            settings.rigid_rod_exponent
            or not settings.flexible_rods
            or (settings.wear_paths and not settings.wear_path_flexible_rods)
        )
        for future in [
            submit(pool, compile_kernels, p, rigid_exponent=rigid_exponent)
            for p in ("flexible", "rigid")
        ]:
            # a speed-up only: a path that fails here fails again, with its message, in
            # the run that needs it
            with contextlib.suppress(Exception):
                future.result()


def _run_stages(run: _Run, long_runs: LongRuns) -> _Results:
    """Every computing stage in order, under the progress stages."""
    with run.stages.stage("before-wear sweep"):
        before = _before_wear_sweep(run)
    with run.stages.stage("wear prediction at 30, 90, 150 rpm"):
        worn, profiles, wear_info = _collect_wear(run, long_runs)
    with run.stages.stage("after-wear sweeps"):
        after = _after_wear_sweeps(run, worn)
    state_scenes = {"before wear": wear_scene_of(run.base_scene)}
    if 150 in worn:
        state_scenes["after wear"] = worn[150]
    with run.stages.stage("element convergence"):
        convergence, convergence_errors = _element_convergence(run)
    with run.stages.stage("orbit diagrams over speed"):
        orbits = _orbit_diagrams(run, state_scenes)
    with run.stages.stage(WEAR_PATHS_STAGE):
        wear_paths = _collect_wear_paths(run, long_runs)
    with run.stages.stage("long runs for the chaos analysis and exponents"):
        trajectories, equations, rigid_equations = _collect_long_runs(run, long_runs)
    return _Results(
        before=before,
        after=after,
        profiles=profiles,
        wear_info=wear_info,
        state_scenes=state_scenes,
        convergence=convergence,
        convergence_errors=convergence_errors,
        orbits=orbits,
        trajectories=trajectories,
        equations=equations,
        rigid_equations=rigid_equations,
        wear_paths=wear_paths,
    )


def _collect_wear_paths(run: _Run, long_runs: LongRuns) -> dict[tuple[float, float], Any]:
    """Each wear path's WearLife, or the exception its run raised (the answer says it
    cannot tell, and why)."""
    found: dict[tuple[float, float], Any] = {}
    for key, future in long_runs.paths().items():
        try:
            found[key] = future.result()
        except Exception as exc:
            found[key] = exc
            run.unavailable.append(
                f"wear path at {path_label(*key)} failed: {type(exc).__name__}: {exc}"
            )
    return found


def _before_wear_sweep(run: _Run) -> xr.Dataset:
    """Clearance × speed before wear (the clearance tables and the before-wear row)."""
    return sweep(
        run.base_scene,
        grid={
            "joints.C.clearance": list(CLEARANCES),
            "drive.speed_rpm": list(BEFORE_SPEEDS),
            SPR: [run.settings.samples_per_revolution],
        },
        revolutions=run.settings.revolutions,
        analysis=run.analysis,
        client=run.backend,
        store=run.store("before"),
        progress=False,
    ).isel({SPR: 0}, drop=True)


def _collect_wear(
    run: _Run, long_runs: LongRuns
) -> tuple[dict[float, Any], dict[str, xr.Dataset], list[str]]:
    """The worn scenes by speed (rpm), their wear profiles and one line on each wear; a
    failed prediction is noted as unavailable."""
    worn: dict[float, Any] = {}
    profiles: dict[str, xr.Dataset] = {}
    wear_info: list[str] = []
    for rpm, future in long_runs.wear().items():
        try:
            worn[rpm], profile, info = future.result()
        except Exception as exc:
            run.unavailable.append(
                f"wear prediction at {rpm:g} rpm failed: {type(exc).__name__}: {exc}"
            )
            continue
        wear_info.append(info)
        if profile is not None:
            profiles[f"worn at {rpm:g} rpm"] = profile
    return worn, profiles, wear_info


def _after_wear_sweeps(run: _Run, worn: Mapping[float, Any]) -> dict[float, xr.Dataset]:
    """Each worn scene at its own speed: one point per speed (rpm)."""
    after: dict[float, xr.Dataset] = {}
    for speed in SPEEDS:
        if speed not in worn:
            continue
        after[speed] = sweep(
            worn[speed],
            grid={"drive.speed_rpm": [speed], SPR: [run.settings.samples_per_revolution]},
            revolutions=run.settings.revolutions,
            analysis=run.analysis,
            client=run.backend,
            store=run.store(f"after-{speed:g}rpm"),
            progress=False,
        ).isel({SPR: 0, "drive.speed_rpm": 0}, drop=True)
    return after


def _element_convergence(run: _Run) -> tuple[dict[int, list[float]], list[str]]:
    """Rod strains by elements per rod (flexible rods, before wear) and the failures."""
    rows: dict[int, list[float]] = {}
    errors: list[str] = []
    scene = wear_scene_of(run.base_scene).replace({"effects.flexibility": True})
    for n in run.settings.elements:
        try:
            rows[n] = convergence_run(scene, n, run.settings)
        except Exception as exc:
            errors.append(f"{n} elements: {type(exc).__name__}: {exc}")
    return rows, errors


def _orbit_diagrams(run: _Run, state_scenes: Mapping[str, Any]) -> dict[str, xr.Dataset]:
    """The orbit diagram over crank speed of each state; a failure is noted."""
    settings = run.settings
    orbits: dict[str, xr.Dataset] = {}
    for state, sc in state_scenes.items():
        store = run.store(f"orbit-{state.replace(' ', '-')}")
        try:
            orbits[state] = bifurcation(
                sc.replace(
                    {
                        "effects.flexibility": settings.orbit_flexible_rods,
                        # rigid rods: the error control and the approach limit resolve
                        # the impacts; the study's step cap is for the fixed-step
                        # generalized-α of flexible rods
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
                client=run.backend,
                store=store,
            )
        except Exception as exc:
            run.unavailable.append(f"orbit diagram {state}: {type(exc).__name__}: {exc}")
    return orbits


def _collect_long_runs(
    run: _Run, long_runs: LongRuns
) -> tuple[dict[str, xr.Dataset], dict[str, Any], dict[str, Any]]:
    """The chaos runs' series, the exponents on the series' model and the rigid-rod
    exponents, by state; each failure is noted (its exponent None)."""
    trajectories: dict[str, xr.Dataset] = {}
    equations: dict[str, Any] = {}
    rigid_equations: dict[str, Any] = {}
    for state, (chaos_future, exponent_future, rigid_future) in long_runs.states().items():
        try:
            trajectories[state] = chaos_future.result()
        except Exception as exc:
            run.unavailable.append(f"chaos run {state} failed: {type(exc).__name__}: {exc}")
        for found, future, model in (
            (equations, exponent_future, "the series' model"),
            (rigid_equations, rigid_future, "rigid rods"),
        ):
            if future is None:
                continue
            try:
                found[state] = future.result()
            except Exception as exc:
                found[state] = None
                run.unavailable.append(
                    f"exponent from the equations ({model}), {state}: {type(exc).__name__}: {exc}"
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
                    run.unavailable.append(
                        f"exponent from the equations (rigid rods), {state}: "
                        f"{type(exc).__name__}: {exc}"
                    )
    return trajectories, equations, rigid_equations


def _report(
    run: _Run,
    results: _Results,
    tables: dict[str, pd.DataFrame],
    *,
    command: str | None,
    t0: float,
    executor: Any,
) -> Any:
    """The chaos analysis (:func:`chaoskit.report`, its states classified on ``executor``
    when not None) with the summary and the wear profiles in front; adds the chaos table
    to ``tables``."""
    settings, trajectories = run.settings, results.trajectories
    has_after = 150 in results.after
    notes = table_notes(settings, run.unavailable, has_wear=has_after, wear_info=results.wear_info)
    if command is None:
        command = " ".join(shlex.quote(a) for a in sys.argv) if sys.argv else "run_paper_study"
    analysis_options = chaos_analysis_options(settings, executor=executor) if trajectories else {}
    extras = chaoskit.ReportExtras(
        exponents={
            s: e for s, e in results.equations.items() if e is not None and s in trajectories
        },
        chaos_reference=chaos_reference(run.paper, trajectories) if trajectories else None,
        reference_name="paper",
        chaos_notes=notes["chaos"],
        tables=report_tables(tables, run.paper, notes, has_after=has_after),
        parameters={"quick": run.quick, "settings": settings.to_dict()},
        command=command,
    )
    rep = chaoskit.report(
        trajectories or None,
        **analysis_options,
        title="Is the six-bar press with a worn clearance joint chaotic? Jia et al. (2025) "
        "reproduced" + (" (quick settings)" if run.quick else ""),
        extras=extras,
    )
    chaos = rep.table("Chaos table").data if trajectories else pd.DataFrame()
    tables["chaos"] = chaos
    headline: list[chaoskit.ReportFigure] = []
    if trajectories:
        headline.append(strobe_headline(trajectories, rep, settings, analysis_options["discard"]))
    if results.orbits:
        headline.append(orbit_figure(results.orbits, settings))
    summary = summary_section(
        states=[s for s in ("before wear", "after wear") if s in results.state_scenes],
        motions=rep.motions,
        chaos=chaos,
        paper_chaos=run.paper["chaos"],
        claims=paper_claims(),
        equations=results.equations,
        rigid_equations=results.rigid_equations,
        paper_step=PERIOD_150 / PAPER_SAMPLES,
        settings_text=settings_text(
            settings,
            quick=run.quick,
            trajectories=trajectories,
            wall_so_far=time.perf_counter() - t0,
        ),
        figures=headline,
        series_rods=rods_of(trajectories, settings),
    )
    if results.wear_paths:
        summary = _with_wear_life(summary, results.wear_paths, settings)
    sections = [summary]
    if results.profiles:
        sections.append(
            wear_profile_section(
                results.profiles, sectors=paper_wear_zones(), sector_label="paper's wear zones"
            )
        )
    try:
        # a stored result (computing it is minutes of CPU): data/route_rigid.json
        sections.append(route_section())
    except (OSError, ValueError, KeyError) as exc:
        run.unavailable.append(f"route to chaos over crank speed: the stored result: {exc}")
    return dataclasses.replace(rep, sections=(*sections, *rep.sections))


def _with_wear_life(
    summary: chaoskit.ReportSection,
    paths: Mapping[tuple[float, float], Any],
    settings: StudySettings,
) -> chaoskit.ReportSection:
    """The summary opening with the wear-life answer: its sentences first, then the claims
    and the paths tables before the before/after-wear answer."""
    outcomes = outcomes_of(paths)
    verdicts = judge_claims(TRANSITION_CLAIMS, outcomes)
    opening = wear_life_opening(outcomes, verdicts, settings)
    return dataclasses.replace(
        summary,
        text=f"{opening} {summary.text}",
        items=(*wear_life_tables(outcomes, verdicts, settings), *summary.items),
    )


def _keep_or_drop_trajectories(
    run: _Run, trajectories: Mapping[str, xr.Dataset], *, keep: bool
) -> None:
    """Save the chaos runs' series (``keep``) or drop the sweep stores' trajectories."""
    if keep:
        folder = run.out / "trajectories"
        folder.mkdir(exist_ok=True)
        for state, traj in trajectories.items():
            chaoskit.save_trajectory(traj, folder / f"{state.replace(' ', '-')}.nc")
    else:
        for store in run.stores:
            drop_trajectories(store)


def _finish(
    run: _Run, results: _Results, tables: dict[str, pd.DataFrame], rep: Any, *, t0: float
) -> PaperStudy:
    """Add the run's facts and cost to the report, rewrite it, and return the result."""
    run.stages.report()
    wall = time.perf_counter() - t0
    size = folder_size(run.out)
    cpu = float(run.stages.summary().at["total", "cpu_min"]) * 60.0
    rep = with_run_facts(
        rep,
        wall=wall,
        cpu=cpu,
        size=size,
        wear_info=results.wear_info,
        unavailable=run.unavailable,
    )
    rep = dataclasses.replace(rep, sections=(*rep.sections, cost_section(run.stages)))
    rep.write(run.out / "report.html")
    return PaperStudy(
        tables=tables,
        paper=run.paper,
        report_html=run.out / "report.html",
        report_markdown=run.out / "report.md",
        output=run.out,
        settings=run.settings,
        quick=run.quick,
        unavailable=tuple(run.unavailable),
        wall_time=time.perf_counter() - t0,
        output_size=folder_size(run.out),
        sweeps={
            "before": results.before,
            **{f"after {k:g} rpm": v for k, v in results.after.items()},
        },
        motions=dict(rep.motions),
        wear_paths=dict(results.wear_paths),
        transition_claims=claims_frame(
            judge_claims(TRANSITION_CLAIMS, outcomes_of(results.wear_paths))
        )
        if results.wear_paths
        else pd.DataFrame(),
    )
