"""Poincaré sections of sampled trajectories: level crossings located between samples."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._validate import check_choice
from . import _kernels
from ._common import as_flow, check_order, check_real, points_dataset, series, stack_columns

__all__ = ["poincare_section"]

Direction = Literal["up", "down", "both"]


def crossing_brackets(g: np.ndarray, direction: str) -> np.ndarray:
    """Indices ``i`` where ``g`` crosses zero between samples ``i`` and ``i + 1``.

    Upward: ``g[i] < 0 <= g[i + 1]``; downward: ``g[i] > 0 >= g[i + 1]``. The half-open rule
    counts a sample that lands exactly on the level once, not twice.
    """
    before, after = g[:-1], g[1:]
    up = (before < 0.0) & (after >= 0.0)
    down = (before > 0.0) & (after <= 0.0)
    mask = up if direction == "up" else down if direction == "down" else up | down
    return np.flatnonzero(mask).astype(np.int64)


def poincare_section(
    data: Any,
    *,
    variable: str,
    level: float = 0.0,
    direction: Direction = "up",
    coords: Sequence[str] | None = None,
    order: int = 7,
) -> xr.Dataset:
    r"""Every crossing of ``variable`` through ``level``, located between samples.

    In each interval :math:`[t_i, t_{i+1}]` where :math:`x(t) - \text{level}` changes sign in
    the requested direction, the crossing time :math:`t^*` solves :math:`p(t^*) = \text{level}`,
    where :math:`p` is the Lagrange polynomial of degree ``order`` through the
    ``order + 1`` samples centred on the interval. Sampled data cannot be integrated onto
    the section (Hénon's trick), so the crossing is located by interpolation, as in Parker &
    Chua, *Practical Numerical Algorithms for Chaotic Systems* (Springer, 1989), chapter on
    Poincaré maps. The other variables are interpolated at :math:`t^*` with the same
    polynomial weights. The
    error is :math:`O(h^{\text{order}+1})` in the sample spacing :math:`h`: with the default
    degree 7, a sine sampled 50 times per period gives crossing times and values exact to
    about 2e-10 relative (1.5e-8 at 20 samples per period, where degree 3 gives 4e-5).
    Within ``(order + 1) // 2`` samples of either end the polynomial's nodes cannot be
    centred and the error grows (about 100-fold for the default degree).

    Parameters
    ----------
    data
        A trajectory (:class:`xarray.Dataset` with a ``time`` coordinate in s, or anything
        :func:`chaoskit.load_trajectory` accepts). Sampling need not be uniform.
    variable
        The variable whose level crossings define the section.
    level
        The section level, in the units of ``variable``.
    direction
        ``"up"`` (increasing through the level), ``"down"`` or ``"both"``.
    coords
        Variables to interpolate at the crossings (default: every variable along ``time``
        except ``variable``). Variables with extra dimensions are interpolated element-wise.
    order
        Degree of the local interpolating polynomial: 3, 5, 7 (default) or 9.

    Returns
    -------
    xarray.Dataset
        One point per crossing along the ``crossing`` dimension, with the crossing ``time``
        (s) as a coordinate and the interpolated ``coords`` (attributes kept). Global
        attributes record the section (``section_kind="poincare"``, ``section_variable``,
        ``section_level``, ``section_direction``, ``interpolation_order``).

    Raises
    ------
    ValueError
        If ``variable`` or a ``coords`` entry is missing or not along ``time``, if the
        trajectory is indexed by ``step`` (a map), or if an option is out of range.

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> ds = chaoskit.load_trajectory(
    ...     np.column_stack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t)]),
    ...     dt=0.01, variables=["x", "v"])
    >>> sec = chaoskit.poincare_section(ds, variable="x", direction="up")
    >>> np.round(sec.time.values[:3], 8)
    array([1., 2., 3.])
    >>> bool(np.allclose(sec.v.values, 1.0, rtol=1e-9))
    True
    """
    ds = as_flow(data, what="poincare_section")
    how = check_choice(direction, name="direction", choices=("up", "down", "both"))
    order = check_order(order)
    level = check_real(level, name="level")
    x = series(ds, variable, what="variable")
    t = np.ascontiguousarray(ds["time"].values, dtype=np.float64)
    y, columns = stack_columns(ds, coords, exclude=(variable,))
    brackets = crossing_brackets(x - level, how)
    targets = np.full(brackets.size, level)
    times = _kernels.find_roots(t, x, brackets, targets, order)
    values = _kernels.interpolate_at(t, y, brackets, times, order)
    return points_dataset(
        ds,
        values=values,
        columns=columns,
        times=times,
        title=f"Poincaré section {variable} = {level:g} ({how})",
        history=(
            f"chaoskit.poincare_section(variable={variable!r}, level={level!r}, "
            f"direction={how!r}, order={order})"
        ),
        attrs={
            "section_kind": "poincare",
            "section_variable": variable,
            "section_level": level,
            "section_direction": how,
            "interpolation_order": order,
        },
    )
