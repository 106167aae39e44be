"""Views and verdict: sections, 0–1 test, surrogates, classify and analyze.

No speed target is set by the issue; these show what a call costs. Run with
``python -m pytest benchmarks/test_bench_verdict.py --benchmark-only`` (JIT warmed up first).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import chaoskit
from chaoskit import (
    analyze,
    classify,
    iaaft_surrogates,
    poincare_section,
    stroboscopic_map,
    systems,
    zero_one_test,
)


@pytest.fixture(scope="module", autouse=True)
def _warm_up() -> None:
    classify(systems.logistic(600, r=3.9), rng=0)
    classify(systems.lorenz(3000)[:, 0], dt=0.01, rng=0)


@pytest.fixture(scope="module")
def lorenz_ds() -> xr.Dataset:
    return chaoskit.load_trajectory(systems.lorenz(1_000_000), dt=0.01, variables=["x", "y", "z"])


def test_poincare_section_1e6_samples(benchmark, lorenz_ds) -> None:
    sec = benchmark(poincare_section, lorenz_ds, variable="z", level=27.0, direction="up")
    assert sec.sizes["crossing"] > 1000


def test_stroboscopic_map_1e6_samples(benchmark, lorenz_ds) -> None:
    strobe = benchmark(stroboscopic_map, lorenz_ds, period=0.75)
    assert strobe.sizes["crossing"] > 10_000


def test_zero_one_test_n5000(benchmark) -> None:
    x = systems.logistic(5000, r=3.9)
    assert benchmark(zero_one_test, x, rng=0).k > 0.9


def test_iaaft_19_surrogates_n4096(benchmark) -> None:
    x = systems.lorenz(4096)[:, 0]
    s = benchmark(iaaft_surrogates, x, n_surrogates=19, max_iter=100, rng=0)
    assert s.shape == (19, 4096)


@pytest.mark.parametrize("n", [2_000, 10_000])
def test_classify_lorenz(benchmark, n: int) -> None:
    x = systems.lorenz(n)[:, 0]
    verdict = benchmark.pedantic(classify, args=(x,), kwargs={"dt": 0.01, "rng": 0}, rounds=3)
    assert verdict.label in ("chaotic", "undetermined")


def test_analyze_sample_file(benchmark) -> None:
    ds = chaoskit.load_trajectory("data/lorenz.nc")
    table = benchmark.pedantic(analyze, args=(ds,), kwargs={"rng": 0}, rounds=2)
    assert table.sizes["variable"] == 3


def test_classify_white_noise(benchmark) -> None:
    x = np.random.default_rng(0).standard_normal(5000)
    assert benchmark.pedantic(classify, args=(x,), kwargs={"rng": 0}, rounds=3).label == (
        "noise-like"
    )
