"""The equations' exponent as an arbiter of the motion verdict: what its interval says."""

from __future__ import annotations

import math
from typing import Any, Literal

Arbiter = Literal["chaotic", "regular"]


def arbiter_values(obj: Any) -> tuple[float, float, float]:
    """(exponent, low, high) of an exponent object: ``exponent`` or ``mle``, and a 95 %
    interval ``ci`` or ``interval``."""
    value = getattr(obj, "exponent", None)
    if value is None:
        value = getattr(obj, "mle", None)
    interval = getattr(obj, "ci", None)
    if interval is None:
        interval = getattr(obj, "interval", None)
    try:
        lo, hi = (float(v) for v in interval)  # type: ignore[union-attr]
        value = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(
            "exponent must have 'exponent' (1/s) and a 95 % interval 'ci' (or 'interval') "
            f"of two numbers; got {type(obj).__name__}."
        ) from None
    if lo > hi:
        raise ValueError(f"exponent's interval must have low <= high; got [{lo!r}, {hi!r}].")
    return value, lo, hi


def equations_arbiter(obj: Any) -> tuple[Arbiter | None, str]:
    value, lo, hi = arbiter_values(obj)
    if not (math.isfinite(value) and math.isfinite(lo) and math.isfinite(hi)):
        return None, (
            f"the equations' exponent λ₁ = {value:.4g} [{lo:.4g}, {hi:.4g}] has no finite 95 % "
            "interval (too few renormalisation intervals); it is not used as evidence"
        )
    say: Arbiter = "chaotic" if lo > 0.0 else "regular"
    why = "95 % interval above 0" if say == "chaotic" else "95 % interval not above 0"
    return say, f"the equations say {say}: λ₁ = {value:.4g} [{lo:.4g}, {hi:.4g}] ({why})"
