"""Architecture rules: chaoskit never imports mechanism; the layout the issues promise exists."""

from __future__ import annotations

import ast
import subprocess
import sys

import pytest

from tests.conftest import REPO


def _imported_modules(path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module.split(".")[0])
    return names


def test_chaoskit_sources_never_import_mechanism() -> None:
    offenders = [
        str(p.relative_to(REPO))
        for p in (REPO / "chaoskit").rglob("*.py")
        if "mechanism" in _imported_modules(p)
    ]
    assert offenders == []


def test_importing_chaoskit_does_not_load_mechanism() -> None:
    code = "import sys, chaoskit, chaoskit.cli; sys.exit('mechanism' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0


@pytest.mark.parametrize(
    "name",
    [
        "pyproject.toml",
        "README.md",
        "chaoskit",
        "mechanism",
        "tests",
        "data",
        "notebooks",
        "benchmarks",
        "docs",
        ".ci/run",
        "constraints.txt",
    ],
)
def test_top_level_layout(name: str) -> None:
    assert (REPO / name).exists()


def test_public_api_is_curated() -> None:
    import chaoskit
    import mechanism

    for pkg in (chaoskit, mechanism):
        assert pkg.__all__, pkg.__name__
        for name in pkg.__all__:
            assert not name.startswith("_") or name == "__version__"
            assert hasattr(pkg, name), f"{pkg.__name__}.{name} is listed but missing"


def test_constraints_pin_exact_versions() -> None:
    lines = [
        ln.strip()
        for ln in (REPO / "constraints.txt").read_text().splitlines()
        if ln.strip() and not ln.startswith("#")
    ]
    assert lines and all("==" in ln for ln in lines)
    names = {ln.split("==")[0].lower() for ln in lines}
    for required in ("numpy", "scipy", "numba", "xarray", "h5netcdf", "nolds", "pytest"):
        assert required in names
