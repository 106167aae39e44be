"""Friction laws of the clearance joint: closed forms, continuity, limits, dissipation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from mechanism.core.contact import _kernels as k

pytestmark = pytest.mark.filterwarnings("error")

MU = 0.15
FN = 1234.0
V0, V1 = 1e-4, 2e-4


def friction(law: int, vt: float, fn: float = FN) -> float:
    return k.friction_force(law, MU, V0, V1, fn, vt)


def test_no_friction_and_no_load_give_zero() -> None:
    for vt in (-1.0, 0.0, 1e-5, 3.0):
        assert friction(k.FRICTION_NONE, vt) == 0.0
        for law in (k.FRICTION_COULOMB, k.FRICTION_AMBROSIO):
            assert friction(law, vt, fn=0.0) == 0.0
            assert friction(law, vt, fn=-5.0) == 0.0


@pytest.mark.parametrize("vt", [-3e-3, -1.5e-4, -2e-5, 0.0, 2e-5, 1e-4, 1.7e-4, 5e-4, 2.0])
def test_coulomb_closed_form(vt) -> None:
    assert_allclose(
        friction(k.FRICTION_COULOMB, vt), -MU * FN * math.tanh(vt / V0), rtol=1e-14, atol=1e-300
    )


def _ambrosio(vt: float) -> float:
    s = abs(vt)
    cd = 0.0 if s <= V0 else 1.0 if s >= V1 else (s - V0) / (V1 - V0)
    return -MU * cd * FN * np.sign(vt)


@pytest.mark.parametrize("vt", [-3e-3, -1.5e-4, -2e-5, 0.0, 2e-5, 1e-4, 1.25e-4, 1.7e-4, 2.0])
def test_ambrosio_closed_form(vt) -> None:
    assert_allclose(friction(k.FRICTION_AMBROSIO, vt), _ambrosio(vt), rtol=1e-14, atol=0.0)


def test_ambrosio_dynamic_correction_breakpoints() -> None:
    assert k.ambrosio_factor(0.0, V0, V1) == 0.0
    assert k.ambrosio_factor(V0, V0, V1) == 0.0
    assert_allclose(k.ambrosio_factor(0.5 * (V0 + V1), V0, V1), 0.5, rtol=1e-14)
    assert k.ambrosio_factor(V1, V0, V1) == 1.0
    assert k.ambrosio_factor(10 * V1, V0, V1) == 1.0


@pytest.mark.parametrize("law", [k.FRICTION_COULOMB, k.FRICTION_AMBROSIO])
def test_friction_is_continuous_in_the_sliding_speed(law) -> None:
    # no jump anywhere, in particular at 0, v0 and v1: the slope is bounded by μFₙ/v0
    # (Coulomb) or μFₙ/(v1 − v0) (Ambrósio)
    v = np.linspace(-5 * V1, 5 * V1, 200_001)
    f = np.array([friction(law, x) for x in v])
    slope = MU * FN / (V0 if law == k.FRICTION_COULOMB else V1 - V0)
    assert np.max(np.abs(np.diff(f))) <= slope * (v[1] - v[0]) * (1 + 1e-9)
    for point in (0.0, V0, V1, -V0, -V1):
        eps = 1e-12
        assert abs(friction(law, point + eps) - friction(law, point - eps)) < 1e-5 * MU * FN


@pytest.mark.parametrize("law", [k.FRICTION_COULOMB, k.FRICTION_AMBROSIO])
def test_friction_limits_opposition_and_odd_symmetry(law) -> None:
    rng = np.random.default_rng(3)
    for vt in np.concatenate([rng.normal(0, 3 * V1, 500), rng.normal(0, 1.0, 500)]):
        f = friction(law, vt)
        assert f * vt <= 0.0  # never drives the sliding: dissipative
        assert abs(f) <= MU * FN * (1 + 1e-15)
        assert friction(law, -vt) == -f
    # fully developed sliding: |F| = μ Fₙ
    for vt in (50 * V1, -50 * V1, 1.0, -10.0):
        assert_allclose(abs(friction(law, vt)), MU * FN, rtol=1e-14)
    assert friction(law, 0.0) == 0.0


def test_ambrosio_sticks_below_v0_coulomb_does_not() -> None:
    # the two regularisations differ below v0: Ambrósio has no force at all there
    assert friction(k.FRICTION_AMBROSIO, 0.5 * V0) == 0.0
    assert_allclose(friction(k.FRICTION_COULOMB, 0.5 * V0), -MU * FN * math.tanh(0.5), rtol=1e-14)
