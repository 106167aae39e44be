"""Wear profiles in figures and reports: a polar plot and a report section of worn arcs.

:func:`plot_wear_profile` draws depth against angle on polar axes (the convention of
:mod:`chaoskit.plot`: ``ax=None`` makes a figure, the Axes is returned, matplotlib is
imported only when drawing). :func:`wear_profile_section` builds the "Wear profiles"
section a wear study adds to its :class:`chaoskit.Report`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from chaoskit import ReportFigure, ReportSection, ReportTable
from chaoskit.reporting import MISSING

__all__ = ["plot_wear_profile", "wear_profile_section"]

#: Length units drawn in micrometres (wear depths are a few µm to a few hundred µm).
_MICRO = {"m": 1e6, "mm": 1e3, "um": 1.0, "µm": 1.0}


def _profile_dataset(profile: Any) -> xr.Dataset:
    to_dataset = getattr(profile, "to_dataset", None)
    if callable(to_dataset) and not isinstance(profile, (xr.Dataset, xr.DataArray)):
        profile = to_dataset()  # e.g. a wear-profile object of the simulator
    if isinstance(profile, xr.DataArray):
        profile = profile.to_dataset(name=str(profile.name or "wear_depth"))
    if not isinstance(profile, xr.Dataset) or "angle" not in profile.dims:
        raise ValueError(
            "plot_wear_profile() needs a Dataset or DataArray along the dimension 'angle' "
            "(rad), or an object with a to_dataset() method that returns one."
        )
    return profile


def _profile_variables(ds: xr.Dataset, variables: Sequence[str] | str | None) -> list[str]:
    along = [str(k) for k, v in ds.data_vars.items() if v.dims == ("angle",)]
    if variables is None:
        names = [n for n in along if "depth" in n] or along
    else:
        names = [variables] if isinstance(variables, str) else list(variables)
    missing = [n for n in names if n not in along]
    if missing or not names:
        raise ValueError(
            f"variables {missing or names} are not 1-D along 'angle'; available: {along}."
        )
    return names


def plot_wear_profile(
    profile: Any,
    *,
    variables: Sequence[str] | str | None = None,
    sectors: Sequence[tuple[float, float]] | None = None,
    sector_label: str = "highlighted sectors",
    ax: Any = None,
    **kwargs: Any,
) -> Any:
    """Draw wear depth against angle on polar axes.

    The radius is the depth :math:`h(\\varphi)` of each angular region (in µm when the
    variable's ``units`` are a length), the angle :math:`\\varphi` the region centre in the
    surface's own frame, counter-clockwise from the +x axis. The curve is closed over
    :math:`2\\pi`.

    Parameters
    ----------
    profile
        A Dataset along ``angle`` (rad) — e.g. the ``to_dataset()`` of a worn profile, with
        ``wear_depth`` (bearing) and ``journal_wear_depth`` — a DataArray along ``angle``,
        or any object with a ``to_dataset()`` method returning such a Dataset.
    variables
        The depth variables to draw (default: every 1-D variable along ``angle`` whose name
        contains ``depth``, or all of them if none does).
    sectors
        Angular intervals ``(start, stop)`` in degrees to shade, e.g. the wear zones
        reported in a paper; ``stop < start`` wraps through 0°.
    sector_label
        Legend entry of the shaded sectors.
    ax
        Polar Axes to draw on (``projection="polar"``); a new figure when None.
    **kwargs
        Passed to ``Axes.plot``.

    Returns
    -------
    matplotlib.axes.Axes
        The polar Axes.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> import mechanism
    >>> phi = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    >>> depth = xr.DataArray(1e-6 * (1 + np.cos(phi) ** 2), dims="angle",
    ...                      coords={"angle": phi}, name="wear_depth",
    ...                      attrs={"units": "m", "long_name": "bearing wear depth"})
    >>> ax = mechanism.plot_wear_profile(depth, sectors=[(75, 132), (252, 310)])
    >>> ax.name
    'polar'
    """
    ds = _profile_dataset(profile)
    names = _profile_variables(ds, variables)
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(
            figsize=(4.6, 4.6), layout="constrained", subplot_kw={"projection": "polar"}
        )
    elif getattr(ax, "name", "") != "polar":
        raise ValueError(
            "plot_wear_profile() draws on polar axes; pass ax=... with projection='polar'."
        )
    angle = np.asarray(ds["angle"].values, dtype=np.float64)
    order = np.argsort(np.mod(angle, 2.0 * np.pi))
    phi = np.mod(angle, 2.0 * np.pi)[order]
    phi = np.append(phi, phi[0] + 2.0 * np.pi)
    top = 0.0
    unit_text = ""
    for i, name in enumerate(names):
        var = ds[name]
        units = str(var.attrs.get("units", ""))
        scale = _MICRO.get(units, 1.0)
        unit_text = "µm" if units in _MICRO else units
        r = np.asarray(var.values, dtype=np.float64)[order] * scale
        r = np.append(r, r[0])
        style = {"lw": 1.2, "color": f"C{i}"}
        style.update(kwargs)
        ax.plot(phi, r, label=str(var.attrs.get("long_name", name)), **style)
        top = max(top, float(np.nanmax(r)) if r.size else 0.0)
    top = top if top > 0 else 1.0
    for k, (start, stop) in enumerate(sectors or ()):
        a0, a1 = np.deg2rad(float(start)), np.deg2rad(float(stop))
        if a1 < a0:
            a1 += 2.0 * np.pi
        ax.bar(
            (a0 + a1) / 2.0,
            1.05 * top,
            width=a1 - a0,
            bottom=0.0,
            color="0.6",
            alpha=0.25,
            linewidth=0,
            label=sector_label if k == 0 else None,
        )
    ax.set_theta_zero_location("E")
    ax.set_theta_direction(1)
    ax.set_ylim(0.0, 1.1 * top)
    ax.set_title(f"wear depth [{unit_text}]" if unit_text else "wear depth", fontsize=9)
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(-0.15, -0.15))
    return ax


def wear_profile_section(
    profiles: Any,
    *,
    sectors: Sequence[tuple[float, float]] | None = None,
    sector_label: str = "reference wear zones",
    title: str = "Wear profiles",
) -> ReportSection:
    """A report section of wear profiles: one polar figure each, and a table of worn arcs.

    Parameters
    ----------
    profiles
        A profile or ``{label: profile}``; each a :class:`~mechanism.WornProfile`, its
        ``to_dataset()`` or any Dataset/DataArray along ``angle`` (rad).
    sectors, sector_label
        Angular intervals (deg) shaded on the polar plots and listed in the captions (e.g.
        the wear zones a paper reports).
    title
        Section heading.

    Returns
    -------
    chaoskit.ReportSection
        Add it to a report with :meth:`chaoskit.Report.with_sections`.
    """
    out: list[Any] = []
    if isinstance(profiles, Mapping):
        items = [(str(k), v) for k, v in profiles.items()]
    else:
        items = [("wear profile", profiles)]
    rows, keys = [], []
    zones = _arc_text([(float(a), float(b)) for a, b in sectors]) if sectors else ""
    all_lengths = True
    for label, profile in items:
        ds = _profile_dataset(profile)
        names = _profile_variables(ds, None)

        def draw(axes: Any, ds: xr.Dataset = ds) -> None:
            plot_wear_profile(ds, sectors=sectors, sector_label=sector_label, ax=axes[0, 0])

        described = ", ".join(str(ds[n].attrs.get("long_name", n)) for n in names)
        out.append(
            _polar_figure(
                draw,
                section=title,
                name=f"wear-profile-{label}",
                caption=f"Wear profile ({label}): {described} against the angle of the "
                "surface, counter-clockwise from +x"
                + (f"; shaded: {sector_label} {zones}." if zones else "."),
            )
        )
        angle = np.asarray(ds["angle"].values, dtype=np.float64)
        for n in names:
            depth = np.asarray(ds[n].values, dtype=np.float64)
            units = str(ds[n].attrs.get("units", ""))
            scale = _MICRO.get(units, 1.0)
            all_lengths = all_lengths and units in _MICRO
            k = int(np.argmax(depth)) if depth.size else 0
            rows.append(
                {
                    "max_depth": float(depth[k]) * scale if depth.size else float("nan"),
                    "angle_of_max": float(np.rad2deg(angle[k]) % 360.0),
                    "arcs": _arc_text(_worn_arcs(angle, depth, 0.1)),
                }
            )
            keys.append((label, str(ds[n].attrs.get("long_name", n))))
    unit = "µm" if all_lengths else "units of the data"
    out.append(
        ReportTable(
            caption=(
                f"Wear profiles: largest depth ({unit}), its angle (deg), and the arcs where "
                "the depth is at least 10 % of the largest"
                + (f"; {sector_label}: {zones}." if zones else ".")
            ),
            data=pd.DataFrame(
                rows, index=pd.MultiIndex.from_tuples(keys, names=["profile", "surface"])
            ).astype(object),
            labels={
                "max_depth": f"largest depth ({unit})",
                "angle_of_max": "at angle (deg)",
                "arcs": "worn arcs (≥ 10 % of largest)",
            },
            section=title,
        )
    )
    return ReportSection(title=title, items=tuple(out))


def _worn_arcs(angle: np.ndarray, depth: np.ndarray, fraction: float) -> list[tuple[float, float]]:
    """Arcs (deg, counter-clockwise) where depth ≥ fraction × max, regions as equal bins."""
    order = np.argsort(np.mod(angle, 2 * np.pi))
    phi = np.mod(angle, 2 * np.pi)[order]
    h = depth[order]
    top = float(np.max(h)) if h.size else 0.0
    if top <= 0 or h.size < 3:
        return []
    worn = h >= fraction * top
    if worn.all():
        return [(0.0, 360.0)]
    half = np.pi / h.size
    start = int(np.flatnonzero(~worn)[0])  # walk from an unworn region: arcs never split
    arcs, run = [], None
    for k in range(1, h.size + 1):
        i = (start + k) % h.size
        if worn[i] and run is None:
            run = i
        if run is not None and (not worn[i] or k == h.size):
            last = (i - 1) % h.size if not worn[i] else i
            a0 = np.rad2deg(phi[run] - half) % 360.0
            a1 = np.rad2deg(phi[last] + half) % 360.0
            arcs.append((float(a0), float(a1) if a1 > 0 else 360.0))
            run = None
    return arcs


def _arc_text(arcs: list[tuple[float, float]]) -> str:
    return ", ".join(f"[{a:.0f}°, {b:.0f}°]" for a, b in arcs) if arcs else MISSING


def _polar_figure(
    draw: Callable[[Any], None], *, caption: str, name: str, section: str
) -> ReportFigure:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 5.0), layout="constrained")
    axes = fig.subplots(1, 1, squeeze=False, subplot_kw={"projection": "polar"})
    draw(axes)
    return ReportFigure.from_matplotlib(fig, caption=caption, name=name, section=section)
