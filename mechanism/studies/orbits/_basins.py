"""``mechanism.basins``: which motion each initial state of a clearance joint settles on,
over a grid of initial journal eccentricities (coexisting motions at one parameter)."""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import check_int, check_positive, stamp
from mechanism.core import simulate
from mechanism.core.record import SectionsRecord
from mechanism.core.scene import MotorDrive, Scene

from ._orbit import PeriodicOrbit
from ._poincare import no_load_turn

__all__ = ["Basins", "basins", "plot_basins"]

#: labels of initial states that settle on no periodic motion, or lie outside the disc
UNDETERMINED = "undetermined"
OUTSIDE = "outside"
FAILED = "failed"
#: a motor-driven start runs this many times the crank turns at the no-load speed, so a
#: crank that settles at 2/3 of it or faster still turns ``revolutions`` times
MOTOR_TIME_MARGIN = 1.5


@dataclass(frozen=True, kw_only=True)
class Basins:
    """Labelled grid of initial journal eccentricities of one clearance joint.

    Attributes
    ----------
    scene_name, joint : str
        The scene and the clearance joint whose initial eccentricity varies.
    x, y : numpy.ndarray
        Initial eccentricity (m) along x (columns) and y (rows).
    label : numpy.ndarray
        (y, x) str: ``"period k #j"`` (attractor j, a periodic motion of period k), the
        name ``"orbit i (period k)"`` when the strobes lie on ``orbits[i]``,
        ``"undetermined"`` (no period up to ``max_period`` within the tolerance after
        the transient: chaotic, quasi-periodic or still settling), ``"outside"`` (beyond
        the clearance disc) or ``"failed"`` (the integration failed).
    period : numpy.ndarray
        (y, x) int: the period k of the motion, 0 when not periodic.
    attractor : numpy.ndarray
        (y, x) int: index into ``attractors``, −1 when not periodic.
    attractors : tuple of str
        The distinct periodic motions found.
    attractor_points : tuple of numpy.ndarray
        Their strobe eccentricities (k, joints, 2) (m).
    clearance : float
        Radial clearance of ``joint`` (m).
    settings : dict
        Revolutions, transient, tolerances and the strobe tolerance.
    cpu_time : float
        Process CPU time of the whole grid (s).
    crank_speed : numpy.ndarray
        Initial crank speeds (rpm) of a motor-driven scene's grid (``crank_speeds``);
        then ``label``, ``period`` and ``attractor`` are (crank_speed, y, x). Empty for
        the (y, x) grid of one start speed.
    """

    scene_name: str
    joint: str
    x: np.ndarray
    y: np.ndarray
    label: np.ndarray
    period: np.ndarray
    attractor: np.ndarray
    attractors: tuple[str, ...]
    attractor_points: tuple[np.ndarray, ...]
    clearance: float
    settings: dict[str, Any] = field(default_factory=dict)
    cpu_time: float = 0.0
    crank_speed: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def coexisting(self) -> bool:
        """More than one motion (periodic attractors and undetermined ones) on the grid."""
        kinds = {str(v) for v in self.label.ravel()} - {OUTSIDE, FAILED}
        return len(kinds) > 1

    def to_dataset(self) -> xr.Dataset:
        """The grid as a Dataset (units and long names)."""
        dims = ("crank_speed", "y", "x") if self.crank_speed.size else ("y", "x")
        ds = xr.Dataset(
            {
                "label": (dims, self.label.astype(object), {
                    "units": "1", "long_name": "motion the initial state settles on"}),
                "period": (dims, self.period, {
                    "units": "1", "long_name": "period (drive periods) of the motion, 0: none"}),
                "attractor": (dims, self.attractor, {
                    "units": "1", "long_name": "index of the periodic attractor, -1: none"}),
            },
            coords={
                "x": ("x", self.x, {"units": "m",
                                    "long_name": f"initial eccentricity x of joint {self.joint}"}),
                "y": ("y", self.y, {"units": "m",
                                    "long_name": f"initial eccentricity y of joint {self.joint}"}),
            },
        )  # fmt: skip
        if self.crank_speed.size:
            speed_attrs = {"units": "rpm", "long_name": "initial crank speed of the motor drive"}
            ds = ds.assign_coords(crank_speed=("crank_speed", self.crank_speed, speed_attrs))
        extra = {f"setting_{k}": v for k, v in self.settings.items()}
        extra.update(
            scene_name=self.scene_name,
            joint=self.joint,
            attractors=";".join(self.attractors),
            clearance=self.clearance,
            clearance_units="m",
            cpu_time=self.cpu_time,
        )
        return stamp(
            ds,
            title=f"basins of the motions of {self.scene_name} over the initial "
            f"eccentricity of joint {self.joint}",
            source="mechanism.basins",
            history="mechanism.basins",
            extra=extra,
        )


