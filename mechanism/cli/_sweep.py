"""The grid commands: ``sweep`` (a scene over a grid of keys) and ``bifurcation`` (the orbit
diagram over one parameter), both on dask and resumable."""

from __future__ import annotations

import tomllib
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import typer

from mechanism import Analysis, BifurcationSettings, bifurcation, plot_bifurcation, sweep
from mechanism.studies import parse_values

from ._app import app
from ._common import (
    SET_HELP,
    check_output_folder,
    check_output_option,
    load_scene_option,
    write_output,
)

GRID_HELP = (
    "A swept key and its values, e.g. --grid joints.C.clearance=1e-4,2e-4 "
    "--grid drive.speed_rpm=30,90,150 --grid wear=before,after; values are TOML literals "
    "(a bare word is a string). Repeatable: the grid is every combination."
)


def parse_grid_options(options: Sequence[str]) -> dict[str, list[Any]]:
    """Parse ``--grid KEY=V1,V2,...`` options into the ``grid`` mapping of ``mechanism.sweep``.

    Examples
    --------
    >>> parse_grid_options(["joints.C.clearance=1e-4,2e-4", "drive.speed_rpm=30,90", "wear=before"])
    {'joints.C.clearance': [0.0001, 0.0002], 'drive.speed_rpm': [30, 90], 'wear': ['before']}
    """
    grid: dict[str, list[Any]] = {}
    for option in options:
        key, sep, text = option.partition("=")
        key = key.strip()
        items = [t.strip() for t in text.split(",")]
        if not sep or not key or not all(items):
            raise typer.BadParameter(
                f"{option!r}: expected KEY=V1,V2,... e.g. joints.C.clearance=1e-4,2e-4",
                param_hint="--grid",
            )
        if key in grid:
            raise typer.BadParameter(f"{key!r} is given twice", param_hint="--grid")
        values = []
        for item in items:
            try:
                values.append(tomllib.loads(f"value = {item}")["value"])
            except tomllib.TOMLDecodeError:
                values.append(item)
        grid[key] = values
    return grid


#: Default revolutions of ``mechanism sweep``: a motion verdict needs at least 20 drive
#: periods and 20 section points after the discarded revolution (docs/sweeps.md measures
#: it: the rigid paper scene at 150 rpm is undetermined at 10 revolutions, chaotic at 25).
SWEEP_REVOLUTIONS = 25.0


def sweep_table(ds: Any) -> str:
    """The result of every point of a sweep as a fixed-width text table: the grid values,
    the status, the motion verdict with its confidence (or each variable's verdict) and
    the peak contact force."""
    dims = [d for d in ds["status"].dims]
    stacked = ds.stack(point=dims) if dims else ds.expand_dims("point")
    header = [*dims, "status"]
    verdict = "motion_label" in ds or "label" in ds
    if verdict:
        header += ["verdict", "confidence"]
    if "peak_contact_force" in ds:
        header.append("peak contact force (N)")
    rows = [header]
    for i in range(stacked.sizes["point"]):
        point = stacked.isel(point=i)
        row = [_cell(point[d].item(), "g") for d in dims] + [str(point["status"].item())]
        if "motion_label" in ds:
            row += [str(point["motion_label"].item()) or "—", _cell(point["motion_confidence"])]
        elif "label" in ds:
            labels = [str(v) for v in np.atleast_1d(point["label"].values)]
            row += ["/".join(labels), _cell(np.atleast_1d(point["confidence"].values)[0])]
        if "peak_contact_force" in ds:
            row.append(_cell(point["peak_contact_force"], ".4g"))
        rows.append(row)
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip() for r in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _cell(value: Any, fmt: str = ".3g") -> str:
    """A table cell: numbers plainly (NaN as a dash), anything else as text."""
    if hasattr(value, "values"):
        value = value.values
    value = np.asarray(value).item() if np.ndim(value) == 0 else value
    if isinstance(value, bool | str) or not isinstance(value, int | float):
        return str(value) or "—"
    if isinstance(value, float) and not np.isfinite(value):
        return "—"
    return format(value, fmt) if isinstance(value, float) else str(value)


