"""``chaoskit analyze --denoise``: explicit noise reduction before the analysis, stated in
the output and in the data's attributes, never applied without the option."""

from __future__ import annotations

import re

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import chaoskit
from chaoskit import systems
from chaoskit.cli import _denoise, app

runner = CliRunner()


def _noisy_henon(n: int = 2000, level: float = 0.05) -> np.ndarray:
    x = systems.henon(n)[:, 0]
    return x + level * x.std() * np.random.default_rng(3).standard_normal(n)


def _csv(tmp_path, x: np.ndarray) -> str:
    path = tmp_path / "henon.csv"
    path.write_text("x\n" + "\n".join(f"{v:.12g}" for v in x) + "\n", encoding="utf-8")
    return str(path)


def test_denoise_is_stated_with_the_parameters_chosen_from_the_data(tmp_path) -> None:
    """The line names the method and the parameters that local_projective_denoise chose
    for the same series, and the analysis runs on the cleaned series."""
    x = _noisy_henon()
    out = runner.invoke(app, ["analyze", _csv(tmp_path, x), "--step", "step", "--denoise"])
    assert out.exit_code == 0, out.output
    ref = chaoskit.local_projective_denoise(x)
    line = next(s for s in out.output.splitlines() if s.strip().startswith("denoised x:"))
    assert "local projective noise reduction" in line
    expected = (
        f"embedding_dim={ref.embedding_dim}, lag={ref.lag}, "
        f"manifold_dim={ref.manifold_dim}, iterations=3"
    )
    assert expected in line
    share = float(re.search(r"\(([0-9.]+) % of the standard deviation\)", line).group(1))
    assert share == pytest.approx(100 * ref.noise_level / ref.original.std(), rel=1e-3)
    assert re.search(r"^x +chaotic", out.output, re.MULTILINE), out.output


def test_denoise_iterations_are_passed_on(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _csv(tmp_path, _noisy_henon(600)), "--step", "step",
                              "--denoise", "--denoise-iterations", "1"])  # fmt: skip
    assert out.exit_code == 0, out.output
    line = next(s for s in out.output.splitlines() if "denoised x:" in s)
    assert "iterations=1," in line
    assert len(re.search(r"correction_rms=(.*)$", line).group(1).split(",")) == 1


def test_without_the_option_nothing_is_denoised(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _csv(tmp_path, _noisy_henon(600)), "--step", "step"])
    assert out.exit_code == 0, out.output
    assert "denoised" not in out.output


@pytest.mark.parametrize("value", ["0", "101", "-3"])
def test_bad_iteration_counts_exit_2_with_one_line(tmp_path, value) -> None:
    out = runner.invoke(app, ["analyze", _csv(tmp_path, _noisy_henon(400)), "--step", "step",
                              "--denoise", "--denoise-iterations", value])  # fmt: skip
    assert out.exit_code == 2
    assert out.output.strip() == f"error: --denoise-iterations must be in [1, 100]; got {value}."


def test_a_series_too_short_to_denoise_exits_2_with_one_line(tmp_path) -> None:
    out = runner.invoke(app, ["analyze", _csv(tmp_path, _noisy_henon(150)), "--step", "step",
                              "--denoise"])  # fmt: skip
    assert out.exit_code == 2
    last = out.output.strip().splitlines()[-1]
    assert last.startswith("error: ") and "samples" in last
    assert "Traceback" not in out.output


def test_a_selected_label_is_cleaned_in_place_and_recorded() -> None:
    """A series picked by label from a two-dimensional variable is replaced where it sits;
    the other label is untouched; the attribute and the history say what was done."""
    x = _noisy_henon(1000)
    other = np.arange(1000.0)
    ds = xr.Dataset(
        {"e": (("step", "joint"), np.column_stack([x, other]), {"units": "m", "long_name": "e"})},
        coords={"step": np.arange(1000), "joint": ["B", "C"]},
        attrs={"history": "made by a test"},
    )
    out, lines = _denoise(ds, ["e[joint=B]"], 2)
    ref = chaoskit.local_projective_denoise(ds["e"].sel(joint="B"), iterations=2)
    np.testing.assert_array_equal(out["e"].sel(joint="B").values, ref.cleaned)
    np.testing.assert_array_equal(out["e"].sel(joint="C").values, other)
    np.testing.assert_array_equal(ds["e"].sel(joint="B").values, x)  # the input is kept
    assert out["e"].attrs["units"] == "m"
    assert out["e"].attrs["denoised"].startswith("e[joint=B]: local projective")
    history = out.attrs["history"].splitlines()
    assert history[0] == "made by a test"
    assert history[1].startswith("e[joint=B] denoised by chaoskit analyze --denoise: ")
    assert lines == [f"  denoised e[joint=B]: {out['e'].attrs['denoised'][12:]}"]
