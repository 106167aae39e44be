"""Bifurcation (orbit) diagrams of a scene over one parameter, on the sweep machinery.

Each parameter value is one sweep point whose simulation records only stroboscopic
sections and the response metrics (``simulate(..., record=SectionsRecord(companion=False))``:
no ideal companion, so no errors against the ideal mechanism), so a value costs the
integration alone; the store, resume, failures as data and the dask backends
are those of :func:`mechanism.sweep`.
"""

from __future__ import annotations

import contextlib
import math
import os
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import __version__, stamp
from mechanism.core import default_step, drive_period, simulate, step_limits
from mechanism.core.integrate import (
    Dopri5,
    StepSettings,
    TangentSettings,
    clearance_kinematics,
    integrate_tangent,
    project_state,
    section_latch,
)
from mechanism.core.model import assemble, initial_state
from mechanism.core.record import SectionsRecord

from ._lyapunov import lyapunov_exponent
from .sweep import Analysis, resolve_scene, revolution_time, simulated_span, sweep

__all__ = ["EXPONENT_VARIABLES", "BifurcationSettings", "bifurcation", "parse_values"]

ECCENTRICITY = "eccentricity"
# the per-value exponent a bifurcation Dataset can carry: estimate and 95 % interval
EXPONENT_VARIABLES = ("lyapunov_exponent", "lyapunov_exponent_low", "lyapunov_exponent_high")
_SOURCE = f"mechanism (chaoskit {__version__})"


#: Tolerance of the orbit diagram's error-controlled runs (rigid models): at a scene's
#: rtol = atol = 1e-5 the step control accepts 10 µm on positions, and a regular orbit's
#: strobes scatter by up to a micrometre; from 1e-7 on they coincide (docs/sweeps.md).
ORBIT_TOLERANCE = 1e-7
#: sweep directions: None, each value from the scene's start; up / down, state continuation
DIRECTIONS = (None, "up", "down")
#: the section variables of a sweep with state continuation
CONTINUED_VARIABLES = (ECCENTRICITY, "eccentricity_x", "eccentricity_y")
#: no renormalisation of the (zero) deviation: the reference alone is integrated
_NO_RENORMALIZATION = 2**62


def _scene_exponent(
    scene: Any, *, revolutions: float, discard: float
) -> tuple[float, float, float]:
    """λ₁ of one value from the equations of motion (:func:`lyapunov_exponent` at its own
    default tolerances), with its 95 % interval, in 1/s."""
    free = free_crank_period(scene)
    if free is None:
        result = lyapunov_exponent(scene, revolutions=revolutions, discard=discard)
    else:
        result = lyapunov_exponent(scene, t_end=revolutions * free, discard=discard * free)
    low, high = result.ci
    return float(result.exponent), float(low), float(high)


def free_crank_period(scene: Any) -> float | None:
    """The time scale of a revolution of a motor-driven crank, whose motion has no
    prescribed period: 2π/ω₀ at the motor's no-load speed ω₀ (s); None for a scene with a
    periodic drive or without a motor.

    A crank turns at most about once per such period (slower under load), so a value run
    for ``revolutions`` of them reaches at most that many crank-angle crossings."""
    return None if drive_period(scene) is not None else revolution_time(scene)


# Hook for the exponent of one value: (scene, revolutions=, discard=) -> (λ, low, high) in
# 1/s; tests replace it with a stand-in.
largest_exponent: Callable[..., tuple[float, float, float]] = _scene_exponent


