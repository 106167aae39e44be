"""``mechanism.bifurcation``: orbit diagrams on the sweep machinery, the figure, the CLI."""

from __future__ import annotations

import inspect

import matplotlib
import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import mechanism
import mechanism.studies._orbit_diagram as bif
from mechanism.cli import app

matplotlib.use("Agg")

SCENE = "slider-crank-clearance"
SPEEDS = [3000.0, 5000.0]


def _speeds(store, **kwargs):
    """The slider-crank's orbit diagram over crank speed, in this process."""
    settings = {"values": SPEEDS, "revolutions": 5, "discard": 2, **kwargs}
    return mechanism.bifurcation(
        SCENE, parameter="drive.speed_rpm", client="serial", store=store, **settings
    )


@pytest.fixture(scope="module")
def diagram(tmp_path_factory):
    store = tmp_path_factory.mktemp("bifurcation")
    return _speeds(store), store


def test_points_are_those_of_a_sections_run(diagram) -> None:
    ds, _ = diagram
    assert ds.eccentricity.dims == ("drive.speed_rpm", "crossing", "joint")
    assert ds.crossing.values.tolist() == [2, 3, 4, 5]
    assert ds["drive.speed_rpm"].values.tolist() == SPEEDS
    assert ds.eccentricity.attrs["units"] == "m"
    assert (ds.status.values == "ok").all()
    scene = mechanism.load_scene(SCENE).replace({"drive.speed_rpm": SPEEDS[1]})
    alone = mechanism.simulate(
        scene, revolutions=5, record=mechanism.SectionsRecord(discard=2), rtol=1e-7, atol=1e-7
    )  # the orbit diagram's tolerance, not the scene's
    expected = np.hypot(alone.eccentricity_x.values, alone.eccentricity_y.values)
    np.testing.assert_array_equal(ds.eccentricity.isel({"drive.speed_rpm": 1}).values, expected)
    np.testing.assert_array_equal(ds.time.isel({"drive.speed_rpm": 1}).values, alone.time.values)
    assert float(ds.peak_contact_force[1]) == float(alone.peak_contact_force)
    # the journal stays inside clearance + penetration
    clearance = scene.joints["B"].clearance
    assert np.all(ds.eccentricity.values < 1.5 * clearance)


def test_a_rerun_resumes_from_the_store(diagram) -> None:
    ds, store = diagram
    again = _speeds(store)
    assert "0 to run, 2 already done" in again.attrs["history"]
    np.testing.assert_array_equal(again.eccentricity.values, ds.eccentricity.values)
    with pytest.raises(mechanism.SweepStoreMismatch):
        _speeds(store, discard=1)


def test_a_failing_value_is_data(tmp_path, monkeypatch) -> None:
    def diverging(scene, **kwargs):
        if scene.drive.speed_rpm < 0:
            raise mechanism.SimulationError("the solution became non-finite")
        return mechanism.simulate(scene, **kwargs)

    monkeypatch.setattr(bif, "simulate", diverging)
    ds = _speeds(
        tmp_path, values=[-4000.0, 4000.0], revolutions=3, discard=1,
        variables=("eccentricity_x", "contact_force"),
    )  # fmt: skip
    assert ds.status.values.tolist() == ["failed", "ok"]
    assert "non-finite" in str(ds.message.values[0])
    assert np.isnan(ds.eccentricity_x.values[0]).all()
    assert np.isfinite(ds.eccentricity_x.values[1]).all()
    assert ds.contact_force.dims == ("drive.speed_rpm", "crossing", "joint")
    axes = mechanism.plot_bifurcation(ds)
    assert len(axes) == 1 and "1 failed" in axes[0].get_title()


