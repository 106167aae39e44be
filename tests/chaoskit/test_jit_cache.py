"""Cached compiled kernels follow the sources they were compiled from, wherever numba
keeps them, and an install where nothing can be written beside the sources or in the
home folder still imports: its kernels are cached in a private folder, or compiled
without a cache after one warning."""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from chaoskit.contract import refresh_jit_cache

REPO = Path(__file__).resolve().parents[2]

CALLER = """
from numba import njit
from .inner import value

@njit(cache=True)
def outer():
    return value() + 0.0
"""


def _inner(result: float) -> str:
    return f"from numba import njit\n\n@njit\ndef value():\n    return {result!r}\n"


def _call(root: Path, *, refresh: bool, env: dict[str, str] | None = None) -> float:
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
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env
    )
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


def test_a_changed_callee_is_compiled_again_in_an_external_cache(tmp_path: Path) -> None:
    """The same with the caches in ``NUMBA_CACHE_DIR``, away from the sources (as in a
    read-only install)."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "caller.py").write_text(CALLER)
    (pkg / "inner.py").write_text(_inner(1.0))
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    assert _call(tmp_path, refresh=True, env=env) == 1.0
    assert list((tmp_path / "cache").rglob("caller.outer-*.nbi"))
    assert not list(pkg.rglob("*.nbi"))  # nothing beside the sources
    (pkg / "inner.py").write_text(_inner(2.0))
    assert _call(tmp_path, refresh=False, env=env) == 1.0
    assert _call(tmp_path, refresh=True, env=env) == 2.0


def _read_only_install(tmp_path: Path) -> tuple[dict[str, str], Path]:
    """Both packages copied into a read-only folder where no cache can be written beside
    the sources (each ``__pycache__`` is a regular file: that holds for root too, which
    permission bits do not stop), a home folder below a regular file, no
    ``NUMBA_CACHE_DIR``, and a temporary folder of its own. Returns the environment of a
    subprocess and that temporary folder."""
    site = tmp_path / "site"
    for name in ("chaoskit", "mechanism"):
        shutil.copytree(REPO / name, site / name, ignore=shutil.ignore_patterns("__pycache__"))
    folders = [site, *(p for p in site.rglob("*") if p.is_dir())]
    for folder in folders:
        (folder / "__pycache__").touch()
    for path in [*site.rglob("*"), site]:
        path.chmod(stat.S_IMODE(path.stat().st_mode) & ~0o222)
    blocked = tmp_path / "blocked"
    blocked.write_text("a file: nothing can be made below it")
    temp = tmp_path / "tmp"
    temp.mkdir()
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME")}
    env.update(HOME=str(blocked / "home"), TMPDIR=str(temp), PYTHONPATH=str(site),
               PYTHONDONTWRITEBYTECODE="1")  # fmt: skip
    return env, temp


#: imports both packages from the copy and calls one small compiled kernel
KERNEL = """
import os, sys
import chaoskit, mechanism
from chaoskit.systems import logistic
assert chaoskit.__file__.startswith(sys.path[1]), chaoskit.__file__
print(round(float(logistic(5, r=3.5, discard=0)[-1]), 6), os.environ.get("NUMBA_CACHE_DIR"))
"""


def _python(code: str, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600,
        cwd=env["TMPDIR"],
    )  # fmt: skip


def _warnings(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "Warning" in line]


def test_a_read_only_install_caches_its_kernels_in_a_private_folder(tmp_path: Path) -> None:
    env, temp = _read_only_install(tmp_path)
    runs = [_python(KERNEL, env) for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr
        assert _warnings(run.stderr) == [], run.stderr
    folder = temp / f"chaoskit-numba-{os.getuid()}"
    assert runs[0].stdout.split() == ["0.390829", str(folder)]
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    index = list(folder.rglob("_systems_kernels.logistic-*.nbi"))
    assert len(index) == 1  # compiled once, loaded by the second run
    cli = subprocess.run(
        [sys.executable, "-c", "import sys; from mechanism.cli import app; app()", "--version"],
        capture_output=True, text=True, env=env, timeout=600, cwd=str(temp),
    )  # fmt: skip
    assert cli.returncode == 0, cli.stderr
    assert cli.stdout.startswith("mechanism (chaoskit ")
    assert _warnings(cli.stderr) == []


@pytest.mark.parametrize("case", ["no temporary folder", "a folder others can write"])
def test_with_no_cache_folder_kernels_compile_uncached_after_one_warning(
    tmp_path: Path, case: str
) -> None:
    env, temp = _read_only_install(tmp_path)
    if case == "no temporary folder":
        # every place a temporary folder could be is refused
        code = f"import tempfile; tempfile.tempdir = {str(tmp_path / 'blocked' / 't')!r}\n"
    else:
        # a folder of that name that is not private is never used (its caches could be
        # anyone's code)
        shared = temp / f"chaoskit-numba-{os.getuid()}"
        shared.mkdir()
        shared.chmod(0o777)
        code = ""
    run = _python(code + KERNEL, env)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["0.390829", "None"]
    (warning,) = _warnings(run.stderr)
    assert "RuntimeWarning: no writable folder for compiled-kernel caches" in warning
    assert "set NUMBA_CACHE_DIR to a writable folder" in warning
    assert not list(temp.rglob("*.nbi"))
