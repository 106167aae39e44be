"""Settings of the wear update loop: defaults, limits and their checks (shared by
:func:`mechanism.predict_wear` and :func:`mechanism.wear_life`)."""

from __future__ import annotations

import math
from typing import Any

from chaoskit.contract import check_int, check_positive

__all__ = [
    "DEFAULT_AVERAGED_REVOLUTIONS",
    "DEFAULT_MAX_DEPTH_INCREMENT",
    "MAX_AVERAGED_REVOLUTIONS",
    "MAX_SUB_UPDATES",
    "PENETRATION_LIMIT",
]

#: Default of ``max_depth_increment``: the largest depth one sub-update may add, as a
#: fraction of the radial clearance (docs/wear.md, "Sub-updates").
DEFAULT_MAX_DEPTH_INCREMENT = 0.025
#: The hard check: a simulated state whose penetration exceeds this fraction of the joint's
#: radial clearance stops the prediction (the compliant contact law describes a small overlap).
PENETRATION_LIMIT = 1.0
#: Most sub-updates one update may be split into before the prediction stops.
MAX_SUB_UPDATES = 100
#: Default of ``averaged_revolutions`` in :func:`predict_wear`: one revolution, the
#: published update scheme (Flores 2009), so its results are unchanged; where the motion is
#: irregular use more (:func:`mechanism.wear_life` defaults to more; docs/wear.md).
DEFAULT_AVERAGED_REVOLUTIONS = 1
#: Largest accepted ``averaged_revolutions``.
MAX_AVERAGED_REVOLUTIONS = 1000
#: Most batches of consecutive revolutions behind the 95 % interval of the wear per cycle.
MAX_BATCHES = 10
#: Regions whose mean wear per cycle is at least this fraction of their surface's largest
#: enter the largest *relative* half-width (elsewhere the relative width of a vanishing
#: rate says nothing about the profile).
RELATIVE_HALFWIDTH_FLOOR = 0.1


def checked_settings(
    updates: Any, cycles_per_update: Any, max_depth_increment: Any, settle_revolutions: Any
) -> tuple[int, float, float, float]:
    """The settings of :func:`predict_wear`, or a ValueError naming the one out of range."""
    n = check_int(updates, name="updates", minimum=1)
    block = check_positive(cycles_per_update, name="cycles_per_update")
    limit = check_depth_increment(max_depth_increment)
    settle = float(settle_revolutions)
    if not (math.isfinite(settle) and settle >= 0.0):
        raise ValueError(f"settle_revolutions must be >= 0; got {settle_revolutions!r}.")
    return n, block, limit, settle


def check_depth_increment(value: Any) -> float:
    """``max_depth_increment`` as a float in (0, 1], or a ValueError naming its range."""
    try:
        limit = float(value)
    except (TypeError, ValueError):
        limit = math.nan
    if not 0.0 < limit <= 1.0:  # NaN fails too
        raise ValueError(
            "max_depth_increment must be in (0, 1] (a fraction of the radial clearance); "
            f"got {value!r}."
        )
    return limit


def check_averaged_revolutions(value: Any) -> int:
    """``averaged_revolutions`` as an int, or a ValueError naming its range."""
    return check_int(
        value, name="averaged_revolutions", minimum=1, maximum=MAX_AVERAGED_REVOLUTIONS
    )


def check_first_revolutions(value: Any, discard: float) -> float | None:
    """``lyapunov_first_revolutions`` as a float (None kept), or a ValueError naming it."""
    if value is None:
        return None
    try:
        out = float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and out > discard):
        raise ValueError(
            "lyapunov_first_revolutions must be None or a number of revolutions > "
            f"lyapunov_discard ({discard:g}); got {value!r}."
        )
    return out


def check_fraction(value: Any, name: str) -> float:
    """``value`` as a fraction of the drive period in (0, 1), or a ValueError naming it."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not 0.0 < out < 1.0:
        raise ValueError(
            f"{name} must be in (0, 1) (a fraction of the drive period); got {value!r}."
        )
    return out


def check_increment_settle(value: Any) -> int | None:
    """``increment_settle_revolutions`` as an int in [0, 100] (None kept), or a ValueError
    naming it."""
    if value is None:
        return None
    return check_int(value, name="increment_settle_revolutions", minimum=0, maximum=100)