def test_the_settings_reach_each_value_as_a_sections_record(tmp_path, monkeypatch) -> None:
    """Phase, transient and tolerances reach ``simulate`` as one ``SectionsRecord``
    without the ideal companion, and the points keep the phase."""
    seen = []

    def spy(scene, **kwargs):
        seen.append(kwargs)
        return mechanism.simulate(scene, **kwargs)

    monkeypatch.setattr(bif, "simulate", spy)
    settings = mechanism.BifurcationSettings(phase=0.5, rtol=1e-6, atol=1e-6)
    ds = _speeds(tmp_path, values=[3000.0], revolutions=3, discard=1, settings=settings)
    (kwargs,) = seen
    assert set(kwargs) == {"revolutions", "record", "throw", "rtol", "atol"}
    assert kwargs["record"] == mechanism.SectionsRecord(phase=0.5, discard=1.0, companion=False)
    assert (kwargs["rtol"], kwargs["atol"]) == (1e-6, 1e-6)
    assert ds.status.values.tolist() == ["ok"], ds.message.values
    assert ds.crossing.values.tolist() == [1, 2]


def test_the_settings_object_is_checked() -> None:
    with pytest.raises(ValueError, match=r"^phase must be a finite angle in rad; got nan\.$"):
        mechanism.BifurcationSettings(phase=float("nan"))
    wrong = r"^settings must be a mechanism\.BifurcationSettings; got dict\.$"
    with pytest.raises(TypeError, match=wrong):
        mechanism.bifurcation(
            SCENE, parameter="drive.speed_rpm", values=[3000.0], revolutions=3, discard=1,
            settings={"phase": 0.5},
        )  # fmt: skip


def test_the_studies_take_at_most_twelve_parameters() -> None:
    for study in (mechanism.bifurcation, mechanism.lyapunov_exponent, mechanism.wear_life):
        assert len(inspect.signature(study).parameters) <= 12, study.__name__


def test_the_exponent_is_the_one_from_the_equations(tmp_path) -> None:
    ds = _speeds(tmp_path, values=[3000.0], revolutions=3, discard=1, exponent=True)
    scene = mechanism.load_scene(SCENE).replace({"drive.speed_rpm": 3000.0})
    direct = mechanism.lyapunov_exponent(scene, revolutions=3, discard=1)
    np.testing.assert_allclose(ds.lyapunov_exponent.values, [direct.exponent], rtol=1e-12)
    np.testing.assert_allclose(ds.lyapunov_exponent_low.values, [direct.ci[0]], rtol=1e-12)
    np.testing.assert_allclose(ds.lyapunov_exponent_high.values, [direct.ci[1]], rtol=1e-12)
    # the value's summary keeps the exponent's CPU time beside the simulation's
    (summary,) = (tmp_path / "points").glob("*.summary.nc")
    with xr.open_dataset(summary, engine="h5netcdf") as point:
        assert point.attrs["solver_exponent_cpu_time"] > 0.0
        assert point.attrs["solver_cpu_time"] > 0.0


def test_the_exponent_hook_fills_the_lower_panel(tmp_path, monkeypatch) -> None:
    def stand_in(scene, *, revolutions, discard):
        # no tolerance: the exponent keeps lyapunov_exponent's own default
        speed = scene.drive.speed_rpm
        return speed / 1000.0 - 4.0, speed / 1000.0 - 4.5, speed / 1000.0 - 3.5

    monkeypatch.setattr(bif, "largest_exponent", stand_in)
    ds = _speeds(tmp_path / "with", revolutions=3, discard=1, exponent=True)
    np.testing.assert_allclose(ds.lyapunov_exponent.values, [-1.0, 1.0])
    np.testing.assert_allclose(ds.lyapunov_exponent_high.values, [-0.5, 1.5])
    assert ds.lyapunov_exponent.attrs["units"] == "s-1"
    axes = mechanism.plot_bifurcation(ds)
    assert len(axes) == 2
    assert axes[1].get_ylabel() == "λ (1/s)"


