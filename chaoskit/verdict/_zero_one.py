"""The Gottwald–Melbourne 0–1 test for chaos (correlation method, median over c)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from .._progress import stage
from .._validate import as_series, check_int
from . import _kernels
from ._rng import as_generator

__all__ = ["ZeroOneResult", "zero_one_test"]

C_RANGE = (np.pi / 5.0, 4.0 * np.pi / 5.0)


@dataclass(frozen=True, kw_only=True)
class ZeroOneResult:
    """Outcome of :func:`zero_one_test`.

    Attributes
    ----------
    k
        Median of ``k_values``: near 0 for regular dynamics, near 1 for chaotic dynamics.
    k_values
        The correlation coefficient :math:`K_c` for each frequency in ``c_values``.
    c_values
        The random frequencies :math:`c \\in (\\pi/5, 4\\pi/5)` used, rad per sample.
    ncut
        Largest displacement lag :math:`n` used in the mean-square displacement.
    n_samples
        Length of the series tested.
    """

    k: float
    k_values: np.ndarray
    c_values: np.ndarray
    ncut: int
    n_samples: int

    def to_dataset(self) -> xr.Dataset:
        """The per-frequency :math:`K_c` as a Dataset over the dimension ``c``."""
        ds = xr.Dataset(
            {
                "k_c": (
                    "c",
                    self.k_values,
                    {"units": "1", "long_name": "0-1 test K for frequency c"},
                )
            },
            coords={"c": ("c", self.c_values, {"units": "rad", "long_name": "frequency c"})},
        )
        ds.attrs.update(
            {"k_median": self.k, "ncut": self.ncut, "n_samples": self.n_samples, "method": "0-1"}
        )
        return ds


def zero_one_test(
    x: Any,
    *,
    n_c: int = 100,
    ncut: int | None = None,
    rng: Any = None,
) -> ZeroOneResult:
    r"""Gottwald–Melbourne 0–1 test for chaos.

    The observable :math:`\phi(j)` drives the translation variables
    :math:`p_c(n) = \sum_{j\le n} \phi(j)\cos jc` and :math:`q_c(n) = \sum_{j\le n} \phi(j)\sin jc`.
    Their mean-square displacement, with the bounded oscillatory term removed,

    .. math::

        D_c(n) = \langle (p_c(j+n)-p_c(j))^2 + (q_c(j+n)-q_c(j))^2 \rangle_j
                 - \bar\phi^{\,2}\,\frac{1-\cos nc}{1-\cos c},

    grows linearly in :math:`n` for chaotic dynamics and stays bounded for regular dynamics.
    :math:`K_c` is the correlation coefficient of :math:`D_c(n)` with :math:`n`
    (:math:`n = 1 \ldots n_{cut}`, :math:`n_{cut} = N/10`), and :math:`K` is the median of
    :math:`K_c` over ``n_c`` frequencies drawn uniformly from :math:`(\pi/5, 4\pi/5)`; the
    median discards the isolated resonant frequencies at which a regular signal also gives
    :math:`K_c \approx 1`.

    The test needs a series that is not oversampled: for a flow, test a section or a series
    subsampled to a few samples per characteristic time (:func:`chaoskit.classify` uses the
    delay). Noise also gives :math:`K \approx 1`; the test separates regular from irregular,
    not chaos from noise.

    Parameters
    ----------
    x
        The observable, one sample per map iteration or per subsampled time step.
    n_c
        Number of random frequencies :math:`c`.
    ncut
        Largest displacement lag (default ``N // 10``).
    rng
        Seed or :class:`numpy.random.Generator` for the frequencies.

    Returns
    -------
    ZeroOneResult

    References
    ----------
    G. A. Gottwald and I. Melbourne, "A new test for chaos in deterministic systems",
    Proc. R. Soc. Lond. A 460, 603–611 (2004); "On the implementation of the 0–1 test for
    chaos", SIAM J. Appl. Dyn. Syst. 8, 129–145 (2009).

    Examples
    --------
    >>> from chaoskit import systems, zero_one_test
    >>> round(zero_one_test(systems.logistic(2000, r=3.9), rng=0).k, 1)
    1.0
    >>> zero_one_test(systems.logistic(2000, r=3.5), rng=0).k < 0.1
    True
    """
    stage("zero-one")
    phi = as_series(x, name="x", min_length=100)
    n = phi.size
    n_c = check_int(n_c, name="n_c", minimum=1)
    if ncut is None:
        ncut = n // 10
    ncut = check_int(ncut, name="ncut", minimum=10, maximum=n // 2)
    c_values = np.sort(as_generator(rng).uniform(C_RANGE[0], C_RANGE[1], size=n_c))
    k_values = _kernels.zero_one_k(phi, np.ascontiguousarray(c_values), ncut)
    return ZeroOneResult(
        k=float(np.median(k_values)),
        k_values=k_values,
        c_values=c_values,
        ncut=ncut,
        n_samples=n,
    )
