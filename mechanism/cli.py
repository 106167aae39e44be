"""Command-line interface of the simulator: a thin layer that loads, calls the library and prints."""

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
