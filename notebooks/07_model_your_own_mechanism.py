# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 07 — Model your own mechanism
#
# A scene is plain TOML data: bodies, joints, force elements, a drive and the solver
# settings. This notebook writes one from scratch — a small press: a slider-crank with a
# dry clearance joint at the rod–slider pin, a return spring–damper on the slider and a
# working force over part of the stroke — simulates it with a prescribed crank speed,
# then lets a motor with a flywheel drive it instead and watches the crank speed follow
# the load. It ends with the largest Lyapunov exponent of the motor-driven motion.
#
# Every key, its unit and its accepted range are in `docs/scenes.md` (the *Scenes* page of
# the documentation); the force laws and the motor drive are in `docs/force-elements.md`.
# Runs in about 10 s once the simulator is compiled (the first run of a session compiles
# it, 30–60 s).

# %%
import matplotlib.pyplot as plt
import numpy as np

import mechanism
from mechanism.core.model import assemble
from mechanism.core.scene import scene_from_toml

# %% [markdown]
# ## The scene
#
# SI units throughout (m, kg, s, rad, N); only `speed_rpm` is in rev/min.
#
# * `[ground_points]` — points of the frame: the crank pivot `O` and the spring anchor `G`.
# * `[bodies.NAME]` — rigid bodies (the default `type`): `mass`, `inertia` about the centre
#   of mass, the pose at t = 0 (`position` of the centre of mass, `angle`) and named
#   `points` in body coordinates relative to the centre of mass. The pose needs only be
#   close: assembly refines it so that the joints close.
# * `[joints.NAME]` — `revolute` and `prismatic` joints name their two `bodies` and one
#   point on each. The crank (40 mm) and the rod (160 mm) give a stroke of 80 mm, from
#   x = 0.12 m to 0.20 m.
# * `[joints.B]` — the clearance joint: a `bearing` (the hole in the slider) and a
#   `journal` (the rod's pin), radius 10 mm, radial clearance 0.5 mm, steel on steel, a
#   Lankarani–Nikravesh contact (the default `[joints.B.contact]`) with restitution 0.9 and
#   Ambrósio dry friction (coefficient 0.1). No lubricant: the pin flies free inside the
#   clearance and hits the wall.
# * `[forces.return_spring]` — a translational spring–damper between `G` on the frame
#   and the slider's `B`: stiffness (N/m), damping (N s/m), free length (m).
# * `[forces.press]` — the working force: −300 N along x at the slider, times a factor
#   h(s) over the slider coordinate s of the prismatic joint `P`, active only while s
#   increases (the outward stroke). The factor ramps in from 0.15 m to 0.16 m and back to
#   0 before the dead centre at 0.20 m, so the force is continuous where the slider turns
#   (`docs/force-elements.md` §1 says why this matters for the exponent).
# * `[drive]` — the crank turns at a constant 600 rpm, starting at angle 0.
# * `[outputs]` — which joint is the slider's (`slider_position`, ...) and the crank's
#   (`crank_angle`).

# %%
SCENE = """
name = "my-press"
description = "Slider-crank press with a dry clearance joint at the rod-slider pin"
gravity = [0.0, -9.81]

[effects]
clearance = true
friction = true
gravity = true

[ground_points]
O = [0.0, 0.0]
G = [0.35, 0.0]

[bodies.crank]
mass = 0.4
inertia = 2e-4
position = [0.02, 0.0]
points = { O = [-0.02, 0.0], A = [0.02, 0.0] }

[bodies.rod]
mass = 0.25
inertia = 5e-4
position = [0.12, 0.0]
points = { A = [-0.08, 0.0], B = [0.08, 0.0] }

[bodies.slider]
mass = 0.2
inertia = 1e-4
position = [0.2, 0.0]
points = { B = [0.0, 0.0] }

[joints.O]
type = "revolute"
bodies = ["ground", "crank"]
points = ["O", "O"]

[joints.A]
type = "revolute"
bodies = ["crank", "rod"]
points = ["A", "A"]

[joints.B]
type = "clearance_revolute"
bearing = ["slider", "B"]
journal = ["rod", "B"]
bearing_radius = 0.01
clearance = 5e-4
length = 0.02
bearing_material = { youngs_modulus = 207e9, poisson_ratio = 0.3 }
journal_material = { youngs_modulus = 207e9, poisson_ratio = 0.3 }
restitution = 0.9
friction = { law = "ambrosio", coefficient = 0.1, v0 = 1e-4, v1 = 1e-3 }

[joints.P]
type = "prismatic"
bodies = ["ground", "slider"]
points = ["O", "B"]
axis = [1.0, 0.0]

[forces.return_spring]
type = "spring_damper"
bodies = ["ground", "slider"]
points = ["G", "B"]
stiffness = 1500.0
damping = 5.0
free_length = 0.18

[forces.press]
type = "load"
body = "slider"
point = "B"
force = [-300.0, 0.0]
frame = "global"

[forces.press.coordinate_profile]
joint = "P"
coordinate = [0.15, 0.16, 0.19, 0.198]
factor = [0.0, 1.0, 1.0, 0.0]
active = "increasing"

[drive]
type = "constant_speed"
joint = "O"
speed_rpm = 600.0

[outputs]
slider_joint = "P"
crank_joint = "O"
"""

