"""chaoskit.report: the page renders, every table and figure is there, the twin agrees.

Two states of a forced Duffing oscillator stand in for "before wear" (γ = 0.28, period 2)
and "after wear" (γ = 0.5, chaotic), stored like a simulated trajectory: the analysed
series is ``eccentricity_x`` of joint ``C`` in a ``(time, joint)`` variable whose joint
``A`` holds a plain sine, so picking the wrong joint changes the verdict.
"""

from __future__ import annotations

import base64
import html
import io
import json
import math
import re
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from PIL import Image

import chaoskit
from chaoskit import ReportExtras, ReportOptions, select_series, systems
from chaoskit.reporting import (
    ReportFigure,
    ReportTable,
    SweepMap,
    format_number,
    markdown_text,
    parse_variable,
)

OMEGA = 1.2
DRIVE = 2 * np.pi / OMEGA
SCENE = {"name": "duffing-standin", "joints": {"C": {"clearance": 2e-4}}, "drive": {"omega": 1.2}}
STATES = ("before wear", "after wear")
ECC_NAME = "journal centre minus bearing centre, x"


def _trajectory(gamma: float, n_periods: int, *, wear: str) -> xr.Dataset:
    t, state = systems.duffing(
        n_periods * 50, gamma=gamma, samples_per_period=50, discard_periods=200
    )
    sine = np.sin(OMEGA * t)
    ecc = 1e-4 * np.column_stack([sine, state[:, 0]])  # joint A: a sine; joint C: Duffing
    ds = xr.Dataset(
        {
            "eccentricity_x": (("time", "joint"), ecc, {"units": "m", "long_name": ECC_NAME}),
            "crank_angle": ("time", OMEGA * t, {"units": "rad", "long_name": "crank angle"}),
            "slider_position": (
                ("time", "body"),
                state[:, :1],
                {"units": "m", "long_name": "slider position"},
            ),
        },
        coords={"time": ("time", t, {"units": "s"}), "joint": ["A", "C"], "body": ["slider"]},
        attrs={
            "title": f"Duffing stand-in, {wear}",
            "scene": json.dumps({**SCENE, "wear": wear}),
            "scene_name": "duffing-standin",
        },
    )
    return chaoskit.load_trajectory(ds)


@pytest.fixture(scope="module")
def trajectories() -> dict[str, xr.Dataset]:
    return {
        "before wear": _trajectory(0.28, 60, wear="before"),
        "after wear": _trajectory(0.5, 100, wear="after"),
    }


METRICS = pd.DataFrame(
    {"peak_contact_force": [9500.0, 21000.0], "max_penetration": [8.1e-5, 1.5e-4]},
    index=pd.Index(list(STATES), name="state"),
)
PAPER = pd.DataFrame(
    {"peak_contact_force": [9182.0, 23330.0], "max_penetration": [8.03e-5, 1.46e-4]},
    index=pd.Index(list(STATES), name="state"),
)
CHAOS_PAPER = pd.DataFrame(
    {
        "lag": [24, 24],
        "embedding_dim": [5, 6],
        "mle_wolf_bits": [0.001, 0.0042],
        "verdict": ["periodic", "chaotic"],
    },
    index=pd.MultiIndex.from_tuples([("X", s) for s in STATES], names=["variable", "state"]),
)


def _sweep() -> xr.Dataset:
    clear = [1e-4, 2e-4, 5e-4]
    speed = [30, 90, 150]
    wear = ["before", "after"]
    rng = np.random.default_rng(3)
    shape = (3, 3, 2, 1)
    mle = rng.normal(0.0, 50.0, shape)
    mle[0, 0, 0, 0] = np.nan  # a failed point
    label = np.where(mle > 0, "chaotic", "periodic").astype(object)
    label[0, 0, 0, 0] = ""
    status = np.full(shape[:3], "ok", dtype=object)
    status[0, 0, 0] = "failed"
    dims = ("joints.C.clearance", "drive.speed_rpm", "wear", "variable")
    return xr.Dataset(
        {
            "mle_rosenstein": (dims, mle, {"units": "s-1", "long_name": "largest exponent"}),
            "label": (dims, label, {"long_name": "verdict"}),
            "status": (dims[:3], status),
        },
        coords={
            "joints.C.clearance": ("joints.C.clearance", clear, {"units": "m"}),
            "drive.speed_rpm": ("drive.speed_rpm", speed, {"units": "rpm"}),
            "wear": wear,
            "variable": ["eccentricity_x"],
        },
    )