@dataclass(frozen=True)
class _SectionPoint:
    """The simulation of one bifurcation value (pickled to the dask workers); its repr
    names the settings in the store's manifest, so a resumed store must match them."""

    discard: float
    phase: float
    exponent: bool
    rtol: float | None = None
    atol: float | None = None
    exponent_revolutions: float | None = None
    exponent_discard: float | None = None

    def __call__(self, scene: Any, *, revolutions: float) -> xr.Dataset:
        # the tolerance is the error control's: a flexible model's fixed-step
        # generalized-α keeps the scene's Newton and error settings
        tolerance = {} if _flexible(scene) else {
            key: value for key, value in (("rtol", self.rtol), ("atol", self.atol))
            if value is not None
        }  # fmt: skip
        # the diagram needs no ideal mechanism: at 1e-8 it cost a third (150 rpm) to
        # two thirds (30 rpm) more than the run itself
        record = SectionsRecord(phase=self.phase, discard=self.discard, companion=False)
        # a motor-driven crank has no period: run for as many no-load periods; its
        # sections are crank-angle crossings and ``discard`` counts crank revolutions
        ds = simulate(
            scene, record=record, throw=False, **simulated_span(scene, revolutions), **tolerance
        )
        if self.exponent and ds.attrs.get("solver_status") == 0:
            cpu = time.process_time()
            discard = self.discard if self.exponent_discard is None else self.exponent_discard
            kept = (
                revolutions - self.discard
                if self.exponent_revolutions is None
                else self.exponent_revolutions
            )
            value, low, high = largest_exponent(scene, revolutions=discard + kept, discard=discard)
            # the exponent's one-core cost beside the simulation's (``solver_cpu_time``);
            # the sweep keeps ``solver_*`` attributes in the value's summary
            ds.attrs["solver_exponent_cpu_time"] = time.process_time() - cpu
            for name, number, what in zip(
                EXPONENT_VARIABLES,
                (value, low, high),
                ("largest Lyapunov exponent", "its 95 % interval, low", "its 95 % interval, high"),
                strict=True,
            ):
                ds[name] = xr.DataArray(
                    float(number),
                    attrs={
                        "units": "s-1",
                        "long_name": what,
                        "revolutions_kept": kept,
                        "revolutions_discarded": discard,
                    },
                )
        return ds


def _revolutions(value: Any, name: str, *, positive: bool) -> float | None:
    """An optional revolution count: None, or a finite number > 0 (``positive``) / >= 0."""
    if value is None:
        return None
    number = not isinstance(value, bool) and isinstance(value, int | float)
    if not (number and math.isfinite(value) and (value > 0 if positive else value >= 0)):
        bound = "> 0" if positive else ">= 0"
        raise ValueError(f"{name} must be a number {bound} (revolutions); got {value!r}.")
    return float(value)


@dataclass(frozen=True, kw_only=True)
class BifurcationSettings:
    r"""How :func:`bifurcation` samples and integrates each value: the strobe phase, the
    tolerances of the points and the length of the per-value exponent.

    Every field is checked on construction (a ValueError names the field and its
    accepted range).

    Parameters
    ----------
    phase : float
        Crank phase :math:`\varphi` of the strobe, rad (finite).
    rtol, atol : float or None
        Tolerances of the error-controlled integration of a rigid model's points, in
        (0, 1) (default 1e-7; None: the scene's). At a scene's usual 1e-5 the error
        accepted on positions is 10 µm and a regular orbit's strobes scatter by up to a
        micrometre, which reads as a thin band; at 1e-7 and tighter they coincide
        (``docs/sweeps.md``). The exponent runs at :func:`lyapunov_exponent`'s own
        default, 1e-8 (at 1e-7 it is not converged). Flexible models (fixed-step
        generalized-α) keep the scene's settings.
    exponent_revolutions, exponent_discard : float or None
        Revolutions the exponent keeps (> 0) and the transient it discards before them
        (>= 0); default (None) those of the points. They apply with
        ``bifurcation(..., exponent=True)`` only. The exponent costs about three times
        the points per revolution, so a diagram over many values can keep fewer for it:
        its interval widens about as the inverse square root of the kept revolutions,
        which ``docs/sweeps.md`` measures against the cost.
    direction : {None, "up", "down"}
        None (default): every value starts from the scene's initial state, the values
        run in parallel. ``"up"`` / ``"down"``: state continuation, the values run one
        after the other in increasing / decreasing order, each starting from the final
        state of the previous one (the first from the scene's start), so coexisting
        motions and hysteresis show as different points up and down. Rigid scenes with
        a constant crank speed and whole ``revolutions`` only; the points are the
        journals' eccentricity (``"eccentricity"``, ``"eccentricity_x"``,
        ``"eccentricity_y"``); no exponent, no store and no dask client (the values
        depend on each other).

    Examples
    --------
    >>> import mechanism
    >>> mechanism.BifurcationSettings(rtol=1e-8, atol=1e-8).phase
    0.0
    """

    phase: float = 0.0
    rtol: float | None = ORBIT_TOLERANCE
    atol: float | None = ORBIT_TOLERANCE
    exponent_revolutions: float | None = None
    exponent_discard: float | None = None
    direction: str | None = None

    def __post_init__(self) -> None:
        if self.direction not in DIRECTIONS:
            raise ValueError(
                f"direction must be 'up', 'down' or None (each value from the scene's "
                f"start); got {self.direction!r}."
            )
        phase = self.phase
        if (
            isinstance(phase, bool)
            or not isinstance(phase, int | float)
            or not math.isfinite(phase)
        ):
            raise ValueError(f"phase must be a finite angle in rad; got {phase!r}.")
        object.__setattr__(self, "phase", float(phase))
        for name in ("rtol", "atol"):
            value = getattr(self, name)
            number = not isinstance(value, bool) and isinstance(value, int | float)
            if value is not None and not (number and 0.0 < value < 1.0):
                raise ValueError(f"{name} must be in (0, 1) or None (the scene's); got {value!r}.")
            object.__setattr__(self, name, None if value is None else float(value))
        object.__setattr__(
            self,
            "exponent_revolutions",
            _revolutions(self.exponent_revolutions, "exponent_revolutions", positive=True),
        )
        object.__setattr__(
            self,
            "exponent_discard",
            _revolutions(self.exponent_discard, "exponent_discard", positive=False),
        )


