"""Every figure function renders with the Agg backend and returns the Axes it drew on."""

from __future__ import annotations

import subprocess
import sys

import matplotlib.pyplot as plt  # tests/conftest.py selects the Agg backend
import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import plot, systems


@pytest.fixture(scope="module")
def verdict():
    return chaoskit.classify(systems.henon(600)[:, 0], rng=0)


@pytest.fixture(scope="module")
def flow() -> xr.Dataset:
    t = np.arange(0.0, 60.0, 0.05)
    return chaoskit.load_trajectory(
        np.column_stack([np.sin(t), np.cos(t), np.sin(0.5 * t)]), dt=0.05,
        variables=["x", "v", "w"],
    )  # fmt: skip


def _drawn(ax) -> bool:
    """The Axes holds data and the figure renders to pixels."""
    has_data = bool(ax.lines or ax.collections)
    ax.figure.canvas.draw()
    pixels = np.asarray(ax.figure.canvas.buffer_rgba())
    plt.close(ax.figure)
    return has_data and pixels.shape[0] > 0 and pixels.std() > 0


def test_phase_portrait_from_a_trajectory_and_from_a_portrait(flow) -> None:
    ax = plot.phase_portrait(flow, variable="x")
    assert ax.get_xlabel() and _drawn(ax)
    portrait = chaoskit.phase_portrait(flow, variable="w")
    _, given = plt.subplots()
    assert plot.phase_portrait(portrait, ax=given) is given
    assert _drawn(given)
    with pytest.raises(ValueError, match="variable"):
        plot.phase_portrait(flow)


def test_poincare_of_a_section_and_of_a_verdict(flow, verdict) -> None:
    sec = chaoskit.poincare_section(flow, variable="x")
    ax = plot.poincare(sec, x="v", y="w")
    assert ax.get_xlabel().startswith("v") and _drawn(ax)
    assert _drawn(plot.poincare(sec[["v"]]))  # one variable: the return map
    assert _drawn(plot.poincare(verdict))
    with pytest.raises(ValueError, match="section"):
        plot.poincare(flow)


def test_divergence_marks_the_fit_range(verdict) -> None:
    for result in (verdict.rosenstein, verdict.wolf):
        ax = plot.divergence(result)
        spans = [p for p in ax.patches]
        assert spans, "the fitted range is shaded"
        x0, x1 = spans[0].get_x(), spans[0].get_x() + spans[0].get_width()
        assert (x0, x1) == pytest.approx(tuple(result.fit_range))  # dt = 1 for a map
        assert _drawn(ax)


def test_mutual_information_and_fnn(verdict) -> None:
    ax = plot.mutual_information(verdict)
    assert any(line.get_label() == f"lag = {verdict.lag}" for line in ax.lines)
    assert _drawn(ax)
    ax = plot.false_nearest_neighbors(verdict.dimension)
    assert any(line.get_label() == f"m = {verdict.embedding_dim}" for line in ax.lines)
    assert _drawn(ax)


def test_bifurcation() -> None:
    runs = [
        xr.Dataset({"x": ("step", systems.logistic(100, r=r))}, coords={"step": np.arange(100)},
                   attrs={"r": r})
        for r in (3.2, 3.5, 3.9)
    ]  # fmt: skip
    diagram = chaoskit.bifurcation_diagram(runs, parameter="r", variable="x", last=50)
    ax = plot.bifurcation(diagram)
    assert ax.collections[0].get_offsets().shape == (150, 2)
    assert _drawn(ax)
    with pytest.raises(ValueError, match="bifurcation_diagram"):
        plot.bifurcation(runs[0])


def test_plotting_is_lazy_and_never_shows() -> None:
    code = "import sys, chaoskit, chaoskit.plot; sys.exit(int('matplotlib.pyplot' in sys.modules))"
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0
    source = (chaoskit.plot.__file__, chaoskit.plot._figures.__file__)
    for path in source:
        with open(path, encoding="utf-8") as fh:
            assert ".show(" not in fh.read()