def _period(points: np.ndarray, max_period: int, tolerance: float) -> int:
    """Smallest k ≤ ``max_period`` with the last strobes repeating after k, else 0."""
    n = points.shape[0]
    for k in range(1, max_period + 1):
        if n < 3 * k:
            break
        tail = points[-2 * k :]
        before = points[-3 * k : -k]
        if np.max(np.linalg.norm(tail - before, axis=-1)) <= tolerance:
            return k
    return 0


def _same_cycle(a: np.ndarray, b: np.ndarray, tolerance: float) -> bool:
    """Whether two period-k strobe sets are the same cycle (any shift)."""
    if a.shape != b.shape:
        return False
    k = a.shape[0]
    return any(
        np.max(np.linalg.norm(np.roll(a, s, axis=0) - b, axis=-1)) <= tolerance for s in range(k)
    )


def basins(
    scene: Scene,
    *,
    joint: str | None = None,
    points: int = 8,
    extent: float = 0.9,
    revolutions: int = 40,
    discard: int = 25,
    max_period: int = 4,
    tolerance: float = 1e-3,
    orbits: Sequence[PeriodicOrbit] = (),
    rtol: float = 1e-8,
    atol: float = 1e-8,
    crank_speeds: Sequence[float] | None = None,
) -> Basins:
    """Which motion each initial state settles on: a grid of initial journal
    eccentricities of one clearance joint (journal at rest relative to its bearing),
    each run to its attractor and labelled.

    Each grid point is the scene with ``joints.<joint>.initial_eccentricity`` set,
    simulated for ``revolutions`` drive periods recording the stroboscopic section after
    ``discard``. A point whose last strobes repeat after k periods (k ≤ ``max_period``,
    within ``tolerance`` of the clearance) is periodic; periodic points with the same
    cycle of strobes are one attractor, and one that lies on a given orbit (its
    ``evidence`` approach within ``tolerance``) carries the orbit's name. The rest is
    ``"undetermined"``: chaotic, quasi-periodic or still settling (an exponent or the
    motion verdict of that start decides which). Runs are serial, one per grid point.

    Parameters
    ----------
    scene : mechanism.scene.Scene
        A scene with a periodic drive or a motor drive and at least one clearance joint.
    joint : str, optional
        Clearance joint whose initial eccentricity varies (default: the first).
    points : int
        Grid points per axis (in [2, 64]); points beyond ``extent`` × the clearance from
        the centre are ``"outside"`` and not run.
    extent : float
        Half width of the grid over the clearance, in (0, 1].
    revolutions, discard : int
        Drive periods simulated (≥ 2) and the transient before the strobes compared
        (≥ 0, < revolutions).
    max_period : int
        Largest period looked for (≥ 1); ``revolutions − discard`` must hold 3 of them.
    tolerance : float
        Strobe distance over the clearance within which points repeat (> 0; 1e-3).
    orbits : sequence of PeriodicOrbit
        Orbits of the same scene to name the attractors by (e.g. from
        :func:`mechanism.periodic_orbit`).
    rtol, atol : float
        Tolerances of the runs (default 1e-8).
    crank_speeds : sequence of float, optional
        Motor-driven scenes only: initial crank speeds (rpm, ``drive.initial_speed_rpm``;
        0 starts at rest) as a third axis of the grid. A motor-driven start (with or
        without it) runs for 1.5 × ``revolutions`` crank turns at the motor's no-load
        speed, its strobes are the crank angle's crossings (``discard`` counts crank
        turns) and the last ``revolutions − discard`` of them are compared.

    Returns
    -------
    Basins

    Raises
    ------
    ValueError
        On bad arguments or a scene without clearance joints.
    """
    cpu0 = time.process_time()
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    points = check_int(points, name="points", minimum=2, maximum=64)
    revolutions = check_int(revolutions, name="revolutions", minimum=2)
    discard = check_int(discard, name="discard", minimum=0, maximum=revolutions - 1)
    max_period = check_int(max_period, name="max_period", minimum=1)
    if revolutions - discard < 3 * max_period:
        raise ValueError(
            f"revolutions - discard must be at least 3 * max_period = {3 * max_period} "
            f"(strobes to compare); got {revolutions - discard}."
        )
    extent = check_positive(extent, name="extent")
    if extent > 1.0:
        raise ValueError(f"extent must be in (0, 1]; got {extent!r}.")
    tolerance = check_positive(tolerance, name="tolerance")
    names = [n for n, j in scene.joints.items() if getattr(j, "clearance", 0.0)]
    if not names:
        raise ValueError(f"the scene {scene.name!r} has no clearance joint.")
    joint = names[0] if joint is None else joint
    if joint not in names:
        raise ValueError(f"joint must be one of the clearance joints {names}; got {joint!r}.")
    clearance = float(scene.joints[joint].clearance)
    speeds = _crank_speeds(scene, crank_speeds)
    axis = extent * clearance * np.linspace(-1.0, 1.0, points)
    shape = (max(speeds.size, 1), points, points)
    label = np.full(shape, OUTSIDE, dtype=object)
    period = np.zeros(shape, dtype=np.int64)
    attractor = np.full(shape, -1, dtype=np.int64)
    found: list[tuple[str, np.ndarray]] = []
    record = SectionsRecord(discard=float(discard), companion=False)
    span: dict[str, Any] = {"revolutions": revolutions}
    if isinstance(scene.drive, MotorDrive):
        # autonomous: run long enough for the crank to turn ``revolutions`` times; the
        # sections are its angle's crossings, ``discard`` counts its turns
        span = {"t_end": MOTOR_TIME_MARGIN * revolutions * no_load_turn(scene)}
    for (i_s, iy, ix), _ in np.ndenumerate(label):
        ex, ey = axis[ix], axis[iy]
        if math.hypot(ex, ey) > extent * clearance * (1.0 + 1e-12):
            continue
        changes: dict[str, Any] = {f"joints.{joint}.initial_eccentricity": (float(ex), float(ey))}
        if speeds.size:
            changes["drive.initial_speed_rpm"] = float(speeds[i_s])
        ds = simulate(
            scene.replace(changes), record=record, rtol=rtol, atol=atol, throw=False, **span
        )
        if ds.attrs.get("solver_status", 0) != 0:
            label[i_s, iy, ix] = FAILED
            continue
        strobes = np.stack(
            [np.asarray(ds["eccentricity_x"].values), np.asarray(ds["eccentricity_y"].values)],
            axis=-1,
        ).reshape(ds.sizes["crossing"], -1, 2)
        k = _period(strobes[-(revolutions - discard) :], max_period, tolerance * clearance)
        if k == 0:
            label[i_s, iy, ix] = UNDETERMINED
            continue
        cycle = strobes[-k:]
        index = next(
            (
                i
                for i, (_, pts) in enumerate(found)
                if _same_cycle(pts, cycle, 10.0 * tolerance * clearance)
            ),
            None,
        )
        if index is None:
            found.append((_name(ds, k, len(found), orbits, tolerance), cycle))
            index = len(found) - 1
        label[i_s, iy, ix] = found[index][0]
        period[i_s, iy, ix] = k
        attractor[i_s, iy, ix] = index
    if not speeds.size:
        label, period, attractor = label[0], period[0], attractor[0]
    return Basins(
        scene_name=scene.name,
        joint=joint,
        x=axis,
        y=axis.copy(),
        label=label.astype(str),
        period=period,
        attractor=attractor,
        attractors=tuple(name for name, _ in found),
        attractor_points=tuple(pts for _, pts in found),
        clearance=clearance,
        settings={"revolutions": revolutions, "discard": discard, "max_period": max_period,
                  "tolerance": tolerance, "extent": extent, "rtol": rtol, "atol": atol},
        cpu_time=time.process_time() - cpu0,
        crank_speed=speeds,
    )  # fmt: skip