def _flexible(scene: Any) -> bool:
    """Whether the scene's model has ANCF beams (integrated by fixed-step generalized-α)."""
    return bool(scene.effects.flexibility) and any(
        getattr(body, "type", "rigid") != "rigid" for body in scene.bodies.values()
    )


def parse_values(text: str) -> list[float]:
    """Parameter values from ``START:STOP:COUNT`` (COUNT values from START to STOP, both
    included) or a comma-separated list.

    Examples
    --------
    >>> parse_values("30:300:4")
    [30.0, 120.0, 210.0, 300.0]
    >>> parse_values("1e-4, 2e-4")
    [0.0001, 0.0002]
    """
    text = text.strip()
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            n = int(count)
            if n < 1:
                raise ValueError
            return [float(v) for v in np.linspace(float(start), float(stop), n)]
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(
            f"values must be START:STOP:COUNT (e.g. 30:300:60) or V1,V2,...; got {text!r}."
        ) from None


@contextlib.contextmanager
def _store_folder(store: str | os.PathLike[str] | None) -> Iterator[Path]:
    if store is not None:
        yield Path(store)
        return
    with tempfile.TemporaryDirectory(prefix="mechanism-bifurcation-") as tmp:
        yield Path(tmp)


def _point_variable(section: xr.Dataset, name: str) -> xr.DataArray:
    if name == ECCENTRICITY and name not in section:
        ex, ey = section["eccentricity_x"], section["eccentricity_y"]
        return xr.DataArray(
            np.hypot(ex.values, ey.values),
            dims=ex.dims,
            attrs={"units": "m", "long_name": "journal eccentricity |e| in its bearing"},
        )
    if name not in section:
        raise ValueError(
            f"variable {name!r} is not recorded at the sections; available: "
            f"{sorted(map(str, section.data_vars))} and {ECCENTRICITY!r}."
        )
    var = section[name]
    extra = [d for d in var.dims if d not in ("crossing", "joint")]
    if "crossing" not in var.dims or extra:
        raise ValueError(
            f"variable {name!r} has dims {var.dims}; a bifurcation variable is along "
            "'crossing' (and 'joint')."
        )
    return var


