"""Kernels the compiled loops call are compiled without wrappers for calls from Python.

numba gives every kernel a CPython wrapper (which unboxes each argument: for the model
and workspace tuples, hundreds of fields) and a C wrapper; a kernel called only from other
kernels needs neither. ``njit_inner`` drops both; a call from Python then runs a twin
compiled with them instead of jumping into a missing wrapper (numba's own kernel without
a CPython wrapper crashes the interpreter there).
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

from mechanism.core._jit import InnerKernel, njit_inner, njit_noalloc
from mechanism.core.model import assemble, initial_state
from mechanism.core.model import kernels as model_kernels
from tests.mechanism.scenes import rigid_paper


@njit_inner()
def _scaled_sum(x, scale):
    out = 0.0
    for i in range(x.shape[0]):
        out += scale * x[i]
    return out


@njit_noalloc()
def _caller(x):
    return _scaled_sum(x, 2.0) + 1.0


def test_a_python_call_of_an_inner_kernel_runs_its_twin() -> None:
    """Called from a kernel, the inner kernel is compiled without wrappers; called from
    Python, it returns the same value through its twin (no crash)."""
    x = np.array([0.5, 1.25, -0.25])
    assert _caller(x) == 4.0
    assert isinstance(_scaled_sum, InnerKernel)
    assert _scaled_sum(x, 2.0) == 3.0
    twin = _scaled_sum.__dict__["_python_twin"]
    assert twin.py_func.__qualname__ == "_scaled_sum_py"
    assert len(twin.signatures) == 1
    # the kernel itself is compiled without the wrappers, its twin with them
    assert _scaled_sum.targetoptions["no_cpython_wrapper"] is True
    assert _scaled_sum.targetoptions["no_cfunc_wrapper"] is True
    assert "no_cpython_wrapper" not in twin.targetoptions


def test_a_model_kernel_called_from_python_gives_what_the_loop_uses() -> None:
    """A model kernel the loop calls (the clearance state) called from Python gives the
    values the right-hand side leaves in the workspace."""
    model = assemble(rigid_paper())
    km, ws = model.kernel, model.workspace()
    q, v = initial_state(model)
    y = np.concatenate([q, v])
    vimp = np.full(km.cj_i.shape[0], 0.01)
    counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    assert model_kernels.rhs(km, ws, 0.0, y, vimp, np.zeros_like(y), counters) == 0
    assert isinstance(model_kernels.clearance_state, InnerKernel)
    delta, ddot, kn = model_kernels.clearance_state(km, ws, y, 0)
    # δ is (δ₀ + c₀) − c₀ there: equal to the rounding of c₀ (about 1e-4 m)
    assert delta == pytest.approx(ws.cj[0, model_kernels.CJ_DELTA], rel=0.0, abs=1e-18)
    assert ddot == ws.cj[0, model_kernels.CJ_DELTA_DOT]
    assert kn == ws.cj[0, model_kernels.CJ_K]


#: child process: a rigid paper run recording sections from an empty cache; prints the
#: twins (kernels compiled for calls from Python) of the inner kernels it compiled
CHILD = textwrap.dedent(
    """
    import json, sys
    import mechanism
    from mechanism.core._jit import InnerKernel
    from mechanism.core.contact import _kernels as ck
    from mechanism.core.joints import _kernels as jk
    from mechanism.core.model import _kernels as mk
    from tests.mechanism.scenes import rigid_paper

    mechanism.simulate(rigid_paper(), revolutions=0.05, record="sections")
    inner = twins = 0
    for module in (mk, jk, ck):
        for name, obj in vars(module).items():
            if isinstance(obj, InnerKernel) and obj.signatures:
                inner += 1
                twins += "_python_twin" in obj.__dict__
    print(json.dumps({"inner": inner, "twins": twins}))
    """
)


@pytest.mark.slow
def test_a_fresh_rigid_run_calls_no_inner_kernel_from_python(tmp_path: Path) -> None:
    """From an empty cache, a rigid run compiles its inner kernels without wrappers and no
    twin: nothing in a run calls them from Python. Over 20 s: it compiles a whole run."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_NUM_THREADS": "1"}
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-c", CHILD],
        env=env, cwd=root, capture_output=True, text=True, timeout=1800, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    counts = json.loads(done.stdout.strip().splitlines()[-1])
    assert counts["twins"] == 0
    assert counts["inner"] >= 30
