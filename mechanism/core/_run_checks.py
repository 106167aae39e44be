"""Warnings a user needs about a run: memory it will take, and contact deeper than the law.

Both thresholds are stated here and in ``docs/simulator.md``; a warning is a
:class:`SimulationWarning` (a ``UserWarning``), so ``warnings.filterwarnings`` can silence or
escalate it.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from .integrate import Recording

__all__ = [
    "OUTPUT_WARNING_BYTES",
    "PENETRATION_WARNING_FRACTION",
    "SimulationWarning",
    "estimated_run_bytes",
    "warn_if_deep_penetration",
    "warn_if_large",
]

#: A run whose recordings and output are estimated above this size (bytes) is announced.
OUTPUT_WARNING_BYTES = 2**30
#: A penetration above this fraction of a joint's radial clearance is announced: the
#: compliant contact laws describe a small local overlap of the surfaces, not a journal
#: that sinks a sizeable part of its clearance into the bearing.
PENETRATION_WARNING_FRACTION = 0.5


class SimulationWarning(UserWarning):
    """A simulation ran, but its settings or results deserve a look (see the message)."""


def estimated_run_bytes(models: Any, n_out: int) -> int:
    """Memory (bytes) that a run on ``n_out`` output samples holds at its end: the raw
    recording of each of ``models`` (the run and its ideal companion; allocated as
    ``Recording.empty`` does) and the Dataset built from them, counted as large as the first
    recording (an upper estimate; tests/mechanism/test_run_warnings.py bounds the ratio).
    """
    per_sample = [sum(a.nbytes for a in Recording.empty(m, 1)) for m in models]
    return int(n_out) * (sum(per_sample) + per_sample[0])


def warn_if_large(models: Any, n_out: int, output_step: float, *, stacklevel: int = 3) -> None:
    """Warn before allocating when a run would exceed :data:`OUTPUT_WARNING_BYTES`."""
    nbytes = estimated_run_bytes(models, n_out)
    if nbytes > OUTPUT_WARNING_BYTES:
        warnings.warn(
            f"this run records {n_out} samples (output step {output_step:.3g} s) and will "
            f"hold about {nbytes / 1e9:.1f} GB (recordings and output), above "
            f"{OUTPUT_WARNING_BYTES / 1e9:.1f} GB; raise output_step or shorten the run "
            "if that is more than you need.",
            SimulationWarning,
            stacklevel=stacklevel,
        )


def warn_if_deep_penetration(ds: Any, scene: Any, *, stacklevel: int = 3) -> None:
    """Warn when a joint's largest penetration exceeds
    :data:`PENETRATION_WARNING_FRACTION` of its clearance."""
    if "penetration" not in ds or "joint" not in ds["penetration"].dims:
        return
    names = [str(name) for name in ds["joint"].values]
    deepest = np.asarray(ds["penetration"].max("time").values, dtype=np.float64)
    for name, depth in zip(names, deepest, strict=True):
        # a slider corner's row is named JOINT.corner (a joint name holds no dot)
        clearance = float(scene.joints[str(name).split(".", 1)[0]].clearance)
        if np.isfinite(depth) and depth > PENETRATION_WARNING_FRACTION * clearance:
            warnings.warn(
                f"joint {name}: the largest penetration, {depth:.3g} m, is "
                f"{depth / clearance:.0%} of the clearance {clearance:.3g} m (above "
                f"{PENETRATION_WARNING_FRACTION:.0%}); the contact law assumes a small overlap, "
                "so forces and motion are doubtful here: check the speed, clearance and "
                "contact stiffness.",
                SimulationWarning,
                stacklevel=stacklevel,
            )
