"""Warnings a user needs: contact deeper than the law allows, and runs that need gigabytes."""

from __future__ import annotations

import warnings

import pytest

import mechanism
from mechanism.core import _run_checks
from mechanism.core.model import assemble

SCENE = mechanism.load_scene("slider-crank-clearance")  # c = 0.5 mm at joint B


@pytest.mark.parametrize(
    ("change", "low", "high"),
    [
        ({"drive.speed_rpm": 20000.0}, 0.50, 0.60),  # measured 53 % of the clearance
        ({"joints.B.clearance": 1e-7}, 5.0, 20.0),  # measured 11 times the clearance
    ],
)
def test_penetration_beyond_half_the_clearance_warns(change, low, high) -> None:
    scene = SCENE.replace(change)
    with pytest.warns(_run_checks.SimulationWarning, match=r"joint B: the largest penetration"):
        ds = mechanism.simulate(scene, revolutions=1)
    ratio = float(ds["penetration"].max()) / float(scene.joints["B"].clearance)
    assert low < ratio < high


def test_an_ordinary_run_is_silent() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = mechanism.simulate(SCENE, revolutions=1)  # measured 16 % of the clearance
    assert float(ds["penetration"].max()) < 0.5 * float(SCENE.joints["B"].clearance)


def test_a_run_above_the_stated_size_warns_before_it_starts(monkeypatch) -> None:
    monkeypatch.setattr(_run_checks, "OUTPUT_WARNING_BYTES", 10**5)
    with pytest.warns(_run_checks.SimulationWarning, match=r"will hold about .* GB") as rec:
        mechanism.simulate(SCENE, revolutions=0.02, progress=False)
    assert rec[0].filename == __file__  # attributed to the caller of simulate


@pytest.mark.parametrize(
    ("name", "change"),
    [
        ("slider-crank-clearance", {}),
        ("slider-crank", {}),
        ("paper", {"effects.flexibility": False}),
        ("paper", {}),
    ],
)
def test_the_size_estimate_bounds_the_output_from_above(name, change) -> None:
    scene = mechanism.load_scene(name).replace(change) if change else mechanism.load_scene(name)
    ds = mechanism.simulate(scene, revolutions=0.02)
    model = assemble(scene)
    models = [model, model] if model.clearance_joints else [model]
    estimate = _run_checks.estimated_run_bytes(models, ds.sizes["time"])
    assert ds.nbytes <= estimate <= 12 * ds.nbytes


def test_the_size_estimate_of_a_million_rpm_run() -> None:
    """1e6 rpm for a tenth of a second at the default grid (T/10 000): ~17 M samples."""
    scene = SCENE.replace({"drive.speed_rpm": 1e6})
    period = 60.0 / 1e6
    n_out = round(0.1 / (period / 10_000)) + 1
    model = assemble(scene)
    estimate = _run_checks.estimated_run_bytes([model, model], n_out)
    assert estimate > _run_checks.OUTPUT_WARNING_BYTES
