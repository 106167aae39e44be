"""Delay embedding and the choice of its delay and dimension.

Curves first, choices second: :func:`mutual_information` and :func:`autocorrelation` return
curves over lag, :func:`estimate_delay` picks a lag from them; :func:`false_nearest_neighbors`
and :func:`cao` return curves over dimension with the chosen ``embedding_dim``.
"""

from __future__ import annotations

from ._delay import (
    DelayCurve,
    DelayResult,
    autocorrelation,
    estimate_delay,
    lag_or_estimate,
    mutual_information,
)
from ._dimension import (
    DEFAULT_FNN_THRESHOLD,
    DimensionResult,
    cao,
    estimate_embedding_dim,
    false_nearest_neighbors,
    fnn_curve,
)
from ._embed import delay_embed, embed, min_length, standardize

# lag_or_estimate, fnn_curve, DEFAULT_FNN_THRESHOLD, embed, standardize and min_length are
# imported above for the sibling estimator folders (dimension, lyapunov, recurrence); they
# are not public API, so they stay out of __all__.
__all__ = [
    "DelayCurve",
    "DelayResult",
    "DimensionResult",
    "autocorrelation",
    "cao",
    "delay_embed",
    "estimate_delay",
    "estimate_embedding_dim",
    "false_nearest_neighbors",
    "mutual_information",
]
