"""Cost of wear in the dynamics: the paper scene, one revolution at 150 rpm.

* ``unworn`` — no profile, ``effects.wear`` off: the unworn code path (the worn tables are
  empty and ``worn_contact`` is never called, see ``test_wear_dynamics.py``).
* ``worn-profile`` — a 360-region worn profile on the bearing and journal: local clearance
  and tabulated local stiffness in every contact evaluation. Goal: within 10 % of unworn.
* ``wear-on`` — the same plus the run's Archard accumulation from the output samples.

Every call includes the ideal companion and the Dataset; numba is warmed up first. Run with
``python -m pytest benchmarks/test_bench_wear.py --benchmark-only``.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mechanism


def _worn(scene, wear_on: bool):
    joint = scene.joints["C"]
    angle = (np.arange(360) + 0.5) * np.pi / 180.0
    hb = 2e-5 * (np.exp(-(((angle - 2.0) / 0.3) ** 2)) + np.exp(-(((angle - 5.0) / 0.3) ** 2)))
    hj = 5e-6 * np.exp(-(((angle - 1.0) / 0.5) ** 2))
    wear = dataclasses.replace(joint.wear, bearing_profile=tuple(hb), journal_profile=tuple(hj))
    joints = dict(scene.joints)
    joints["C"] = dataclasses.replace(joint, wear=wear)
    scene = dataclasses.replace(scene, joints=joints)
    return scene.replace({"effects.wear": True}) if wear_on else scene


CASES = {
    "unworn": lambda s: s,
    "worn-profile": lambda s: _worn(s, False),
    "wear-on": lambda s: _worn(s, True),
}


@pytest.mark.parametrize("case", list(CASES))
def test_paper_revolution(benchmark, case) -> None:
    # rigid rods, as the published rows were measured (the built-in default is flexible)
    scene = CASES[case](mechanism.load_scene("paper").replace({"effects.flexibility": False}))
    mechanism.simulate(scene, revolutions=0.01)  # compile / load
    ds = benchmark.pedantic(
        mechanism.simulate, args=(scene,), kwargs={"revolutions": 1}, rounds=3, warmup_rounds=1
    )
    assert ds.attrs["solver_status"] == 0
    benchmark.extra_info.update(
        steps=ds.attrs["solver_steps"],
        function_evaluations=ds.attrs["solver_function_evaluations"],
        contact_events=ds.attrs["solver_contact_events"],
    )
