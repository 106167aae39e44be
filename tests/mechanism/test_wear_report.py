"""Wear profiles in figures and reports: the polar plot and the report section."""

from __future__ import annotations

import matplotlib.pyplot as plt  # tests/conftest.py selects the Agg backend
import numpy as np
import pytest
import xarray as xr

import chaoskit
import mechanism
from mechanism.studies._wear_report import _worn_arcs


def _rendered(ax) -> bool:
    ax.figure.canvas.draw()
    pixels = np.asarray(ax.figure.canvas.buffer_rgba())
    plt.close(ax.figure)
    return pixels.std() > 0


def _profile(n: int = 360) -> xr.Dataset:
    phi = 2 * np.pi * (np.arange(n) + 0.5) / n
    depth = 1e-6 * (2.0 + np.cos(phi) ** 2)
    return xr.Dataset(
        {
            "wear_depth": ("angle", depth, {"units": "m", "long_name": "bearing wear depth"}),
            "journal_wear_depth": ("angle", 0.5 * depth, {"units": "m", "long_name": "journal"}),
            "curvature_radius": ("angle", np.full(n, 0.015), {"units": "m", "long_name": "rho"}),
        },
        coords={"angle": ("angle", phi, {"units": "rad"})},
    )


class _ProfileObject:
    """Stands for a simulator's wear-profile object: anything with to_dataset()."""

    def to_dataset(self) -> xr.Dataset:
        return _profile(90)


def test_wear_profile_draws_depths_in_micrometres_on_a_closed_polar_curve() -> None:
    ds = _profile()
    ax = mechanism.plot_wear_profile(ds, sectors=[(75, 132), (300, 20)])
    assert ax.name == "polar"
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == ["bearing wear depth", "journal"]  # no curvature
    theta, r = lines[0].get_data()
    np.testing.assert_allclose(r[:-1], ds["wear_depth"].values * 1e6, rtol=1e-12)
    np.testing.assert_allclose(theta[:-1], ds["angle"].values, rtol=1e-12)
    assert theta[-1] == pytest.approx(theta[0] + 2 * np.pi) and r[-1] == r[0]  # closed
    bars = ax.patches
    widths = sorted(np.rad2deg(b.get_width()) for b in bars)
    np.testing.assert_allclose(widths, [57.0, 80.0])  # 300° -> 20° wraps through 0°
    assert _rendered(ax)


def test_wear_profile_accepts_a_dataarray_an_object_and_a_given_polar_axes() -> None:
    fig = plt.figure()
    polar = fig.add_subplot(projection="polar")
    da = _profile()["wear_depth"]
    assert mechanism.plot_wear_profile(da, ax=polar) is polar
    assert _rendered(polar)
    ax = mechanism.plot_wear_profile(_ProfileObject(), variables="curvature_radius")
    _, r = ax.get_lines()[0].get_data()
    np.testing.assert_allclose(r, 0.015e6)
    plt.close(ax.figure)


def test_wear_profile_refuses_bad_input() -> None:
    _, flat = plt.subplots()
    with pytest.raises(ValueError, match="polar"):
        mechanism.plot_wear_profile(_profile(), ax=flat)
    plt.close(flat.figure)
    with pytest.raises(ValueError, match="angle"):
        mechanism.plot_wear_profile(xr.Dataset({"h": ("x", np.ones(4))}))
    with pytest.raises(ValueError, match="not 1-D along 'angle'"):
        mechanism.plot_wear_profile(_profile(), variables=["nope"])


ZONES = [(75.0, 132.0), (252.0, 310.0)]


def _zoned_profile() -> xr.Dataset:
    """360 regions; bearing wear only inside the two zones (deepest 12 µm at 100°)."""
    centre = np.arange(360) + 0.5
    inside = ((centre > 75) & (centre < 132)) | ((centre > 252) & (centre < 310))
    depth = np.where(inside, 6e-6 + 6e-6 * np.exp(-(((centre - 100.5) / 10) ** 2)), 0.0)
    return xr.Dataset(
        {
            "wear_depth": ("angle", depth, {"units": "m", "long_name": "bearing wear depth"}),
            "journal_wear_depth": (
                "angle",
                0.5 * depth,
                {"units": "m", "long_name": "journal wear depth"},
            ),
        },
        coords={"angle": ("angle", np.deg2rad(centre), {"units": "rad"})},
    )


def test_wear_profile_table_finds_the_worn_arcs() -> None:
    section = mechanism.wear_profile_section({"after wear": _zoned_profile()}, sectors=ZONES)
    table = next(i for i in section.items if isinstance(i, chaoskit.ReportTable))
    bearing = table.data.loc[("after wear", "bearing wear depth")]
    np.testing.assert_allclose(float(bearing["max_depth"]), 12.0, rtol=1e-3)  # µm
    assert float(bearing["angle_of_max"]) == pytest.approx(100.5)
    assert bearing["arcs"] == "[75°, 132°], [252°, 310°]"
    journal = table.data.loc[("after wear", "journal wear depth")]
    np.testing.assert_allclose(float(journal["max_depth"]), 6.0, rtol=1e-3)


def test_worn_arcs_wrap_through_zero() -> None:
    centre = np.deg2rad(np.arange(360) + 0.5)
    depth = np.zeros(360)
    depth[350:] = depth[:10] = 1.0
    np.testing.assert_allclose(_worn_arcs(centre, depth, 0.1), [(350.0, 10.0)], atol=1e-9)
    depth[100:120] = 0.05  # below 10 % of the largest: not worn
    depth[200:220] = 0.5
    np.testing.assert_allclose(
        _worn_arcs(centre, depth, 0.1), [(200.0, 220.0), (350.0, 10.0)], atol=1e-9
    )
    assert _worn_arcs(centre, np.ones(360), 0.1) == [(0.0, 360.0)]
    assert _worn_arcs(centre, np.zeros(360), 0.1) == []


def _trajectory(wobble: float) -> xr.Dataset:
    t, s = chaoskit.systems.duffing(2000, gamma=wobble, samples_per_period=50)
    return chaoskit.load_trajectory(s, dt=t[1] - t[0], variables=["x", "v"])


def test_the_wear_section_joins_an_analysis_report_in_place_and_renumbered() -> None:
    rep = chaoskit.report(
        {"before": _trajectory(0.28)},
        variables=["x"],
        drive_period=2 * np.pi / 1.2,
        options=chaoskit.ReportOptions(rng=0),
    )
    section = mechanism.wear_profile_section(
        mechanism.WornProfile.unworn(bearing_radius=0.01, clearance=2e-4, length=0.02).with_depth(
            bearing_depth=_zoned_profile()["wear_depth"].values
        ),
        sectors=ZONES,
    )
    joined = rep.with_sections(section, after="Divergence curves")
    titles = [s.title for s in joined.sections]
    assert titles[titles.index("Divergence curves") + 1] == "Wear profiles"
    assert titles[-1] == "Parameters and provenance"
    assert [t.number for t in joined.tables] == list(range(1, len(joined.tables) + 1))
    assert [f.number for f in joined.figures] == list(range(1, len(joined.figures) + 1))
    wear = joined.table("Wear profiles")
    assert wear.section == "Wear profiles"
    assert len(joined.figures) == len(rep.figures) + 1
    assert len(joined.tables) == len(rep.tables) + 1