def _crank_speeds(scene: Scene, crank_speeds: Sequence[float] | None) -> np.ndarray:
    """The checked initial crank speeds (rpm) of a motor-driven scene's grid (empty for
    None)."""
    if crank_speeds is None:
        return np.zeros(0)
    if not isinstance(scene.drive, MotorDrive):
        raise ValueError(
            "crank_speeds needs a motor drive (the crank speed of a constant_speed or "
            "prescribed drive is not an initial condition); leave it None."
        )
    speeds = np.asarray(crank_speeds, dtype=np.float64).ravel()
    limit = 1e6
    if speeds.size == 0 or not np.all(np.isfinite(speeds)) or np.any(np.abs(speeds) > limit):
        raise ValueError(
            f"crank_speeds must be 1 or more finite speeds in [-{limit:g}, {limit:g}] rpm; "
            f"got {crank_speeds!r}."
        )
    return speeds


def _name(
    ds: xr.Dataset, k: int, index: int, orbits: Sequence[PeriodicOrbit], tolerance: float
) -> str:
    """The attractor's name: the given orbit it lies on, else its period and index."""
    for i, orbit in enumerate(orbits):
        if orbit.period != k:
            continue
        try:
            evidence = orbit.evidence(ds, sections=k, tolerance=tolerance)
        except ValueError:
            continue
        if evidence.approach <= tolerance:
            return f"orbit {i} (period {k})"
    return f"period {k} #{index}"


