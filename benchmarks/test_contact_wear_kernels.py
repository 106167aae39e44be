"""Contact, friction and wear kernels per evaluation.

The integrator evaluates one normal force and one friction force per clearance joint and
right-hand side; with wear on it also looks up the local clearance and stiffness, and after
each accepted step adds one Archard increment per worn surface. The loops below run inside
numba, so the numbers are the kernels' own cost without Python dispatch. Run with
``python -m pytest benchmarks/test_contact_wear_kernels.py --benchmark-only``.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from mechanism.core.contact import _kernels as ck
from mechanism.core.wear import WornProfile, archard_wear
from mechanism.core.wear import _kernels as wk

RB, C0, L = 0.015, 2e-4, 0.011
E_STAR = 113.736e9
K = 1.309e10
SAMPLES = 100_000


@njit(cache=False)
def _contact_loop(delta, rate, vt, law, friction):
    total = 0.0
    for i in range(delta.size):
        fn = ck.normal_force(law, K, 1.5, 0.9, delta[i], rate[i], 0.2)
        total += fn + ck.friction_force(friction, 0.15, 1e-4, 2e-4, fn, vt[i])
    return total


@njit(cache=False)
def _worn_contact_loop(hb, hj, phi, ecc, rate):
    total = 0.0
    for i in range(phi.size):
        c = wk.local_clearance(C0, hb, hj, phi[i], 0.3 * phi[i])
        kn = wk.local_stiffness(E_STAR, 1, RB, RB - C0, hb, hj, phi[i], 0.3 * phi[i], 5, 10.0)
        total += ck.normal_force(0, kn, 1.5, 0.9, ecc[i] - c, rate[i], 0.2)
    return total


@njit(cache=False)
def _worn_contact_loop_tabulated(kb, kj, hb, hj, phi, ecc, rate):
    total = 0.0
    for i in range(phi.size):
        c = wk.local_clearance(C0, hb, hj, phi[i], 0.3 * phi[i])
        kn = wk.local_stiffness_tabulated(
            E_STAR, 1, RB, RB - C0, kb, kj, phi[i], 0.3 * phi[i], 10.0
        )
        total += ck.normal_force(0, kn, 1.5, 0.9, ecc[i] - c, rate[i], 0.2)
    return total


@njit(cache=False)
def _archard_loop(hb, phi, force, slip, half_width):
    applied = 0.0
    for i in range(phi.size):
        _status, v = wk.archard_increment(
            hb, phi[i], force[i], slip[i], 1.827e-13, RB, L, half_width, True, 1e-6
        )
        applied += v
    return applied


def _inputs():
    rng = np.random.default_rng(0)
    return (
        rng.uniform(-2e-5, 8e-5, SAMPLES),
        rng.uniform(-0.5, 0.5, SAMPLES),
        rng.uniform(-1e-3, 1e-3, SAMPLES),
        rng.uniform(0, 2 * np.pi, SAMPLES),
    )


@pytest.mark.parametrize("law", ["lankarani-nikravesh", "hu-guo"])
def test_normal_and_friction_force(benchmark, law: str) -> None:
    delta, rate, vt, _ = _inputs()
    code = ck.LAW_LANKARANI_NIKRAVESH if law == "lankarani-nikravesh" else ck.LAW_HU_GUO
    _contact_loop(delta, rate, vt, code, ck.FRICTION_AMBROSIO)  # compile
    benchmark(_contact_loop, delta, rate, vt, code, ck.FRICTION_AMBROSIO)
    benchmark.extra_info["evaluations"] = SAMPLES


@pytest.mark.parametrize("curvature", ["on-the-fly", "tabulated"])
def test_worn_contact_lookup(benchmark, curvature: str) -> None:
    _, rate, _, phi = _inputs()
    rng = np.random.default_rng(1)
    hb = rng.uniform(0, 2e-5, 360)
    hj = rng.uniform(0, 5e-6, 360)
    ecc = C0 + rng.uniform(-2e-5, 6e-5, SAMPLES)
    if curvature == "tabulated":
        p = WornProfile(
            bearing_radius=RB, clearance=C0, length=L, bearing_depth=hb, journal_depth=hj
        )
        args = (p.curvature(surface="bearing"), p.curvature(surface="journal"), hb, hj)
        _worn_contact_loop_tabulated(*args, phi, ecc, rate)
        benchmark(_worn_contact_loop_tabulated, *args, phi, ecc, rate)
    else:
        _worn_contact_loop(hb, hj, phi, ecc, rate)
        benchmark(_worn_contact_loop, hb, hj, phi, ecc, rate)
    benchmark.extra_info["evaluations"] = SAMPLES


@pytest.mark.parametrize("half_width", [0.0, 1e-4, 1e-3])
def test_archard_increment(benchmark, half_width: float) -> None:
    _, _, _, phi = _inputs()
    rng = np.random.default_rng(2)
    force = rng.uniform(0, 5e3, SAMPLES)
    slip = rng.uniform(0, 1e-5, SAMPLES)
    _archard_loop(np.zeros(360), phi, force, slip, half_width)
    benchmark(lambda: _archard_loop(np.zeros(360), phi, force, slip, half_width))
    benchmark.extra_info["evaluations"] = SAMPLES


def test_archard_wear_one_cycle(benchmark) -> None:
    # one crank cycle at the paper's output step (10 000 samples), both surfaces, spread
    rng = np.random.default_rng(3)
    n = 10_000
    kw = dict(
        bearing_angle=rng.uniform(1.3, 2.3, n),
        journal_angle=rng.uniform(0, 2 * np.pi, n),
        normal_force=rng.uniform(0, 9e3, n),
        slip=rng.uniform(0, 1e-5, n),
        coefficient=1.827e-13,
        effective_modulus=E_STAR,
    )
    profile = WornProfile.unworn(bearing_radius=RB, clearance=C0, length=L)
    archard_wear(profile, **kw)
    benchmark(archard_wear, profile, **kw)
