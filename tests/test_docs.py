"""The documentation site: every public name is documented once, and the site builds.

The API reference is written by Sphinx autodoc from the docstrings
(``docs/reference/*.md``); the build runs in nitpicky mode with warnings as errors, so a
docstring that names a function, class or module that does not exist fails it.
"""

from __future__ import annotations

import dataclasses
import inspect
import re
import subprocess
import sys
import types
from pathlib import Path

import pytest

import chaoskit
import chaoskit.plot
import mechanism
from tests.conftest import REPO

DOCS = REPO / "docs"
NAMESPACES = (chaoskit, chaoskit.plot, mechanism)
DIRECTIVE = re.compile(r"^\.\. auto(?:function|class|exception|data)::\s+([\w.]+)\s*$", re.M)


def first_paragraph(obj: object) -> str:
    """The first paragraph of ``obj``'s own docstring on one line ("" if it has none)."""
    own = isinstance(obj, type | types.FunctionType | types.BuiltinFunctionType)
    doc = inspect.getdoc(obj) if own else None
    if not doc or (isinstance(obj, type) and doc.startswith(f"{obj.__name__}(")):
        return ""  # dataclasses put their signature where a docstring is missing
    return " ".join(doc.strip().split("\n\n", 1)[0].split())


def _public() -> list[str]:
    return [
        f"{ns.__name__}.{name}" for ns in NAMESPACES for name in ns.__all__ if name != "__version__"
    ]


def _documented() -> list[str]:
    return [
        name
        for page in sorted((DOCS / "reference").glob("*.md"))
        for name in DIRECTIVE.findall(page.read_text(encoding="utf-8"))
    ]


def test_public_names_are_not_modules() -> None:
    modules = [n for n in _public() if isinstance(_resolve(n), types.ModuleType)]
    assert modules == [], "modules are not listed in __all__; they have reference pages"


def test_every_public_name_has_one_reference_entry() -> None:
    documented = _documented()
    twice = sorted({n for n in documented if documented.count(n) > 1})
    assert twice == []
    assert set(_public()) - set(documented) == set(), "add it to a page in docs/reference"
    assert set(documented) - set(_public()) == set(), "the page names what is not public"


def _resolve(dotted: str) -> object:
    module, _, name = dotted.rpartition(".")
    return getattr(sys.modules[module], name)


@pytest.mark.parametrize("dotted", _public())
def test_public_name_is_documented(dotted: str) -> None:
    obj = _resolve(dotted)
    if not isinstance(obj, type | types.FunctionType):
        pytest.skip("plain data carries its type's docstring")
    assert len(first_paragraph(obj)) >= 10, f"{dotted} has no docstring of its own"


def test_first_paragraph_ignores_dataclass_default_doc() -> None:
    @dataclasses.dataclass(frozen=True)
    class Bare:
        x: int = 0

    @dataclasses.dataclass(frozen=True)
    class Documented:
        """One line
        on two.

        More text.
        """

        x: int = 0

    assert first_paragraph(Bare) == ""
    assert first_paragraph(Documented) == "One line on two."


def test_reference_directives_are_found() -> None:
    text = "```{eval-rst}\n.. autofunction:: chaoskit.classify\n.. autoclass:: a.B\n```\n"
    assert DIRECTIVE.findall(text) == ["chaoskit.classify", "a.B"]


def test_site_builds_nitpicky_without_warnings(tmp_path: Path) -> None:
    """Every cross-reference of the docstrings and pages resolves (-n), no warning (-W)."""
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-n",
            "-W",
            "--keep-going",
            "-q",
            "-b",
            "html",
            "-d",
            str(tmp_path / "doctrees"),
            str(DOCS),
            str(tmp_path / "html"),
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=600,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    assert (tmp_path / "html" / "reference" / "chaoskit.html").is_file()
