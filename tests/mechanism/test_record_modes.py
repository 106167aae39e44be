"""``simulate(record=...)``: full trajectory, response metrics, stroboscopic sections.

What is recorded must not change the integration: the output grid neither bounds the step
nor moves a step, the metrics are taken at every accepted state (and inside contact
steps), and section points are located on the integrator's dense output.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import mechanism
from mechanism.cli import app
from mechanism.core.record import METRICS, response_metrics
from tests.mechanism.scenes import rigid_paper

PERIOD = 0.4  # s, the paper scene at 150 rpm


@pytest.fixture(scope="module")
def scene():
    return rigid_paper()


@pytest.fixture(scope="module")
def full_fine(scene):
    """Three revolutions recorded in full at T/10000."""
    return mechanism.simulate(scene, revolutions=3, output_step=PERIOD / 10000)


@pytest.fixture(scope="module")
def sections(scene):
    return mechanism.simulate(scene, revolutions=3, record=mechanism.SectionsRecord(discard=1))


def test_peak_force_does_not_depend_on_the_output_step(scene, full_fine) -> None:
    metrics = mechanism.MetricsRecord(discard=1)
    fine = mechanism.simulate(scene, revolutions=3, record=metrics, output_step=PERIOD / 10000)
    coarse = mechanism.simulate(scene, revolutions=3, record=metrics, output_step=PERIOD / 100)
    peak_fine = float(fine["peak_contact_force"])
    peak_coarse = float(coarse["peak_contact_force"])
    assert peak_fine > 1000.0  # the journal impacts the bearing in every revolution
    np.testing.assert_allclose(peak_coarse, peak_fine, rtol=5e-3)
    # the same integration: the steps do not depend on the grid
    assert (
        coarse.attrs["solver_steps"]
        == fine.attrs["solver_steps"]
        == full_fine.attrs["solver_steps"]
    )
    # and the peak is that of the dense T/10000 samples of the full record (to 0.5 %)
    start = int(full_fine.time.searchsorted(PERIOD))
    sampled = response_metrics(full_fine, start)
    np.testing.assert_allclose(peak_fine, float(sampled["peak_contact_force"]), rtol=5e-3)
    np.testing.assert_allclose(
        float(fine["max_penetration"]), float(sampled["max_penetration"]), rtol=5e-3
    )
    # errors are compared on the output grid: the fine grid reproduces the full record's
    for name in ("max_displacement_error", "max_speed_error"):
        np.testing.assert_allclose(float(fine[name]), float(sampled[name]), rtol=1e-9)


def test_full_record_does_not_depend_on_the_output_grid(scene, full_fine) -> None:
    coarse = mechanism.simulate(scene, revolutions=3, output_step=PERIOD / 100)
    # the step limits (the approach floor is the scene's default output step) do not
    # depend on the grid asked for
    assert coarse.attrs["max_step"] == full_fine.attrs["max_step"] == math.inf
    assert coarse.attrs["approach_floor"] == full_fine.attrs["approach_floor"] == PERIOD / 10000
    fine = full_fine.isel(time=slice(None, None, 100))
    # the grids agree to round-off in time (0.004 k against 0.00004 (100 k))
    np.testing.assert_allclose(coarse.time.values, fine.time.values, rtol=0, atol=1e-15)
    # dense output of the same steps at the same instants: equal to round-off
    for name in ("eccentricity_x", "contact_force", "slider_position", "driving_torque"):
        scale = float(np.abs(fine[name]).max())
        np.testing.assert_allclose(coarse[name].values, fine[name].values, atol=1e-9 * scale)


def test_sections_are_located_on_the_dense_output(scene, sections, full_fine) -> None:
    assert sections.attrs["record"] == "sections"
    assert sections.attrs["section_kind"] == "stroboscopic"
    assert sections.drive_cycle.values.tolist() == [1, 2, 3]
    # the crank angle at a section is 2πk to round-off
    np.testing.assert_allclose(
        sections.crank_angle.values, 2 * np.pi * sections.drive_cycle.values, atol=1e-11
    )
    # a constant-speed drive crosses at t = kT (up to the Baumgarte-controlled drift)
    np.testing.assert_allclose(sections.time.values, PERIOD * np.arange(1, 4), atol=1e-9)
    # the same integration sampled on the fine grid at t = kT gives the same state
    at = full_fine.sel(time=sections.time.values, method="nearest")
    for name in ("eccentricity_x", "eccentricity_y"):
        np.testing.assert_allclose(
            sections[name].values, at[name].values, atol=1e-7 * 2.5e-4, rtol=0
        )
    # chaoskit's stroboscopic map of the fine record interpolates to the same points
    strobe = chaoskit.stroboscopic_map(
        full_fine[["eccentricity_x", "crank_angle"]].isel(joint=0),
        phase_variable="crank_angle",
    )
    strobe = strobe.isel(crossing=strobe.drive_cycle.values >= 1)
    np.testing.assert_allclose(
        sections.eccentricity_x.isel(joint=0).values,
        strobe.eccentricity_x.values,
        atol=1e-6 * 2.5e-4,
    )


def test_sections_carry_every_variable_and_the_metrics(sections) -> None:
    for name in ("eccentricity_x", "contact_force", "position", "slider_position"):
        assert sections[name].dims[0] == "crossing"
    assert "slider_position_ideal" not in sections
    for name, (units, long_name) in METRICS.items():
        assert sections[name].dims == ()
        assert sections[name].attrs == {"units": units, "long_name": long_name}
    diagram = chaoskit.bifurcation_diagram(
        [sections.isel(joint=0)], parameter="speed", variable="eccentricity_x", values=[150.0]
    )
    assert diagram.sizes["point"] == 3


def test_phase_moves_the_strobe(scene) -> None:
    quarter = mechanism.simulate(
        scene,
        revolutions=2,
        record=mechanism.SectionsRecord(phase=math.pi / 2),
        output_step=PERIOD / 10,
    )
    np.testing.assert_allclose(quarter.time.values, PERIOD * np.array([0.25, 1.25]), atol=1e-9)
    np.testing.assert_allclose(
        quarter.crank_angle.values, math.pi / 2 + 2 * np.pi * np.arange(2), atol=1e-11
    )


def test_the_initial_state_is_a_section_without_discard(scene) -> None:
    ds = mechanism.simulate(scene, revolutions=1, record="sections")
    assert ds.drive_cycle.values.tolist() == [0, 1]
    assert ds.time.values[0] == 0.0


def test_named_variables_are_the_full_record_values_without_the_companion(scene, full_fine) -> None:
    names = ("crank_angle", "eccentricity_x", "eccentricity_y", "slider_position")
    light = mechanism.simulate(
        scene,
        revolutions=3,
        output_step=PERIOD / 10000,
        record=mechanism.FullRecord(variables=[*names, "slider_velocity"]),
    )
    # the same steps, the same dense output at the same instants: equal to the last bit
    assert light.attrs["solver_steps"] == full_fine.attrs["solver_steps"]
    np.testing.assert_array_equal(light.time.values, full_fine.time.values)
    for name in (*names, "slider_velocity"):
        np.testing.assert_array_equal(light[name].values, full_fine[name].values)
        assert light[name].attrs["units"] == full_fine[name].attrs["units"]
        assert light[name].attrs["long_name"] == full_fine[name].attrs["long_name"]
    assert set(light.data_vars) == {*names, "slider_velocity"}
    assert light.joint.values.tolist() == ["C"]
    # the ideal companion does not run
    assert not any(key.startswith("ideal_solver_") for key in light.attrs)
    assert light.attrs["variables"].startswith("crank_angle, eccentricity_x")
    assert light.nbytes < full_fine.nbytes / 10


def test_without_the_companion_the_run_is_the_same_and_the_errors_are_nan(scene, sections):
    """``companion=False`` drops only the ideal mechanism: the run, its strobes and its own
    metrics are those with the companion, to the last bit; the errors against the ideal
    mechanism are NaN and the companion's statistics are absent."""
    alone = mechanism.simulate(
        scene, revolutions=3, record=mechanism.SectionsRecord(discard=1, companion=False)
    )
    assert alone.attrs["solver_steps"] == sections.attrs["solver_steps"]
    np.testing.assert_array_equal(alone.time.values, sections.time.values)
    np.testing.assert_array_equal(alone.eccentricity_x.values, sections.eccentricity_x.values)
    for name in ("peak_contact_force", "max_penetration", "driving_torque_extreme"):
        assert float(alone[name]) == float(sections[name])
    for name in ("max_displacement_error", "max_speed_error"):
        assert math.isfinite(float(sections[name])) and math.isnan(float(alone[name]))
    assert not any(key.startswith("ideal_") for key in alone.attrs)
    assert any(key.startswith("ideal_solver_") for key in sections.attrs)
    metrics = mechanism.simulate(
        scene, revolutions=2, record=mechanism.MetricsRecord(companion=False)
    )
    assert math.isnan(float(metrics["max_displacement_error"]))
    assert float(metrics["peak_contact_force"]) > 0.0


