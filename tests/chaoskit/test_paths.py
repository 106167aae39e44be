"""Names from user data never become paths outside the folder they are written to."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from chaoskit import systems
from chaoskit._paths import safe_filename, unique_filename
from chaoskit.cli import app


@settings(max_examples=300, deadline=None)
@given(name=st.text(max_size=120))
def test_any_name_is_one_harmless_path_component(name: str) -> None:
    folder = Path("/some/folder")
    for out in (safe_filename(name), unique_filename(name)):
        assert out and "/" not in out and "\\" not in out and "\x00" not in out
        assert not out.startswith(".")
        assert (folder / out).parent == folder
        assert (folder / out).resolve().parent == folder.resolve()
    assert len(safe_filename(name)) <= 80


def test_names_that_sanitise_alike_stay_apart() -> None:
    assert unique_filename("a/b") != unique_filename("a_b") == "a_b"
    assert unique_filename("../x") != unique_filename("..x")


def test_analyze_writes_every_figure_inside_the_requested_folder(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    figures = tmp_path / "run" / "figs"
    evil_abs = str(outside / "abs")
    xy = systems.henon(600)
    frame = pd.DataFrame(
        {"time": np.arange(600) * 0.01, evil_abs: xy[:, 0], "../../escape": xy[:, 1]}
    )
    csv = tmp_path / "evil.csv"
    frame.to_csv(csv, index=False)
    out = CliRunner().invoke(app, ["analyze", str(csv), "--figures", str(figures)])
    assert out.exit_code == 0, out.output
    inside = sorted(p for p in figures.rglob("*.png"))
    everywhere = sorted(p for p in tmp_path.rglob("*.png"))
    assert inside and everywhere == inside
    assert all(p.parent == figures for p in inside)
    assert not outside.exists()
