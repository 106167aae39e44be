"""The ``continuation`` command: periodic orbits followed over a scene key, with their
bifurcations and the route to chaos."""

from __future__ import annotations

from pathlib import Path

import typer
import xarray as xr

from mechanism import ContinuationSettings, SimulationError, continuation, route

from ._app import app
from ._common import SET_HELP, check_output_option, load_scene_option, write_output


@app.command("continuation")
def continuation_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    parameter: str = typer.Option(
        ..., "--parameter", help="Scene key to vary, e.g. drive.speed_rpm."
    ),
    start: float = typer.Option(..., "--start", help="First value of the key."),
    stop: float = typer.Option(..., "--stop", help="Last value of the key."),
    step: float | None = typer.Option(
        None, "--step", help="First step (default 1/100 of the span); steps grow to 4 times it."
    ),
    locate: float | None = typer.Option(
        None, "--locate", help="Width a bifurcation is located to (default 1/1000 of the span)."
    ),
    max_period: int = typer.Option(
        2, "--max-period", help="Largest period followed after period doublings (>= 1)."
    ),
    windows: str | None = typer.Option(
        None,
        "--windows",
        help="A bifurcation netCDF file with the exponent: print the route to its chaotic windows.",
    ),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    output: str | None = typer.Option(
        None, "-o", "--output", help="Write the branches and bifurcations to this netCDF file."
    ),
) -> None:
    """Follow a periodic orbit of a rigid scene over one key and name its bifurcations."""
    if output is not None:
        check_output_option(output)
    resolved = load_scene_option(scene, set_options)
    width = abs(stop - start)
    try:
        if not start != stop:
            raise ValueError(f"--start and --stop must differ; got {start:g} and {stop:g}.")
        first = step if step is not None else width / 100
        settings = ContinuationSettings(
            step=first, min_step=first / 64, max_step=4 * first,
            locate_tolerance=locate if locate is not None else width / 1e3,
            max_period=max_period, easy_iterations=5, max_iterations=8,
        )  # fmt: skip
        diagram = None
        if windows is not None:
            if not Path(windows).is_file():
                raise ValueError(f"--windows: no file {windows!r}.")
            diagram = xr.load_dataset(windows)
        result = continuation(resolved, parameter=parameter, span=(start, stop), settings=settings)
        path = route(result, diagram) if diagram is not None else None
    except ValueError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    units = result.units
    for i, branch in enumerate(result.branches):
        p = branch.parameter
        typer.echo(
            f"branch {i} (period {branch.period}, {branch.origin}): {p[0]:.6g}–{p[-1]:.6g} "
            f"{units}, {len(p)} points, {int(branch.stable.sum())} stable; {branch.end}"
        )
    for bif in result.bifurcations:
        typer.echo(f"{bif.kind} at {bif.parameter:.6g} {units}: {bif.explanation}")
    if path is not None:
        for line in path.lines():
            typer.echo(line)
    typer.echo(f"{result.orbit_solves} orbit solves, {result.cpu_time:.3g} s CPU")
    if output is not None:
        write_output(result.to_dataset(), Path(output))
        typer.echo(f"wrote {output}")
