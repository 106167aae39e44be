"""Contact modes along a recorded orbit: free flight, impact, continuous contact."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: a contact shorter than this share of the drive period is an impact
IMPACT_SHARE = 0.01


@dataclass(frozen=True)
class ContactPhase:
    """One phase of a clearance joint along the orbit.

    Attributes
    ----------
    joint : str
        Clearance joint name.
    mode : str
        ``"free flight"``, ``"impact"`` (a contact shorter than 1 % of the drive period)
        or ``"continuous contact"``.
    start : float
        Time (s, from the section) the phase starts, to the recording's sample spacing; a
        phase that runs through the section starts at 0.
    """

    joint: str
    mode: str
    start: float


def contact_phases(
    t: np.ndarray,
    contact: np.ndarray,
    events: np.ndarray,
    joints: tuple[str, ...],
    drive_period: float,
) -> tuple[ContactPhase, ...]:
    """Phases of every clearance joint from its contact flags at the samples ``t``.

    ``contact`` (samples, joints) holds the flags, ``events`` the count of contact
    entries since the start at each sample: an entry between two separated samples is
    an impact the samples missed (with several joints it is given to each joint separated
    at both samples). Phases are in time order per joint, joints one after the other.
    """
    phases: list[ContactPhase] = []
    short = IMPACT_SHARE * drive_period
    for j, name in enumerate(joints):
        flags = contact[:, j] != 0
        # contact episodes as [first sample in contact, first sample separated after it)
        episodes: list[tuple[float, float]] = []
        i = 0
        while i < t.size:
            if flags[i]:
                end = i
                while end < t.size and flags[end]:
                    end += 1
                episodes.append((t[i], t[min(end, t.size - 1)]))
                i = end
            else:
                if i > 0 and not flags[i - 1] and events[i] > events[i - 1]:
                    episodes.append((t[i - 1], t[i - 1]))
                i += 1
        episodes.sort()
        if not flags[0]:
            phases.append(ContactPhase(name, "free flight", float(t[0])))
        for start, stop in episodes:
            mode = "impact" if stop - start < short else "continuous contact"
            phases.append(ContactPhase(name, mode, float(start)))
            if stop < t[-1] or not flags[-1]:
                phases.append(ContactPhase(name, "free flight", float(stop)))
        phases = _merge(phases)
    return tuple(phases)


def _merge(phases: list[ContactPhase]) -> list[ContactPhase]:
    """Consecutive free-flight phases of one joint as one."""
    out: list[ContactPhase] = []
    for p in phases:
        if out and out[-1].joint == p.joint and out[-1].mode == p.mode == "free flight":
            continue
        out.append(p)
    return out
