"""Generate the built-in paper scenes (paper.toml, paper-gc.toml, paper-clearance-b.toml).

The TOML files are the source of truth; this script only records how their coordinates
were computed: the positions of the six-bar of Jia et al. (Lubricants 2025, 13(3), 130)
at crank angle 0 from the link lengths, as in `docs/paper-model.md` §2 (the reconstructed
geometry, and the alternative plate reading). Run it from the repository root after
changing a length::

    python mechanism/core/scene/builtin/_make_paper.py

Conventions (§1–2): O = (0, 0), C = (Hx, Hy); the rocker end B above the O–C
line; D to the right of A→B (the far side of the crank pin); slider E on the vertical
guide x = Hx, below D. Every rigid body starts at angle 0, so its body-frame point
coordinates are the global offsets from its centre of mass at crank angle 0.
"""

from __future__ import annotations

import math
from pathlib import Path

HERE = Path(__file__).resolve().parent

# Paper table [S] (mm → m) and reconstruction defaults [I]/[A] of docs/paper-model.md.
L1 = 0.075  # crank O–A
L21, L22, L23 = 0.55514, 0.985, 0.47366  # plate sides as printed
L3 = 0.584  # rod 3 (rocker) C–B
L4 = 0.450  # rod 4 (connecting rod) D–E
HX, HY = 0.350, 0.060  # frame: rocker pivot C relative to O
M1, M2, M3, M4, M5 = 0.738, 21.483, 4.708, 3.663, 0.922  # kg
J1_ABOUT_O = 1.977e-3  # kg m2, printed 1.977e-9 "kg m3" ("Units of the printed inertias")
J2 = 1.349  # kg m2 about the plate centroid ("Units of the printed inertias")
J5 = 1.059e-3  # kg m2 (unused: the slider does not rotate)

# §2 table (mm) for a sanity check of the construction, rounded to 0.01 mm
TABLE = {
    "reconstructed": {"B": (38.41, 553.93), "D": (362.99, -376.05), "E": (350.00, -825.87)},
    "alternative": {"B": (38.41, 553.93), "D": (274.44, 964.60), "E": (350.00, 520.99)},
}


def _circles(p0, r0, p1, r1):
    """Both intersections of the circles (p0, r0) and (p1, r1)."""
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    d = math.hypot(dx, dy)
    a = (r0 * r0 - r1 * r1 + d * d) / (2 * d)
    h = math.sqrt(r0 * r0 - a * a)
    mx, my = p0[0] + a * dx / d, p0[1] + a * dy / d
    return (mx - h * dy / d, my + h * dx / d), (mx + h * dy / d, my - h * dx / d)


def _cross(o, p, q):
    return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])


def geometry(variant: str) -> dict[str, tuple[float, float]]:
    """Joint positions (m) at crank angle 0 for geometry "reconstructed" or "alternative"."""
    ab, bd, ad = (L21, L22, L23) if variant == "reconstructed" else (L21, L23, L22)
    o, a, c = (0.0, 0.0), (L1, 0.0), (HX, HY)
    b = next(p for p in _circles(a, ab, c, L3) if _cross(o, c, p) > 0)
    d = next(p for p in _circles(a, ad, b, bd) if _cross(a, b, p) < 0)
    e = (HX, d[1] - math.sqrt(L4 * L4 - (HX - d[0]) ** 2))
    points = {"O": o, "A": a, "B": b, "C": c, "D": d, "E": e}
    for name, (x, y) in TABLE[variant].items():
        px, py = points[name]
        assert abs(px * 1e3 - x) < 0.006 and abs(py * 1e3 - y) < 0.006, (variant, name)
    return points


def _v(p) -> str:
    return f"[{p[0]!r}, {p[1]!r}]"


def _sub(p, q):
    return (p[0] - q[0], p[1] - q[1])


def _clearance_joint(clearance_at: str) -> str:
    """The clearance joint's tables at C (bearing in the frame) or B (in the plate)."""
    return f"""[joints.{clearance_at}]
type = "clearance_revolute"
{
        'bearing = ["ground", "C"]      # bearing in the frame ("Clearance joint location")'
        if clearance_at == "C"
        else 'bearing = ["plate", "B"]       # bearing in the plate (the alternative location)'
    }
{
        'journal = ["rod3", "start"]    # pin at the frame end of rod 3 (node 1)'
        if clearance_at == "C"
        else 'journal = ["rod3", "end"]      # pin at the plate end of rod 3 (last node)'
    }
bearing_radius = 0.015          # R1 = 15 mm [S]
clearance = 0.0002              # c = 0.2 mm, the paper's default is not printed ("Clearance size")
length = 0.011                  # axial contact length L = 11 mm [S]
restitution = 0.9               # c_e [S]
initial_eccentricity = [0.0, 0.0]  # journal concentric at t = 0 (§7)
bearing_material = {{ youngs_modulus = 207.0e9, poisson_ratio = 0.3 }}  # E, nu [S]
journal_material = {{ youngs_modulus = 207.0e9, poisson_ratio = 0.3 }}

[joints.{clearance_at}.contact]
law = "lankarani-nikravesh"     # [L]
stiffness = "sum-of-radii"      # K = 1.31e10 N/m^1.5 reproduces the tables ("Contact stiffness")
exponent = 1.5

[joints.{clearance_at}.friction]
law = "ambrosio"                # modified Coulomb, dynamic correction c_d [L]
coefficient = 0.15              # c_f [S]
v0 = 1.0e-4                     # ("Friction band")
v1 = 2.0e-4                     # ("Friction band")

[joints.{clearance_at}.wear]
coefficient = 1.827e-13         # Archard k, m2/N (§6) [S]
regions = 360                   # 1 degree per region ("Worn surfaces")
surfaces = "both"               # bearing and journal wear ("Worn surfaces")
spread_over_contact_width = true
smoothing_regions = 5           # moving average before the curvature (§6)
"""


