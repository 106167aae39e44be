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
# # 04 — Bring your own data: a CSV from a sensor
#
# Import a measured signal, give it units, classify it and write a report. The file used
# here, `data/measured-journal.csv`, is **synthetic**: two proximity probes watching the
# journal of the press's clearance joint, made from a simulation plus sensor noise and
# 12-bit quantisation (`data/README.md`). Replace the path with your own file.

# %%
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import chaoskit


def find_data() -> Path:
    """The repository's data/ folder, from the notebook's folder or the installed package."""
    here = Path.cwd().resolve()
    for root in [here, *here.parents, Path(chaoskit.__file__).resolve().parents[1]]:
        if (root / "data" / "measured-journal.csv").exists():
            return root / "data"
    raise FileNotFoundError("data/ not found: run from the repository or set the path")


CSV = find_data() / "measured-journal.csv"
print("".join(CSV.read_text(encoding="utf-8").splitlines(keepends=True)[:10]))

# %% [markdown]
# ## Import
#
# `load_trajectory` reads one column per variable. Lines starting with `#` are skipped;
# the time column is found by name (`time` or `t`) or given with `time=`. A file without a
# time column needs `dt=` (the sampling interval in s). Units the file does not state are
# set to `"unknown"` — fix them before analysing, and convert to SI.

# %%
raw = chaoskit.load_trajectory(CSV, time="t_s", require_uniform=True)
print({name: var.attrs["units"] for name, var in raw.data_vars.items()})
print(f"{raw.sizes['time']} samples, dt = {chaoskit.sampling_interval(raw) * 1e3:.3f} ms")

ds = raw.rename({"probe_x_um": "x", "probe_y_um": "y"})
for axis in ("x", "y"):
    ds[axis] = ds[axis] * 1e-6  # µm -> m
    ds[axis].attrs = {"units": "m", "long_name": f"journal displacement {axis} (probe)"}
ds = chaoskit.validate_trajectory(ds)

# %% [markdown]
# ## Look first
#
# A press at 150 rpm turns once every 0.4 s. Drop the first 0.8 s (start-up) and plot the
# signal and the orbit; the quantisation steps are visible when you zoom in.

# %%
drive_period = 60.0 / 150.0  # s
run = ds.sel(time=slice(2 * drive_period, None))

fig, axes = plt.subplots(1, 3, figsize=(13, 4))
(run.x * 1e6).plot(ax=axes[0])
axes[0].set_ylabel("x (µm)")
axes[1].plot(run.x * 1e6, run.y * 1e6, lw=0.4)
axes[1].set_aspect("equal")
axes[1].set_xlabel("x (µm)")
axes[1].set_ylabel("y (µm)")
zoom = run.isel(time=slice(0, 40))
axes[2].step(zoom.time, zoom.x * 1e6, where="mid")
axes[2].set_xlabel("time (s)")
axes[2].set_title("40 samples: noise and quantisation")
fig.tight_layout()

# %% [markdown]
# ## Classify
#
# There is no crank-angle channel, so the stroboscopic section is taken by the clock once
# per drive period (`drive_period=`). Noise is estimated from the data and widens the
# tolerance of the section's clusters; the surrogate test guards against calling noise
# chaos.

# %%
verdict = chaoskit.classify(run, variable="x", drive_period=drive_period, rng=0)
print(f"{verdict.label} (confidence {verdict.confidence:.2f}): {verdict.reason}")
print(f"noise level estimated from the data: {verdict.noise_level:.3g} (in units of std(x))")
print(dict(verdict.votes))

# %% [markdown]
# Compare with the noise-free simulation of the same journal in notebook 01: 1.5 µm of
# sensor noise widens the exponents' intervals and the tolerance of the section's clusters.
# When an exponent is no longer *clearly* positive (95 % interval above zero and growth of
# at least 10 % per drive period), the rule answers *undetermined* instead of guessing;
# `votes` shows which evidence disagreed. Longer records or lower noise sharpen the answer.

# %%
table = chaoskit.analyze(run, variables=["x", "y"], drive_period=drive_period, rng=0)
table[["label", "confidence", "mle_rosenstein", "mle_wolf", "surrogate_p_value"]].to_dataframe()

# %% [markdown]
# ## Report
#
# `chaoskit.report` writes a self-contained HTML page and its Markdown twin: verdicts,
# the chaos table, phase portraits, stroboscopic maps and divergence curves, with the
# parameters and provenance. Here it goes to a temporary folder.

# %%
out = Path(tempfile.mkdtemp()) / "report.html"
rep = chaoskit.report(
    {"measured": ds},
    variables=["x", "y"],
    drive_period=drive_period,
    discard=2 * drive_period,
    title="Synthetic probe recording, joint C at 150 rpm",
    output=out,
)
print(sorted(p.name for p in out.parent.iterdir()))
rep.table("Chaos table").data  # noqa: B018 (the notebook displays it)

# %%
plt.close("all")
