"""CLI skeletons answer --help and --version."""

from __future__ import annotations

from typer.testing import CliRunner

import chaoskit
from chaoskit.cli import app as chaoskit_app
from mechanism.cli import app as mechanism_app

runner = CliRunner()


def test_chaoskit_version_and_help() -> None:
    out = runner.invoke(chaoskit_app, ["--version"])
    assert out.exit_code == 0 and chaoskit.__version__ in out.output
    assert runner.invoke(chaoskit_app, ["--help"]).exit_code == 0


def test_mechanism_version_and_help() -> None:
    out = runner.invoke(mechanism_app, ["--version"])
    assert out.exit_code == 0 and chaoskit.__version__ in out.output
    assert runner.invoke(mechanism_app, ["--help"]).exit_code == 0
