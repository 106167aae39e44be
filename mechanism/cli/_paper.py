"""The ``paper`` command: the paper's study of the press before and after wear, reported."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path

import typer

from mechanism import run_paper_study

from ._app import app
from ._common import check_output_folder


@app.command("paper")
def paper_command(
    output: Path = typer.Option(..., "-o", "--output", help="Folder for the report and runs."),
    quick: bool = typer.Option(
        False, "--quick", help="Documented reductions (docs/paper-study.md)."
    ),
    workers: int | None = typer.Option(
        None, "--workers", min=1, help="Workers of the local dask cluster (default: CPU count)."
    ),
    scheduler: str | None = typer.Option(
        None,
        "--scheduler",
        metavar="ADDRESS",
        help="dask scheduler address (tcp://host:8786); 'serial' runs in this process.",
    ),
    progress: bool = typer.Option(
        True, "--progress/--no-progress", help="Print each stage with the time left."
    ),
    keep_trajectories: bool = typer.Option(
        False,
        "--keep-trajectories",
        help="Keep the simulated trajectories (hundreds of MB); default: metrics only.",
    ),
) -> None:
    """Is the press chaotic before and after wear? Reproduce the paper's study and report."""
    if scheduler is not None and workers is not None:
        raise typer.BadParameter("give --scheduler or --workers, not both", param_hint="--workers")
    check_output_folder(output)
    study = run_paper_study(
        output,
        quick=quick,
        client=scheduler,
        n_workers=workers,
        progress=progress,
        keep_trajectories=keep_trajectories,
        command="mechanism " + " ".join(shlex.quote(a) for a in sys.argv[1:]),
    )
    for line in study.unavailable:
        typer.echo(f"not available in this version: {line}")
    claims = study.transition_claims
    if not claims.empty:
        # the wear-life answer first: the paper's claims on the transition to chaos, judged
        # on the wear paths
        typer.echo("Wear life against the paper's claims on the transition to chaos:")
        for short, row in claims.iterrows():
            typer.echo(f"  {row['agreement']}: {short} — {row['why']}")
        typer.echo("")
    # the answer, right above the files: the motion verdict of each state
    typer.echo("Motion verdict per state:")
    typer.echo(study.answer.to_string() if study.motions else "  none (no chaos run finished)")
    typer.echo("")
    typer.echo(f"report: {study.report_html}")
    if study.report_markdown is not None:
        typer.echo(f"markdown: {study.report_markdown}")
    typer.echo(f"wall time: {study.wall_time:.1f} s; output: {study.output_size / 1e6:.1f} MB")
