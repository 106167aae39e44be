"""The paper report's route to chaos over crank speed, from the stored continuation."""

from __future__ import annotations

import json

import pytest

from mechanism.studies.paper._route import ROUTE_DATA, TITLE, route_section, stored_route


def _edge(kind: str, rpm: float, lo: float, hi: float, *, end: bool = True) -> dict:
    return {"kind": kind, "rpm": rpm, "bracket_rpm": [lo, hi], "period": 1,
            "branch_end": end, "explanation": ""}  # fmt: skip


def _data() -> dict:
    return {
        "scene": "paper, effects.flexibility = false, radial clearance 0.2 mm",
        "span_rpm": [30.0, 300.0],
        "locate_rpm": 0.5,
        "windows": [
            {
                "rpm": [71.19, 126.1],
                "onset": _edge("grazing", 64.4727, 64.4375, 64.5078),
                "closing": _edge("end", 127.5, 127.25, 127.75),
            },
            {"rpm": [148.98, 162.71], "onset": None, "closing": None},
        ],
        "branches": [],
        "coexistence": {
            "rpm": 150.0,
            "stable_orbits_followed": [],
            "basins": {
                "grid": "8x8",
                "revolutions": 24,
                "starts": 32,
                "extent": 0.9,
                "max_period": 4,
                "undetermined": 32,
                "periodic": 0,
                "cpu_s": 118.6,
            },
        },
        "cost": {"date": "2026-11-29", "cpu_s": 600.0, "orbit_solves": 80},
    }


def test_section_states_the_located_edges_and_the_coexistence() -> None:
    """Each window's opening and closing point with its value and bracket, and the answer
    on coexisting motions at 150 rpm, in the text and the table."""
    section = route_section(_data())
    assert section.title == TITLE
    assert (
        "The chaotic window 71 – 126 rpm is opened by the grazing at 64.47 rpm; going down "
        "from the regular motion above it, the periodic orbit ends abruptly (no multiplier "
        "near +-1, no grazing margin closing) at 127.50 rpm." in section.text
    )
    assert "The chaotic window 149 – 163 rpm is opened by no located point." in section.text
    assert (
        "At 150 rpm nothing periodic coexists with the chaotic motion: of 32 starts" in section.text
    )
    assert "no stable periodic orbit was followed there" in section.text
    table = section.items[0].data
    assert table.loc["71.2 – 126.1", "opened from below by"] == (
        "grazing at 64.47 rpm [64.44, 64.51] (end of a branch of period 1)"
    )
    assert table.loc["149.0 – 162.7", "regular motion above it ends in"] == "none located"
    assert "Recompute: NUMBA_NUM_THREADS=1 python benchmarks/continuation.py sweep" in (
        section.footer
    )


def test_stored_route_rejects_another_file(tmp_path) -> None:
    path = tmp_path / "other.json"
    path.write_text(json.dumps({"scene": "x"}))
    with pytest.raises(ValueError, match=r"is not a stored route: no span_rpm, windows"):
        stored_route(path)


def test_shipped_route_opens_the_first_window_with_a_located_point() -> None:
    """The shipped result (computed once by benchmarks/continuation.py) names what opens
    the first chaotic window, inside its bracket of at most 0.5 rpm."""
    data = stored_route()
    assert ROUTE_DATA.name == "route_rigid.json"
    first = data["windows"][0]
    assert first["rpm"][0] == pytest.approx(71.19, abs=0.01)
    onset = first["onset"]
    lo, hi = onset["bracket_rpm"]
    assert onset["kind"] in ("grazing", "fold", "period-doubling", "neimark-sacker", "end")
    assert lo <= onset["rpm"] <= hi and hi - lo <= 0.5 + 1e-9
    assert f"{onset['rpm']:.2f} rpm" in route_section(data).text
