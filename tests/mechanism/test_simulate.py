"""mechanism.simulate: the output contract, integrators, failure as data, the CLI."""

from __future__ import annotations

import dataclasses
import doctest
import json
import math
import pickle
import re
import tracemalloc

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import mechanism
import mechanism.core._simulate
from mechanism.cli import app
from mechanism.core import _status as st
from mechanism.core.integrate import Dopri5, GeneralizedAlpha, ScipyIVP, resolve_method
from mechanism.core.integrate import _dopri_kernels as dk
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state
from tests.mechanism.scenes import rigid_paper, rotating_guide, s3

CLEARANCE_VARS = (
    "eccentricity_x",
    "eccentricity_y",
    "penetration",
    "contact_force",
    "friction_force",
    "contact_angle",
    "in_contact",
)
SLIDER_VARS = ("slider_position", "slider_velocity", "slider_acceleration")


@pytest.fixture(scope="module")
def paper_ds():
    return mechanism.simulate(rigid_paper(), revolutions=0.1)


def test_dataset_follows_the_data_contract(paper_ds) -> None:
    ds = paper_ds
    chaoskit.validate_trajectory(ds, require_uniform=True)
    assert ds.time.dtype == np.float64
    for name, var in ds.data_vars.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    for name in ("crank_angle", "driving_torque", "displacement_error", "speed_error"):
        assert ds[name].dims == ("time",)
    for name in SLIDER_VARS:
        assert ds[name].dims == ("time",) and ds[f"{name}_ideal"].dims == ("time",)
    for name in CLEARANCE_VARS:
        assert ds[name].dims == ("time", "joint")
    assert ds.position.dims == ("time", "body", "axis")
    assert list(ds.axis.values) == ["x", "y", "theta"]
    assert list(ds.joint.values) == ["C"]
    assert set(ds.body.values) == {"crank", "plate", "rod3", "rod4", "slider"}
    assert ds.joint_force.dims == ("time", "ideal_joint")
    for key in ("steps", "rejected_steps", "function_evaluations", "contact_events"):
        assert isinstance(ds.attrs[f"solver_{key}"], int)
    assert ds.attrs["solver_status"] == 0 and ds.attrs["solver_wall_time"] > 0
    assert ds.attrs["solver_message"]


def test_output_grid_defaults_to_a_ten_thousandth_of_the_period(paper_ds) -> None:
    period = 60.0 / 150.0
    assert chaoskit.sampling_interval(paper_ds) == pytest.approx(period / 10000, rel=1e-9)
    assert paper_ds.sizes["time"] == 1001
    assert paper_ds.attrs["output_step"] == pytest.approx(period / 10000)


def test_scene_attribute_round_trips(paper_ds) -> None:
    scene = mechanism.scene_from_json(paper_ds.attrs["scene"])
    assert scene == rigid_paper()
    assert json.loads(paper_ds.attrs["scene"])["name"] == "paper"


def test_crank_angle_and_driving_torque(paper_ds) -> None:
    ds = paper_ds
    w = 150 * 2 * math.pi / 60
    np.testing.assert_allclose(ds.crank_angle.values, w * ds.time.values, atol=1e-8)
    # T = −λ_drive is the torque the drive delivers: its power equals the rate of change of
    # the mechanism's energy (no dissipation except contact damping and friction)
    assert np.isfinite(ds.driving_torque.values).all()
    power = ds.driving_torque_ideal.values * w
    energy = ds.mechanical_energy.values
    assert ds.displacement_error.values[0] == pytest.approx(0.0, abs=1e-12)
    # the ideal mechanism conserves energy up to the drive's work
    dt = float(ds.time[1] - ds.time[0])
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * dt)])
    ideal = mechanism.simulate(rigid_paper({"effects.clearance": False}), revolutions=0.1)
    np.testing.assert_allclose(
        ideal.mechanical_energy.values - ideal.mechanical_energy.values[0], work, atol=2e-3
    )
    assert energy.shape == power.shape


