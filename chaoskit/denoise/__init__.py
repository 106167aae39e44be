"""Noise reduction of a measured series, as an explicit, optional step.

:func:`local_projective_denoise` moves each delay vector towards the local surface the
dynamics lives on (Grassberger, Hegger, Kantz, Schaffrath & Schreiber 1993, the method of
TISEAN's ``ghkss``). No estimator applies it by itself: call it, then pass
``result.cleaned`` on.
"""

from __future__ import annotations

from ._local import MAX_ITERATIONS as MAX_ITERATIONS  # the command line's bound
from ._local import local_projective_denoise
from ._result import DenoiseResult

__all__ = ["DenoiseResult", "local_projective_denoise"]