def _bifurcation() -> xr.Dataset:
    runs = [
        xr.Dataset(
            {"x": ("step", systems.logistic(150, r=r), {"units": "1", "long_name": "x"})},
            coords={"step": np.arange(150)},
            attrs={"r": r},
        )
        for r in (2.8, 3.2, 3.5, 3.9)
    ]
    return chaoskit.bifurcation_diagram(runs, parameter="r", variable="x", last=100)


def _extra_figure() -> ReportFigure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3, 2))
    fig.subplots().plot([0, 1], [1, 0])
    return ReportFigure.from_matplotlib(fig, caption="A caller's own figure.", name="extra")


@pytest.fixture(scope="module")
def built(trajectories, tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "study.html"
    rep = chaoskit.report(
        trajectories,
        variables={"X": "eccentricity_x[joint=C]"},
        phase_variable="crank_angle",
        title="Stand-in study",
        output=out,
        options=ReportOptions(rng=0),
        extras=ReportExtras(
            chaos_reference=CHAOS_PAPER,
            reference_name="paper",
            chaos_notes="The stand-in is not the paper's mechanism.",
            tables=[
                ReportTable(
                    caption="Response metrics before and after wear.",
                    data=METRICS,
                    reference=PAPER,
                    reference_name="paper",
                    ratio=("after wear", "before wear"),
                    labels={
                        "peak_contact_force": "peak contact force (N)",
                        "max_penetration": "max penetration (m)",
                    },
                )
            ],
            sweep_maps=[
                SweepMap(
                    data=_sweep(),
                    x="drive.speed_rpm",
                    y="joints.C.clearance",
                    select={"wear": "after"},
                )
            ],
            bifurcations=[_bifurcation()],
            figures=[_extra_figure()],
            parameters={"revolutions": 10, "integrator": {"rtol": 1e-5}},
            command="chaoskit report before.nc after.nc",
        ),
    )
    return rep, out


# ------------------------------------------------------------------ HTML parsing


class _Page(HTMLParser):
    """Tables (caption, header rows, body rows) and figures (img src, caption) of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.tables: list[dict] = []
        self.figures: list[dict] = []
        self.codes: list[str] = []
        self._stack: list[str] = []
        self._text: list[str] | None = None
        self._row: list[str] | None = None
        self._in_code = False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self._stack.append(tag)
        if tag == "table":
            self.tables.append({"caption": "", "head": [], "body": []})
        elif tag == "figure":
            self.figures.append({"src": None, "caption": "", "alt": ""})
        elif tag == "img" and self.figures:
            self.figures[-1]["src"] = attrs.get("src")
            self.figures[-1]["alt"] = attrs.get("alt", "")
        elif tag == "tr":
            self._row = []
        elif tag in ("th", "td", "caption", "figcaption"):
            self._text = []
        elif tag == "code":
            self._in_code = True
            self.codes.append("")

    def handle_endtag(self, tag):
        if tag in ("th", "td") and self._row is not None and self._text is not None:
            self._row.append("".join(self._text).strip())
            self._text = None
        elif tag == "tr" and self._row is not None:
            part = "head" if "thead" in self._stack else "body"
            self.tables[-1][part].append(self._row)
            self._row = None
        elif tag == "caption" and self._text is not None:
            self.tables[-1]["caption"] = "".join(self._text).strip()
            self._text = None
        elif tag == "figcaption" and self._text is not None:
            self.figures[-1]["caption"] = "".join(self._text).strip()
            self._text = None
        elif tag == "code":
            self._in_code = False
        if self._stack and self._stack[-1] == tag:
            self._stack.pop()
        elif tag in self._stack:
            while self._stack and self._stack.pop() != tag:
                pass

    def handle_data(self, data):
        if self._text is not None:
            self._text.append(data)
        if self._in_code:
            self.codes[-1] += data


@pytest.fixture(scope="module")
def page(built) -> _Page:
    _, out = built
    parser = _Page()
    parser.feed(out.read_text(encoding="utf-8"))
    return parser


def _markdown_tables(text: str) -> list[dict]:
    """Caption and rows of every pipe table (the caption is the bold line above)."""
    tables = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = re.match(r"^\*\*Table (\d+)\.\*\* (.*)$", lines[i])
        if m:
            j = i + 1
            while not lines[j].startswith("|"):
                j += 1
            rows = []
            while j < len(lines) and lines[j].startswith("|"):
                cells = re.split(r"(?<!\\)\|", lines[j].strip())[1:-1]
                # what a viewer shows: backslash escapes and entities resolved
                rows.append([html.unescape(re.sub(r"\\(.)", r"\1", c.strip())) for c in cells])
                j += 1
            caption = f"Table {m[1]}. " + html.unescape(re.sub(r"\\(.)", r"\1", m[2]))
            tables.append({"caption": caption, "head": rows[0], "body": rows[2:]})
            i = j
        else:
            i += 1
    return tables


# ------------------------------------------------------------------ tests


EXPECTED_TABLES = [
    "Verdict per variable and state",
    "Response metrics before and after wear",
    "Chaos table",
    "Values behind the map",
    "Evidence behind each verdict",
    "Provenance",
    "Inputs",
    "Analysis settings",
    "Parameters of the run",
]


def test_every_expected_table_is_in_the_page_numbered_and_captioned(built, page) -> None:
    rep, _ = built
    captions = [t["caption"] for t in page.tables]
    assert len(captions) == len(rep.tables) == len(EXPECTED_TABLES)
    for k, (caption, expected) in enumerate(zip(captions, EXPECTED_TABLES, strict=True)):
        assert caption.startswith(f"Table {k + 1}. {expected}"), caption
    for table in page.tables:
        assert table["body"] and all(len(r) == len(table["body"][0]) for r in table["body"])


def test_every_image_is_an_embedded_png_with_a_caption(built, page) -> None:
    rep, out = built
    # X: phase portrait, stroboscopic map, divergence; chaos map; bifurcation; the caller's
    # figure
    assert len(page.figures) == len(rep.figures) == 6
    html = out.read_text(encoding="utf-8")
    assert html.count("<img") == 6 and "http://" not in html and "https://" not in html
    for k, fig in enumerate(page.figures):
        assert fig["src"].startswith("data:image/png;base64,")
        raw = base64.b64decode(fig["src"].split(",", 1)[1], validate=True)
        assert raw.startswith(b"\x89PNG\r\n\x1a\n")
        with Image.open(io.BytesIO(raw)) as img:
            img.verify()
        with Image.open(io.BytesIO(raw)) as img:
            assert img.format == "PNG" and img.width > 100 and img.height > 100
        assert raw == rep.figures[k].png
        assert re.match(rf"^Figure {k + 1}\. \S", fig["caption"]), fig["caption"]
        assert len(fig["caption"]) > 30


def test_markdown_twin_lists_the_same_numbers_as_the_html(built, page) -> None:
    rep, out = built
    md = out.with_suffix(".md").read_text(encoding="utf-8")
    tables = _markdown_tables(md)
    assert [t["caption"] for t in tables] == [t["caption"] for t in page.tables]
    for md_table, html_table in zip(tables, page.tables, strict=True):
        assert md_table["body"] == html_table["body"], html_table["caption"]
    # and the same figures, as PNG files next to the twin, with the same captions
    links = re.findall(r"^!\[Figure (\d+)\]\(([^)]+)\)$", md, flags=re.M)
    assert [int(n) for n, _ in links] == list(range(1, len(rep.figures) + 1))
    for (n, link), fig in zip(links, rep.figures, strict=True):
        assert (out.parent / link).read_bytes() == fig.png
        assert f"**Figure {n}.** {markdown_text(fig.caption)}" in md


def test_chaos_table_numbers_are_those_of_an_independent_analysis(built, trajectories) -> None:
    rep, _ = built
    table = rep.table("Chaos table")
    shown = table.display()
    for state, ds in trajectories.items():
        series = ds[["eccentricity_x", "crank_angle"]].sel(joint="C", drop=True)
        alone = chaoskit.analyze(
            series, variables=["eccentricity_x"], phase_variable="crank_angle", rng=1
        )
        row = alone.sel(variable="eccentricity_x")
        ours = table.data.loc[("X", state)]
        for key in (
            "lag",
            "embedding_dim",
            "mle_wolf",
            "mle_wolf_low",
            "mle_wolf_high",
            "mle_rosenstein",
        ):
            np.testing.assert_allclose(float(ours[key]), float(row[key]), rtol=1e-12)
        dt = float(row["dt"])
        to_bits = dt / math.log(2.0)
        np.testing.assert_allclose(
            float(ours["mle_wolf_bits"]), float(row["mle_wolf"]) * to_bits, rtol=1e-12
        )
        np.testing.assert_allclose(
            [float(ours["mle_wolf_bits_low"]), float(ours["mle_wolf_bits_high"])],
            [float(row["mle_wolf_low"]) * to_bits, float(row["mle_wolf_high"]) * to_bits],
            rtol=1e-12,
        )
        wolf_label = "MLE Wolf (bit/sample) [95% CI]"

        def cells(label: str, column: str, state: str = state) -> str:
            # beside a reference the chaos table is long: one row per quantity
            return str(shown.loc[("X", state, label), (column, "")])

        expected = (
            f"{format_number(float(ours['mle_wolf_bits']))} "
            f"[{format_number(float(row['mle_wolf_low']) * to_bits)}, "
            f"{format_number(float(row['mle_wolf_high']) * to_bits)}]"
        )
        if (("X", state), "mle_wolf_bits") in table.marks:  # the verdict voted against it
            expected += " †"
        assert cells(wolf_label, "ours") == expected
        paper = float(CHAOS_PAPER.loc[("X", state), "mle_wolf_bits"])
        mine = float(ours["mle_wolf_bits"])
        diff = f"{100 * (abs(mine) - abs(paper)) / abs(paper):+.1f}"
        if mine * paper < 0:
            diff += ", opposite sign"
        assert cells(wolf_label, "paper") == format_number(paper, 6)
        assert cells(wolf_label, "difference (%)") == diff
        assert cells("lag (samples)", "ours") == format_number(float(row["lag"]))
    # joint C (Duffing) was analysed, not joint A (a sine): the verdicts say so
    assert table.data.loc[("X", "before wear"), "verdict"] == "periodic"
    assert table.data.loc[("X", "after wear"), "verdict"] == "chaotic"
    assert shown.loc[("X", "after wear", "verdict"), ("difference (%)", "")] == "same"


def test_response_metrics_beside_the_paper_with_ratios_and_differences(built) -> None:
    rep, _ = built
    shown = rep.table("Response metrics").display()
    ratio = "ratio after wear / before wear"
    assert list(shown.index) == [*STATES, ratio]
    force = "peak contact force (N)"
    for state in STATES:
        ours, paper = METRICS.at[state, "peak_contact_force"], PAPER.at[state, "peak_contact_force"]
        assert shown.at[state, (force, "ours")] == format_number(ours)
        assert shown.at[state, (force, "paper")] == format_number(paper, 6)
        assert shown.at[state, (force, "difference (%)")] == f"{100 * (ours - paper) / paper:+.1f}"
    ours_ratio = 21000.0 / 9500.0
    paper_ratio = 23330.0 / 9182.0  # the paper's "increased by 1.54 times" = ratio 2.54
    assert shown.at[ratio, (force, "ours")] == format_number(ours_ratio) == "2.211"
    assert shown.at[ratio, (force, "paper")] == format_number(paper_ratio, 6) == "2.54084"
    assert shown.at[ratio, (force, "difference (%)")] == (
        f"{100 * (ours_ratio - paper_ratio) / paper_ratio:+.1f}"
    )


def test_sweep_map_table_holds_the_selected_slice(built) -> None:
    rep, _ = built
    table = rep.table("Values behind the map").data
    sweep = _sweep().sel(wear="after", variable="eccentricity_x")
    for (c, s), row in table.iterrows():
        point = {"joints.C.clearance": c, "drive.speed_rpm": s}
        expected = float(sweep["mle_rosenstein"].sel(point))
        np.testing.assert_equal(float(row["mle"]), expected)
        assert row["verdict"] == ("chaotic" if expected > 0 else "periodic")
    assert len(table) == 9


def test_provenance_has_versions_command_date_and_the_scene(built, page) -> None:
    rep, _ = built
    prov = dict(
        zip(rep.table("Provenance").data.index, rep.table("Provenance").data["value"], strict=True)
    )
    assert prov["chaoskit"] == chaoskit.__version__
    assert prov["numpy"] == np.__version__ and prov["pandas"] == pd.__version__
    assert prov["command"] == "chaoskit report before.nc after.nc"
    assert re.match(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00$", prov["created (UTC)"])
    scenes = [json.loads(code) for code in page.codes if code.lstrip().startswith("{")]
    assert {json.dumps(s, sort_keys=True) for s in scenes} == {
        json.dumps({**SCENE, "wear": w}, sort_keys=True) for w in ("before", "after")
    }
    # the provenance is the last section
    assert rep.sections[-1].title == "Parameters and provenance"
    params = rep.table("Parameters of the run").data["value"]
    assert params["integrator"] == '{"rtol": 1e-05}' and params["revolutions"] == "10"


def test_report_analysis_dataset_stacks_the_states(built) -> None:
    rep, _ = built
    assert rep.analysis is not None
    assert list(rep.analysis["state"].values) == list(STATES)
    assert list(rep.analysis["variable"].values) == ["X"]
    assert set(rep.verdicts) == set(STATES)


def test_markdown_can_embed_figures(built) -> None:
    rep, _ = built
    md = rep.to_markdown(figures="embed")
    assert md.count("](data:image/png;base64,") == len(rep.figures)


# ------------------------------------------------------------------ selection and inputs


def test_variable_specs_and_selection(trajectories) -> None:
    ds = trajectories["before wear"]
    spec = parse_variable("X = eccentricity_x[joint=C]")
    assert (spec.alias, spec.name, dict(spec.selectors)) == ("X", "eccentricity_x", {"joint": "C"})
    assert parse_variable("eccentricity_x[joint=C]").alias == "eccentricity_x[joint=C]"
    picked = select_series(ds, spec)
    np.testing.assert_array_equal(picked.values, ds["eccentricity_x"].sel(joint="C").values)
    assert picked.dims == ("time",) and picked.name == "X"
    assert picked.attrs["units"] == "m" and "joint C" in picked.attrs["long_name"]
    by_sel = select_series(ds, "eccentricity_x", sel={"joint": "A"})
    np.testing.assert_array_equal(by_sel.values, ds["eccentricity_x"].sel(joint="A").values)
    # a spec's own selection wins over sel=
    np.testing.assert_array_equal(
        select_series(ds, "eccentricity_x[joint=C]", sel={"joint": "A"}).values, picked.values
    )
    # an extra dimension of length 1 is squeezed
    squeezed = select_series(ds, "slider_position")
    assert squeezed.dims == ("time",)
    with pytest.raises(ValueError, match=r"extra dimensions \{'joint': \['A', 'C'\]\}"):
        select_series(ds, "eccentricity_x")
    with pytest.raises(ValueError, match="joint='B' not found"):
        select_series(ds, "eccentricity_x[joint=B]")
    with pytest.raises(ValueError, match="no dimension"):
        select_series(ds, "crank_angle[joint=C]")
    with pytest.raises(ValueError, match="DIM=VALUE"):
        parse_variable("eccentricity_x[joint]")
    with pytest.raises(ValueError, match="not found"):
        select_series(ds, "nope")


def test_numeric_coordinates_are_selected_by_value() -> None:
    t = np.arange(5.0)
    strain = np.arange(15.0).reshape(5, 3)
    ds = xr.Dataset(
        {"strain": (("time", "station"), strain, {"units": "1", "long_name": "axial strain"})},
        coords={"time": t, "station": [0.0, 0.25, 0.5]},
    )
    np.testing.assert_array_equal(select_series(ds, "strain[station=0.25]").values, strain[:, 1])
    np.testing.assert_array_equal(
        select_series(ds, "strain", sel={"station": 0.5}).values, strain[:, 2]
    )
    with pytest.raises(ValueError, match=r"station=0.3 not found.*\[0.0, 0.25, 0.5\]"):
        select_series(ds, "strain[station=0.3]")
    with pytest.raises(ValueError, match="station is numeric"):
        select_series(ds, "strain[station=mid]")


def test_bad_inputs_raise_clear_errors(trajectories) -> None:
    with pytest.raises(ValueError, match="extra dimensions"):
        chaoskit.report(trajectories, variables=["eccentricity_x"])
    with pytest.raises(ValueError, match="variables="):
        chaoskit.report(trajectories)
    with pytest.raises(ValueError, match="labels has 1"):
        chaoskit.report(list(trajectories.values()), variables=["crank_angle"], labels=["a"])
    with pytest.raises(ValueError, match="distinct"):
        chaoskit.report(list(trajectories.values()), variables=["crank_angle"], labels=["a", "a"])
    with pytest.raises(ValueError, match="discard"):
        chaoskit.report(trajectories, variables=["crank_angle"], discard=-1.0)
    with pytest.raises(ValueError, match="ReportTable"):
        chaoskit.report(extras=ReportExtras(tables=[METRICS]))
    with pytest.raises(ValueError, match="ratio must name two rows"):
        ReportTable(caption="x", data=METRICS, ratio=("after", "before wear"))
    with pytest.raises(ValueError, match="caption"):
        ReportTable(caption=" ", data=METRICS)
    with pytest.raises(ValueError, match="PNG"):
        ReportFigure(caption="x", png=b"GIF89a")


def test_chaos_reference_with_unknown_columns_is_refused(trajectories) -> None:
    ref = CHAOS_PAPER.rename(columns={"lag": "delay"})
    with pytest.raises(ValueError, match="delay"):
        chaoskit.report(
            {"before wear": trajectories["before wear"]},
            variables={"X": "eccentricity_x[joint=C]"},
            drive_period=DRIVE,
            extras=ReportExtras(chaos_reference=ref),
            options=ReportOptions(max_samples=1000),
        )


def test_tables_only_report_and_long_layout(tmp_path) -> None:
    table = ReportTable(
        caption="Metrics in long layout.",
        data=METRICS,
        reference=PAPER,
        reference_name="paper",
        layout="long",
    )
    rep = chaoskit.report(title="Tables only", extras=ReportExtras(tables=[table], command="test"))
    shown = rep.tables[0].display()
    assert list(shown.columns.get_level_values(0)) == ["ours", "paper", "difference (%)"]
    assert shown.loc[("after wear", "peak_contact_force")].tolist() == ["21000", "23330", "-10.0"]
    written = rep.write(tmp_path / "tables.html")
    assert written["markdown"].exists() and written["figures"] == []
    assert rep.analysis is None and [s.title for s in rep.sections] == [
        "Response metrics",
        "Parameters and provenance",
    ]


def test_format_number() -> None:
    assert format_number(43.41) == "43.41"
    assert format_number(-799.7) == "-799.7"
    assert format_number(23330.0) == "23330"
    assert format_number(0.0042) == "0.0042"
    assert format_number(1.234567e-5) == "1.235e-05"
    assert format_number(2.5e9) == "2.5e+09"
    assert format_number(24) == "24"
    assert format_number(float("nan")) == "—" and format_number(None) == "—"
    assert format_number(float("inf")) == "∞"
    assert format_number(True) == "yes" and format_number("chaotic") == "chaotic"


def test_difference_compares_magnitudes_so_negative_quantities_read_right() -> None:
    from chaoskit.reporting._content import _difference

    # a torque of -184.6 N m against the paper's -478.5: ours is 61.4 % smaller
    assert _difference(-184.6, -478.5) == "-61.4"
    assert _difference(478.5 * 1.1, 478.5) == "+10.0"
    assert _difference(173.7, -799.7) == f"{100 * (173.7 - 799.7) / 799.7:+.1f}, opposite sign"
    assert _difference(1.0, 0.0) == "—"


def test_motion_verdict_comes_first_one_per_state(trajectories) -> None:
    from types import SimpleNamespace

    eq = {"after wear": SimpleNamespace(exponent=0.1, ci=(0.05, 0.15))}
    rep = chaoskit.report(
        trajectories,
        variables={"X": "eccentricity_x[joint=C]", "A": "eccentricity_x[joint=A]"},
        phase_variable="crank_angle",
        extras=ReportExtras(exponents=eq),
        options=ReportOptions(rng=0),
    )
    assert rep.sections[0].title == "Motion verdict"
    assert set(rep.motions) == set(STATES)
    after, before = rep.motions["after wear"], rep.motions["before wear"]
    # joint A moves as a sine of the crank angle: it follows the drive and is set aside
    assert after.drive_variables == ("A",) and before.drive_variables == ("A",)
    assert after.label == "chaotic" and after.equations_say == "chaotic"
    assert (before.label, before.period) == ("periodic", 2)
    assert rep.verdicts["after wear"]["X"] is after.variables["X"]  # one analysis, not two
    table = rep.table("The motion verdict").data
    assert table.loc["after wear", "verdict"] == "chaotic"
    assert table.loc["before wear", "set_aside"] == "A"
    assert table.loc["after wear", "equations"] == pytest.approx(0.1)
    with pytest.raises(ValueError, match="exponents names states"):
        chaoskit.report(
            trajectories,
            variables=["crank_angle"],
            extras=ReportExtras(exponents={"nope": eq}),
        )


def test_states_classified_on_an_executor_give_the_same_verdicts(trajectories) -> None:
    import pickle
    from concurrent.futures import ThreadPoolExecutor

    def build(executor: object) -> chaoskit.Report:
        return chaoskit.report(
            trajectories,
            variables={"X": "eccentricity_x[joint=C]", "A": "eccentricity_x[joint=A]"},
            phase_variable="crank_angle",
            options=ReportOptions(rng=0, executor=executor),
        )

    here = build(None)
    with ThreadPoolExecutor(2) as pool:
        there = build(pool)
    # each state has its own stream: the same numbers, not merely the same labels
    assert there.analysis.identical(here.analysis)
    assert there.table("Chaos table").data.equals(here.table("Chaos table").data)
    for state in STATES:
        assert there.motions[state].label == here.motions[state].label
        assert there.motions[state].confidence == here.motions[state].confidence
        assert there.motions[state].label != "undetermined"
    # what a process pool sends back survives pickling
    back = pickle.loads(pickle.dumps((here.motions, here.verdicts)))
    assert {s: m.label for s, m in back[0].items()} == {s: m.label for s, m in here.motions.items()}
    with pytest.raises(ValueError, match="executor must be None or an executor"):
        chaoskit.report(
            trajectories, variables=["crank_angle"], options=ReportOptions(executor=object())
        )