def test_saved_trajectory_round_trips(tmp_path, paper_ds) -> None:
    path = chaoskit.save_trajectory(paper_ds, tmp_path / "run.nc")
    back = xr.open_dataset(path, engine="h5netcdf")
    np.testing.assert_array_equal(back.contact_force.values, paper_ds.contact_force.values)
    assert back.attrs["solver_steps"] == paper_ds.attrs["solver_steps"]


@pytest.mark.parametrize(
    "method",
    ["dopri5", "RK45", "DOP853", "Radau", "BDF", "LSODA", "generalized-alpha"],
)
def test_every_method_reproduces_the_rotating_guide(method) -> None:
    """A mechanism with a moving prismatic guide, a welded body, a profile drive and a
    pendulum: all integrators agree with a tight dopri5 reference."""
    scene = rotating_guide(clearance=False)
    kw = {"t_end": 0.2, "output_step": 0.01}
    ref = mechanism.simulate(scene, rtol=1e-11, atol=1e-11, **kw)
    tol = 1e-6 if method == "generalized-alpha" else 1e-8
    ds = mechanism.simulate(scene, method=method, rtol=tol, atol=tol, **kw)
    assert ds.attrs["solver_method"] == method
    assert ds.attrs["solver_status"] == 0
    err = np.abs(ds.position.values - ref.position.values).max()
    assert err < (1e-5 if method == "generalized-alpha" else 1e-6)
    assert np.abs(ds.slider_position.values - ref.slider_position.values).max() < 1e-5
    assert ds.constraint_violation.values.max() < 1e-6


def test_projection_removes_the_drift_that_no_stabilisation_leaves() -> None:
    """Without Baumgarte terms the constraints drift; projecting q and q̇ after each step
    leaves only the interpolation error of the dense output between steps."""
    base = rotating_guide(clearance=False).replace(
        {"solver.baumgarte_alpha": 0.0, "solver.baumgarte_beta": 0.0, "solver.max_step": 0.002}
    )
    kw = {"t_end": 0.2, "output_step": 0.01, "rtol": 1e-6, "atol": 1e-6}
    drift = mechanism.simulate(base, **kw).constraint_violation.values.max()
    ds = mechanism.simulate(base.replace({"solver.projection": True}), **kw)
    assert ds.attrs["projection"] == 1
    assert drift > 1e-7
    assert ds.constraint_violation.values.max() < 1e-10


def test_strategy_objects_and_names() -> None:
    assert isinstance(resolve_method("dopri5"), Dopri5)
    assert isinstance(resolve_method("generalized-alpha"), GeneralizedAlpha)
    assert resolve_method("LSODA") == ScipyIVP(method="LSODA")
    with pytest.raises(ValueError, match="method must be one of"):
        resolve_method("euler")
    with pytest.raises(ValueError, match="rho_inf"):
        GeneralizedAlpha(rho_inf=1.5)
    with pytest.raises(ValueError, match="method must be one of"):
        ScipyIVP(method="RK23")  # type: ignore[arg-type]


def test_failure_raises_or_becomes_data() -> None:
    scene = mechanism.load_scene("slider-crank")
    with pytest.raises(mechanism.SimulationError, match="maximum number of steps"):
        mechanism.simulate(scene, revolutions=1, method=Dopri5(max_steps=5))
    ds = mechanism.simulate(scene, revolutions=1, method=Dopri5(max_steps=5), throw=False)
    assert ds.attrs["solver_status"] < 0
    assert "maximum number of steps" in ds.attrs["solver_message"]
    assert 1 < ds.sizes["time"] < 10001
    chaoskit.validate_trajectory(ds)