def _joints_b_c(clearance_at: str) -> tuple[str, str]:
    """The tables of joints B and C in file order: one ideal, one with clearance."""
    ideal_joint = (
        '[joints.C]\ntype = "revolute"\nbodies = ["ground", "rod3"]\npoints = ["C", "start"]\n'
        if clearance_at == "B"
        else '[joints.B]\ntype = "revolute"\nbodies = ["plate", "rod3"]\npoints = ["B", "end"]\n'
    )
    return (
        (ideal_joint, _clearance_joint(clearance_at))
        if clearance_at == "C"
        else (_clearance_joint(clearance_at), ideal_joint)
    )


def _header(*, name: str, variant: str, clearance_at: str, description: str, pts) -> str:
    """The file comment, top-level keys, effects and ground points."""
    variant_text = (
        "reconstructed geometry" if variant == "reconstructed" else "alternative plate reading"
    )
    o, c, guide = pts["O"], pts["C"], (HX, 0.0)
    return f"""# Built-in scene "{name}": the six-bar press mechanism of Jia, Meng, Jiang, Kang,
# "Wear Prediction and Chaos Identification of Rigid Flexible Coupling Multi-Link
# Mechanisms with Clearance", Lubricants 2025, 13(3), 130, as reconstructed in
# docs/paper-model.md: {variant_text} (§2), clearance at {clearance_at}.
# Tags: [S] stated in the paper, [I] inferred, [A] assumed; quoted names are entries of
# "Reconstruction choices" in docs/paper-model.md.
# Coordinates are those of §2 at crank angle 0, computed by _make_paper.py; assembly
# refines them. This file is the source of truth; docs/scenes.md explains every choice.

name = "{name}"
description = "{description}"
gravity = [0.0, -9.81]          # along -y (§4)

[effects]
clearance = true
friction = true
gravity = true
flexibility = true              # rods 3 and 4 flexible [S], 16 ANCF elements each [I];
                                # false: rigid bars at rigid-model cost (docs/ancf.md §10)
wear = false

[ground_points]
# O: crank pivot; C: rocker pivot at (Hx, Hy) [S] (§2); guide: a point of the vertical
# slider guide x = Hx ("Geometry")
O = {_v(o)}
C = {_v(c)}
guide = {_v(guide)}

"""


def _bodies(pts) -> str:
    """The crank, plate, the two ANCF rods and the slider at crank angle 0."""
    o, a, b, c, d, e = (pts[k] for k in "OABCDE")
    crank_cm = (L1 / 2, 0.0)
    j1 = round(J1_ABOUT_O - M1 * (L1 / 2) ** 2, 15)  # drop float noise: 9.391875e-4
    plate_cm = ((a[0] + b[0] + d[0]) / 3, (a[1] + b[1] + d[1]) / 3)
    return f"""[bodies.crank]                  # crank 1, L1 = 75 mm [S]
type = "rigid"
# CoM at mid-length [A]; inertia = 1.977e-3 kg m2 about O minus m (L1/2)^2
# ("Units of the printed inertias")
mass = {M1!r}
inertia = {j1!r}
position = {_v(crank_cm)}
angle = 0.0
points = {{ O = {_v(_sub(o, crank_cm))}, A = {_v(_sub(a, crank_cm))} }}

[bodies.plate]                  # triangle plate 2 [S]
# CoM at the centroid of A, B, D [A]; printed inertia 1348.94e-9 "kg m3" read as
# 1.349 kg m2 about the centroid ("Units of the printed inertias")
type = "rigid"
mass = {M2!r}
inertia = {J2!r}
position = {_v(plate_cm)}
angle = 0.0

[bodies.plate.points]
A = {_v(_sub(a, plate_cm))}
B = {_v(_sub(b, plate_cm))}
D = {_v(_sub(d, plate_cm))}

[bodies.rod3]                   # rod 3, the rocker C-B, flexible in the paper [S/I]
type = "ancf_beam"
length = {L3!r}
elements = 16                   # [I] (convergence table)
area = 1.0e-3                   # 0.05 x 0.02 m [S]
second_moment = 3.33e-8         # [S]
youngs_modulus = 207.0e9        # as the joint steel [A]
density = 7800.0                # printed 780 ("Rod density"); switch: docs/scenes.md
mass = {M3!r}                   # [S]; the rigid fallback uses m L^2/12 about the centre
# node 1 at C, last node at B
start = {_v(c)}
end = {_v(b)}

[bodies.rod4]                   # rod 4, the connecting rod D-E, flexible in the paper [S/I]
type = "ancf_beam"
length = {L4!r}
elements = 16
area = 1.0e-3
second_moment = 3.33e-8
youngs_modulus = 207.0e9
density = 7800.0
mass = {M4!r}
# node 1 at D, last node at E
start = {_v(d)}
end = {_v(e)}

[bodies.slider]                 # slider 5 [S]
type = "rigid"
mass = {M5!r}
inertia = {J5!r}                # printed 1.059e-9 "kg m3" read as kg m2; no rotation
position = {_v(e)}
angle = 0.0
points = {{ E = [0.0, 0.0] }}

"""


