"""Delay (Takens) embedding."""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import as_series, check_int

__all__ = ["delay_embed"]


def standardize(x: np.ndarray) -> np.ndarray:
    """``(x − mean) / std`` computed without overflow for huge amplitudes (x not constant)."""
    y = x / np.max(np.abs(x))
    y = y - y.mean()
    return y / y.std()


def embed(x: np.ndarray, embedding_dim: int, lag: int) -> np.ndarray:
    """Unchecked delay embedding of a contiguous float64 series (C-contiguous copy)."""
    n = x.size - (embedding_dim - 1) * lag
    out = np.empty((n, embedding_dim))
    for k in range(embedding_dim):
        out[:, k] = x[k * lag : k * lag + n]
    return out


def min_length(embedding_dim: int, lag: int, extra: int = 0) -> int:
    """Samples needed for one embedded point plus ``extra`` more."""
    return (embedding_dim - 1) * lag + 1 + extra


def delay_embed(x: Any, *, embedding_dim: int, lag: int) -> np.ndarray:
    r"""Reconstruct states from a scalar series by delay embedding.

    .. math:: \mathbf y_i = (x_i, x_{i+\tau}, \dots, x_{i+(m-1)\tau}),
              \quad i = 0, \dots, N - (m-1)\tau - 1

    Parameters
    ----------
    x
        Scalar series (numpy array, pandas Series or 1-D xarray DataArray), any units.
    embedding_dim
        Embedding dimension :math:`m \ge 1`.
    lag
        Delay :math:`\tau \ge 1` in samples.

    Returns
    -------
    numpy.ndarray
        C-contiguous float64 array of shape ``(N - (m-1)τ, m)``, same units as ``x``.

    Raises
    ------
    ValueError
        If ``x`` is not a finite, non-constant numeric series or is shorter than
        ``(m-1)τ + 1`` samples.

    References
    ----------
    F. Takens, "Detecting strange attractors in turbulence", Lecture Notes in Mathematics
    898 (1981) 366–381.

    Examples
    --------
    >>> import numpy as np
    >>> from chaoskit import delay_embed
    >>> delay_embed(np.arange(6.0), embedding_dim=3, lag=2)
    array([[0., 2., 4.],
           [1., 3., 5.]])
    """
    embedding_dim = check_int(embedding_dim, name="embedding_dim", minimum=1)
    lag = check_int(lag, name="lag", minimum=1)
    arr = as_series(x, min_length=min_length(embedding_dim, lag))
    return embed(arr, embedding_dim, lag)
