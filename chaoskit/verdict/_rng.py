"""One way to turn a user's ``rng`` argument into a numpy Generator."""

from __future__ import annotations

from typing import Any

import numpy as np


def as_generator(rng: Any) -> np.random.Generator:
    """Accept None (fresh entropy), an int seed, a SeedSequence or a Generator."""
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None or isinstance(rng, (int, np.integer, np.random.SeedSequence)):
        if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool) and rng < 0:
            raise ValueError(f"rng seed must be a non-negative integer; got {rng}.")
        return np.random.default_rng(rng)
    raise ValueError(
        f"rng must be None, a non-negative int seed or a numpy Generator; got {type(rng).__name__}."
    )