def test_failure_names_the_time_it_stopped_whatever_is_recorded() -> None:
    """The message gives the integrator's time at the failure, also when only named
    variables are recorded (their grid is not the full record's)."""
    scene = mechanism.load_scene("slider-crank")
    times = []
    for variables in (None, ("crank_angle",)):
        with pytest.raises(mechanism.SimulationError) as err:
            mechanism.simulate(
                scene,
                revolutions=1,
                method=Dopri5(max_steps=8),
                record=mechanism.FullRecord(variables=variables),
            )
        found = re.search(r"failed after t = (\S+) s", str(err.value))
        assert found is not None, err.value
        np.testing.assert_allclose(err.value.time, float(found.group(1)), rtol=1e-5)
        again = pickle.loads(pickle.dumps(err.value))  # from a pool's process
        assert again.time == err.value.time and str(again) == str(err.value)
        times.append(err.value.time)
    assert times[0] > 0.0
    assert times[1] == times[0]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"revolutions": 1, "t_end": 0.1}, "either revolutions or t_end"),
        ({"revolutions": -1}, "revolutions"),
        ({"rtol": 0.0}, "rtol"),
        ({"output_step": 1.0, "t_end": 0.01}, "output_step"),
        ({"method": "euler"}, "method"),
    ],
)
def test_bad_arguments_raise_value_errors(kwargs, message) -> None:
    with pytest.raises(ValueError, match=message):
        mechanism.simulate(mechanism.load_scene("slider-crank"), **kwargs)


def test_scene_without_drive_needs_t_end() -> None:
    scene = mechanism.load_scene("slider-crank").replace({"drive": None})
    with pytest.raises(ValueError, match="t_end"):
        mechanism.simulate(scene, revolutions=2)
    ds = mechanism.simulate(scene, t_end=0.05, output_step=0.001)
    # released at rest, the mechanism falls under gravity: no driving torque output
    assert "driving_torque" not in ds and ds.sizes["time"] == 51


def test_progress_bar_is_opt_in(capsys) -> None:
    scene = mechanism.load_scene("slider-crank")
    mechanism.simulate(scene, revolutions=0.05)
    assert capsys.readouterr().err == ""
    mechanism.simulate(scene, revolutions=0.05, progress=True)
    assert "100%" in capsys.readouterr().err


def test_ideal_companion_and_errors() -> None:
    ds = mechanism.simulate(s3(friction=0.1), t_end=0.004, output_step=1e-5)
    np.testing.assert_allclose(
        ds.displacement_error.values,
        ds.slider_position.values - ds.slider_position_ideal.values,
    )
    rigid = mechanism.simulate(mechanism.load_scene("slider-crank"), t_end=0.004, output_step=1e-5)
    np.testing.assert_allclose(
        ds.slider_position_ideal.values, rigid.slider_position.values, atol=1e-9
    )
    # the journal can move at most the clearance away from the ideal position
    assert np.abs(ds.displacement_error.values).max() < 2 * 5e-4
    assert np.abs(ds.displacement_error.values).max() > 1e-5
    assert ds.attrs["ideal_solver_contact_evaluations"] == 0


