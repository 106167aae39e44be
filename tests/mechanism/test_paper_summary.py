"""The paper study's summary pieces: one verdict per state, stage progress, wear ratios."""

from __future__ import annotations

import io
import math
import re
import time
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from matplotlib.figure import Figure

import chaoskit
import mechanism
from chaoskit.reporting import CONFIDENCE_NOTE
from mechanism.studies.paper import COLUMNS
from mechanism.studies.paper._report import orbit_display, wear_comparison
from mechanism.studies.paper._runs import compile_kernels
from mechanism.studies.paper._summary import (
    Stages,
    motion_verdict,
    strobe_figure,
    strobe_points,
    summary_section,
)


def _motion(
    label: str,
    confidence: float,
    *,
    votes: dict | None = None,
    equations_say: str | None = "regular",
    variables: dict | None = None,
) -> SimpleNamespace:
    """A stand-in for a MotionVerdict: its label, votes and the evidence they stand for."""
    names = variables or {"X": SimpleNamespace(label=label), "Y": SimpleNamespace(label=label)}
    default = {"equations": "supports", **{f"variable {n}": "supports" for n in names}}
    return SimpleNamespace(
        label=label,
        confidence=confidence,
        reason=f"every variable says {label}",
        reasons=(f"every variable says {label}", "the equations say regular: λ₁ = -3"),
        voting=tuple(names),
        variables=names,
        votes=votes if votes is not None else default,
        equations_say=equations_say,
        exponent_positive=False,
        structure=SimpleNamespace(kind="clusters", n_clusters=1, n_points=198),
    )


def test_motion_verdict_is_the_motion_of_the_state_from_all_its_series() -> None:
    t, s = chaoskit.systems.duffing(4000, gamma=0.5, samples_per_period=40)
    crank = 1.2 * t  # the drive's phase, like the crank angle of a mechanism
    series = xr.Dataset(
        {"X": ("time", s[:, 0]), "Y": ("time", s[:, 1]), "crank_angle": ("time", crank)},
        coords={"time": t},
    )
    eq = SimpleNamespace(exponent=0.1, ci=(0.07, 0.13))  # Duffing γ = 0.5: λ₁ ≈ 0.1 s⁻¹
    mv = motion_verdict(series, exponent=eq)
    assert isinstance(mv, chaoskit.MotionVerdict)
    assert mv.label == "chaotic" and set(mv.variables) == {"X", "Y"}
    assert mv.equations_say == "chaotic" and mv.votes["equations"] == "supports"


def test_stages_print_each_stage_with_the_time_left_scaled_by_measured_cost() -> None:
    stream = io.StringIO()
    stages = Stages({"a": 1.0, "b": 3.0}, stream=stream)
    with stages.stage("a"):
        pass
    stages._done_time = 10.0  # a took 10 s for a weight of 1: b (weight 3) needs 30 s
    with stages.stage("b"):
        pass
    lines = stream.getvalue().splitlines()
    assert lines[0].startswith("[1/2] a") and "estimating time left" in lines[0]
    assert lines[1].startswith("[2/2] b") and "about 30 s left" in lines[1]
    with pytest.raises(ValueError, match="unknown stage"):
        with stages.stage("c"):
            pass
    silent = io.StringIO()
    with Stages({"a": 1.0}, enabled=False, stream=silent).stage("a"):
        pass
    assert silent.getvalue() == ""


def test_a_stage_of_no_prior_cost_is_timed_but_left_out_of_the_estimate() -> None:
    """The kernels' compilation takes minutes on a fresh install and seconds after: it is
    listed, but its time must not scale the estimate of the stages after it."""
    stream = io.StringIO()
    stages = Stages({"compile": 0.0, "a": 1.0, "b": 3.0}, stream=stream)
    with stages.stage("compile"):
        time.sleep(0.05)
    with stages.stage("a"):
        pass
    assert "estimating time left" in stream.getvalue().splitlines()[1]
    stages._done_time = 10.0  # a: 10 s for a weight of 1, the compilation not counted
    with stages.stage("b"):
        pass
    assert "about 30 s left" in stream.getvalue().splitlines()[2]
    assert stages.times["compile"] >= 0.05 and "compile" in stages.summary().index


