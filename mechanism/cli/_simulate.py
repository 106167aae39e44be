"""The ``simulate`` command: one run of a scene written as a trajectory, metrics or sections."""

from __future__ import annotations

import typer

import chaoskit
from chaoskit.contract import check_choice
from mechanism import (
    FullRecord,
    MetricsRecord,
    RecordMode,
    SectionsRecord,
    SimulationError,
    simulate,
)

from ._app import app
from ._common import (
    SET_HELP,
    check_output_option,
    load_scene_option,
    warnings_as_lines,
    write_output,
)


def _record_option(record: str, discard: float, variables: list[str] | None) -> RecordMode:
    """The record mode that ``--record``, ``--discard`` and ``--var`` choose."""
    name = check_choice(record, name="record", choices=("full", "metrics", "sections"))
    if name == "full":
        if discard != 0.0:
            raise ValueError(
                "--discard applies to --record metrics and sections; slice the full trajectory."
            )
        return FullRecord(variables=variables or None)
    if variables:
        raise ValueError(f"--var applies to --record full only; got --record {name}.")
    mode = MetricsRecord if name == "metrics" else SectionsRecord
    return mode(discard=discard)


@app.command("simulate")
def simulate_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    output: str = typer.Option(..., "-o", "--output", help="Trajectory file (.nc)."),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    revolutions: float | None = typer.Option(
        None, "--revolutions", help="Simulated drive periods (default 1)."
    ),
    t_end: float | None = typer.Option(None, "--t-end", help="Simulated time in s."),
    method: str | None = typer.Option(
        None,
        "--method",
        help="auto (by the model: generalized-alpha-fixed with ANCF beams, else dopri5), "
        "dopri5, RK45, DOP853, Radau, BDF, LSODA, generalized-alpha or "
        "generalized-alpha-fixed (default: the scene's solver.method).",
    ),
    rtol: float | None = typer.Option(None, "--rtol", help="Relative tolerance."),
    atol: float | None = typer.Option(None, "--atol", help="Absolute tolerance."),
    output_step: float | None = typer.Option(
        None,
        "--output-step",
        help="Output spacing in s (default drive period / 10000; / 1000 for metrics and "
        "sections, where it only sets the grid of the slider errors).",
    ),
    record: str = typer.Option(
        "full",
        "--record",
        help="full (the trajectory), metrics (response metrics only) or sections "
        "(stroboscopic points and the metrics).",
    ),
    discard: float = typer.Option(
        0.0, "--discard", help="Revolutions treated as transient by metrics and sections."
    ),
    variables: list[str] | None = typer.Option(
        None,
        "--var",
        help="Record only this variable (repeatable; full record): crank_angle, "
        "slider_position, slider_velocity, eccentricity_x, eccentricity_y. A long run then "
        "holds a few arrays instead of the full state.",
    ),
    force: bool = typer.Option(
        False,
        "--force",
        help="Run even when the run is estimated to need more than 80 % of the available "
        "memory (refused by default).",
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar."),
) -> None:
    """Simulate a scene and write its trajectory, metrics or sections (netCDF)."""
    path = check_output_option(output)
    resolved = load_scene_option(scene, set_options)
    try:
        with warnings_as_lines():
            ds = simulate(
                resolved,
                revolutions=revolutions,
                t_end=t_end,
                method=method,
                rtol=rtol,
                atol=atol,
                output_step=output_step,
                record=_record_option(record, discard, variables),
                progress=progress,
                force=force,
            )
    except ValueError as exc:  # a bad option or scene, or a run refused before it starts
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    if record != "full":
        write_output(ds, path)
        what = f"{ds.sizes['crossing']} sections, " if record == "sections" else ""
        typer.echo(
            f"{path}: {what}peak contact force {float(ds['peak_contact_force']):.6g} N, "
            f"{ds.attrs['solver_steps']} steps ({ds.attrs['solver_rejected_steps']} rejected)"
        )
        return
    write_output(ds, path, chaoskit.save_trajectory)
    wall = ds.attrs["solver_wall_time"] + ds.attrs.get("ideal_solver_wall_time", 0.0)
    typer.echo(
        f"{path}: {ds.sizes['time']} samples, t_end = {ds.attrs['t_end']:.6g} s, "
        f"{ds.attrs['solver_steps']} steps ({ds.attrs['solver_rejected_steps']} rejected), "
        f"{ds.attrs['solver_contact_events']} contact events, {wall:.3g} s"
    )
