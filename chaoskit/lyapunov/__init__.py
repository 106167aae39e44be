"""Largest Lyapunov exponent from a scalar series (Rosenstein 1993, Kantz 1994, Wolf 1985)."""

from __future__ import annotations

from ._kantz import KantzResult, lyapunov_kantz
from ._result import LyapunovResult
from ._rosenstein import lyapunov_rosenstein
from ._spectrum import LyapunovSpectrumResult, lyapunov_spectrum
from ._wolf import lyapunov_wolf

__all__ = [
    "KantzResult",
    "LyapunovResult",
    "LyapunovSpectrumResult",
    "lyapunov_kantz",
    "lyapunov_rosenstein",
    "lyapunov_spectrum",
    "lyapunov_wolf",
]
