"""The ``convergence`` command: extreme rod strains against the elements per ANCF beam."""

from __future__ import annotations

import typer

from mechanism import SimulationError, element_convergence

from ._app import app
from ._common import SET_HELP, check_output_option, load_scene_option, write_output


@app.command("convergence")
def convergence_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    rod: list[str] | None = typer.Option(
        None, "--rod", help="ANCF beam to refine (repeatable; default: every beam)."
    ),
    elements: str = typer.Option(
        "4,8,12,16,20,24", "--elements", help="Comma-separated element counts."
    ),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="Simulated drive periods (default 1)."
    ),
    t_end: float | None = typer.Option(None, "--t-end", help="Simulated time in s."),
    method: str | None = typer.Option(None, "--method", help="Integrator (default: the scene's)."),
    output: str | None = typer.Option(None, "-o", "--output", help="Write the table (.nc)."),
    progress: bool = typer.Option(False, "--progress/--no-progress", help="Show progress bars."),
) -> None:
    """Element-convergence table: extreme rod strains (µε) against elements per rod."""
    path = None if output is None else check_output_option(output)
    resolved = load_scene_option(scene, set_options)
    try:
        counts = [int(x) for x in elements.split(",") if x.strip()]
    except ValueError:
        typer.echo(
            f"Error: --elements must be comma-separated integers; got {elements!r}.", err=True
        )
        raise typer.Exit(code=2) from None
    try:
        table = element_convergence(
            resolved,
            rods=rod or None,
            elements=counts,
            revolutions=revolutions,
            t_end=t_end,
            method=method,
            progress=progress,
        )
    except ValueError as exc:  # a bad option or scene: a user error
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    typer.echo(table.to_markdown())
    if path is not None:
        write_output(table.to_dataset(), path)
        typer.echo(f"{path}: written")
