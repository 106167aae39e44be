"""The contract other packages build on: validation helpers, the provenance stamp, atomic writes.

A package that produces trajectories for chaoskit (``mechanism`` is one) uses these names
instead of chaoskit's private modules, so the data it writes follows ``docs/data-model.md``
and its error messages read like chaoskit's own.

Validation
    :func:`as_series`, :func:`check_int`, :func:`check_positive`, :func:`check_probability`,
    :func:`check_choice` turn user input into checked values or raise a one-line
    :class:`ValueError` naming the parameter and the accepted range. A
    :class:`ParameterError` names parameters so that a command line can word the same
    message with its options (``--dt`` for ``dt=``).
Provenance
    :func:`stamp` sets the global attributes of the data contract (``Conventions``,
    ``title``, ``source``, ``history``, ``created``); :func:`append_history` adds a line;
    :func:`validate_trajectory` and :func:`sampling_interval` check a Dataset;
    :func:`variable` builds a variable with its ``units`` and ``long_name``;
    :func:`variable_name` turns a column header into a variable name of the contract.
Files
    :func:`atomic_write` writes through a temporary file in the target folder and renames it,
    so a reader never sees a half-written file; :func:`write_netcdf` writes a Dataset that way
    after :func:`check_free_space`; :func:`safe_filename` and :func:`unique_filename` turn
    names from user data into file names that cannot leave their folder.
Compiled kernels
    :func:`refresh_jit_cache` deletes a package's cached compiled kernels when any of its
    sources changed (numba keys its cache on one file, not on the modules a kernel calls).

Examples
--------
>>> from chaoskit.contract import check_int
>>> check_int(3, name="embedding_dim", minimum=1)
3
"""

from __future__ import annotations

from ._contract import (
    CONVENTIONS,
    REQUIRED_GLOBAL_ATTRS,
    ParameterError,
    append_history,
    sampling_interval,
    stamp,
    validate_trajectory,
    variable,
    variable_name,
)
from ._io import atomic_write, check_free_space, write_netcdf
from ._jit_cache import refresh_jit_cache
from ._paths import folder_problem, safe_filename, unique_filename
from ._validate import as_series, check_choice, check_int, check_positive, check_probability
from ._version import __version__

__all__ = [
    "CONVENTIONS",
    "REQUIRED_GLOBAL_ATTRS",
    "ParameterError",
    "__version__",
    "append_history",
    "as_series",
    "atomic_write",
    "check_choice",
    "check_free_space",
    "check_int",
    "check_positive",
    "check_probability",
    "folder_problem",
    "refresh_jit_cache",
    "safe_filename",
    "sampling_interval",
    "stamp",
    "unique_filename",
    "validate_trajectory",
    "variable",
    "variable_name",
    "write_netcdf",
]
