"""Refactoring guard: what ``simulate`` computes does not change when its code is reorganised.

Two kinds of check:

* the record-mode object and its shorthand string give identical Datasets (every data
  variable, coordinate and variable attribute; only the run's timing and creation
  attributes differ) — this holds on any machine;
* a SHA-256 digest of the float64 bytes of the main variables of three scenes (the rigid
  and the flexible paper scene, the clearance slider-crank), recorded on one machine. The
  compiled kernels are built for the host CPU and the results of transient contact runs
  depend on the last bit of every operation, so a digest holds only for the CPU, numba
  and numpy it was recorded with; elsewhere the check is skipped (it says why). Where it
  runs, a digest may change only deliberately: a change of the numerics (a model, an
  integrator, a kernel), never a reorganisation. Whoever makes such a change records the
  new digests here (the failure message shows the digest computed) and says why in the
  change.
"""

from __future__ import annotations

import hashlib
import platform

import llvmlite.binding as llvm
import numba
import numpy as np
import pytest
import xarray as xr

import mechanism
from mechanism import FullRecord, MetricsRecord, SectionsRecord
from tests.mechanism.scenes import rigid_paper

#: The machine the digests were recorded on: host CPU (numba compiles for it), numba, numpy.
RECORDED_ON = ("x86_64", "znver4", "0.68.1", "2.4.6")
#: Dataset attributes that describe the run's timing and creation, not its results.
TIMING_ATTRS = (
    "solver_cpu_time",
    "solver_wall_time",
    "ideal_solver_cpu_time",
    "ideal_solver_wall_time",
    "created",
    "history",
)
#: The variables whose float64 bytes are hashed (those a scene has).
MAIN_VARIABLES = (
    "time",
    "crank_angle",
    "position",
    "velocity",
    "slider_position",
    "slider_velocity",
    "eccentricity_x",
    "eccentricity_y",
    "contact_force",
    "driving_torque",
)


def _this_machine() -> tuple[str, str, str, str]:
    return (platform.machine(), llvm.get_host_cpu_name(), numba.__version__, np.__version__)


def _digest(ds: xr.Dataset) -> str:
    sha = hashlib.sha256()
    for name in MAIN_VARIABLES:
        if name in ds.variables:
            values = np.ascontiguousarray(ds[name].values, dtype="<f8")
            sha.update(name.encode())
            sha.update(values.tobytes())
    return sha.hexdigest()


def _results(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` without the attributes of its timing and creation."""
    out = ds.copy()
    out.attrs = {k: v for k, v in ds.attrs.items() if k not in TIMING_ATTRS}
    return out


def test_a_record_object_and_its_name_give_identical_datasets() -> None:
    scene = rigid_paper()
    by_name = mechanism.simulate(scene, revolutions=1)
    by_object = mechanism.simulate(scene, revolutions=1, record=FullRecord())
    xr.testing.assert_identical(_results(by_name), _results(by_object))
    assert set(by_name.attrs) == set(by_object.attrs)
    # a name is its mode with the default options
    by_name = mechanism.simulate(scene, revolutions=2, record="sections")
    obj = mechanism.simulate(scene, revolutions=2, record=SectionsRecord(discard=0, phase=0.0))
    xr.testing.assert_identical(_results(by_name), _results(obj))
    assert by_name.sizes["crossing"] == 3
    metrics = mechanism.simulate(scene, revolutions=2, record="metrics")
    same = mechanism.simulate(scene, revolutions=2, record=MetricsRecord(companion=True))
    xr.testing.assert_identical(_results(metrics), _results(same))


DIGESTS = {
    "rigid paper, 2 revolutions": (
        rigid_paper,
        2.0,
        "312181b3d16033d66d51471fd204038141bb89b83ebc973c7f7aa78b949e1d2f",
    ),
    "slider-crank-clearance, 1 revolution": (
        lambda: mechanism.load_scene("slider-crank-clearance"),
        1.0,
        "c9b815777b53a7385f86c47c7d3975a30e4d2e530772b81014fd74830342e103",
    ),
}


def _check_digest(scene: mechanism.Scene, revolutions: float, expected: str) -> None:
    if _this_machine() != RECORDED_ON:
        pytest.skip(
            f"digests recorded on {RECORDED_ON} (machine, CPU, numba, numpy); this is "
            f"{_this_machine()}: the compiled kernels round differently"
        )
    got = _digest(mechanism.simulate(scene, revolutions=revolutions))
    assert got == expected, (
        f"the trajectory changed (digest {got}); update it only for a deliberate change "
        "of the numerics"
    )


@pytest.mark.parametrize("case", sorted(DIGESTS))
def test_trajectories_of_rigid_scenes_are_unchanged(case: str) -> None:
    make, revolutions, expected = DIGESTS[case]
    _check_digest(make(), revolutions, expected)


@pytest.mark.slow
def test_the_flexible_trajectory_is_unchanged() -> None:
    """The flexible paper scene (ANCF rods, generalized-α): its first compile and steps
    take over 20 s, hence slow."""
    _check_digest(
        mechanism.load_scene("paper"),
        0.05,
        # recorded on this machine: the digests of the other were not at hand
        "015eb0d998ca01513970fe99f5205cf31ed57bae17e924d9cc87865529920093",
    )
