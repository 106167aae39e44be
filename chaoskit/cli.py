"""Command-line interface: a thin layer that loads, calls the library and prints."""

from __future__ import annotations

import os
import shlex
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import typer
from typer.core import TyperGroup

from . import plot
from ._contract import ParameterError
from ._formats import SUFFIXES as _RIG_SUFFIXES
from ._io import CSV_SUFFIXES, NAN_POLICIES, NPZ_SUFFIXES, RESAMPLE_METHODS, load_trajectory
from ._measure_registry import measure_figures, measures_for_verdicts, measures_text, parse_measures
from ._paths import folder_problem, unique_filename
from ._portraits import phase_portrait
from ._samples import sample_path
from ._selection import expand_variables, parse_variable, select_series, variable_spec
from ._validate import check_choice, check_int, check_positive
from ._version import __version__
from .denoise import MAX_ITERATIONS as DENOISE_MAX_ITERATIONS
from .denoise import local_projective_denoise
from .reporting import ReportExtras, ReportOptions, plural
from .reporting import report as build_report
from .verdict import (
    MotionVerdict,
    classify_motion,
    classify_variables,
    series_dataset,
    verdict_table,
)

#: exit status of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it)
EXIT_INTERRUPTED = 130


class _Commands(TyperGroup):
    """The command group: Ctrl-C ends any command with one line and exit status 130."""

    def invoke(self, ctx: Any) -> Any:
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            typer.echo("interrupted", err=True)
            if sys.stderr is sys.__stderr__:  # a process of its own, not an in-process runner
                # The interpreter's teardown (numba's compiled modules, a full garbage
                # collection) takes 1-9 s, so the process ends here. Nothing is lost: the
                # with-blocks and finally clauses (temporary files of atomic writes) ran
                # while the interruption unwound, and the streams are flushed.
                sys.stdout.flush()
                sys.stderr.flush()
                os._exit(EXIT_INTERRUPTED)
            raise typer.Exit(code=EXIT_INTERRUPTED) from None


app = typer.Typer(
    name="chaoskit",
    help="Decide from a trajectory whether the motion is periodic, quasi-periodic or chaotic.",
    no_args_is_help=True,
    add_completion=False,
    cls=_Commands,
    # plain (click) help at a fixed 100 columns: long option names, help texts and command
    # summaries wrap instead of being cut at the terminal's width as in the rich panels,
    # and flags show no value type
    rich_markup_mode=None,
    context_settings={"terminal_width": 100, "max_content_width": 100},
)

DEFAULT_SAMPLE = "lorenz.nc"  # chaoskit.sample_path finds it wherever chaoskit is installed
#: Options whose name is not the library parameter's with dashes (``skip_rows`` → ``--skip-rows``).
OPTIONS = {"variables": "--var"}
#: ``coverage_content_type`` values (ACDD) of variables that are not the motion itself.
AUXILIARY = ("auxiliaryInformation", "qualityInformation", "referenceInformation")


@contextmanager
def _user_errors() -> Iterator[None]:
    """Everyday mistakes (bad input, missing or unreadable files) end in one line and exit 2.

    A :class:`~chaoskit.contract.ParameterError` is worded with the options of the command
    line (``--dt``) instead of the library's parameters (``dt=``)."""
    try:
        yield
    except (ValueError, OSError) as exc:
        if isinstance(exc, ParameterError):
            text = exc.render(command_line=True, options=OPTIONS)
        else:
            text = str(exc)
        text = text.strip() or type(exc).__name__
        typer.echo(f"error: {text.splitlines()[0]}", err=True)
        raise typer.Exit(code=2) from None


@contextmanager
def _bar_line_ended(progress: bool) -> Iterator[None]:
    """On Ctrl-C, end the line of the progress bar, so that ``interrupted`` is a line of
    its own (the bar redraws its line with carriage returns and no newline)."""
    try:
        yield
    except KeyboardInterrupt:
        if progress:
            typer.echo("", err=True)
        raise


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"chaoskit {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
) -> None:
    """chaoskit command line."""


def _interval(value: float, low: float, high: float) -> str:
    if value != value:  # NaN
        return "—"
    return f"{value:.4g} [{low:.3g}, {high:.3g}]"


