"""The scene commands: ``scenes`` (the built-in list) and ``show`` (a resolved scene)."""

from __future__ import annotations

import typer

from mechanism import list_scenes

from ._app import app
from ._common import SET_HELP, load_scene_option


@app.command("scenes")
def scenes_command() -> None:
    """List the built-in scenes with their descriptions."""
    table = list_scenes()
    width = max(map(len, table), default=0)
    for name, description in table.items():
        typer.echo(f"{name:<{width}}  {description}")


@app.command("show")
def show_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    as_json: bool = typer.Option(False, "--json", help="Print JSON instead of TOML."),
) -> None:
    """Print the resolved scene (after any --set changes) as TOML."""
    resolved = load_scene_option(scene, set_options)
    typer.echo(resolved.to_json() if as_json else resolved.to_toml(), nl=as_json)
