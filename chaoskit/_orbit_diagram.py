"""Bifurcation (orbit) diagrams: section points against a swept parameter."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr

from ._contract import stamp
from ._io import load_trajectory
from ._validate import check_choice, check_int
from .sections import poincare_section, stroboscopic_map

__all__ = ["bifurcation_diagram"]

SectionKind = Literal["poincare", "stroboscopic", "samples"]


def _parameter_value(ds: xr.Dataset, parameter: str, position: int) -> float:
    for source in (ds.coords, ds.data_vars):
        if parameter in source and source[parameter].ndim == 0:
            return float(source[parameter].values)
    if parameter in ds.attrs:
        return float(ds.attrs[parameter])
    raise ValueError(
        f"result {position} carries no value of {parameter!r} (looked for a scalar coordinate "
        "or variable and a global attribute); pass values=[...]."
    )


def _members(
    results: Any, parameter: str, values: Sequence[float] | None
) -> list[tuple[float, xr.Dataset]]:
    """Split the input into (parameter value, dataset) pairs."""
    if isinstance(results, xr.Dataset):
        if parameter not in results.dims:
            raise ValueError(
                f"a sweep Dataset must have the dimension {parameter!r}; it has "
                f"{dict(results.sizes)}. Pass a list of Datasets instead."
            )
        other = [d for d in results.dims if d not in (parameter, "time", "step", "crossing")]
        if other:
            raise ValueError(
                f"the sweep Dataset has other grid dimensions {other}; select one value of "
                "each first (e.g. ds.sel(...)), or stack them into one parameter."
            )
        grid = np.asarray(results[parameter].values, dtype=np.float64)
        members = [results.isel({parameter: i}, drop=True) for i in range(grid.size)]
        pvals = list(grid) if values is None else list(values)
    else:
        if isinstance(results, (str, os.PathLike)) or not isinstance(results, Sequence):
            raise ValueError(
                "results must be a sequence of trajectories (Datasets or file paths) or a sweep "
                f"Dataset with the dimension {parameter!r}; got {type(results).__name__}."
            )
        members = [r if isinstance(r, xr.Dataset) else load_trajectory(r) for r in results]
        if values is None:
            pvals = [_parameter_value(ds, parameter, i) for i, ds in enumerate(members)]
        else:
            pvals = list(values)
    if len(pvals) != len(members):
        raise ValueError(f"values has {len(pvals)} entries but there are {len(members)} results.")
    if not members:
        raise ValueError("results is empty.")
    return [(float(p), ds) for p, ds in zip(pvals, members, strict=True)]


def _points(
    ds: xr.Dataset,
    *,
    variable: str,
    section: str | None,
    options: Mapping[str, Any],
) -> tuple[np.ndarray, np.ndarray | None, dict[str, Any]]:
    if section is None:
        if "crossing" in ds.dims:
            sec = ds
        elif "step" in ds.dims:
            section = "samples"
        else:
            raise ValueError(
                "a continuous-time trajectory needs section='poincare' or 'stroboscopic' (with "
                "section_options); only section datasets and maps can be used as they are."
            )
    if section == "samples":
        sec = ds
    elif section == "poincare":
        sec = poincare_section(ds, **options)
    elif section == "stroboscopic":
        sec = stroboscopic_map(ds, **options)
    if variable not in sec.data_vars:
        raise ValueError(
            f"variable {variable!r} not among the section's variables {list(sec.data_vars)} "
            "(the section variable itself is constant on a Poincaré section)."
        )
    var = sec[variable]
    if var.ndim != 1:
        raise ValueError(f"variable {variable!r} must be 1-D along the points; dims {var.dims}.")
    times = np.asarray(sec["time"].values, dtype=np.float64) if "time" in sec.coords else None
    return np.asarray(var.values, dtype=np.float64), times, dict(var.attrs)


def bifurcation_diagram(
    results: Any,
    *,
    parameter: str,
    variable: str,
    section: SectionKind | None = None,
    section_options: Mapping[str, Any] | None = None,
    values: Sequence[float] | None = None,
    last: int | None = None,
    parameter_attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    r"""Section points of ``variable`` against a swept ``parameter`` (an orbit diagram).

    For each run the asymptotic set is reduced to points — a Poincaré section, a
    stroboscopic map (one point per drive period), or the iterates of a map — and every
    point is kept with its parameter value. A period-:math:`k` response shows :math:`k`
    points above its parameter value, a chaotic one a band (Feigenbaum, J. Stat. Phys. 19,
    25, 1978; Strogatz, *Nonlinear Dynamics and Chaos*, 2nd ed., 2015, §10.2).

    Parameters
    ----------
    results
        A sequence of runs (Datasets or trajectory file paths), or a sweep Dataset with the
        dimension ``parameter``. A run may be a trajectory (``time`` or ``step``) or an
        already computed section (dimension ``crossing``).
    parameter
        Name of the swept parameter: a dimension of the sweep Dataset, or in each run a
        scalar coordinate, scalar variable or global attribute.
    variable
        The variable whose section values are plotted.
    section
        ``"poincare"`` (:func:`chaoskit.poincare_section`), ``"stroboscopic"``
        (:func:`chaoskit.stroboscopic_map`) or ``"samples"`` (every sample, for maps).
        Default: sections and maps are used as they are; trajectories need a choice.
    section_options
        Keyword arguments of the section function, e.g. ``{"period": 2 * np.pi / 1.2}`` or
        ``{"variable": "v", "level": 0.0, "direction": "down"}``.
    values
        Parameter values, one per run, overriding those found in the data.
    last
        Keep only the last ``last`` points of each run (drop the transient).
    parameter_attrs
        Attributes for the parameter variable (default ``units="1"``).

    Returns
    -------
    xarray.Dataset
        Along ``point`` (sorted by parameter value, then time): the ``parameter`` value, the
        ``variable`` value and, when known, the ``time`` of each point.

    Examples
    --------
    >>> import numpy as np, xarray as xr, chaoskit
    >>> runs = []
    >>> for r in (2.8, 3.2, 3.5):
    ...     x = chaoskit.systems.logistic(64, r=r)
    ...     runs.append(xr.Dataset({"x": ("step", x)}, coords={"step": np.arange(64)},
    ...                            attrs={"r": r}))
    >>> diagram = chaoskit.bifurcation_diagram(runs, parameter="r", variable="x", last=16)
    >>> [len(np.unique(np.round(diagram.x.values[diagram.r.values == r], 6)))
    ...  for r in (2.8, 3.2, 3.5)]
    [1, 2, 4]
    """
    if section is not None:
        section = check_choice(  # type: ignore[assignment]
            section, name="section", choices=("poincare", "stroboscopic", "samples")
        )
    if last is not None:
        last = check_int(last, name="last", minimum=1)
    options = dict(section_options or {})
    pvals: list[np.ndarray] = []
    xvals: list[np.ndarray] = []
    tvals: list[np.ndarray] = []
    attrs: dict[str, Any] = {}
    have_time = True
    for p, ds in _members(results, parameter, values):
        x, t, attrs = _points(ds, variable=variable, section=section, options=options)
        if last is not None:
            x = x[-last:]
            t = None if t is None else t[-last:]
        pvals.append(np.full(x.size, p))
        xvals.append(x)
        if t is None:
            have_time = False
        else:
            tvals.append(t)
    pv = np.concatenate(pvals)
    xv = np.concatenate(xvals)
    order = np.argsort(pv, kind="stable")
    data_vars = {
        parameter: (
            "point",
            pv[order],
            dict(parameter_attrs or {"units": "1", "long_name": parameter}),
        ),
        variable: ("point", xv[order], attrs or {"units": "1", "long_name": variable}),
    }
    coords: dict[str, Any] = {"point": np.arange(pv.size)}
    if have_time:
        coords["time"] = (
            "point",
            np.concatenate(tvals)[order],
            {"units": "s", "long_name": "time of the point"},
        )
    out = xr.Dataset(data_vars, coords=coords)
    out.attrs.update(
        {
            "diagram_parameter": parameter,
            "diagram_variable": variable,
            "section_kind": section or "given",
        }
    )
    return stamp(
        out,
        title=f"bifurcation diagram of {variable} against {parameter}",
        history=f"chaoskit.bifurcation_diagram(parameter={parameter!r}, variable={variable!r}, "
        f"section={section!r}, last={last!r})",
    )
