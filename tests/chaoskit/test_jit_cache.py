"""Cached compiled kernels follow the sources they were compiled from."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

from chaoskit.contract import refresh_jit_cache

CALLER = """
from numba import njit
from .inner import value

@njit(cache=True)
def outer():
    return value() + 0.0
"""


def _inner(result: float) -> str:
    return f"from numba import njit\n\n@njit\ndef value():\n    return {result!r}\n"


def _call(root: Path, *, refresh: bool) -> float:
    code = textwrap.dedent(
        f"""
        import sys
        sys.path.insert(0, {str(root)!r})
        from chaoskit.contract import refresh_jit_cache
        if {refresh!r}:
            refresh_jit_cache({str(root / "pkg")!r})
        from pkg.caller import outer
        print(outer())
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(out.stdout.split()[-1])


def test_a_changed_callee_is_compiled_again(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "caller.py").write_text(CALLER)
    (pkg / "inner.py").write_text(_inner(1.0))
    assert _call(tmp_path, refresh=True) == 1.0
    assert list(pkg.glob("__pycache__/*.nbi"))  # the caller's kernel is cached
    (pkg / "inner.py").write_text(_inner(2.0))  # only the callee's module changes
    # numba's own cache keys on the caller's file alone and loads the old machine code
    assert _call(tmp_path, refresh=False) == 1.0
    # the package check sees the changed source and has the kernel compiled again
    assert _call(tmp_path, refresh=True) == 2.0
    assert refresh_jit_cache(pkg) is False  # sources unchanged since: the cache stands
    assert list(pkg.glob("__pycache__/*.nbi"))


def test_every_package_checks_its_caches_before_importing_a_kernel() -> None:
    allowed = ("from __future__", "from ._jit_cache", "from chaoskit.contract")
    for package in ("chaoskit", "mechanism"):
        init = Path(__file__).resolve().parents[2] / package / "__init__.py"
        head = init.read_text().split("refresh_jit_cache(__file__)")[0]
        imports = [ln for ln in head.splitlines() if ln.startswith(("from ", "import "))]
        assert imports and all(ln.startswith(allowed) for ln in imports), (package, imports)
