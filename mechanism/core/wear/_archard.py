"""Archard wear of a clearance joint's surfaces from a history of contact samples.

Per contact sample with normal force Fₙ and slip ``Δs = |v_t| Δt`` (docs/paper-model.md §6):

* Hertz line-contact half-width a = √(4 Fₙ R*/(π L E*)), R* the local effective radius;
* mean pressure p = Fₙ/(2 a L), Archard depth Δh = k p Δs, volume ΔV = k Fₙ Δs;
* ΔV is removed from the touched region, or spread over the regions covered by ±a/R with
  the semi-elliptical Hertz pressure, so that the summed worn volume grows by exactly ΔV.

Volume, not depth, is the conserved quantity: a region of arc width R Δ > 2a gets the
region-averaged depth ΔV_i/(L R Δ) rather than the peak k p Δs.

References
----------
.. [A53] J. F. Archard, "Contact and rubbing of flat surfaces", J. Appl. Phys. 24 (1953)
   981–988.
.. [F09] P. Flores, "Modeling and simulation of wear in revolute clearance joints in
   multibody systems", Mech. Mach. Theory 44 (2009) 1211–1222.
.. [J85] K. L. Johnson, Contact Mechanics, Cambridge University Press (1985), §4.3 (the
   semi-elliptical pressure of a cylinder contact).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import check_positive
from mechanism.core.contact import StiffnessForm, form_code
from mechanism.core.contact import hertz_half_width as _half_width_kernel

from . import _kernels as wear_kernels
from ._profile import DEFAULT_RADIUS_RATIO_LIMIT, WornProfile

__all__ = ["ArchardResult", "archard_wear", "hertz_half_width"]


def hertz_half_width(
    normal_force: float, *, effective_radius: float, length: float, effective_modulus: float
) -> float:
    """Half-width a = √(4 Fₙ R*/(π L E*)) (m) of a Hertz line (cylinder) contact [J85].

    The mean contact pressure is p = Fₙ/(2 a L) and the peak 4p/π.

    Examples
    --------
    >>> a = hertz_half_width(1000.0, effective_radius=7.45e-3, length=0.011,
    ...                      effective_modulus=113.7e9)
    >>> round(a * 1e6, 2)  # µm
    87.09
    """
    force = check_positive(normal_force, name="normal_force", allow_zero=True)
    r_star = check_positive(effective_radius, name="effective_radius")
    length = check_positive(length, name="length")
    e_star = check_positive(effective_modulus, name="effective_modulus")
    return float(_half_width_kernel(force, r_star, length, e_star))


@dataclass(frozen=True, kw_only=True, eq=False)
class ArchardResult:
    """Outcome of :func:`archard_wear`: the worn profile and the volume bookkeeping.

    Attributes
    ----------
    profile : WornProfile
        The profile after the history.
    requested_volume : float
        Σ k Fₙ Δs over the applied samples (m³), what each worn surface should lose.
    bearing_volume, journal_volume : float
        Volume actually removed from each surface by this call (m³).
    samples, reduced, rejected : int
        Samples with load and slip; increments scaled down by ``max_increment`` or the
        worn-through guard; increments rejected for non-finite input.
    coefficient, max_increment : float
        k (m² N⁻¹) and the per-sample depth cap (m, ``inf`` = none).
    spread : bool
        Whether increments were spread over the Hertz contact width.
    """

    profile: WornProfile
    requested_volume: float
    bearing_volume: float
    journal_volume: float
    samples: int
    reduced: int
    rejected: int
    coefficient: float
    max_increment: float
    spread: bool

    @property
    def success(self) -> bool:
        """True when every increment was applied in full."""
        return self.reduced == 0 and self.rejected == 0

    def to_dataset(self) -> xr.Dataset:
        """The worn profile's Dataset with the bookkeeping added to ``attrs``."""
        ds = self.profile.to_dataset()
        ds.attrs.update(
            archard_coefficient=self.coefficient,
            requested_volume=self.requested_volume,
            applied_bearing_volume=self.bearing_volume,
            applied_journal_volume=self.journal_volume,
            samples=self.samples,
            reduced_increments=self.reduced,
            rejected_increments=self.rejected,
            max_increment=self.max_increment,
            spread_over_contact_width=int(self.spread),
        )
        return ds


def _samples(values: Any, name: str) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array; got shape {arr.shape}.")
    if not np.isfinite(arr).all():
        raise ValueError(f"{name} contains non-finite values.")
    return arr