def format_table(table: Any) -> str:
    """The rows of :func:`chaoskit.analyze` as a fixed-width text table."""
    unit = table["mle_rosenstein"].attrs.get("units", "")
    unit = "1/s" if unit == "s-1" else "per iteration"
    header = (
        "variable",
        "verdict",
        "period",
        "confidence",
        "lag",
        "m",
        f"MLE Rosenstein ({unit}) [95% CI]",
        f"MLE Wolf ({unit}) [95% CI]",
        "0-1 K",
        "surrogate p",
    )
    rows = [header]
    for name in table["variable"].values:
        r = table.sel(variable=name)

        def num(key: str, fmt: str, r: Any = r) -> str:
            value = float(r[key])
            return "—" if value != value else format(value, fmt)

        rows.append(
            (
                str(name),
                str(r["label"].item()),
                num("period", ".0f"),
                num("confidence", ".2f"),
                num("lag", ".0f"),
                num("embedding_dim", ".0f"),
                _interval(
                    float(r["mle_rosenstein"]),
                    float(r["mle_rosenstein_low"]),
                    float(r["mle_rosenstein_high"]),
                ),
                _interval(
                    float(r["mle_wolf"]), float(r["mle_wolf_low"]), float(r["mle_wolf_high"])
                ),
                num("zero_one_k", ".2f"),
                num("surrogate_p_value", ".2f"),
            )
        )
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    lines = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)) for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(line.rstrip() for line in lines)


