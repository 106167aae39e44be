"""The table of verdicts: one row of scalars per variable, with units and long names.

Shared by :meth:`Verdict.to_dataset` and :func:`chaoskit.verdict.verdict_table`; it knows
the fields of a verdict's summary, not how a verdict is reached.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Protocol

import numpy as np
import xarray as xr

__all__ = ["FIELDS", "stack_verdicts"]

#: Every field of an analyze row: (long_name, units). ``T`` stands for the time unit of the
#: data (s for flows, iterations for maps); the actual unit is written into ``units``.
FIELDS: dict[str, tuple[str, str]] = {
    "label": ("verdict", ""),
    "period": ("period k of a period-k orbit (section points per period)", "1"),
    "confidence": ("fraction of the evidence agreeing with the verdict", "1"),
    "lag": ("embedding delay", "samples"),
    "lag_time": ("embedding delay", "T"),
    "embedding_dim": ("embedding dimension", "1"),
    "mle_rosenstein": ("largest Lyapunov exponent, Rosenstein", "T-1"),
    "mle_rosenstein_low": ("lower end of the 95% interval, Rosenstein", "T-1"),
    "mle_rosenstein_high": ("upper end of the 95% interval, Rosenstein", "T-1"),
    "mle_rosenstein_bits": ("largest Lyapunov exponent, Rosenstein, bits per sample", "bit"),
    "mle_wolf": ("largest Lyapunov exponent, Wolf", "T-1"),
    "mle_wolf_low": ("lower end of the 95% interval, Wolf", "T-1"),
    "mle_wolf_high": ("upper end of the 95% interval, Wolf", "T-1"),
    "mle_wolf_bits": ("largest Lyapunov exponent, Wolf, bits per sample", "bit"),
    "zero_one_k": ("0-1 test for chaos, median K", "1"),
    "surrogate_p_value": ("surrogate test p-value (prediction error, IAAFT)", "1"),
    "surrogate_effect": ("relative predictability gain over the median surrogate", "1"),
    "section_points": ("points in the Poincare/stroboscopic set", "1"),
    "section_structure": ("structure of the section set", ""),
    "characteristic_time": ("characteristic time of the growth test", "T"),
    "noise_level": ("estimated noise standard deviation over the signal's", "1"),
    "dt": ("sampling interval", "T"),
    "n_samples": ("series length", "samples"),
}
_STRINGS = ("label", "section_structure")


class SummarisedVerdict(Protocol):
    """What the table reads of a verdict: its summary row, its kind and its reason."""

    kind: str
    reason: str

    def summary(self) -> dict[str, Any]: ...


def stack_verdicts(verdicts: Mapping[str, SummarisedVerdict], labels: Sequence[str]) -> xr.Dataset:
    """Stack verdicts into a Dataset over the dimension ``variable``; ``labels`` are the
    verdict labels stored as the ``flag_meanings`` of ``label``.

    Exponents and times are in s and s⁻¹ when any verdict comes from a flow, per iteration
    when all come from maps.
    """
    names = list(verdicts)
    rows = [v.summary() for v in verdicts.values()]
    time_unit = "1" if rows and all(v.kind == "map" for v in verdicts.values()) else "s"
    data_vars = {}
    for key, (long_name, units) in FIELDS.items():
        values = [row[key] for row in rows]
        if key in _STRINGS:
            arr = np.array(values, dtype=object)
            attrs = {"long_name": long_name}
        else:
            arr = np.array(values, dtype=np.float64)
            unit = units.replace("T-1", "s-1" if time_unit == "s" else "1")
            attrs = {"long_name": long_name, "units": unit.replace("T", time_unit)}
        data_vars[key] = ("variable", arr, attrs)
    ds = xr.Dataset(
        data_vars,
        coords={"variable": ("variable", np.array(names, dtype=object), {"long_name": "variable"})},
    )
    ds["label"].attrs["flag_meanings"] = " ".join(labels)
    ds.attrs["reasons"] = " | ".join(f"{n}: {v.reason}" for n, v in verdicts.items())
    return ds
