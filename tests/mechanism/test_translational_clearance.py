"""Translational clearance joint (``type = "clearance_prismatic"``): a slider in a guide.

Closed forms: a slider resting on the lower guide surface sinks to the static solution of
the contact law; a free slider bouncing across a frictionless guide rebounds at the ratio
a point mass meets with the same law. With friction the mechanical energy never grows.
The built-in slider-crank with a translational clearance runs through ``simulate``,
``lyapunov_exponent`` and ``mechanism sweep``; its checks assert only what survives a
1e-12 perturbation of the initial state (bounds, not trajectories).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from typer.testing import CliRunner

import mechanism
from mechanism.cli import app
from mechanism.core.contact import corner_stiffness, law_code, normal_force
from mechanism.core.scene import Material, SceneError, scene_from_dict

STEEL = {"youngs_modulus": 207e9, "poisson_ratio": 0.3}
MASS = 0.1  # kg
CLEARANCE = 1e-3  # m
CORNER_RADIUS = 1e-3  # m
BUILTIN = "slider-crank-translational-clearance"


def free_slider(
    *,
    law: str = "hu-guo",
    restitution: float = 0.8,
    friction: float | None = None,
    gravity: bool = False,
    push: tuple[float, float] = (10.0, 10.0),
    initial_offset: float = 0.0,
) -> mechanism.Scene:
    """A 0.1 kg slider (100 × 50 mm) in a guide fixed to the ground, 1 mm clearance per side.

    Without gravity a load ``push`` (N) acts on its centre during the first millisecond
    (then none until the profile's period, 1e6 s, ends), so the slider starts across the
    guide at push·1 ms/m (0.1 m/s each way by default) and flies freely from then on.
    """
    data = {
        "name": "free-slider",
        "effects": {"gravity": gravity, "friction": friction is not None},
        "ground_points": {"O": [0.0, 0.0]},
        "bodies": {"slider": {"mass": MASS, "inertia": 1e-4, "points": {"C": [0.0, 0.0]}}},
        "joints": {
            "G": {
                "type": "clearance_prismatic",
                "guide": ["ground", "O"],
                "slider": ["slider", "C"],
                "slider_length": 0.1,
                "slider_width": 0.05,
                "clearance": CLEARANCE,
                "corner_radius": CORNER_RADIUS,
                "guide_material": STEEL,
                "slider_material": STEEL,
                "contact": {"law": law},
                "restitution": restitution,
                "friction": {"law": "coulomb", "coefficient": friction or 0.0, "v0": 1e-3},
                "initial_offset": initial_offset,
            }
        },
        "solver": {"rtol": 1e-9, "atol": 1e-12},
    }
    if not gravity:
        data["forces"] = {
            "push": {
                "type": "load",
                "body": "slider",
                "point": "C",
                "force": list(push),
                "time_profile": {
                    "type": "table",
                    "period": 1e6,
                    "time": [0.0, 1e-3, 1.001e-3, 9.99e5],
                    "factor": [1.0, 1.0, 0.0, 0.0],
                },
            }
        }
    return scene_from_dict(data)


def stiffness() -> float:
    steel = Material(**STEEL)
    return corner_stiffness(CORNER_RADIUS, steel, steel)


# --- closed forms --------------------------------------------------------------------------


def test_corner_stiffness_is_hertz_of_a_sphere_on_a_plane() -> None:
    e_star = 207e9 / (2.0 * (1.0 - 0.3**2))
    assert stiffness() == pytest.approx(4.0 / 3.0 * e_star * math.sqrt(CORNER_RADIUS), rel=1e-14)


def test_a_resting_slider_sinks_to_the_static_penetration_of_the_law() -> None:
    """Both lower corners carry half the weight: K δⁿ = m g / 2 (n = 1.5). The slider
    starts touching the lower surface at rest; the Flores law (cₑ = 0.5) damps the small
    oscillation about the static state within the 0.2 s simulated."""
    scene = free_slider(law="flores", restitution=0.5, gravity=True, initial_offset=-CLEARANCE)
    ds = mechanism.simulate(scene, t_end=0.2)
    assert ds.attrs["solver_status"] == 0
    static = (MASS * 9.81 / 2.0 / stiffness()) ** (1.0 / 1.5)
    last = ds.isel(time=-1)
    lower = ["G.lower_front", "G.lower_rear"]
    np.testing.assert_allclose(last.penetration.sel(joint=lower).values, static, rtol=1e-6)
    np.testing.assert_allclose(
        last.contact_force.sel(joint=lower).values, MASS * 9.81 / 2, rtol=1e-6
    )
    assert (last.contact_force.sel(joint=["G.upper_front", "G.upper_rear"]).values == 0.0).all()


def point_mass_rebound(law: str, restitution: float) -> float:
    """|v_out|/v_in of a point mass meeting a flat wall through the law (scale-free: the
    ratio depends on the law, cₑ and n = 1.5 only), the approach speed latched at entry."""
    code, k, mass, v_in = law_code(law), 1e9, 1.0, 1.0

    def rhs(t, y):
        return [y[1], -normal_force(code, k, 1.5, restitution, y[0], y[1], v_in) / mass]

    def separated(t, y):
        return y[0]

    separated.terminal, separated.direction = True, -1
    scale = (5 * mass * v_in**2 / (4 * k)) ** 0.4
    sol = solve_ivp(
        rhs, (0.0, 50 * scale / v_in), [0.0, v_in], method="DOP853", rtol=1e-11,
        atol=[1e-9 * scale, 1e-12], max_step=scale / v_in / 50, events=separated,
    )  # fmt: skip
    assert sol.status == 1
    return -sol.y_events[0][0][1] / v_in


def _rebounds(ds) -> list[float]:
    """|v_y after / v_y before| of every impact: the samples next to each contact phase
    are in free flight, where the lateral velocity is constant."""
    vy = ds.velocity.sel(body="slider", axis="y").values
    touching = (ds.in_contact.values > 0).any(axis=1).astype(int)
    edges = np.flatnonzero(np.diff(touching))
    assert edges.size >= 4 and edges.size % 2 == 0
    return [
        abs(vy[end + 1] / vy[start]) for start, end in zip(edges[::2], edges[1::2], strict=True)
    ]


@pytest.mark.parametrize(
    ("law", "ce"), [("hu-guo", 0.8), ("flores", 0.4), ("lankarani-nikravesh", 0.9)]
)
def test_a_slider_bouncing_across_its_guide_rebounds_at_the_law_restitution(law, ce) -> None:
    """Two impacts, on the upper then the lower surface, each with two corners at once:
    the rebound speed ratio is the point-mass one (0.79920, 0.36287, 0.91318) to 1e-6
    (measured within 4e-8: the corners of one side hit together, the slider does not
    turn, and the samples next to an impact are in free flight)."""
    # the second impact comes 2 mm after the first, at 0.1 cₑ m/s
    ds = mechanism.simulate(free_slider(law=law, restitution=ce), t_end=0.075, output_step=1e-5)
    assert ds.attrs["solver_status"] == 0
    expected = point_mass_rebound(law, ce)
    ratios = _rebounds(ds)
    assert len(ratios) >= 2
    np.testing.assert_allclose(ratios[:2], expected, atol=1e-6)
    first = ds.in_contact.values[np.argmax((ds.in_contact.values > 0).any(axis=1))]
    assert first.tolist() == [1, 1, 0, 0]  # the upper corners, pushed towards +y


def test_friction_only_takes_energy_out() -> None:
    """With Coulomb friction (μ = 0.3) the mechanical energy (kinetic + contact potential)
    never grows after the push, to the integration tolerance, and the sliding slows."""
    ds = mechanism.simulate(free_slider(friction=0.3), t_end=0.06, output_step=1e-5)
    assert ds.attrs["solver_status"] == 0
    free = ds.time.values > 1.01e-3
    energy = ds.mechanical_energy.values[free]
    assert np.diff(energy).max() <= 1e-8 * energy[0]
    assert energy[-1] < 0.5 * energy[0]
    vx = ds.velocity.sel(body="slider", axis="x").values
    assert vx[-1] < 0.5 * vx[np.argmax(free)]


def test_an_elastic_slider_keeps_its_energy_through_the_impacts() -> None:
    ds = mechanism.simulate(free_slider(law="hertz"), t_end=0.06, output_step=1e-5)
    energy = ds.mechanical_energy.values[ds.time.values > 1.01e-3]
    # the Hertz law stores and returns the impact's energy: what changes across the two
    # impacts is the integration error at rtol 1e-9 (measured 1.9e-7 of the energy)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-6)


def test_clearance_off_makes_the_joint_an_ideal_prismatic() -> None:
    scene = mechanism.load_scene(BUILTIN).replace({"effects.clearance": False})
    ds = mechanism.simulate(scene, revolutions=0.5)
    assert "joint" not in ds.dims
    np.testing.assert_allclose(ds.position.sel(body="slider", axis="y").values, 0.0, atol=1e-12)
    np.testing.assert_allclose(ds.slider_position, ds.slider_position_ideal, rtol=0, atol=1e-12)


# --- scene keys ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"joints.P.initial_offset": 2e-3},
            "joints.P.initial_offset: |offset| must be <= clearance = 0.001 (m); got 0.002",
        ),
        (
            {"joints.P.corner_radius": None},
            "joints.P.corner_radius: required with contact.stiffness = 'conformal' "
            "(K = (4/3) E* sqrt(corner_radius)); give a radius in [1e-06, 10] (m) or "
            "contact.stiffness as a number in [1000, 1e+16] (N m^-n)",
        ),
        ({"joints.P.axis": [1.0, 1.0]}, "joints.P.axis: must be a unit vector; got length 1.41421"),
        (
            {"joints.P.slider": ["ground", "O"]},
            "joints.P.slider[0]: the slider must be a rigid body, not the ground",
        ),
        (
            {"effects.wear": True},
            "joints.P.type: wear is modelled in clearance_revolute joints only; set "
            "effects.wear = false for a scene with a clearance_prismatic joint",
        ),
        ({"joints.P.clearance": -1e-3}, "joints.P.clearance: must be"),
        ({"joints.P.slider_width": 0.0}, "joints.P.slider_width: must be"),
    ],
)
def test_bad_keys_are_one_line_errors_naming_the_key(changes, message) -> None:
    scene = mechanism.load_scene(BUILTIN)
    with pytest.raises(SceneError) as err:
        scene.replace(changes)
    assert message in str(err.value)


def test_scene_round_trips_through_toml(tmp_path) -> None:
    scene = mechanism.load_scene(BUILTIN)
    assert mechanism.load_scene(mechanism.save_scene(scene, tmp_path / "s.toml")) == scene


# --- the built-in slider-crank -----------------------------------------------------------------


def test_builtin_slider_crank_simulates_with_its_corners_inside_the_guide() -> None:
    """Two revolutions: the slider's centre stays within its clearance plus the contact's
    penetration, every corner touches, and the penetration stays a small share of c."""
    scene = mechanism.load_scene(BUILTIN)
    ds = mechanism.simulate(scene, revolutions=2.0)
    assert ds.attrs["solver_status"] == 0
    assert list(ds.joint.values) == [
        "P.upper_front",
        "P.upper_rear",
        "P.lower_front",
        "P.lower_rear",
    ]
    y = ds.position.sel(body="slider", axis="y").values
    depth = float(ds.penetration.max())
    assert 0.0 < depth < 0.2 * CLEARANCE
    assert np.abs(y).max() <= CLEARANCE + depth + 1e-9
    assert np.abs(y).max() > 0.5 * CLEARANCE  # it crosses its guide
    assert ((ds.in_contact.values > 0).sum(axis=0) > 0).all()
    stroke = ds.slider_position.values
    assert stroke.min() == pytest.approx(0.153, abs=2e-3)
    assert stroke.max() == pytest.approx(0.459, abs=2e-3)


def test_builtin_slider_crank_lyapunov_exponent_runs() -> None:
    result = mechanism.lyapunov_exponent(mechanism.load_scene(BUILTIN), revolutions=1.0)
    assert math.isfinite(result.exponent)


def test_builtin_slider_crank_sweeps_from_the_command_line(tmp_path) -> None:
    args = [
        "sweep", BUILTIN, "--grid", "joints.P.clearance=5e-4,1e-3", "--store",
        str(tmp_path / "store"), "--revolutions", "1", "--discard", "0.5", "--scheduler", "serial",
        "--no-analysis", "--no-progress",
    ]  # fmt: skip
    result = CliRunner().invoke(app, args)
    assert result.exit_code == 0, result.output
    assert "2 points: 2 to run, 0 already done" in result.output


def carrier_scene(friction: float | None) -> mechanism.Scene:
    """The free slider's guide cut into a free 1 kg carrier body instead of the ground: the
    pair is isolated once the 1 ms push on the slider (started 0.2 m ahead of the carrier's
    centre of mass, so its impacts turn the carrier) is over."""
    data = free_slider(law="hertz" if friction is None else "hu-guo").to_dict()
    data["bodies"] = {
        "carrier": {"mass": 1.0, "inertia": 0.01, "points": {"G": [0.0, 0.0]}},
        "slider": {
            "mass": MASS,
            "inertia": 1e-4,
            "position": [0.2, 0.0],
            "points": {"C": [0.0, 0.0]},
        },
    }
    data["ground_points"] = {}
    data["joints"]["G"]["guide"] = ["carrier", "G"]
    data["effects"]["friction"] = friction is not None
    data["joints"]["G"]["friction"]["coefficient"] = friction or 0.0
    return scene_from_dict(data)


def _momenta(ds) -> tuple[np.ndarray, np.ndarray]:
    """Linear momentum (N s, x and y) and angular momentum about the origin (N m s)."""
    pos, vel = ds.position.values, ds.velocity.values  # (time, body, [x, y, θ])
    masses = np.array([1.0, MASS])[None, :]
    inertias = np.array([0.01, 1e-4])[None, :]
    linear = np.stack([(masses * vel[:, :, i]).sum(axis=1) for i in (0, 1)], axis=1)
    angular = (
        inertias * vel[:, :, 2]
        + masses * (pos[:, :, 0] * vel[:, :, 1] - pos[:, :, 1] * vel[:, :, 0])
    ).sum(axis=1)
    return linear, angular


@pytest.mark.parametrize("friction", [None, 0.3])
def test_a_guide_on_a_free_body_takes_the_opposite_force_at_the_corner(friction) -> None:
    """The guide body takes −f where the corner touches it (its guide point's force plus the
    moment e × (−f)): the isolated pair keeps its linear and angular momentum through the
    impacts, with and without friction, and the elastic law its energy (the penetration
    rate includes the guide's rotation). Measured drifts: 5e-14 of the momenta, 2e-8 of
    the energy (carrier turned at up to 0.26 rad/s)."""
    ds = mechanism.simulate(carrier_scene(friction), t_end=0.06, output_step=1e-5)
    assert ds.attrs["solver_status"] == 0
    free = ds.time.values > 1.01e-3
    assert int((ds.in_contact.values[free] > 0).any(axis=1).sum()) > 0
    linear, angular = _momenta(ds.isel(time=free))
    assert np.abs(linear - linear[0]).max() <= 1e-12 * np.abs(linear[0]).max()
    assert np.abs(angular - angular[0]).max() <= 1e-12 * abs(angular[0])
    turn = ds.velocity.sel(body="carrier", axis="theta").values[free]
    assert np.abs(turn).max() > 1e-3  # the impacts turned the carrier
    energy = ds.mechanical_energy.values[free]
    if friction is None:
        np.testing.assert_allclose(energy, energy[0], rtol=1e-6)
    else:
        assert np.diff(energy).max() <= 1e-8 * energy[0]
        assert energy[-1] < 0.9 * energy[0]


def test_a_deep_corner_penetration_is_announced_with_the_corner_name() -> None:
    """A soft contact (static penetration 0.64 mm) lets the slider, released at rest on the
    lower surface, sink past half its clearance: the warning names the corner's row and
    compares with the joint's clearance."""
    scene = free_slider(law="hu-guo", restitution=0.9, gravity=True, initial_offset=-CLEARANCE)
    soft = scene.replace({"joints.G.contact.stiffness": 3e4})
    with pytest.warns(mechanism.SimulationWarning) as caught:
        mechanism.simulate(soft, t_end=0.05)
    named = sorted(str(w.message).split(":")[0] for w in caught)
    assert named == ["joint G.lower_front", "joint G.lower_rear"]
    assert "of the clearance 0.001 m (above 50%)" in str(caught[0].message)
