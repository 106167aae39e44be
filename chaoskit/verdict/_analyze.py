"""``analyze``: the one call that reports and sweeps use — one row per variable.

``classify_variables`` gives the verdicts themselves (with their curves, for figures) and
``verdict_table`` turns any verdicts into the same table.
"""

from __future__ import annotations

import contextlib
from collections.abc import Mapping, Sequence
from typing import Any

import xarray as xr

from .._contract import stamp
from .._io import load_trajectory
from .._progress import finish_item, stage_bar
from .._selection import expand_variables, select_series, variable_spec
from ._classify import classify
from ._result import Verdict
from ._rng import as_generator
from ._rule import LABELS, VerdictRule
from ._table import FIELDS as FIELDS
from ._table import stack_verdicts

__all__ = ["analyze", "classify_variables", "verdict_table"]


def verdict_table(verdicts: Mapping[str, Verdict]) -> xr.Dataset:
    """Stack verdicts into a Dataset over the dimension ``variable`` (see :func:`analyze`).

    Exponents and times are in s and s⁻¹ when any verdict comes from a flow, per iteration
    when all come from maps.
    """
    return stack_verdicts(verdicts, LABELS)


def classify_variables(
    data: Any,
    *,
    variables: Sequence[str] | None = None,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    n_surrogates: int = 19,
    rule: VerdictRule | None = None,
    rng: Any = None,
    progress: bool = False,
) -> dict[str, Verdict]:
    """:func:`chaoskit.classify` for several variables of one trajectory, failures as data.

    A variable whose analysis raises a ``ValueError`` gets an ``"undetermined"`` verdict whose
    reason and ``errors`` hold the message; the others are still analysed. Parameters as in
    :func:`analyze`; the verdicts are keyed by selection (``"eccentricity_x[joint=C]"`` for
    one joint of a multi-dimensional variable).
    """
    ds, variables = series_dataset(data, variables=variables, phase_variable=phase_variable)
    index = "time" if "time" in ds.coords else "step"
    streams = as_generator(rng).spawn(len(variables))
    with contextlib.ExitStack() as stack:
        bar = stack.enter_context(stage_bar(len(variables), desc="analyze")) if progress else None
        verdicts: dict[str, Verdict] = {}
        for i, (name, stream) in enumerate(zip(variables, streams, strict=True)):
            if bar is not None:
                finish_item(bar, i, f"analyze {name} ({i + 1}/{len(variables)})")
            verdicts[name] = _classify_one(
                ds, name, stream, index, drive_period, phase_variable, n_surrogates, rule
            )
        if bar is not None:
            finish_item(bar, len(variables), "analyze")
    return verdicts


def series_dataset(
    data: Any, *, variables: Sequence[str] | None, phase_variable: str | None
) -> tuple[xr.Dataset, list[str]]:
    """The 1-D series selected by ``variables`` (expanded by label, see
    :func:`~chaoskit._selection.expand_variables`) and the phase variable, as one Dataset
    keyed by selection; and the selections in order."""
    ds = load_trajectory(data)
    phase = None if phase_variable is None else variable_spec(ds, phase_variable)
    exclude = [] if phase is None else [phase.name]
    specs = expand_variables(ds, variables, exclude=exclude)
    if not specs:
        raise ValueError("no variable to analyse.")
    columns = {spec.alias: select_series(ds, spec) for spec in specs}
    if phase is not None and phase_variable is not None:
        columns[phase_variable] = select_series(ds, phase).rename(phase_variable)
    return xr.Dataset(columns, attrs=ds.attrs), list(dict.fromkeys(s.alias for s in specs))


