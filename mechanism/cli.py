"""Simulator command line: a thin layer that loads, calls the library and prints."""

from __future__ import annotations

import shlex
import signal
import sys
import tomllib
from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import typer
from typer.core import TyperGroup

import chaoskit
from chaoskit.contract import __version__, check_choice, folder_problem, write_netcdf
from mechanism import (
    Analysis,
    BifurcationSettings,
    FullRecord,
    LyapunovSettings,
    MetricsRecord,
    RecordMode,
    Scene,
    SceneError,
    SectionsRecord,
    SimulationError,
    SimulationWarning,
    WearPredictionError,
    bifurcation,
    element_convergence,
    list_scenes,
    load_scene,
    lyapunov_exponent,
    plot_bifurcation,
    predict_wear,
    run_paper_study,
    save_scene,
    simulate,
    sweep,
    wear_life,
)
from mechanism.core.integrate import interrupt_integrations
from mechanism.studies import (
    DEFAULT_DEVIATION_RTOL,
    DEFAULT_MAX_DEPTH_INCREMENT,
    DEFAULT_WEAR_LIFE_AVERAGED_REVOLUTIONS,
    parse_values,
)

#: exit status of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it)
EXIT_INTERRUPTED = 130


def _on_sigint(signum: int, frame: Any) -> None:
    # integrations in other threads (a run's ideal companion) stop with the main thread,
    # also while it is only waiting for them
    interrupt_integrations()
    raise KeyboardInterrupt


class _Commands(TyperGroup):
    """The command group: Ctrl-C ends any command with one line and exit status 130."""

    def invoke(self, ctx: Any) -> Any:
        previous = signal.getsignal(signal.SIGINT)
        if previous is signal.default_int_handler:
            signal.signal(signal.SIGINT, _on_sigint)
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            # files a command already wrote (sweep points, bifurcation values) are whole:
            # each is written atomically, and a re-run with the same --store resumes
            typer.echo("interrupted", err=True)
            raise typer.Exit(code=EXIT_INTERRUPTED) from None
        finally:
            if previous is signal.default_int_handler:
                signal.signal(signal.SIGINT, previous)


