"""Record modes: what :func:`mechanism.simulate` keeps of a run, as small frozen objects.

Each mode owns its options (validated when it is built), says what the run needs (a
periodic drive, the ideal companion), estimates the memory its output takes, tells the
integrator what to record, and builds the Dataset from the integration. ``simulate`` only
orchestrates: a new record mode is a new subclass of :class:`RecordMode` here, with no
change to ``simulate``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np
import xarray as xr

from chaoskit.contract import check_choice, check_positive
from mechanism.core._run_checks import (
    SimulationWarning,
    estimated_run_bytes,
    warn_if_deep_penetration,
    warn_if_large,
)
from mechanism.core.integrate import Integration, Recording, RecordPlan
from mechanism.core.model import Model
from mechanism.core.model import kernels as model_kernels
from mechanism.core.scene import MotorDrive
from mechanism.core.wear import add_run_wear

from ._record import (
    LIGHT_VARIABLES,
    light_dataset,
    metrics_dataset,
    sections_dataset,
    to_dataset,
)
from ._wear_record import WEAR_VARIABLES, wear_dataset

__all__ = [
    "RECORD_MODES",
    "FullRecord",
    "MetricsRecord",
    "RecordMode",
    "RunTimes",
    "SectionsRecord",
    "WearRecord",
    "available_variables",
    "record_mode",
]

# A warning raised by a mode's method reaches the caller of ``simulate`` from here:
# warnings.warn → the check → the mode's method → simulate → the wrapper that refuses loose
# record options → the caller.
_CALLER = 5


def _number(value: Any) -> Any:
    """A numpy scalar as the Python number it holds (also in messages)."""
    return value.item() if isinstance(value, np.generic) else value


def _shown(value: Any) -> str:
    """A value for a message: numbers as plain numbers (never ``np.float64(...)``)."""
    value = _number(value)
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list | tuple | np.ndarray):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    return repr(value)


def _discard(value: Any) -> float:
    return check_positive(_number(value), name="discard", allow_zero=True)


def _companion(value: Any) -> bool:
    if not isinstance(value, bool | np.bool_):
        raise ValueError(f"companion must be True or False; got {_shown(value)}.")
    return bool(value)


@dataclass(frozen=True)
class RunTimes:
    """The time extent of a run, as the record modes need it.

    Parameters
    ----------
    duration : float
        Simulated time (s).
    period : float or None
        Drive period (s); None: no periodic drive.
    output_step : float
        Spacing (s) of the output grid.
    n_out : int
        Samples of the output grid.
    scene_step : float
        The scene's default output step (s): ``solver.output_step``, else the drive
        period / 10000.
    """

    duration: float
    period: float | None
    output_step: float
    n_out: int
    scene_step: float


@dataclass(frozen=True)
class RecordMode:
    """What a run records; pass an instance as ``simulate(..., record=...)``.

    A subclass sets :attr:`name` (the ``record`` attribute of the Dataset and the
    shorthand string ``simulate`` accepts), :attr:`needs_period` and
    :attr:`grid_divisions`, validates its options in ``__post_init__`` and implements
    :meth:`estimated_bytes`, :meth:`plans` and :meth:`dataset`.
    """

    #: The mode's name: ``simulate(record=name)`` means the mode with default options.
    name: ClassVar[str] = ""
    #: True: the mode counts revolutions, so the scene needs a periodic drive.
    needs_period: ClassVar[bool] = False
    #: The default output grid divides a drive period into this many steps; None: the
    #: scene's default output step (``solver.output_step``, else the drive period / 10000).
    grid_divisions: ClassVar[int | None] = None

    @property
    def companion(self) -> bool:
        """True when the ideal companion is integrated alongside a model with clearance."""
        return True

    def check(self, model: Model, times: RunTimes) -> None:
        """Raise a ValueError when the mode cannot record a run of ``model`` over ``times``."""
        if self.needs_period and times.period is None:
            raise ValueError(
                f"record={self.name!r} needs a periodic drive (its revolutions and "
                "sections); use record='full'."
            )

    def output_times(self, grid: np.ndarray, times: RunTimes) -> np.ndarray:
        """The times (s) the integrator reports at, from the output ``grid`` (s)."""
        return grid

    def end_time(self, t_out: np.ndarray, times: RunTimes) -> float:
        """The ``t_end`` attribute (s) of the Dataset."""
        return float(times.duration)

    def estimated_bytes(self, model: Model, times: RunTimes) -> int:
        """Memory (bytes) a run of ``model`` over ``times`` holds at its end (an estimate;
        nothing is allocated)."""
        raise NotImplementedError

    def lighter(self, model: Model, times: RunTimes) -> list[tuple[RecordMode, str]]:
        """Modes that record less of the same run, each with the option that selects it
        (offered when a run does not fit in memory)."""
        return []

    def plans(self, model: Model, times: RunTimes) -> tuple[RecordPlan, RecordPlan]:
        """What the main run and the ideal companion record."""
        raise NotImplementedError

    def dataset(
        self, model: Model, run: Integration, ideal_model: Model,
        ideal_run: Integration | None, t_out: np.ndarray, times: RunTimes,
        attrs: dict[str, Any],
    ) -> xr.Dataset:  # fmt: skip
        """The Dataset of ``run`` (and of ``ideal_run``, None when the companion did not
        run) on the times ``t_out``, with ``attrs``."""
        raise NotImplementedError


def available_variables(model: Model) -> tuple[str, ...]:
    """The variables :class:`FullRecord` can record alone for ``model`` (those whose
    crank, slider or clearance joints it has)."""
    absent = {
        "crank_angle": model.crank_points is None,
        "slider_position": model.slider is None,
        "slider_velocity": model.slider is None,
        "eccentricity_x": not model.clearance_joints,
        "eccentricity_y": not model.clearance_joints,
    }
    return tuple(v for v in LIGHT_VARIABLES if not absent.get(v, False))


def _free_crank(model: Model) -> bool:
    """True when a motor drives the crank: its angle is a free coordinate, the motion
    autonomous, and revolutions are counted on the crank angle, not the clock."""
    return isinstance(model.scene.drive, MotorDrive)


#: a motor-driven crank's sections are stored up to this many times the revolutions at
#: the motor's no-load speed (a run that turns faster keeps the first ones)
_FREE_CRANK_MARGIN = 4.0


def _light_row(model: Model) -> int:
    """Bytes of one light sample of ``model``."""
    return 8 * (model_kernels.LIGHT_COLUMNS + 2 * len(model.clearance_joints))


@dataclass(frozen=True, kw_only=True)
class FullRecord(RecordMode):
    """The trajectory on the output grid (``record="full"``, the default).

    Parameters
    ----------
    variables : sequence of str, optional
        Record just these variables, names from ``crank_angle``, ``slider_position``,
        ``slider_velocity``, ``eccentricity_x``, ``eccentricity_y``. They are read from the
        integrator's dense output without a right-hand-side evaluation and the ideal
        companion does not run, so a long run at a fine grid holds a few arrays of the
        grid's length instead of the full state. The integration, and so every recorded
        value, is the same as with the full record. Default: every variable (below).

    Notes
    -----
    The Dataset holds ``crank_angle``, ``position``/``velocity`` (time, body, axis),
    ``slider_position``/``_velocity``/``_acceleration`` and their ``*_ideal`` twins,
    ``displacement_error``, ``speed_error``, per clearance joint (dim ``joint``)
    ``eccentricity_x``/``_y``, ``penetration``, ``contact_force``, ``friction_force``,
    ``contact_angle``, ``in_contact``; per lubricated joint (dim ``lubricated_joint``,
    only when the scene has one) the oil-film force ``film_force_radial``,
    ``film_force_tangential``, ``film_force_x``, ``film_force_y`` and the minimum film
    thickness ``film_thickness``; ``driving_torque``; ``joint_force`` (time,
    ideal_joint); ``mechanical_energy``; ``constraint_violation``; with
    ``effects.wear`` on, the wear of the run. The default output grid is the scene's
    (``solver.output_step``, else the drive period / 10000).
    """

    variables: tuple[str, ...] | None = None
    name: ClassVar[str] = "full"

    def __post_init__(self) -> None:
        variables = self.variables
        if variables is None:
            return
        ok = (
            isinstance(variables, Sequence)
            and not isinstance(variables, str)
            and len(variables) > 0
            and all(isinstance(v, str) and v in LIGHT_VARIABLES for v in variables)
        )
        if not ok:
            raise ValueError(
                f"variables must be a non-empty list of names from {list(LIGHT_VARIABLES)}; "
                f"got {_shown(variables)}."
            )
        object.__setattr__(self, "variables", tuple(dict.fromkeys(variables)))

    @property
    def companion(self) -> bool:
        return self.variables is None

    def check(self, model: Model, times: RunTimes) -> None:
        if self.variables is None:
            return
        present = available_variables(model)
        missing = [v for v in self.variables if v not in present]
        if missing:
            raise ValueError(
                f"variables {missing} are not outputs of scene {model.scene.name!r} "
                "(no crank, slider or clearance joint to measure them on)."
            )

    def end_time(self, t_out: np.ndarray, times: RunTimes) -> float:
        return float(t_out[-1])

    def estimated_bytes(self, model: Model, times: RunTimes) -> int:
        n_out = times.n_out
        grid = 8 * n_out  # the output times
        if self.variables is not None:  # the light samples and the Dataset's variables
            return grid + n_out * (_light_row(model) + 8 * len(self.variables))
        runs = 2 if model.clearance_joints else 1
        return grid + estimated_run_bytes([model] * runs, n_out)

    def lighter(self, model: Model, times: RunTimes) -> list[tuple[RecordMode, str]]:
        if self.variables is not None:
            return []
        found: list[tuple[RecordMode, str]] = []
        light = available_variables(model)
        if light:
            found.append(
                (
                    FullRecord(variables=light),
                    f"record=FullRecord(variables={list(light)}) (--var; light samples only)",
                )
            )
        if times.period is not None:
            found.append((MetricsRecord(), "record='metrics' or 'sections' (--record)"))
        return found

    def plans(self, model: Model, times: RunTimes) -> tuple[RecordPlan, RecordPlan]:
        if self.variables is not None:
            # the named variables from the dense output alone; no ideal companion
            plan = RecordPlan(grid="light")
            return plan, plan
        models = [model, model] if model.clearance_joints else [model]
        # one frame deeper than the dataset: simulate → _integrate → plans
        warn_if_large(models, times.n_out, times.output_step, stacklevel=_CALLER + 1)
        plan = RecordPlan()
        return plan, plan

    def dataset(
        self, model: Model, run: Integration, ideal_model: Model,
        ideal_run: Integration | None, t_out: np.ndarray, times: RunTimes,
        attrs: dict[str, Any],
    ) -> xr.Dataset:  # fmt: skip
        if self.variables is not None:
            attrs.pop("ideal_max_step", None)  # no ideal mechanism is recorded
            attrs["variables"] = ", ".join(self.variables)
            return light_dataset(model, run, t_out, self.variables, attrs=attrs)
        ds = to_dataset(model, run, ideal_model, ideal_run, attrs=attrs)
        scene = model.scene
        warn_if_deep_penetration(ds, scene, stacklevel=_CALLER)
        if scene.effects.wear and model.clearance_joints:
            ds = add_run_wear(ds, scene)
        return ds


@dataclass(frozen=True, kw_only=True)
class MetricsRecord(RecordMode):
    """The response metrics only (``record="metrics"``), as scalar variables.

    Peak contact force, penetration and driving torque are taken at every accepted
    integrator state (and inside contact steps), not on a grid; the slider is compared
    with the ideal mechanism (``max_displacement_error``, ``max_speed_error``) on the
    output grid, default the drive period / 1000. Needs a periodic drive.

    Parameters
    ----------
    discard : float
        Revolutions treated as transient (≥ 0, less than the simulated revolutions): the
        metrics are taken over the time after them.
    companion : bool
        Integrate the ideal companion (default). False leaves it out:
        ``max_displacement_error`` and ``max_speed_error`` are then NaN, and the run costs
        what the mechanism with clearance alone costs.
    """

    discard: float = 0.0
    companion: bool = True  # type: ignore[assignment]
    name: ClassVar[str] = "metrics"
    needs_period: ClassVar[bool] = True
    grid_divisions: ClassVar[int | None] = 1000

    def __post_init__(self) -> None:
        object.__setattr__(self, "discard", _discard(self.discard))
        object.__setattr__(self, "companion", _companion(self.companion))

    def check(self, model: Model, times: RunTimes) -> None:
        super().check(model, times)
        assert times.period is not None
        if not self.discard * times.period < times.duration:
            raise ValueError(
                f"discard must be below the simulated {times.duration / times.period:g} "
                f"revolutions; got {self.discard:g}."
            )

    def sections(self, times: RunTimes) -> int:
        """Capacity of the stroboscopic recording (0: none)."""
        return 0

    def estimated_bytes(self, model: Model, times: RunTimes) -> int:
        n_out = times.n_out
        runs = 2 if model.clearance_joints and self.companion else 1
        sample = sum(a.nbytes for a in Recording.empty(model, 1))
        # light samples of each run, and the sections recorded and then stored
        sections = (runs + 1) * self.sections(times) * sample
        return 8 * n_out + runs * n_out * _light_row(model) + sections

    def plans(self, model: Model, times: RunTimes) -> tuple[RecordPlan, RecordPlan]:
        assert times.period is not None
        # contact steps longer than the default output step are sampled inside, so the
        # extremes resolve an impact at least as finely as the default full record
        plan = RecordPlan(
            grid="light", sections=self.sections(times), discard=self.discard,
            metrics_from=self.discard * times.period, peak_step=times.scene_step,
        )  # fmt: skip
        return plan, RecordPlan(grid="light")

    def dataset(
        self, model: Model, run: Integration, ideal_model: Model,
        ideal_run: Integration | None, t_out: np.ndarray, times: RunTimes,
        attrs: dict[str, Any],
    ) -> xr.Dataset:  # fmt: skip
        assert times.period is not None
        attrs["discard_revolutions"] = float(self.discard)
        window = self.discard * times.period
        return metrics_dataset(model, run, ideal_run, t_out, window=window, attrs=attrs)


@dataclass(frozen=True, kw_only=True)
class SectionsRecord(MetricsRecord):
    """The stroboscopic points and the response metrics (``record="sections"``).

    Every variable of the full record (without the ideal twins and errors), sampled where
    the crank angle passes ``phase`` + 2πk after ``discard`` revolutions, located on the
    integrator's dense output (not interpolated from a grid), along the dimension
    ``crossing`` with coordinates ``time`` and ``drive_cycle`` (the layout of
    :func:`chaoskit.stroboscopic_map`), plus the metrics of :class:`MetricsRecord`.
    Needs a periodic drive.

    Parameters
    ----------
    phase : float
        Strobe phase (rad), finite.
    discard : float
        Revolutions treated as transient (≥ 0, less than the simulated revolutions): no
        section before them, and the metrics are taken after them.
    companion : bool
        Integrate the ideal companion (default); False: as for :class:`MetricsRecord`.
    """

    phase: float = 0.0
    name: ClassVar[str] = "sections"

    def __post_init__(self) -> None:
        super().__post_init__()
        phase = _number(self.phase)
        if (
            isinstance(phase, bool)
            or not isinstance(phase, int | float)
            or not math.isfinite(phase)
        ):
            raise ValueError(f"phase must be a finite angle in rad; got {_shown(phase)}.")
        object.__setattr__(self, "phase", float(phase))

    def check(self, model: Model, times: RunTimes) -> None:
        if not _free_crank(model):
            super().check(model, times)

    def sections(self, times: RunTimes, model: Model | None = None) -> int:
        if model is not None and _free_crank(model):
            drive = model.scene.drive
            turns = _FREE_CRANK_MARGIN * times.duration * drive.no_load_speed / (2.0 * math.pi)
            return math.ceil(turns) + 2
        assert times.period is not None
        return math.ceil(times.duration / times.period - self.discard) + 2

    def estimated_bytes(self, model: Model, times: RunTimes) -> int:
        if not _free_crank(model):
            return super().estimated_bytes(model, times)
        sample = sum(a.nbytes for a in Recording.empty(model, 1))
        light = times.n_out * (8 + _light_row(model))
        return light + 2 * self.sections(times, model) * sample

    def plans(self, model: Model, times: RunTimes) -> tuple[RecordPlan, RecordPlan]:
        if _free_crank(model):
            # revolutions of a free crank are counted on its angle (the strobe starts
            # after ``discard`` turns of it); the metrics cover the whole run
            plan = RecordPlan(
                grid="light", sections=self.sections(times, model), discard=self.discard,
                metrics_from=0.0, peak_step=times.scene_step, phase=self.phase,
            )  # fmt: skip
            return plan, RecordPlan(grid="light")
        plan, ideal_plan = super().plans(model, times)
        return replace(plan, phase=self.phase), ideal_plan

    def output_times(self, grid: np.ndarray, times: RunTimes) -> np.ndarray:
        if times.period is None:
            return grid
        # run a hair past the end so the strobe at the last revolution is always taken
        # (the crank angle at the end may fall short of it by round-off); it is kept only
        # if within the simulated revolutions
        return np.append(grid, times.duration + 1e-6 * times.period)

    def dataset(
        self, model: Model, run: Integration, ideal_model: Model,
        ideal_run: Integration | None, t_out: np.ndarray, times: RunTimes,
        attrs: dict[str, Any],
    ) -> xr.Dataset:  # fmt: skip
        if _free_crank(model):
            attrs["discard_revolutions"] = float(self.discard)
            metrics = metrics_dataset(model, run, ideal_run, t_out, window=0.0, attrs=attrs)
        else:
            metrics = super().dataset(model, run, ideal_model, ideal_run, t_out, times, attrs)
        ds = sections_dataset(model, run, ideal_run, metrics=metrics, phase=self.phase, attrs=attrs)
        if _free_crank(model) and ds.sizes["crossing"] >= self.sections(times, model):
            # the crank outran the room reserved for its sections (an overrunning load
            # drove it far past the motor's no-load speed): say so rather than drop quietly
            warnings.warn(
                f"the crank turned faster than {_FREE_CRANK_MARGIN:g} × the motor's no-load "
                f"speed on average; only the first {ds.sizes['crossing']} sections are kept "
                "(shorten t_end or raise drive.no_load_speed_rpm).",
                SimulationWarning,
                stacklevel=2,
            )
        return ds.isel(crossing=ds["time"].values <= times.duration * (1.0 + 1e-9))


@dataclass(frozen=True, kw_only=True)
class WearRecord(RecordMode):
    """What the wear of a run and a wear path's analysis read (``record="wear"``).

    On the output grid, per clearance joint (dim ``joint``): ``eccentricity_x``,
    ``eccentricity_y``, ``penetration``, ``contact_force``, ``sliding_velocity``,
    ``contact_angle``, ``contact_angle_journal``; and ``crank_angle`` when the scene has a
    crank. Each is the full record's variable of the same run, sample for sample (the
    integration and the output grid are the same); the ideal companion does not run, and
    the bodies, the ideal joints' forces, the energy and the run's wear are not kept
    (``mechanism.core.wear.run_wear`` of the Dataset gives the wear). Needs a clearance
    joint. :func:`mechanism.wear_life` records its runs this way.
    """

    name: ClassVar[str] = "wear"

    @property
    def companion(self) -> bool:
        return False

    def check(self, model: Model, times: RunTimes) -> None:
        if not model.clearance_joints:
            raise ValueError(
                f"record='wear' needs a clearance joint; scene {model.scene.name!r} has "
                "none (use record='full')."
            )

    def end_time(self, t_out: np.ndarray, times: RunTimes) -> float:
        return float(t_out[-1])

    def estimated_bytes(self, model: Model, times: RunTimes) -> int:
        # the raw recording of the run, then the kept variables
        sample = sum(a.nbytes for a in Recording.empty(model, 1))
        kept = 8 * (1 + len(WEAR_VARIABLES) * len(model.clearance_joints))
        return times.n_out * (8 + sample + kept)

    def plans(self, model: Model, times: RunTimes) -> tuple[RecordPlan, RecordPlan]:
        plan = RecordPlan()
        return plan, plan

    def dataset(
        self, model: Model, run: Integration, ideal_model: Model,
        ideal_run: Integration | None, t_out: np.ndarray, times: RunTimes,
        attrs: dict[str, Any],
    ) -> xr.Dataset:  # fmt: skip
        ds = wear_dataset(model, run, attrs=attrs)
        warn_if_deep_penetration(ds, model.scene, stacklevel=_CALLER)
        return ds


#: The record modes by name: ``simulate(record=name)`` is the mode with default options.
RECORD_MODES: dict[str, type[RecordMode]] = {
    mode.name: mode for mode in (FullRecord, MetricsRecord, SectionsRecord, WearRecord)
}


def record_mode(record: RecordMode | str) -> RecordMode:
    """The record mode ``record``: a mode object as given, a name (``"full"``,
    ``"metrics"``, ``"sections"``, ``"wear"``) as that mode with its default options."""
    if isinstance(record, RecordMode):
        return record
    if not isinstance(record, str):
        objects = ", ".join(f"{mode.__name__}()" for mode in RECORD_MODES.values())
        names = ", ".join(map(repr, RECORD_MODES))
        raise ValueError(
            f"record must be a record mode object ({objects}) or one of {names}; "
            f"got {_given(record)}."
        )
    return RECORD_MODES[check_choice(record, name="record", choices=tuple(RECORD_MODES))]()


def _given(value: Any) -> str:
    """``value`` for a message; a class by its name (a mode class given for an object)."""
    return f"the class {value.__name__}" if isinstance(value, type) else repr(value)
