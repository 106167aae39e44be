"""Regenerate the sample trajectories in this folder.

Run from the repository root:  python data/make_samples.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

import chaoskit
from chaoskit import systems
from chaoskit._contract import stamp

HERE = Path(__file__).resolve().parent


def lorenz_sample() -> xr.Dataset:
    """Lorenz (σ=10, ρ=28, β=8/3) sampled at dt = 0.01 after a 50-unit transient."""
    dt, n = 0.01, 10_000
    xyz = systems.lorenz(n, dt=dt)
    t = np.arange(n) * dt
    attrs = {"units": "1", "long_name": "Lorenz {} coordinate"}
    ds = xr.Dataset(
        {
            name: ("time", xyz[:, i], {**attrs, "long_name": attrs["long_name"].format(name)})
            for i, name in enumerate("xyz")
        },
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
    )
    return stamp(
        ds,
        title="Lorenz attractor, sigma=10 rho=28 beta=8/3, dt=0.01 (largest exponent 0.9056 1/s)",
        history="data/make_samples.py: chaoskit.systems.lorenz(10000, dt=0.01)",
    )


SAMPLES = {"lorenz.nc": lorenz_sample}


def main() -> None:
    for name, make in SAMPLES.items():
        chaoskit.save_trajectory(make(), HERE / name)
        print(f"wrote {HERE / name}")


if __name__ == "__main__":
    main()