app = typer.Typer(
    name="mechanism",
    help="Simulate planar rigid-flexible mechanisms with clearance joints and wear.",
    no_args_is_help=True,
    add_completion=False,
    cls=_Commands,
    # plain (click) help at a fixed 100 columns: long option names, help texts and command
    # summaries wrap instead of being cut at the terminal's width as in the rich panels,
    # and flags show no value type
    rich_markup_mode=None,
    context_settings={"terminal_width": 100, "max_content_width": 100},
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


# --- scenes (scene loading): commands below this line only ---
import contextlib  # noqa: E402
import os  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Iterator  # noqa: E402
from typing import TYPE_CHECKING  # noqa: E402

import numpy as np  # noqa: E402

if TYPE_CHECKING:
    from collections.abc import Sequence

SET_HELP = (
    "Change a scene key, e.g. --set joints.C.clearance=2e-4 --set effects.wear=true; "
    "values are TOML literals (a bare word is a string). Repeatable."
)


def parse_set_options(options: Sequence[str] | None) -> dict[str, Any]:
    """Parse ``--set KEY=VALUE`` options into the mapping :meth:`Scene.replace` takes.

    Each value is read as a TOML literal: ``2e-4`` → float, ``16`` → int, ``true`` → bool,
    ``[0.0, -9.81]`` → list, ``{ law = "hertz" }`` → dict, ``"text"`` → str. Anything that
    is not a TOML literal is kept as the plain string (``solver.method=Radau``). Later
    options win over earlier ones for the same key.

    Examples
    --------
    >>> parse_set_options(["joints.C.clearance=2e-4", "solver.method=Radau", "effects.wear=true"])
    {'joints.C.clearance': 0.0002, 'solver.method': 'Radau', 'effects.wear': True}
    """
    changes: dict[str, Any] = {}
    for option in options or ():
        key, sep, text = option.partition("=")
        key = key.strip()
        if not sep or not key or any(not part for part in key.split(".")):
            raise typer.BadParameter(
                f"{option!r}: expected KEY=VALUE with a dotted key, e.g. joints.C.clearance=2e-4",
                param_hint="--set",
            )
        text = text.strip()
        try:
            value = tomllib.loads(f"value = {text}")["value"]
        except tomllib.TOMLDecodeError:
            value = text
        changes[key] = value
    return changes


NETCDF_SUFFIXES = (".nc", ".nc4", ".netcdf", ".h5", ".hdf5")


def check_output_option(
    output: str | os.PathLike[str], *, suffixes: Sequence[str] = NETCDF_SUFFIXES
) -> Path:
    """The ``-o`` path of a command that writes netCDF (or a file ending in one of
    ``suffixes``), checked before any work: the suffix, not a folder, in a folder that
    exists or can be made and takes a file. Exits with status 2 and one line naming the
    problem otherwise."""
    path = Path(output)
    problem = None
    if suffixes is NETCDF_SUFFIXES and path.suffix.lower() not in suffixes:
        problem = (
            f"{path}: the output is netCDF; give a name ending in .nc (got "
            f"{path.suffix or 'no suffix'}). Multi-dimensional outputs do not fit CSV or npz; "
            "select 1-D series and convert them with chaoskit.save_trajectory."
        )
    elif path.suffix.lower() not in suffixes:
        problem = f"{path}: give a name ending in {', '.join(suffixes)}."
    elif path.is_dir():
        problem = f"{path} is a folder; give a file name ending in {path.suffix}."
    else:
        problem = folder_problem(path.parent, f"cannot create {path}")
    if problem is not None:
        typer.echo(f"Error: {problem}", err=True)
        raise typer.Exit(code=2)
    return path


def check_output_folder(folder: str | os.PathLike[str], option: str = "-o") -> Path:
    """An output folder (``-o`` of ``paper``, ``--store``), checked before any work: a
    folder, or one that can be made, that takes a file. Exits with status 2 and one line
    naming the problem otherwise."""
    path = Path(folder)
    problem = folder_problem(path, f"{option} {path}")
    if problem is not None:
        typer.echo(f"Error: {problem}", err=True)
        raise typer.Exit(code=2)
    return path


@contextlib.contextmanager
def _warnings_as_lines() -> Iterator[None]:
    """Print each SimulationWarning as one ``Warning: ...`` line on stderr, as it comes."""

    def show(message: Any, category: Any, *args: Any, **kwargs: Any) -> None:
        if issubclass(category, SimulationWarning):
            typer.echo(f"Warning: {message}", err=True)
        else:
            default(message, category, *args, **kwargs)

    with warnings.catch_warnings():
        warnings.simplefilter("always", SimulationWarning)
        default = warnings.showwarning
        warnings.showwarning = show
        yield


def write_output(ds: Any, path: Path, writer: Any = write_netcdf) -> None:
    """Write ``ds`` with ``writer``; a failure (a full disk) is one line and exit status 1."""
    try:
        writer(ds, path)
    except OSError as exc:
        typer.echo(f"Error: cannot write {path}: {exc}", err=True)
        raise typer.Exit(code=1) from None


def load_scene_option(scene: str, set_options: Sequence[str] | None = None) -> Scene:
    """Load ``scene`` (built-in name or TOML path) and apply ``--set`` options; exit with
    status 2 and the scene error on stderr when it is invalid. For all scene commands."""
    changes = parse_set_options(set_options)
    try:
        resolved = load_scene(scene)
        return resolved.replace(changes) if changes else resolved
    except SceneError as exc:
        typer.echo(f"Error: {exc}", err=True)
        raise typer.Exit(code=2) from None


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


# --- simulation (core): commands below this line only ---


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
        with _warnings_as_lines():
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


# --- wear: commands below this line only ---


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
        with _warnings_as_lines():
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
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Show a progress bar."),
) -> None:
    """Wear the scene's clearance joints and analyse the motion at checkpoints.

    Writes ``wear-life.nc`` (dim checkpoint) and ``worn.toml`` (the scene at the last
    finished checkpoint) into the output folder and prints the summary. A state the wear
    model cannot represent ends the path: what finished is written, the reason is printed
    and the exit status is 1; bad options exit with 2.
    """
    folder = check_output_folder(output)
    resolved = load_scene_option(scene, set_options)
    try:
        with _warnings_as_lines():
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


# --- flexibility: commands below this line only ---


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


# --- sweeps: commands below this line only ---

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


# --- paper study: commands below this line only ---


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
    # the answer, right above the files: the motion verdict of each state
    typer.echo("Motion verdict per state:")
    typer.echo(study.answer.to_string() if study.motions else "  none (no chaos run finished)")
    typer.echo("")
    typer.echo(f"report: {study.report_html}")
    if study.report_markdown is not None:
        typer.echo(f"markdown: {study.report_markdown}")
    typer.echo(f"wall time: {study.wall_time:.1f} s; output: {study.output_size / 1e6:.1f} MB")


# --- chaos from the equations: commands below this line only ---


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


if __name__ == "__main__":
    app()
