"""An integration that gives up says where and names the keys that change the outcome.

Every :class:`mechanism.SimulationError` raised by :func:`mechanism.simulate` for a failed
integration is one line with the time reached, the step size it had come to, whether a
clearance joint was in contact, and the scene keys or arguments to change. A run whose
step count, extrapolated from its progress after a compiled chunk, would exceed the
integrator's ``max_steps``, or without ``force=True`` the step budget of 2e7, is stopped
there instead of running for hours (into the cap). The runs here are short transients
and the numbers asserted hold with wide margins (the forecasts 4.67e8 and 4.67e7 against
bounds of 4e8 and [2e7, 2e8]), so they survive a change of rounding.
"""

from __future__ import annotations

import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

import mechanism
from mechanism.core.integrate import Dopri5

SCENE = "slider-crank-clearance"
#: 0.001 rpm is the slowest drive the validator accepts; one revolution is 60 000 s, held
#: at the contact's step: about 4.7e8 attempted steps, more than the 2e8 a run may take
CRAWL = {"drive.speed_rpm": 0.001}
LIMIT = Dopri5().max_steps
#: 0.1 revolution at 0.001 rpm (6000 s): about 4.7e7 attempted steps, a quarter of an hour
#: to an hour, below max_steps but above the budget a run takes without force
SHORT_CRAWL = 0.1
MAX_STEP_KEYS = (
    "the keys that change the outcome: revolutions (or t_end), drive.speed_rpm, "
    "solver.rtol, solver.max_step, solver.method"
)
ESTIMATE = re.compile(r"would need about ([0-9.e+]+) attempted steps to reach t = (\d+) s")
STEP_BUDGET = 2e7  # attempted steps a run takes without force=True (simulate's docstring)
BUDGET_TEXT = (
    "more than the 2e+07 a run takes unless forced; stopped early, force=True (--force) "
    "runs it anyway"
)


def test_a_run_at_its_step_cap_names_the_keys_and_where_it_stopped() -> None:
    """One revolution takes about 1200 attempted steps; a cap of 600 ends it midway."""
    scene = mechanism.load_scene(SCENE)
    with pytest.raises(mechanism.SimulationError) as info:
        mechanism.simulate(scene, revolutions=1.0, method=Dopri5(max_steps=600))
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"simulation of '{SCENE}' failed after t = "), text
    assert "of 0.012 s (dopri5): the maximum number of steps was reached; step size " in text
    assert re.search(r", (joint B|no clearance joint) in contact; the keys that change", text), text
    assert MAX_STEP_KEYS in text, text
    assert 0.0 < info.value.time < 0.012


def test_a_run_forecast_beyond_max_steps_is_stopped_after_its_first_chunk() -> None:
    scene = mechanism.load_scene(SCENE).replace(CRAWL)
    start = time.perf_counter()
    with pytest.raises(mechanism.SimulationError) as info:
        mechanism.simulate(scene, revolutions=1.0, record=mechanism.MetricsRecord(companion=False))
    took = time.perf_counter() - start
    text = str(info.value)
    assert "\n" not in text
    found = ESTIMATE.search(text)
    assert found is not None, text
    # the forecast, 4.7e8 on the development machine, is at least twice the cap
    assert float(found.group(1)) > 2.0 * LIMIT and found.group(2) == "60000", text
    assert f"more than max_steps = {LIMIT:.3g}; stopped early" in text
    assert MAX_STEP_KEYS in text, text
    # stopped within the first seconds of simulated time, not after hours of stepping
    assert info.value.time < 10.0, text
    assert took < 120.0, took


def _mechanism(*args: str) -> list[str]:
    code = "import sys; from mechanism.cli import app; sys.argv[0] = 'mechanism'; app()"
    return [sys.executable, "-c", code, *args]


def test_a_run_forecast_beyond_the_step_budget_is_stopped_unless_forced() -> None:
    scene = mechanism.load_scene(SCENE).replace(CRAWL)
    run = {"revolutions": SHORT_CRAWL, "record": mechanism.MetricsRecord(companion=False)}
    with pytest.raises(mechanism.SimulationError) as info:
        mechanism.simulate(scene, **run)
    text = str(info.value)
    found = ESTIMATE.search(text)
    assert found is not None and found.group(2) == "6000", text
    # 4.7e7 on the development machine: above the budget, below max_steps
    assert STEP_BUDGET < float(found.group(1)) < LIMIT, text
    assert BUDGET_TEXT in text, text
    assert MAX_STEP_KEYS in text, text
    assert info.value.time < 10.0, text
    # force=True lifts the budget, not the cap: with a cap of 30 000 steps the same
    # forecast now stops it for the cap
    with pytest.raises(mechanism.SimulationError) as info:
        mechanism.simulate(scene, **run, force=True, method=Dopri5(max_steps=30_000))
    assert "more than max_steps = 3e+04; stopped early" in str(info.value), str(info.value)


def test_the_command_line_stops_a_forecast_overrun_with_one_line(tmp_path: Path) -> None:
    """``mechanism simulate slider-crank-clearance --revolutions 0.1 --set
    drive.speed_rpm=0.001``: stopped after its first chunk, exit 1, one line naming the
    keys and --force; no output file."""
    output = tmp_path / "crawl.nc"
    cmd = _mechanism(
        "simulate", SCENE, "--revolutions", str(SHORT_CRAWL), "--set",
        "drive.speed_rpm=0.001", "-o", str(output),
    )  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    # the progress bars redraw their lines; besides them the command prints one line
    lines = [
        line
        for line in re.split(r"[\r\n]", proc.stderr)
        if line.strip() and "%|" not in line and line.strip() != "\x1b[A"
    ]
    assert proc.returncode == 1, proc.stderr
    assert "Traceback" not in proc.stderr
    assert len(lines) == 1, proc.stderr
    assert lines[0].startswith(f"Error: simulation of '{SCENE}' failed after t = "), lines
    assert BUDGET_TEXT in lines[0], lines
    assert MAX_STEP_KEYS in lines[0], lines
    assert not output.exists()
