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
# # 03 — Sweeps, bifurcation diagrams and chaos maps
#
# Run one simulation per point of a parameter grid on a local dask cluster, then read the
# results as a bifurcation diagram (stroboscopic points against a parameter) and a chaos
# map (largest Lyapunov exponent and verdict over two parameters). `docs/sweeps.md`
# describes the store, resume and the backends.
#
# The mechanism is the slider-crank with a dry clearance joint at the rod–slider pin
# (5000 rpm); the grid varies the pin's friction coefficient and clearance. Settings are
# small so that the notebook runs in about a minute on two cores: 10 revolutions per point
# and 250 output samples per revolution. Scale `revolutions`, the grid and the output step
# up for real studies.

# %%
import tempfile

import matplotlib.pyplot as plt
from dask.distributed import Client, LocalCluster

import chaoskit
import mechanism

# %% [markdown]
# ## The base scene and the grid
#
# Dotted keys are the scene's own field names (`mechanism show slider-crank-clearance`
# lists them). The integrator's step is capped at T/5000 explicitly, so that the coarse
# output grid does not also coarsen the integration.

# %%
scene = mechanism.load_scene("slider-crank-clearance")
period = 60.0 / scene.drive.speed_rpm  # s
scene = scene.replace({"solver.max_step": period / 5000, "solver.output_step": period / 250})

grid = {
    "joints.B.clearance": [2.5e-4, 5e-4],  # m
    "joints.B.friction.coefficient": [0.0, 0.03, 0.06, 0.1],
}
analysis = mechanism.Analysis(variables=("eccentricity_x",), discard_revolutions=2)
store = tempfile.mkdtemp(prefix="sweep-")

# %% [markdown]
# ## Run on a local dask cluster
#
# In a script, put this under `if __name__ == "__main__":` (dask starts its workers as new
# Python processes). In a notebook the cluster is created directly; close it when done.
# `client=None` would start and close a cluster for the call; `client="serial"` runs in
# this process without dask.

# %%
cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
client = Client(cluster)
try:
    sweep = mechanism.sweep(
        scene, grid=grid, revolutions=10, analysis=analysis, client=client, store=store
    )
finally:
    client.close()
    cluster.close()

print(sweep.attrs["history"].splitlines()[-1])
sweep[["status", "peak_contact_force", "max_penetration", "label"]].to_dataframe()

# %% [markdown]
# Every point's trajectory and summary are in the store; a rerun with the same `store`
# skips the finished points. `mechanism.load_sweep(store)` reads the gathered result back.

# %%
again = mechanism.load_sweep(store)
assert (again["status"] == sweep["status"]).all()

# %% [markdown]
# ## Response metrics over the grid

# %%
fig, axes = plt.subplots(1, 2, figsize=(11, 4))
(sweep.peak_contact_force / 1e3).plot.line(
    x="joints.B.friction.coefficient", hue="joints.B.clearance", marker="o", ax=axes[0]
)
axes[0].set_ylabel("peak contact force (kN)")
(sweep.max_penetration * 1e6).plot.line(
    x="joints.B.friction.coefficient", hue="joints.B.clearance", marker="o", ax=axes[1]
)
axes[1].set_ylabel("max penetration (µm)")
fig.tight_layout()

# %% [markdown]
# ## Bifurcation diagram
#
# `stroboscopic_points` samples each point's stored trajectory once per crank revolution
# (after the discarded transient). One grid line of it, handed to
# `chaoskit.bifurcation_diagram`, is a bifurcation diagram: a single dot per parameter
# value is a period-1 response, a vertical spread is an irregular one.

# %%
points = mechanism.stroboscopic_points(sweep, variables=["eccentricity_x", "eccentricity_y"])
line = points.sel({"joints.B.clearance": 5e-4})
diagram = chaoskit.bifurcation_diagram(
    line, parameter="joints.B.friction.coefficient", variable="eccentricity_x"
)
ax = chaoskit.plot.bifurcation(diagram)
ax.set_title("stroboscopic journal x against friction, clearance 0.5 mm")

# %% [markdown]
# ## Chaos map
#
# `chaos_map` arranges the exponent and the verdict of every point on a two-parameter
# plane; `chaoskit.plot.chaos_map` colours the exponent and writes the verdicts.

# %%
cmap = mechanism.chaos_map(
    sweep, x="joints.B.friction.coefficient", y="joints.B.clearance", variable="eccentricity_x"
)
ax = chaoskit.plot.chaos_map(cmap)
ax.set_title("Rosenstein exponent (1/s) and verdict")
cmap[["mle", "verdict"]].to_dataframe()

# %% [markdown]
# Eight revolutions after the transient give only eight stroboscopic points and 2000
# samples per point, too little for firm verdicts: expect many *undetermined* (and some
# *noise-like*) cells here. The verdict says so rather than guessing; for a real map use
# 50–100 revolutions per point (the press study of `mechanism paper` uses more).

# %%
plt.close("all")