def archard_wear(
    profile: WornProfile,
    *,
    bearing_angle: Any,
    normal_force: Any,
    slip: Any,
    coefficient: float,
    effective_modulus: float,
    journal_angle: Any | None = None,
    form: StiffnessForm = "sum-of-radii",
    spread: bool = True,
    max_increment: float | None = None,
    radius_ratio_limit: float = DEFAULT_RADIUS_RATIO_LIMIT,
) -> ArchardResult:
    """Accumulate Archard wear over a history of contact samples.

    Parameters
    ----------
    profile : WornProfile
        Starting profile (not modified; the result holds a new one).
    bearing_angle : array_like
        Contact direction in the bearing frame per sample (rad).
    normal_force : array_like
        Fₙ per sample (N, ≥ 0; zero-force samples are skipped).
    slip : array_like
        Sliding distance per sample ``Δs = |v_t| Δt`` (m, ≥ 0).
    coefficient : float
        Archard coefficient k (m² N⁻¹, V = k Fₙ s; the paper uses 1.827e-13).
    effective_modulus : float
        E* (Pa) for the Hertz half-width.
    journal_angle : array_like, optional
        Contact direction in the journal frame (rad); required when
        ``profile.surfaces == "both"``.
    form : {"sum-of-radii", "conformal"}
        How the local R* of the half-width combines the curvatures; use the form of the
        stiffness (docs/paper-model.md "Contact stiffness").
    spread : bool
        Spread each increment over ±a/R with the Hertz pressure profile (else the touched
        region takes it all). Either way the volume is conserved.
    max_increment : float, optional
        Cap on the depth a region may gain from one sample (m); increments that would
        exceed it are scaled down and counted in ``reduced``.
    radius_ratio_limit : float
        Bound of the local R* relative to the unworn R* (see
        :meth:`WornProfile.local_effective_radius`).

    Returns
    -------
    ArchardResult

    Examples
    --------
    >>> p = WornProfile.unworn(bearing_radius=0.015, clearance=2e-4, length=0.011)
    >>> r = archard_wear(p, bearing_angle=1.0, journal_angle=0.0, normal_force=1000.0,
    ...                  slip=0.01, coefficient=1.827e-13, effective_modulus=113.7e9)
    >>> bool(np.isclose(r.profile.bearing_volume, 1.827e-13 * 1000.0 * 0.01, rtol=1e-12))
    True
    """
    if not isinstance(profile, WornProfile):
        raise ValueError(f"profile must be a WornProfile; got {type(profile).__name__}.")
    force = _samples(normal_force, "normal_force")
    angle_b = _samples(bearing_angle, "bearing_angle")
    ds = _samples(slip, "slip")
    wear_journal = profile.surfaces == "both"
    if journal_angle is None:
        if wear_journal:
            raise ValueError(
                "journal_angle is required when profile.surfaces == 'both' (the contact "
                "direction in the journal's own frame, rad)."
            )
        journal_angle = 0.0
    angle_j = _samples(journal_angle, "journal_angle")
    n = max(force.size, angle_b.size, ds.size, angle_j.size)
    arrays = []
    for name, arr in (
        ("normal_force", force),
        ("bearing_angle", angle_b),
        ("slip", ds),
        ("journal_angle", angle_j),
    ):
        if arr.size not in (1, n):
            raise ValueError(f"{name} has {arr.size} samples; expected 1 or {n}.")
        arrays.append(np.ascontiguousarray(np.broadcast_to(arr, (n,))))
    force, angle_b, ds, angle_j = arrays
    if (force < 0.0).any():
        raise ValueError("normal_force must be >= 0 (N).")
    if (ds < 0.0).any():
        raise ValueError("slip must be >= 0 (m); pass |v_t| dt.")
    k = check_positive(coefficient, name="coefficient")
    e_star = check_positive(effective_modulus, name="effective_modulus")
    code = form_code(form)
    limit = check_positive(radius_ratio_limit, name="radius_ratio_limit")
    if limit < 1.0:
        raise ValueError(f"radius_ratio_limit must be >= 1; got {radius_ratio_limit!r}.")
    cap = np.inf if max_increment is None else check_positive(max_increment, name="max_increment")

    hb = np.array(profile.bearing_depth, dtype=np.float64)
    hj = np.array(profile.journal_depth, dtype=np.float64)
    counters = np.zeros(3, dtype=np.int64)
    volumes = np.zeros(3)
    wear_kernels.archard_history(
        hb,
        hj,
        angle_b,
        angle_j,
        force,
        ds,
        k,
        profile.bearing_radius,
        profile.journal_radius,
        profile.length,
        e_star,
        code,
        profile.smoothing_regions,
        limit,
        bool(spread),
        wear_journal,
        cap if np.isfinite(cap) else -1.0,
        counters,
        volumes,
    )
    return ArchardResult(
        profile=profile.with_depth(bearing_depth=hb, journal_depth=hj),
        requested_volume=float(volumes[0]),
        bearing_volume=float(volumes[1]),
        journal_volume=float(volumes[2]),
        samples=int(counters[0]),
        reduced=int(counters[1]),
        rejected=int(counters[2]),
        coefficient=k,
        max_increment=float(cap),
        spread=bool(spread),
    )
