"""The result of a largest-Lyapunov-exponent estimate."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

__all__ = ["LyapunovResult"]

_LN2 = float(np.log(2.0))


@dataclass(frozen=True, kw_only=True)
class LyapunovResult:
    """Largest Lyapunov exponent with its curve, fit and uncertainty.

    Attributes
    ----------
    method
        ``"rosenstein"``, ``"kantz"`` or ``"wolf"``.
    mle
        Largest Lyapunov exponent, natural log, per unit of ``dt`` (per second when ``dt``
        is in seconds; per iteration for maps with ``dt = 1``).
    mle_bits_per_sample
        The same in bits per sample: ``mle · dt / ln 2``.
    ci
        95 % confidence interval for ``mle`` (same units); see ``ci_method``.
    ci_method
        How ``ci`` was obtained, in words.
    dt
        Sampling interval (units of the caller; s for measured signals).
    embedding_dim, lag, theiler_window
        Embedding dimension, delay (samples) and Theiler window (samples) used.
    lag_rule, dim_rule
        How ``lag`` and ``embedding_dim`` were obtained ("given" or the estimator's rule).
    fit_range
        Rosenstein: first and last horizon (samples) of the fitted line. Wolf: first and last
        evolution index of the averaging window.
    fit_found
        Rosenstein: whether the automatic rule found a straight scaling region (``False``:
        the whole pre-saturation range was fitted; treat the number with care). Always
        ``True`` for a user-given range and for Wolf.
    r2
        Coefficient of determination of the fitted line (Rosenstein); NaN for Wolf, which
        fits no line.
    horizon
        Rosenstein: divergence horizon in samples. Wolf: evolution index (samples).
    curve
        Rosenstein: mean natural-log divergence ⟨ln d(k)⟩. Wolf: running estimate of the
        exponent (natural log per sample).
    n_points
        Reference points used (Rosenstein) or replacement steps (Wolf).
    n_samples
        Length of the input series.
    subsampled
        Whether the reference points were an evenly spaced subset of all points.
    params
        Further parameters actually used (method-specific), as a plain dict.
    """

    method: str
    mle: float
    mle_bits_per_sample: float
    ci: tuple[float, float]
    ci_method: str
    dt: float
    embedding_dim: int
    lag: int
    theiler_window: int
    lag_rule: str
    dim_rule: str
    fit_range: tuple[int, int]
    fit_found: bool
    r2: float
    horizon: np.ndarray
    curve: np.ndarray
    n_points: int
    n_samples: int
    subsampled: bool
    params: dict

    @property
    def mle_per_sample(self) -> float:
        """Exponent in nats per sample (``mle · dt``)."""
        return self.mle * self.dt

    def to_dataset(self) -> xr.Dataset:
        """Curve over ``horizon`` with every scalar in the attributes (netCDF-safe types)."""
        if self.method in ("rosenstein", "kantz"):
            name, long, units = "log_divergence", "mean natural-log divergence <ln d(k)>", "1"
            hlong = "divergence horizon in samples"
        else:
            name, long, units = "running_mle", "running Lyapunov estimate (nats per sample)", "1"
            hlong = "evolution index in samples"
        attrs = {
            "method": self.method,
            "mle": self.mle,
            "mle_units": "per unit of dt (natural log)",
            "mle_bits_per_sample": self.mle_bits_per_sample,
            "ci_low": self.ci[0],
            "ci_high": self.ci[1],
            "ci_method": self.ci_method,
            "dt": self.dt,
            "embedding_dim": self.embedding_dim,
            "lag": self.lag,
            "theiler_window": self.theiler_window,
            "lag_rule": self.lag_rule,
            "dim_rule": self.dim_rule,
            "fit_start": self.fit_range[0],
            "fit_stop": self.fit_range[1],
            "fit_found": int(self.fit_found),
            "r2": self.r2,
            "n_points": self.n_points,
            "n_samples": self.n_samples,
            "subsampled": int(self.subsampled),
        }
        for key, value in self.params.items():
            attrs[f"param_{key}"] = value if not isinstance(value, bool) else int(value)
        return xr.Dataset(
            {name: ("horizon", self.curve, {"units": units, "long_name": long})},
            coords={"horizon": ("horizon", self.horizon, {"units": "1", "long_name": hlong})},
            attrs=attrs,
        )