def plot_basins(result: Basins, *, ax: Any = None, speed: int = 0) -> Any:
    """Draw the labelled grid: one colour per motion over the initial eccentricity (µm).

    Parameters
    ----------
    result : Basins
    ax : matplotlib.axes.Axes, optional
        Where to draw (default: a new figure's axes).
    speed : int
        Index into ``result.crank_speed`` of the slice drawn (a grid over crank speeds).

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 4.5))
    label = result.label if result.label.ndim == 2 else result.label[speed]
    kinds = sorted({str(v) for v in label.ravel()} - {OUTSIDE})
    code = np.full(label.shape, np.nan)
    for i, kind in enumerate(kinds):
        code[label == kind] = i
    cmap = plt.get_cmap("tab10", max(len(kinds), 1))
    ax.pcolormesh(result.x * 1e6, result.y * 1e6, code, cmap=cmap, vmin=-0.5,
                  vmax=len(kinds) - 0.5, shading="nearest")  # fmt: skip
    for i, kind in enumerate(kinds):
        ax.plot([], [], "s", color=cmap(i), label=kind)
    ax.set_xlabel(f"initial eccentricity x of {result.joint} (µm)")
    ax.set_ylabel(f"initial eccentricity y of {result.joint} (µm)")
    ax.set_aspect("equal")
    ax.legend(loc="upper right", fontsize="small")
    return ax
