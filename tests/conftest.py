"""Shared test configuration."""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

REPO = Path(__file__).resolve().parents[1]


def verdict_docs_block(name: str) -> str:
    """The text between ``<!-- NAME ... -->`` and ``<!-- /NAME -->`` of docs/verdict.md."""
    page = (REPO / "docs" / "verdict.md").read_text(encoding="utf-8")
    block = page[page.index(f"<!-- {name}") : page.index(f"<!-- /{name} -->")]
    return block[block.index("-->") + 3 :]
