"""A Dormand–Prince run is one compiled entry point.

numba links the code of every kernel a kernel calls into that kernel's own module and
optimises and emits the whole module again, once per compiled kernel; a kernel called from
Python is compiled on its own, with everything under it. So the start of a run (k1 and the
initial step) and the recording after each step (samples, sections) are inlined into the
loop ``dopri5_advance`` at numba's IR level, and the loop records the initial state itself
on its first call: none of them is compiled as a kernel of its own, and the right-hand side
is optimised inside the loop once, not once more per recording kernel.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from mechanism.core.integrate import Dopri5, RecordPlan, StepSettings
from mechanism.core.integrate import _dopri_kernels as dopri_kernels
from mechanism.core.integrate import _step_kernels as step_kernels
from mechanism.core.integrate._driver import initial_latch, loop_output, step_control
from mechanism.core.model import assemble, initial_state
from mechanism.core.model import kernels as model_kernels
from tests.mechanism.scenes import rigid_paper

#: kernels inlined into ``dopri5_advance``: none may be compiled on its own in a run
INLINED = ("dopri5_start", "initial_step", "_initial_step", "after_step", "_sections",
           "record_sample", "_crank_at", "record_start")  # fmt: skip

#: child process: a rigid paper run recording sections, then one recording the full grid,
#: from an empty cache; prints the signature count of the loop and of each inlined kernel
CHILD = textwrap.dedent(
    """
    import json, sys
    import mechanism
    from mechanism.core.integrate import _dopri_kernels, _step_kernels
    from tests.mechanism.scenes import rigid_paper

    mechanism.simulate(rigid_paper(), revolutions=0.05, record="sections")
    mechanism.simulate(rigid_paper(), revolutions=0.05)
    counts = {"dopri5_advance": len(_dopri_kernels.dopri5_advance.signatures)}
    for name in json.loads(sys.argv[1]):
        module = _dopri_kernels if hasattr(_dopri_kernels, name) else _step_kernels
        counts[name] = len(getattr(module, name).signatures)
    print(json.dumps(counts))
    """
)


@pytest.mark.slow
def test_a_fresh_rigid_run_compiles_one_entry_point(tmp_path: Path) -> None:
    """From an empty cache, rigid runs recording sections and the full grid compile the
    loop once and none of the kernels inlined into it. Over 20 s: it compiles a whole run."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_NUM_THREADS": "1"}
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(INLINED)],
        env=env, cwd=root, capture_output=True, text=True, timeout=1800, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    assert counts == {"dopri5_advance": 1, **dict.fromkeys(INLINED, 0)}


@pytest.mark.parametrize(
    ("speed_rpm", "phase", "discard", "grid"),
    [(150.0, 0.0, 0.0, "full"), (-150.0, 0.3, 0.5, "light"), (150.0, -2.0, 1.0, "full")],
    ids=["section-at-start", "backwards-light", "negative-phase"],
)
def test_the_loop_records_the_start_as_the_python_side_did(
    speed_rpm: float, phase: float, discard: float, grid: str
) -> None:
    """The first grid sample, the first strobe angle and a section at the start, recorded
    by the loop's first call, are those :func:`loop_output` records from Python, bit for
    bit; the first call then steps on as before."""
    scene = rigid_paper({"drive.speed_rpm": speed_rpm})
    model = assemble(scene)
    q0, v0 = initial_state(model)
    y0 = np.concatenate([q0, v0])
    t_out = np.linspace(0.0, 0.01, 11)
    plan = RecordPlan(grid=grid, sections=4, phase=phase, discard=discard)
    vimp, contact = initial_latch(model, y0)
    python = loop_output(model, model.workspace(), y0, vimp.copy(), t_out, plan)
    ws = model.workspace()
    kernel = loop_output(model, ws, y0, vimp, t_out, plan, in_kernel=True)
    assert kernel.cursor.tolist() == [0, 0]
    y = y0.copy()
    counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    loop = step_kernels.LoopState(
        y=y, f=np.zeros_like(y), apse=np.zeros(0), step=np.array([0.0, 0.0, 0.0, -1.0]),
        vimp=vimp, contact=contact, counters=counters,
        work=np.zeros((dopri_kernels.DOPRI_WORK_ROWS, y.size)),
        tally=np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64),
    )  # fmt: skip
    steps = StepSettings(rtol=1e-8, atol=1e-8, max_step=1e-3, approach_floor=0.0,
                         projection=False)  # fmt: skip
    ctl = step_control(Dopri5(), 0.0, 0.01, steps)
    # a stop time at the start: the first call records the start, sets the step, returns
    status = dopri_kernels.dopri5_advance(model.kernel, ws, loop, kernel, ctl, 0.0)
    assert status == 1  # STATUS_RUNNING: stopped at t_stop
    assert kernel.cursor.tolist() == python.cursor.tolist()
    assert kernel.strobe.tobytes() == python.strobe.tobytes()
    assert loop.step[0] == 0.0 and loop.step[1] > 0.0 and loop.step[3] == 0.0
    assert counters[model_kernels.CNT_FEV] == 2  # k1 and the initial step's probe only
    for name in ("t", "q", "v", "a", "lam", "cj", "out", "jf"):
        got = getattr(kernel.sections, name)[: kernel.cursor[1]]
        want = getattr(python.sections, name)[: python.cursor[1]]
        assert got.tobytes() == want.tobytes(), name
        if grid == "full":
            got = getattr(kernel.rec, name)[:1]
            assert got.tobytes() == getattr(python.rec, name)[:1].tobytes(), name
    assert kernel.light[:1].tobytes() == python.light[:1].tobytes()
