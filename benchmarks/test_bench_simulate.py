"""Simulator wall time: whole ``mechanism.simulate`` calls.

* S3 — the clearance slider-crank with friction (μ = 0.1) for 1 s at 5000 rpm at the
  settings that keep the first impact within 3 % (rtol = atol = 1e-5 and an output step of
  1e-4 s, which is also the default maximum step of a run with clearance; the 3 % are
  asserted by ``tests/mechanism/test_slider_crank.py``). Goal ≤ 3 s.
* The paper scene with rigid rods and the clearance joint, one revolution at 150 rpm at
  the scene's settings (rtol = atol = 1e-5, output step T/10000; the step is not bounded
  by the grid). Goal ≤ 0.5 s.
* The same over 10 revolutions recording only stroboscopic sections and the metrics.
  Goal ≤ 0.1 s per revolution on one core (``benchmarks/record_modes.py`` measures the
  CPU time, which is the one-core cost of the run and its companion).
* The same two with ``effects.clearance = false``. Goal: ≥ 5× cheaper than with it.

Every call includes the ideal-mechanism companion run and the Dataset assembly; numba is
warmed up by an untimed round first. Run with
``python -m pytest benchmarks/test_bench_simulate.py --benchmark-only``.
"""

from __future__ import annotations

import pytest

import mechanism


def _s3(clearance: bool = True):
    scene = mechanism.load_scene("slider-crank-clearance").replace(
        {"joints.B.friction.coefficient": 0.1}
    )
    return scene.replace({"effects.clearance": False}) if not clearance else scene


def _paper(clearance: bool = True):
    # rigid rods: the published rows measure the rigid paper scene (the built-in default
    # is flexible by default; its flexible cost is in test_bench_flexible.py)
    scene = mechanism.load_scene("paper").replace({"effects.flexibility": False})
    return scene.replace({"effects.clearance": False}) if not clearance else scene


CASES = {
    "s3-1s-friction": (lambda: _s3(True), {"t_end": 1.0, "output_step": 1e-4}),
    "s3-1s-clearance-off": (lambda: _s3(False), {"t_end": 1.0, "output_step": 1e-4}),
    "paper-1rev": (lambda: _paper(True), {"revolutions": 1}),
    "paper-1rev-clearance-off": (lambda: _paper(False), {"revolutions": 1}),
    "paper-10rev-sections": (lambda: _paper(True), {"revolutions": 10, "record": "sections"}),
}


@pytest.mark.parametrize("case", list(CASES))
def test_simulate(benchmark, case) -> None:
    make, kwargs = CASES[case]
    scene = make()
    kwargs = {**kwargs, "rtol": 1e-5, "atol": 1e-5}
    mechanism.simulate(scene, t_end=scene.solver.output_step or 1e-3)  # compile / load
    ds = benchmark.pedantic(
        mechanism.simulate, args=(scene,), kwargs=kwargs, rounds=3, warmup_rounds=1
    )
    assert ds.attrs["solver_status"] == 0
    benchmark.extra_info.update(
        steps=ds.attrs["solver_steps"],
        rejected=ds.attrs["solver_rejected_steps"],
        function_evaluations=ds.attrs["solver_function_evaluations"],
        contact_events=ds.attrs["solver_contact_events"],
        ideal_steps=ds.attrs["ideal_solver_steps"],
        samples=ds.sizes["time"] if "time" in ds.dims else ds.sizes["crossing"],
    )
