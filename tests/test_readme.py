"""The README's commands and CI stay in step."""

from __future__ import annotations

import re

from tests.conftest import REPO


def _bash_blocks(text: str) -> list[str]:
    return [b.strip() for b in re.findall(r"```bash\n(.*?)```", text, flags=re.S)]


def test_readme_has_exactly_two_setup_commands() -> None:
    blocks = _bash_blocks((REPO / "README.md").read_text())
    assert len(blocks) == 2
    assert all(len(b.splitlines()) == 1 for b in blocks)
    assert blocks[0].startswith("python -m pip install .")


def test_ci_runs_the_readme_test_command_verbatim() -> None:
    test_command = _bash_blocks((REPO / "README.md").read_text())[1]
    ci_lines = [ln.strip() for ln in (REPO / ".ci" / "run").read_text().splitlines()]
    assert test_command in ci_lines


def test_ci_script_is_strict_bash() -> None:
    text = (REPO / ".ci" / "run").read_text()
    assert text.startswith("#!/usr/bin/env bash")
    assert "set -euo pipefail" in text
    assert "venv" in text
