"""An oil film at the clearance joint turns the chaotic journal motion into a regular one.

The rigid paper scene at 150 rpm with a dry clearance joint at C is chaotic: the largest
exponent from the equations of motion has its 95 % interval above 0 and the journal's
stroboscopic points are scattered over a fifth of the clearance. With an SAE-10-like oil
in the same joint (0.04 Pa s, the default bearing length and film breakdown) the journal
hugs the bearing on a squeeze film: its stroboscopic points gather within a few tenths
of a percent of the clearance, the exponent is not positive and the motion verdict is
periodic with period 1 — the qualitative result of Flores, Ambrósio, Claro, Lankarani &
Koshy, Mech. Mach. Theory 41 (2006) 247, reproduced with the library's own tools
(docs/contact-and-wear.md, "Effect on the journal orbit").

Both runs are chaotic or transient, so the default test asserts only what held from
starts whose crank angles differ by up to 2e-12 of a revolution (measured in each
docstring); the slow variant re-runs it from those starts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

import chaoskit
import mechanism

#: oil viscosity (Pa s): the film damps the journal's flights without lifting it off the
#: wall, so the explicit steps stay cheap (a load-carrying 1 Pa s film costs ~100x)
VISCOSITY = 0.04
#: output samples per drive period
PER_PERIOD = 200
#: simulated drive periods for the strobe and the verdict, and the ones dropped before
REVOLUTIONS, STROBE_FROM, VERDICT_FROM = 30, 10, 5
#: (simulated, discarded) drive periods of the exponents
DRY_EXPONENT, WET_EXPONENT = (24, 4), (30, 5)
#: bound on the lubricated journal's strobe spread, as a fraction of the clearance
WET_SPREAD = 0.02
JOURNAL = ["eccentricity_x", "eccentricity_y"]
SHIFTS = (-2e-12, -1e-12, 1e-12, 2e-12)


@dataclass(frozen=True)
class Motion:
    """The journal of joint C: strobe spread / clearance, exponent and motion verdict."""

    spread: float
    exponent: mechanism.SceneLyapunov
    verdict: chaoskit.MotionVerdict | None


def motion(*, lubricated: bool, shift: float = 0.0, verdict: bool = False) -> Motion:
    """The rigid paper scene at 150 rpm, dry or oiled at C, the crank turned by ``shift``
    of a revolution at the start; the motion verdict (10 to 20 s of CPU) if ``verdict``."""
    changes: dict[str, object] = {
        "effects.flexibility": False,
        "drive.initial_angle": 2.0 * math.pi * shift,
    }
    if lubricated:
        changes["joints.C.lubrication"] = {"viscosity": VISCOSITY}
    scene = mechanism.load_scene("paper").replace(changes)
    assert scene.drive.speed_rpm == 150.0
    clearance = scene.joints["C"].clearance
    period = 60.0 / scene.drive.speed_rpm
    revolutions, discard = WET_EXPONENT if lubricated else DRY_EXPONENT
    exponent = mechanism.lyapunov_exponent(scene, revolutions=revolutions, discard=discard)

    traj = mechanism.simulate(scene, revolutions=REVOLUTIONS, output_step=period / PER_PERIOD)
    journal = traj[[*JOURNAL, "crank_angle"]].isel(joint=0, drop=True)
    strobe = journal.isel(time=slice(STROBE_FROM * PER_PERIOD, None, PER_PERIOD))
    # the samples at whole drive periods: the crank back at its starting angle
    turns = (strobe.crank_angle.values - 2.0 * math.pi * shift) / (2.0 * math.pi)
    np.testing.assert_allclose(turns, np.round(turns), atol=1e-9)
    x, y = strobe.eccentricity_x.values, strobe.eccentricity_y.values
    spread = float(np.hypot(x - x.mean(), y - y.mean()).max()) / clearance

    if not verdict:
        return Motion(spread, exponent, None)
    kept = journal.isel(time=slice(VERDICT_FROM * PER_PERIOD, None))
    label = chaoskit.classify_motion(
        kept, variables=JOURNAL, phase_variable="crank_angle", exponent=exponent, rng=0
    )
    return Motion(spread, exponent, label)


def check_dry_chaotic_and_wet_regular(shift: float, *, verdict: bool = False) -> None:
    """The dry joint's motion is chaotic, the oiled one's regular (with the motion
    verdicts if ``verdict``)."""
    dry = motion(lubricated=False, shift=shift, verdict=verdict)
    wet = motion(lubricated=True, shift=shift, verdict=verdict)
    # dry: chaotic by the equations, a scattered strobe
    assert dry.exponent.ci[0] > 0.0
    assert dry.spread > 0.1
    # oiled: a tight strobe, no positive exponent, a period-1 verdict
    assert wet.spread < WET_SPREAD
    assert wet.exponent.ci[0] <= 0.0
    assert wet.exponent.exponent < 0.0
    assert wet.exponent.ci[1] < dry.exponent.ci[0]  # the two intervals are apart
    if verdict:
        assert dry.verdict.label == "chaotic"
        assert (wet.verdict.label, wet.verdict.period) == ("periodic", 1)


@pytest.mark.slow  # compiles the oiled scene's run and tangent kernels: about 90 s fresh
def test_oil_film_makes_the_chaotic_journal_orbit_regular() -> None:
    """Measured from starts shifted by 0, ±1e-12 and ±2e-12 of a revolution. Dry: the
    exponent over revolutions 5–24 6.65 – 10.8 s⁻¹, its interval from 3.28 – 6.34 s⁻¹
    (bound 0); strobe spread over revolutions 11–30 0.21 – 0.29 of the clearance (bound
    0.1). Oiled (0.04 Pa s): strobe spread 0.0024 – 0.0043 (bound 0.02); exponent over
    revolutions 6–30 −0.78 to −0.22 s⁻¹ (bound 0), its interval's lower end −1.18 to
    −0.91 s⁻¹ (bound 0), its upper end −0.43 to 0.64 s⁻¹, below the dry interval's lower
    end. The motion verdicts are in the slow test."""
    check_dry_chaotic_and_wet_regular(0.0)


@pytest.mark.slow
@pytest.mark.parametrize("shift", (0.0, *SHIFTS))
def test_oil_film_makes_the_journal_orbit_regular_by_the_verdict(shift: float) -> None:
    """The default test's assertions from starts shifted by ``shift`` of a revolution, and
    the motion verdicts of the journal (revolutions 6–30, the equations' exponent as
    evidence): dry chaotic, oiled periodic with period 1."""
    check_dry_chaotic_and_wet_regular(shift, verdict=True)
