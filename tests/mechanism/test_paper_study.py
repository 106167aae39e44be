"""The paper study: published numbers as data, and the pipeline end to end.

The default tests run a tiny variant of the whole study (1.5 revolutions, a coarse output
step, one wear update) and check that the report holds every paper table with ours beside
it, and that our numbers are the reductions of the stored trajectories. The real
``mechanism paper --quick`` run is marked slow.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib.util
import math
import os
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
import mechanism
import mechanism.cli
from chaoskit.reporting import plural
from mechanism.cli import _paper as cli_paper
from mechanism.studies import StudySettings
from mechanism.studies.paper import COLUMNS, paper_wear_zones
from mechanism.studies.paper import _report as paper_report
from mechanism.studies.paper import _runs as paper_runs
from mechanism.studies.paper import _schedule as paper_schedule
from mechanism.studies.paper._published import WEAR_PATHS
from mechanism.studies.paper._summary import strobe_figure

# CI clones the repository with shared/ beside it; developers have it at ../shared too.
SEED_CANDIDATES = [
    os.environ.get("CHAOSKIT_REFERENCE", ""),
    str(Path(__file__).resolve().parents[3] / "shared" / "reference"),
    "/work/shared/reference",
]


def _seed_paper() -> str:
    for folder in SEED_CANDIDATES:
        path = Path(folder) / "seed-paper.txt"
        if folder and path.is_file():
            return path.read_text(encoding="utf-8")
    pytest.skip("seed-paper.txt not found (set CHAOSKIT_REFERENCE to its folder)")


def _number(text: str) -> float:
    return float(text.replace("−", "-").replace("\u2212", "-").strip())


def _rows(text: str) -> dict[str, list[list[float]]]:
    """Every '|'-separated line whose cells after the label are all numbers, by label."""
    out: dict[str, list[list[float]]] = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.split("|")]
        cells = [c for c in cells if c]
        if len(cells) < 2:
            continue
        label, values = cells[0], cells[1:]
        # the chaos table carries the state in the second cell ("X direction | Before wear")
        if len(values) > 1 and not re.fullmatch(r"[−\-0-9.]+", values[0]):
            label, values = f"{label} / {values[0]}", values[1:]
        try:
            numbers = [_number(v) for v in values]
        except ValueError:
            continue
        out.setdefault(label, []).append(numbers)
    return out


# --------------------------------------------------------------------------- the data file


def test_published_numbers_match_the_seed_paper_text():
    rows = _rows(_seed_paper())
    t = mechanism.paper_tables()

    conv = t["convergence"]
    assert list(conv.index) == [4, 8, 12, 16, 20, 24]
    np.testing.assert_array_equal(conv["rod3_strain"], rows["Strain of rod 3 (μm)"][0])
    np.testing.assert_array_equal(conv["rod4_strain"], rows["Strain of rod 4 (μm)"][0])

    seven = {k: [r for r in v if len(r) == 7] for k, v in rows.items()}
    np.testing.assert_array_equal(t["wear"].loc["before wear"], seven["Before wear"][0])
    np.testing.assert_array_equal(t["wear"].loc["after wear"], seven["After wear"][0])
    for label in ("0.1 mm", "0.2 mm", "0.5 mm"):
        np.testing.assert_array_equal(t["clearance"].loc[label], seven[label][0])
    for label in ("30 rpm", "90 rpm", "150 rpm"):
        np.testing.assert_array_equal(t["speed"].loc[label], seven[label][0])
    assert list(t["wear"].columns) == list(COLUMNS)

    chaos = t["chaos"]
    three = {k: [r for r in v if len(r) == 3] for k, v in rows.items()}
    expected = {
        ("X", "before wear"): three["X direction / Before wear"][0],
        ("X", "after wear"): three["After wear"][0],  # the row under "X direction"
        ("Y", "before wear"): three["Y direction / Before wear"][0],
        ("Y", "after wear"): three["After wear"][1],
    }
    for key, (lag, dim, mle) in expected.items():
        assert chaos.loc[key, "lag"] == lag
        assert chaos.loc[key, "embedding_dim"] == dim
        assert chaos.loc[key, "mle_wolf_bits"] == mle

    # the zones and the "1.54 times" of the text (ratio 2.54) follow from the same numbers
    text = _seed_paper()
    for lo, hi in paper_wear_zones():
        assert f"[{lo:g}°, {hi:g}°]" in text
    ratio = (
        t["wear"].loc["after wear", "contact_force"] / t["wear"].loc["before wear", "contact_force"]
    )
    assert "increased by 1.54 times" in text
    assert math.isclose(ratio - 1.0, 1.54, abs_tol=0.005)


def test_settings_reject_bad_values():
    with pytest.raises(ValueError, match="revolutions"):
        StudySettings(revolutions=1.0, discard_revolutions=1.0)
    with pytest.raises(ValueError, match="samples_per_revolution"):
        StudySettings(samples_per_revolution=10)
    with pytest.raises(ValueError, match="elements"):
        StudySettings(elements=())
    with pytest.raises(ValueError, match=r"wear_max_depth_increment must be in \(0, 1\]"):
        StudySettings(wear_max_depth_increment=1.5)
    quick = StudySettings.quick()
    assert quick.revolutions < StudySettings.paper().revolutions
    assert StudySettings.paper().samples_per_revolution == 10_000


# --------------------------------------------------------------------------- the pipeline

TINY = {
    "revolutions": 1.5,
    "discard_revolutions": 0.5,
    "samples_per_revolution": 400,
    "flexible_rods": False,
    "wear_updates": 1,
    "wear_cycles_per_update": 1.0e4,
    "wear_settle_revolutions": 0.25,
    "elements": (4,),
    "convergence_revolutions": 0.02,
    "n_surrogates": 19,
    "max_samples": 500,
    "chaos_revolutions": 2.0,
    "chaos_samples_per_revolution": 400,
    "exponent_revolutions": 1.0,
    "orbit_speeds": (150.0,),
    "orbit_revolutions": 2.0,
    "orbit_discard_revolutions": 1.0,
    "orbit_flexible_rods": False,
    # the wear paths (five wear_life runs) are tested in test_paper_wear_life.py
    "wear_paths": False,
}


@pytest.fixture(scope="module")
def tiny_study(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    # One worn update on 1.5 revolutions can leave a profile whose runs pass the
    # penetration warning (57 % of the clearance after wear at 150 rpm, against 50 %):
    # the study reports such warnings; here they must not abort its runs.
    with warnings.catch_warnings():
        warnings.simplefilter("always", mechanism.SimulationWarning)
        return mechanism.run_paper_study(
            out, client="serial", settings=TINY, command="test", keep_trajectories=True
        )


def _report_tables(md: str) -> list[str]:
    """Captions of the Markdown tables ("**Table n.** caption")."""
    return re.findall(r"Table \d+\.\**\s*(.+)", md)


def test_report_files_hold_every_paper_table_with_ours_beside(tiny_study):
    study = tiny_study
    assert study.report_html.is_file() and study.report_markdown.is_file()
    html = study.report_html.read_text(encoding="utf-8")
    md = study.report_markdown.read_text(encoding="utf-8")
    captions = " ".join(_report_tables(md))
    for needle in (
        "Before and after wear",
        "Clearance size, before wear, 150 rpm",
        "Clearance size, before wear, 90 rpm",
        "Driving speed",
        "Element convergence",
        "Chaos table",
    ):
        assert needle in captions, needle
        assert needle in html, needle
    assert "ours" in md and "paper" in md and "difference (%)" in md
    # every published number is printed (reference cells use up to 6 significant digits)
    paper = mechanism.paper_tables()
    for name in ("wear", "clearance", "speed", "convergence"):
        for value in paper[name].to_numpy().ravel():
            text = f"{value:.6g}"
            assert f"| {text} |" in md, (name, text)
    for value in paper["chaos"]["mle_wolf_bits"]:
        assert f"{value:.6g}" in md
    assert "ours ratio after/before" in md and "paper ratio after/before" in md
    # parts this version lacks are said so, not skipped
    for line in study.unavailable:
        assert "NOT AVAILABLE IN THIS VERSION" in md
        assert line.split(" (")[0] in md


def test_our_numbers_are_reductions_of_the_stored_trajectories(tiny_study):
    study = tiny_study
    before = study.sweeps["before"]
    point = before.sel({"joints.C.clearance": 2e-4, "drive.speed_rpm": 150})
    path = Path(before.attrs["store"]) / str(point["trajectory_file"].values)
    with xr.open_dataset(path, engine="h5netcdf") as traj:
        angle = traj["crank_angle"].values
        keep = np.abs(angle - angle[0]) >= 2 * np.pi * TINY["discard_revolutions"] * (1 - 1e-12)
        force = traj["contact_force"].values[keep].max()
        depth = traj["penetration"].values[keep].max()
        torque = traj["driving_torque"].values[keep]
        torque_extreme = torque[np.argmax(np.abs(torque))]
        err = np.abs(traj["displacement_error"].values[keep]).max()
    row = study.tables["wear"].loc["before wear"]
    np.testing.assert_allclose(row["contact_force"], force * 1e-3, rtol=1e-12)
    np.testing.assert_allclose(row["embedding_depth"], depth * 1e3, rtol=1e-12)
    np.testing.assert_allclose(row["driving_torque"], torque_extreme, rtol=1e-12)
    np.testing.assert_allclose(row["displacement_error"], err * 1e3, rtol=1e-12)
    # the 150 rpm clearance row and the before-wear row are the same point
    pd.testing.assert_series_equal(study.tables["clearance"].loc["0.2 mm"], row, check_names=False)
    # rigid rods: no strains
    assert np.isnan(row["rod3_strain"])
    if "after 150 rpm" in study.sweeps:
        after = study.tables["wear"].loc["after wear"]
        speed = study.tables["speed"].loc["150 rpm"]
        np.testing.assert_allclose(after.to_numpy(float), speed.to_numpy(float), rtol=1e-12)
    conv = study.tables["convergence"]
    assert list(conv.index) == [4, 8, 12, 16, 20, 24]  # every published row, ours or NaN
    if hasattr(mechanism, "element_convergence"):
        assert np.isfinite(conv.loc[4]).all(), conv
        assert np.isnan(conv.loc[24]).all()  # not run in the tiny variant
    ds = study.to_dataset()
    assert set(ds["ours"].dims) == {"case", "quantity"}
    assert ds["paper"].sel(case="wear: after wear", quantity="contact_force") == 23.33
    for var in ds.data_vars.values():
        assert var.attrs["units"] and var.attrs["long_name"]


@pytest.mark.slow
def test_quick_command_runs_end_to_end(tmp_path):
    """The README's main job: ``mechanism paper --quick -o DIR`` (several minutes)."""
    out = tmp_path / "paper-quick"
    command = Path(sys.executable).parent / "mechanism"
    done = subprocess.run(
        [str(command), "paper", "--quick", "--no-progress", "-o", str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    md = (out / "report.md").read_text(encoding="utf-8")
    assert "Chaos table" in md and "Before and after wear" in md


def test_report_opens_with_the_answer_and_cites_nothing_outside_the_repository(tiny_study):
    md = tiny_study.report_markdown.read_text(encoding="utf-8")
    html = tiny_study.report_html.read_text(encoding="utf-8")
    headings = re.findall(r"^## (.+)$", md, flags=re.M)
    assert headings[0] == "Summary", headings
    summary = md.split("\n## ", 2)[1]
    for needle in ("The answer", "our verdict", "paper's claim", "agreement", "Rosenstein"):
        assert needle in summary, needle
    for state, claim in mechanism.paper_claims().items():
        assert state in summary and claim["motion"] in summary
    # the run states its settings, wall time, output size and the per-speed wear
    assert re.search(r"wall time \d+\.\d min, output \d+\.\d MB", summary)
    for rpm in (30, 90, 150):
        assert f"{rpm} rpm:" in summary and "crank cycles" in summary
    assert "worn at its own speed" in md
    # user-facing text points to the repository's own model description only
    for text in (md, html):
        assert "seed-paper" not in text and "paper-model §" not in text
        assert not re.search(r"\bA1?\d\b[:)]|\(S\d\)|\bG-a\b|issue \d", text)
        assert "docs/paper-model.md" in text
    # result tables stay narrow: at most 8 columns (the provenance's input list is wider)
    results = md.split("\n## Parameters and provenance")[0]
    for line in results.splitlines():
        if line.startswith("|"):
            assert line.count("|") - 1 <= 8, line


def test_speed_table_uses_a_profile_worn_at_each_speed(tiny_study):
    sweeps = tiny_study.sweeps
    assert {"after 30 rpm", "after 90 rpm", "after 150 rpm"} <= set(sweeps)
    speed = tiny_study.tables["speed"]
    for rpm in (30, 90, 150):
        point = sweeps[f"after {rpm} rpm"]
        force = float(point["peak_contact_force"].values) * 1e-3
        np.testing.assert_allclose(speed.loc[f"{rpm} rpm", "contact_force"], force, rtol=1e-12)


def test_default_output_keeps_metrics_and_drops_trajectories(tiny_study, tmp_path):
    store = Path(tiny_study.sweeps["before"].attrs["store"])
    copy = tmp_path / "store"
    shutil.copytree(store, copy)
    names = {p.name for p in (copy / "points").iterdir()}
    assert any(n.endswith(".summary.nc") for n in names)
    assert any(not n.endswith(".summary.nc") for n in names if n.endswith(".nc"))
    paper_schedule.drop_trajectories(copy)
    left = {p.name for p in (copy / "points").iterdir()}
    assert left == {n for n in names if not n.endswith(".nc") or n.endswith(".summary.nc")}
    assert (tiny_study.output / "trajectories" / "before-wear.nc").is_file()  # kept on request


@pytest.mark.slow
def test_report_first_screen_in_headless_chromium(tiny_study, tmp_path):
    """The report as a page: the summary is on the first screen (docs/paper-study.md),
    rendered by ``benchmarks/paper_screenshot.py``."""
    path = Path(__file__).resolve().parents[2] / "benchmarks" / "paper_screenshot.py"
    spec = importlib.util.spec_from_file_location("paper_screenshot", path)
    assert spec is not None and spec.loader is not None
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    if script.find_browser() is None:
        pytest.skip("chromium is not installed (apt-get install chromium)")
    png = script.screenshot(tiny_study.report_html, tmp_path / "first-screen.png")
    assert png.read_bytes().startswith(b"\x89PNG")
    assert script.main([str(tmp_path / "missing.html")]) == 2
    # what the first screen holds: the title, then the summary section and its first table
    html = tiny_study.report_html.read_text(encoding="utf-8")
    body = html[html.index("<body") :]
    first_h2 = re.search(r"<h2[^>]*>(.*?)</h2>", body, flags=re.S)
    assert first_h2 is not None and "Summary" in first_h2.group(1)
    assert body.index("The answer") < body.index("Before and after wear")


@pytest.mark.slow
def test_quick_settings_reach_the_verdict_of_the_paper_settings_before_wear():
    """One state (before wear, 150 rpm, flexible rods, 200 revolutions at T/10000): the
    analysis reductions of --quick give the verdict of the paper settings. Long: the run is
    the chaos run of the study (several minutes on 2 cores)."""
    quick, full = StudySettings.quick(), StudySettings.paper()
    assert quick.flexible_rods and full.flexible_rods
    assert quick.chaos_revolutions == full.chaos_revolutions >= 200
    scene = paper_runs.wear_scene_of(mechanism.load_scene("paper"))
    # the output grid does not set the integration steps, so the quick series is the
    # paper settings' series at every second sample
    traj = paper_runs.chaos_run(scene, full)
    assert traj.sizes["time"] >= 200 * full.chaos_samples_per_revolution
    stride = full.chaos_samples_per_revolution // quick.chaos_samples_per_revolution
    verdicts = {}
    for name, settings, data in (
        ("quick", quick, traj.isel(time=slice(None, None, stride))),
        ("paper", full, traj),
    ):
        rep = chaoskit.report(
            {"before wear": data},
            **paper_runs.chaos_analysis_options(settings),
            extras=chaoskit.ReportExtras(
                exponents={"before wear": paper_runs.equation_exponent(scene, settings)}
            ),
        )
        verdicts[name] = rep.motions["before wear"]
    assert verdicts["quick"].label == verdicts["paper"].label, verdicts
    assert verdicts["quick"].period == verdicts["paper"].period, verdicts


def _one_revolution_state():
    """Settings of a one-revolution long run and the before-wear state of the study."""
    settings = StudySettings(
        revolutions=2.0, discard_revolutions=1.0, chaos_revolutions=1.0,
        chaos_samples_per_revolution=100,
    )  # fmt: skip
    return settings, paper_runs.wear_scene_of(mechanism.load_scene("paper"))


def test_a_diverged_flexible_long_run_falls_back_to_rigid_rods_and_says_so(monkeypatch):
    """A flexible-rod long run that stops is replaced by the rigid-rod run of the same
    state, and the series carry the reason (the report's summary repeats it)."""
    real = paper_runs.simulate
    calls = []

    def flexible_fails(scene, **kwargs):
        calls.append(scene.effects.flexibility)
        if scene.effects.flexibility:
            raise mechanism.SimulationError(
                "simulation of 'paper' failed after t = 0.8 s (x)", time=0.8
            )
        return real(scene, **kwargs)

    monkeypatch.setattr(paper_runs, "simulate", flexible_fails)
    settings, scene = _one_revolution_state()
    ds = paper_runs.chaos_run(scene, settings)
    assert calls == [True, False]
    assert ds.sizes["time"] == 2 * 100 + 1
    note = ds.attrs["rods_note"]
    assert note.startswith("the run with flexible rods stopped after 2 of 2 revolutions")
    assert note.endswith("its series are from rigid rods")
    assert paper_report.rods_of({"after wear": ds}, settings) == "flexible (after wear: rigid)"


def test_a_flexible_long_run_whose_journal_leaves_the_bearing_falls_back_too(monkeypatch):
    """A run that completes with the journal outside its worn bearing is not analysed."""
    real = paper_runs.simulate

    def flexible_escapes(scene, **kwargs):
        ds = real(scene.replace({"effects.flexibility": False}), **kwargs)
        if scene.effects.flexibility:
            ds["eccentricity_x"] = ds["eccentricity_x"] * 0.0 + 1.0e-3  # 1 mm: outside
        return ds

    monkeypatch.setattr(paper_runs, "simulate", flexible_escapes)
    settings, scene = _one_revolution_state()
    assert paper_runs.bearing_room(scene) == pytest.approx(3.0e-4)  # unworn: 1.5 c
    ds = paper_runs.chaos_run(scene, settings)
    assert float(abs(ds["eccentricity_x"]).max()) < 3.0e-4
    assert ds.attrs["rods_note"].startswith(
        "the journal of the run with flexible rods left the bearing (eccentricity up to 1."
    )


@pytest.mark.parametrize("threads", [False, True])
def test_long_runs_queue_both_exponents_with_flexible_rods(monkeypatch, threads):
    """With flexible rods each state gets its chaos run, the exponent on the series' model
    and the rigid-rod one; with rigid rods no companion. (Stand-ins for the runs; with
    ``threads`` the queue runs in its thread and submits to a pool, as the study does.)"""
    from concurrent.futures import ThreadPoolExecutor

    monkeypatch.setattr(paper_schedule, "predict_worn", lambda scene, s: (scene, None, "worn"))
    monkeypatch.setattr(paper_schedule, "chaos_run", lambda scene, s: "series")
    monkeypatch.setattr(
        paper_schedule, "equation_exponent", lambda scene, s, *, rigid=False: ("λ", rigid)
    )
    monkeypatch.setattr(paper_schedule, "wear_path", lambda scene, rpm, c, s: ("path", rpm, c))
    base = mechanism.load_scene("paper")
    for flexible, rigid_rods, third in (
        (True, True, ("λ", True)),
        (True, False, None),  # the quick settings leave the rigid-rod exponent out
        (False, True, None),
    ):
        settings = StudySettings(flexible_rods=flexible, rigid_rod_exponent=rigid_rods)
        with ThreadPoolExecutor(2) if threads else contextlib.nullcontext() as pool:
            long_runs = paper_schedule.LongRuns(pool, base, settings)
            states = long_runs.states()
            assert list(states) == ["before wear", "after wear"]
            for state, (chaos, exponent, rigid) in states.items():
                assert chaos.result() == "series"
                assert exponent.result() == ("λ", False)
                assert (rigid.result() if rigid is not None else None) == third
                # a series that fell back to rigid rods gets its rigid-rod exponent anyway
                assert long_runs.rigid_exponent(state).result() == ("λ", True)
            # the five wear paths, each one task
            paths = {key: f.result() for key, f in long_runs.paths().items()}
            assert paths == {key: ("path", *key) for key in WEAR_PATHS}


def _kept_trajectories(study) -> dict[str, xr.Dataset]:
    folder = study.output / "trajectories"
    return {
        state: chaoskit.load_trajectory(folder / f"{state.replace(' ', '-')}.nc")
        for state in study.motions
    }


def test_strobe_figure_shows_the_points_the_motion_table_counts(tiny_study):
    """Figure 1 and the motion verdict's table count the same points: those of the joint
    section, never the initial state (the crank angle is 0 at t = 0, a strobe instant)."""
    md = tiny_study.report_markdown.read_text(encoding="utf-8")
    assert "The points are those of the joint section the motion verdict counts" in md
    trajectories = _kept_trajectories(tiny_study)
    assert set(trajectories) == {"before wear", "after wear"}
    discard = TINY["discard_revolutions"] * 0.4
    fig = strobe_figure(trajectories, motions=tiny_study.motions, discard=discard)
    motion_rows = md.split("The motion verdict:")[1].split("\n\n")[1].splitlines()
    for ax, (state, traj) in zip(fig.axes, trajectories.items(), strict=True):
        n = tiny_study.motions[state].structure.n_points
        (line,) = ax.lines
        assert line.get_xdata().size == n
        row = next(r for r in motion_rows if r.startswith(f"| {state} |"))
        assert f"({plural(n, 'point')})" in row
        # the whole trajectory's strobe starts at the initial state, which is not shown
        whole = chaoskit.stroboscopic_map(
            traj.sel(joint="C"), phase_variable="crank_angle", coords=["eccentricity_x"]
        )
        assert whole["time"].values[0] == 0.0 and whole.sizes["crossing"] > n
        assert not np.any(
            np.isclose(line.get_xdata(), whole["eccentricity_x"].values[0] * 1e3, atol=0)
        )


def test_summary_opens_with_the_answer_and_ends_with_the_run_notes(tiny_study):
    md = tiny_study.report_markdown.read_text(encoding="utf-8")
    summary = md.split("\n## ", 2)[1]
    first = summary.split("\n\n")[1]
    assert first.startswith("Before wear: ") and "After wear: " in first
    answer = summary.index("**Table 1.** The answer")
    for note in ("Settings: ", "Run: wall time", "crank cycles in 1 update;"):
        assert answer < summary.index(note), note


def test_report_text_reads_plainly(tiny_study):
    """No "update(s)", no "after 1 of transient", no "wear worn"."""
    for path in (tiny_study.report_markdown, tiny_study.report_html):
        text = "\n".join(
            line
            for line in path.read_text(encoding="utf-8").splitlines()
            # the estimators' own reasons are quoted as they wrote them
            if "| reason |" not in line and '<th scope="row">reason</th>' not in line
        )
        assert not re.search(r"\w\(s\)", text), re.findall(r".{30}\w\(s\).{10}", text)
        assert not re.search(r"\d of transient", text)
        assert not re.search(r"\b1 (revolutions|updates|points)\b", text)
        assert "wear worn" not in text and "scene key" not in text
    assert "in 1 update;" in tiny_study.report_markdown.read_text(encoding="utf-8")


def test_paper_command_prints_the_answer_before_the_files(tiny_study, monkeypatch, tmp_path):
    monkeypatch.setattr(cli_paper, "run_paper_study", lambda *args, **kwargs: tiny_study)
    result = CliRunner().invoke(mechanism.cli.app, ["paper", "--quick", "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    head = lines.index("Motion verdict per state:")
    assert lines[head + 1].split() == ["verdict", "confidence", "λ₁", "[95", "%]", "λ₁", "from"]
    rows = lines[head + 3 : head + 5]
    for row, (state, mv) in zip(rows, tiny_study.motions.items(), strict=True):
        assert row.startswith(state) and mv.label in row
        assert re.search(r"  (\d\.\d\d|—)  ", row), row
        # λ₁ with its interval and where it comes from (the equations when they decide)
        assert re.search(r"\[\S+, \S+\] 1/s +(equations of motion|data, joint)", row), row
    assert lines[head + 5] == "" and lines[head + 6] == f"report: {tiny_study.report_html}"


def test_paper_command_opens_with_the_judged_transition_claims(tiny_study, monkeypatch, tmp_path):
    """With wear paths, the first lines name each of the paper's transition claims with
    agree / disagree / cannot tell and why, above the motion verdicts."""
    claims = pd.DataFrame(
        {
            "claim": ["“speeds below 90 rpm …”", "“enlarged clearances …”"],
            "agreement": ["disagree", "cannot tell"],
            "why": ["30 rpm turns chaotic after 5 000 cycles", "the 0.5 mm path failed"],
        },
        index=pd.Index(["low speeds stabilise", "clearance accelerates"], name="paper's claim"),
    )
    study = dataclasses.replace(tiny_study, transition_claims=claims)
    monkeypatch.setattr(cli_paper, "run_paper_study", lambda *args, **kwargs: study)
    result = CliRunner().invoke(mechanism.cli.app, ["paper", "--quick", "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    head = lines.index("Wear life against the paper's claims on the transition to chaos:")
    assert lines[head + 1 : head + 3] == [
        "  disagree: low speeds stabilise — 30 rpm turns chaotic after 5 000 cycles",
        "  cannot tell: clearance accelerates — the 0.5 mm path failed",
    ]
    assert lines[head + 3] == "" and lines[head + 4] == "Motion verdict per state:"


def test_settings_mapping_replaces_fields_of_the_paper_settings(tiny_study):
    assert tiny_study.settings == dataclasses.replace(StudySettings.paper(), **TINY)
    assert not tiny_study.quick


def test_settings_of_another_type_are_refused_before_anything_runs(tmp_path):
    with pytest.raises(TypeError) as err:
        mechanism.run_paper_study(tmp_path / "out", settings=3)  # type: ignore[arg-type]
    assert str(err.value) == (
        "settings must be a mechanism.StudySettings or a mapping of its fields; got int."
    )
    assert not (tmp_path / "out").exists()
