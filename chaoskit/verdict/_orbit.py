"""A periodic orbit found in the equations of motion, as evidence for the motion verdict."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["PeriodicOrbitEvidence"]


@dataclass(frozen=True)
class PeriodicOrbitEvidence:
    r"""A periodic orbit of the equations of motion and its Floquet multipliers.

    Produced by a solver of the equations (e.g. a shooting method on the stroboscopic map:
    :math:`\mathbf P^k(\mathbf x^*) = \mathbf x^*`) and read by
    :func:`chaoskit.classify_motion` (``orbit=``): a converged, stable orbit that the
    simulated motion approaches says "the equations say regular: periodic with period
    :math:`k`".

    Attributes
    ----------
    period
        :math:`k`: drive periods (or iterations) per period of the orbit, at least 1.
    multipliers
        The non-neutral Floquet multipliers (eigenvalues of the monodromy matrix
        :math:`\partial \mathbf P^k / \partial \mathbf x` at the orbit), complex. The orbit
        is linearly stable when all lie inside the unit circle.
    neutral_multipliers
        The multipliers that are 1 by construction (a constraint, a conserved quantity,
        the direction along an autonomous orbit), complex; not used for stability.
    residual
        Relative closing error of the orbit, :math:`\|\mathbf P^k(\mathbf x^*) - \mathbf
        x^*\| / \|\mathbf x^*\|` (or over a reference scale the solver states).
    approach
        Relative distance between the simulated motion's stroboscopic state and the orbit
        (after the transient the simulation discarded).
    tolerance
        Relative distance below which the orbit counts as converged (``residual``) and the
        motion as attracted to it (``approach``).

    Raises
    ------
    ValueError
        If ``period`` is not an integer of at least 1, a multiplier is not finite, or
        ``residual``, ``approach`` or ``tolerance`` is negative or not finite
        (``tolerance`` must be positive).

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import PeriodicOrbitEvidence
    >>> ev = PeriodicOrbitEvidence(1, np.array([0.3 + 0.1j, 0.5]), np.array([1.0]),
    ...                            1e-10, 1e-6, 1e-4)
    >>> ev.stable, ev.attracting, ev.converged
    (True, True, True)
    """

    period: int
    multipliers: np.ndarray
    neutral_multipliers: np.ndarray
    residual: float
    approach: float
    tolerance: float

    def __post_init__(self) -> None:
        if isinstance(self.period, bool) or not isinstance(self.period, (int, np.integer)):
            raise ValueError(f"period must be an integer >= 1; got {self.period!r}.")
        if self.period < 1:
            raise ValueError(f"period must be an integer >= 1; got {self.period}.")
        object.__setattr__(self, "period", int(self.period))
        for name in ("multipliers", "neutral_multipliers"):
            values = np.atleast_1d(np.asarray(getattr(self, name), dtype=np.complex128)).ravel()
            if not np.all(np.isfinite(values)):
                raise ValueError(f"{name} must be finite complex numbers; got {values}.")
            values.setflags(write=False)
            object.__setattr__(self, name, values)
        for name in ("residual", "approach", "tolerance"):
            try:
                value = float(getattr(self, name))
            except (TypeError, ValueError):
                raise ValueError(
                    f"{name} must be a finite number >= 0; got {getattr(self, name)!r}."
                ) from None
            if not math.isfinite(value) or value < 0.0:
                raise ValueError(f"{name} must be a finite number >= 0; got {value!r}.")
            object.__setattr__(self, name, value)
        if self.tolerance == 0.0:
            raise ValueError("tolerance must be > 0 (a relative distance); got 0.")

    @property
    def largest_multiplier(self) -> float:
        """Largest modulus among the non-neutral multipliers (0 if there are none)."""
        return float(np.max(np.abs(self.multipliers))) if self.multipliers.size else 0.0

    @property
    def stable(self) -> bool:
        """All non-neutral multipliers inside the unit circle."""
        return bool(self.largest_multiplier < 1.0)

    @property
    def attracting(self) -> bool:
        """The simulated motion is within ``tolerance`` of the orbit."""
        return bool(self.approach <= self.tolerance)

    @property
    def converged(self) -> bool:
        """The orbit closes within ``tolerance``."""
        return bool(self.residual <= self.tolerance)

    def problem(self) -> str | None:
        """Why the orbit is no evidence of regular motion (None if it is)."""
        problems = []
        if not self.converged:
            problems.append(
                f"it did not converge (closing error {self.residual:.3g} > tolerance "
                f"{self.tolerance:.3g})"
            )
        if not self.stable:
            problems.append(
                f"it is unstable (largest multiplier |μ| = {self.largest_multiplier:.4g} ≥ 1)"
            )
        if not self.attracting:
            problems.append(
                f"the motion does not approach it (distance {self.approach:.3g} > tolerance "
                f"{self.tolerance:.3g})"
            )
        return "; ".join(problems) if problems else None
