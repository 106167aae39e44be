"""Estimator timings: delay, dimension and largest Lyapunov exponent.

Targets: Rosenstein on Lorenz x, N = 50,000, defaults (delay and dimension estimation
included) ≤ 0.2 s warm; N = 10^6 ≤ 10 s and ≤ 1 GB; ≥ 100× faster than ``nolds.lyap_r`` at
N = 10,000 with the same parameters; FNN m = 1…10 on N = 10^5 ≤ 3 s; MI to lag 100 on
N = 10^6 ≤ 2 s; Wolf on the Hénon and logistic maps, N = 10^5, ≤ 1 s. Run with
``python -m pytest benchmarks/test_bench_estimators.py --benchmark-only`` (JIT warmed up
before timing). Peak memory of the 10^6 case is measured in a fresh process by
``benchmarks/mle_accuracy_vs_n.py``.
"""

from __future__ import annotations

import nolds
import numpy as np
import pytest

from chaoskit import (
    estimate_delay,
    false_nearest_neighbors,
    lyapunov_rosenstein,
    lyapunov_wolf,
    mutual_information,
    systems,
)


@pytest.fixture(scope="module")
def lorenz_x() -> np.ndarray:
    return systems.lorenz(1_000_000, dt=0.01)[:, 0]


@pytest.fixture(scope="module", autouse=True)
def _warm_up() -> None:
    x = systems.lorenz(3000)[:, 0]
    lyapunov_rosenstein(x, dt=0.01)
    lyapunov_wolf(x, dt=0.01)


@pytest.mark.parametrize("n", [10_000, 50_000])
def test_rosenstein_defaults(benchmark, lorenz_x, n: int) -> None:
    x = lorenz_x[:n].copy()
    res = benchmark(lyapunov_rosenstein, x, dt=0.01)
    benchmark.extra_info.update(mle=res.mle, lag=res.lag, embedding_dim=res.embedding_dim)


def test_rosenstein_defaults_1e6(benchmark, lorenz_x) -> None:
    res = benchmark.pedantic(
        lyapunov_rosenstein, args=(lorenz_x,), kwargs={"dt": 0.01}, rounds=2, iterations=1
    )
    benchmark.extra_info.update(mle=res.mle, n_points=res.n_points)


def test_rosenstein_same_parameters_as_nolds(benchmark, lorenz_x) -> None:
    x = lorenz_x[:10_000].copy()
    kw = {
        "embedding_dim": 3,
        "lag": 17,
        "dt": 0.01,
        "theiler_window": 167,
        "max_horizon": 300,
        "fit_range": (60, 300),
        "max_points": 10**6,
        "neighbor": "sample",  # nolds pairs nearest samples
    }
    res = benchmark(lyapunov_rosenstein, x, **kw)
    benchmark.extra_info.update(mle=res.mle)


def test_nolds_lyap_r_10k(benchmark, lorenz_x) -> None:
    x = lorenz_x[:10_000].copy()
    kw = {
        "emb_dim": 3,
        "lag": 17,
        "tau": 0.01,
        "min_tsep": 167,
        "trajectory_len": 301,
        "fit": "poly",
        "fit_offset": 60,
    }
    res = benchmark.pedantic(nolds.lyap_r, args=(x,), kwargs=kw, rounds=2, iterations=1)
    benchmark.extra_info.update(mle=float(res))


@pytest.mark.parametrize("n", [10_000, 50_000])
def test_wolf_defaults(benchmark, lorenz_x, n: int) -> None:
    res = benchmark(lyapunov_wolf, lorenz_x[:n].copy(), dt=0.01)
    benchmark.extra_info.update(mle=res.mle)


@pytest.mark.parametrize("system", ["henon", "logistic"])
def test_wolf_maps_1e5(benchmark, system: str) -> None:
    """Maps replace the neighbour every 1–2 samples: the compiled loop's worst case."""
    x = systems.henon(100_000)[:, 0] if system == "henon" else systems.logistic(100_000)
    lyapunov_wolf(x[:2000])  # warm-up of this input's code path
    res = benchmark.pedantic(lyapunov_wolf, args=(x,), rounds=3, iterations=1)
    benchmark.extra_info.update(mle=res.mle, replacements=res.n_points)


def test_fnn_1e5(benchmark, lorenz_x) -> None:
    x = lorenz_x[:100_000].copy()
    res = benchmark.pedantic(
        false_nearest_neighbors,
        args=(x,),
        kwargs={"lag": 17, "max_dim": 10},
        rounds=3,
        iterations=1,
    )
    benchmark.extra_info.update(embedding_dim=res.embedding_dim)


def test_mutual_information_1e6(benchmark, lorenz_x) -> None:
    res = benchmark.pedantic(
        mutual_information, args=(lorenz_x,), kwargs={"max_lag": 100}, rounds=3, iterations=1
    )
    benchmark.extra_info.update(first_value=float(res.curve[1]))


def test_estimate_delay_1e6(benchmark, lorenz_x) -> None:
    res = benchmark.pedantic(estimate_delay, args=(lorenz_x,), rounds=3, iterations=1)
    benchmark.extra_info.update(lag=res.lag)
