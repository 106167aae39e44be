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
# # 01 — Quickstart: is this motion chaotic?
#
# Load a sample trajectory, ask `chaoskit` for a verdict, and look at the evidence behind
# it. The sample is the journal of the clearance joint C of the six-bar press of
# Jia et al. (*Lubricants* 2025, 13(3), 130), simulated by `mechanism` at 150 rpm before
# wear (`data/README.md` says how it was made). Runs in well under a minute.

# %%
from pathlib import Path

import matplotlib.pyplot as plt

import chaoskit


def find_data() -> Path:
    """The repository's data/ folder, from the notebook's folder or the installed package."""
    here = Path.cwd().resolve()
    for root in [here, *here.parents, Path(chaoskit.__file__).resolve().parents[1]]:
        if (root / "data" / "paper-150rpm-before.nc").exists():
            return root / "data"
    raise FileNotFoundError("data/ not found: run from the repository or set the path")


DATA = find_data()

# %% [markdown]
# ## Load
#
# `load_trajectory` reads netCDF, CSV or npz and checks the data contract
# (`docs/data-model.md`): a `time` coordinate in s, and `units` and `long_name` on every
# variable.

# %%
ds = chaoskit.load_trajectory(DATA / "paper-150rpm-before.nc")
print(ds.attrs["title"])
for name, var in ds.data_vars.items():
    print(f"{name:20s} {var.dims!s:18s} {var.attrs['units']:8s} {var.attrs['long_name']}")

# %% [markdown]
# The clearance-joint variables have a `joint` dimension (here only joint C). Pick joint C,
# drop the first two revolutions (start-up transient) and plot the journal's path inside
# the bearing clearance.

# %%
period = float(ds.attrs["drive_period"])  # s, one crank revolution
run = ds.sel(joint="C", drop=True).sel(time=slice(2 * period, None))

fig, axes = plt.subplots(1, 2, figsize=(10, 4))
(run.eccentricity_x * 1e6).plot(ax=axes[0])
axes[0].set_ylabel("journal x in bearing (µm)")
axes[1].plot(run.eccentricity_x * 1e6, run.eccentricity_y * 1e6, lw=0.4)
axes[1].set_aspect("equal")
axes[1].set_xlabel("x (µm)")
axes[1].set_ylabel("y (µm)")
axes[1].set_title("journal centre orbit")
fig.tight_layout()

# %% [markdown]
# ## Classify
#
# `classify` estimates the delay and embedding dimension, two largest-Lyapunov-exponent
# estimates (Rosenstein, Wolf) with 95 % intervals, the 0–1 test, a surrogate test and the
# structure of the stroboscopic section (once per crank revolution, taken from
# `crank_angle`), then applies the written rule of `docs/verdict.md`.

# %%
verdict = chaoskit.classify(run, variable="eccentricity_x", phase_variable="crank_angle", rng=0)
print(f"label      : {verdict.label}")
print(f"confidence : {verdict.confidence:.2f}")
print(f"reason     : {verdict.reason}")
print(f"votes      : {dict(verdict.votes)}")
print(f"delay      : {verdict.lag} samples, embedding dimension {verdict.embedding_dim}")
for est in (verdict.rosenstein, verdict.wolf):
    low, high = est.ci
    print(f"{est.method:11s}: {est.mle:.3g} 1/s, 95 % interval [{low:.3g}, {high:.3g}]")

# %% [markdown]
# Eighteen revolutions are a short record, so the exponent intervals are wide. The verdict
# says *chaotic* only when both exponents are clearly positive, the surrogate test rejects
# linear noise and the section is irregular; when the evidence is not that clear it says
# *undetermined*, and `votes` shows which piece disagreed. Longer runs narrow the intervals
# (`05_accuracy_vs_cost.py` shows how accuracy grows with the record length).

# %% [markdown]
# ## The evidence, plotted
#
# Every plot function takes `ax=` and returns the Axes; they accept the result objects or
# the verdict that carries them.

# %%
fig, axes = plt.subplots(2, 2, figsize=(10, 8))
chaoskit.plot.mutual_information(verdict, ax=axes[0, 0])
chaoskit.plot.false_nearest_neighbors(verdict, ax=axes[0, 1])
chaoskit.plot.divergence(verdict, ax=axes[1, 0])
chaoskit.plot.phase_portrait(run, variable="eccentricity_x", ax=axes[1, 1])
fig.tight_layout()

# %% [markdown]
# ## Many variables at once
#
# `analyze` runs the verdict on several variables and returns one row of scalars per
# variable — the table that reports and sweeps stack.

# %%
table = chaoskit.analyze(
    run,
    variables=["eccentricity_x", "eccentricity_y"],
    phase_variable="crank_angle",
    rng=0,
)
columns = ["label", "confidence", "lag", "embedding_dim", "mle_rosenstein", "mle_wolf"]
table[columns].to_dataframe()

# %% [markdown]
# ## A periodic contrast
#
# The slider-crank with a clearance joint and friction 0.1 settles into permanent contact:
# its stroboscopic map is a single point, and the verdict says periodic.

# %%
crank = chaoskit.load_trajectory(DATA / "slider-crank-clearance.nc")
crank_period = float(crank.attrs["drive_period"])
crank_run = crank.isel(joint=0, drop=True).sel(time=slice(5 * crank_period, None))
crank_verdict = chaoskit.classify(
    crank_run, variable="eccentricity_x", phase_variable="crank_angle", rng=0
)
print(crank_verdict.label, crank_verdict.period, f"{crank_verdict.confidence:.2f}")

strobe_chaotic = chaoskit.stroboscopic_map(run, phase_variable="crank_angle")
strobe_periodic = chaoskit.stroboscopic_map(crank_run, phase_variable="crank_angle")
fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for ax, strobe, name in [
    (axes[0], strobe_chaotic, "six-bar"),
    (axes[1], strobe_periodic, "slider-crank"),
]:
    ax.plot(strobe.eccentricity_x * 1e6, strobe.eccentricity_y * 1e6, "o", ms=4)
    ax.set_title(f"{name}: once per revolution")
    ax.set_xlabel("x (µm)")
    ax.set_ylabel("y (µm)")
fig.tight_layout()

# %% [markdown]
# ## Next
#
# * `02_paper_reproduced.py` — simulate the press and reproduce the paper's tables;
# * `03_sweeps_and_bifurcations.py` — parameter sweeps on a dask cluster;
# * `04_bring_your_own_data.py` — classify a CSV from your own measurements.

# %%
plt.close("all")