def test_the_exponent_can_keep_fewer_revolutions_than_the_points(tmp_path, monkeypatch) -> None:
    seen = []

    def stand_in(scene, *, revolutions, discard):
        seen.append((revolutions, discard))
        return 1.0, 0.5, 1.5

    monkeypatch.setattr(bif, "largest_exponent", stand_in)
    settings = mechanism.BifurcationSettings(exponent_revolutions=1.5, exponent_discard=0.5)
    ds = _speeds(
        tmp_path, values=[3000.0], revolutions=5, discard=2, exponent=True, settings=settings
    )
    assert seen == [(2.0, 0.5)]  # 0.5 discarded + 1.5 kept, not the points' 5 and 2
    assert ds.crossing.values.tolist() == [2, 3, 4, 5]  # the points keep theirs
    assert ds.lyapunov_exponent.attrs["revolutions_kept"] == 1.5
    assert ds.lyapunov_exponent.attrs["revolutions_discarded"] == 0.5
    seen.clear()
    same = _speeds(tmp_path / "same", values=[3000.0], revolutions=5, discard=2, exponent=True)
    assert seen == [(5.0, 2.0)]  # by default the points' revolutions and transient
    assert same.lyapunov_exponent.attrs["revolutions_kept"] == 3.0
    for kwargs, match in (
        ({"exponent_revolutions": 0}, "exponent_revolutions must be a number > 0"),
        ({"exponent_discard": -1}, "exponent_discard must be a number >= 0"),
        ({"exponent_revolutions": float("nan")}, "exponent_revolutions"),
    ):
        with pytest.raises(ValueError, match=match):
            mechanism.BifurcationSettings(**kwargs)
    with pytest.raises(ValueError, match="pass exponent=True"):
        _speeds(tmp_path / "bad", settings=mechanism.BifurcationSettings(exponent_revolutions=3))


REGULAR_ORBIT = {"parameter": "drive.speed_rpm", "values": [60.0], "revolutions": 16,
                 "discard": 8, "client": "serial"}  # fmt: skip


def strobe_spreads(scene: mechanism.Scene, store) -> dict[str, float]:
    """Spread (m) of the strobed eccentricities of ``scene`` at 60 rpm over revolutions
    9 – 16, at the diagram's default tolerance (``tight``) and at the scene's (``loose``)."""
    tight = mechanism.bifurcation(scene, store=store / "tight", **REGULAR_ORBIT)
    scenes = mechanism.BifurcationSettings(rtol=None, atol=None)
    loose = mechanism.bifurcation(scene, store=store / "loose", settings=scenes, **REGULAR_ORBIT)
    return {
        k: float(np.ptp(d.eccentricity.values)) for k, d in (("tight", tight), ("loose", loose))
    }


def test_a_regular_orbit_is_one_point_at_the_diagram_tolerance(tmp_path) -> None:
    """The rigid paper scene at 60 rpm is period-1 (its exponent from the equations is
    negative): at the scene's rtol = atol = 1e-5 its strobes scatter by integration error
    (0.14 µm measured over 40 revolutions), at the diagram's default 1e-7 they coincide.
    Measured from starts whose crank angles differ by up to 2e-12 of a revolution: 14 –
    28 pm (bound 100 pm) and 19 – 110 nm (bound 1 nm)."""
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    spread = strobe_spreads(scene, tmp_path)
    assert spread["tight"] < 1e-10  # m: one point
    assert spread["loose"] > 1e-9  # integration scatter at the scene's tolerance
    with pytest.raises(ValueError, match="rtol"):
        mechanism.BifurcationSettings(rtol=2.0)


