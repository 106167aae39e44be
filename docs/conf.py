"""Sphinx configuration of the documentation site.

Build it from the repository root (the test suite runs the same build)::

    python -m sphinx -n -W --keep-going -b html docs docs/_build/html

The Markdown pages are read by MyST, the API reference is written by autodoc from the
numpydoc docstrings, and the notebooks (jupytext percent files in ``notebooks/``) are
rendered without being executed. ``-n`` (nitpicky) with ``-W`` makes every cross-reference
to a first-party name an error when it does not resolve; third-party names are not
checked, since the build runs without network access to their inventories.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import chaoskit

HERE = Path(__file__).resolve().parent
NOTEBOOKS = HERE.parent / "notebooks"
RENDERED = HERE / "notebooks"

project = "chaoskit"
author = "the chaoskit developers"
release = chaoskit.__version__
version = release

extensions = ["sphinx.ext.autodoc", "numpydoc", "myst_nb"]
source_suffix = {".md": "myst-nb", ".py": "myst-nb"}
nb_custom_formats = {".py": ["jupytext.reads", {"fmt": "py:percent"}]}
nb_execution_mode = "off"
myst_heading_anchors = 3
myst_enable_extensions = ["dollarmath"]

exclude_patterns = ["_build", "benchmarks", "make_api.py", "conf.py", "README.md"]
html_theme = "alabaster"

autodoc_typehints = "none"
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

nitpicky = True
# GitHub draws the ```mermaid diagrams of the Markdown pages; Pygments has no lexer for them
suppress_warnings = ["misc.highlighting_failure"]
_THIRD_PARTY = (
    r"(numpy|np|xarray|xr|pandas|pd|scipy|matplotlib|dask|distributed|os|pathlib|"
    r"collections|typing|numba|h5py|nolds|jinja2|datetime|enum|io)(\..*)?"
)
nitpick_ignore_regex = [
    ("py:.*", _THIRD_PARTY),
    ("py:class", r"(int|float|str|bool|complex|dict|list|tuple|None|callable|object|bytes)"),
    ("py:class", r"(optional|array_like|array-like|sequence|mapping|iterable|path-like)"),
]


def _copy_notebooks(app: object) -> None:
    """The notebooks live outside the source folder: render copies of them."""
    RENDERED.mkdir(exist_ok=True)
    for path in sorted(NOTEBOOKS.glob("[0-9]*.py")):
        target = RENDERED / path.name
        if not target.exists() or target.read_bytes() != path.read_bytes():
            shutil.copyfile(path, target)


def setup(app: object) -> None:
    app.connect("builder-inited", _copy_notebooks)  # type: ignore[attr-defined]
