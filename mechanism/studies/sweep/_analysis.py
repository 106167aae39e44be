"""What each grid point of a sweep analyses: :class:`Analysis`."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True, kw_only=True)
class Analysis:
    """What each grid point analyses after its simulation, and over which samples.

    Parameters
    ----------
    variables
        Trajectory variables handed to :func:`chaoskit.analyze` (one row each in the
        result's ``variable`` dimension), each ``NAME`` or ``NAME[DIM=VALUE,...]`` as in
        ``chaoskit analyze`` (e.g. ``"eccentricity_x[joint=C]"``). With two or more, the
        point's motion is classified as a whole (:func:`chaoskit.classify_motion`) and the
        result gets one ``motion_label``, ``motion_confidence``, ``motion_period``, ... per
        point beside the rows. Default: the journal eccentricity ``x`` and ``y`` of the
        clearance joint, the paper's "X and Y direction" series. Empty: response metrics
        only.
    joint
        Clearance joint for the variables with a ``joint`` dimension whose name selects none;
        default the first.
    discard_revolutions
        Crank revolutions dropped from the start before metrics and analysis (transient), ≥ 0.
        The paper evaluates after the first revolution.
    decimation
        Keep every ``decimation``-th sample of the analysed series (≥ 1).
    max_samples
        Upper bound on the analysed series length; the stride grows to respect it (None: no
        bound). The estimators cost grows faster than linearly with the length, and the
        default output step gives 10 000 samples per revolution.
    options
        Extra keyword arguments for :func:`chaoskit.analyze` (e.g. ``n_surrogates``; with
        several variables, those of :func:`chaoskit.classify_motion`); must be
        JSON-serialisable, since they are stored in the sweep manifest. By default the sweep
        passes ``phase_variable="crank_angle"`` (the stroboscopic evidence of the verdict).
    seed
        Base seed of the random parts of the analysis (surrogates, the 0–1 test): each point
        gets ``rng`` derived from ``seed`` and its point name, so results depend neither on
        the backend nor on the order in which points run.

    Examples
    --------
    >>> import mechanism
    >>> mechanism.Analysis(variables=("eccentricity_y",), discard_revolutions=2.0)
    Analysis(variables=('eccentricity_y',), joint=None, discard_revolutions=2.0, \
decimation=1, max_samples=20000, options={}, seed=0)
    """

    variables: tuple[str, ...] = ("eccentricity_x", "eccentricity_y")
    joint: str | None = None
    discard_revolutions: float = 1.0
    decimation: int = 1
    max_samples: int | None = 20_000
    options: Mapping[str, Any] = field(default_factory=dict)
    seed: int = 0

    def __post_init__(self) -> None:
        if isinstance(self.variables, str):
            object.__setattr__(self, "variables", (self.variables,))
        object.__setattr__(self, "variables", tuple(str(v) for v in self.variables))
        if len(set(self.variables)) != len(self.variables):
            raise ValueError(f"Analysis.variables has duplicates: {self.variables}.")
        d = self.discard_revolutions
        if isinstance(d, bool) or not isinstance(d, (int, float)) or not (0 <= d < math.inf):
            raise ValueError(
                f"Analysis.discard_revolutions must be a finite number >= 0; got {d!r}."
            )
        dec = self.decimation
        if isinstance(dec, bool) or not isinstance(dec, int) or dec < 1:
            raise ValueError(f"Analysis.decimation must be an integer >= 1; got {dec!r}.")
        m = self.max_samples
        if m is not None and (isinstance(m, bool) or not isinstance(m, int) or m < 16):
            raise ValueError(f"Analysis.max_samples must be None or an integer >= 16; got {m!r}.")
        try:
            json.dumps(dict(self.options))
        except TypeError as exc:
            raise ValueError(f"Analysis.options must be JSON-serialisable: {exc}.") from None
        object.__setattr__(self, "options", dict(self.options))
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ValueError(f"Analysis.seed must be an integer >= 0; got {self.seed!r}.")

    def __hash__(self) -> int:  # options is a dict; hash the stored (JSON) form instead
        return hash(json.dumps(self.to_dict(), sort_keys=True))

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready form (stored in the sweep manifest and the result's attrs)."""
        return {
            "variables": list(self.variables),
            "joint": self.joint,
            "discard_revolutions": float(self.discard_revolutions),
            "decimation": self.decimation,
            "max_samples": self.max_samples,
            "options": dict(self.options),
            "seed": self.seed,
        }