def test_thousands_of_points_stay_visible() -> None:
    rng = np.random.default_rng(0)
    values = np.linspace(30, 300, 60)
    data = xr.Dataset(
        {
            "eccentricity": (
                ("drive.speed_rpm", "crossing", "joint"),
                rng.uniform(0, 1e-4, (60, 100, 1)),
                {"units": "m", "long_name": "journal eccentricity"},
            ),
            "status": ("drive.speed_rpm", np.full(60, "ok")),
        },
        coords={"drive.speed_rpm": values, "crossing": np.arange(100), "joint": ["C"]},
        attrs={"bifurcation_parameter": "drive.speed_rpm", "bifurcation_variables": "eccentricity"},
    )
    (ax,) = mechanism.plot_bifurcation(data)
    (points,) = ax.collections
    assert points.get_offsets().shape == (6000, 2)
    # 6 000 points: dots of 2 pt² (12 000/N), neither specks nor blots
    assert float(points.get_sizes()[0]) == pytest.approx(2.0)
    assert points.get_rasterized()


def test_clockwise_drive_is_strobed_too() -> None:
    scene = mechanism.load_scene(SCENE).replace({"drive.speed_rpm": -4000.0})
    ds = mechanism.simulate(scene, revolutions=2, record="sections")
    assert ds.drive_cycle.values.tolist() == [0, -1, -2]
    np.testing.assert_allclose(ds.crank_angle.values, [0, -2 * np.pi, -4 * np.pi], atol=1e-10)


def test_parse_values() -> None:
    assert bif.parse_values("30:300:60")[:2] == pytest.approx([30.0, 34.576271186440678])
    assert len(bif.parse_values("30:300:60")) == 60
    assert bif.parse_values("2e-4") == [2e-4]
    for bad in ("30:300", "30:300:0", "a,b", ""):
        with pytest.raises(ValueError, match="START:STOP:COUNT"):
            bif.parse_values(bad)


def test_command_line(tmp_path) -> None:
    runner = CliRunner()
    figure = tmp_path / "orbit.png"
    output = tmp_path / "orbit.nc"
    result = runner.invoke(
        app,
        [
            "bifurcation", SCENE, "--param", "drive.speed_rpm", "--values", "3000:4000:2",
            "--revolutions", "3", "--discard", "1", "--scheduler", "serial",
            "--store", str(tmp_path / "store"), "--figure", str(figure), "-o", str(output),
            "--no-progress",
        ],
    )  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "2 values: 2 ok" in result.output
    assert figure.stat().st_size > 1000 and output.exists()
    bad = runner.invoke(
        app,
        ["bifurcation", SCENE, "--param", "drive.speed_rpm", "--values", "30:300",
         "--scheduler", "serial"],
    )  # fmt: skip
    assert bad.exit_code == 2
    assert "START:STOP:COUNT" in bad.output
    assert "Traceback" not in bad.output
    with_exponent = runner.invoke(
        app,
        ["bifurcation", SCENE, "--param", "drive.speed_rpm", "--values", "3000",
         "--revolutions", "3", "--discard", "1", "--exponent", "--exponent-revolutions", "1",
         "--exponent-discard", "0.5", "--scheduler", "serial", "--no-progress",
         "-o", str(tmp_path / "exponent.nc")],
    )  # fmt: skip
    assert with_exponent.exit_code == 0, with_exponent.output
    with xr.open_dataset(tmp_path / "exponent.nc", engine="h5netcdf") as ds:
        assert np.isfinite(ds.lyapunov_exponent.values).all()
        assert ds.lyapunov_exponent.attrs["revolutions_kept"] == 1.0
    bad = runner.invoke(
        app,
        ["bifurcation", SCENE, "--param", "drive.speed_rpm", "--values", "3000",
         "--scheduler", "serial", "--exponent-revolutions", "-2"],
    )  # fmt: skip
    assert bad.exit_code == 2 and "exponent_revolutions must be" in bad.output, bad.output
    for tol in ("loose", "5"):
        bad = runner.invoke(
            app,
            ["bifurcation", SCENE, "--param", "drive.speed_rpm", "--values", "3000",
             "--scheduler", "serial", "--tolerance", tol],
        )  # fmt: skip
        assert bad.exit_code == 2, bad.output
        assert "Traceback" not in bad.output
