"""``mechanism.lyapunov_exponent``: the largest Lyapunov exponent of a scene from its equations.

The two-trajectory (Benettin) method on the full state [q; q̇], with the second trajectory
kept as a small deviation that shares the reference's step sequence and contact events
(:func:`mechanism.core.integrate.integrate_tangent` on Dormand–Prince steps for a rigid
scene, :func:`mechanism.core.integrate.integrate_tangent_flexible` on generalized-α steps
for a flexible one); see ``docs/mechanism-lyapunov.md``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import check_int, check_positive
from mechanism.core import SimulationError, default_step, drive_period, step_limits
from mechanism.core.integrate import (
    Dopri5,
    GeneralizedAlpha,
    SolverStats,
    StepSettings,
    TangentIntegration,
    TangentSettings,
    initial_deviation,
    integrate_tangent,
    integrate_tangent_flexible,
    length_scale,
    resolve_method,
)
from mechanism.core.model import Model, assemble, initial_state
from mechanism.core.scene import Scene

__all__ = ["LyapunovSettings", "SceneLyapunov", "lyapunov_exponent"]

#: segments of the running estimate of a scene without a periodic drive
UNDRIVEN_SEGMENTS = 100
#: default rtol = atol: at the scenes' usual 1e-5 an explicit method resolves the stiff
#: contact-friction directions only at its stability limit, and the deviation measures
#: the integrator (docs/mechanism-lyapunov.md §3)
DEFAULT_TOLERANCE = 1e-8
#: default ε / L: in the middle of the range 1e-9 – 1e-5 over which the estimate does not
#: depend on it (docs/mechanism-lyapunov.md §3)
DEFAULT_PERTURBATION = 1e-7
#: default relative tolerance of the deviation's own error estimate per step: without it
#: the step control sees the reference alone, and where the reference rides the stiff
#: friction ramp at the explicit method's stability limit the deviation measures the
#: integrator's amplification (docs/mechanism-lyapunov.md §2, *Step control*)
DEFAULT_DEVIATION_RTOL = 1e-4
#: how the deviation's rate is differenced (``LyapunovSettings.difference``)
DIFFERENCES = ("directional", "split")
#: an interval decides the exponent's sign when it lies beyond zero by this many of its
#: half-widths (``SceneLyapunov.sign_decided``, ``decide_after``)
DECIDED_MARGIN = 1.0


def _optional_positive(value: Any, name: str) -> float | None:
    return None if value is None else check_positive(value, name=name)


@dataclass(frozen=True, kw_only=True)
class LyapunovSettings:
    """How :func:`lyapunov_exponent` estimates the exponent: the deviation, its
    renormalisation, the interval and the integration of both trajectories.

    Every field is checked on construction (a ValueError names the field and its
    accepted range); the defaults are those measured in ``docs/mechanism-lyapunov.md``.

    Parameters
    ----------
    perturbation : float
        ε / L, in (0, 1e-4]: the size of the finite differences and of the renormalised
        deviation. The estimate is the same from 1e-9 to 1e-4 (round-off shows below,
        the kinks of the contact law above: at 5e-4 the deviation's step control fails
        on the rigid paper scene; docs/mechanism-lyapunov.md §3).
    renormalize_every : int
        Accepted steps between renormalisations (≥ 1); it also happens at every
        segment end.
    deviation_rtol : float
        Relative tolerance of the deviation's error estimate per step (mass-weighted
        norm, relative to the deviation's size), in [0, 0.1]; 0 leaves the step control
        to the reference alone (then the steps are those of :func:`mechanism.simulate`,
        and where the reference rides a stiff friction ramp at the explicit method's
        stability limit the estimate measures the integrator, not the mechanism).
        Rigid scenes only.
    batches : int
        Batches of consecutive segments for the 95 % interval (≥ 2; fewer when there are
        fewer segments).
    seed : int
        Seed of the random initial direction of the deviation (≥ 0).
    rtol, atol : float, optional
        Tolerances of the reference (> 0); default 1e-8 for a rigid scene (not
        ``scene.solver``'s: on the paper scene the estimate is the same from 1e-5 to 1e-9
        within its interval and costs the same, since the journals' approach and the
        deviation's error set the steps, so the tighter one is free;
        docs/mechanism-lyapunov.md §3), ``scene.solver``'s for a flexible one (the
        fixed-step generalized-α reads them only in its Newton test, and its reference
        then takes the steps of :func:`mechanism.simulate`).
    max_step : float, optional
        Largest step (s, > 0), and then the only bound. Default: the step limits of
        :func:`mechanism.simulate` (``scene.solver.max_step`` if set; else, with active
        clearance joints, the bound by the journals' approach to their walls, never below
        the scene's default output step; unlimited without).
    difference : {"directional", "split"}
        How the deviation's rate is differenced at each stage (rigid scenes):
        ``"directional"``, one right-hand side along the whole deviation, its smaller part
        (position or velocity) scaled to ε unless the larger one would then move by more
        than 10 ε; ``"split"``, one along each part, each scaled to ε (twice the
        evaluations; on the reference's own steps the per-revolution exponents of the two
        agree within 2.5 % on the paper scene, docs/mechanism-lyapunov.md §1).

    Examples
    --------
    >>> import mechanism
    >>> mechanism.LyapunovSettings(perturbation=1e-9, seed=3).perturbation
    1e-09
    """

    perturbation: float = DEFAULT_PERTURBATION
    renormalize_every: int = 1
    deviation_rtol: float = DEFAULT_DEVIATION_RTOL
    batches: int = 10
    seed: int = 0
    rtol: float | None = None
    atol: float | None = None
    max_step: float | None = None
    difference: str = "directional"

    def __post_init__(self) -> None:
        perturbation = check_positive(self.perturbation, name="perturbation")
        if perturbation > 1e-4:
            raise ValueError(f"perturbation must be in (0, 1e-4]; got {perturbation!r}.")
        deviation_rtol = check_positive(self.deviation_rtol, name="deviation_rtol", allow_zero=True)
        if deviation_rtol > 0.1:
            raise ValueError(f"deviation_rtol must be in [0, 0.1]; got {deviation_rtol!r}.")
        if self.difference not in DIFFERENCES:
            raise ValueError(
                f"difference must be one of {', '.join(DIFFERENCES)}; got {self.difference!r}."
            )
        checked = {
            "perturbation": perturbation,
            "renormalize_every": check_int(
                self.renormalize_every, name="renormalize_every", minimum=1
            ),
            "deviation_rtol": deviation_rtol,
            "batches": check_int(self.batches, name="batches", minimum=2),
            "seed": check_int(self.seed, name="seed", minimum=0),
            "rtol": _optional_positive(self.rtol, "rtol"),
            "atol": _optional_positive(self.atol, "atol"),
            "max_step": _optional_positive(self.max_step, "max_step"),
        }
        for name, value in checked.items():
            object.__setattr__(self, name, value)


@dataclass(frozen=True, kw_only=True)
class SceneLyapunov:
    """Largest Lyapunov exponent of a scene, with its running estimate and interval.

    Attributes
    ----------
    exponent : float
        λ₁ (1/s, natural log): total log growth of the renormalised deviation over the
        kept time divided by that time.
    ci : tuple of float
        95 % interval of ``exponent`` (1/s) from batch means (see ``ci_method``).
    ci_method : str
    drive_period : float or None
        Drive period T (s), None for a scene without a periodic drive.
    time : numpy.ndarray
        End time (s) of each segment of the kept run (one drive period each, else
        1/100 of the kept time).
    running_exponent : numpy.ndarray
        Estimate over the kept run up to each ``time`` (1/s).
    segment_exponent : numpy.ndarray
        Exponent over each segment alone (1/s); its fluctuation sets ``ci``.
    batches : int
        Number of batches of consecutive segments behind ``ci``.
    settings : dict
        Everything the estimate depends on: ``revolutions``/``t_end`` (of the run made),
        ``discard`` (s), ``decide_after`` (as given; NaN: none), ``perturbation``
        (relative), ``length_scale`` (m), ``perturbation_size`` (m), ``time_scale`` (s),
        ``renormalize_every`` (accepted steps), ``rtol``, ``atol``, ``max_step`` (s),
        ``approach_floor`` (s), ``deviation_rtol``, ``seed``, ``difference`` (``"copy"``
        for a flexible scene: a perturbed copy's own step).
    renormalizations : int
    stats : SolverStats
        Cost of the whole run (discarded part included); ``function_evaluations``
        counts both trajectories.
    scene_name : str
    """

    exponent: float
    ci: tuple[float, float]
    ci_method: str
    drive_period: float | None
    time: np.ndarray
    running_exponent: np.ndarray
    segment_exponent: np.ndarray
    batches: int
    settings: dict[str, Any] = field(default_factory=dict)
    renormalizations: int = 0
    stats: SolverStats | None = None
    scene_name: str = ""

    @property
    def sign_decided(self) -> bool:
        """True when ``ci`` lies beyond zero by at least its half-width (above: chaotic by
        the equations; below: regular); False for an interval that is not finite."""
        return _sign_decided(self.ci)

    @property
    def exponent_per_period(self) -> float:
        """λ₁ T: nats per drive period (NaN without a periodic drive)."""
        return self.exponent * self.drive_period if self.drive_period else math.nan

    @property
    def ci_per_period(self) -> tuple[float, float]:
        """``ci`` in nats per drive period."""
        p = self.drive_period or math.nan
        return (self.ci[0] * p, self.ci[1] * p)

    def to_dataset(self) -> xr.Dataset:
        """Running and per-segment exponents over ``time``; scalars and settings in attrs."""
        attrs: dict[str, Any] = {
            "scene": self.scene_name,
            "exponent": self.exponent,
            "exponent_units": "s-1",
            "exponent_per_period": self.exponent_per_period,
            "ci_low": self.ci[0],
            "ci_high": self.ci[1],
            "ci_method": self.ci_method,
            "batches": self.batches,
            "drive_period": math.nan if self.drive_period is None else self.drive_period,
            "renormalizations": self.renormalizations,
        }
        for key, value in self.settings.items():
            attrs[f"setting_{key}"] = math.nan if value is None else value
        if self.stats is not None:
            attrs.update(self.stats.as_attrs())
        long = "largest Lyapunov exponent"
        return xr.Dataset(
            {
                "running_exponent": (
                    "time",
                    self.running_exponent,
                    {"units": "s-1", "long_name": f"running estimate of the {long}"},
                ),
                "segment_exponent": (
                    "time",
                    self.segment_exponent,
                    {"units": "s-1", "long_name": f"{long} over each segment"},
                ),
            },
            coords={"time": ("time", self.time, {"units": "s", "long_name": "segment end"})},
            attrs=attrs,
        )


def _sign_decided(ci: tuple[float, float]) -> bool:
    lo, hi = (float(x) for x in ci)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return False
    half = 0.5 * (hi - lo)
    return lo > DECIDED_MARGIN * half or hi < -DECIDED_MARGIN * half


def _batch_interval(
    t: np.ndarray, log_growth: np.ndarray, batches: int
) -> tuple[tuple[float, float], int]:
    """95 % batch-means interval of the exponent from the growth at segment ends."""
    from scipy import stats

    n_seg = t.size - 1
    b = min(batches, n_seg)
    if b < 2:
        return (math.nan, math.nan), b
    edges = np.round(np.linspace(0, n_seg, b + 1)).astype(int)
    rates = np.diff(log_growth[edges]) / np.diff(t[edges])
    half = float(stats.t.ppf(0.975, b - 1) * rates.std(ddof=1) / math.sqrt(b))
    centre = float((log_growth[-1] - log_growth[0]) / (t[-1] - t[0]))
    return (centre - half, centre + half), b


def lyapunov_exponent(
    scene: Scene,
    *,
    revolutions: float | None = None,
    t_end: float | None = None,
    discard: float = 0.0,
    decide_after: float | None = None,
    settings: LyapunovSettings | None = None,
    progress: bool = False,
) -> SceneLyapunov:
    r"""Largest Lyapunov exponent of a scene from its equations of motion.

    A reference trajectory from the scene's initial state (as :func:`mechanism.simulate`)
    and a deviation of size :math:`\varepsilon = ` ``perturbation`` × L (L the smallest
    radial clearance, or the mechanism's size without clearance joints) are advanced by
    the same Dormand–Prince steps: the deviation's rate at every stage is the directional
    derivative of the compiled right-hand side along d, by one finite difference along d
    whose smaller part (position or velocity) moves by ε (``difference``), on the
    reference's branch of the contact law; the contact latch is decided by the reference,
    and a step is accepted when both the reference's error estimate and the deviation's
    (relative to its size, ``deviation_rtol``) pass. A flexible scene (ANCF beams) is
    integrated by the scene's generalized-α method instead, exactly as
    :func:`mechanism.simulate` integrates it; after every step the reference accepts, the
    perturbed copy takes the same step with its own implicit solve (its acceleration and
    pseudo-acceleration deviations are carried along; ``deviation_rtol`` and
    ``difference`` do not apply there). Every ``renormalize_every``
    accepted steps the deviation is projected onto the tangent space of the constraints
    (Φq δq = 0, Φq δq̇ + (Φq q̇)_q δq = 0; rigid models) and rescaled to ε in the
    mass-weighted norm

    .. math:: \|d\|^2 = (\delta q^\top M \delta q + \tau^2 \delta\dot q^\top M
              \delta\dot q) / m_\mathrm{total},

    :math:`\tau = T/2\pi` (1 s without a periodic drive), and

    .. math:: \lambda_1 = \frac{1}{t - t_d} \sum \ln \frac{\|d\|}{\varepsilon}

    over the kept time (Benettin, Galgani, Giorgilli & Strelcyn 1980).

    Parameters
    ----------
    scene : mechanism.scene.Scene
        A rigid or flexible mechanism (a flexible one with a generalized-α
        ``solver.method``, as ``"auto"`` resolves it, and ``solver.projection = false``).
    revolutions : float, optional
        Simulated drive periods, discarded ones included.
    t_end : float, optional
        Simulated time (s), instead of ``revolutions`` (required without a periodic drive).
    discard : float
        Transient left out of the estimate (the deviation still evolves through it):
        drive periods with ``revolutions``, seconds with ``t_end``.
    decide_after : float, optional
        End the run early when its sign is already clear: at the first segment end at
        or after ``decide_after`` (drive periods with ``revolutions``, seconds with
        ``t_end``; in (``discard``, the run's length)) the interval of the segments kept
        so far is read once, and when it lies beyond zero by at least its half-width
        (:attr:`SceneLyapunov.sign_decided`) the estimate of those segments is the
        result; otherwise the run goes on to its end, with the numbers of a run without
        ``decide_after``. ``settings["revolutions"]``/``t_end`` state the length run.
    settings : LyapunovSettings, optional
        The deviation (``perturbation`` ε / L, ``renormalize_every``, ``deviation_rtol``,
        ``seed``), the interval (``batches``) and the integration (``rtol``, ``atol``,
        ``max_step``); default ``LyapunovSettings()``.
    progress : bool
        Show a progress bar.

    Returns
    -------
    SceneLyapunov

    Raises
    ------
    ValueError
        On bad arguments, a flexible model without a generalized-α method or with
        projection, or a scene without a degree of freedom.
    SimulationError
        When the integration fails.

    References
    ----------
    G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9–20.
    T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*,
    Springer 1989, §3.4.

    Examples
    --------
    >>> import mechanism
    >>> scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    >>> result = mechanism.lyapunov_exponent(scene, revolutions=0.2)
    >>> result.time.size
    2
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    period = drive_period(scene)
    duration, t_discard = _run_time(period, revolutions, t_end, discard)
    t_decide = _decide_time(decide_after, period if revolutions is not None else None,
                            t_discard, duration)  # fmt: skip
    if settings is None:
        settings = LyapunovSettings()
    elif not isinstance(settings, LyapunovSettings):
        raise TypeError(
            f"settings must be a mechanism.LyapunovSettings; got {type(settings).__name__}."
        )
    model = assemble(scene)
    method = _integrator(scene, model)
    tau = period / (2.0 * math.pi) if period is not None else 1.0
    segment = period if period is not None else (duration - t_discard) / UNDRIVEN_SEGMENTS
    tangent = _tangent_settings(scene, model, method, settings, duration, tau, segment)
    q0, v0 = initial_state(model)
    y0 = np.concatenate([q0, v0])
    length = length_scale(model, y0)
    size = settings.perturbation * length
    d0 = initial_deviation(model, y0, t0=0.0, size=size, time_scale=tau, seed=settings.seed)
    n_seg = max(1, round((duration - t_discard) / segment))
    kept = t_discard + (duration - t_discard) * np.arange(n_seg + 1) / n_seg
    stops = np.concatenate([[0.0], kept]) if t_discard > 0.0 else kept
    shown = f"{scene.name} (lyapunov)" if progress else False
    until = None if t_decide is None else _decision(t_decide, t_discard, segment, settings.batches)
    if isinstance(method, GeneralizedAlpha):
        run = integrate_tangent_flexible(
            model, y0, d0, stops, method=method, settings=tangent, until=until,
            progress=shown,
        )  # fmt: skip
    else:
        run = integrate_tangent(model, y0, d0, stops, settings=tangent, until=until, progress=shown)
    if not run.stats.success:
        raise SimulationError(
            f"exponent of {scene.name!r}: the integration failed after t = {run.t[-1]:.6g} s: "
            f"{run.stats.message}"
        )
    if run.t.size < stops.size:  # ended by decide_after: the length run
        duration = float(run.t[-1])
        if revolutions is not None:
            revolutions = round(duration / period, 9)  # type: ignore[operator]
    recorded = {
        "revolutions": None if revolutions is None else float(revolutions),
        "t_end": float(duration),
        "discard": float(t_discard),
        "decide_after": math.nan if decide_after is None else float(decide_after),
        "perturbation": float(settings.perturbation),
        "length_scale": float(length),
        "perturbation_size": float(size),
        "time_scale": float(tau),
        "renormalize_every": int(settings.renormalize_every),
        "rtol": float(tangent.steps.rtol),
        "atol": float(tangent.steps.atol),
        "max_step": float(tangent.steps.max_step),
        "approach_floor": float(tangent.steps.approach_floor),
        "deviation_rtol": float(settings.deviation_rtol),
        "seed": int(settings.seed),
        "difference": settings.difference if not model.beams else "copy",
        "model": "flexible" if model.beams else "rigid",
    }
    return _estimate(scene, run, period, t_discard, settings.batches, recorded)


def _run_time(
    period: float | None, revolutions: float | None, t_end: float | None, discard: float
) -> tuple[float, float]:
    """(simulated time, discarded time) in s from the arguments of
    :func:`lyapunov_exponent`, checked."""
    if (revolutions is None) == (t_end is None):
        raise ValueError("pass exactly one of revolutions or t_end.")
    discard = check_positive(discard, name="discard", allow_zero=True)
    if revolutions is not None:
        if period is None:
            raise ValueError(
                "the scene has no periodic drive, so revolutions cannot be converted to "
                "time; pass t_end (s)."
            )
        revolutions = check_positive(revolutions, name="revolutions")
        if not discard < revolutions:
            raise ValueError(
                f"discard must be smaller than revolutions ({revolutions!r}); got {discard!r}."
            )
        return revolutions * period, discard * period
    duration = check_positive(t_end, name="t_end")
    if not discard < duration:
        raise ValueError(f"discard must be smaller than t_end ({duration!r} s); got {discard!r}.")
    return duration, discard


def _decide_time(
    decide_after: float | None, period: float | None, t_discard: float, duration: float
) -> float | None:
    """``decide_after`` in seconds (drive periods with a ``period``), checked to lie in
    (discard, duration); None stays None."""
    if decide_after is None:
        return None
    value = check_positive(decide_after, name="decide_after")
    t = value * period if period is not None else value
    if not t_discard < t < duration:
        unit = period if period is not None else 1.0
        raise ValueError(
            f"decide_after must lie in (discard, the run's length) = ({t_discard / unit:g}, "
            f"{duration / unit:g}); got {decide_after!r}."
        )
    return t


def _decision(
    t_decide: float, t_discard: float, segment: float, batches: int
) -> Callable[[np.ndarray, np.ndarray], bool]:
    """The ``until`` of the tangent integration for ``decide_after``: at the first
    segment end at or after ``t_decide`` (once), whether the kept segments' interval
    decides the sign."""
    read: list[bool] = []

    def until(t: np.ndarray, log_growth: np.ndarray) -> bool:
        if read or t[-1] < t_decide - 1e-9 * segment:
            return False
        read.append(True)
        first = 1 if t_discard > 0.0 else 0
        ci, _ = _batch_interval(t[first:], log_growth[first:], batches)
        return _sign_decided(ci)

    return until


def _integrator(scene: Scene, model: Model) -> Dopri5 | GeneralizedAlpha:
    """Dormand–Prince for a rigid model; the scene's generalized-α method for a flexible
    one (checked: no other method, no projection)."""
    if not model.beams:
        return Dopri5()
    resolved = resolve_method(scene.solver.method, model)
    if not isinstance(resolved, GeneralizedAlpha):
        raise ValueError(
            "the exponent of a flexible scene rides on generalized-alpha steps; set "
            f"solver.method to 'auto' or a generalized-alpha method (got {scene.solver.method!r})."
        )
    if scene.solver.projection:
        raise ValueError("the exponent of a flexible scene needs solver.projection = false.")
    return resolved


def _tangent_settings(
    scene: Scene,
    model: Model,
    method: Dopri5 | GeneralizedAlpha,
    settings: LyapunovSettings,
    duration: float,
    tau: float,
    segment: float,
) -> TangentSettings:
    """The tangent integration's settings: tolerances (``DEFAULT_TOLERANCE`` rigid, the
    scene's flexible, unless given), the step limits of :func:`mechanism.simulate` (or
    ``settings.max_step`` alone) and the deviation's options."""
    solver = scene.solver
    flexible = isinstance(method, GeneralizedAlpha)
    default_tol = (solver.rtol, solver.atol) if flexible else (DEFAULT_TOLERANCE,) * 2
    rtol = default_tol[0] if settings.rtol is None else settings.rtol
    atol = default_tol[1] if settings.atol is None else settings.atol
    if settings.max_step is None:
        # the step limits of mechanism.simulate with its integrator: the same step rule
        max_step, floor = step_limits(model, method, default_step(scene, duration))
    else:
        max_step, floor = settings.max_step, 0.0
    steps = StepSettings(
        rtol=float(rtol), atol=float(atol), max_step=float(max_step),
        approach_floor=float(floor), projection=bool(solver.projection),
    )  # fmt: skip
    if flexible:
        return TangentSettings(
            steps=steps, time_scale=tau, renormalize_every=settings.renormalize_every
        )
    return TangentSettings(
        steps=steps, time_scale=tau, renormalize_every=settings.renormalize_every,
        deviation_rtol=settings.deviation_rtol, neutral_latch_after=segment,
        difference=settings.difference,
    )  # fmt: skip


def _estimate(
    scene: Scene,
    run: TangentIntegration,
    period: float | None,
    t_discard: float,
    batches: int,
    recorded: dict[str, Any],
) -> SceneLyapunov:
    """The exponent, its running estimate and interval over the kept segments of ``run``."""
    first = 1 if t_discard > 0.0 else 0
    t = run.t[first:]
    growth = run.log_growth[first:]
    exponent = float((growth[-1] - growth[0]) / (t[-1] - t[0]))
    ci, used = _batch_interval(t, growth, batches)
    running = (growth[1:] - growth[0]) / (t[1:] - t[0])
    segments = np.diff(growth) / np.diff(t)
    unit = "drive period" if period is not None else f"1/{UNDRIVEN_SEGMENTS} of the kept time"
    return SceneLyapunov(
        exponent=exponent,
        ci=ci,
        ci_method=(
            f"batch means: {used} batches of consecutive segments (one {unit} each), "
            "Student t, 95 %"
        ),
        drive_period=period,
        time=t[1:],
        running_exponent=running,
        segment_exponent=segments,
        batches=used,
        settings=recorded,
        renormalizations=run.renormalizations,
        stats=run.stats,
        scene_name=scene.name,
    )
