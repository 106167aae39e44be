"""The clearance-table rows of a translational clearance joint: one row per slider corner.

A ``clearance_prismatic`` joint becomes four rows of the clearance table, one per corner of
the slider's rectangle, each against the guide surface on its side (``CI_KIND =
CONTACT_GUIDE``; geometry in ``mechanism.core.joints._guide_kernels``). The rows share the
joint's contact and friction settings and each has its own impact-velocity latch, so the
integrators, the contact bookkeeping and the records treat a corner like a journal. With
clearance off (``effects.clearance = false`` or the ideal companion mechanism) the joint is
an ideal prismatic joint instead, see :func:`mechanism.core.model._tables.joint_tables`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from mechanism.core.contact import ContactParameters
from mechanism.core.scene import ClearancePrismatic

from . import _kernels as model_kernels

__all__ = ["CORNERS", "CornerRow", "corner_rows", "guide_frame"]

#: corner names in row order: (side, end) with side +1 on the left of the guide axis
#: ("upper") and end +1 at the front along the axis
CORNERS = (("upper_front", 1, 1), ("upper_rear", 1, -1), ("lower_front", -1, 1),
           ("lower_rear", -1, -1))  # fmt: skip


@dataclass(frozen=True)
class CornerRow:
    """One corner's rows of the clearance tables and its name (``JOINT.upper_front``...)."""

    name: str
    local: tuple[float, float]  # the corner in the slider body's frame, m
    row_i: list[int]  # [guide point, corner point, law, friction, CONTACT_GUIDE]
    row_f: list[float]
    worn_i: list[int]
    worn_f: list[float]


def contact_row(
    p: ContactParameters, *, outer: float, inner: float, clearance: float
) -> list[float]:
    """A ``CF_*`` row of a clearance contact: its geometry (the outer surface's radius or
    distance, the inner body's radius, the clearance, m) and its contact and friction
    laws; the other columns are 0."""
    row_f = [0.0] * model_kernels.CF_COLUMNS
    row_f[model_kernels.CF_RB] = outer
    row_f[model_kernels.CF_RJ] = inner
    row_f[model_kernels.CF_C] = clearance
    row_f[model_kernels.CF_K] = p.stiffness
    row_f[model_kernels.CF_EXP] = p.exponent
    row_f[model_kernels.CF_CE] = p.restitution
    row_f[model_kernels.CF_MU] = p.friction_coefficient
    row_f[model_kernels.CF_V0] = p.v0
    row_f[model_kernels.CF_V1] = p.v1
    row_f[model_kernels.CF_FLOOR] = p.impact_velocity_floor
    return row_f


def guide_frame(joint: ClearancePrismatic) -> tuple[float, float, float, float]:
    """(ux, uy, nx, ny): the unit guide axis and its left normal in the guide body's frame."""
    ux, uy = (float(c) for c in joint.axis)
    norm = math.hypot(ux, uy)
    if not norm > 0.0:
        raise ValueError(f"axis must be a non-zero vector; got {joint.axis!r}.")
    ux, uy = ux / norm, uy / norm
    return ux, uy, -uy, ux


def corner_rows(
    name: str,
    joint: ClearancePrismatic,
    p: ContactParameters,
    *,
    slider_point: tuple[float, float],
    relative_angle: float,
    friction_code: int,
    guide_point: int,
    add_point: Callable[[tuple[float, float]], int],
) -> list[CornerRow]:
    """The four corner rows of ``joint`` (named ``name``) with contact settings ``p``.

    ``slider_point`` is the slider centre in the slider body's frame and ``relative_angle``
    the slider body's angle minus the guide body's in the scene's pose, in which the
    rectangle is aligned with the guide; ``guide_point`` is the guide point's row of the
    point table and ``add_point`` adds a point of the slider body (its local coordinates)
    to that table and returns its row.
    """
    ux, uy, nx, ny = guide_frame(joint)
    # the guide's axes seen from the slider body in the scene's pose: turned by −rel
    c, s = math.cos(relative_angle), math.sin(relative_angle)
    ax, ay = c * ux + s * uy, -s * ux + c * uy
    half_l, half_w = 0.5 * joint.slider_length, 0.5 * joint.slider_width
    rows = []
    for corner, side, end in CORNERS:
        local = (
            slider_point[0] + end * half_l * ax - side * half_w * ay,
            slider_point[1] + end * half_l * ay + side * half_w * ax,
        )
        # the surface's distance from the centre line
        row_f = contact_row(p, outer=half_w + joint.clearance, inner=0.0, clearance=joint.clearance)
        row_f[model_kernels.CF_NX] = side * nx
        row_f[model_kernels.CF_NY] = side * ny
        row_i = [
            guide_point,
            add_point(local),
            p.law_code,
            friction_code,
            model_kernels.CONTACT_GUIDE,
        ]
        rows.append(
            CornerRow(
                name=f"{name}.{corner}",
                local=local,
                row_i=row_i,
                row_f=row_f,
                worn_i=[0] * model_kernels.CW_COLUMNS,  # never worn: the unworn contact path
                worn_f=[p.effective_modulus, 1.0],
            )
        )
    return rows
