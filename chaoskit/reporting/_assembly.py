"""Assemble a report: analyse every trajectory and collect the sections in print order.

``report`` analyses every trajectory (one state of the system each) with
:func:`chaoskit.classify_variables` (:func:`chaoskit.classify_motion` for two or more
variables), draws the figures with :mod:`chaoskit.plot` and adds whatever the caller passes
in (tables with reference values, sweep maps, bifurcation diagrams, figures, parameters).
Nothing here knows about the simulator or any particular study: tables come in as plain
pandas and xarray objects.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from .._measure_registry import parse_measures
from .._selection import VariableSpec, parse_variable
from ..verdict import as_generator, classify_motion, classify_variables, verdict_table
from ._analysis_figures import analysis_figures, report_figure
from ._analysis_tables import analysis_tables
from ._content import ReportFigure, ReportSection, ReportTable
from ._further_measures import measure_items
from ._model import APPENDIX, PROVENANCE, SECTION_ORDER, Report, now
from ._options import ReportExtras, ReportOptions, checked_options, fields_in_objects
from ._provenance import provenance_items
from ._states import (
    State,
    check_display_units,
    normalise_trajectories,
    normalise_variables,
    prepare_state,
)
from ._sweeps import bifurcation_items, sweep_items

__all__ = ["report"]


@fields_in_objects
def report(
    trajectories: Any = None,
    *,
    variables: Sequence[str] | Mapping[str, str] | None = None,
    labels: Sequence[str] | None = None,
    sel: Mapping[str, Any] | None = None,
    discard: float = 0.0,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    title: str = "chaoskit report",
    output: str | os.PathLike[str] | None = None,
    extras: ReportExtras | None = None,
    options: ReportOptions | None = None,
) -> Report:
    r"""Analyse trajectories and assemble a captioned report (HTML page and Markdown twin).

    Each trajectory is one *state* of the system (e.g. "before wear", "after wear"). For
    every state the report runs :func:`chaoskit.classify_motion` on its variables (with
    the ``exponents`` from the equations when given; :func:`chaoskit.classify_variables` when
    there is one variable) and shows

    * first, the motion verdict: one label per state from all its variables together, with
      the joint section, the exponent of the mixed embedding, the equations' exponent and
      what would decide an undetermined motion;
    * the verdicts (one line per variable, one column per state);
    * the chaos table: delay :math:`\tau` (samples and s), embedding dimension :math:`m`,
      the largest Lyapunov exponent by Wolf's and Rosenstein's method with its 95 %
      interval in 1/s (natural log) and in bits per sample,
      :math:`\lambda_\text{bit} = \lambda\,\Delta t/\ln 2` — the unit of Wolf et al.'s
      (1985) program used by most papers — the verdict and its confidence; with
      ``chaos_reference`` each reference value is shown beside ours with the difference;
    * the evidence behind each verdict (votes, 0–1 K, surrogate p-value, reason);
    * phase portraits :math:`(x, \dot x)`, Poincaré/stroboscopic maps (stroboscopic
      :math:`(x, \dot x)` once per drive period when ``drive_period`` or
      ``phase_variable`` is given; otherwise the return map of successive maxima; for
      maps the return map of the iterates), and the divergence curves of both methods
      with their fit ranges — one figure per variable, one panel per state.

    Then the caller's material (:class:`~chaoskit.ReportExtras`): ``tables`` (e.g.
    response metrics with a paper's values, ratios and differences), ``sweep_maps``
    (MLE/verdict maps over two swept parameters, with a table), ``bifurcations`` (diagrams
    from :func:`chaoskit.bifurcation_diagram`), ``figures``; and at the end the parameters
    and provenance: date, command, package versions, every input (source, samples,
    sampling interval), the analysis settings, ``parameters`` and the scene JSON stored in
    each trajectory's ``scene`` attribute. Every table and figure is numbered and
    captioned.

    Parameters
    ----------
    trajectories
        A trajectory (Dataset or file path), a sequence of them, or a mapping
        ``{state label: trajectory}``; None for a report of tables and figures only.
    variables
        Series to analyse: specs ``"NAME"``, ``"NAME[DIM=VALUE,...]"`` (one element along
        extra dimensions, e.g. ``"eccentricity_x[joint=C]"``) or ``"ALIAS=SPEC"``, or a
        mapping ``{alias: spec}`` (e.g. ``{"X": "eccentricity_x[joint=C]"}``). Extra
        dimensions of length 1 are squeezed.
    labels
        State labels for a sequence of trajectories (default: file stems, or
        "trajectory 1", ...).
    sel
        Selections applied to every variable that has the dimension, e.g.
        ``{"joint": "C"}``; a spec's own selection wins.
    discard
        Transient dropped from the start of each trajectory, in units of its index (s for
        ``time``, iterations for ``step``).
    drive_period, phase_variable
        Drive of a forced system (s, or an angle variable such as ``crank_angle``, which
        may also be a spec): used by the verdict's stroboscopic section and the maps.
    title
        Page title.
    output
        If given, write the HTML page there and the Markdown twin beside it
        (:meth:`Report.write`).
    extras
        What the caller adds: the equations' exponents, reference values for the chaos
        table, tables, sweep maps, bifurcation diagrams, figures, run parameters and the
        command (:class:`~chaoskit.ReportExtras`).
    options
        Finer settings: subsampling, surrogates and their random stream, further measures,
        display units, how the Markdown twin holds its figures, a progress bar
        (:class:`~chaoskit.ReportOptions`).

        The fields of these two objects are not keywords of ``report``: given as one,
        a TypeError names the object that holds it.

    Returns
    -------
    Report

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> t, s = chaoskit.systems.duffing(3000, gamma=0.28, samples_per_period=50)
    >>> before = chaoskit.load_trajectory(s, dt=t[1] - t[0], variables=["x", "v"])
    >>> t, s = chaoskit.systems.duffing(3000, gamma=0.5, samples_per_period=50)
    >>> after = chaoskit.load_trajectory(s, dt=t[1] - t[0], variables=["x", "v"])
    >>> rep = chaoskit.report({"before": before, "after": after}, variables=["x"],
    ...                       drive_period=2 * np.pi / 1.2,
    ...                       options=chaoskit.ReportOptions(rng=0))
    >>> rep.table("chaos").data.loc[("x", "after"), "verdict"]
    'chaotic'
    """
    created = now()
    extras, options = checked_options(extras, options)
    pairs = normalise_trajectories(trajectories, labels)
    specs = normalise_variables(variables)
    discard, phase, measure_names, shown_units = _checked_inputs(
        pairs, specs, discard=discard, phase_variable=phase_variable, extras=extras, options=options
    )
    states = _analyse_states(
        pairs,
        specs,
        sel=sel,
        phase=phase,
        discard=discard,
        max_samples=options.max_samples,
        common={
            "drive_period": drive_period,
            "n_surrogates": options.n_surrogates,
            "progress": options.progress,
        },
        exponents=extras.exponents,
        rng=options.rng,
        executor=options.executor,
    )

    sections: dict[str, list[Any]] = {name: [] for name in SECTION_ORDER}
    texts: dict[str, str] = {}

    def put(item: Any, section: str | None = None) -> None:
        sections.setdefault(section or item.section, []).append(item)

    for t in extras.tables:
        put(t)
    analysis = None
    if states:
        kinds = {v.kind for st in states for v in st.verdicts.values()}
        kind = "map" if kinds == {"map"} else "flow"
        analysis_tables(
            states,
            specs,
            put,
            texts,
            kind=kind,
            motion=any(st.motion is not None for st in states),
            chaos_reference=extras.chaos_reference,
            reference_name=extras.reference_name,
            chaos_notes=extras.chaos_notes,
        )
        analysis_figures(
            states,
            specs,
            put,
            kind=kind,
            drive_period=drive_period,
            phase=phase,
            display_units=shown_units,
        )
        if measure_names:
            rng = options.rng
            seed = int(rng) if isinstance(rng, (int, np.integer)) else 0
            measure_items(states, specs, measure_names, put, report_figure, rng=seed)
        analysis = xr.concat(
            [verdict_table(st.verdicts) for st in states],
            dim=pd.Index([st.label for st in states], name="state"),
        )
    for m in extras.sweep_maps:
        sweep_items(m, put)
    if extras.bifurcations is not None:
        bifurcation_items(extras.bifurcations, put)
    for f in extras.figures:
        put(f)
    prov = provenance_items(
        states,
        specs=specs,
        created=created,
        title=title,
        command=extras.command,
        settings={
            "variables": {s.alias: s.spec for s in specs},
            "sel": dict(sel or {}),
            "discard": discard,
            "max_samples": options.max_samples,
            "drive_period": drive_period,
            "phase_variable": None if phase is None else phase.spec,
            "n_surrogates": options.n_surrogates,
            "rng": options.rng if isinstance(options.rng, (int, np.integer)) else repr(options.rng),
            **({"display_units": shown_units} if shown_units else {}),
        },
        parameters=extras.parameters,
    )
    sections.pop(PROVENANCE, None)
    appendix = sections.pop(APPENDIX, [])
    ordered = [(name, items) for name, items in sections.items() if items]
    if appendix:
        ordered.append((APPENDIX, appendix))
    ordered.append((PROVENANCE, prov))
    rep = Report(
        title=title,
        sections=tuple(
            ReportSection(title=name, items=tuple(items), text=texts.get(name, ""))
            for name, items in ordered
        ),
        created=created,
        analysis=analysis,
        verdicts={st.label: dict(st.verdicts) for st in states},
        motions={st.label: st.motion for st in states if st.motion is not None},
    )
    if output is not None:
        rep.write(output, markdown_figures=options.markdown_figures)
    return rep


def _checked_inputs(
    pairs: list[tuple[str, Any]],
    specs: list[VariableSpec],
    *,
    discard: float,
    phase_variable: str | None,
    extras: ReportExtras,
    options: ReportOptions,
) -> tuple[float, VariableSpec | None, tuple[str, ...], dict[str, str]]:
    """Refuse bad arguments of :func:`report` before any analysis runs; the discard, the
    phase variable, the measures and the display units, parsed."""
    max_samples, markdown_figures = options.max_samples, options.markdown_figures
    exponents = extras.exponents
    if pairs and not specs:
        raise ValueError("give variables=[...] (the series to analyse) with the trajectories.")
    if specs and not pairs:
        raise ValueError("variables= given but no trajectories to analyse.")
    discard = float(discard)
    if not math.isfinite(discard) or discard < 0:
        raise ValueError(f"discard must be a finite number >= 0; got {discard!r}.")
    if max_samples is not None and (not isinstance(max_samples, int) or max_samples < 200):
        raise ValueError(f"max_samples must be an integer >= 200 or None; got {max_samples!r}.")
    if options.executor is not None and not callable(getattr(options.executor, "submit", None)):
        raise ValueError(
            "executor must be None or an executor with a submit method "
            f"(concurrent.futures); got {type(options.executor).__name__}."
        )
    if markdown_figures not in ("files", "embed"):
        raise ValueError(f"markdown_figures must be 'files' or 'embed'; got {markdown_figures!r}.")
    for t in extras.tables:
        if not isinstance(t, ReportTable):
            raise ValueError(f"tables must hold ReportTable objects; got {type(t).__name__}.")
    for f in extras.figures:
        if not isinstance(f, ReportFigure):
            raise ValueError(f"figures must hold ReportFigure objects; got {type(f).__name__}.")
    phase = parse_variable(phase_variable) if phase_variable is not None else None
    measure_names = parse_measures(options.measures)
    shown_units = check_display_units(options.display_units, specs)
    if exponents is not None:
        if not isinstance(exponents, Mapping):
            raise ValueError("exponents must be a mapping {state label: exponent}.")
        unknown = [k for k in exponents if k not in [lab for lab, _ in pairs]]
        if unknown:
            raise ValueError(
                f"exponents names states {unknown} that are not among {[lab for lab, _ in pairs]}."
            )
    return discard, phase, measure_names, shown_units


def _analyse_states(
    pairs: list[tuple[str, Any]],
    specs: list[VariableSpec],
    *,
    sel: Mapping[str, Any] | None,
    phase: VariableSpec | None,
    discard: float,
    max_samples: int | None,
    common: Mapping[str, Any],
    exponents: Mapping[str, Any] | None,
    rng: Any,
    executor: Any,
) -> list[State]:
    """Prepare and classify every state, each with its own stream spawned from ``rng``;
    on ``executor``, one task per state (the same verdicts: each task has its stream)."""
    streams = as_generator(rng).spawn(len(pairs)) if pairs else []
    prepared = []
    tasks = []
    for (label, source), stream in zip(pairs, streams, strict=True):
        view, info = prepare_state(
            label,
            source,
            specs=specs,
            sel=sel,
            phase=phase,
            discard=discard,
            max_samples=max_samples,
        )
        prepared.append((label, view, info))
        settings: dict[str, Any] = {
            "variables": [s.alias for s in specs],
            "drive_period": common["drive_period"],
            "phase_variable": None if phase is None else phase.alias,
            "n_surrogates": common["n_surrogates"],
            "rng": stream,
            "progress": common["progress"],
        }
        exponent = None if exponents is None else exponents.get(label)
        tasks.append((view, len(specs) > 1, exponent, settings))
    if executor is not None and len(tasks) > 1:
        futures = [executor.submit(_classify_state, *task) for task in tasks]
        outcomes = [f.result() for f in futures]
    else:
        outcomes = [_classify_state(*task) for task in tasks]
    return [
        State(label=label, view=view, verdicts=verdicts, motion=motion, **info)
        for (label, view, info), (verdicts, motion) in zip(prepared, outcomes, strict=True)
    ]


def _classify_state(
    view: xr.Dataset, joint: bool, exponent: Any, settings: dict[str, Any]
) -> tuple[dict[str, Any], Any]:
    """One state's verdicts by variable and its motion verdict (None unless ``joint``:
    :func:`classify_motion` of all its variables together)."""
    if joint:
        motion = classify_motion(view, exponent=exponent, **settings)
        return dict(motion.variables), motion
    return classify_variables(view, **settings), None
