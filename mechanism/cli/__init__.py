"""Simulator command line: a thin layer that loads, calls the library and prints.

One module per command group, each registering its commands on :data:`app`:

* ``_app`` -- the Typer application, Ctrl-C (exit status 130) and ``--version``;
* ``_common`` -- ``--set`` parsing, output checks, the scene option, warnings as lines;
* ``_scenes`` -- ``scenes``, ``show``;
* ``_simulate`` -- ``simulate``;
* ``_wear`` -- ``wear``, ``wear-life``;
* ``_convergence`` -- ``convergence``;
* ``_sweep`` -- ``sweep``, ``bifurcation``;
* ``_paper`` -- ``paper``;
* ``_lyapunov`` -- ``lyapunov``;
* ``_orbits`` -- ``continuation``.

``mechanism --help`` lists the commands in the order of ``_app.COMMAND_ORDER``.
"""

from __future__ import annotations

from ._app import EXIT_INTERRUPTED, app, main
from ._common import (
    NETCDF_SUFFIXES,
    SET_HELP,
    check_output_folder,
    check_output_option,
    load_scene_option,
    parse_set_options,
    warnings_as_lines,
    write_output,
)

# the command modules register their commands on import (the help's order: COMMAND_ORDER)
# isort: off
from ._scenes import scenes_command, show_command
from ._simulate import simulate_command
from ._wear import wear_command, wear_life_command, wear_update_lines
from ._convergence import convergence_command
from ._sweep import (
    GRID_HELP,
    SWEEP_REVOLUTIONS,
    bifurcation_command,
    parse_grid_options,
    sweep_command,
    sweep_table,
)
from ._paper import paper_command
from ._lyapunov import lyapunov_command
from ._orbits import continuation_command
# isort: on

__all__ = [
    "EXIT_INTERRUPTED",
    "GRID_HELP",
    "NETCDF_SUFFIXES",
    "SET_HELP",
    "SWEEP_REVOLUTIONS",
    "app",
    "bifurcation_command",
    "check_output_folder",
    "check_output_option",
    "continuation_command",
    "convergence_command",
    "load_scene_option",
    "lyapunov_command",
    "main",
    "paper_command",
    "parse_grid_options",
    "parse_set_options",
    "scenes_command",
    "show_command",
    "simulate_command",
    "sweep_command",
    "sweep_table",
    "warnings_as_lines",
    "wear_command",
    "wear_life_command",
    "wear_update_lines",
]