def test_named_variables_of_flexible_rods_are_the_full_record_values() -> None:
    """The journal of the paper scene sits on an ANCF rod: its eccentricity comes from the
    beam's nodal coordinates (a stale compiled loop once recorded it as a constant)."""
    scene = mechanism.load_scene("paper").replace({"solver.max_step": PERIOD / 10000})
    full = mechanism.simulate(scene, revolutions=0.1, output_step=PERIOD / 1000)
    light = mechanism.simulate(
        scene,
        revolutions=0.1,
        output_step=PERIOD / 1000,
        record=mechanism.FullRecord(variables=("eccentricity_x",)),
    )
    assert np.ptp(full["eccentricity_x"].values) > 1e-5
    np.testing.assert_array_equal(light["eccentricity_x"].values, full["eccentricity_x"].values)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (lambda: {"record": mechanism.FullRecord(variables=("position",))},
         "variables must be a non-empty list of names from"),
        (lambda: {"record": mechanism.FullRecord(variables="crank_angle")},
         "variables must be a non-empty list"),
        (lambda: {"record": mechanism.FullRecord(variables=())},
         "variables must be a non-empty list"),
        (lambda: {"record": mechanism.FullRecord(variables=("crank_angle",)), "method": "RK45"},
         "records the full trajectory only"),
        (lambda: {"record": "trajectory"}, "record must be one of"),
        (lambda: {"record": mechanism.MetricsRecord(discard=2)}, "discard must be below"),
        (lambda: {"record": mechanism.MetricsRecord(discard=-1)},
         "discard must be finite and >= 0"),
        (lambda: {"record": mechanism.SectionsRecord(phase=math.nan)},
         "phase must be a finite angle"),
        (lambda: {"record": "metrics", "method": "RK45"}, "records the full trajectory only"),
    ],
)  # fmt: skip
def test_bad_record_settings_raise(scene, kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        mechanism.simulate(scene, revolutions=2, **kwargs())


def test_named_variables_must_exist_in_the_scene() -> None:
    pendulum = mechanism.load_scene("slider-crank")
    with pytest.raises(ValueError, match=r"variables \['eccentricity_x'\] are not outputs"):
        mechanism.simulate(
            pendulum, revolutions=1, record=mechanism.FullRecord(variables=("eccentricity_x",))
        )


def test_command_line_records_sections(tmp_path) -> None:
    out = tmp_path / "strobe.nc"
    args = ["simulate", "slider-crank-clearance", "-o", str(out), "--revolutions", "3",
            "--record", "sections", "--discard", "1", "--no-progress"]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "3 sections" in result.output
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.drive_cycle.values.tolist() == [1, 2, 3]
    bad = CliRunner().invoke(app, [*args[:3], str(tmp_path / "strobe.csv"), *args[4:]])
    assert bad.exit_code == 2 and "netCDF" in bad.output


def test_options_of_other_modes_cannot_be_written() -> None:
    """The exclusions between keywords are gone: an option exists only on its mode."""
    for make, option in (
        (lambda: mechanism.FullRecord(discard=1), "discard"),
        (lambda: mechanism.FullRecord(companion=False), "companion"),
        (lambda: mechanism.MetricsRecord(variables=("crank_angle",)), "variables"),
        (lambda: mechanism.MetricsRecord(phase=0.5), "phase"),
    ):
        with pytest.raises(TypeError, match=f"unexpected keyword argument '{option}'"):
            make()
    mode = mechanism.SectionsRecord(phase=0.25, discard=1)
    with pytest.raises(AttributeError):
        mode.phase = 0.5  # type: ignore[misc]
    assert mode == mechanism.SectionsRecord(discard=1.0, phase=0.25)
    assert hash(mode) == hash(mechanism.SectionsRecord(discard=1.0, phase=0.25))


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: mechanism.MetricsRecord(discard=-1), "discard must be finite and >= 0; got -1."),
        (
            lambda: mechanism.SectionsRecord(discard=np.float64(math.inf)),
            "discard must be finite and >= 0; got inf.",
        ),
        (
            lambda: mechanism.SectionsRecord(phase=math.nan),
            "phase must be a finite angle in rad; got nan.",
        ),
        (
            lambda: mechanism.SectionsRecord(phase="0"),
            "phase must be a finite angle in rad; got '0'.",
        ),
        (
            lambda: mechanism.MetricsRecord(companion="no"),
            "companion must be True or False; got 'no'.",
        ),
        (
            lambda: mechanism.FullRecord(variables=("position",)),
            "variables must be a non-empty list of names from ['crank_angle', "
            "'slider_position', 'slider_velocity', 'eccentricity_x', 'eccentricity_y']; "
            "got ['position'].",
        ),
    ],
)
def test_a_record_object_checks_its_options(make, message) -> None:
    with pytest.raises(ValueError) as info:
        make()
    assert str(info.value) == message


