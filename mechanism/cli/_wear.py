"""The wear commands: ``wear`` (cycle extrapolation of the profile) and ``wear-life`` (wear
with the motion analysed at checkpoints)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from mechanism import (
    SimulationError,
    WearLifeSettings,
    WearPredictionError,
    predict_wear,
    save_scene,
    wear_life,
    wear_life_map,
    wear_life_report,
)
from mechanism.studies import DEFAULT_MAX_DEPTH_INCREMENT, DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS

from ._app import app
from ._common import (
    SET_HELP,
    check_output_folder,
    check_output_option,
    load_scene_option,
    warnings_as_lines,
    write_output,
)
from ._sweep import parse_grid_options


@app.command("wear")
def wear_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    output: str = typer.Option(..., "-o", "--output", help="Wear prediction file (.nc)."),
    updates: int = typer.Option(..., "--updates", help="Number of profile updates (>= 1)."),
    cycles_per_update: float = typer.Option(
        ..., "--cycles-per-update", help="Crank cycles extrapolated per update (> 0)."
    ),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    max_depth_increment: float = typer.Option(
        DEFAULT_MAX_DEPTH_INCREMENT,
        "--max-depth-increment",
        help="Largest depth one sub-update adds, as a fraction of the radial clearance, in "
        "(0, 1]; a block of cycles that would wear deeper is worn in sub-updates.",
    ),
    settle_revolutions: float = typer.Option(
        2.0, "--settle-revolutions", help="Revolutions simulated before the measured cycle."
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar."),
) -> None:
    """Predict the worn profile (cycle extrapolation) and write it with the worn scene.

    A state whose penetration exceeds the radial clearance stops the prediction: the
    finished updates are written with ``status = "failed"`` in the file's attributes, the
    reason is the last line and the exit status is 1.
    """
    path = check_output_option(output)
    resolved = load_scene_option(scene, set_options)
    try:
        with warnings_as_lines():
            pred = predict_wear(
                resolved,
                updates=updates,
                cycles_per_update=cycles_per_update,
                max_depth_increment=max_depth_increment,
                settle_revolutions=settle_revolutions,
                progress=progress,
            )
    except ValueError as exc:  # a bad option or scene: a user error
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except WearPredictionError as exc:  # the finished updates are kept
        if exc.prediction is None:
            typer.echo(f"Error: {exc}", err=True)
            raise typer.Exit(code=1) from None
        pred = exc.prediction
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    ds = pred.to_dataset()
    write_output(ds, path)
    for line in wear_update_lines(ds):
        typer.echo(line)
    if not pred.success:
        typer.echo(
            f"{output}: written with the {pred.updates} of {updates} updates that finished "
            "(status failed)"
        )
        typer.echo(f"Error: {pred.reason}", err=True)
        raise typer.Exit(code=1)
    force = ds["peak_contact_force"].values
    typer.echo(
        f"{output}: {pred.updates} updates, {float(pred.cycles[-1]):.6g} cycles in "
        f"{ds.sizes['sub_update']} sub-updates, "
        f"max depth {float(ds['wear_depth'].isel(update=-1).max()):.3g} m, "
        f"peak contact force {force[0]:.4g} -> {force[-1]:.4g} N"
    )


def wear_update_lines(ds: Any) -> list[str]:
    """One line per update state of a wear prediction Dataset: its cycles, peak contact
    force (last revolution), largest penetration over its run in % of the clearance, and
    how the next block was split into sub-updates."""
    lines = []
    for u in range(ds.sizes["update"]):
        state = ds.isel(update=u)
        line = (
            f"update {u}: {float(state['cycles']):.6g} cycles, peak contact force "
            f"{float(state['peak_contact_force']):.4g} N (last revolution), penetration up "
            f"to {100.0 * float(state['penetration_fraction']):.0f} % of the clearance (whole "
            "run)"
        )
        subs = ds["sub_update_cycles"].values[ds["sub_update_of"].values == u]
        if subs.size > 1:
            line += (
                f"; the next {subs.sum():.6g} cycles in {subs.size} sub-updates of "
                f"{subs.min():.4g}-{subs.max():.4g} cycles (each within "
                f"{ds.attrs['max_depth_increment']:g} of the clearance)"
            )
        lines.append(line)
    return lines


@app.command("wear-life")
def wear_life_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    output: str = typer.Option(..., "-o", "--output", help="Output folder (created)."),
    cycles: float = typer.Option(..., "--cycles", help="Crank cycles of wear (> 0)."),
    checkpoints: list[float] = typer.Option(
        ...,
        "--checkpoint",
        help="Cumulative cycles of a checkpoint (repeat; increasing, in (0, cycles]).",
    ),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    averaged_revolutions: int = typer.Option(
        DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS,
        "--averaged-revolutions",
        help="Revolutions whose mean wear is the wear per cycle, in [1, 1000].",
    ),
    max_depth_increment: float = typer.Option(
        DEFAULT_MAX_DEPTH_INCREMENT,
        "--max-depth-increment",
        help="Largest depth one increment adds, as a fraction of the radial clearance, in (0, 1].",
    ),
    exponent: bool = typer.Option(
        True,
        "--exponent/--no-exponent",
        help="Compute the Lyapunov exponent from the equations at each checkpoint.",
    ),
    grid: str | None = typer.Option(
        None,
        "--grid",
        metavar="KEY=V1,V2,...",
        help="One wear path per value of a scene key, e.g. --grid drive.speed_rpm=30,90,150 "
        "or --grid joints.C.clearance=1e-4,2e-4 (m); the paths run as dask tasks in "
        "OUTPUT/store (a re-run resumes).",
    ),
    workers: int | None = typer.Option(
        None, "--workers", help="With --grid: workers of the local dask cluster (>= 1)."
    ),
    scheduler: str | None = typer.Option(
        None,
        "--scheduler",
        metavar="ADDRESS",
        help="With --grid: dask scheduler address (tcp://host:8786); 'serial' runs here.",
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar."),
) -> None:
    """Wear the scene's clearance joints and analyse the motion at checkpoints.

    Writes ``wear-life.nc`` (dim checkpoint) and ``worn.toml`` (the scene at the last
    finished checkpoint) into the output folder and prints the summary. A state the wear
    model cannot represent ends the path: what finished is written, the reason is printed
    and the exit status is 1; bad options exit with 2.

    With ``--grid KEY=V1,V2,...`` every value is its own path (a dask task): the output
    folder gets the store (``store/``, resumed by a re-run), ``wear-life-map.nc`` (dims
    value, checkpoint), the report ``wear-life.html`` and ``wear-life.md`` with its
    figures, and the answer per value is printed; a value whose path did not complete
    makes the exit status 1.
    """
    folder = check_output_folder(output)
    resolved = load_scene_option(scene, set_options)
    if grid is not None:
        settings = _map_settings(averaged_revolutions, max_depth_increment, exponent)
        _wear_life_map_command(
            resolved, folder, grid, cycles=cycles, checkpoints=checkpoints, settings=settings,
            workers=workers, scheduler=scheduler, progress=progress,
        )  # fmt: skip
        return
    if workers is not None or scheduler is not None:
        typer.echo("Error: --workers and --scheduler apply with --grid only.", err=True)
        raise typer.Exit(code=2)
    try:
        with warnings_as_lines():
            life = wear_life(
                resolved, cycles=cycles, checkpoints=checkpoints,
                averaged_revolutions=averaged_revolutions,
                max_depth_increment=max_depth_increment, exponent=exponent, progress=progress,
            )  # fmt: skip
    except ValueError as exc:  # a bad option or scene: a user error
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except SimulationError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=1) from None
    folder.mkdir(parents=True, exist_ok=True)
    write_output(life.to_dataset(), folder / "wear-life.nc")
    save_scene(life.worn_scene, folder / "worn.toml")
    typer.echo(life.summary())
    if not life.success:
        typer.echo(f"Error: {life.reason}", err=True)
        raise typer.Exit(code=1)


def _map_settings(averaged: int, limit: float, exponent: bool) -> WearLifeSettings:
    try:
        return WearLifeSettings(
            averaged_revolutions=averaged, max_depth_increment=limit, exponent=exponent
        )
    except ValueError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None


def _wear_life_map_command(
    scene: Any, folder: Path, grid: str, *, cycles: float, checkpoints: list[float],
    settings: WearLifeSettings, workers: int | None, scheduler: str | None, progress: bool,
) -> None:  # fmt: skip
    """``wear-life --grid``: one path per value, the map, the report and the answers."""
    try:
        ((parameter, values),) = parse_grid_options([grid]).items()
    except typer.BadParameter as exc:
        typer.echo(f"Error: --grid: {exc}", err=True)
        raise typer.Exit(code=2) from None
    try:
        with warnings_as_lines():
            life = wear_life_map(
                scene, parameter=parameter, values=values, cycles=cycles,
                checkpoints=checkpoints, settings=settings, store=folder / "store",
                workers=workers, scheduler=scheduler, progress=progress,
            )  # fmt: skip
    except (ValueError, TypeError) as exc:  # a bad option, scene or store: a user error
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except OSError as exc:  # e.g. the disk filled up: nothing more can be recorded
        typer.echo(f"Error: the paths stopped: {exc}", err=True)
        raise typer.Exit(code=1) from None
    write_output(life.to_dataset(), folder / "wear-life-map.nc")
    import matplotlib  # plotting is optional

    matplotlib.use("Agg")  # files only: no display needed
    wear_life_report(life, output=folder / "wear-life.html")
    typer.echo(life.summary())
    typer.echo(f"map: {folder / 'wear-life-map.nc'}; report: {folder / 'wear-life.html'}")
    failed = [
        f"{label}: {reason}"
        for label, reason, status in zip(life.labels(), life.reasons, life.statuses, strict=True)
        if status != "complete"
    ]
    if failed:
        for line in failed:
            typer.echo(f"Error: {line}", err=True)
        raise typer.Exit(code=1)
