"""The option objects of :func:`chaoskit.report`: what the caller adds, how it runs.

:class:`ReportExtras` holds the material a caller adds beside the analysis (reference
values, tables, maps, figures, the equations' exponents, provenance); :class:`ReportOptions`
holds the finer settings of the analysis and of the files.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any, Literal

import pandas as pd

from ._content import ReportFigure, ReportTable
from ._model import SweepMap

__all__ = ["ReportExtras", "ReportOptions", "checked_options", "fields_in_objects"]


@dataclass(frozen=True, kw_only=True, eq=False)
class ReportExtras:
    """What a caller adds to the analysis of :func:`chaoskit.report`.

    Parameters
    ----------
    exponents
        ``{state label: exponent}``: the largest exponent from the equations of motion of
        each state (e.g. :func:`mechanism.lyapunov_exponent`; any object with ``exponent``
        in 1/s and a 95 % interval ``ci``), a vote in the motion verdict.
    chaos_reference
        Reference values for the chaos table, indexed by ``(variable alias, state)`` with
        columns among ``lag``, ``lag_time``, ``embedding_dim``, ``mle_wolf``,
        ``mle_wolf_bits``, ``mle_rosenstein``, ``mle_rosenstein_bits``, ``verdict``,
        ``confidence``.
    reference_name
        Header of the reference values in the chaos table.
    chaos_notes
        Text under the chaos table (e.g. how the settings differ from the paper's).
    tables
        :class:`ReportTable` objects, placed in their ``section`` (default "Response
        metrics").
    sweep_maps
        :class:`SweepMap` objects (exponent and verdict over two swept parameters).
    bifurcations
        Datasets from :func:`chaoskit.bifurcation_diagram`, or ``{caption: Dataset}``.
    figures
        Further :class:`ReportFigure` objects, placed in their ``section``.
    parameters
        Run parameters to list in the provenance (values: numbers, text, JSON-able).
    command
        The command that produced the report (default: this process's command line).

    Examples
    --------
    >>> import pandas as pd, chaoskit
    >>> from chaoskit.reporting import ReportExtras
    >>> table = chaoskit.ReportTable(caption="Metrics", data=pd.DataFrame({"x": [1.0]}))
    >>> rep = chaoskit.report(extras=ReportExtras(tables=[table], command="demo"))
    >>> rep.tables[0].caption
    'Metrics'
    """

    exponents: Mapping[str, Any] | None = None
    chaos_reference: pd.DataFrame | None = None
    reference_name: str = "reference"
    chaos_notes: str = ""
    tables: Sequence[ReportTable] = ()
    sweep_maps: Sequence[SweepMap] = ()
    bifurcations: Any = None
    figures: Sequence[ReportFigure] = ()
    parameters: Mapping[str, Any] | None = None
    command: str | None = None


@dataclass(frozen=True, kw_only=True, eq=False)
class ReportOptions:
    """Finer settings of the analysis and the files of :func:`chaoskit.report`.

    Parameters
    ----------
    max_samples
        Subsample (plain stride, no filter) so that at most this many samples are
        analysed (an integer >= 200, or None for all); the lag in samples and the exponent
        in bits per sample refer to the analysed sampling interval, which the provenance
        lists.
    n_surrogates, rng
        Passed to :func:`chaoskit.classify_variables`; each state gets its own stream
        spawned from ``rng``.
    measures
        Further measures for every state and variable, in a section of their own (table and
        figures): a subset of ``"d2"``, ``"rqa"``, ``"spectrum"``, ``"sampen"``, ``"dfa"``,
        ``"hurst"`` (a sequence or a comma-separated string, or ``"all"``).
    display_units
        ``{variable: unit}``: the unit a length variable is drawn in (``"m"``, ``"mm"``,
        ``"µm"``, ``"nm"``), e.g. ``{"X": "mm"}`` for journal displacements stored in m.
        Figures only: the analysis and the tables stay in the stored (SI) units.
    markdown_figures
        ``"files"`` (PNG files in ``<stem>_figures/``) or ``"embed"`` (data URIs), when
        the report is written.
    progress
        Show a tqdm bar over the variables of each state.
    executor
        Where the states are classified: None (in this process, one after another) or an
        executor of ``concurrent.futures`` (anything with ``submit``), e.g. a
        ``ProcessPoolExecutor``, which takes one task per state. The verdicts are the
        same either way: each state has its own stream spawned from ``rng``.
    """

    max_samples: int | None = None
    n_surrogates: int = 19
    rng: Any = 0
    measures: Sequence[str] | str = ()
    display_units: Mapping[str, str] | None = None
    markdown_figures: Literal["files", "embed"] = "files"
    progress: bool = False
    executor: Any = None


def fields_in_objects(func: Callable[..., Any]) -> Callable[..., Any]:
    """``func`` (:func:`report`) refusing a field of :class:`ReportExtras` or
    :class:`ReportOptions` given as a keyword, with a TypeError naming the object that
    holds it (Python's own message names only the keyword)."""
    owners = {f.name: ("extras", "ReportExtras") for f in fields(ReportExtras)}
    owners |= {f.name: ("options", "ReportOptions") for f in fields(ReportOptions)}

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        for key in kwargs:
            if key in owners:
                arg, kind = owners[key]
                raise TypeError(
                    f"{func.__name__}() got an unexpected keyword argument {key!r}; pass it "
                    f"in the {kind} object: {arg}={kind}({key}=...)."
                )
        return func(*args, **kwargs)

    return wrapper


def checked_options(
    extras: ReportExtras | None, options: ReportOptions | None
) -> tuple[ReportExtras, ReportOptions]:
    """``extras`` and ``options`` of :func:`report` (None: the defaults), type-checked."""
    out = []
    for given, kind, arg in ((extras, ReportExtras, "extras"), (options, ReportOptions, "options")):
        if given is None:
            given = kind()
        elif not isinstance(given, kind):
            raise ValueError(f"{arg} must be a {kind.__name__}; got {type(given).__name__}.")
        out.append(given)
    return out[0], out[1]
