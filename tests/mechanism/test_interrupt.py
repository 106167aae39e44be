"""Ctrl-C stops a compiled run: the loops return to Python every ``chunk_steps`` attempted
steps, and the results do not depend on where they return (bit for bit, with a budget of
7 steps against the default), and the command line ends an interrupted run with one
line and exit status 130."""

from __future__ import annotations

import dataclasses
import math
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mechanism
from mechanism.core import default_step, drive_period, step_limits
from mechanism.core.integrate import (
    Dopri5,
    GeneralizedAlpha,
    StepSettings,
    TangentSettings,
    initial_deviation,
    integrate_tangent,
    integrate_tangent_flexible,
    interrupt_integrations,
    length_scale,
    resolve_method,
)
from mechanism.core.model import assemble, initial_state

TINY_BUDGET = 7  # attempted steps per call: the loops return after rejections too
SOLVER_TIMES = ("solver_wall_time", "solver_cpu_time")


def _assert_same_run(a, b) -> None:
    """Two datasets of :func:`mechanism.simulate` hold identical arrays and counters."""
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        x, y = a[name].values, b[name].values
        nan = x.dtype.kind in "fc"
        assert np.array_equal(x, y, equal_nan=nan), name
    for key, value in a.attrs.items():
        if key.startswith("solver_") and not key.endswith(SOLVER_TIMES):
            assert b.attrs[key] == value, key


@pytest.mark.parametrize(
    ("scene_name", "revolutions", "method", "adaptive"),
    [
        ("slider-crank-clearance", 0.5, Dopri5(), True),
        ("slider-crank-clearance", 0.2, GeneralizedAlpha(), True),
        ("paper", 0.05, GeneralizedAlpha(step="max_step"), False),
    ],
    ids=["rigid-dopri5", "rigid-generalized-alpha", "flexible-generalized-alpha-fixed"],
)
def test_a_run_returning_every_few_steps_is_bit_identical(
    scene_name: str, revolutions: float, method, adaptive: bool
) -> None:
    scene = mechanism.load_scene(scene_name)
    whole = mechanism.simulate(scene, revolutions=revolutions, method=method)
    tiny = dataclasses.replace(method, chunk_steps=TINY_BUDGET)
    chunked = mechanism.simulate(scene, revolutions=revolutions, method=tiny)
    assert whole.attrs["solver_contact_events"] >= 1  # impacts fall inside the run
    assert whole.attrs["solver_steps"] > 20 * TINY_BUDGET
    if adaptive:  # calls also end right after rejected steps
        assert whole.attrs["solver_rejected_steps"] >= 1
    _assert_same_run(whole, chunked)


def _same_tangent(a, b) -> None:
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_array_equal(a.log_growth, b.log_growth)
    np.testing.assert_array_equal(a.final_state, b.final_state)
    np.testing.assert_array_equal(a.final_deviation, b.final_deviation)
    assert a.renormalizations == b.renormalizations
    assert dataclasses.replace(a.stats, wall_time=0.0) == dataclasses.replace(
        b.stats, wall_time=0.0
    )
    assert (a.newton_iterations, a.unconverged_steps) == (b.newton_iterations, b.unconverged_steps)


def _tangent_start(scene_name: str, revolutions: float):
    scene = mechanism.load_scene(scene_name)
    model = assemble(scene)
    q0, v0 = initial_state(model)
    y0 = np.concatenate([q0, v0])
    tau = drive_period(scene) / (2.0 * math.pi)
    t_end = revolutions * drive_period(scene)
    d0 = initial_deviation(model, y0, t0=0.0, size=1e-7 * length_scale(model, y0), time_scale=tau)
    return scene, model, y0, d0, tau, np.linspace(0.0, t_end, 5)


def test_rigid_tangent_integration_returning_every_few_steps_is_bit_identical() -> None:
    scene, model, y0, d0, tau, stops = _tangent_start("slider-crank-clearance", 0.5)
    max_step, floor = step_limits(model, Dopri5(), default_step(scene, stops[-1]))

    steps = StepSettings(rtol=1e-8, atol=1e-8, max_step=max_step, approach_floor=floor)

    def run(**budget: int):
        settings = TangentSettings(steps=steps, time_scale=tau, deviation_rtol=1e-4, **budget)
        return integrate_tangent(model, y0, d0, stops, settings=settings)

    whole, chunked = run(), run(chunk_steps=TINY_BUDGET)
    assert whole.stats.success and whole.stats.rejected_steps >= 1
    assert whole.stats.steps > 20 * TINY_BUDGET
    _same_tangent(whole, chunked)


