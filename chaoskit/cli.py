"""Command-line interface: a thin layer that loads, calls the library and prints."""

from __future__ import annotations

import os
import shlex
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pandas as pd
import typer

from . import plot
from ._io import load_trajectory
from ._measures import measure_figures, measures_for_verdicts, measures_text, parse_measures
from ._paths import unique_filename
from ._portraits import phase_portrait
from ._samples import sample_path
from ._selection import select_series, variable_spec
from ._version import __version__
from .reporting import report as build_report
from .verdict import MotionVerdict, classify_motion, classify_variables, verdict_table
from .verdict._analyze import series_dataset

app = typer.Typer(
    name="chaoskit",
    help="Decide from a trajectory whether the motion is periodic, quasi-periodic or chaotic.",
    no_args_is_help=True,
    add_completion=False,
)

DEFAULT_SAMPLE = "lorenz.nc"  # chaoskit.sample_path finds it wherever chaoskit is installed


@contextmanager
def _user_errors() -> Iterator[None]:
    """Everyday mistakes (bad input, missing or unreadable files) end in one line and exit 2."""
    try:
        yield
    except (ValueError, OSError) as exc:
        text = str(exc).strip() or type(exc).__name__
        typer.echo(f"error: {text.splitlines()[0]}", err=True)
        raise typer.Exit(code=2) from None


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


def _run_analysis(
    path: Path,
    variables: list[str] | None,
    *,
    figures: Path | None,
    drive_period: float | None,
    phase_variable: str | None,
    seed: int,
    progress: bool,
    time: str | None = None,
    dt: float | None = None,
    step: str | None = None,
    measures: str | None = None,
    motion: str | None = None,
    drive_variables: list[str] | None = None,
) -> None:
    with _user_errors():
        names = parse_measures(measures)
        ds = load_trajectory(path, time=time, dt=dt, step=step)
        off = motion is not None and motion.strip().lower() == "none"
        chosen = (_split_specs(motion) if motion else None) if not off else None
        if motion is not None and not off and not chosen:
            raise ValueError("--motion must name variables (x,y,...) or be 'none'.")
        _, rows = series_dataset(ds, variables=variables or None, phase_variable=phase_variable)
        motion_names = rows
        if chosen is not None:
            _, motion_names = series_dataset(ds, variables=chosen, phase_variable=phase_variable)
        mv = None
        if not off and len(motion_names) >= 2:
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
            verdicts = classify_variables(
                ds,
                variables=rows,
                drive_period=drive_period,
                phase_variable=phase_variable,
                rng=seed,
                progress=progress,
            )
        table = verdict_table(verdicts)
    index = "time" if "time" in ds.coords else "step"
    typer.echo(f"{path}: {ds.attrs.get('title', '')}")
    typer.echo(f"  {ds.sizes[index]} samples along {index!r}")
    typer.echo("")
    if mv is not None:
        typer.echo(_motion_text(mv))
        typer.echo("")
    typer.echo(format_table(table))
    typer.echo("")
    for name, verdict in verdicts.items():
        typer.echo(f"{name}: {verdict.reason}")
    with _user_errors():
        results = measures_for_verdicts(ds, verdicts, names, rng=seed) if names else None
    if results:
        typer.echo("")
        typer.echo(measures_text(results))
    if figures is not None:
        with _user_errors():
            written = _write_figures(ds, verdicts, figures, results)
        typer.echo(f"\n{len(written)} figure(s) written to {figures}")
    failed = [name for name, v in verdicts.items() if "classify" in v.errors]
    if failed and len(failed) == len(verdicts):
        typer.echo(
            f"error: the analysis failed for every variable ({', '.join(failed)}).", err=True
        )
        raise typer.Exit(code=1)


@app.command()
def analyze(
    path: Path = typer.Argument(..., help="Trajectory file (netCDF, CSV or npz)."),
    var: list[str] = typer.Option(
        None,
        "--var",
        help="Variable to analyse: NAME or NAME[DIM=VALUE] (repeat; default: all). A variable "
        "with extra dimensions is analysed once per label, e.g. eccentricity_x[joint=C].",
    ),
    figures: Path | None = typer.Option(
        None, "--figures", help="Folder for the figures (PNG), one set per variable."
    ),
    drive_period: float | None = typer.Option(
        None, "--drive-period", help="Period of an external drive, s (stroboscopic section)."
    ),
    phase_variable: str | None = typer.Option(
        None, "--phase-variable", help="Drive angle variable, rad (stroboscopic section)."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the 0-1 test and the surrogates."),
    time: str | None = typer.Option(
        None, "--time", help="Name of the time column, s (default: time, t, ... if present)."
    ),
    dt: float | None = typer.Option(
        None, "--dt", help="Sampling interval, s, for data without a time column."
    ),
    step: str | None = typer.Option(
        None,
        "--step",
        help="Map data: the integer iteration column ('--step step' numbers the rows).",
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
        "first. Default: the analysed variables (every time series of the file, "
        "multi-dimensional ones by label); 'none' or a single variable: per-variable only.",
    ),
    drive_variable: list[str] = typer.Option(
        None,
        "--drive-variable",
        help="A variable of the motion that follows the drive alone (e.g. a prescribed crank "
        "angle): set aside from the motion verdict (repeat). Such variables are also found "
        "by themselves when --drive-period or --phase-variable is given.",
    ),
) -> None:
    """Classify the motion of a trajectory (all its variables together) and each variable,
    and print the motion verdict, then the evidence table.

    Exit status: 0 on success, 2 for bad input (nothing analysed), 1 when the analysis failed
    for every variable.
    """
    _run_analysis(
        path,
        list(var) if var else None,
        figures=figures,
        drive_period=drive_period,
        phase_variable=phase_variable,
        seed=seed,
        progress=True,
        time=time,
        dt=dt,
        step=step,
        measures=measures,
        motion=motion,
        drive_variables=list(drive_variable) if drive_variable else None,
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
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        raise ValueError(f"cannot create {path}: {parent} is not a folder.")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(f"cannot write {path}: {parent} is not writable.")


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
            max_samples=max_samples,
            drive_period=drive_period,
            phase_variable=phase_variable,
            rng=seed,
            chaos_reference=reference,
            reference_name=reference_name,
            title=title,
            command=shlex.join(["chaoskit", *sys.argv[1:]]),
            measures=measures or (),
            progress=True,
        )
        written = rep.write(output, markdown_figures="embed" if embed_figures else "files")
    overview = rep.table("verdict per variable").display()
    typer.echo(overview.droplevel(1, axis=1).to_string())
    typer.echo("")
    typer.echo(f"report: {written['html']}")
    typer.echo(f"markdown: {written['markdown']} ({len(written['figures'])} figure file(s))")


if __name__ == "__main__":
    app()