def _scheduler_option() -> Any:
    return typer.Option(
        None,
        "--scheduler",
        metavar="ADDRESS",
        help="dask scheduler address (tcp://host:8786); 'serial' runs in this process.",
    )


def _workers_option() -> Any:
    return typer.Option(
        None, "--workers", min=1, help="Workers of the local dask cluster (default: CPU count)."
    )


@app.command("sweep")
def sweep_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    grid: list[str] = typer.Option(..., "--grid", metavar="KEY=V1,V2,...", help=GRID_HELP),
    store: Path = typer.Option(
        ..., "--store", help="Folder for the point files and summary.nc; a re-run resumes."
    ),
    revolutions: float = typer.Option(
        SWEEP_REVOLUTIONS,
        "--revolutions",
        help="Crank revolutions per point; a motion verdict needs at least 20 after --discard.",
    ),
    scheduler: str | None = _scheduler_option(),
    workers: int | None = _workers_option(),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    variables: list[str] | None = typer.Option(
        None, "--var", help="Variable for chaoskit.analyze (default: eccentricity_x and _y)."
    ),
    no_analysis: bool = typer.Option(False, "--no-analysis", help="Response metrics only."),
    discard: float = typer.Option(
        1.0, "--discard", help="Revolutions discarded before metrics and analysis."
    ),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Progress bar."),
) -> None:
    """Simulate and analyse a scene over a grid, one dask task per point."""
    if scheduler is not None and workers is not None:
        raise typer.BadParameter("give --scheduler or --workers, not both", param_hint="--workers")
    parsed = parse_grid_options(grid)
    check_output_folder(store, "--store")
    resolved = load_scene_option(scene, set_options)
    try:
        analysis = Analysis(
            variables=() if no_analysis else tuple(variables or Analysis().variables),
            discard_revolutions=discard,
        )
        ds = sweep(
            resolved,
            grid=parsed,
            revolutions=revolutions,
            analysis=analysis,
            client=scheduler,
            n_workers=workers,
            store=store,
            progress=progress,
        )
    except ValueError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    except OSError as exc:  # e.g. the disk filled up: nothing more can be recorded
        typer.echo(f"Error: the sweep stopped: {exc}", err=True)
        raise typer.Exit(code=1) from None
    status = ds["status"].values.ravel()
    counts = ", ".join(f"{(status == s).sum()} {s}" for s in ("ok", "failed", "diverged"))
    typer.echo(ds.attrs["history"].splitlines()[-1].split(" ", 1)[1])
    typer.echo("")
    typer.echo(sweep_table(ds))
    typer.echo("")
    typer.echo(f"{status.size} points: {counts}")
    if "motion_label" in ds:
        motions = [str(v) for v in ds["motion_label"].values.ravel() if str(v)]
        tally = ", ".join(f"{n} {lab}" for lab, n in sorted(Counter(motions).items()))
        typer.echo(f"motion verdicts: {tally or 'none'}")
    messages = ds["message"].values.ravel()
    for pid, state, message in zip(ds["point_id"].values.ravel(), status, messages, strict=True):
        if state != "ok":
            typer.echo(f"  {state:>8}  {pid}: {message}")
    typer.echo(f"summary: {Path(ds.attrs['store']) / 'summary.nc'}")


# --- bifurcation diagrams: commands below this line only ---


