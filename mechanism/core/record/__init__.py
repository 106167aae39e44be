"""Recording: an integration as an xarray Dataset, and the response metrics read from one."""

from ._metrics import (
    METRICS,
    ROD_STRAIN,
    friction_sign_flips,
    response_metrics,
    window_start,
)
from ._record import to_dataset

__all__ = [
    "METRICS",
    "ROD_STRAIN",
    "friction_sign_flips",
    "response_metrics",
    "to_dataset",
    "window_start",
]