def test_what_depends_on_the_scene_is_checked_before_the_run(scene) -> None:
    undriven = mechanism.load_scene("slider-crank").replace({"drive": None})
    for mode in (mechanism.MetricsRecord(), mechanism.SectionsRecord()):
        with pytest.raises(ValueError) as info:
            mechanism.simulate(undriven, t_end=0.05, record=mode)
        assert str(info.value) == (
            f"record={mode.name!r} needs a periodic drive (its revolutions and sections); "
            "use record='full'."
        )
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, revolutions=2, record=mechanism.SectionsRecord(discard=2))
    assert str(info.value) == "discard must be below the simulated 2 revolutions; got 2."


_LOOSE = "simulate() got an unexpected keyword argument {!r}; pass it in the record object: "


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"record": "sections", "discard": 1},
         _LOOSE.format("discard")
         + "record=MetricsRecord(discard=...) or record=SectionsRecord(discard=...)."),
        ({"record": mechanism.SectionsRecord(), "phase": 0.5},
         _LOOSE.format("phase") + "record=SectionsRecord(phase=...)."),
        ({"variables": ["crank_angle"]},
         _LOOSE.format("variables") + "record=FullRecord(variables=...)."),
        ({"record": "metrics", "companion": False},
         _LOOSE.format("companion")
         + "record=MetricsRecord(companion=...) or record=SectionsRecord(companion=...)."),
    ],
)  # fmt: skip
def test_a_record_option_given_as_a_keyword_names_its_record_object(scene, kwargs, message) -> None:
    """The record options live in the mode objects: as keywords of simulate they are a
    TypeError whose one line says which object takes them."""
    with pytest.raises(TypeError) as info:
        mechanism.simulate(scene, revolutions=2, **kwargs)
    assert str(info.value) == message
    with pytest.raises(TypeError) as info:
        mechanism.simulate(scene, revolutions=2, record="sections", phases=0.5)
    assert str(info.value) == "simulate() got an unexpected keyword argument 'phases'"


def test_a_mode_class_given_for_a_mode_object_is_refused(scene) -> None:
    with pytest.raises(ValueError) as info:
        mechanism.simulate(scene, revolutions=2, record=mechanism.SectionsRecord)
    assert str(info.value) == (
        "record must be a record mode object (FullRecord(), MetricsRecord(), "
        "SectionsRecord(), WearRecord()) or one of 'full', 'metrics', 'sections', 'wear'; "
        "got the class SectionsRecord."
    )


def test_simulate_takes_at_most_twelve_parameters() -> None:
    assert len(inspect.signature(mechanism.simulate).parameters) <= 12