@app.command("bifurcation")
def bifurcation_command(
    scene: str = typer.Argument(..., help="Built-in scene name or path of a TOML scene."),
    param: str = typer.Option(
        ..., "--param", help="Swept scene key, e.g. drive.speed_rpm or joints.C.clearance."
    ),
    values: str = typer.Option(
        ..., "--values", help="START:STOP:COUNT (both ends included) or V1,V2,..."
    ),
    revolutions: float = typer.Option(
        120.0, "--revolutions", help="Drive periods simulated per value (transient included)."
    ),
    discard: float = typer.Option(20.0, "--discard", help="Revolutions treated as transient."),
    variables: list[str] | None = typer.Option(
        None, "--var", help="Section variable (default: the journal eccentricity). Repeatable."
    ),
    exponent: bool = typer.Option(
        False,
        "--exponent",
        help="Also the largest Lyapunov exponent of every value from the equations of "
        "motion, drawn under the points.",
    ),
    exponent_revolutions: float | None = typer.Option(
        None,
        "--exponent-revolutions",
        help="Revolutions the exponent keeps (default: those of the points; implies "
        "--exponent); fewer cost less and widen its interval.",
    ),
    exponent_discard: float | None = typer.Option(
        None,
        "--exponent-discard",
        help="Revolutions the exponent discards first (default: --discard).",
    ),
    tolerance: str = typer.Option(
        "1e-7",
        "--tolerance",
        help="rtol = atol of a rigid model's error-controlled points, or 'scene' for the "
        "scene's own (at 1e-5 a regular orbit's points scatter by up to a micrometre); "
        "the exponent keeps its own 1e-8.",
    ),
    store: Path | None = typer.Option(
        None, "--store", help="Folder for the per-value files; a re-run resumes."
    ),
    direction: str | None = typer.Option(
        None,
        "--direction",
        help="up or down: state continuation, the values in that order, each from the "
        "previous one's final state (rigid scenes, this process, no store); default: every "
        "value from the scene's start.",
    ),
    output: Path | None = typer.Option(None, "-o", "--output", help="Write the Dataset (.nc)."),
    figure: Path | None = typer.Option(
        None, "--figure", help="Draw the orbit diagram (.png, .pdf, .svg)."
    ),
    scheduler: str | None = _scheduler_option(),
    workers: int | None = _workers_option(),
    set_options: list[str] | None = typer.Option(None, "--set", metavar="KEY=VALUE", help=SET_HELP),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Progress bar."),
) -> None:
    """Orbit diagram: stroboscopic points of a scene over one parameter (dask, resumable)."""
    if scheduler is not None and workers is not None:
        raise typer.BadParameter("give --scheduler or --workers, not both", param_hint="--workers")
    if figure is not None and figure.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise typer.BadParameter("the figure must end in .png, .pdf or .svg", param_hint="--figure")
    # every place a result goes is checked before hours of simulation
    if output is not None:
        check_output_option(output)
    if figure is not None:
        check_output_option(figure, suffixes=(".png", ".pdf", ".svg"))
    if store is not None:
        check_output_folder(store, "--store")
    try:
        tol = None if tolerance.strip() == "scene" else float(tolerance)
    except ValueError:
        raise typer.BadParameter(
            f"expected a number in (0, 1) or 'scene'; got {tolerance!r}", param_hint="--tolerance"
        ) from None
    resolved = load_scene_option(scene, set_options)
    # either exponent option asks for the exponent
    exponent = exponent or exponent_revolutions is not None or exponent_discard is not None
    try:
        ds = bifurcation(
            resolved,
            parameter=param,
            values=parse_values(values),
            revolutions=revolutions,
            discard=discard,
            variables=tuple(variables) if variables else ("eccentricity",),
            exponent=exponent,
            settings=BifurcationSettings(
                rtol=tol,
                atol=tol,
                exponent_revolutions=exponent_revolutions,
                exponent_discard=exponent_discard,
                direction=direction,
            ),
            client=scheduler,
            n_workers=workers,
            store=store,
            progress=progress,
        )
    except ValueError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None
    status = ds["status"].values
    counts = ", ".join(f"{(status == s).sum()} {s}" for s in ("ok", "failed", "diverged"))
    typer.echo(f"{status.size} values: {counts}; {ds.sizes['crossing']} revolutions kept")
    for value, state, message in zip(ds[param].values, status, ds["message"].values, strict=True):
        if state != "ok":
            typer.echo(f"  {state:>8}  {param} = {value}: {message}")
    if output is not None:
        write_output(ds, output)
        typer.echo(f"dataset: {output}")
    if figure is not None:
        import matplotlib

        matplotlib.use("Agg")
        axes = plot_bifurcation(ds)
        axes[0].figure.savefig(figure, dpi=200, bbox_inches="tight")
        typer.echo(f"figure: {figure}")