def test_the_kernels_compile_once_per_path_and_load_from_the_cache_after() -> None:
    """The study compiles every compiled path in its pool before the workers start; each
    part runs its tiny problems and returns the CPU time (compiled already by the time
    the tests get here: a few seconds)."""
    for part in ("flexible", "rigid"):
        assert compile_kernels(part) > 0.0


def test_wear_table_ratios_compare_magnitudes_of_negative_quantities() -> None:
    paper = mechanism.paper_tables()["wear"]
    ours = paper.copy()
    ours.loc["before wear", "driving_torque"] = -184.6
    ours.loc["after wear", "driving_torque"] = -562.6
    table = wear_comparison(ours, paper)
    torque = table.loc["driving torque (N m)"]
    np.testing.assert_allclose(torque["ours_ratio"], 562.6 / 184.6, rtol=1e-12)
    np.testing.assert_allclose(torque["paper_ratio"], 799.7 / 478.5, rtol=1e-12)
    np.testing.assert_allclose(
        table.loc["contact force (kN)", "paper_ratio"], 23.33 / 9.182, rtol=1e-12
    )
    assert len(table) == len(COLUMNS) and table.shape[1] == 6


def test_summary_section_puts_the_paper_beside_ours_with_agreement() -> None:
    states = ["before wear", "after wear"]
    motions = {"before wear": _motion("periodic", 0.9), "after wear": _motion("periodic", 0.7)}
    index = pd.MultiIndex.from_product([["X", "Y"], states], names=["variable", "state"])
    chaos = pd.DataFrame(
        {
            "mle_wolf": [-1.0, 2.0, -1.0, 2.0],
            "mle_wolf_low": [-2.0, 1.0, -2.0, 1.0],
            "mle_wolf_high": [-0.5, 3.0, -0.5, 3.0],
            "mle_rosenstein": [0.1, 0.2, 0.1, 0.2],
            "mle_rosenstein_low": [0.0, 0.1, 0.0, 0.1],
            "mle_rosenstein_high": [0.2, 0.3, 0.2, 0.3],
        },
        index=index,
    )
    eq = SimpleNamespace(exponent=-3.0, ci=(-4.0, -2.0))
    section = summary_section(
        states=states,
        motions=motions,
        chaos=chaos,
        paper_chaos=mechanism.paper_tables()["chaos"],
        claims=mechanism.paper_claims(),
        equations={"before wear": eq, "after wear": None},
        paper_step=0.4 / 10_000,
        settings_text="Settings: test.",
    )
    answer, exponents = section.items
    data = answer.data
    assert data.at["before wear", "agreement"] == "agree"  # paper: not chaotic
    assert data.at["after wear", "agreement"] == "disagree"  # paper: chaotic
    shown = exponents.display()
    assert shown.shape[1] <= 8
    rows = exponents.data
    # one row per state and estimate: the equations', then Wolf and Rosenstein per series
    assert rows.loc["before wear"].index.tolist() == [
        "equations (rigid rods)",
        "Wolf, X",
        "Wolf, Y",
        "Rosenstein, X",
        "Rosenstein, Y",
    ]
    to_bits = 0.4 / 10_000 / math.log(2.0)
    wolf = rows.loc[("after wear", "Wolf, X")]
    np.testing.assert_allclose(
        wolf[["bits", "bits_low", "bits_high"]].to_numpy(dtype=float),
        np.array([2.0, 1.0, 3.0]) * to_bits,
        rtol=1e-12,
    )
    assert wolf["paper_bits"] == 0.0042 and wolf["sign"] == "agree"
    assert rows.at[("before wear", "Wolf, Y"), "sign"] == "agree"  # both negative
    assert rows.at[("before wear", "Wolf, X"), "sign"] == "disagree"  # paper: +0.001
    # the equations' exponent is compared with the claim: not chaotic, and λ < 0
    equations = rows.loc[("before wear", "equations (rigid rods)")]
    assert equations["per_s"] == -3.0 and equations["sign"] == "agrees with claim"
    np.testing.assert_allclose(equations["bits_low"], -4.0 * to_bits, rtol=1e-12)
    missing = rows.loc[("after wear", "equations (rigid rods)")]
    assert math.isnan(float(missing["per_s"])) and missing["sign"] == "—"
    assert re.match(
        r"ours: the exponent from the equations \(interval not above zero\) and the variables "
        r"X, Y \(periodic\) agree; paper: chaotic",
        data.at["after wear", "why"],
    )
    # the answer opens the section, the settings close it
    assert section.text.startswith("Before wear: periodic (confidence 0.90); the paper:")
    assert section.footer == "Settings: test."


