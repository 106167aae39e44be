"""Regenerate the sample trajectories in this folder.

Run from the repository root::

    python data/make_samples.py                    # rewrite every sample in data/
    python data/make_samples.py --out /tmp/samples # write them elsewhere
    python data/make_samples.py --only lorenz.nc   # one (or a few) of them

What each file is and how it is made is in ``data/README.md``. Everything is deterministic:
the simulations use the compiled Dormand–Prince integrator with fixed settings and the
synthetic sensor noise of the "measured" CSV a fixed seed, so a rerun on the same platform
gives the same numbers (``tests/test_sample_data.py`` checks it).

The built-in ``paper`` scene has flexible rods 3 and 4 by default (issue 6); the paper
samples were made, and are still made, with rigid rods: ``RIGID_RODS`` switches
``effects.flexibility`` off explicitly (the rigid model, at rigid-model cost).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

import chaoskit
from chaoskit import systems
from chaoskit._contract import stamp

HERE = Path(__file__).resolve().parent

#: The simulator outputs kept in the sample files (the rest would multiply their size).
KEPT_VARIABLES = (
    "crank_angle",
    "slider_position",
    "displacement_error",
    "speed_error",
    "driving_torque",
    "eccentricity_x",
    "eccentricity_y",
    "penetration",
    "contact_force",
    "contact_angle",
    "in_contact",
)

#: The paper samples use rigid rods 3 and 4 (the built-in scene is flexible by default).
RIGID_RODS = {"effects.flexibility": False}
#: Paper scene at its nominal 150 rpm: revolutions and output samples per revolution.
PAPER_REVOLUTIONS = 20
PAPER_SAMPLES_PER_REV = 400
#: Wear prediction behind the "after wear" sample (mechanism.predict_wear): the settings
#: of a sweep's ``wear = "after"`` (docs/wear.md), 4 updates x 1000 crank cycles.
WEAR_UPDATES = 4
WEAR_CYCLES_PER_UPDATE = 1000.0
WEAR_MAX_DEPTH_INCREMENT = 0.25
WEAR_SETTLE_REVOLUTIONS = 1.0
#: Slider-crank with a clearance joint (S3, 5000 rpm).
SLIDER_REVOLUTIONS = 30
SLIDER_SAMPLES_PER_REV = 400
#: Integrator step cap in drive periods (the scenes' default resolution, T/10000), set
#: explicitly so that the coarse output grid does not also coarsen the step.
MAX_STEP_PER_PERIOD = 1e-4

#: Synthetic sensor of the "measured" CSV: two eddy-current probes on bearing C.
SENSOR_NOISE_RMS = 1.5e-6  # m, white noise of the probe electronics
SENSOR_LSB = 2e-3 / 4096  # m, 12-bit converter over a ±1 mm range (0.49 µm)
SENSOR_SEED = 20250130


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


def _simulate(scene, *, revolutions: int, samples_per_rev: int) -> xr.Dataset:
    import mechanism

    period = 60.0 / scene.drive.speed_rpm
    # dopri5 named explicitly: the scenes' "auto" resolves to it for rigid models too
    scene = scene.replace(
        {"solver.max_step": MAX_STEP_PER_PERIOD * period, "solver.method": "dopri5"}
    )
    ds = mechanism.simulate(scene, revolutions=revolutions, output_step=period / samples_per_rev)
    return ds[[v for v in KEPT_VARIABLES if v in ds.data_vars]]


def paper_before() -> xr.Dataset:
    """The paper's six-bar press (rigid rods, clearance at C) at 150 rpm, unworn."""
    import mechanism

    ds = _simulate(
        mechanism.load_scene("paper").replace(RIGID_RODS),
        revolutions=PAPER_REVOLUTIONS,
        samples_per_rev=PAPER_SAMPLES_PER_REV,
    )
    return stamp(
        ds,
        title=f"Paper six-bar press at 150 rpm before wear, {PAPER_REVOLUTIONS} revolutions",
        source=ds.attrs["source"],
        history=(
            f"data/make_samples.py: simulate('paper', revolutions={PAPER_REVOLUTIONS}, "
            f"output_step=T/{PAPER_SAMPLES_PER_REV}, max_step=T/10000), "
            f"kept {len(ds.data_vars)} variables"
        ),
    )


def paper_after() -> xr.Dataset:
    """The same press (rigid rods) after the wear predicted by ``mechanism.predict_wear``."""
    import mechanism

    prediction = mechanism.predict_wear(
        mechanism.load_scene("paper").replace(RIGID_RODS),
        updates=WEAR_UPDATES,
        cycles_per_update=WEAR_CYCLES_PER_UPDATE,
        max_depth_increment=WEAR_MAX_DEPTH_INCREMENT,
        settle_revolutions=WEAR_SETTLE_REVOLUTIONS,
    )
    ds = _simulate(
        prediction.worn_scene, revolutions=PAPER_REVOLUTIONS, samples_per_rev=PAPER_SAMPLES_PER_REV
    )
    return stamp(
        ds,
        title=f"Paper six-bar press at 150 rpm after wear, {PAPER_REVOLUTIONS} revolutions",
        source=ds.attrs["source"],
        history=(
            f"data/make_samples.py: predict_wear('paper', updates={WEAR_UPDATES}, "
            f"cycles_per_update={WEAR_CYCLES_PER_UPDATE:g}, "
            f"max_depth_increment={WEAR_MAX_DEPTH_INCREMENT}, "
            f"settle_revolutions={WEAR_SETTLE_REVOLUTIONS}), then simulate(worn scene, "
            f"revolutions={PAPER_REVOLUTIONS}, output_step=T/{PAPER_SAMPLES_PER_REV}, "
            f"max_step=T/10000), kept {len(ds.data_vars)} variables"
        ),
    )