def test_cli_simulate_writes_a_trajectory(tmp_path) -> None:
    out = tmp_path / "sc.nc"
    result = CliRunner().invoke(
        app,
        [
            "simulate",
            "slider-crank-clearance",
            "--revolutions",
            "0.5",
            "--set",
            "drive.speed_rpm=1000",
            "--output-step",
            "1e-4",
            "--no-progress",
            "-o",
            str(out),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "contact events" in result.output
    ds = chaoskit.load_trajectory(out)
    assert ds.sizes["time"] == 301
    assert mechanism.scene_from_json(ds.attrs["scene"]).drive.speed_rpm == 1000


def test_cli_reports_bad_values(tmp_path) -> None:
    result = CliRunner().invoke(
        app, ["simulate", "slider-crank", "--rtol", "-1", "-o", str(tmp_path / "x.nc")]
    )
    assert result.exit_code == 2  # a user error
    assert result.stderr == "Error: rtol must be finite and > 0; got -1.0.\n"


def test_docstring_examples_run() -> None:
    failures, _ = doctest.testmod(mechanism.core._simulate, raise_on_error=False)
    assert failures == 0
    failures, _ = doctest.testmod(mechanism.core.integrate._methods, raise_on_error=False)
    assert failures == 0


def test_paper_scene_runs_three_revolutions_with_kilonewton_contact_forces() -> None:
    """Rigid rods, clearance at C, 150 rpm, other scene defaults (the published study reports
    9.18 kN before wear with flexible rods)."""
    ds = mechanism.simulate(rigid_paper(), revolutions=3)
    assert ds.attrs["solver_status"] == 0 and ds.attrs["revolutions"] == pytest.approx(3.0)
    late = ds.isel(time=slice(10000, None))  # discard the first revolution
    peak = float(late.contact_force.max())
    assert 1e3 < peak < 3e4
    clearance = 2e-4
    assert 0 < float(late.penetration.max()) < 0.5 * clearance
    assert ds.attrs["solver_contact_events"] > 3
    assert float(late.in_contact.mean()) > 0.5
    # Baumgarte keeps the drift at the error control's level (rtol = atol = 1e-5; steps
    # bounded only near contact: 2.1e-7 m measured), well below the clearance
    assert ds.constraint_violation.values.max() < 5e-3 * clearance
    assert np.abs(late.driving_torque.values).max() > 10.0


def test_one_status_table_for_the_model_kernels_and_the_time_loops() -> None:
    codes = [getattr(st, name) for name in st.__all__ if name.startswith("STATUS_")]
    assert len(set(codes)) == len(codes) == 9 and set(st.MESSAGES) == set(codes)
    # failures are negative; OK, RUNNING and a reduced (still applied) wear increment are not
    not_failures = (st.STATUS_OK, st.STATUS_RUNNING, st.STATUS_REDUCED)
    assert all(c < 0 for c in codes if c not in not_failures)
    model = assemble(mechanism.load_scene("slider-crank"))
    q, v = initial_state(model)
    y = np.concatenate([q, v])
    y[0] = np.nan  # a non-finite state: the model kernel and the loop report the same code
    counters = np.zeros(k.CNT_COLUMNS, dtype=np.int64)
    vimp = np.zeros(0)
    acc = np.zeros(model.n_dof)
    ws = model.workspace()
    n = model.n_dof
    assert k.accelerations(model.kernel, ws, 0.0, y[:n], y[n:], vimp, acc, counters) == (
        st.STATUS_NONFINITE
    )
    k1, state, y1, f1 = np.zeros_like(y), np.zeros(4), np.zeros_like(y), np.zeros_like(y)
    status = dk.dopri5_start(
        model.kernel, ws, 0.0, y, k1, vimp, state, counters, 1e-6, 1e-8, 1e-3, y1, f1
    )
    assert status == st.STATUS_NONFINITE


# --- runs refused before they start ------------------------------------------------------


@pytest.mark.parametrize(
    ("changes", "kwargs", "message"),
    [
        # "Maximum allowed size exceeded" from numpy before
        (
            {"solver.output_step": 1e-300},
            {},
            "the output grid would hold 1.2e+298 samples (revolutions = 1 at "
            "drive.speed_rpm = 5000, 0.012 s, at solver.output_step = 1e-300 s), more than "
            "the 2e+08 steps an integrator may take (max_steps; each sample costs about a "
            "step): raise solver.output_step (or pass output_step, --output-step), or "
            "simulate less time.",
        ),
        # a MemoryError traceback (a 74.5 GiB output grid) before
        (
            {},
            {"revolutions": 1e6},
            "the output grid would hold 1e+10 samples (revolutions = 1e+06 at "
            "drive.speed_rpm = 5000, 1.2e+04 s, at the default output step (drive period / "
            "10000) = 1.2e-06 s), more than the 2e+08 steps",
        ),
        (
            {},
            {"t_end": 1e4, "output_step": 1e-5},
            "the output grid would hold 1e+09 samples (t_end = 10000 s, 1e+04 s, at "
            "output_step = 1e-05 s)",
        ),
        (
            {"solver.max_step": 1e-12},
            {"record": "metrics"},
            "the run would take at least 1.2e+10 steps (revolutions = 1 at drive.speed_rpm = "
            "5000, 0.012 s, at solver.max_step = 1e-12 s), more than the 2e+08 an integrator "
            "may take (max_steps): it would fail after hours; raise solver.max_step, or "
            "simulate less time.",
        ),
    ],
)
def test_absurd_step_counts_are_refused_before_the_run(changes, kwargs, message) -> None:
    scene = mechanism.load_scene("slider-crank-clearance").replace(changes)
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, **kwargs)
    assert str(info.value).startswith(message), str(info.value)
    assert "\n" not in str(info.value)


class _Memory:
    def __init__(self, available: float) -> None:
        self.available = int(available)


def test_a_run_larger_than_the_memory_is_refused_before_allocating(monkeypatch) -> None:
    # the rigid paper scene over 3000 revolutions at the default grid: about 62.9 GB,
    # which a 23 GB machine only warned about and then ran out of memory
    monkeypatch.setattr(mechanism.core._simulate.psutil, "virtual_memory", lambda: _Memory(16e9))
    rigid = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    tracemalloc.start()
    try:
        with pytest.raises(ValueError) as info:
            mechanism.simulate(rigid, revolutions=3000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6  # the estimate allocates nothing of the run's size
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(
        "this run would hold about 62.9 GB (3e+07 samples of the full record at the "
        "default output step (drive period / 10000) = 4e-05 s, revolutions = 3000 at "
        "drive.speed_rpm = 150), more than the 12.8 GB it may use (80% of the 16 GB of "
        "memory available); what fits: output_step >= 0.0002 s (--output-step); "
        "record=FullRecord(variables=['crank_angle', 'slider_position', 'slider_velocity', "
        "'eccentricity_x', 'eccentricity_y']) (--var; light samples only); record='metrics' or "
        "'sections' "
        "(--record); force=True (--force) runs it anyway."
    ), text


def test_force_runs_a_run_larger_than_the_memory(monkeypatch) -> None:
    monkeypatch.setattr(mechanism.core._simulate.psutil, "virtual_memory", lambda: _Memory(1e5))
    scene = mechanism.load_scene("slider-crank-clearance")
    with pytest.raises(ValueError, match=r"^this run would hold about 0\.689 MB \(501 samples"):
        mechanism.simulate(scene, revolutions=0.05)
    ds = mechanism.simulate(scene, revolutions=0.05, force=True)
    assert ds.sizes["time"] == 501 and bool(np.isfinite(ds.slider_position).all())
    # the light record of a few variables holds far less: it fits
    light = mechanism.simulate(
        scene, revolutions=0.05, record=mechanism.FullRecord(variables=["slider_position"])
    )
    assert light.sizes["time"] == 501


def test_a_scene_built_in_python_is_validated_by_simulate() -> None:
    # a mass of 1e300 kg was run and reported as a singular constraint Jacobian
    scene = mechanism.load_scene("slider-crank")
    heavy = dataclasses.replace(
        scene,
        bodies={**scene.bodies, "crank": dataclasses.replace(scene.bodies["crank"], mass=1e300)},
    )
    with pytest.raises(mechanism.SceneError, match=r"^bodies\.crank\.mass: must be in \[1e-06"):
        mechanism.simulate(heavy, revolutions=0.01)


def test_messages_show_numpy_numbers_as_plain_numbers() -> None:
    scene = mechanism.load_scene("slider-crank")
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, revolutions=np.float64(29.990000000000002),
                           record=mechanism.MetricsRecord(discard=np.float64(30.5)))  # fmt: skip
    assert str(info.value) == "discard must be below the simulated 29.99 revolutions; got 30.5."
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, revolutions=np.float64(-1.0))
    assert "np.float64" not in str(info.value)
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, t_end=np.float64(0.01), output_step=np.float64(0.02))
    assert str(info.value) == "output_step (0.02 s) must not exceed the simulated time (0.01 s)."
