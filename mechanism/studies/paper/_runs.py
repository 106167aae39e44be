"""The study's single computations: wear, the long chaos runs, exponents from the
equations, element convergence, and a kernel warm-up. Module-level functions, so
that they run in the process pool."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from chaoskit.reporting import plural
from mechanism.core import FullRecord, SimulationError, WornProfile, load_scene, simulate
from mechanism.core.scene import ClearanceRevolute

from .._convergence import element_convergence
from .._lyapunov import lyapunov_exponent
from .._orbit_diagram import ORBIT_TOLERANCE
from .._wear_life import WearLife, WearLifeSettings, wear_life
from .._wear_prediction import predict_wear
from ._published import (
    CHAOS_VARIABLES,
    DEFAULT_CLEARANCE,
    PAPER_SAMPLES,
    RODS,
    STEP,
)
from ._settings import StudySettings


def predict_worn(scene: Any, settings: StudySettings) -> tuple[Any, xr.Dataset | None, str]:
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


def chaos_run(scene: Any, settings: StudySettings) -> xr.Dataset:
    """The analysed series of one state: ≥ 200 revolutions after the transient at the
    paper's step T/10000, output every T/``chaos_samples_per_revolution`` (runs in a pool).

    Only the journal-centre eccentricity and the crank angle are recorded
    (``FullRecord(variables=...)``): no full state on the grid and no ideal companion, so
    the run holds a few arrays of the grid's length and costs the integration of the worn
    mechanism alone.
    """
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    step = min(scene.solver.max_step or math.inf, period / PAPER_SAMPLES)
    revolutions = settings.discard_revolutions + settings.chaos_revolutions

    def run(sc: Any) -> xr.Dataset:
        return simulate(
            sc.replace({"solver.max_step": step}),
            revolutions=revolutions,
            output_step=period / settings.chaos_samples_per_revolution,
            record=FullRecord(variables=CHAOS_VARIABLES),
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
        room = bearing_room(scene)
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


def bearing_room(scene: Any) -> float:
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


def chaos_analysis_options(settings: StudySettings, *, executor: Any = None) -> dict[str, Any]:
    """The :func:`chaoskit.report` options of the study's chaos analysis of one state's
    series from :func:`chaos_run` (the journal centre of joint C as ``X`` and ``Y``, the
    crank angle as the drive's phase, the transient dropped, the finer settings in
    ``options``; the states classified on ``executor`` when not None)."""
    return {
        "variables": {"X": "eccentricity_x[joint=C]", "Y": "eccentricity_y[joint=C]"},
        "phase_variable": "crank_angle",
        "discard": settings.discard_revolutions * 60.0 / 150.0,
        "options": chaoskit.ReportOptions(
            max_samples=settings.max_samples,
            n_surrogates=settings.n_surrogates,
            rng=0,
            # journal displacements in mm in every figure, as in the stroboscopic maps
            display_units={"X": "mm", "Y": "mm"},
            executor=executor,
        ),
    }


def equation_exponent(scene: Any, settings: StudySettings, *, rigid: bool = False) -> Any:
    """:func:`mechanism.lyapunov_exponent` of a state (pool task): on the model of the
    analysed series (flexible rods when ``settings.flexible_rods``, at the long runs' step
    T/10000), or on the rigid-rod model with ``rigid``."""
    if rigid or not settings.flexible_rods:
        model = scene.replace({"effects.flexibility": False})
    else:
        period = 60.0 / abs(float(scene.drive.speed_rpm))
        step = min(scene.solver.max_step or math.inf, period / PAPER_SAMPLES)
        model = scene.replace({"effects.flexibility": True, "solver.max_step": step})
    return lyapunov_exponent(
        model,
        revolutions=settings.discard_revolutions + settings.exponent_revolutions,
        discard=settings.discard_revolutions,
    )


def wear_path_scene(scene: Any, rpm: float, clearance: float, settings: StudySettings) -> Any:
    """The scene of one wear path: ``scene`` at ``rpm`` with radial clearance ``clearance``
    at C and the wear paths' rods (flexible ones at the study's step, rigid ones at the
    error control's)."""
    flexible = settings.wear_path_flexible_rods
    return scene.replace(
        {
            "drive.speed_rpm": float(rpm),
            "joints.C.clearance": float(clearance),
            "effects.flexibility": flexible,
            "solver.max_step": STEP if flexible else None,
        }
    )


