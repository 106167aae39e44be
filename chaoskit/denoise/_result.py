"""The result of a noise reduction: the cleaned series and how it was obtained."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from .._contract import stamp

__all__ = ["DenoiseResult"]


@dataclass(frozen=True, kw_only=True)
class DenoiseResult:
    """A noise-reduced series with the parameters used and the size of each correction.

    Attributes
    ----------
    cleaned
        The noise-reduced series, same length and units as the input.
    original
        The input series (float64 copy).
    method
        ``"local_projective"``.
    embedding_dim, lag
        Embedding dimension and delay (samples) of the delay vectors that were projected.
    manifold_dim
        Dimension of the local subspaces the delay vectors were projected onto.
    radius
        Neighbourhood radius (units of the series) of each iteration; every neighbourhood
        also holds at least ``min_neighbors`` points.
    min_neighbors
        Smallest number of points in a neighbourhood.
    theiler_window
        Delay vectors closer in time than this (samples) are not neighbours.
    iterations
        Number of correction passes.
    noise_level
        Noise standard deviation estimated from the input before the first pass (units of
        the series): the root-mean-square spread of the neighbourhoods off their
        ``manifold_dim`` leading directions. Close to the noise level for noisy data, a
        measure of local curvature for clean data.
    correction_rms
        Root-mean-square correction of each pass (units of the series).
    local_spread
        Median over sampled neighbourhoods of the standard deviation along each local
        principal direction, largest first (units of the series): the local singular-value
        spectrum the automatic ``manifold_dim`` was read from.
    embedding_dim_rule, lag_rule, manifold_dim_rule, radius_rule
        How each parameter was obtained (``"given"`` or the rule applied to the data).
    dt
        Sampling interval (units of the time axis; 1 for a series indexed by sample).
    name, units, long_name
        Name and attributes of the input (``"x"``, ``"unknown"``, ``"x"`` for plain arrays).
    dim, coord
        Dimension name and coordinate values of the input series.
    """

    cleaned: np.ndarray
    original: np.ndarray
    method: str
    embedding_dim: int
    lag: int
    manifold_dim: int
    radius: np.ndarray
    min_neighbors: int
    theiler_window: int
    iterations: int
    noise_level: float
    correction_rms: np.ndarray
    local_spread: np.ndarray
    embedding_dim_rule: str
    lag_rule: str
    manifold_dim_rule: str
    radius_rule: str
    dt: float
    name: str = "x"
    units: str = "unknown"
    long_name: str = "x"
    dim: str = "step"
    coord: np.ndarray = field(default_factory=lambda: np.empty(0))
    coord_attrs: dict[str, Any] = field(default_factory=dict)

    def _coords(self) -> dict[str, Any]:
        values = self.coord if self.coord.size else np.arange(self.cleaned.size) * self.dt
        attrs = dict(self.coord_attrs) or (
            {"units": "1", "long_name": "sample index"}
            if self.dim == "step" and self.dt == 1.0
            else {"units": "s", "long_name": "time"}
        )
        return {self.dim: (self.dim, values, attrs)}

    def _params(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "embedding_dim": self.embedding_dim,
            "embedding_dim_rule": self.embedding_dim_rule,
            "lag": self.lag,
            "lag_rule": self.lag_rule,
            "manifold_dim": self.manifold_dim,
            "manifold_dim_rule": self.manifold_dim_rule,
            "radius_rule": self.radius_rule,
            "min_neighbors": self.min_neighbors,
            "theiler_window": self.theiler_window,
            "iterations": self.iterations,
            "noise_level": self.noise_level,
            "dt": self.dt,
        }

    def to_dataarray(self) -> xr.DataArray:
        """The cleaned series on the input's axis, with ``units``, ``long_name`` and the
        parameters used in the attributes."""
        attrs = {
            "units": self.units,
            "long_name": f"{self.long_name}, noise-reduced (local projective)",
            **self._params(),
        }
        return xr.DataArray(
            self.cleaned, dims=(self.dim,), coords=self._coords(), name=self.name, attrs=attrs
        )

    def to_dataset(self) -> xr.Dataset:
        """Cleaned and original series, their difference, and the per-iteration correction
        size and radius; parameters and rules in the attributes, which carry the global
        attributes of the data contract (``docs/data-model.md``)."""
        unit = self.units
        it = np.arange(1, self.iterations + 1)
        data = {
            self.name: (
                self.dim,
                self.cleaned,
                {"units": unit, "long_name": f"{self.long_name}, noise-reduced"},
            ),
            f"{self.name}_original": (
                self.dim,
                self.original,
                {"units": unit, "long_name": f"{self.long_name}, as given"},
            ),
            "correction": (
                self.dim,
                self.cleaned - self.original,
                {"units": unit, "long_name": "total correction (noise-reduced minus given)"},
            ),
            "correction_rms": (
                "iteration",
                self.correction_rms,
                {"units": unit, "long_name": "root-mean-square correction of the pass"},
            ),
            "radius": (
                "iteration",
                self.radius,
                {"units": unit, "long_name": "neighbourhood radius of the pass"},
            ),
            "local_spread": (
                "direction",
                self.local_spread,
                {"units": unit, "long_name": "median local standard deviation per direction"},
            ),
        }
        coords = {
            **self._coords(),
            "iteration": ("iteration", it, {"units": "1", "long_name": "correction pass"}),
            "direction": (
                "direction",
                np.arange(1, self.local_spread.size + 1),
                {"units": "1", "long_name": "local principal direction, largest first"},
            ),
        }
        ds = xr.Dataset(data, coords=coords, attrs=self._params())
        return stamp(
            ds,
            title=f"{self.long_name}, noise-reduced",
            history=(
                f"chaoskit.local_projective_denoise: embedding_dim={self.embedding_dim}, "
                f"lag={self.lag}, manifold_dim={self.manifold_dim}, "
                f"iterations={self.iterations}"
            ),
        )
