"""Delay embedding: values, input types and errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from numpy.testing import assert_array_equal

from chaoskit import delay_embed


def test_rows_are_delayed_copies() -> None:
    x = np.arange(20.0) ** 2
    y = delay_embed(x, embedding_dim=3, lag=4)
    assert y.shape == (20 - 2 * 4, 3)
    for i in range(y.shape[0]):
        assert_array_equal(y[i], [x[i], x[i + 4], x[i + 8]])
    assert y.flags.c_contiguous and y.dtype == np.float64


@pytest.mark.parametrize("wrap", [pd.Series, lambda a: xr.DataArray(a, dims="time")])
def test_pandas_and_xarray_inputs(wrap) -> None:
    x = np.sin(np.arange(50.0))
    assert_array_equal(
        delay_embed(wrap(x), embedding_dim=2, lag=3), delay_embed(x, embedding_dim=2, lag=3)
    )


def test_minimum_length_is_accepted_and_one_less_is_rejected() -> None:
    x = np.arange(9.0)  # (m - 1) lag + 1 = 9
    assert delay_embed(x, embedding_dim=3, lag=4).shape == (1, 3)
    with pytest.raises(ValueError, match="minimum here is 9"):
        delay_embed(x[:8], embedding_dim=3, lag=4)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"embedding_dim": 0, "lag": 1}, "embedding_dim"),
        ({"embedding_dim": 2, "lag": 0}, "lag"),
        ({"embedding_dim": 2.5, "lag": 1}, "embedding_dim must be an integer"),
    ],
)
def test_bad_options(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        delay_embed(np.arange(10.0), **kwargs)


@pytest.mark.parametrize(
    ("x", "match"),
    [
        (np.array([1.0, np.nan, 2.0, 3.0]), "NaN"),
        (np.array(["a", "b", "c"]), "numeric"),
        (np.ones(10), "constant"),
    ],
)
def test_bad_series(x, match) -> None:
    with pytest.raises(ValueError, match=match):
        delay_embed(x, embedding_dim=1, lag=1)