scene = scene_from_toml(SCENE)
print(scene.name, "—", scene.description)
print("bodies:", list(scene.bodies), " joints:", list(scene.joints), " forces:", list(scene.forces))

# %% [markdown]
# A mistake is a one-line `SceneError` naming the key path, the accepted range and the
# unit, before anything runs:

# %%
try:
    scene_from_toml(SCENE.replace("clearance = 5e-4", "clearance = 0.02"))
except mechanism.SceneError as exc:
    print(exc)

# %% [markdown]
# `mechanism.save_scene(scene, "my-press.toml")` stores it as a file, and
# `mechanism.load_scene("my-press.toml")` or `mechanism show ./my-press.toml` read it back.
#
# ## Simulate at a prescribed crank speed
#
# Four revolutions (0.4 s). `simulate` also integrates the same mechanism with ideal
# joints alongside, for the `*_ideal` outputs and the errors.

# %%
ds = mechanism.simulate(scene, revolutions=4)
contact = ds.contact_force.sel(joint="B")

fig, axes = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
axes[0].plot(ds.time, ds.slider_position * 1e3, label="clearance joint")
axes[0].plot(ds.time, ds.slider_position_ideal * 1e3, "--", label="ideal joints")
axes[0].set_ylabel("slider position (mm)")
axes[0].legend()
axes[1].plot(ds.time, contact, lw=0.6)
axes[1].set_ylabel("contact force at B (N)")
axes[1].set_xlabel("time (s)")
fig.tight_layout()
print(f"peak contact force {float(contact.max()):.0f} N")
print(f"largest slider displacement error {float(abs(ds.displacement_error).max()) * 1e3:.2f} mm")

# %% [markdown]
# The contact force is a train of impacts: the pin crosses the clearance whenever the
# force in the rod changes sign (near the dead centres, and where the working force ramps
# in and out), and each impact peaks at the order of a kilonewton for a fraction of a
# millisecond. Between them the pin slides on the wall (continuous contact: the flat
# parts, where the working force goes through the pin) or flies free (zero force). The
# largest displacement error is how far the slider strays from the ideal mechanism's.
#
# ## A motor with a flywheel
#
# `[drive] type = "motor"` replaces the prescribed angle by a torque
# T(ω) = `stall_torque` (1 − ω/ω₀): here 10 N m at rest, zero at ω₀ = 700 rpm, and a
# flywheel of 0.02 kg m² on the crank. The crank angle is now a free coordinate and the
# motion is autonomous: there is no drive period, so the run length is `t_end` (s). The
# mechanism starts from rest and runs up with the time constant J ω₀ / T_s ≈ 0.15 s (J the
# crank's moment of inertia with the flywheel), so in about half a second.

# %%
motor = scene.replace(
    {
        "drive": {
            "type": "motor",
            "joint": "O",
            "stall_torque": 10.0,
            "no_load_speed_rpm": 700.0,
            "flywheel_inertia": 0.02,
        }
    }
)
dm = mechanism.simulate(motor, t_end=1.5)
omega = dm.velocity.sel(body="crank", axis="theta")  # rad/s (the frame does not turn)

# the motor torque is recorded as the force element "drive"
model = assemble(motor)
n = dm.time.size
values = model.force_element_values(
    dm.time.values, dm.position.values.reshape(n, -1), dm.velocity.values.reshape(n, -1)
)
torque = values[:, model.force_elements.index("drive"), 0]  # N m
press_on = values[:, model.force_elements.index("press"), 0] > 0  # load factor h > 0

