"""Raw integrator arrays → a trajectory :class:`xarray.Dataset` (the package's one
labelled-data boundary).

The Dataset follows the data contract (``docs/data-model.md``): a float64 ``time``
coordinate in seconds, every variable with ``units`` and ``long_name``, the global
attributes of :func:`chaoskit.contract.stamp`, the resolved scene as JSON in ``scene`` and
the solver statistics as ``solver_*`` attributes (``ideal_solver_*`` for the ideal
mechanism run alongside). Variables are listed in ``docs/simulator.md``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import __version__, stamp, variable
from mechanism.core.integrate import Integration, Recording
from mechanism.core.integrate import kernels as integrate_kernels
from mechanism.core.model import Model
from mechanism.core.model import kernels as model_kernels

from ._film import film_variables
from ._metrics import METRICS

__all__ = ["LIGHT_VARIABLES", "light_dataset", "metrics_dataset", "sections_dataset", "to_dataset"]

_AXES = ("x", "y", "theta")

#: Variables a full record can hold alone (``FullRecord(variables=...)``): read from
#: the light samples, positions and velocities only.
LIGHT_VARIABLES: tuple[str, ...] = (
    "crank_angle",
    "slider_position",
    "slider_velocity",
    "eccentricity_x",
    "eccentricity_y",
)


def _body_block(model: Model, values: np.ndarray) -> np.ndarray:
    """(N, n_rigid, 3) slice of a (N, n) coordinate array for the rigid bodies."""
    offsets = dict(zip(model.body_names, model.body_offsets, strict=True))
    idx = np.array([[offsets[b] + j for j in range(3)] for b in model.rigid_bodies], dtype=int)
    return values[:, idx] if idx.size else np.zeros((values.shape[0], 0, 3))


def _common(model: Model, rec: Recording, suffix: str, label: str) -> dict[str, xr.Variable]:
    out: dict[str, xr.Variable] = {}
    if model.rigid_bodies:
        out[f"position{suffix}"] = variable(
            ("time", "body", "axis"),
            _body_block(model, rec.q),
            "m (x, y), rad (theta)",
            f"centre-of-mass position and angle of each rigid body{label}",
        )
        out[f"velocity{suffix}"] = variable(
            ("time", "body", "axis"),
            _body_block(model, rec.v),
            "m s-1 (x, y), rad s-1 (theta)",
            f"centre-of-mass velocity and angular velocity of each rigid body{label}",
        )
    if model.slider is not None:
        out[f"slider_position{suffix}"] = variable(
            ("time",),
            rec.out[:, model_kernels.OUT_S],
            "m",
            f"slider position along its guide{label}",
        )
        out[f"slider_velocity{suffix}"] = variable(
            ("time",),
            rec.out[:, model_kernels.OUT_SD],
            "m s-1",
            f"slider velocity along its guide{label}",
        )
        out[f"slider_acceleration{suffix}"] = variable(
            ("time",),
            rec.out[:, model_kernels.OUT_SDD],
            "m s-2",
            f"slider acceleration along its guide{label}",
        )
    if model.drive_row is not None:
        out[f"driving_torque{suffix}"] = variable(
            ("time",),
            -rec.lam[:, model.drive_row],
            "N m",
            f"driving torque of the drive joint (T = -lambda_drive){label}",
        )
    return out


def _beam_outputs(model: Model, rec: Recording) -> tuple[dict[str, xr.Variable], dict[str, Any]]:
    """Axial strain along every ANCF beam, its signed extreme and the mid-span deflection.

    Stations are the nodes and element mid-points (the accurate points of the
    gradient-deficient element's axial strain, docs/ancf.md §6.7) as fractions s/L of
    each rod's length; rods with different element counts share the stations of the
    finest mesh.
    """
    names = tuple(model.beams)
    offsets = dict(zip(model.body_names, model.body_offsets, strict=True))
    n_el = max(lay.mesh.n_elements for lay in model.beams.values())
    fraction = np.linspace(0.0, 1.0, 2 * n_el + 1)
    strain = np.empty((rec.q.shape[0], len(names), fraction.size))
    deflection = np.empty((rec.q.shape[0], len(names)))
    arc = np.empty((len(names), fraction.size))
    out: dict[str, xr.Variable] = {}
    for b, name in enumerate(names):
        mesh = model.beams[name].mesh
        arc[b] = fraction * mesh.length
        strain[:, b] = mesh.axial_strain_history(rec.q, arc[b], offset=offsets[name])
        deflection[:, b] = mesh.midspan_deflection_history(rec.q, offset=offsets[name])
        flat = strain[:, b].reshape(-1)
        extreme = float(flat[np.argmax(np.abs(flat))]) if flat.size else float("nan")
        out[f"strain_{name}"] = variable(
            (),
            np.array(1e6 * extreme),
            "1e-6",
            f"signed extreme axial strain of {name} over time and stations "
            "(micro-strain, positive = tension)",
        )
    out["strain"] = variable(
        ("time", "rod", "station"),
        strain,
        "1",
        "axial strain along each flexible rod (|r,x| - 1 or the Green strain)",
    )
    out["midspan_deflection"] = variable(
        ("time", "rod"),
        deflection,
        "m",
        "distance of the rod's mid-point from the chord of its end nodes, positive to the left",
    )
    coords = {
        "rod": ("rod", np.array(names, dtype=object)),
        "station": (
            "station",
            fraction,
            {"units": "1", "long_name": "arc length along the rod over its length (s/L)"},
        ),
        "arc_length": (
            ("rod", "station"),
            arc,
            {"units": "m", "long_name": "unstressed arc length along the rod"},
        ),
    }
    return out, coords


def to_dataset(
    model: Model,
    run: Integration,
    ideal_model: Model,
    ideal_run: Integration | None,
    *,
    attrs: dict[str, Any] | None = None,
    sections: bool = False,
) -> xr.Dataset:
    """Build the trajectory Dataset of a simulation and its ideal-mechanism companion.

    Both recordings must share the output grid (the shorter one sets the length). With
    ``sections``, the run's section samples instead, without the ideal twins (the
    companion's statistics are still attached); the dimension is still ``time``.
    """
    if sections:
        assert run.sections is not None
        rec = run.sections
        irec = None
    else:
        assert ideal_run is not None, "the full record needs the ideal companion"
        rec = run.recording
        n = min(rec.t.size, ideal_run.recording.t.size)
        rec = rec.head(n)
        irec = ideal_run.recording.head(n)
    data: dict[str, xr.Variable] = crank_angle_variable(model, rec)
    data.update(_common(model, rec, "", ""))
    if irec is not None:
        data.update(_common(ideal_model, irec, "_ideal", " (ideal mechanism)"))
    if "slider_position" in data and "slider_position_ideal" in data:
        data["displacement_error"] = variable(
            ("time",),
            data["slider_position"].values - data["slider_position_ideal"].values,
            "m",
            "slider position minus that of the ideal mechanism",
        )
        data["speed_error"] = variable(
            ("time",),
            data["slider_velocity"].values - data["slider_velocity_ideal"].values,
            "m s-1",
            "slider velocity minus that of the ideal mechanism",
        )
    if model.ideal_joints:
        fx = rec.jf[:, :, 0]
        fy = rec.jf[:, :, 1]
        dims = ("time", "ideal_joint")
        data["joint_force"] = variable(
            dims, np.hypot(fx, fy), "N", "magnitude of the reaction force of each ideal joint"
        )
        data["joint_force_x"] = variable(
            dims, fx, "N", "reaction force on the joint's second body, x component"
        )
        data["joint_force_y"] = variable(
            dims, fy, "N", "reaction force on the joint's second body, y component"
        )
    if model.clearance_joints:
        cj = rec.cj
        dims = ("time", "joint")
        delta = cj[:, :, model_kernels.CJ_DELTA]
        data["eccentricity_x"] = variable(
            dims, cj[:, :, model_kernels.CJ_EX], "m", "journal centre minus bearing centre, x"
        )
        data["eccentricity_y"] = variable(
            dims, cj[:, :, model_kernels.CJ_EY], "m", "journal centre minus bearing centre, y"
        )
        data["penetration"] = variable(
            dims, np.maximum(delta, 0.0), "m", "penetration depth max(|e| - c, 0)"
        )
        data["contact_force"] = variable(
            dims, cj[:, :, model_kernels.CJ_FN], "N", "normal contact force"
        )
        data["friction_force"] = variable(
            dims,
            cj[:, :, model_kernels.CJ_FT],
            "N",
            "friction force on the journal along the tangent",
        )
        data["contact_angle"] = variable(
            dims,
            cj[:, :, model_kernels.CJ_PHI_B],
            "rad",
            "direction of the eccentricity in the bearing frame",
        )
        data["contact_angle_journal"] = variable(
            dims,
            cj[:, :, model_kernels.CJ_PHI_J],
            "rad",
            "direction of the eccentricity in the journal frame",
        )
        data["penetration_velocity"] = variable(
            dims,
            cj[:, :, model_kernels.CJ_DELTA_DOT],
            "m s-1",
            "rate of |e| - c (positive approaching)",
        )
        data["sliding_velocity"] = variable(
            dims,
            cj[:, :, model_kernels.CJ_VT],
            "m s-1",
            "tangential velocity of the journal contact point",
        )
        data["in_contact"] = variable(
            dims, (delta > 0.0).astype(np.int8), "1", "journal touches the bearing (1) or not (0)"
        )
    if model.beams:
        strain_vars, strain_coords = _beam_outputs(model, rec)
        data.update(strain_vars)
    # the oil film of the lubricated joints (nothing for a dry scene)
    film_vars, film_coords = film_variables(model, rec.q, rec.v)
    data.update(film_vars)
    data["mechanical_energy"] = variable(
        ("time",),
        rec.out[:, model_kernels.OUT_ENERGY],
        "J",
        "kinetic + gravity + contact potential + beam strain energy + energy stored by "
        "the force elements",
    )
    data["constraint_violation"] = variable(
        ("time",),
        rec.out[:, model_kernels.OUT_VIOLATION],
        "m",
        "largest constraint residual |Phi| (angle rows in rad)",
    )
    coords: dict[str, Any] = {
        "time": ("time", rec.t.astype(np.float64), {"units": "s", "long_name": "time"}),
        "axis": ("axis", np.array(_AXES, dtype=object)),
    }
    coords["body"] = ("body", np.array(model.rigid_bodies, dtype=object))
    if model.clearance_joints:
        coords["joint"] = ("joint", np.array(model.clearance_joints, dtype=object))
    if model.ideal_joints:
        coords["ideal_joint"] = (
            "ideal_joint",
            np.array([j.name for j in model.ideal_joints], dtype=object),
        )
    if model.beams:
        coords.update(strain_coords)
    coords.update(film_coords)
    return _finish(xr.Dataset(data, coords=coords), model, run, ideal_run, attrs)


def light_dataset(
    model: Model,
    run: Integration,
    t_out: np.ndarray,
    variables: tuple[str, ...],
    *,
    attrs: dict[str, Any] | None = None,
) -> xr.Dataset:
    """The ``variables`` (names of :data:`LIGHT_VARIABLES`) of a run recorded with light
    grid samples, on the output grid, with the units and names of :func:`to_dataset`."""
    light = run.light
    assert light is not None
    n = light.shape[0]
    n_cj = len(model.clearance_joints)
    ecc = light[:, model_kernels.LIGHT_COLUMNS : model_kernels.LIGHT_COLUMNS + 2 * n_cj]
    made = {
        "crank_angle": lambda: variable(
            ("time",),
            light[:, 0],
            "rad",
            "crank angle (relative angle of the crank joint, unwrapped)",
        ),
        "slider_position": lambda: variable(
            ("time",), light[:, 1], "m", "slider position along its guide"
        ),
        "slider_velocity": lambda: variable(
            ("time",), light[:, 2], "m s-1", "slider velocity along its guide"
        ),
        "eccentricity_x": lambda: variable(
            ("time", "joint"), ecc[:, 0::2], "m", "journal centre minus bearing centre, x"
        ),
        "eccentricity_y": lambda: variable(
            ("time", "joint"), ecc[:, 1::2], "m", "journal centre minus bearing centre, y"
        ),
    }
    data = {name: made[name]() for name in variables}
    coords: dict[str, Any] = {
        "time": ("time", t_out[:n].astype(np.float64), {"units": "s", "long_name": "time"})
    }
    if any(data[name].dims == ("time", "joint") for name in data):
        coords["joint"] = ("joint", np.array(model.clearance_joints, dtype=object))
    return _finish(xr.Dataset(data, coords=coords), model, run, None, attrs)


def _finish(
    ds: xr.Dataset,
    model: Model,
    run: Integration,
    ideal_run: Integration | None,
    attrs: dict[str, Any] | None,
) -> xr.Dataset:
    """The scene, the solver statistics (the ideal companion's when it ran), ``attrs``
    and the data contract's stamp."""
    ds.attrs["scene"] = model.scene.to_json()
    ds.attrs["scene_name"] = model.scene.name
    _mark_roles(ds)
    ds.attrs.update(run.stats.as_attrs("solver_"))
    if ideal_run is not None:
        ds.attrs.update(ideal_run.stats.as_attrs("ideal_solver_"))
    if attrs:
        ds.attrs.update(attrs)
    return stamp(
        ds,
        title=f"mechanism simulation of scene {model.scene.name!r}",
        source=f"mechanism (chaoskit {__version__})",
        history=f"mechanism.simulate({model.scene.name!r}, method={run.stats.method!r})",
    )


def crank_angle_variable(model: Model, rec: Recording) -> dict[str, xr.Variable]:
    """``{"crank_angle": ...}`` of a recording, or ``{}`` when the scene has no crank."""
    if model.crank_points is None:
        return {}
    return {
        "crank_angle": variable(
            ("time",),
            rec.out[:, model_kernels.OUT_CRANK],
            "rad",
            "crank angle (relative angle of the crank joint, unwrapped)",
        )
    }


def finish_dataset(
    ds: xr.Dataset, model: Model, run: Integration, attrs: dict[str, Any] | None
) -> xr.Dataset:
    """``ds`` of a run without an ideal companion, finished as every record mode's
    Dataset: the scene, the solver statistics, ``attrs`` and the data contract's stamp."""
    return _finish(ds, model, run, None, attrs)


#: The series that describe the motion, in order of preference: the journal centres of the
#: clearance joints, else the slider.
_MOTION_CHOICES = (("eccentricity_x", "eccentricity_y"), ("slider_position",))


def _mark_roles(ds: xr.Dataset) -> None:
    """Tell an analysis which series are the motion and which are auxiliary.

    ``motion_variables`` (file attribute) lists the series an analysis takes by default,
    ``phase_variable`` names the drive angle, and ``coverage_content_type`` (ACDD) marks
    the ideal-mechanism copies, the errors against them and the solver's residual as
    auxiliary, so that ``chaoskit analyze`` of a run analyses the motion, not every copy.
    """
    for names in _MOTION_CHOICES:
        if all(n in ds.data_vars for n in names):
            ds.attrs["motion_variables"] = " ".join(names)
            break
    if "crank_angle" in ds.data_vars:
        ds.attrs["phase_variable"] = "crank_angle"
    for name, var in ds.data_vars.items():
        if str(name).endswith("_ideal") or name in ("displacement_error", "speed_error"):
            var.attrs["coverage_content_type"] = "referenceInformation"
        elif name in ("constraint_violation", "mechanical_energy"):
            var.attrs["coverage_content_type"] = "qualityInformation"


def _metric(name: str, value: float) -> xr.Variable:
    units, long_name = METRICS[name]
    return variable((), np.array(value, dtype=np.float64), units, long_name)


def metrics_dataset(
    model: Model,
    run: Integration,
    ideal_run: Integration | None,
    t_out: np.ndarray,
    *,
    window: float,
    attrs: dict[str, Any] | None = None,
) -> xr.Dataset:
    """The response metrics (``mechanism._metrics.METRICS``) of a run recorded with
    running extremes and light grid samples, over the time from ``window`` on.

    Peak contact force, penetration and driving torque are the extremes over every
    accepted integrator state; the slider errors compare the light samples of the run and
    its ideal companion on the output grid ``t_out`` (NaN without a companion). NaN where
    not simulated.
    """
    assert run.metrics is not None
    met = run.metrics
    nan = math.nan
    data: dict[str, xr.Variable] = {}
    touching = bool(model.clearance_joints) and math.isfinite(met[integrate_kernels.MET_FN])
    data["peak_contact_force"] = _metric(
        "peak_contact_force", met[integrate_kernels.MET_FN] if touching else nan
    )
    data["max_penetration"] = _metric(
        "max_penetration", max(met[integrate_kernels.MET_DELTA], 0.0) if touching else nan
    )
    disp = speed = nan
    light = run.light
    ideal = None if ideal_run is None else ideal_run.light
    if model.slider is not None and light is not None and ideal is not None:
        n = min(light.shape[0], ideal.shape[0])
        keep = np.flatnonzero(t_out[:n] >= window * (1.0 - 1e-12))
        if keep.size:
            disp = float(np.max(np.abs(light[keep, 1] - ideal[keep, 1])))
            speed = float(np.max(np.abs(light[keep, 2] - ideal[keep, 2])))
    data["max_displacement_error"] = _metric("max_displacement_error", disp)
    data["max_speed_error"] = _metric("max_speed_error", speed)
    high, low = met[integrate_kernels.MET_TORQUE_MAX], met[integrate_kernels.MET_TORQUE_MIN]
    torque = nan
    if model.drive_row is not None and math.isfinite(high):
        torque = high if abs(high) >= abs(low) else low
    data["driving_torque_extreme"] = _metric("driving_torque_extreme", torque)
    return _finish(xr.Dataset(data), model, run, ideal_run, attrs)


def sections_dataset(
    model: Model,
    run: Integration,
    ideal_run: Integration | None,
    *,
    metrics: xr.Dataset,
    phase: float,
    attrs: dict[str, Any] | None = None,
) -> xr.Dataset:
    """The run's stroboscopic samples along ``crossing`` (coordinates ``time`` and
    ``drive_cycle`` k, where the crank angle is ``phase`` + 2πk), with the ``metrics``.

    The layout is that of :func:`chaoskit.stroboscopic_map`, so the result goes straight
    into :func:`chaoskit.bifurcation_diagram`.
    """
    ds = to_dataset(model, run, model, ideal_run, attrs=attrs, sections=True)
    ds = ds.rename_dims({"time": "crossing"})
    if "crank_angle" in ds:
        angle = np.asarray(ds["crank_angle"].values, dtype=np.float64)
        cycles = np.rint((angle - phase) / (2.0 * math.pi)).astype(np.int64)
    else:
        cycles = np.arange(ds.sizes["crossing"], dtype=np.int64)
    ds = ds.assign_coords(
        drive_cycle=("crossing", cycles, {"units": "1", "long_name": "drive cycle k"})
    )
    for name, var in metrics.data_vars.items():
        ds[name] = var
    ds.attrs.update(
        {"section_kind": "stroboscopic", "phase_variable": "crank_angle", "drive_phase": phase}
    )
    return ds
