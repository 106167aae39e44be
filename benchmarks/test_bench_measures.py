"""Timings of the measures toolbox (warm JIT).

Targets: correlation dimension at N = 5·10⁴ with 5 embedding dimensions in at most half
TISEAN ``d2``'s time (the side-by-side ratio is measured by ``measures_vs_peers.py``);
N = 10⁵ with defaults in seconds; RQA at N = 2·10⁴ faster than pyunicorn. Run with
``python -m pytest benchmarks/test_bench_measures.py --benchmark-only``.
"""

from __future__ import annotations

import numpy as np
import pytest

from chaoskit import correlation_dimension, lyapunov_spectrum, recurrence_analysis, systems


@pytest.fixture(scope="module")
def lorenz_x() -> np.ndarray:
    return systems.lorenz(100_000, dt=0.01)[:, 0]


@pytest.fixture(scope="module", autouse=True)
def _warm_up() -> None:
    x = systems.henon(2000)[:, 0]
    correlation_dimension(x, embedding_dims=[1, 2], lag=1)
    lyapunov_spectrum(x, embedding_dim=2, lag=1, spurious_check="none")


def test_d2_50k_five_dims(benchmark, lorenz_x) -> None:
    x = lorenz_x[:50_000].copy()
    res = benchmark(
        correlation_dimension, x, embedding_dims=[1, 2, 3, 4, 5], lag=10, theiler_window=50
    )
    benchmark.extra_info.update(d2=res.d2)


def test_d2_100k_defaults(benchmark, lorenz_x) -> None:
    res = benchmark.pedantic(correlation_dimension, args=(lorenz_x,), rounds=2, iterations=1)
    benchmark.extra_info.update(d2=res.d2)


def test_rqa_20k(benchmark, lorenz_x) -> None:
    x = lorenz_x[:20_000].copy()
    res = benchmark.pedantic(
        recurrence_analysis,
        args=(x,),
        kwargs={"embedding_dim": 3, "lag": 10, "threshold": 2.0, "norm": "chebyshev"},
        rounds=2,
        iterations=1,
    )
    benchmark.extra_info.update(det=res.determinism)


def test_spectrum_lorenz_50k(benchmark, lorenz_x) -> None:
    x = lorenz_x[:50_000].copy()
    res = benchmark.pedantic(
        lyapunov_spectrum,
        args=(x,),
        kwargs={"embedding_dim": 4, "lag": 8, "dt": 0.01, "step": 10},
        rounds=2,
        iterations=1,
    )
    benchmark.extra_info.update(lambda_1=float(res.exponents[0]))
