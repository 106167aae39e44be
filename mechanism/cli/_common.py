"""What every scene command shares: ``--set`` parsing, output checks, the scene option,
warnings as lines and the write of a result."""

from __future__ import annotations

import contextlib
import os
import tomllib
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import typer

from chaoskit.contract import folder_problem, write_netcdf
from mechanism import Scene, SceneError, SimulationWarning, load_scene

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
def warnings_as_lines() -> Iterator[None]:
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