def bifurcation(
    scene: Any,
    *,
    parameter: str,
    values: Sequence[float],
    revolutions: float,
    discard: float,
    variables: Sequence[str] = (ECCENTRICITY,),
    exponent: bool = False,
    settings: BifurcationSettings | None = None,
    client: Any = None,
    n_workers: int | None = None,
    store: str | os.PathLike[str] | None = None,
    progress: bool = False,
) -> xr.Dataset:
    r"""Orbit diagram of a scene over one parameter: stroboscopic points per value.

    For every value of ``parameter`` the scene is simulated for ``revolutions`` drive
    periods recording only the stroboscopic section (the full state where the crank angle
    passes :math:`\varphi + 2\pi k`, located on the integrator's dense output) after
    ``discard`` revolutions, and the response metrics (without the ideal companion:
    ``max_displacement_error`` and ``max_speed_error`` are NaN). A period-:math:`n` response gives
    :math:`n` distinct points above its value, a chaotic one a band (Strogatz, *Nonlinear
    Dynamics and Chaos*, 2nd ed., 2015, §10.2). The values run as the points of a
    :func:`mechanism.sweep` over ``{parameter: values}``: one dask task each, a store that a
    re-run resumes, and failures as data.

    Parameters
    ----------
    scene
        A :class:`mechanism.Scene`, a built-in scene name or a TOML path.
    parameter
        A dotted scene key, e.g. ``"drive.speed_rpm"`` or ``"joints.C.clearance"``.
    values
        Its values (see ``parse_values`` for the ``START:STOP:COUNT`` form).
    revolutions
        Drive periods simulated per value (the transient included).
    discard
        Revolutions treated as transient; the points are those of the revolutions after.
    variables
        Section variables to keep (default: the journal eccentricity :math:`|e|` of each
        clearance joint); any variable of ``simulate(record="sections")`` along
        ``crossing`` (and ``joint``).
    exponent
        Also estimate the largest Lyapunov exponent of every value from the equations of
        motion (variables ``lyapunov_exponent`` and its 95 % interval
        ``lyapunov_exponent_low`` / ``_high``, 1/s), by default over the same
        revolutions as the points (see ``settings``).
    settings
        The strobe phase (rad), the tolerances of the points (default 1e-7), the
        revolutions of the exponent and the sweep direction (default: every value from
        the scene's start; ``"up"`` / ``"down"``: state continuation, each value from
        the previous one's final state, recorded in the attribute
        ``bifurcation_direction``): a :class:`BifurcationSettings` (default
        ``BifurcationSettings()``).
    client, n_workers, progress
        As for :func:`mechanism.sweep` (default: a ``LocalCluster``; ``"serial"``: this
        process).
    store
        Folder of the per-value files (a re-run resumes); default a temporary folder,
        removed afterwards.

    Returns
    -------
    xarray.Dataset
        Along ``parameter`` and ``crossing`` (coordinate: the drive cycle :math:`k`), and
        ``joint`` for per-joint variables: the section values, NaN where a value has fewer
        points (failed, diverged); the strobe instants as coordinate ``time``; per value
        the response metrics, ``status``, ``message``, ``point_id`` and, with
        ``exponent``, the exponent variables. Draw it with
        :func:`mechanism.plot_bifurcation`.

    Examples
    --------
    >>> import mechanism
    >>> ds = mechanism.bifurcation(
    ...     "slider-crank-clearance", parameter="drive.speed_rpm", values=[3000, 4000],
    ...     revolutions=4, discard=2, client="serial")
    >>> ds.eccentricity.dims
    ('drive.speed_rpm', 'crossing', 'joint')
    >>> ds.crossing.values.tolist()
    [2, 3, 4]
    """
    scene = resolve_scene(scene)
    if isinstance(values, str):
        values = parse_values(values)
    values = [float(v) for v in values]
    if not values or not all(math.isfinite(v) for v in values):
        raise ValueError(f"values must be a non-empty list of finite numbers; got {values!r}.")
    if isinstance(variables, str):
        variables = (variables,)
    variables = tuple(variables)
    if not variables:
        raise ValueError("variables must name at least one section variable.")
    if isinstance(discard, bool) or not isinstance(discard, int | float) or discard < 0:
        raise ValueError(f"discard must be a number >= 0 (revolutions); got {discard!r}.")
    if settings is None:
        settings = BifurcationSettings()
    elif not isinstance(settings, BifurcationSettings):
        raise TypeError(
            f"settings must be a mechanism.BifurcationSettings; got {type(settings).__name__}."
        )
    for name in ("exponent_revolutions", "exponent_discard"):
        if getattr(settings, name) is not None and not exponent:
            raise ValueError(
                f"settings.{name} applies to the exponent; pass exponent=True with it."
            )
    if settings.direction is not None:
        _check_continued(scene, variables, revolutions, exponent, client, store)
        ds = _continued(scene, parameter, values, float(revolutions), float(discard),
                        variables, settings)  # fmt: skip
        return ds
    simulator = _SectionPoint(
        discard=float(discard), phase=settings.phase, exponent=bool(exponent),
        rtol=settings.rtol, atol=settings.atol,
        exponent_revolutions=settings.exponent_revolutions,
        exponent_discard=settings.exponent_discard,
    )  # fmt: skip
    with _store_folder(store) as folder:
        summary = sweep(
            scene,
            grid={parameter: values},
            revolutions=revolutions,
            analysis=Analysis(variables=(), discard_revolutions=float(discard)),
            client=client,
            n_workers=n_workers,
            store=folder,
            progress=progress,
            _simulator=simulator,
        )
        sections = [_load_section(folder, str(f)) for f in summary["trajectory_file"].values]
    return _assemble(summary, sections, parameter=parameter, variables=variables, store=store)


