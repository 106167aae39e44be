"""The option objects of :func:`chaoskit.report`: what the caller adds, how it runs.

:class:`ReportExtras` holds the material a caller adds beside the analysis (reference
values, tables, maps, figures, the equations' exponents, provenance); :class:`ReportOptions`
holds the finer settings of the analysis and of the files. Their fields are also accepted
by :func:`chaoskit.report` as keywords of the same name.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import pandas as pd

from ._content import ReportFigure, ReportTable
from ._model import SweepMap

__all__ = ["ReportExtras", "ReportOptions", "resolve_options"]


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
    """

    max_samples: int | None = None
    n_surrogates: int = 19
    rng: Any = 0
    measures: Sequence[str] | str = ()
    display_units: Mapping[str, str] | None = None
    markdown_figures: Literal["files", "embed"] = "files"
    progress: bool = False


_EXTRAS = tuple(f.name for f in dataclasses.fields(ReportExtras))
_OPTIONS = tuple(f.name for f in dataclasses.fields(ReportOptions))


def resolve_options(
    extras: ReportExtras | None, options: ReportOptions | None, keywords: Mapping[str, Any]
) -> tuple[ReportExtras, ReportOptions]:
    """``extras`` and ``options`` with the fields given as keywords of :func:`report` set.

    A field may come in its object or as a keyword, not both; any other keyword is refused
    as Python refuses an unknown keyword argument.
    """
    unknown = [k for k in keywords if k not in _EXTRAS and k not in _OPTIONS]
    if unknown:
        raise TypeError(f"report() got an unexpected keyword argument {unknown[0]!r}")
    out = []
    for given, kind, names in ((extras, ReportExtras, _EXTRAS), (options, ReportOptions, _OPTIONS)):
        fields = {k: v for k, v in keywords.items() if k in names}
        if given is None:
            out.append(kind(**fields))
            continue
        if not isinstance(given, kind):
            arg = "extras" if kind is ReportExtras else "options"
            raise ValueError(f"{arg} must be a {kind.__name__}; got {type(given).__name__}.")
        if fields:
            arg = "extras" if kind is ReportExtras else "options"
            raise ValueError(
                f"give {', '.join(fields)} either in {arg}= ({kind.__name__}) or as "
                "keywords, not both."
            )
        out.append(given)
    return out[0], out[1]
