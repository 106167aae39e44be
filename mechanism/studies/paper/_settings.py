"""How much of the paper study is run: :class:`StudySettings`."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from ._published import PAPER_SAMPLES


@dataclass(frozen=True, kw_only=True)
class StudySettings:
    """How much of the study is run: the paper's settings or documented reductions.

    Parameters
    ----------
    revolutions
        Crank revolutions simulated per response point (peaks need ≥ 3; the paper's
        simulation length is not printed: docs/paper-model.md, “Simulation length”).
    discard_revolutions
        Transient dropped before metrics and chaos analysis (revolutions).
    samples_per_revolution
        Output samples per crank revolution of the response points; the output step is
        T / this. The paper: 10 000.
    flexible_rods
        Rods 3 and 4 as ANCF beams (the paper, and the default everywhere) or rigid bars.
    wear_updates, wear_cycles_per_update, wear_max_depth_increment, wear_settle_revolutions
        Cycle extrapolation of :func:`mechanism.predict_wear` (docs/paper-model.md §6): the
        number of profile updates and the crank cycles per update set the amount of wear
        (the cycle count is stated in the report); the cap on one update's depth increment
        (fraction of the clearance) is a safety limit only; the revolutions settled before
        the measured cycle. Each speed of the speed table is worn at its own speed. The
        paper's settings and the quick ones wear the same 10 000 cycles, in 5 updates and
        in 1.
    elements
        ANCF elements per rod for the convergence table (paper: 4 … 24).
    convergence_revolutions
        Revolutions per run of the convergence table.
    chaos_revolutions
        Revolutions analysed per state (before, after wear) after the transient, ≥ 200:
        fewer drive periods cannot separate periodic, quasi-periodic and chaotic motion.
    chaos_samples_per_revolution
        Output samples per revolution of the analysed series; the integration step stays
        the paper's T/10000.
    exponent_revolutions
        Revolutions of :func:`mechanism.lyapunov_exponent` per state, on the model of the
        analysed series.
    rigid_rod_exponent
        With flexible rods, also the exponent of each state with rigid rods (a check that
        the answer does not hang on the rod model; the quick settings leave it out).
    orbit_speeds, orbit_revolutions, orbit_discard_revolutions, orbit_flexible_rods
        The orbit diagrams over crank speed before and after wear
        (:func:`mechanism.bifurcation`): speeds (rpm), revolutions per speed, transient,
        and whether the rods are flexible there.
    n_surrogates
        Surrogates per series of the verdict's surrogate test (at least 19: with fewer
        the test cannot reach its 5 % level).
    max_samples
        At most this many samples of each analysed series (plain stride); None: all.
    """

    revolutions: float = 11.0
    discard_revolutions: float = 1.0
    samples_per_revolution: int = PAPER_SAMPLES
    flexible_rods: bool = True
    wear_updates: int = 5
    wear_cycles_per_update: float = 2.0e3
    wear_max_depth_increment: float = 1.0
    wear_settle_revolutions: float = 2.0
    elements: tuple[int, ...] = (4, 8, 12, 16, 20, 24)
    convergence_revolutions: float = 1.0
    chaos_revolutions: float = 200.0
    chaos_samples_per_revolution: int = 2000
    exponent_revolutions: float = 100.0
    rigid_rod_exponent: bool = True
    orbit_speeds: tuple[float, ...] = tuple(float(v) for v in range(30, 151, 15))
    orbit_revolutions: float = 30.0
    orbit_discard_revolutions: float = 15.0
    orbit_flexible_rods: bool = True
    n_surrogates: int = 19
    max_samples: int | None = 400_000

    def __post_init__(self) -> None:
        def number(name: str, low: float, *, integer: bool = False) -> None:
            v = getattr(self, name)
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            if not ok or v < low or (integer and int(v) != v):
                kind = "an integer" if integer else "a number"
                raise ValueError(f"StudySettings.{name} must be {kind} >= {low:g}; got {v!r}.")

        number("revolutions", 1.0)
        number("discard_revolutions", 0.0)
        number("samples_per_revolution", 100, integer=True)
        number("wear_updates", 1, integer=True)
        number("wear_cycles_per_update", 0.0)
        number("wear_settle_revolutions", 0.0)
        number("wear_max_depth_increment", 1e-6)
        number("convergence_revolutions", 0.01)
        number("chaos_revolutions", 1.0)
        number("chaos_samples_per_revolution", 100, integer=True)
        number("exponent_revolutions", 1.0)
        number("orbit_revolutions", 1.0)
        number("orbit_discard_revolutions", 0.0)
        # the surrogate test's rank test needs 1/alpha - 1 surrogates to reach alpha = 0.05
        number("n_surrogates", 19, integer=True)
        if self.wear_max_depth_increment > 1.0:
            raise ValueError(
                "StudySettings.wear_max_depth_increment must be in (0, 1] (a fraction of the "
                f"clearance); got {self.wear_max_depth_increment:g}."
            )
        if self.revolutions <= self.discard_revolutions:
            raise ValueError(
                f"StudySettings.revolutions ({self.revolutions:g}) must exceed "
                f"discard_revolutions ({self.discard_revolutions:g})."
            )
        if self.orbit_revolutions <= self.orbit_discard_revolutions:
            raise ValueError(
                f"StudySettings.orbit_revolutions ({self.orbit_revolutions:g}) must exceed "
                f"orbit_discard_revolutions ({self.orbit_discard_revolutions:g})."
            )
        if self.max_samples is not None:
            number("max_samples", 200, integer=True)
        elements = tuple(int(e) for e in self.elements)
        if not elements or any(e < 1 for e in elements):
            raise ValueError(f"StudySettings.elements must be integers >= 1; got {self.elements}.")
        speeds = tuple(float(v) for v in self.orbit_speeds)
        if any(not math.isfinite(v) or v <= 0 for v in speeds):
            raise ValueError(
                f"StudySettings.orbit_speeds must be positive speeds in rpm; got {speeds}."
            )
        object.__setattr__(self, "elements", elements)
        object.__setattr__(self, "orbit_speeds", speeds)
        object.__setattr__(self, "flexible_rods", bool(self.flexible_rods))
        object.__setattr__(self, "orbit_flexible_rods", bool(self.orbit_flexible_rods))
        object.__setattr__(self, "rigid_rod_exponent", bool(self.rigid_rod_exponent))

    @classmethod
    def paper(cls) -> StudySettings:
        """The paper's settings (T/10000, flexible rods, 4 … 24 elements, 200 revolutions)."""
        return cls()

    @classmethod
    def quick(cls) -> StudySettings:
        """The documented reductions of ``mechanism paper --quick`` (``docs/paper-study.md``).

        Flexible rods and the 200 analysed revolutions per state are kept; the response
        points run 4 revolutions with output T/2500, the wear 1 update of 10 000 cycles,
        the convergence table 3 meshes over the first impact, the analysed series at most
        100 000 samples, the exponent from the equations 10 revolutions (flexible rods
        only), and the orbit diagrams rigid rods at 5 speeds.
        """
        return cls(
            revolutions=4.0,
            discard_revolutions=1.0,
            samples_per_revolution=2500,
            flexible_rods=True,
            wear_updates=1,
            wear_cycles_per_update=1.0e4,
            wear_max_depth_increment=1.0,
            wear_settle_revolutions=1.0,
            elements=(4, 8, 16),
            convergence_revolutions=0.15,
            chaos_revolutions=200.0,
            chaos_samples_per_revolution=1000,
            exponent_revolutions=10.0,
            rigid_rod_exponent=False,
            orbit_speeds=(30.0, 60.0, 90.0, 120.0, 150.0),
            orbit_revolutions=30.0,
            orbit_discard_revolutions=10.0,
            orbit_flexible_rods=False,
            n_surrogates=19,
            max_samples=100_000,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready form (listed in the report's parameters)."""
        d = dataclasses.asdict(self)
        d["elements"] = list(self.elements)
        d["orbit_speeds"] = list(self.orbit_speeds)
        return d