def wear_path(scene: Any, rpm: float, clearance: float, settings: StudySettings) -> WearLife:
    """One wear path of the wear-life answer (pool task): :func:`mechanism.wear_life` of
    :func:`wear_path_scene` with the settings' cycles, checkpoints and analysis."""
    return wear_life(
        wear_path_scene(scene, rpm, clearance, settings),
        cycles=settings.wear_path_cycles,
        checkpoints=list(settings.wear_path_checkpoints),
        averaged_revolutions=settings.wear_path_averaged_revolutions,
        settings=WearLifeSettings(
            analysis_revolutions=settings.wear_path_analysis_revolutions,
            lyapunov_revolutions=settings.wear_path_lyapunov_revolutions,
            lyapunov_discard=settings.wear_path_lyapunov_discard,
        ),
    )


def convergence_run(scene: Any, elements: int, settings: StudySettings) -> list[float]:
    """Extreme strains (µε) of rods 3 and 4 with ``elements`` per rod."""
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    # the scene's "auto" method runs flexible rods with the fixed-step generalized-α at
    # max_step: keep that step at the paper's T/10000 even when the output grid is coarser
    step = min(scene.solver.max_step or math.inf, period / PAPER_SAMPLES)
    result = element_convergence(
        scene.replace({"solver.max_step": step}),
        rods=tuple(RODS.values()),
        elements=(int(elements),),
        revolutions=settings.convergence_revolutions,
        output_step=period / settings.samples_per_revolution,
    )
    rods = list(result.rods)
    # element_convergence already reports micro-strain
    return [
        float(result.strain[0, rods.index(rod)]) if rod in rods else math.nan
        for rod in RODS.values()
    ]


def compile_kernels(part: str, *, rigid_exponent: bool = True) -> float:
    """Run each compiled path of the study once on a tiny problem (pool task), so that
    numba compiles it and writes its cache; returns the CPU seconds spent.

    On a fresh install every worker process would otherwise compile the same kernels at
    the same time (about two minutes of CPU each); compiled once here, in the pool's two
    processes in parallel, the others load them from the cache. ``part`` is
    ``"flexible"`` (the generalized-α runs: full record, the chaos runs' series, wear, and
    the flexible exponent, which reuses the run's kernels) or ``"rigid"`` (sections, the
    rigid exponent when ``rigid_exponent``, the analysis). Pass ``rigid_exponent`` when
    any run of the study takes a rigid exponent, the wear paths' included: two paths
    starting together would otherwise each compile it.
    """
    cpu = time.process_time()
    scene = load_scene("paper").replace({"effects.flexibility": True, "solver.max_step": STEP})
    period = 60.0 / abs(float(scene.drive.speed_rpm))
    if part == "flexible":
        simulate(scene, revolutions=0.01, output_step=period / 2500)
        simulate(
            scene,
            revolutions=0.01,
            output_step=period / 1000,
            record=FullRecord(variables=CHAOS_VARIABLES),
        )
        predict_wear(
            scene,
            updates=1,
            cycles_per_update=1.0,
            settle_revolutions=0.0,
            output_step=period / 2500,
        )
        lyapunov_exponent(scene, revolutions=0.02, discard=0.01)
    else:
        rigid = scene.replace({"effects.flexibility": False, "solver.max_step": None})
        simulate(
            rigid, revolutions=0.2, record="sections", rtol=ORBIT_TOLERANCE, atol=ORBIT_TOLERANCE
        )
        if rigid_exponent:
            lyapunov_exponent(rigid, revolutions=0.2, discard=0.1)
        t = np.arange(4000) * 0.05
        chaoskit.classify(np.sin(t) + 0.5 * np.sin(np.sqrt(2.0) * t), dt=0.05)
    return time.process_time() - cpu


def wear_scene_of(scene: Any) -> Any:
    """The before-wear state of the chaos analysis: 150 rpm, c = 0.2 mm."""
    return scene.replace({"drive.speed_rpm": 150, "joints.C.clearance": DEFAULT_CLEARANCE})


def at_speed(scene: Any, rpm: float) -> Any:
    """``scene`` at crank speed ``rpm``."""
    return scene.replace({"drive.speed_rpm": rpm})
