"""Command-line interface: a thin layer that loads, calls the library and prints."""

from __future__ import annotations

from pathlib import Path

import typer

from ._version import __version__

app = typer.Typer(
    name="chaoskit",
    help="Decide from a trajectory whether the motion is periodic, quasi-periodic or chaotic.",
    no_args_is_help=True,
    add_completion=False,
)

DEFAULT_SAMPLE = Path("data") / "lorenz.nc"


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"chaoskit {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
) -> None:
    """chaoskit command line."""


@app.command()
def demo(
    path: Path = typer.Argument(DEFAULT_SAMPLE, help="Trajectory file (netCDF, CSV or npz)."),
) -> None:
    """Analyse a sample trajectory from data/ and print the result."""
    from ._io import load_trajectory

    ds = load_trajectory(path)
    typer.echo(f"{path}: {ds.attrs.get('title', '')}")
    names = ", ".join(map(str, ds.data_vars))
    typer.echo(f"  {ds.sizes.get('time', 0)} samples, variables: {names}")
