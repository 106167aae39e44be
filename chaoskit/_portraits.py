"""Phase portraits: a variable against its rate of change."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr
from scipy.signal import savgol_filter

from ._contract import sampling_interval, stamp
from ._io import load_trajectory
from ._validate import check_int

__all__ = ["phase_portrait", "savgol_derivative"]

#: Names under which a trajectory may already hold the derivative of ``v``, tried in order.
DERIVATIVE_NAMES = ("{v}_dot", "d{v}_dt", "{v}_rate", "{v}_velocity", "v{v}", "{v}_t")


def savgol_derivative(
    x: np.ndarray, *, dt: float, window: int = 11, polyorder: int = 5
) -> np.ndarray:
    """First derivative by a Savitzky–Golay filter (least-squares polynomial over ``window``).

    The ``window``-sample local fit of degree ``polyorder`` is differentiated at its centre;
    the first and last ``window // 2`` samples use the fit of the end window. For a
    symmetric window the derivative is exact for polynomials of degree ``polyorder + 1``
    when ``polyorder`` is odd. A. Savitzky and M. J. E. Golay, Anal. Chem. 36, 1627 (1964).
    """
    window = check_int(window, name="window", minimum=3)
    if window % 2 == 0:
        raise ValueError(f"window must be odd; got {window}.")
    polyorder = check_int(polyorder, name="polyorder", minimum=1, maximum=window - 1)
    if x.size < window:
        raise ValueError(
            f"the series has {x.size} samples, fewer than the derivative window ({window})."
        )
    return savgol_filter(x, window, polyorder, deriv=1, delta=dt, mode="interp")


def _find_derivative(ds: xr.Dataset, variable: str) -> str | None:
    for pattern in DERIVATIVE_NAMES:
        name = pattern.format(v=variable)
        if name in ds.data_vars and ds[name].dims == ("time",):
            return name
    return None


def phase_portrait(
    data: Any,
    *,
    variable: str,
    derivative: str | None = None,
    window: int = 11,
    polyorder: int = 5,
) -> xr.Dataset:
    r"""The pair :math:`(x, \dot x)` of one variable of a trajectory.

    The derivative is taken from the data when it is there: the variable named by
    ``derivative``, or else the first of ``{v}_dot``, ``d{v}_dt``, ``{v}_rate``,
    ``{v}_velocity``, ``v{v}``, ``{v}_t`` (with ``{v}`` = ``variable``) found along
    ``time``. Otherwise it is estimated with a Savitzky–Golay filter: the least-squares
    polynomial of degree ``polyorder`` over ``window`` samples, differentiated at the
    centre (Savitzky & Golay, Anal. Chem. 36, 1627, 1964). With the defaults (11 samples,
    degree 5) the estimate of :math:`\dot x` for a sine sampled 50 times per period is
    accurate to about 1e-6 relative (1e-4 in the first and last five samples); the filter
    also smooths measurement noise.

    Parameters
    ----------
    data
        A trajectory with a uniformly sampled ``time`` coordinate (s), or anything
        :func:`chaoskit.load_trajectory` accepts.
    variable
        The variable :math:`x`.
    derivative
        Name of the variable holding :math:`\dot x`, if the data have it under another name.
    window, polyorder
        Savitzky–Golay window (odd, samples) and polynomial degree, used only when the
        derivative is estimated.

    Returns
    -------
    xarray.Dataset
        Along ``time``: ``variable`` and its derivative, named ``d{variable}_dt`` when
        estimated (units ``<units> s-1``) or keeping its own name when taken from the data;
        attributes ``portrait_variable``, ``portrait_derivative`` and ``derivative_source``
        (``"data"`` or ``"savitzky-golay(window=..., polyorder=...)"``).

    Examples
    --------
    >>> import numpy as np, chaoskit
    >>> t = np.arange(0.0, 4.0, 0.02)
    >>> ds = chaoskit.load_trajectory(np.sin(2 * np.pi * t), dt=0.02)
    >>> pp = chaoskit.phase_portrait(ds, variable="x")
    >>> bool(np.allclose(pp["dx_dt"], 2 * np.pi * np.cos(2 * np.pi * t), atol=1e-3))
    True
    """
    ds = load_trajectory(data)
    if "time" not in ds.coords:
        raise ValueError(
            "phase_portrait needs a 'time' coordinate (s); for a map (indexed by 'step'), plot "
            "x[n + 1] against x[n] instead."
        )
    if variable not in ds.data_vars:
        raise ValueError(f"variable {variable!r} not found; available: {list(ds.data_vars)}.")
    if ds[variable].dims != ("time",):
        raise ValueError(
            f"variable {variable!r} must be 1-D along 'time'; dims {ds[variable].dims}."
        )
    xvar = ds[variable]
    units = str(xvar.attrs.get("units", "unknown"))
    if derivative is not None:
        if derivative not in ds.data_vars:
            raise ValueError(
                f"derivative {derivative!r} not found; available: {list(ds.data_vars)}."
            )
        name: str | None = derivative
    else:
        name = _find_derivative(ds, variable)
    if name is not None:
        dvar = ds[name]
        source = "data"
    else:
        dt = sampling_interval(ds)
        x = np.ascontiguousarray(xvar.values, dtype=np.float64)
        rate = savgol_derivative(x, dt=dt, window=window, polyorder=polyorder)
        name = f"d{variable}_dt"
        source = f"savitzky-golay(window={window}, polyorder={polyorder})"
        dvar = xr.DataArray(
            rate,
            dims=("time",),
            attrs={
                "units": "s-1" if units in ("1", "") else f"{units} s-1",
                "long_name": f"rate of change of {xvar.attrs.get('long_name', variable)}",
            },
        )
    out = xr.Dataset({variable: xvar.variable, name: dvar.variable}, coords={"time": ds["time"]})
    out.attrs.update(
        {
            "portrait_variable": variable,
            "portrait_derivative": name,
            "derivative_source": source,
            "history": ds.attrs.get("history", ""),
        }
    )
    return stamp(
        out,
        title=f"phase portrait of {variable}",
        history=f"chaoskit.phase_portrait(variable={variable!r}, derivative from {source})",
    )