def slider_crank_clearance() -> xr.Dataset:
    """Flores' slider-crank with a dry clearance joint at the rod–slider pin (S3)."""
    import mechanism

    ds = _simulate(
        mechanism.load_scene("slider-crank-clearance"),
        revolutions=SLIDER_REVOLUTIONS,
        samples_per_rev=SLIDER_SAMPLES_PER_REV,
    )
    return stamp(
        ds,
        title=(
            f"Slider-crank with a clearance joint at the rod-slider pin, 5000 rpm, "
            f"{SLIDER_REVOLUTIONS} revolutions"
        ),
        source=ds.attrs["source"],
        history=(
            f"data/make_samples.py: simulate('slider-crank-clearance', "
            f"revolutions={SLIDER_REVOLUTIONS}, output_step=T/{SLIDER_SAMPLES_PER_REV}, "
            f"max_step=T/10000), kept {len(ds.data_vars)} variables"
        ),
    )


MEASURED_HEADER = """\
# SYNTHETIC "measured" signal -- not a real measurement.
# Two proximity probes (x, y) watching the journal of joint C of the paper's six-bar press
# at 150 rpm, made by data/make_samples.py from paper-150rpm-before.nc: the simulated
# eccentricity plus {noise_um:.1f} um RMS white sensor noise (seed {seed}), quantised by a
# 12-bit converter over +-1 mm (LSB {lsb_um:.3f} um). Sampled at {rate:.0f} Hz.
# Columns: t_s = time (s); probe_x_um, probe_y_um = journal displacement (micrometres).
"""


def measured_journal(before: xr.Dataset) -> pd.DataFrame:
    """A synthetic probe recording derived from the before-wear trajectory."""
    rng = np.random.default_rng(SENSOR_SEED)
    t = before["time"].to_numpy()
    out = {"t_s": np.round(t, 9)}
    for axis in "xy":
        clean = before[f"eccentricity_{axis}"].isel(joint=0).to_numpy()
        noisy = clean + SENSOR_NOISE_RMS * rng.standard_normal(clean.size)
        counts = np.round(noisy / SENSOR_LSB)
        out[f"probe_{axis}_um"] = np.round(counts * SENSOR_LSB * 1e6, 3)
    return pd.DataFrame(out)


def write_measured(frame: pd.DataFrame, path: Path) -> Path:
    """Write the synthetic recording as a plain CSV with a comment header."""
    rate = 1.0 / float(np.median(np.diff(frame["t_s"].to_numpy())))
    header = MEASURED_HEADER.format(
        noise_um=SENSOR_NOISE_RMS * 1e6, seed=SENSOR_SEED, lsb_um=SENSOR_LSB * 1e6, rate=rate
    )
    tmp = path.with_name(f".{path.name}.tmp")
    with tmp.open("w", encoding="utf-8", newline="\n") as fh:
        fh.write(header)
        frame.to_csv(fh, index=False, float_format="%.9g", lineterminator="\n")
    tmp.replace(path)
    return path


def _wear_available() -> bool:
    import mechanism

    return hasattr(mechanism, "predict_wear")


#: netCDF samples: file name -> (maker, is it available in this installation?).
NETCDF_SAMPLES: Mapping[str, tuple[Callable[[], xr.Dataset], Callable[[], bool]]] = {
    "lorenz.nc": (lorenz_sample, lambda: True),
    "paper-150rpm-before.nc": (paper_before, lambda: True),
    "paper-150rpm-after.nc": (paper_after, _wear_available),
    "slider-crank-clearance.nc": (slider_crank_clearance, lambda: True),
}
MEASURED_CSV = "measured-journal.csv"
SAMPLE_NAMES = (*NETCDF_SAMPLES, MEASURED_CSV)


def make(out: Path, only: list[str] | None = None) -> list[Path]:
    """Write the samples named in ``only`` (default: all available) into ``out``."""
    names = list(only) if only else list(SAMPLE_NAMES)
    unknown = [n for n in names if n not in SAMPLE_NAMES]
    if unknown:
        raise ValueError(f"unknown sample(s) {unknown}; choose from {list(SAMPLE_NAMES)}.")
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    made: dict[str, xr.Dataset] = {}
    for name in names:
        if name == MEASURED_CSV:
            continue
        maker, available = NETCDF_SAMPLES[name]
        if not available():
            print(f"skipped {name}: mechanism.predict_wear is not available")
            continue
        made[name] = maker()
        written.append(chaoskit.save_trajectory(made[name], out / name))
        print(f"wrote {out / name}")
    if MEASURED_CSV in names:
        before = made.get("paper-150rpm-before.nc")
        if before is None:
            src = out / "paper-150rpm-before.nc"
            before = chaoskit.load_trajectory(src if src.exists() else HERE / src.name)
        written.append(write_measured(measured_journal(before), out / MEASURED_CSV))
        print(f"wrote {out / MEASURED_CSV}")
    return written


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Regenerate the sample data.")
    parser.add_argument("--out", type=Path, default=HERE, help="output folder (default data/)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help=f"some of {SAMPLE_NAMES}")
    args = parser.parse_args(argv)
    make(args.out, args.only)


if __name__ == "__main__":
    main()