def test_summary_shows_the_flexible_exponent_with_its_rigid_rod_companion() -> None:
    """The series' model first (flexible rods), the rigid-rod model of the state beside it;
    each labelled by the model its result ran."""
    states = ["before wear"]
    index = pd.MultiIndex.from_product([["X"], states], names=["variable", "state"])
    chaos = pd.DataFrame({"mle_wolf": [2.0], "mle_rosenstein": [3.0]}, index=index)
    flexible = SimpleNamespace(exponent=40.0, ci=(35.0, 45.0), settings={"model": "flexible"})
    rigid = SimpleNamespace(exponent=9.0, ci=(5.0, 13.0), settings={"model": "rigid"})
    section = summary_section(
        states=states,
        motions={"before wear": _motion("chaotic", 0.9)},
        chaos=chaos,
        paper_chaos=mechanism.paper_tables()["chaos"],
        claims=mechanism.paper_claims(),
        equations={"before wear": flexible},
        rigid_equations={"before wear": rigid},
        paper_step=0.4 / 10_000,
        settings_text="Settings: test.",
    )
    rows = section.items[1].data
    assert rows.loc["before wear"].index.tolist()[:2] == [
        "equations (flexible rods)",
        "equations (rigid rods)",
    ]
    assert rows.at[("before wear", "equations (flexible rods)"), "per_s"] == 40.0
    assert rows.at[("before wear", "equations (rigid rods)"), "per_s"] == 9.0
    # the paper calls the state before wear not chaotic
    assert rows.at[("before wear", "equations (rigid rods)"), "sign"] == "contradicts claim"


def _summary(motions, chaos, **kwargs):
    return summary_section(
        states=list(motions),
        motions=motions,
        chaos=chaos,
        paper_chaos=mechanism.paper_tables()["chaos"],
        claims=mechanism.paper_claims(),
        equations=kwargs.pop("equations", {}),
        paper_step=0.4 / 10_000,
        settings_text="Settings: test.",
        **kwargs,
    )


def _chaos(wolf: tuple[float, float, float], state: str = "before wear") -> pd.DataFrame:
    index = pd.MultiIndex.from_product([["X"], [state]], names=["variable", "state"])
    return pd.DataFrame(
        {
            "mle_wolf": [wolf[0]],
            "mle_wolf_low": [wolf[1]],
            "mle_wolf_high": [wolf[2]],
            "mle_rosenstein": [-1.0],
            "mle_rosenstein_low": [-2.0],
            "mle_rosenstein_high": [-0.5],
        },
        index=index,
    )


def test_why_says_which_evidence_decided_over_which() -> None:
    """Equations and data disagree: the line names the winner and what it overruled."""
    mv = _motion(
        "chaotic",
        2 / 3,
        votes={"equations": "supports", "exponent": "opposes", "section": "supports"},
        equations_say="chaotic",
    )
    mv.structure = SimpleNamespace(kind="scattered", n_points=198)
    section = _summary({"after wear": mv}, _chaos((1.0, 0.5, 1.5), "after wear"))
    why = section.items[0].data.at["after wear", "why"]
    assert why.startswith(
        "ours: the exponent from the equations (interval above zero) and the joint section "
        "(scattered) decide over the joint exponent of the data estimators (not clearly "
        "positive); paper: chaotic"
    )
    assert "\n" not in why


def test_confidence_has_two_decimals_and_a_sentence_on_what_it_is() -> None:
    section = _summary({"after wear": _motion("chaotic", 2 / 3)}, _chaos((1, 0.5, 1.5)))
    answer = section.items[0]
    assert answer.display().at["after wear", ("confidence", "")] == "0.67"
    assert CONFIDENCE_NOTE in answer.notes
    assert "(confidence 0.67)" in section.text


