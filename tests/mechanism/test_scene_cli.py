"""CLI: ``mechanism scenes``, ``mechanism show`` and the shared ``--set`` parser."""

from __future__ import annotations

import pytest
import typer
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app, load_scene_option, parse_set_options
from mechanism.core.scene import scene_from_json, scene_from_toml

runner = CliRunner()


def test_scenes_lists_every_builtin_with_its_description() -> None:
    out = runner.invoke(app, ["scenes"])
    assert out.exit_code == 0
    for name, description in mechanism.list_scenes().items():
        assert any(
            line.split()[0] == name and description in line for line in out.output.splitlines()
        )


def test_show_prints_the_resolved_scene_as_toml() -> None:
    out = runner.invoke(
        app, ["show", "paper", "--set", "joints.C.clearance=5e-4", "--set", "drive.speed_rpm=90"]
    )
    assert out.exit_code == 0, out.output
    shown = scene_from_toml(out.output)
    expected = mechanism.load_scene("paper").replace(
        {"joints.C.clearance": 5e-4, "drive.speed_rpm": 90.0}
    )
    assert shown == expected
    out = runner.invoke(app, ["show", "slider-crank", "--json"])
    assert scene_from_json(out.output) == mechanism.load_scene("slider-crank")


def test_show_reads_a_file(tmp_path) -> None:
    path = mechanism.save_scene(mechanism.load_scene("slider-crank-clearance"), tmp_path / "s.toml")
    out = runner.invoke(app, ["show", str(path)])
    assert out.exit_code == 0 and scene_from_toml(out.output) == mechanism.load_scene(path)


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (
            ["show", "paper", "--set", "joints.C.clearance=-1"],
            "joints.C.clearance: must be in [1e-08, 1] (m)",
        ),
        (["show", "paper", "--set", "joints.C.clearence=1e-4"], "valid keys there"),
        (["show", "no-such-scene"], "no built-in scene or file named"),
    ],
)
def test_show_reports_scene_errors_with_exit_code_2(args: list[str], fragment: str) -> None:
    out = runner.invoke(app, args)
    assert out.exit_code == 2
    assert fragment in out.output


def test_show_rejects_a_set_option_without_a_value() -> None:
    out = runner.invoke(app, ["show", "paper", "--set", "joints.C.clearance"])
    assert out.exit_code == 2


def test_parse_set_options_reads_toml_literals() -> None:
    parsed = parse_set_options(
        [
            "joints.C.clearance=2e-4",
            "bodies.rod3.elements=8",
            "effects.wear=true",
            "gravity=[0.0, -1.62]",
            'joints.C.contact={ law = "hertz" }',
            "solver.method=Radau",
            'description="quoted = text"',
            "name = spaced ",
            "drive.speed_rpm=1",
            "drive.speed_rpm=2",
        ]
    )
    assert parsed == {
        "joints.C.clearance": 2e-4,
        "bodies.rod3.elements": 8,
        "effects.wear": True,
        "gravity": [0.0, -1.62],
        "joints.C.contact": {"law": "hertz"},
        "solver.method": "Radau",
        "description": "quoted = text",
        "name": "spaced",
        "drive.speed_rpm": 2,
    }
    assert type(parsed["bodies.rod3.elements"]) is int
    assert parse_set_options(None) == {} and parse_set_options([]) == {}
    for bad in ["novalue", "=1", "a..b=1"]:
        with pytest.raises(typer.BadParameter):
            parse_set_options([bad])


def test_load_scene_option_applies_changes() -> None:
    scene = load_scene_option("paper", ["effects.clearance=false", "drive.speed_rpm=30"])
    assert scene.effects.clearance is False and scene.drive.speed_rpm == 30.0  # type: ignore[union-attr]
    assert load_scene_option("paper") == mechanism.load_scene("paper")