def _classify_one(
    ds: xr.Dataset,
    name: str,
    stream: Any,
    index: str,
    drive_period: float | None,
    phase_variable: str | None,
    n_surrogates: int,
    rule: VerdictRule | None,
) -> Verdict:
    """:func:`classify` of one variable, a ``ValueError`` turned into an undetermined verdict."""
    keep = [name] if phase_variable is None else [name, phase_variable]
    try:
        return classify(
            ds[keep],
            variable=name,
            drive_period=drive_period,
            phase_variable=phase_variable,
            n_surrogates=n_surrogates,
            rule=rule,
            rng=stream,
        )
    except ValueError as exc:
        return Verdict(
            label="undetermined",
            period=None,
            confidence=float("nan"),
            reason=f"analysis failed: {exc}",
            votes={},
            errors={"classify": str(exc)},
            variable=name,
            kind="map" if index == "step" else "flow",
            dt=1.0,
            n_samples=int(ds.sizes[index]),
        )


def analyze(
    data: Any,
    *,
    variables: Sequence[str] | None = None,
    drive_period: float | None = None,
    phase_variable: str | None = None,
    n_surrogates: int = 19,
    rule: VerdictRule | None = None,
    rng: Any = None,
    progress: bool = False,
) -> xr.Dataset:
    """Classify each variable of a trajectory and tabulate the evidence: one row per variable.

    Runs :func:`chaoskit.classify` on every requested variable and keeps scalars only, so
    that the tables of many runs stack with ``xarray.concat`` along new grid dimensions.
    A variable whose analysis fails is recorded as ``"undetermined"`` with NaN fields and
    the error in the ``reasons`` attribute, and the others are still analysed. For the
    verdicts themselves (curves, section points) use :func:`classify_variables` and
    :func:`verdict_table`.

    Parameters
    ----------
    data
        A trajectory (anything :func:`chaoskit.load_trajectory` accepts).
    variables
        Variables to analyse, each ``NAME`` or ``NAME[DIM=VALUE,...]`` (default: every
        variable along ``time``/``step`` except ``phase_variable``). A variable with extra
        dimensions (e.g. ``eccentricity_x`` per ``joint``) is analysed once per label of
        each dimension not selected, as ``eccentricity_x[joint=B]``, ... .
    drive_period, phase_variable, n_surrogates, rule
        Passed to :func:`chaoskit.classify`.
    rng
        Seed or Generator; each variable gets an independent stream spawned from it.
    progress
        Show a progress bar (after the first two seconds) naming the variable and the
        estimator running.

    Returns
    -------
    xarray.Dataset
        Dimension ``variable``; fields ``label`` (string), ``period``, ``confidence``,
        ``lag`` (samples), ``lag_time``, ``embedding_dim``, ``mle_rosenstein`` and
        ``mle_wolf`` with ``_low``/``_high`` (95 % interval) and ``_bits`` (bits per
        sample), ``zero_one_k``, ``surrogate_p_value``, ``surrogate_effect``,
        ``section_points``, ``section_structure`` (string), ``characteristic_time``,
        ``noise_level``, ``dt``, ``n_samples``. Exponents are natural-log per second for
        flows and per iteration for maps; NaN where undefined (e.g. no period unless
        periodic).

    Examples
    --------
    >>> import chaoskit
    >>> ds = chaoskit.load_trajectory(chaoskit.systems.henon(1500), dt=1.0,
    ...                               variables=["x", "y"])
    >>> table = chaoskit.analyze(ds, variables=["x"], rng=0)
    >>> str(table.label.sel(variable="x").item())
    'chaotic'
    """
    ds = load_trajectory(data)
    verdicts = classify_variables(
        ds,
        variables=variables,
        drive_period=drive_period,
        phase_variable=phase_variable,
        n_surrogates=n_surrogates,
        rule=rule,
        rng=rng,
        progress=progress,
    )
    out = verdict_table(verdicts)
    out.attrs["history"] = ds.attrs.get("history", "")
    return stamp(
        out,
        title=f"chaoskit.analyze of {ds.attrs.get('title', 'a trajectory')}",
        history=f"chaoskit.analyze(variables={list(verdicts)!r}, drive_period={drive_period!r}, "
        f"phase_variable={phase_variable!r}, n_surrogates={n_surrogates})",
    )
