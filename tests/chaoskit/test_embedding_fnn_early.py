"""The automatic dimension's early decision: the choice of the full false-neighbour curve."""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import systems
from chaoskit.embedding import DEFAULT_FNN_THRESHOLD, fnn_curve, standardize

SERIES = {
    "lorenz": (lambda: systems.lorenz(6000, dt=0.01)[:, 0], 17, 160),
    "henon": (lambda: systems.henon(6000)[:, 0], 1, 4),
    "rossler": (lambda: systems.rossler(6000, dt=0.1)[:, 0], 15, 60),
    "logistic": (lambda: systems.logistic(6000), 1, 2),
    "noise": (lambda: np.random.default_rng(3).standard_normal(6000), 1, 1),
}


@pytest.mark.parametrize("name", list(SERIES))
def test_early_decision_chooses_the_full_curves_dimension(name: str) -> None:
    """Stopping a dimension once its false fraction is decided to reach the threshold
    keeps the chosen dimension and the rule; the rejected entries stay at or above the
    threshold and the chosen one is the full curve's value."""
    make, lag, w = SERIES[name]
    arr = standardize(np.asarray(make(), dtype=np.float64))
    args = (arr, lag, 8, 15.0, 2.0, w, DEFAULT_FNN_THRESHOLD, 5000)
    full = fnn_curve(*args, stop_early=False)
    early = fnn_curve(*args, stop_early=True)
    assert early.embedding_dim == full.embedding_dim
    assert early.rule == full.rule
    assert early.found == full.found
    d = early.curve.size
    assert (early.curve[:-1] >= DEFAULT_FNN_THRESHOLD).all()
    if early.found:
        assert early.curve[-1] == full.curve[d - 1]
