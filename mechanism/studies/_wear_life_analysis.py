"""The motion of one worn state of a wear path (:func:`mechanism.wear_life`).

A checkpoint's state is analysed in two parts. What the state's own run gives — its
stroboscopic points, contact forces and contact modes — is read where the run is, as the
path wears on (:func:`observe`). The exponent from the equations and the motion verdict,
the costliest part, need only the worn scene and a thinned copy of the journals' motion
(:func:`judge`), so a path may hand them to an executor and wear on while they run
(:class:`Judgements`): the numbers are the same either way.
"""

from __future__ import annotations

import time
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

import chaoskit
from mechanism.core import Scene, SimulationError
from mechanism.core.record import window_start

from ._lyapunov import SceneLyapunov, lyapunov_exponent
from ._turns import (
    cut_at_turns,
    exponent_revolutions,
    exponent_span,
    revolution_time,
    simulate_turns,
)
from ._wear_statistics import contact_modes

__all__ = ["CheckpointAnalysis", "Judgements", "checkpoint_exponent", "judge", "observe"]

#: the journals' motion the verdict reads
_MOTION = ["eccentricity_x", "eccentricity_y", "crank_angle"]


@dataclass(frozen=True)
class CheckpointAnalysis:
    """How each checkpoint's state is analysed (see :func:`mechanism.wear_life`)."""

    discard: float
    revolutions: int
    exponent: bool
    lyapunov_revolutions: float
    lyapunov_discard: float
    lyapunov_first: float | None
    continuous_fraction: float
    verdict_samples: int
    simulate_kwargs: dict[str, Any]


def checkpoint_exponent(scene: Scene, how: CheckpointAnalysis) -> SceneLyapunov | None:
    """The exponent of one state: one run, ended after its first ``lyapunov_first``
    revolutions when their interval decides the sign (``decide_after`` of
    :func:`mechanism.lyapunov_exponent`), else run on to ``lyapunov_revolutions``; None
    when an integration fails."""
    full, first = how.lyapunov_revolutions, how.lyapunov_first
    span = exponent_span(scene, full, how.lyapunov_discard)
    if first is not None and first < full:
        early = exponent_span(scene, first, how.lyapunov_discard)  # in the span's units
        span["decide_after"] = early["revolutions"] if "revolutions" in early else early["t_end"]
    try:
        return lyapunov_exponent(scene, **span)
    except SimulationError:
        return None


def observe(
    scene: Scene,
    names: list[str],
    how: CheckpointAnalysis,
    traj: xr.Dataset | None = None,
    cpu: dict[str, float] | None = None,
) -> tuple[dict[str, Any], xr.Dataset]:
    """What one worn state's run gives (a SimulationError propagates): its record
    (stroboscopic points, peak and mean contact force, contact modes) and the journals'
    motion thinned for the verdict. ``traj``: the state's run when it is shared with the
    increment (it may run longer than the analysis). ``cpu``: CPU seconds of this thread
    are added to its ``"runs"``."""
    cpu = {} if cpu is None else cpu
    period = float(revolution_time(scene))  # type: ignore[arg-type]
    span = how.discard + how.revolutions
    if traj is None:
        start_cpu = time.thread_time()
        traj = simulate_turns(scene, span, **how.simulate_kwargs)
        cpu["runs"] = cpu.get("runs", 0.0) + time.thread_time() - start_cpu
    else:
        traj = cut_at_turns(traj, span)
    start = window_start(traj, how.discard)
    window = traj.isel(time=slice(start, None))
    strobe = chaoskit.stroboscopic_map(window[_MOTION], phase_variable="crank_angle")
    samples = int(window.sizes["time"])
    stride = max(1, int(samples / (how.revolutions * how.verdict_samples)))
    force = traj["contact_force"].isel(time=slice(start, None))
    modes = [
        contact_modes(traj, n, start=start, continuous_time=how.continuous_fraction * period)
        for n in names
    ]
    record = {
        "strobe_x": np.asarray(strobe["eccentricity_x"].transpose("joint", ...).values),
        "strobe_y": np.asarray(strobe["eccentricity_y"].transpose("joint", ...).values),
        "peak_force": [float(force.sel(joint=n).max()) for n in names],
        "mean_force": [float(force.sel(joint=n).mean()) for n in names],
        "modes": modes,
    }
    return record, window[_MOTION].isel(time=slice(None, None, stride)).copy(deep=True)


def judge(scene: Scene, how: CheckpointAnalysis, motion: xr.Dataset) -> dict[str, Any]:
    """The exponent from the equations and the motion verdict of one worn state (the
    journals' ``motion`` from :func:`observe`), and the CPU seconds of this thread each
    took (``"cpu"``: ``{"exponent": …, "verdict": …}``)."""
    start_cpu = time.thread_time()
    lam = checkpoint_exponent(scene, how) if how.exponent else None
    exponent_cpu = time.thread_time() - start_cpu
    start_cpu = time.thread_time()
    verdict = chaoskit.classify_motion(motion, phase_variable="crank_angle", exponent=lam, rng=0)
    return {
        "lyapunov": lam,
        "lyapunov_run": np.nan if lam is None else exponent_revolutions(lam.settings, scene),
        "verdict": verdict,
        "cpu": {"exponent": exponent_cpu, "verdict": time.thread_time() - start_cpu},
    }


class Judgements:
    """The judgements of a path's states, in order: computed here, or submitted to an
    ``executor`` as the states come and collected at the end."""

    def __init__(self, executor: Executor | None) -> None:
        self._executor = executor
        self._pending: list[Any] = []
        #: CPU seconds the judgements took on other threads (through the executor)
        self.elsewhere = 0.0

    def add(self, scene: Scene, how: CheckpointAnalysis, motion: xr.Dataset) -> None:
        if self._executor is None:
            self._pending.append(judge(scene, how, motion))
        else:
            self._pending.append(self._executor.submit(judge, scene, how, motion))

    def collect(self, cpu: dict[str, float]) -> list[dict[str, Any]]:
        """Every judgement, their CPU added to ``cpu``. The executor is the path's own:
        it is shut down here, waiting for the judgements submitted to it."""
        if self._executor is not None:
            self._executor.shutdown(wait=True)
        out = []
        for item in self._pending:
            done = item if self._executor is None else item.result()
            for key, value in done["cpu"].items():
                cpu[key] = cpu.get(key, 0.0) + value
            if self._executor is not None:
                self.elsewhere += sum(done["cpu"].values())
            out.append({k: v for k, v in done.items() if k != "cpu"})
        return out
