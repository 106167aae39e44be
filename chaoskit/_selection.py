"""One selection syntax for every command and function: ``[ALIAS=]NAME[DIM=VALUE,...]``.

A trajectory variable may have dimensions besides ``time``/``step`` (``eccentricity_x``
per ``joint``, ``strain`` per ``rod`` and ``station``). ``select_series`` picks one 1-D
series from it, and ``expand_variables`` lists one selection per label of every extra
dimension, so that an analysis of "every variable" sees each joint's series instead of
skipping them.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

__all__ = [
    "VariableSpec",
    "expand_variables",
    "parse_variable",
    "select_series",
    "variable_spec",
]


@dataclass(frozen=True, kw_only=True)
class VariableSpec:
    """A variable of a trajectory, with selections along its extra dimensions.

    ``alias`` names the series in the report; ``name`` is the variable in the trajectory;
    ``selectors`` pick one element along each extra dimension (e.g. ``{"joint": "C"}``).
    """

    alias: str
    name: str
    selectors: Mapping[str, str] = field(default_factory=dict)

    @property
    def spec(self) -> str:
        """The spec string without alias, e.g. ``eccentricity_x[joint=C]``."""
        if not self.selectors:
            return self.name
        inner = ",".join(f"{k}={v}" for k, v in self.selectors.items())
        return f"{self.name}[{inner}]"


_SPEC = re.compile(
    r"^\s*(?:(?P<alias>[^=\[\]]+?)\s*=\s*)?(?P<name>[^=\[\]]+?)\s*(?:\[(?P<sel>[^\[\]]*)\])?\s*$"
)


def parse_variable(spec: str, *, alias: str | None = None) -> VariableSpec:
    """Parse ``"[ALIAS=]NAME[DIM=VALUE,...]"``, e.g. ``"X=eccentricity_x[joint=C]"``.

    Examples
    --------
    >>> parse_variable("X=eccentricity_x[joint=C]")
    VariableSpec(alias='X', name='eccentricity_x', selectors={'joint': 'C'})
    """
    if not isinstance(spec, str):
        raise ValueError(f"a variable spec must be a string; got {type(spec).__name__}.")
    match = _SPEC.match(spec)
    if match is None:
        raise ValueError(
            f"cannot read the variable spec {spec!r}; write NAME, NAME[DIM=VALUE,...] or "
            "ALIAS=NAME[DIM=VALUE,...] (e.g. 'X=eccentricity_x[joint=C]')."
        )
    selectors: dict[str, str] = {}
    if match["sel"] is not None:
        for part in match["sel"].split(","):
            if not part.strip():
                continue
            key, eq, value = part.partition("=")
            if not eq or not key.strip() or not value.strip():
                raise ValueError(
                    f"selection {part.strip()!r} in {spec!r} must read DIM=VALUE (e.g. joint=C)."
                )
            selectors[key.strip()] = value.strip()
    name = match["name"].strip()
    given = alias if alias is not None else match["alias"]
    if given is None:
        given = (
            spec.strip()
            if not selectors
            else VariableSpec(name=name, alias="", selectors=selectors).spec
        )
    return VariableSpec(alias=str(given).strip(), name=name, selectors=selectors)


def _coord_value(coord: xr.DataArray, value: Any, *, dim: str, variable: str) -> Any:
    values = coord.values
    if isinstance(value, str) and values.dtype.kind in "fiu":
        try:
            value = float(value)
        except ValueError:
            raise ValueError(
                f"{dim}={value!r} for {variable!r}: {dim} is numeric; choose one of "
                f"{values.tolist()}."
            ) from None
    if values.dtype.kind in "fiu":
        hits = np.flatnonzero(
            np.isclose(values.astype(np.float64), float(value), rtol=1e-9, atol=0.0)
        )
    else:
        hits = np.flatnonzero(np.array([str(v) == str(value) for v in values]))
    if hits.size != 1:
        raise ValueError(
            f"{dim}={value!r} not found for {variable!r}; {dim} has {values.tolist()}."
        )
    return int(hits[0])


def select_series(
    ds: xr.Dataset,
    spec: VariableSpec | str,
    *,
    sel: Mapping[str, Any] | None = None,
) -> xr.DataArray:
    """One 1-D series along ``time``/``step`` picked from a possibly multi-dimensional variable.

    The spec's own selectors are applied first, then ``sel`` along the dimensions the
    variable has (the spec wins where both name a dimension); remaining extra dimensions of
    length 1 are squeezed. Attributes are kept; ``long_name`` says what was selected.

    Raises
    ------
    ValueError
        If the variable is missing, a selected value does not exist, or extra dimensions
        longer than 1 remain (the message lists them and their values).
    """
    spec = parse_variable(spec) if isinstance(spec, str) else spec
    index = "time" if "time" in ds.coords else "step"
    if spec.name not in ds.data_vars:
        raise ValueError(f"variable {spec.name!r} not found; available: {list(ds.data_vars)}.")
    var = ds[spec.name]
    if index not in var.dims:
        raise ValueError(f"variable {spec.name!r} has no {index!r} dimension (dims {var.dims}).")
    unknown = [d for d in spec.selectors if d not in var.dims]
    if unknown:
        raise ValueError(
            f"{spec.spec!r}: {spec.name!r} has no dimension {unknown}; its dims are {var.dims}."
        )
    chosen = {**{k: v for k, v in (sel or {}).items() if k in var.dims}, **spec.selectors}
    if index in chosen:
        raise ValueError(f"cannot select along the index dimension {index!r}.")
    picks: dict[str, int] = {}
    for dim, value in chosen.items():
        coord = var[dim] if dim in var.coords else xr.DataArray(np.arange(var.sizes[dim]))
        picks[dim] = _coord_value(coord, value, dim=dim, variable=spec.name)
    out = var.isel(picks)
    extra = [d for d in out.dims if d != index]
    if any(out.sizes[d] > 1 for d in extra):
        listed = {
            d: (out[d].values.tolist() if d in out.coords else f"{out.sizes[d]} entries")
            for d in extra
        }
        raise ValueError(
            f"variable {spec.name!r} has extra dimensions {listed}; pick one element, e.g. "
            f"'{spec.name}[{extra[0]}=...]' or sel={{'{extra[0]}': ...}}."
        )
    out = out.squeeze([d for d in extra], drop=True) if extra else out
    out = out.drop_vars([c for c in out.coords if c != index])
    attrs = dict(var.attrs)
    if chosen or extra:
        parts = []
        for d in [*chosen, *(str(e) for e in extra)]:
            at = picks.get(d, 0)
            parts.append(f"{d} {var[d].values[at] if d in var.coords else at}")
        attrs["long_name"] = f"{attrs.get('long_name', spec.name)} ({', '.join(parts)})"
    out.attrs = attrs
    return out.rename(spec.alias)


def variable_spec(ds: xr.Dataset, text: str) -> VariableSpec:
    """``text`` as a spec: a variable of ``ds`` by that exact name, else parsed."""
    if isinstance(text, str) and text in ds.data_vars:
        return VariableSpec(alias=text, name=text, selectors={})
    return parse_variable(text)


def _labels(var: xr.DataArray, dim: str) -> list[str]:
    if dim in var.coords:
        return [str(v) for v in var[dim].values]
    return [str(i) for i in range(var.sizes[dim])]


def expand_variables(
    ds: xr.Dataset, names: Sequence[str] | None = None, *, exclude: Sequence[str] = ()
) -> list[VariableSpec]:
    """One :class:`VariableSpec` per 1-D series named by ``names`` (default: every variable
    along ``time``/``step`` except ``exclude``).

    A multi-dimensional variable without a selection for some extra dimension is expanded
    over the labels of those dimensions: ``eccentricity_x`` with ``joint = [B, C]`` gives
    ``eccentricity_x[joint=B]`` and ``eccentricity_x[joint=C]``. Each spec's alias is its
    selection string, so results are labelled the way they are selected.

    Raises
    ------
    ValueError
        If a name is not a variable of ``ds``, has no ``time``/``step`` dimension, or names
        a dimension the variable does not have.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> ds = xr.Dataset({"e": (("time", "joint"), np.zeros((3, 2)))},
    ...                 coords={"time": [0.0, 1.0, 2.0], "joint": ["B", "C"]})
    >>> [s.alias for s in expand_variables(ds)]
    ['e[joint=B]', 'e[joint=C]']
    """
    index = "time" if "time" in ds.coords else "step"
    if names is None:
        names = [str(k) for k, v in ds.data_vars.items() if index in v.dims and k not in exclude]
    elif isinstance(names, str):
        names = [names]
    specs = [variable_spec(ds, n) for n in names]
    missing = [s.name for s in specs if s.name not in ds.data_vars]
    if missing:
        raise ValueError(f"variables {missing} not found; available: {list(ds.data_vars)}.")
    out: list[VariableSpec] = []
    for spec in specs:
        var = ds[spec.name]
        if index not in var.dims:
            raise ValueError(f"variable {spec.name!r} has no {index!r} dimension ({var.dims}).")
        unknown = [d for d in spec.selectors if d not in var.dims]
        if unknown:
            raise ValueError(
                f"{spec.spec!r}: {spec.name!r} has no dimension {unknown}; its dims are {var.dims}."
            )
        free = [str(d) for d in var.dims if d != index and d not in spec.selectors]
        if not free:
            out.append(spec)
            continue
        for combo in itertools.product(*(_labels(var, d) for d in free)):
            selectors = {**spec.selectors, **dict(zip(free, combo, strict=True))}
            spec_string = VariableSpec(alias="", name=spec.name, selectors=selectors).spec
            out.append(VariableSpec(alias=spec_string, name=spec.name, selectors=selectors))
    return out
