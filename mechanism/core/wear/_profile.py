"""Worn geometry of a clearance revolute joint: the per-region wear depth of its surfaces.

The bearing (and optionally the journal) surface is a ring of ``regions`` equal angular
regions, each holding a wear depth (m). From it follow the local clearance, a smoothed
local curvature radius, the local effective radius R* and the local contact stiffness that
the contact law uses wherever the journal touches (docs/paper-model.md §6).

References
----------
.. [F09] P. Flores, "Modeling and simulation of wear in revolute clearance joints in
   multibody systems", Mech. Mach. Theory 44 (2009) 1211–1222.
.. [M10] S. Mukras, N. H. Kim, N. A. Mauntler, T. L. Schmitz, W. G. Sawyer, "Analysis of
   planar multibody systems with revolute joint wear", Wear 268 (2010) 643–652.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import xarray as xr

from chaoskit.contract import check_choice, check_int, check_positive
from mechanism.core.contact import StiffnessForm, form_code

from . import _kernels as wear_kernels

if TYPE_CHECKING:
    from mechanism.core.scene import ClearanceRevolute, WearSettings

__all__ = ["DEFAULT_RADIUS_RATIO_LIMIT", "Surface", "WornProfile"]

Surface = Literal["bearing", "journal"]

#: Default bound on the local R* relative to the unworn R* (both ways).
DEFAULT_RADIUS_RATIO_LIMIT = 10.0

_MIN_REGIONS = 3  # the three-point curvature needs a neighbour on each side


def _depth_array(values: Any, *, name: str) -> np.ndarray:
    arr = np.array(values, dtype=np.float64, copy=True)  # own copy: frozen means frozen
    if arr.ndim != 1:
        raise ValueError(
            f"{name} must be one-dimensional (one depth per region); got shape {arr.shape}."
        )
    if arr.size < _MIN_REGIONS:
        raise ValueError(f"{name} needs at least {_MIN_REGIONS} regions; got {arr.size}.")
    finite = np.isfinite(arr)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"{name} contains a non-finite depth at region {bad}.")
    if (arr < 0.0).any():
        bad = int(np.flatnonzero(arr < 0.0)[0])
        raise ValueError(
            f"{name} must be >= 0 everywhere (wear only removes material, so the clearance "
            f"never shrinks); region {bad} has depth {arr[bad]!r} m."
        )
    arr.flags.writeable = False
    return arr


def _angles(angle: Any, name: str) -> np.ndarray:
    arr = np.asarray(angle, dtype=np.float64)
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite (rad).")
    return arr


def _scalar_or_array(arr: np.ndarray) -> Any:
    return float(arr) if arr.ndim == 0 else arr


@dataclass(frozen=True, kw_only=True, eq=False)
class WornProfile:
    """Wear depth per angular region of the bearing and journal of one clearance joint.

    Region i covers body-frame angles [i Δ, (i+1) Δ), Δ = 2π/regions. The bearing surface
    grows outward (local radius R_b + h_b), the journal shrinks inward (R_j − h_j), so the
    local clearance is c(φ_b, φ_j) = c₀ + h_b(φ_b) + h_j(φ_j) ≥ c₀ > 0. Wear is held per
    region; h(φ) is the continuous surface through the region depths at the region
    centres (periodic monotone cubic, C1, never below zero; docs/contact-and-wear.md §5).

    Parameters
    ----------
    bearing_radius : float
        Unworn bearing radius R_b (m).
    clearance : float
        Unworn radial clearance c₀ (m), 0 < c₀ < R_b.
    length : float
        Axial contact length L (m).
    bearing_depth, journal_depth : array_like
        Wear depth per region (m, ≥ 0), equal lengths (≥ 3 regions). A journal region must
        not be worn through (depth < R_j). Depths larger than the clearance are valid: the
        clearance only grows.
    surfaces : {"both", "bearing"}
        Which surfaces wear during :func:`~mechanism.archard_wear`.
    smoothing_regions : int
        Width of the centred moving average applied before the curvature is computed
        (1 = none; [F09] and docs/paper-model.md §6 use 3–5).

    Examples
    --------
    >>> p = WornProfile.unworn(bearing_radius=0.015, clearance=2e-4, length=0.011)
    >>> p.regions, round(p.local_clearance(1.0), 6)
    (360, 0.0002)
    """

    bearing_radius: float
    clearance: float
    length: float
    bearing_depth: np.ndarray
    journal_depth: np.ndarray
    surfaces: Literal["both", "bearing"] = "both"
    smoothing_regions: int = 5

    def __post_init__(self) -> None:
        rb = check_positive(self.bearing_radius, name="bearing_radius")
        c = check_positive(self.clearance, name="clearance")
        if c >= rb:
            raise ValueError(
                f"clearance must be smaller than bearing_radius; got clearance={c!r} m, "
                f"bearing_radius={rb!r} m."
            )
        length = check_positive(self.length, name="length")
        hb = _depth_array(self.bearing_depth, name="bearing_depth")
        hj = _depth_array(self.journal_depth, name="journal_depth")
        if hj.size != hb.size:
            raise ValueError(
                f"bearing_depth and journal_depth must have the same number of regions; got "
                f"{hb.size} and {hj.size}."
            )
        rj = rb - c
        if hj.max() >= rj:
            bad = int(np.argmax(hj))
            raise ValueError(
                f"journal region {bad} is worn through: depth {hj[bad]!r} m >= journal radius "
                f"{rj!r} m."
            )
        check_choice(self.surfaces, name="surfaces", choices=("both", "bearing"))
        smoothing = check_int(
            self.smoothing_regions, name="smoothing_regions", minimum=1, maximum=hb.size // 2
        )
        for name, value in (
            ("bearing_radius", rb),
            ("clearance", c),
            ("length", length),
            ("bearing_depth", hb),
            ("journal_depth", hj),
            ("smoothing_regions", smoothing),
        ):
            object.__setattr__(self, name, value)

    # --- construction and conversion ---------------------------------------------------

    @classmethod
    def unworn(
        cls,
        *,
        bearing_radius: float,
        clearance: float,
        length: float,
        regions: int = 360,
        surfaces: Literal["both", "bearing"] = "both",
        smoothing_regions: int = 5,
    ) -> WornProfile:
        """A profile with zero depth everywhere."""
        n = check_int(regions, name="regions", minimum=_MIN_REGIONS)
        return cls(
            bearing_radius=bearing_radius,
            clearance=clearance,
            length=length,
            bearing_depth=np.zeros(n),
            journal_depth=np.zeros(n),
            surfaces=surfaces,
            smoothing_regions=smoothing_regions,
        )

    @classmethod
    def from_joint(cls, joint: ClearanceRevolute) -> WornProfile:
        """The profile a scene's clearance joint carries (``joint.wear``).

        Empty ``bearing_profile`` / ``journal_profile`` tuples mean unworn surfaces;
        non-empty ones must hold ``joint.wear.regions`` depths.
        """
        wear = joint.wear
        n = check_int(wear.regions, name="wear.regions", minimum=_MIN_REGIONS)
        depths = {}
        for surface in ("bearing", "journal"):
            values = getattr(wear, f"{surface}_profile")
            if len(values) == 0:
                depths[surface] = np.zeros(n)
            elif len(values) != n:
                raise ValueError(
                    f"wear.{surface}_profile must hold wear.regions = {n} depths (or be "
                    f"empty for an unworn surface); got {len(values)}."
                )
            else:
                depths[surface] = np.asarray(values, dtype=np.float64)
        return cls(
            bearing_radius=joint.bearing_radius,
            clearance=joint.clearance,
            length=joint.length,
            bearing_depth=depths["bearing"],
            journal_depth=depths["journal"],
            surfaces=wear.surfaces,
            smoothing_regions=wear.smoothing_regions,
        )

    def to_wear_settings(self, settings: WearSettings) -> WearSettings:
        """``settings`` with this profile's depths (and region count, surfaces, smoothing).

        An unworn surface is stored as an empty tuple.
        """

        def as_tuple(depth: np.ndarray) -> tuple[float, ...]:
            return tuple(float(h) for h in depth) if depth.any() else ()

        return dataclasses.replace(
            settings,
            regions=self.regions,
            surfaces=self.surfaces,
            smoothing_regions=self.smoothing_regions,
            bearing_profile=as_tuple(self.bearing_depth),
            journal_profile=as_tuple(self.journal_depth),
        )

    def apply_to(self, joint: ClearanceRevolute) -> ClearanceRevolute:
        """A copy of ``joint`` carrying this profile (geometry must match the joint)."""
        for name in ("bearing_radius", "clearance", "length"):
            if not math.isclose(getattr(joint, name), getattr(self, name), rel_tol=1e-12):
                raise ValueError(
                    f"the profile's {name} ({getattr(self, name)!r}) differs from the "
                    f"joint's ({getattr(joint, name)!r})."
                )
        return dataclasses.replace(joint, wear=self.to_wear_settings(joint.wear))

    def with_depth(
        self, *, bearing_depth: Any | None = None, journal_depth: Any | None = None
    ) -> WornProfile:
        """A copy with new depth arrays (validated like the constructor)."""
        return dataclasses.replace(
            self,
            bearing_depth=self.bearing_depth if bearing_depth is None else bearing_depth,
            journal_depth=self.journal_depth if journal_depth is None else journal_depth,
        )

    # --- geometry ---------------------------------------------------------------------

    @property
    def regions(self) -> int:
        """Number of angular regions per surface."""
        return int(self.bearing_depth.size)

    @property
    def journal_radius(self) -> float:
        """Unworn journal radius R_j = R_b − c₀ (m)."""
        return self.bearing_radius - self.clearance

    @property
    def region_width(self) -> float:
        """Angular width Δ = 2π/regions of a region (rad)."""
        return 2.0 * math.pi / self.regions

    @property
    def angle(self) -> np.ndarray:
        """Region centre angles (rad)."""
        return (np.arange(self.regions) + 0.5) * self.region_width

    def _depth(self, surface: str) -> np.ndarray:
        check_choice(surface, name="surface", choices=("bearing", "journal"))
        return self.bearing_depth if surface == "bearing" else self.journal_depth

    def _radius(self, surface: str) -> float:
        return self.bearing_radius if surface == "bearing" else self.journal_radius

    def region_index(self, angle: Any) -> Any:
        """Index of the region containing each angle (rad, body frame)."""
        a = _angles(angle, "angle")
        out = np.vectorize(lambda x: wear_kernels.region_index(x, self.regions), otypes=[np.int64])(
            a
        )
        return int(out) if out.ndim == 0 else out

    def wear_depth(self, angle: Any, *, surface: Surface = "bearing") -> Any:
        """Wear depth (m) of the continuous worn surface at body-frame angle(s) (rad).

        The monotone cubic through the region depths at the region centres: the region's
        depth at its centre, C1 in the angle, never outside the range of the two nearest
        region depths (docs/contact-and-wear.md §5).
        """
        depth = self._depth(surface)
        a = _angles(angle, "angle")
        out = np.vectorize(lambda x: wear_kernels.surface_value(depth, x), otypes=[np.float64])(a)
        return _scalar_or_array(out)

    def wear_depth_slope(self, angle: Any, *, surface: Surface = "bearing") -> Any:
        """Angular derivative dh/dφ (m/rad) of :meth:`wear_depth` at angle(s) (rad)."""
        depth = self._depth(surface)
        a = _angles(angle, "angle")
        out = np.vectorize(lambda x: wear_kernels.surface_slope(depth, x), otypes=[np.float64])(a)
        return _scalar_or_array(out)

    def local_clearance(self, bearing_angle: Any, journal_angle: Any = 0.0) -> Any:
        """Local radial clearance c₀ + h_b(φ_b) + h_j(φ_j) (m) at contact angles (rad).

        Examples
        --------
        >>> p = WornProfile.unworn(bearing_radius=0.015, clearance=2e-4, length=0.011)
        >>> hb = np.zeros(360); hb[90] = 1e-5
        >>> round(p.with_depth(bearing_depth=hb).local_clearance(np.radians(90.5)), 9)
        0.00021
        """
        b = _angles(bearing_angle, "bearing_angle")
        j = _angles(journal_angle, "journal_angle")
        c0, hb, hj = self.clearance, self.bearing_depth, self.journal_depth
        out = np.vectorize(
            lambda x, y: wear_kernels.local_clearance(c0, hb, hj, x, y), otypes=[np.float64]
        )(b, j)
        return _scalar_or_array(out)

    def smoothed_depth(self, *, surface: Surface = "bearing") -> np.ndarray:
        """The moving-average depth (m) per region the curvature is computed from."""
        depth = self._depth(surface)
        return np.array(
            [
                wear_kernels.smoothed_depth(depth, i, self.smoothing_regions)
                for i in range(self.regions)
            ]
        )

    def curvature(self, *, surface: Surface = "bearing") -> np.ndarray:
        """Signed local curvature (1/m) per region of the smoothed worn surface.

        1/R on untouched arcs, positive where the centre of curvature lies on the ring's
        side. Tabulate it once per profile for ``_kernels.local_stiffness_tabulated``.
        """
        depth = self._depth(surface)
        kappa = np.empty(self.regions)
        wear_kernels.curvature_profile(
            self._radius(surface), depth, self.smoothing_regions, surface == "bearing", kappa
        )
        return kappa

    def curvature_radius(self, *, surface: Surface = "bearing") -> np.ndarray:
        """Signed local curvature radius (m) per region of the smoothed worn surface.

        R_b (R_j) on untouched arcs; larger where wear flattens the surface, ``inf`` where it
        is locally straight and negative where it bulges towards the ring's centre.
        """
        with np.errstate(divide="ignore"):
            return 1.0 / self.curvature(surface=surface)

    def local_effective_radius(
        self,
        bearing_angle: Any,
        journal_angle: Any = 0.0,
        *,
        form: StiffnessForm = "sum-of-radii",
        radius_ratio_limit: float = DEFAULT_RADIUS_RATIO_LIMIT,
    ) -> Any:
        """Local R* (m) from the smoothed local curvatures of bearing and journal.

        1/R* = κ_j − κ_b (``"conformal"``) or κ_j + κ_b (``"sum-of-radii"``), bounded within a
        factor ``radius_ratio_limit`` of the unworn R*; the region-centre curvatures are
        interpolated by the same monotone cubic as the depth.
        """
        code = form_code(form)
        limit = self._ratio_limit(radius_ratio_limit)
        b = _angles(bearing_angle, "bearing_angle")
        j = _angles(journal_angle, "journal_angle")
        args = (self.bearing_radius, self.journal_radius, self.bearing_depth, self.journal_depth)
        s = self.smoothing_regions
        out = np.vectorize(
            lambda x, y: wear_kernels.local_effective_radius(code, *args, x, y, s, limit),
            otypes=[np.float64],
        )(b, j)
        return _scalar_or_array(out)

    def local_stiffness(
        self,
        bearing_angle: Any,
        journal_angle: Any = 0.0,
        *,
        effective_modulus: float,
        form: StiffnessForm = "sum-of-radii",
        radius_ratio_limit: float = DEFAULT_RADIUS_RATIO_LIMIT,
    ) -> Any:
        """Local stiffness K_n = (4/3) E* √R*_n (N m^-1.5) at contact angles (rad).

        Equals :func:`mechanism.hertz_stiffness` on unworn arcs.

        Examples
        --------
        >>> p = WornProfile.unworn(bearing_radius=0.015, clearance=2e-4, length=0.011)
        >>> f"{p.local_stiffness(2.0, effective_modulus=113.736e9):.3e}"
        '1.309e+10'
        """
        e_star = check_positive(effective_modulus, name="effective_modulus")
        r_star = np.asarray(
            self.local_effective_radius(
                bearing_angle,
                journal_angle,
                form=form,
                radius_ratio_limit=radius_ratio_limit,
            )
        )
        return _scalar_or_array(4.0 / 3.0 * e_star * np.sqrt(r_star))

    @staticmethod
    def _ratio_limit(value: float) -> float:
        limit = check_positive(value, name="radius_ratio_limit")
        if limit < 1.0:
            raise ValueError(f"radius_ratio_limit must be >= 1; got {value!r}.")
        return limit

    # --- volumes and output -----------------------------------------------------------

    @property
    def bearing_volume(self) -> float:
        """Volume the bearing has lost, Σ L Δ h_i (R_b + h_i/2) (m³)."""
        return float(
            wear_kernels.worn_volume(self.bearing_depth, self.bearing_radius, self.length, True)
        )

    @property
    def journal_volume(self) -> float:
        """Volume the journal has lost, Σ L Δ h_i (R_j − h_i/2) (m³)."""
        return float(
            wear_kernels.worn_volume(self.journal_depth, self.journal_radius, self.length, False)
        )

    @property
    def volume(self) -> float:
        """Total worn volume of both surfaces (m³)."""
        return self.bearing_volume + self.journal_volume

    def to_dataset(self) -> xr.Dataset:
        """The profile as a labelled Dataset over the region centre ``angle``.

        Variables ``wear_depth`` (bearing), ``journal_wear_depth``, ``curvature_radius``
        and ``journal_curvature_radius``; geometry and worn volumes in ``attrs``.
        :meth:`from_dataset` reads it back.
        """
        angle = xr.Variable(
            "angle",
            self.angle,
            {"units": "rad", "long_name": "region centre angle in the surface's body frame"},
        )

        def var(values: np.ndarray, units: str, long_name: str) -> xr.Variable:
            return xr.Variable(
                "angle",
                np.asarray(values, dtype=np.float64),
                {"units": units, "long_name": long_name},
            )

        return xr.Dataset(
            {
                "wear_depth": var(self.bearing_depth, "m", "bearing wear depth"),
                "journal_wear_depth": var(self.journal_depth, "m", "journal wear depth"),
                "curvature_radius": var(
                    self.curvature_radius(surface="bearing"),
                    "m",
                    "smoothed local curvature radius of the bearing surface",
                ),
                "journal_curvature_radius": var(
                    self.curvature_radius(surface="journal"),
                    "m",
                    "smoothed local curvature radius of the journal surface",
                ),
            },
            coords={"angle": angle},
            attrs={
                "bearing_radius": self.bearing_radius,
                "clearance": self.clearance,
                "length": self.length,
                "surfaces": self.surfaces,
                "smoothing_regions": self.smoothing_regions,
                "bearing_volume": self.bearing_volume,
                "journal_volume": self.journal_volume,
                "length_units": "m",
                "volume_units": "m3",
            },
        )

    @classmethod
    def from_dataset(cls, ds: xr.Dataset) -> WornProfile:
        """Rebuild a profile from :meth:`to_dataset` output."""
        return cls(
            bearing_radius=float(ds.attrs["bearing_radius"]),
            clearance=float(ds.attrs["clearance"]),
            length=float(ds.attrs["length"]),
            bearing_depth=ds["wear_depth"].values,
            journal_depth=ds["journal_wear_depth"].values,
            surfaces=str(ds.attrs["surfaces"]),  # type: ignore[arg-type]
            smoothing_regions=int(ds.attrs["smoothing_regions"]),
        )