def _write_figures(
    ds: Any, verdicts: dict[str, Any], directory: Path, measures: dict[str, Any] | None = None
) -> list[Path]:
    """One PNG per figure and variable; returns the paths written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    directory.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for name, verdict in verdicts.items():
        if verdict.label == "equilibrium":
            continue
        figures: list[tuple[str, Any]] = []
        if "time" in ds.coords:
            try:
                series = select_series(ds, variable_spec(ds, name)).to_dataset(name=name)
                portrait = phase_portrait(series, variable=name)
                figures.append(
                    ("phase_portrait", lambda ax, p=portrait: plot.phase_portrait(p, ax=ax))
                )
            except ValueError:
                pass  # e.g. non-uniform sampling: no estimated derivative, no portrait
        if verdict.section is not None and verdict.section.sizes.get("crossing", 0) > 1:
            figures.append(("poincare", lambda ax, v=verdict: plot.poincare(v, ax=ax)))
        for method in ("rosenstein", "wolf"):
            result = getattr(verdict, method)
            if result is not None:
                figures.append(
                    (f"divergence_{method}", lambda ax, r=result: plot.divergence(r, ax=ax))
                )
        if verdict.delay is not None:
            figures.append(
                ("mutual_information", lambda ax, v=verdict: plot.mutual_information(v, ax=ax))
            )
        if verdict.dimension is not None:
            figures.append(
                (
                    "false_nearest_neighbors",
                    lambda ax, v=verdict: plot.false_nearest_neighbors(v, ax=ax),
                )
            )
        if measures and name in measures:
            figures += [(kind, draw) for kind, _, draw in measure_figures(measures[name])]
        for kind, draw in figures:
            fig, ax = plt.subplots(figsize=(5.0, 4.0), layout="constrained")
            try:
                draw(ax)
                fig.suptitle(f"{name}: {verdict.label}", fontsize=10)
                path = directory / f"{unique_filename(name)}_{kind}.png"
                fig.savefig(path, dpi=110)
                written.append(path)
            finally:
                plt.close(fig)
    return written


def _split_specs(text: str) -> list[str]:
    """``"x, e[joint=B,axis=0]"`` → ``["x", "e[joint=B,axis=0]"]``: commas inside brackets
    belong to the selection."""
    out, depth, cur = [], 0, ""
    for ch in text:
        depth += (ch == "[") - (ch == "]")
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    out.append(cur.strip())
    return [p for p in out if p]


def _motion_text(mv: MotionVerdict) -> str:
    conf = "" if mv.label == "undetermined" else f" (confidence {mv.confidence:.2f})"
    period = f", period {mv.period}" if mv.period is not None else ""
    lines = [f"Motion ({', '.join(mv.variables)}): {mv.label}{period}{conf}"]
    lines += [f"  {r}" for r in mv.reasons if not r.startswith(tuple(mv.variables))]
    lines += [f"  needs: {n}" for n in mv.needs]
    return "\n".join(lines)


def _is_constant(series: Any) -> bool:
    values = series.values
    return bool(values.size) and bool(values.min() == values.max())


def _default_series(ds: Any, phase: str | None) -> tuple[list[str], str]:
    """The series ``chaoskit analyze`` takes without ``--var``, and a line saying which and why.

    The variables of the motion: those the file lists in its ``motion_variables`` attribute
    (blank-separated names), else every series but those marked auxiliary by their
    ``coverage_content_type``; constant series are left out unless all are constant.
    """
    index = "time" if "time" in ds.coords else "step"
    exclude = [] if phase is None else [variable_spec(ds, phase).name]
    every = expand_variables(ds, None, exclude=exclude)
    listed = [
        n
        for n in str(ds.attrs.get("motion_variables", "")).split()
        if n in ds.data_vars and index in ds[n].dims and n not in exclude
    ]
    if listed:
        specs, why = expand_variables(ds, listed), "the motion variables the file names"
    else:
        aux = sorted(
            str(k)
            for k, v in ds.data_vars.items()
            if v.attrs.get("coverage_content_type") in AUXILIARY and str(k) not in exclude
        )
        specs = [s for s in every if s.name not in aux]
        why = "every series" if not aux else f"every series but the auxiliary {', '.join(aux)}"
    constant = [s.alias for s in specs if _is_constant(select_series(ds, s))]
    chosen = [s.alias for s in specs if s.alias not in constant] or [s.alias for s in specs]
    if constant and len(chosen) < len(specs):
        why += f"; {len(constant)} constant {'ones' if len(constant) != 1 else 'one'} left out"
    shown = ", ".join(chosen[:12]) + (
        f", ... ({len(chosen) - 12} more)" if len(chosen) > 12 else ""
    )
    return chosen, f"series: {shown} ({len(chosen)} of {len(every)}: {why})"


def _discard(ds: Any, discard: float) -> Any:
    """``ds`` without its first ``discard`` seconds (iterations for a map)."""
    discard = check_positive(discard, name="--discard", allow_zero=True)
    if discard == 0.0:
        return ds
    index = "time" if "time" in ds.coords else "step"
    first, last = ds[index].values[0], ds[index].values[-1]
    kept = ds.sel({index: ds[index] >= first + discard})
    if kept.sizes[index] < 2:
        unit = "s" if index == "time" else "iterations"
        raise ValueError(
            f"--discard {discard:g} leaves {kept.sizes[index]} sample"
            f"{'s' * (kept.sizes[index] != 1)}: the record spans "
            f"{float(last - first):g} {unit}."
        )
    return kept


def _load(path: Path, keep: list[str], *, discard: float = 0.0, **options: Any) -> tuple[Any, str]:
    """The trajectory as the options read it, the transient dropped, and a line saying how
    long it is. A table loads only the columns in ``keep`` (when given), so other columns
    may hold text."""
    names = None
    if keep and path.suffix.lower() in CSV_SUFFIXES | NPZ_SUFFIXES | set(_RIG_SUFFIXES):
        names = list(dict.fromkeys(parse_variable(v).name for v in keep))
    ds = _discard(load_trajectory(path, variables=names, **options), discard)
    index = "time" if "time" in ds.coords else "step"
    cut = f" after the first {discard:g} {'s' if index == 'time' else 'iterations'}"
    return ds, f"  {ds.sizes[index]} samples along {index!r}" + (cut if discard else "")


def _denoise(ds: Any, names: list[str], iterations: int) -> tuple[Any, list[str]]:
    """``ds`` with each series of ``names`` replaced by its local projective noise
    reduction (parameters chosen from the data, ``iterations`` passes), the parameters in
    the series' ``denoised`` attribute and the file's ``history``; and one line per series
    saying what was done."""
    ds = ds.copy()
    index = "time" if "time" in ds.coords else "step"
    lines, notes = [], []
    for alias in names:
        spec = variable_spec(ds, alias)
        series = select_series(ds, spec)
        res = local_projective_denoise(series, iterations=iterations)
        std = float(np.std(res.original))
        share = 100.0 * res.noise_level / std if std > 0 else float("nan")
        note = (
            f"local projective noise reduction: embedding_dim={res.embedding_dim}, "
            f"lag={res.lag}, manifold_dim={res.manifold_dim}, iterations={res.iterations}, "
            f"noise_level={res.noise_level:.4g} ({share:.3g} % of the standard deviation), "
            f"correction_rms={', '.join(f'{c:.3g}' for c in res.correction_rms)}"
        )
        var = ds[spec.name]
        where = {
            d: (var.get_index(d).get_loc(series[d].item()) if d in series.coords else 0)
            for d in var.dims
            if d != index
        }
        values = var.values.astype(float)
        values[tuple(where.get(d, slice(None)) for d in var.dims)] = res.cleaned
        attrs = {**var.attrs, "denoised": note if var.ndim == 1 else f"{alias}: {note}"}
        ds[spec.name] = (var.dims, values, attrs)
        lines.append(f"  denoised {alias}: {note}")
        notes.append(f"{alias} denoised by chaoskit analyze --denoise: {note}")
    history = str(ds.attrs.get("history", "")).strip()
    ds.attrs["history"] = "\n".join([*([history] if history else []), *notes])
    return ds, lines


def _run_analysis(
    path: Path,
    variables: list[str] | None,
    *,
    figures: Path | None,
    drive_period: float | None,
    phase_variable: str | None,
    seed: int,
    progress: bool,
    measures: str | None = None,
    motion: str | None = None,
    drive_variables: list[str] | None = None,
    discard: float = 0.0,
    denoise: int = 0,
    **reading: Any,
) -> None:
    """Load, classify and print; ``reading`` holds the options of :func:`load_trajectory`
    (time, dt, step, skip_rows, decimal, nan, group, resample); ``denoise`` passes of noise
    reduction of the analysed series first (0: none)."""
    with _user_errors():
        if drive_period is not None:  # else every variable's analysis fails on it (exit 1)
            check_positive(drive_period, name="--drive-period")
        problem = None if figures is None else folder_problem(figures, f"--figures {figures}")
        if problem is not None:  # refused before the analysis, not after it
            raise ValueError(problem)
        names = parse_measures(measures)
        off = motion is not None and motion.strip().lower() == "none"
        chosen = (_split_specs(motion) if motion else None) if not off else None
        if motion is not None and not off and not chosen:
            raise ValueError("--motion must name variables (x,y,...) or be 'none'.")
        every = variables == ["all"]
        extra = [*(chosen or []), *(drive_variables or []), phase_variable]
        keep = [] if every or not variables else [*variables, *[e for e in extra if e]]
        ds, length = _load(path, keep, discard=discard, **reading)
        if every and "all" not in ds.data_vars:
            variables = None  # every series, as listed
        elif variables == ["all"]:
            every = False  # a variable named "all"
        from_file = phase_variable is None and drive_period is None
        phase_variable = _file_phase(ds) if from_file else phase_variable
        typer.echo(f"{path}: {ds.attrs.get('title', '')}")
        typer.echo(length)
        if variables is None and not every:
            variables, line = _default_series(ds, phase_variable)
            typer.echo(line)
            typer.echo("  others: --var NAME (repeat, or comma-separated); every series: --var all")
        if from_file and phase_variable is not None:
            typer.echo(f"  drive phase: {phase_variable} (the file's phase_variable attribute)")
        typer.echo("")
        _, rows = series_dataset(ds, variables=variables or None, phase_variable=phase_variable)
        motion_names = rows
        if chosen is not None:
            _, motion_names = series_dataset(ds, variables=chosen, phase_variable=phase_variable)
        if denoise:
            setting_aside = {*(drive_variables or []), phase_variable}
            cleaned = [n for n in dict.fromkeys([*rows, *motion_names]) if n not in setting_aside]
            ds, lines = _denoise(ds, cleaned, denoise)
            typer.echo("\n".join(lines))
            typer.echo("")
        mv = None
        if not off and len(motion_names) >= 2:
            with _bar_line_ended(progress):
                mv = classify_motion(
                    ds,
                    variables=motion_names,
                    drive_period=drive_period,
                    phase_variable=phase_variable,
                    drive_variables=drive_variables or (),
                    rng=seed,
                    progress=progress,
                )
        elif drive_variables:
            raise ValueError("--drive-variable needs a motion of two or more variables.")
        if mv is not None and set(rows) <= set(mv.variables):
            verdicts = {name: mv.variables[name] for name in rows}
        else:
            with _bar_line_ended(progress):
                verdicts = classify_variables(
                    ds,
                    variables=rows,
                    drive_period=drive_period,
                    phase_variable=phase_variable,
                    rng=seed,
                    progress=progress,
                )
        table = verdict_table(verdicts)
        if denoise:
            table.attrs["history"] = ds.attrs["history"]
    if progress:
        typer.echo("", err=True)  # end the line of the progress bar
    _print_results(ds, mv, table, verdicts, figures=figures, measures=names, seed=seed)


def _file_phase(ds: Any) -> str | None:
    """The drive-angle variable the file names in its ``phase_variable`` attribute, if any."""
    name = ds.attrs.get("phase_variable")
    return str(name) if isinstance(name, str) and name in ds.data_vars else None


def _print_results(
    ds: Any,
    mv: MotionVerdict | None,
    table: Any,
    verdicts: dict[str, Any],
    *,
    figures: Path | None,
    measures: Any,
    seed: int,
) -> None:
    if mv is not None:
        typer.echo(_motion_text(mv))
        typer.echo("")
    typer.echo(format_table(table))
    typer.echo("")
    for name, verdict in verdicts.items():
        typer.echo(f"{name}: {verdict.reason}")
    with _user_errors():
        results = measures_for_verdicts(ds, verdicts, measures, rng=seed) if measures else None
    if results:
        typer.echo("")
        typer.echo(measures_text(results))
    if figures is not None:
        with _user_errors():
            written = _write_figures(ds, verdicts, figures, results)
        typer.echo(f"\n{len(written)} figure{'s' * (len(written) != 1)} written to {figures}")
    failed = [name for name, v in verdicts.items() if "classify" in v.errors]
    if failed and len(failed) == len(verdicts):
        typer.echo(
            f"error: the analysis failed for every variable ({', '.join(failed)}).", err=True
        )
        raise typer.Exit(code=1)


@app.command()
def analyze(
    path: Path = typer.Argument(
        ...,
        help="Trajectory file: netCDF, CSV or npz, or from a test rig: MATLAB .mat, NI .tdms, "
        "HDF5 .h5, .wav, .parquet.",
    ),
    var: list[str] = typer.Option(
        None,
        "--var",
        "--variables",
        help="Variable to analyse: NAME or NAME[DIM=VALUE] (repeat, or comma-separated); "
        "'all' for every series. A variable with extra dimensions is analysed once per "
        "label, e.g. eccentricity_x[joint=C]. Default: the variables of the motion (those "
        "the file lists in its motion_variables attribute, else every series not marked "
        "auxiliary), constant series left out.",
    ),
    figures: Path | None = typer.Option(
        None, "--figures", help="Folder for the figures (PNG), one set per variable."
    ),
    drive_period: float | None = typer.Option(
        None, "--drive-period", help="Period of an external drive, s (stroboscopic section)."
    ),
    phase_variable: str | None = typer.Option(
        None,
        "--phase-variable",
        help="Drive angle variable, rad (stroboscopic section). Default: the one the file "
        "names in its phase_variable attribute, unless --drive-period is given.",
    ),
    discard: float = typer.Option(
        0.0,
        "--discard",
        help="Transient dropped from the start of the trajectory, s (iterations for maps).",
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the 0-1 test and the surrogates."),
    time: str | None = typer.Option(
        None,
        "--time",
        help="Name of the time column (or variable), s (default: time, t, ... if present).",
    ),
    dt: float | None = typer.Option(
        None, "--dt", help="Sampling interval, s, for data without a time column."
    ),
    step: str | None = typer.Option(
        None,
        "--step",
        help="Map data: the integer iteration column ('--step step' numbers the rows).",
    ),
    skip_rows: int = typer.Option(
        0, "--skip-rows", help="Text tables: lines to skip above the header (a title)."
    ),
    decimal: str = typer.Option(
        ".",
        "--decimal",
        help="Text tables: the decimal mark, '.' or ',' (columns then separated by ';', tab, "
        "'|' or blanks).",
    ),
    nan: str = typer.Option(
        "refuse",
        "--nan",
        help="Missing values: refuse (name the line), drop (the rows; only where the "
        "sampling stays uniform) or interpolate (linear in time).",
    ),
    group: str | None = typer.Option(
        None,
        "--group",
        help="Rig files with several groups or structs: the TDMS or HDF5 group, or the "
        "MATLAB struct, to read.",
    ),
    resample: str | None = typer.Option(
        None,
        "--resample",
        help="'linear': interpolate irregular time stamps onto a uniform grid (of --dt if "
        "given, else their mean interval, gaps left out); rig files with irregular stamps "
        "need it.",
    ),
    measures: str | None = typer.Option(
        None,
        "--measures",
        help="Further measures, comma-separated: d2 (correlation dimension), rqa (recurrence "
        "quantification), spectrum (Lyapunov spectrum), sampen (sample entropy), dfa, hurst; "
        "or all.",
    ),
    motion: str | None = typer.Option(
        None,
        "--motion",
        help="Variables of the motion, comma-separated (e.g. x,y or "
        "eccentricity_x[joint=C],eccentricity_y[joint=C]): one verdict for them all, shown "
        "first. Default: the analysed variables (multi-dimensional ones by label); 'none' or "
        "a single variable: per-variable only.",
    ),
    drive_variable: list[str] = typer.Option(
        None,
        "--drive-variable",
        help="A variable of the motion that follows the drive alone (e.g. a prescribed crank "
        "angle): set aside from the motion verdict (repeat). Such variables are also found "
        "by themselves when --drive-period or --phase-variable is given.",
    ),
    denoise: bool = typer.Option(
        False,
        "--denoise",
        help="Reduce measurement noise in the analysed series before the analysis (local "
        "projective noise reduction, its parameters chosen from the data and printed); off "
        "by default: noise reduction also changes what the estimators see.",
    ),
    denoise_iterations: int = typer.Option(
        3,
        "--denoise-iterations",
        help=f"Passes of the noise reduction with --denoise, 1 to {DENOISE_MAX_ITERATIONS}.",
    ),
) -> None:
    """Classify the motion of a trajectory (its variables together) and each variable,
    and print the motion verdict, then the evidence table.

    Exit status: 0 on success, 2 for bad input (nothing analysed), 1 when the analysis failed
    for every variable.
    """
    specs = [p for v in var or [] for p in _split_specs(v)]
    with _user_errors():  # options first: nothing is read for a bad one
        nan = check_choice(nan, name="--nan", choices=NAN_POLICIES)
        discard = check_positive(discard, name="--discard", allow_zero=True)
        if resample is not None:
            resample = check_choice(resample, name="--resample", choices=RESAMPLE_METHODS)
        denoise_iterations = check_int(
            denoise_iterations,
            name="--denoise-iterations",
            minimum=1,
            maximum=DENOISE_MAX_ITERATIONS,
        )
    _run_analysis(
        path,
        specs or None,
        figures=figures,
        drive_period=drive_period,
        phase_variable=phase_variable,
        seed=seed,
        progress=True,
        time=time,
        dt=dt,
        step=step,
        skip_rows=skip_rows,
        decimal=decimal,
        nan=nan,
        group=group,
        resample=resample,
        discard=discard,
        measures=measures,
        motion=motion,
        drive_variables=list(drive_variable) if drive_variable else None,
        denoise=denoise_iterations if denoise else 0,
    )


@app.command()
def demo(
    path: Path | None = typer.Argument(
        None, help="Trajectory file (default: the Lorenz sample shipped with chaoskit)."
    ),
) -> None:
    """Analyse a sample trajectory (by default the Lorenz system) and print the result."""
    if path is None:
        with _user_errors():
            path = sample_path(DEFAULT_SAMPLE)
    _run_analysis(
        path, None, figures=None, drive_period=None, phase_variable=None, seed=0, progress=False
    )


def _check_output(path: Path) -> None:
    """Refuse, before any analysis, an output that is a folder or lies in an unwritable one."""
    if path.is_dir():
        raise ValueError(
            f"{path} is a folder; give the report's file name, e.g. {path}/report.html"
        )
    problem = folder_problem(path.parent, f"cannot create {path}")
    if problem is not None:
        raise ValueError(problem)


def _parse_selections(items: list[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for item in items:
        key, eq, value = item.partition("=")
        if not eq or not key.strip() or not value.strip():
            raise ValueError(f"--sel {item!r} must read DIM=VALUE (e.g. joint=C).")
        out[key.strip()] = value.strip()
    return out


def _read_reference(path: Path) -> Any:
    frame = pd.read_csv(path, comment="#")
    missing = [c for c in ("variable", "state") if c not in frame.columns]
    if missing:
        raise ValueError(f"the reference table {path} needs the columns variable and state.")
    frame["variable"] = frame["variable"].astype(str)
    frame["state"] = frame["state"].astype(str)
    return frame.set_index(["variable", "state"])


@app.command()
def report(
    paths: list[Path] = typer.Argument(..., help="Trajectory files, one per state."),
    var: list[str] = typer.Option(
        ...,
        "--var",
        help="Variable to analyse: NAME, NAME[DIM=VALUE] or ALIAS=NAME[DIM=VALUE] (repeat).",
    ),
    label: list[str] = typer.Option(
        None, "--label", help="Name of each state, in file order (default: file stems)."
    ),
    output: Path = typer.Option(
        ..., "-o", "--output", help="HTML report to write; the Markdown twin goes beside it."
    ),
    sel: list[str] = typer.Option(
        None, "--sel", help="DIM=VALUE applied to every variable with that dimension (repeat)."
    ),
    discard: float = typer.Option(
        0.0, "--discard", help="Transient dropped from the start of each trajectory, s."
    ),
    max_samples: int | None = typer.Option(
        None, "--max-samples", help="Subsample so that at most this many samples are analysed."
    ),
    drive_period: float | None = typer.Option(
        None, "--drive-period", help="Period of an external drive, s (stroboscopic maps)."
    ),
    phase_variable: str | None = typer.Option(
        None, "--phase-variable", help="Drive angle variable, rad (stroboscopic maps)."
    ),
    chaos_reference: Path | None = typer.Option(
        None,
        "--chaos-reference",
        help="CSV of reference values for the chaos table: columns variable, state, and any "
        "of lag, embedding_dim, mle_wolf_bits, ...",
    ),
    reference_name: str = typer.Option(
        "reference", "--reference-name", help="Header of the reference values (e.g. paper)."
    ),
    title: str = typer.Option("chaoskit report", "--title", help="Title of the report."),
    embed_figures: bool = typer.Option(
        False, "--embed-figures", help="Embed the figures in the Markdown twin too."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the 0-1 test and the surrogates."),
    measures: str | None = typer.Option(
        None,
        "--measures",
        help="Further measures in a section of their own, comma-separated: d2, rqa, "
        "spectrum, sampen, dfa, hurst; or all.",
    ),
) -> None:
    """Analyse trajectories and write an HTML report with its Markdown twin."""
    with _user_errors():
        _check_output(output)
        reference = _read_reference(chaos_reference) if chaos_reference is not None else None
        rep = build_report(
            [str(p) for p in paths],
            variables=list(var),
            labels=list(label) if label else None,
            sel=_parse_selections(list(sel or [])),
            discard=discard,
            drive_period=drive_period,
            phase_variable=phase_variable,
            title=title,
            extras=ReportExtras(
                chaos_reference=reference,
                reference_name=reference_name,
                command=shlex.join(["chaoskit", *sys.argv[1:]]),
            ),
            options=ReportOptions(
                max_samples=max_samples, rng=seed, measures=measures or (), progress=True
            ),
        )
        written = rep.write(output, markdown_figures="embed" if embed_figures else "files")
    overview = rep.table("verdict per variable").display()
    typer.echo(overview.droplevel(1, axis=1).to_string())
    typer.echo("")
    # the answer last, right above the files: the motion verdict of each state
    typer.echo("Motion verdict per state:" if rep.motions else "Verdict per state:")
    typer.echo(rep.answer_table().to_string())
    typer.echo("")
    typer.echo(f"report: {written['html']}")
    figures = plural(len(written["figures"]), "figure file")
    typer.echo(f"markdown: {written['markdown']} ({figures})")


if __name__ == "__main__":
    app()