def _load_section(folder: Path, relative: str) -> xr.Dataset | None:
    if not relative:
        return None
    with xr.open_dataset(folder / relative, engine="h5netcdf") as opened:
        return opened.load()


def _assemble(
    summary: xr.Dataset,
    sections: Sequence[xr.Dataset | None],
    *,
    parameter: str,
    variables: tuple[str, ...],
    store: str | os.PathLike[str] | None,
) -> xr.Dataset:
    """The gathered per-value summary plus the section points over (parameter, crossing)."""
    status = summary["status"].values
    usable = [
        s if s is not None and st == "ok" else None for s, st in zip(sections, status, strict=True)
    ]
    cycles = sorted({int(k) for s in usable if s is not None for k in s["drive_cycle"].values})
    slot = {k: i for i, k in enumerate(cycles)}
    n_values, n_cross = summary.sizes[parameter], len(cycles)
    times = np.full((n_values, n_cross), np.nan)
    columns: dict[str, tuple[np.ndarray, tuple[str, ...], dict[str, Any]]] = {}
    joints: np.ndarray | None = None
    for i, section in enumerate(usable):
        if section is None:
            continue
        where = np.array([slot[int(k)] for k in section["drive_cycle"].values], dtype=int)
        times[i, where] = section["time"].values
        for name in variables:
            var = _point_variable(section, name).transpose("crossing", ...)
            if "joint" in var.dims and joints is None:
                joints = np.asarray(section["joint"].values).astype(str)
            if name not in columns:
                shape = (n_values, n_cross, *var.shape[1:])
                dims = (parameter, "crossing", *map(str, var.dims[1:]))
                columns[name] = (np.full(shape, np.nan), dims, dict(var.attrs))
            columns[name][0][i, where] = var.values
    if not columns:
        # no value succeeded: empty section variables keep the layout
        for name in variables:
            columns[name] = (np.full((n_values, 0), np.nan), (parameter, "crossing"), {})
    ds = summary.drop_vars(["trajectory_file"])
    for name, (data, dims, attrs) in columns.items():
        ds[name] = xr.Variable(dims, data, attrs=attrs)
    coords: dict[str, Any] = {
        "crossing": (
            "crossing",
            np.asarray(cycles, dtype=np.int64),
            {"units": "1", "long_name": "drive cycle k (crank angle = phase + 2 pi k)"},
        ),
        "time": (
            (parameter, "crossing"),
            times,
            {"units": "s", "long_name": "time of the stroboscopic point"},
        ),
    }
    if joints is not None:
        coords["joint"] = ("joint", joints.astype(object))
    ds = ds.assign_coords(coords)
    ds.attrs.pop("store", None)
    extra = {
        "bifurcation_parameter": parameter,
        "bifurcation_variables": ",".join(variables),
        "section_kind": "stroboscopic",
        "phase_variable": "crank_angle",
    }
    if store is not None:
        extra["store"] = str(Path(store).resolve())
    return stamp(
        ds,
        title=f"bifurcation diagram over {parameter} (stroboscopic points)",
        source=_SOURCE,
        history=f"mechanism.bifurcation(parameter={parameter!r}, variables={list(variables)})",
        extra=extra,
    )


