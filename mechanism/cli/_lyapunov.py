"""The ``lyapunov`` command: the largest Lyapunov exponent of a scene from its equations."""

from __future__ import annotations

from pathlib import Path

import typer

from mechanism import LyapunovSettings, SimulationError, lyapunov_exponent
from mechanism.studies import DEFAULT_DEVIATION_RTOL

from ._app import app
from ._common import (
    SET_HELP,
    check_output_option,
    load_scene_option,
    write_output,
)


@app.command("lyapunov")
def lyapunov_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="Simulated drive periods, discarded ones included."
    ),
    t_end: float | None = typer.Option(
        None, "--t-end", help="Simulated time in s (scenes without a periodic drive)."
    ),
    discard: float = typer.Option(
        0.0, "--discard", help="Transient left out: drive periods (with --revolutions) or s."
    ),
    perturbation: float = typer.Option(
        1e-7, "--perturbation", help="Deviation size relative to the smallest clearance."
    ),
    renormalize_every: int = typer.Option(
        1, "--renormalize-every", help="Accepted steps between renormalisations."
    ),
    rtol: float | None = typer.Option(
        None, "--rtol", help="Relative tolerance (default 1e-8; a flexible scene's own)."
    ),
    atol: float | None = typer.Option(
        None, "--atol", help="Absolute tolerance (default 1e-8; a flexible scene's own)."
    ),
    deviation_rtol: float = typer.Option(
        DEFAULT_DEVIATION_RTOL,
        "--deviation-rtol",
        help="Relative tolerance of the deviation's error per step (0: the reference's steps).",
    ),
    output: str | None = typer.Option(
        None, "-o", "--output", help="Write the running estimate to this netCDF file."
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar."),
) -> None:
    """Largest Lyapunov exponent of a scene from its equations of motion."""
    if output is not None:
        check_output_option(output)
    resolved = load_scene_option(scene, set_options)
    if revolutions is None and t_end is None:
        revolutions = 100.0
    try:
        result = lyapunov_exponent(
            resolved,
            revolutions=revolutions,
            t_end=t_end,
            discard=discard,
            settings=LyapunovSettings(
                perturbation=perturbation,
                renormalize_every=renormalize_every,
                rtol=rtol,
                atol=atol,
                deviation_rtol=deviation_rtol,
            ),
            progress=progress,
        )
    except ValueError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    low, high = result.ci
    line = f"{resolved.name}: largest Lyapunov exponent {result.exponent:.6g} 1/s"
    if result.drive_period is not None:
        line += f" ({result.exponent_per_period:.4g} per drive period)"
    typer.echo(f"{line}, 95 % interval [{low:.6g}, {high:.6g}] 1/s")
    if result.stats is not None:
        typer.echo(
            f"{result.stats.steps} steps, {result.renormalizations} renormalisations, "
            f"{result.stats.contact_events} contact events, {result.stats.wall_time:.3g} s"
        )
    if output is not None:
        write_output(result.to_dataset(), Path(output))
        typer.echo(f"wrote {output}")
