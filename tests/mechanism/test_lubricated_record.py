"""The full record of a lubricated scene holds the oil-film force and thickness of each
lubricated joint, equal to the closed-form short-bearing force at the recorded state; a
dry scene records no film variables."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechanism
from mechanism.core.contact import film_factor, positive_film_force, short_bearing_force
from mechanism.core.scene import Scene, scene_from_dict
from tests.mechanism.scenes import rigid_paper

MU, R, L, C = 0.04, 0.015, 0.011, 2.0e-4  # Pa s, m, m, m
OMEGA = 300.0  # rad/s, spin of the rotor
WHIRL = 60.0  # rad/s, rotation of the load
LOAD = 10.0  # N
BREAKDOWN = 1e-6  # m, the default film breakdown thickness
FILM = ("film_force_radial", "film_force_tangential", "film_force_x", "film_force_y")


def _rotor(cavitation: str) -> Scene:
    """A rotor on a lubricated journal in a fixed bearing at the origin (so the rotor's
    position is the eccentricity), spun by an actuator and loaded by a rotating force."""
    period = 2.0 * math.pi / WHIRL
    load = {"type": "load", "body": "rotor", "point": "O"}
    return scene_from_dict(
        {
            "name": "lubricated-rotor",
            "gravity": [0.0, 0.0],
            "effects": {"gravity": False, "friction": False},
            "ground_points": {"O": [0.0, 0.0]},
            "bodies": {
                "rotor": {
                    "mass": 0.1,
                    "inertia": 1e-4,
                    "position": [0.0, 0.0],
                    "angle": 0.0,
                    "points": {"O": [0.0, 0.0]},
                },
            },
            "joints": {
                "J": {
                    "type": "clearance_revolute",
                    "bearing": ["ground", "O"],
                    "journal": ["rotor", "O"],
                    "bearing_radius": R + C,
                    "clearance": C,
                    "length": L,
                    "friction": {"law": "none"},
                    "bearing_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                    "journal_material": {"youngs_modulus": 207e9, "poisson_ratio": 0.3},
                    "lubrication": {"viscosity": MU, "length": L, "cavitation": cavitation},
                },
            },
            "forces": {
                "spin": {
                    "type": "rotational_spring_damper",
                    "joint": "J",
                    "damping": 1e-2,
                    "actuator_torque": 1e-2 * OMEGA,
                },
                "load_x": load
                | {
                    "force": [LOAD, 0.0],
                    "time_profile": {"type": "fourier", "period": period, "cosine": [1.0]},
                },
                "load_y": load
                | {
                    "force": [0.0, LOAD],
                    "time_profile": {"type": "fourier", "period": period, "sine": [1.0]},
                },
            },
            "solver": {"method": "dopri5", "rtol": 1e-8, "atol": 1e-12},
        }
    )


@pytest.mark.parametrize(
    ("cavitation", "force"),
    [("pi-film", short_bearing_force), ("positive-pressure", positive_film_force)],
)
def test_recorded_film_force_is_the_short_bearing_force_of_the_recorded_state(
    cavitation, force
) -> None:
    ds = mechanism.simulate(_rotor(cavitation), t_end=0.05, output_step=1e-3)
    assert list(ds.lubricated_joint.values) == ["J"]
    for name in (*FILM, "film_thickness"):
        assert ds[name].dims == ("time", "lubricated_joint")
        assert ds[name].attrs["units"] == ("m" if name == "film_thickness" else "N")
        assert ds[name].attrs["long_name"]
    pos = ds.position.sel(body="rotor").values
    vel = ds.velocity.sel(body="rotor").values
    checked = 0
    for i in (5, 17, 30, 49):
        ex, ey = pos[i, 0], pos[i, 1]
        vx, vy, spin = vel[i]
        ne = math.hypot(ex, ey)
        eps = ne / C
        eps_dot = (ex * vx + ey * vy) / (ne * C)
        eps_w = eps * spin - 2.0 * (ex * vy - ey * vx) / (C * ne)
        weight = film_factor(C, BREAKDOWN, eps)
        f_r, f_t = force(MU, R, L, C, eps, eps_dot, eps_w)
        f_r, f_t = weight * f_r, weight * f_t
        f_x = (f_r * ex - f_t * ey) / ne
        f_y = (f_r * ey + f_t * ex) / ne
        scale = math.hypot(f_r, f_t)
        assert scale > 0.1  # a film that carries load: the comparison means something
        got = [float(ds[name].values[i, 0]) for name in FILM]
        np.testing.assert_allclose(got, [f_r, f_t, f_x, f_y], rtol=1e-12, atol=1e-12 * scale)
        assert float(ds.film_thickness.values[i, 0]) == pytest.approx(C - ne, rel=1e-12)
        checked += 1
    assert checked == 4


def test_a_dry_scene_records_no_film() -> None:
    ds = mechanism.simulate(rigid_paper(), revolutions=0.02, output_step=1e-3)
    assert "lubricated_joint" not in ds.dims
    assert not [name for name in ds.data_vars if str(name).startswith("film_")]


def test_film_of_a_crank_scene_in_the_full_and_section_records() -> None:
    """The rigid paper scene with oil at C: the film force's x, y components are its
    radial and tangential ones turned by the eccentricity's direction, the thickness is
    c - |e|, and the section record carries the same variables along ``crossing``."""
    scene = rigid_paper({"joints.C.lubrication": {"viscosity": 0.04}})
    c = scene.joints["C"].clearance
    ds = mechanism.simulate(scene, revolutions=0.05, record="full")
    assert list(ds.lubricated_joint.values) == ["C"]
    ex = ds.eccentricity_x.sel(joint="C").values
    ey = ds.eccentricity_y.sel(joint="C").values
    ne = np.hypot(ex, ey)
    f_r = ds.film_force_radial.sel(lubricated_joint="C").values
    f_t = ds.film_force_tangential.sel(lubricated_joint="C").values
    scale = np.max(np.hypot(f_r, f_t))
    assert scale > 1.0  # N: the film acts in this span
    fx = ds.film_force_x.sel(lubricated_joint="C").values
    fy = ds.film_force_y.sel(lubricated_joint="C").values
    np.testing.assert_allclose(fx, (f_r * ex - f_t * ey) / ne, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(fy, (f_r * ey + f_t * ex) / ne, rtol=1e-12, atol=1e-12 * scale)
    thickness = ds.film_thickness.sel(lubricated_joint="C").values
    np.testing.assert_allclose(thickness, c - ne, rtol=0.0, atol=1e-12 * c)
    record = mechanism.SectionsRecord(discard=1, companion=False)
    sections = mechanism.simulate(scene, revolutions=2, record=record)
    for name in (*FILM, "film_thickness"):
        assert sections[name].dims == ("crossing", "lubricated_joint")
