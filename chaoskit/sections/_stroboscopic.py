"""Stroboscopic maps: one point per drive period, by clock or by a rotating angle."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from .._validate import check_positive
from . import _kernels
from ._common import as_flow, check_order, check_real, points_dataset, series, stack_columns

__all__ = ["stroboscopic_map"]

_TWO_PI = 2.0 * np.pi


def _clock_times(t: np.ndarray, period: float, phase: float) -> tuple[np.ndarray, np.ndarray]:
    """Times (phase / 2π + k) · period inside [t[0], t[-1]] and their cycle numbers k."""
    offset = phase / _TWO_PI
    slack = 1e-9  # a strobe time that lands on the first/last sample up to rounding counts
    k0 = int(np.ceil(t[0] / period - offset - slack))
    k1 = int(np.floor(t[-1] / period - offset + slack))
    cycles = np.arange(k0, k1 + 1, dtype=np.int64)
    times = np.clip((cycles + offset) * period, t[0], t[-1])
    return times, cycles


def _angle_crossings(
    t: np.ndarray, angle: np.ndarray, phase: float, order: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Brackets, times and cycle numbers where ``angle`` passes phase + 2πk forwards."""
    angle = np.unwrap(angle)
    forward = 1.0 if angle[-1] >= angle[0] else -1.0
    u = forward * (angle - phase) / _TWO_PI
    cell = np.floor(u)
    brackets = np.flatnonzero(cell[1:] > cell[:-1]).astype(np.int64)
    cycles = cell[brackets + 1].astype(np.int64)
    targets = forward * cycles * _TWO_PI + phase
    times = _kernels.find_roots(t, angle, brackets, np.ascontiguousarray(targets), order)
    if u[0] == cell[0]:  # a first sample exactly on a strobe instant counts, as by the clock
        brackets = np.concatenate([[0], brackets]).astype(np.int64)
        cycles = np.concatenate([[int(cell[0])], cycles]).astype(np.int64)
        times = np.concatenate([[t[0]], times])
    return brackets, times, cycles


def stroboscopic_map(
    data: Any,
    *,
    period: float | None = None,
    phase_variable: str | None = None,
    phase: float = 0.0,
    coords: Sequence[str] | None = None,
    order: int = 7,
) -> xr.Dataset:
    r"""Sample a driven trajectory once per drive period.

    Either by the clock, at :math:`t_k = (\varphi / 2\pi + k)\,T` for ``period`` :math:`T`
    (s) and drive phase :math:`\varphi` = ``phase`` (rad), with :math:`t` the trajectory's
    own time axis; or by an angle: whenever the unwrapped ``phase_variable`` :math:`\theta`
    passes :math:`\varphi + 2\pi k` in its net direction of rotation. The instants are
    located, and every variable is interpolated there, with the local Lagrange polynomial of
    degree ``order`` (see :func:`chaoskit.poincare_section`). The result is the stroboscopic
    (period-:math:`T`) Poincaré map of a periodically forced system (Guckenheimer & Holmes,
    *Nonlinear Oscillations, Dynamical Systems, and Bifurcations of Vector Fields*,
    Springer, 1983, §1.5); a period-:math:`k` response gives :math:`k` distinct points.

    Parameters
    ----------
    data
        A trajectory with a ``time`` coordinate (s), or anything
        :func:`chaoskit.load_trajectory` accepts.
    period
        Drive period in s. Give either ``period`` or ``phase_variable``.
    phase_variable
        Name of an angle variable in rad (e.g. ``crank_angle``); wrapped angles are unwrapped
        first, so it must change by less than π between samples (a faster rotation aliases
        and cannot be detected from the samples).
    phase
        Drive phase :math:`\varphi` of the strobe, rad.
    coords
        Variables to interpolate (default: every variable along ``time``; with
        ``phase_variable``, every variable but the angle).
    order
        Degree of the local interpolating polynomial: 3, 5, 7 (default) or 9.

    Returns
    -------
    xarray.Dataset
        One point per drive cycle along the ``crossing`` dimension, with coordinates ``time``
        (s) and ``drive_cycle`` (the integer :math:`k`), and global attributes
        ``section_kind="stroboscopic"``, ``drive_period`` or ``phase_variable``, and
        ``drive_phase``.

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> t, state = chaoskit.systems.duffing(2000, gamma=0.28, samples_per_period=100)
    >>> ds = chaoskit.load_trajectory(state, dt=t[1] - t[0], variables=["x", "v"])
    >>> ds = ds.assign_coords(time=t)
    >>> strobe = chaoskit.stroboscopic_map(ds, period=2 * np.pi / 1.2)
    >>> strobe.sizes["crossing"]
    20
    """
    ds = as_flow(data, what="stroboscopic_map")
    order = check_order(order)
    phase = check_real(phase, name="phase", units="rad")
    if (period is None) == (phase_variable is None):
        raise ValueError("give exactly one of period= (s) and phase_variable= (an angle, rad).")
    t = np.ascontiguousarray(ds["time"].values, dtype=np.float64)
    attrs: dict[str, Any] = {"section_kind": "stroboscopic", "drive_phase": phase}
    if period is not None:
        period = check_positive(period, name="period")
        y, columns = stack_columns(ds, coords)
        times, cycles = _clock_times(t, period, phase)
        brackets = np.clip(np.searchsorted(t, times, side="right") - 1, 0, max(t.size - 2, 0))
        brackets = brackets.astype(np.int64)
        attrs["drive_period"] = period
        how = f"period={period!r}"
    else:
        assert phase_variable is not None
        angle = series(ds, phase_variable, what="phase_variable")
        y, columns = stack_columns(ds, coords, exclude=(phase_variable,))
        brackets, times, cycles = _angle_crossings(t, angle, phase, order)
        attrs["phase_variable"] = phase_variable
        how = f"phase_variable={phase_variable!r}"
    values = _kernels.interpolate_at(t, y, brackets, times, order)
    return points_dataset(
        ds,
        values=values,
        columns=columns,
        times=times,
        title=f"stroboscopic map ({how}, phase {phase:g} rad)",
        history=f"chaoskit.stroboscopic_map({how}, phase={phase!r}, order={order})",
        attrs={**attrs, "interpolation_order": order},
        extra_coords={
            "drive_cycle": ("crossing", cycles, {"units": "1", "long_name": "drive cycle k"})
        },
    )
