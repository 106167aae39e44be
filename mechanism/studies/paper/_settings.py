"""How much of the paper study is run: :class:`StudySettings`."""

from __future__ import annotations

import dataclasses
import itertools
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
    wear_paths
        Run the wear paths of the wear-life answer (:func:`mechanism.wear_life` at 30, 90
        and 150 rpm with c = 0.2 mm and at 0.1, 0.2 and 0.5 mm with 150 rpm), judged
        against the paper's claims on the transition to chaos.
    wear_path_cycles, wear_path_checkpoints
        Crank cycles of wear of each path and its checkpoints (strictly increasing, in
        (0, cycles]); the unworn state is always analysed too.
    wear_path_averaged_revolutions
        Revolutions whose mean wear is the wear per cycle of a path's increments.
    wear_path_analysis_revolutions
        Revolutions analysed at each checkpoint (≥ 20 for a decided motion verdict).
    wear_path_lyapunov_revolutions, wear_path_lyapunov_discard
        Revolutions of the exponent from the equations at each checkpoint, and those left
        out of it.
    wear_path_flexible_rods
        Rods 3 and 4 of the wear paths as ANCF beams (at the study's step T/10000 at
        150 rpm) or rigid bars (the report says which). Rigid by default, also in the
        paper's settings: flexible paths cost about three times as much, over an hour of
        CPU in the paper's settings (the report states the estimate).
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
    wear_paths: bool = True
    wear_path_cycles: float = 20_000.0
    wear_path_checkpoints: tuple[float, ...] = (5_000.0, 10_000.0, 15_000.0, 20_000.0)
    wear_path_averaged_revolutions: int = 8
    wear_path_analysis_revolutions: int = 25
    wear_path_lyapunov_revolutions: float = 10.0
    wear_path_lyapunov_discard: float = 2.0
    # rigid even in the paper's settings: flexible paths would cost over an hour of CPU
    # (docs/paper-study.md, "Wear-life answer")
    wear_path_flexible_rods: bool = False

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
        self._check_wear_paths()
        object.__setattr__(self, "elements", elements)
        object.__setattr__(self, "orbit_speeds", speeds)
        object.__setattr__(self, "flexible_rods", bool(self.flexible_rods))
        object.__setattr__(self, "orbit_flexible_rods", bool(self.orbit_flexible_rods))
        object.__setattr__(self, "rigid_rod_exponent", bool(self.rigid_rod_exponent))
        object.__setattr__(self, "wear_paths", bool(self.wear_paths))
        object.__setattr__(self, "wear_path_flexible_rods", bool(self.wear_path_flexible_rods))

    def _check_wear_paths(self) -> None:
        """The wear paths' fields: WearLifeSettings and wear_life check them again, but a
        bad value must stop the study before its first run, not in a pool task."""
        cycles = self.wear_path_cycles
        if not isinstance(cycles, (int, float)) or not math.isfinite(cycles) or cycles <= 0:
            raise ValueError(
                f"StudySettings.wear_path_cycles must be a number > 0; got {cycles!r}."
            )
        try:
            points = tuple(float(n) for n in self.wear_path_checkpoints)
        except (TypeError, ValueError):
            points = ()
        if (
            not points
            or points[0] <= 0.0
            or points[-1] > cycles
            or any(b <= a for a, b in itertools.pairwise(points))
        ):
            raise ValueError(
                "StudySettings.wear_path_checkpoints must be strictly increasing cycle "
                f"counts in (0, wear_path_cycles] = (0, {cycles:g}]; got "
                f"{self.wear_path_checkpoints!r}."
            )
        object.__setattr__(self, "wear_path_checkpoints", points)
        averaged = self.wear_path_averaged_revolutions
        if isinstance(averaged, bool) or not isinstance(averaged, int) or not 1 <= averaged <= 1000:
            raise ValueError(
                "StudySettings.wear_path_averaged_revolutions must be an integer in "
                f"[1, 1000]; got {averaged!r}."
            )
        analysed = self.wear_path_analysis_revolutions
        if (
            isinstance(analysed, bool)
            or not isinstance(analysed, int)
            or not 4 <= analysed <= 10000
        ):
            raise ValueError(
                "StudySettings.wear_path_analysis_revolutions must be an integer in "
                f"[4, 10000]; got {analysed!r}."
            )
        revs, discard = self.wear_path_lyapunov_revolutions, self.wear_path_lyapunov_discard
        ok = all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in (revs, discard)
        )
        if not ok or revs <= 0 or not 0 <= discard < revs:
            raise ValueError(
                "StudySettings.wear_path_lyapunov_revolutions must be > 0 and "
                "wear_path_lyapunov_discard in [0, wear_path_lyapunov_revolutions); got "
                f"{revs!r} and {discard!r}."
            )

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
        only), the orbit diagrams rigid rods at 5 speeds, and the wear paths analysed
        unworn and after 10 000 cycles only, the wear per cycle averaged over 2
        revolutions.
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
            wear_paths=True,
            wear_path_cycles=10_000.0,
            wear_path_checkpoints=(10_000.0,),
            wear_path_averaged_revolutions=2,
            wear_path_analysis_revolutions=25,
            wear_path_lyapunov_revolutions=10.0,
            wear_path_lyapunov_discard=2.0,
            wear_path_flexible_rods=False,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready form (listed in the report's parameters)."""
        d = dataclasses.asdict(self)
        d["elements"] = list(self.elements)
        d["orbit_speeds"] = list(self.orbit_speeds)
        d["wear_path_checkpoints"] = list(self.wear_path_checkpoints)
        return d