def test_flexible_tangent_integration_returning_every_few_steps_is_bit_identical() -> None:
    scene, model, y0, d0, tau, stops = _tangent_start("paper", 0.03)
    method = resolve_method(scene.solver.method, model)
    max_step, floor = step_limits(model, method, default_step(scene, stops[-1]))

    steps = StepSettings(
        rtol=scene.solver.rtol, atol=scene.solver.atol, max_step=max_step, approach_floor=floor
    )
    settings = TangentSettings(steps=steps, time_scale=tau)

    def run(m: GeneralizedAlpha):
        return integrate_tangent_flexible(model, y0, d0, stops, method=m, settings=settings)

    whole, chunked = run(method), run(dataclasses.replace(method, chunk_steps=TINY_BUDGET))
    assert whole.stats.success and whole.stats.steps > 20 * TINY_BUDGET
    _same_tangent(whole, chunked)


def test_an_interruption_stops_runs_in_other_threads() -> None:
    """A run in another thread raises KeyboardInterrupt at its next return to Python once
    :func:`interrupt_integrations` has been called (as Ctrl-C in the main thread does)."""
    scene = mechanism.load_scene("slider-crank-clearance")
    mechanism.simulate(scene, revolutions=0.01, record="metrics")  # compiled before timing
    outcome: list[BaseException | None] = []

    def run() -> None:
        try:
            # 1e4 revolutions: about 1.2e7 attempted steps, minutes of stepping and below
            # the step budget (2e7) a run takes without force=True
            mechanism.simulate(scene, revolutions=1e4, record="metrics", output_step=1.0)
            outcome.append(None)
        except BaseException as exc:  # the interruption is the outcome looked for
            outcome.append(exc)

    worker = threading.Thread(target=run)
    worker.start()
    time.sleep(2.0)
    interrupt_integrations()
    worker.join(timeout=30.0)
    assert not worker.is_alive()
    assert len(outcome) == 1 and isinstance(outcome[0], KeyboardInterrupt)
    # a run started afterwards is not affected
    assert mechanism.simulate(scene, revolutions=0.01).attrs["solver_status"] == 0


RUN = ["slider-crank-clearance", "--record", "metrics"]


def _mechanism(*args: str) -> list[str]:
    """The command line as started from a terminal. A test run may itself be a background
    job of a non-interactive shell, which starts with SIGINT ignored; its children inherit
    that, Python then keeps the signal ignored, and so does the command (as any program
    does in the background), so the child sets Python's default handler first."""
    code = (
        "import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
        "from mechanism.cli import app; sys.argv[0] = 'mechanism'; app()"
    )
    return [sys.executable, "-c", code, *args]


def test_ctrl_c_ends_a_long_simulation_promptly_with_status_130(tmp_path: Path) -> None:
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    # the same command over a short time compiles (or loads) every kernel it runs
    warm = _mechanism("simulate", *RUN, "--revolutions", "0.01", "-o", str(tmp_path / "a.nc"))
    subprocess.run(warm, env=env, check=True, capture_output=True, timeout=900)
    # 1e4 revolutions: about 1.2e7 attempted steps (minutes of compiled stepping, each
    # progress chunk seconds), below the step budget (2e7), so it is not stopped early
    output = tmp_path / "long.nc"
    cmd = _mechanism(
        "simulate", *RUN, "--revolutions", "1e4", "--output-step", "1", "-o", str(output)
    )
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    err: list[bytes] = []
    started = threading.Event()

    def read() -> None:
        assert proc.stderr is not None
        while chunk := proc.stderr.read1(4096):
            err.append(chunk)
            if b"%|" in b"".join(err):
                started.set()

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        assert started.wait(120), b"".join(err).decode(errors="replace")
        time.sleep(3.0)  # well inside the compiled loops of both runs
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        code = proc.wait(timeout=30)
        took = time.perf_counter() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    reader.join(timeout=5)
    text = b"".join(err).decode(errors="replace")
    assert code == 130, text
    assert took < 10.0, took
    assert "Traceback" not in text
    assert text.rstrip().splitlines()[-1] == "interrupted"
    assert not output.exists()  # nothing half-written


@pytest.mark.parametrize("value", [0, -1, 2.5, True])
def test_a_step_budget_below_one_names_the_parameter(value) -> None:
    for method in (Dopri5, GeneralizedAlpha):
        with pytest.raises(ValueError, match=r"chunk_steps must be an integer ≥ 1"):
            method(chunk_steps=value)
