"""Flexible-rod wall time: whole ``mechanism.simulate`` calls.

* S6 — Simeon's flexible slider-crank, 16 elements, 1 s simulated with the scene's
  fixed-step generalized-α (1e-4 s), the settings at which the slider position at 0.1 s is
  within 1e-5 m (asserted by ``tests/mechanism/test_flexible.py``). Goal ≤ 1 s.
* The default paper scene: rods 3 and 4 flexible (16 elements each), clearance and
  friction, fixed-step generalized-α at the scene's maximum step (T/10000), one crank
  revolution. Goal ≤ 3 s. The ideal companion runs in a second thread (docs/simulator.md),
  so this figure uses both cores of the 2-core machine.

Numba is warmed up by an untimed short run first. Run with
``python -m pytest benchmarks/test_bench_flexible.py --benchmark-only``; the measured
table is ``docs/benchmarks/flexible-integrators.csv`` (``benchmarks/flexible_integrators.py``).
"""

from __future__ import annotations

import pytest

import mechanism


def _s6():
    return mechanism.load_scene("flexible-slider-crank")


def _paper():
    return mechanism.load_scene("paper")


CASES = {
    "s6-16el-1s": (_s6, {"t_end": 1.0}),
    "paper-flexible-1rev": (_paper, {"revolutions": 1.0}),
}


@pytest.mark.parametrize("case", list(CASES))
def test_simulate_flexible(benchmark, case) -> None:
    make, kwargs = CASES[case]
    scene = make()
    kwargs = {**kwargs, "method": "generalized-alpha-fixed"}
    mechanism.simulate(scene, t_end=2e-3, method="generalized-alpha-fixed")  # compile
    ds = benchmark.pedantic(
        mechanism.simulate, args=(scene,), kwargs=kwargs, rounds=3, warmup_rounds=0
    )
    assert ds.attrs["solver_status"] == 0