def _joints(clearance_at: str) -> str:
    """The joint tables O, A, B, C, D, E and the prismatic guide P."""
    joints_bc = _joints_b_c(clearance_at)
    return f"""[joints.O]
type = "revolute"
bodies = ["ground", "crank"]
points = ["O", "O"]

[joints.A]
type = "revolute"
bodies = ["crank", "plate"]
points = ["A", "A"]

{joints_bc[0]}
{joints_bc[1]}
[joints.D]
type = "revolute"
bodies = ["plate", "rod4"]
points = ["D", "start"]

[joints.E]
type = "revolute"
bodies = ["rod4", "slider"]
points = ["end", "E"]

[joints.P]                      # ideal prismatic guide, vertical through C ("Geometry")
type = "prismatic"
bodies = ["ground", "slider"]
points = ["guide", "E"]
axis = [0.0, 1.0]

"""


# The drive, solver and outputs tables; identical in every paper scene.
_DRIVE_SOLVER_OUTPUTS = """\
[drive]                         # crank at constant speed, counter-clockwise from 0 (§4)
type = "constant_speed"
joint = "O"
speed_rpm = 150.0               # [S]; 30 and 90 rpm in the speed study
initial_angle = 0.0

# output_step unset: (2 pi/omega)/10000 [S], follows drive.speed_rpm; max_step unset:
# steps bounded by the journal's approach to the wall, never below the output step
# (docs/simulator.md, "Step limits"). method "auto": with flexible rods the fixed-step
# generalized-alpha at the output step (the axial modes stall error-controlled methods,
# docs/ancf.md §8) [A]; with rigid rods Dormand-Prince "dopri5", as the paper's MATLAB
# ode45 (§7) [S]
[solver]
method = "auto"
rtol = 1.0e-5                   # [S] (§7)
atol = 1.0e-5
baumgarte_alpha = 50.0          # [S]
baumgarte_beta = 50.0           # [S]
projection = false
rho_inf = 0.5                   # [A] generalized-alpha damping: at 0.8 the friction ramp on
                                # the ANCF journal chatters (374 sign flips per revolution,
                                # 93 at 0.5), docs/ancf.md §8; rigid rods: unused

[outputs]
slider_joint = "P"
crank_joint = "O"
"""


def scene_toml(*, name: str, variant: str, clearance_at: str, description: str) -> str:
    """The TOML text of one paper scene (see SCENES for the arguments)."""
    pts = geometry(variant)
    return (
        _header(
            name=name,
            variant=variant,
            clearance_at=clearance_at,
            description=description,
            pts=pts,
        )
        + _bodies(pts)
        + _joints(clearance_at)
        + _DRIVE_SOLVER_OUTPUTS
    )


SCENES = {
    "paper": dict(
        variant="reconstructed",
        clearance_at="C",
        description=(
            "Jia et al. 2025 six-bar press (reconstructed geometry, docs/paper-model.md), "
            "dry clearance at C, "
            "rods 3 and 4 as 16-element ANCF beams (rigid bars with effects.flexibility "
            "= false), 150 rpm"
        ),
    ),
    "paper-gc": dict(
        variant="alternative",
        clearance_at="C",
        description=(
            "The paper six-bar with the alternative plate reading "
            "(AD = 985, BD = 473.66 mm), clearance at C"
        ),
    ),
    "paper-clearance-b": dict(
        variant="reconstructed",
        clearance_at="B",
        description=(
            "The paper six-bar with the clearance at B (bearing in the plate) instead of C"
        ),
    ),
}


def main() -> None:
    for name, kwargs in SCENES.items():
        path = HERE / f"{name}.toml"
        path.write_text(scene_toml(name=name, **kwargs), encoding="utf-8")
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