def test_a_clearly_positive_wolf_exponent_of_a_periodic_state_is_marked_set_aside() -> None:
    x = SimpleNamespace(label="periodic", wolf_positive=True, rosenstein_positive=False)
    mv = _motion("periodic", 0.75, variables={"X": x})
    section = _summary({"before wear": mv}, _chaos((2.0, 1.0, 3.0)))
    table = section.items[1]
    key = ("before wear", "Wolf, X")
    assert table.marks == {(key, "per_s"): "†", (key, "bits"): "†"}
    shown = table.display()
    assert shown.loc[key, ("λ (1/s)", "")] == "2 [1, 3] †"
    assert shown.loc[("before wear", "Rosenstein, X"), ("λ (1/s)", "")] == "-1 [-2, -0.5]"
    assert table.notes.startswith("† set aside: the estimate points the other way")
    # an undetermined state decided nothing: nothing is set aside
    unsure = _motion("undetermined", math.nan, variables={"X": x})
    assert _summary({"before wear": unsure}, _chaos((2.0, 1.0, 3.0))).items[1].marks == {}


def test_strobe_points_are_the_verdicts_points_never_the_initial_state() -> None:
    traj = chaoskit.load_trajectory(chaoskit.sample_path("paper-150rpm-before.nc"))
    period = 0.4  # 150 rpm; the crank angle is 0 at t = 0, a strobe instant
    whole = chaoskit.stroboscopic_map(traj, phase_variable="crank_angle")
    assert whole["time"].values[0] == 0.0  # the initial state is a strobe instant
    every = strobe_points(traj)
    assert every.sizes["crossing"] == whole.sizes["crossing"] - 1  # all but the start
    np.testing.assert_allclose(every["time"].values, whole["time"].values[1:], rtol=0)
    # a discard of one period keeps the strobe at t = 0.4 s (found at 0.4 - 2e-14 s)
    assert strobe_points(traj, discard=period).sizes["crossing"] == every.sizes["crossing"]
    later = strobe_points(traj, discard=1.5 * period)
    assert later.sizes["crossing"] == every.sizes["crossing"] - 1
    # with a verdict: exactly the instants of its joint section, whatever was discarded
    used = np.arange(2, 18) * period + 1e-12
    motion = SimpleNamespace(section=xr.Dataset(coords={"time": ("crossing", used)}))
    kept = strobe_points(traj, motion=motion)
    np.testing.assert_allclose(kept["time"].values, used, atol=1e-9)
    fig = strobe_figure({"before wear": traj}, motions={"before wear": motion})
    (line,) = fig.axes[0].lines
    assert line.get_xdata().size == used.size == 16
    assert fig.axes[0].get_title() == "before wear: 16 points"
    np.testing.assert_allclose(line.get_xdata(), kept["eccentricity_x"].values * 1e3, rtol=1e-12)


def test_orbit_diagram_is_drawn_in_mm_against_the_crank_speed() -> None:
    speeds = [30.0, 150.0]
    ds = xr.Dataset(
        {
            "eccentricity_x": (
                ("drive.speed_rpm", "point"),
                np.array([[1e-4, 1.5e-4], [-1e-4, 2e-4]]),
                {"units": "m", "long_name": "journal-centre e_x"},
            )
        },
        coords={
            "drive.speed_rpm": (
                "drive.speed_rpm",
                speeds,
                {"units": "rpm", "long_name": "scene key drive.speed_rpm"},
            )
        },
        attrs={
            "bifurcation_parameter": "drive.speed_rpm",
            "bifurcation_variables": "eccentricity_x",
        },
    )
    fig = Figure()
    ax = fig.subplots()
    mechanism.plot_bifurcation(orbit_display(ds), axes=[ax])
    assert ax.get_xlabel() == "crank speed (rpm)"
    assert ax.get_ylabel() == "journal-centre e_x (mm)"
    y = ax.collections[0].get_offsets()[:, 1]
    np.testing.assert_allclose(np.sort(y), [-0.1, 0.1, 0.15, 0.2], rtol=1e-12)
    assert ds["eccentricity_x"].attrs["units"] == "m"  # the study's data stay in SI
