"""The paper's published tables and claims, and the fixed design of the study (its
clearances, speeds, integration step and wear paths), all from Jia et al. (2025)."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

_DATA = Path(__file__).parent / "data" / "paper_tables.toml"

#: Response columns of the paper's tables, in print order.
COLUMNS: tuple[str, ...] = (
    "displacement_error",
    "speed_error",
    "contact_force",
    "embedding_depth",
    "rod3_strain",
    "rod4_strain",
    "driving_torque",
)
LABELS: dict[str, str] = {
    "displacement_error": "displacement error (mm)",
    "speed_error": "speed error (m/s)",
    "contact_force": "contact force (kN)",
    "embedding_depth": "embedding depth (mm)",
    "rod3_strain": "strain of rod 3 (µε)",
    "rod4_strain": "strain of rod 4 (µε)",
    "driving_torque": "driving torque (N m)",
}
# paper column -> (sweep metric, factor from SI to the paper's unit)
FROM_SWEEP: dict[str, tuple[str, float]] = {
    "displacement_error": ("max_displacement_error", 1e3),
    "speed_error": ("max_speed_error", 1.0),
    "contact_force": ("peak_contact_force", 1e-3),
    "embedding_depth": ("max_penetration", 1e3),
    "driving_torque": ("driving_torque_extreme", 1.0),
}
RODS = {"rod3_strain": "rod3", "rod4_strain": "rod4"}
MICRO = 1e6
CLEARANCES = (1e-4, 2e-4, 5e-4)
SPEEDS = (30, 90, 150)
#: the before-wear sweep's speeds: those of its tables (clearance at 150 and at 90 rpm, the
#: before-wear row at 150); a 30 rpm point costs five 150 rpm ones and no table used it
BEFORE_SPEEDS = (90, 150)
DEFAULT_CLEARANCE = 2e-4
PAPER_SAMPLES = 10_000  # the paper's step is T/10000 (its parameter table)
#: Largest integration step of every run of the study (s): the paper's T/10000 at 150 rpm,
#: at every speed. The flexible rods run the fixed-step generalized-α at this step; T/10000
#: at 30 rpm (2e-4 s) diverged on the profile worn at 30 rpm (penetration far beyond the
#: clearance, singular constraint Jacobian after 0.99 s) where 1e-4 s ran, and the sweeps'
#: output grid (T/2500 in --quick) must not become the step (docs/paper-model.md,
#: "Integration step").
STEP = 0.4 / PAPER_SAMPLES
SPR = "samples_per_revolution"
#: crank period at 150 rpm, the speed of the chaos analysis (s)
PERIOD_150 = 60.0 / 150.0
#: what the chaos runs record: the drive's phase and the journal centre (no full state)
CHAOS_VARIABLES = ("crank_angle", "eccentricity_x", "eccentricity_y")
NOT_AVAILABLE = "NOT AVAILABLE IN THIS VERSION"

#: The wear paths of the wear-life answer, (crank speed in rpm, radial clearance in m): the
#: speed table's three speeds at the default clearance, and the clearance table's three
#: clearances at 150 rpm (150 rpm with 0.2 mm is one path, shared by both claims).
WEAR_PATHS: tuple[tuple[float, float], ...] = (
    (30.0, DEFAULT_CLEARANCE),
    (90.0, DEFAULT_CLEARANCE),
    (150.0, DEFAULT_CLEARANCE),
    (150.0, 1e-4),
    (150.0, 5e-4),
)


@dataclass(frozen=True)
class TransitionClaim:
    """One of the paper's conclusions on how the motion changes with wear.

    ``key`` names the parameter the claim varies (``"clearance"`` or ``"speed"``),
    ``quote`` is the paper's wording, ``short`` a few words for the report's table and
    ``paths`` the wear paths (:data:`WEAR_PATHS`) it is judged on, in increasing parameter.
    ``threshold`` is the speed (rpm) below which the claim says the motion is stable.
    """

    key: str
    quote: str
    short: str
    paths: tuple[tuple[float, float], ...]
    threshold: float | None = None


#: The paper's conclusions on the transition to chaos, as the study states them.
TRANSITION_CLAIMS: tuple[TransitionClaim, ...] = (
    TransitionClaim(
        key="clearance",
        quote="enlarged clearances accelerate the transition from periodic to chaotic "
        "motion due to intensified wear",
        short="larger clearances turn chaotic sooner",
        paths=((150.0, 1e-4), (150.0, DEFAULT_CLEARANCE), (150.0, 5e-4)),
    ),
    TransitionClaim(
        key="speed",
        quote="rotational speeds below 90 rpm effectively suppressing wear severity and "
        "stabilizing motion",
        short="below 90 rpm less wear and stable motion",
        paths=((30.0, DEFAULT_CLEARANCE), (90.0, DEFAULT_CLEARANCE), (150.0, DEFAULT_CLEARANCE)),
        threshold=90.0,
    ),
)


# --------------------------------------------------------------------------- the paper's data


def paper_tables() -> dict[str, pd.DataFrame]:
    """The published tables of the seed paper as DataFrames, in the paper's units.

    Keys: ``"convergence"`` (index ``elements``; rod strains in µε), ``"wear"`` (rows
    "before wear", "after wear"), ``"clearance"`` (rows "0.1 mm", "0.2 mm", "0.5 mm"),
    ``"speed"`` (rows "30 rpm", "90 rpm", "150 rpm") — the response tables with the columns
    of ``COLUMNS`` (mm, m/s, kN, mm, µε, µε, N m) — and ``"chaos"`` (index
    ``(variable, state)``; ``lag`` in samples of T/10000, ``embedding_dim``,
    ``mle_wolf_bits`` in bits per sample). Read from
    ``mechanism/studies/paper/data/paper_tables.toml``.

    Examples
    --------
    >>> import mechanism
    >>> t = mechanism.paper_tables()
    >>> float(t["wear"].loc["after wear", "contact_force"])
    23.33
    >>> int(t["chaos"].loc[("Y", "after wear"), "lag"])
    12
    """
    with _DATA.open("rb") as fh:
        raw = tomllib.load(fh)
    out: dict[str, pd.DataFrame] = {}
    conv = raw["convergence"]
    out["convergence"] = pd.DataFrame(
        {"rod3_strain": conv["rod3_strain"], "rod4_strain": conv["rod4_strain"]},
        index=pd.Index(conv["elements"], name="elements"),
    )
    for name, index_name in (("wear", "state"), ("clearance", "clearance"), ("speed", "speed")):
        table = raw[name]
        out[name] = pd.DataFrame(
            [table[row] for row in table["rows"]],
            index=pd.Index(table["rows"], name=index_name),
            columns=table["columns"],
        )
    chaos = raw["chaos"]
    out["chaos"] = pd.DataFrame(
        {k: chaos[k] for k in ("lag", "embedding_dim", "mle_wolf_bits")},
        index=pd.MultiIndex.from_arrays(
            [chaos["variables"], chaos["states"]], names=["variable", "state"]
        ),
    )
    return out


def paper_claims() -> dict[str, dict[str, str]]:
    """The paper's claim about the motion of each state (before, after wear).

    ``{state: {"motion": "chaotic" | "not chaotic", "text": one line}}``, read from the
    ``[claims]`` table of ``mechanism/studies/paper/data/paper_tables.toml``.
    """
    with _DATA.open("rb") as fh:
        raw = tomllib.load(fh)["claims"]
    return {
        state: {"motion": str(motion), "text": str(text)}
        for state, motion, text in zip(raw["states"], raw["motion"], raw["text"], strict=True)
    }


def paper_wear_zones() -> list[tuple[float, float]]:
    """The paper's concentrated wear arcs in degrees: [(75, 132), (252, 310)]."""
    with _DATA.open("rb") as fh:
        zones = tomllib.load(fh)["wear"]["wear_zones_deg"]
    return [(float(a), float(b)) for a, b in zones]