fig, axes = plt.subplots(1, 2, figsize=(11, 4))
axes[0].plot(dm.time, omega * 60 / (2 * np.pi))
axes[0].set_xlabel("time (s)")
axes[0].set_ylabel("crank speed (rpm)")
late = dm.time >= 0.6  # after the run-up
angle = np.degrees(np.mod(dm.crank_angle.values, 2 * np.pi))
working = angle[late.values & press_on]
band = (working.min(), working.max())  # crank angles where the working force acts
axes[1].plot(angle[late.values], omega[late] * 60 / (2 * np.pi), ".", ms=1)
axes[1].axvspan(*band, color="0.9", zorder=0, label="working force on")
axes[1].set_xlabel("crank angle (deg)")
axes[1].set_ylabel("crank speed (rpm)")
axes[1].legend(loc="lower left")
fig.tight_layout()
print(f"working force on from {band[0]:.0f}° to {band[1]:.0f}° of crank angle")
steady = torque[late.values]
print(f"motor torque after the run-up: {steady.min():.2f} to {steady.max():.2f} N m")

# %% [markdown]
# Once it has run up, the crank slows down sharply while the press works (the shaded band,
# late in the outward stroke) and the motor speeds it up again over the rest of the
# revolution: the flywheel lends the work of the stroke and the motor gives it back, with
# a torque that rises as the speed falls.
#
# ## Sections at crank-angle crossings
#
# `SectionsRecord` samples the state where the crank angle passes `phase` + 2πk, located
# on the integrator's dense output; for a motor, `discard` counts revolutions of the
# crank. Sections at eight crank angles give the speed fluctuation over a revolution
# without a fine output grid, and the time between successive crossings of one angle is
# the revolution period.

# %%
phases = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
speed_at = []
for phase in phases:
    sec = mechanism.simulate(
        motor, t_end=1.5, record=mechanism.SectionsRecord(discard=6.0, phase=float(phase))
    )
    speed_at.append(sec.velocity.sel(body="crank", axis="theta").values * 60 / (2 * np.pi))
    if phase == 0.0:
        rev_period = np.diff(sec.time.values)

for phase, rpm in zip(phases, speed_at, strict=True):
    spread = np.ptp(rpm)  # over the kept revolutions
    print(f"crank at {np.degrees(phase):5.1f}°: {rpm.mean():6.1f} rpm (spread {spread:.2f} rpm)")
print("revolution periods at 0° (ms):", np.round(rev_period * 1e3, 2))

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(np.degrees(phases), [rpm.mean() for rpm in speed_at], "o-")
ax.axvspan(*band, color="0.9", zorder=0)
ax.set_xlabel("crank angle at the section (deg)")
ax.set_ylabel("crank speed (rpm)")
fig.tight_layout()

# %% [markdown]
# After the run-up each section repeats from one revolution to the next (the spread is
# small): the motor-driven press settles on a periodic motion whose speed swings with the
# load over a revolution. A larger flywheel (`flywheel_inertia`) narrows the swing.
#
# ## Largest Lyapunov exponent
#
# `lyapunov_exponent` integrates a small deviation along the run, from the equations of
# motion. For an autonomous motion one exponent is always 0: a shift along the flow
# (starting the same motion a little later on the crank angle) neither grows nor decays.
# So the largest exponent of a bounded, regular motor-driven motion tends to 0, not to a
# negative value as with a prescribed crank speed; a chaotic one is clearly positive.
# Here the window is short (2 s, the first 0.5 s discarded), so the 95 % interval is
# wide; for a study take tens of seconds.

# %%
result = mechanism.lyapunov_exponent(motor, t_end=2.0, discard=0.5)
low, high = result.ci
print(f"largest exponent {result.exponent:.3g} 1/s, 95 % interval [{low:.3g}, {high:.3g}]")

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(result.time, result.running_exponent)
ax.axhline(0.0, color="k", lw=0.5)
ax.set_xlabel("time (s)")
ax.set_ylabel("running estimate (1/s)")
fig.tight_layout()

# %% [markdown]
# ## Next
#
# * change a key with `scene.replace({"joints.B.clearance": 2e-4})` and compare;
# * `03_sweeps_and_bifurcations.py` — sweep a parameter (prescribed drive);
# * `01_quickstart.py` — classify the motion from the trajectory alone with `chaoskit`.

# %%
plt.close("all")