def _check_continued(
    scene: Any,
    variables: tuple[str, ...],
    revolutions: Any,
    exponent: bool,
    client: Any,
    store: Any,
) -> None:
    """Refuse what a sweep with state continuation cannot do, naming the argument."""
    if _flexible(scene) or drive_period(scene) is None:
        raise ValueError(
            "settings.direction needs a rigid scene (effects.flexibility = false) with a "
            "constant crank speed."
        )
    unknown = [v for v in variables if v not in CONTINUED_VARIABLES]
    if unknown:
        raise ValueError(
            f"with settings.direction the variables must be among {list(CONTINUED_VARIABLES)}; "
            f"got {unknown}."
        )
    whole = not isinstance(revolutions, bool) and isinstance(revolutions, int | float)
    if not (whole and revolutions >= 1 and float(revolutions).is_integer()):
        raise ValueError(
            f"with settings.direction revolutions must be a whole number >= 1 (each value "
            f"continues from the previous one's state at t = 0 mod T); got {revolutions!r}."
        )
    if exponent:
        raise ValueError("exponent=True is not available with settings.direction.")
    if store is not None or client not in (None, "serial"):
        raise ValueError(
            "with settings.direction the values run one after the other in this process: "
            "pass neither store nor a dask client."
        )


def _continued(
    scene: Any,
    parameter: str,
    values: list[float],
    revolutions: float,
    discard: float,
    variables: tuple[str, ...],
    settings: BifurcationSettings,
) -> xr.Dataset:
    """Orbit diagram with state continuation: the values in the sweep's order, each
    from the final state of the previous one."""
    order = sorted(values, reverse=settings.direction == "down")
    rows: list[dict[str, Any]] = []
    carried: tuple[np.ndarray, np.ndarray] | None = None
    for value in order:
        row = _continued_value(scene.replace({parameter: value}), revolutions, discard,
                               settings, carried)  # fmt: skip
        carried = row.pop("carry")
        rows.append(row)
    cycles = sorted({int(k) for r in rows for k in r["cycle"]})
    slot = {k: i for i, k in enumerate(cycles)}
    n_joints = max((r["ecc"].shape[1] for r in rows if r["ecc"].size), default=0)
    ecc = np.full((len(order), len(cycles), n_joints, 2), np.nan)
    times = np.full((len(order), len(cycles)), np.nan)
    for i, r in enumerate(rows):
        where = np.array([slot[int(k)] for k in r["cycle"]], dtype=int)
        ecc[i, where] = r["ecc"]
        times[i, where] = r["time"]
    names = {
        "x": "journal centre minus bearing centre, x",
        "y": "journal centre minus bearing centre, y",
    }
    data: dict[str, Any] = {}
    dims = (parameter, "crossing", "joint")
    for name in variables:
        if name == ECCENTRICITY:
            data[name] = (
                dims,
                np.hypot(ecc[..., 0], ecc[..., 1]),
                {"units": "m", "long_name": "journal eccentricity |e| in its bearing"},
            )
        else:
            axis = name[-1]
            data[name] = (
                dims,
                ecc[..., "xy".index(axis)],
                {"units": "m", "long_name": names[axis]},
            )
    data["status"] = (
        (parameter,),
        np.array([r["status"] for r in rows], dtype=object),
        {"long_name": "ok, or failed (the next value starts from the scene's start)"},
    )
    data["message"] = (
        (parameter,),
        np.array([r["message"] for r in rows], dtype=object),
        {"long_name": "why the integration failed (empty when ok)"},
    )
    data["start"] = (
        (parameter,),
        np.array([r["start"] for r in rows], dtype=object),
        {"long_name": "initial state of the value: continued or scene start"},
    )
    coords = {
        parameter: (parameter, np.asarray(order, dtype=np.float64)),
        "crossing": ("crossing", np.asarray(cycles, dtype=np.int64),
                     {"units": "1", "long_name": "drive cycle k (crank angle = phase + 2 pi k)"}),
        "time": ((parameter, "crossing"), times,
                 {"units": "s", "long_name": "time of the stroboscopic point"}),
        "joint": ("joint", np.asarray(rows[0]["joints"], dtype=object)),
    }  # fmt: skip
    ds = xr.Dataset(data, coords=coords)
    return stamp(
        ds,
        title=f"bifurcation diagram over {parameter} (stroboscopic points, sweep "
        f"{settings.direction})",
        source=_SOURCE,
        history=f"mechanism.bifurcation(parameter={parameter!r}, variables={list(variables)}, "
        f"direction={settings.direction!r})",
        extra={
            "bifurcation_parameter": parameter,
            "bifurcation_variables": ",".join(variables),
            "bifurcation_direction": settings.direction,
            "section_kind": "stroboscopic",
            "phase_variable": "crank_angle",
            "drive_phase": settings.phase,
        },
    )


