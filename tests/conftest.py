"""Shared test configuration."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib
from hypothesis import settings

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

# The default run draws the same examples every time (a red run is reproducible and a
# green one stays green); HYPOTHESIS_PROFILE=explore searches afresh, as a fuzz run should.
settings.register_profile("default", derandomize=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))

REPO = Path(__file__).resolve().parents[1]


def verdict_docs_block(name: str) -> str:
    """The text between ``<!-- NAME ... -->`` and ``<!-- /NAME -->`` of docs/verdict.md."""
    page = (REPO / "docs" / "verdict.md").read_text(encoding="utf-8")
    block = page[page.index(f"<!-- {name}") : page.index(f"<!-- /{name} -->")]
    return block[block.index("-->") + 3 :]
