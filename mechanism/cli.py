"""Simulator command line: a thin layer that loads, calls the library and prints."""

from __future__ import annotations

import typer

from chaoskit._version import __version__

app = typer.Typer(
    name="mechanism",
    help="Simulate planar rigid-flexible mechanisms with clearance joints and wear.",
    no_args_is_help=True,
    add_completion=False,
)


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"mechanism (chaoskit {__version__})")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
) -> None:
    """mechanism command line."""


# --- scenes (issue 5, scene loading): commands below this line only ---


# --- simulation (issue 5, core): commands below this line only ---


# --- wear (issue 7): commands below this line only ---


# --- flexibility (issue 6): commands below this line only ---