def _continued_value(
    scene: Any,
    revolutions: float,
    discard: float,
    settings: BifurcationSettings,
    carried: tuple[np.ndarray, np.ndarray] | None,
) -> dict[str, Any]:
    """One value of a continued sweep: its section points and the state it ends in."""
    model = assemble(scene)
    big_t = drive_period(scene)
    q0, v0 = initial_state(model)
    y_start = np.concatenate([q0, v0])
    start, latch = "scene start", None
    if carried is not None:
        y, held = carried
        n = len(model.dof_names)
        angles = np.zeros(2 * n, dtype=bool)
        angles[:n] = [name.endswith(".theta") for name in model.dof_names]
        # the same drive phase at t = 0: angles back by whole turns, then onto this
        # value's constraints (a new speed changes the driven velocities)
        y = y.copy()
        y[angles] -= 2.0 * math.pi * np.round((y - y_start)[angles] / (2.0 * math.pi))
        y_start = project_state(model, y, t=0.0)
        latch = section_latch(model, y_start, held)
        start = "continued"
    rtol = scene.solver.rtol if settings.rtol is None else settings.rtol
    atol = scene.solver.atol if settings.atol is None else settings.atol
    max_step, floor = step_limits(model, Dopri5(), default_step(scene, big_t))
    omega = 2.0 * math.pi / big_t
    first = (settings.phase - scene.drive.initial_angle) / (2.0 * math.pi)
    cycles = np.arange(math.floor(first + discard), math.ceil(first + revolutions) + 1)
    t_sec = (cycles - first) * big_t
    keep = (t_sec > discard * big_t - 1e-12 * big_t) & (t_sec <= revolutions * big_t)
    cycles, t_sec = cycles[keep], t_sec[keep]
    stops = np.unique(np.concatenate([[0.0], t_sec, [revolutions * big_t]]))
    steps = StepSettings(rtol=rtol, atol=atol, max_step=max_step, approach_floor=floor)
    tangent = TangentSettings(
        steps=steps, time_scale=1.0 / omega, renormalize_every=_NO_RENORMALIZATION
    )
    run = integrate_tangent(
        model, y_start, np.zeros_like(y_start), stops, settings=tangent, latch=latch,
        record_states=True,
    )  # fmt: skip
    joints = tuple(model.clearance_joints)
    if not run.stats.success:
        return {"cycle": np.zeros(0), "ecc": np.zeros((0, len(joints), 2)), "time": np.zeros(0),
                "status": "failed", "message": str(run.stats.message), "start": start,
                "joints": joints, "carry": None}  # fmt: skip
    rows = np.searchsorted(stops, t_sec)
    kin = clearance_kinematics(model, run.states[rows], t=t_sec, latch=run.latches[rows])
    return {"cycle": cycles, "ecc": kin[:, :, :2], "time": t_sec, "status": "ok",
            "message": "", "start": start, "joints": joints,
            "carry": (run.final_state.copy(), run.final_latch.copy())}  # fmt: skip
