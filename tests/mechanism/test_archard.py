"""Archard wear bookkeeping."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.integrate import quad

from mechanism.core.contact import effective_modulus, effective_radius
from mechanism.core.scene import Material
from mechanism.core.wear import WornProfile, archard_wear, hertz_half_width
from mechanism.core.wear import _kernels as wk

pytestmark = pytest.mark.filterwarnings("error")

RB, C0, L = 0.015, 2e-4, 0.011
RJ = RB - C0
N = 360
STEP = 2 * math.pi / N
K_ARCHARD = 1.827e-13  # m2 N-1, the paper's coefficient
STEEL = Material(youngs_modulus=207e9, poisson_ratio=0.3)
E_STAR = effective_modulus(STEEL, STEEL)


def unworn(**kw) -> WornProfile:
    return WornProfile.unworn(bearing_radius=RB, clearance=C0, length=L, **kw)


def sector_volume(depth: np.ndarray, radius: float, outward: bool) -> float:
    """Independent volume of a worn ring: annular sectors between R and R ± h."""
    # h (2R ± h)/2 per unit angle and length, written without cancellation
    return float(np.sum(L * STEP * depth * (radius + (0.5 if outward else -0.5) * depth)))


# --- S7 volume balance -----------------------------------------------------------------

ANGLES = [0.0, 1.0, 10 * STEP, 2 * math.pi - 1e-9, 2 * math.pi - 0.3 * STEP, -0.2 * STEP, 7.5]


@pytest.mark.parametrize("angle", ANGLES)
@pytest.mark.parametrize("half_width", [0.0, 3e-5, 2.4e-3])
@pytest.mark.parametrize("outward", [True, False])
def test_constant_load_wears_exactly_k_f_s(angle, half_width, outward) -> None:
    force, slip, samples = 3000.0, 0.25, 400
    radius = RB if outward else RJ
    depth = np.zeros(N)
    for _ in range(samples):
        status, applied = wk.archard_increment(
            depth, angle, force, slip / samples, K_ARCHARD, radius, L, half_width, outward, -1.0
        )
        assert status == wk.STATUS_OK
        assert_allclose(applied, K_ARCHARD * force * slip / samples, rtol=1e-12)
    volume = sector_volume(depth, radius, outward)
    assert_allclose(volume, K_ARCHARD * force * slip, rtol=1e-3)  # S7 target
    assert_allclose(volume, K_ARCHARD * force * slip, rtol=1e-10)  # what we achieve
    touched = np.count_nonzero(depth)
    if half_width > 0.1 * RB * STEP:
        assert touched >= 2 * half_width / radius / STEP - 1  # spread over ±a/R
    else:
        assert touched <= 2


def test_volume_balance_whatever_the_pressure_distribution() -> None:
    # a random load history with spread, both surfaces, wrap-around included
    rng = np.random.default_rng(11)
    samples = 5000
    force = rng.uniform(0, 8000, samples)
    slip = rng.uniform(0, 2e-4, samples)
    angle_b = rng.uniform(-1, 1, samples) * 0.4  # straddles 0 / 2π
    angle_j = rng.uniform(0, 2 * np.pi, samples)
    for spread in (True, False):
        for form in ("sum-of-radii", "conformal"):
            r = archard_wear(
                unworn(),
                bearing_angle=angle_b,
                journal_angle=angle_j,
                normal_force=force,
                slip=slip,
                coefficient=K_ARCHARD,
                effective_modulus=E_STAR,
                spread=spread,
                form=form,
            )
            expected = K_ARCHARD * np.sum(force * slip)
            assert r.success and r.samples == samples
            assert_allclose(r.requested_volume, expected, rtol=1e-12)
            for depth, radius, outward in (
                (r.profile.bearing_depth, RB, True),
                (r.profile.journal_depth, RJ, False),
            ):
                assert_allclose(sector_volume(depth, radius, outward), expected, rtol=1e-10)
            assert_allclose(r.profile.bearing_volume, expected, rtol=1e-10)
            assert_allclose(r.profile.journal_volume, expected, rtol=1e-10)
            # the wear straddles 0/2π on the bearing
            assert r.profile.bearing_depth[0] > 0 and r.profile.bearing_depth[-1] > 0


# --- where the volume goes -------------------------------------------------------------


def test_unspread_increment_goes_to_the_touched_region() -> None:
    depth = np.zeros(N)
    angle = 100.3 * STEP
    dv = K_ARCHARD * 2000.0 * 1e-3
    wk.archard_increment(depth, angle, 2000.0, 1e-3, K_ARCHARD, RB, L, 0.0, True, -1.0)
    assert np.flatnonzero(depth).tolist() == [100]
    h = depth[100]
    assert_allclose(L * STEP * h * (RB + h / 2), dv, rtol=1e-12)  # the annular sector
    # region-averaged depth ΔV/(L R Δ) up to the curvature correction h/(2R)
    assert_allclose(h, dv / (L * RB * STEP), rtol=h / RB)


def test_spread_follows_the_semi_elliptical_hertz_pressure() -> None:
    a = 2.0e-3  # about ±7.6 regions on the bearing
    centre = 123.37 * STEP
    depth = np.zeros(N)
    force, slip = 5000.0, 1e-4
    wk.archard_increment(depth, centre, force, slip, K_ARCHARD, RB, L, a, True, -1.0)
    total = K_ARCHARD * force * slip
    half_angle = a / RB
    for i in np.flatnonzero(depth):
        lo = max((i * STEP - centre) / half_angle, -1.0)
        hi = min(((i + 1) * STEP - centre) / half_angle, 1.0)
        share = quad(lambda s: math.sqrt(1 - s * s), lo, hi, epsabs=1e-14)[0] / (math.pi / 2)
        volume = L * STEP * depth[i] * (RB + depth[i] / 2)
        assert_allclose(volume, share * total, rtol=1e-9)
    # the peak region's depth is the Archard depth k p_max Δs of the Hertz peak pressure
    p_max = 2 * force / (math.pi * a * L)
    peak = depth[int(centre / STEP)]
    assert_allclose(peak, K_ARCHARD * p_max * slip, rtol=2e-3)


def test_symmetric_load_history_gives_a_symmetric_profile() -> None:
    rng = np.random.default_rng(5)
    phi = rng.uniform(0, np.pi, 300)
    force = rng.uniform(500, 6000, 300)
    slip = rng.uniform(0, 1e-4, 300)
    # every load at φ is matched by the same load at −φ (mirror about the x axis); region
    # i covers [iΔ, (i+1)Δ), so its mirror is region N − 1 − i
    depth = np.zeros(N)
    for half_width in (0.0, 4e-4):
        for sign in (1.0, -1.0):
            for p, f, s in zip(phi, force, slip, strict=True):
                wk.archard_increment(
                    depth, sign * p, f, s, K_ARCHARD, RB, L, half_width, True, -1.0
                )
        assert depth.max() > 0
        assert_allclose(depth, depth[::-1], rtol=1e-9, atol=1e-12 * depth.max())
    # through archard_wear (unspread, so the order of the samples does not matter)
    r = archard_wear(
        unworn(),
        bearing_angle=np.r_[phi, -phi],
        journal_angle=np.r_[-phi, phi],
        normal_force=np.r_[force, force],
        slip=np.r_[slip, slip],
        coefficient=K_ARCHARD,
        effective_modulus=E_STAR,
        spread=False,
    )
    for h in (r.profile.bearing_depth, r.profile.journal_depth):
        assert_allclose(h, h[::-1], rtol=1e-9, atol=1e-12 * h.max())
    rho = r.profile.curvature_radius()
    assert_allclose(rho, rho[::-1], rtol=1e-6)


# --- guards ----------------------------------------------------------------------------


def test_increment_above_the_limit_is_reduced_and_reported() -> None:
    depth = np.zeros(N)
    limit = 0.01 * C0
    big_force, slip = 2e4, 50.0  # would wear ≈ 0.2 mm in one step
    status, applied = wk.archard_increment(
        depth, 1.0, big_force, slip, K_ARCHARD, RB, L, 1e-3, True, limit
    )
    assert status == wk.STATUS_REDUCED
    assert 0 < applied < K_ARCHARD * big_force * slip
    assert depth.max() <= limit * (1 + 1e-12)
    assert_allclose(depth.max(), limit, rtol=1e-9)  # the binding region reaches the limit
    assert_allclose(sector_volume(depth, RB, True), applied, rtol=1e-10)
    r = archard_wear(
        unworn(),
        bearing_angle=1.0,
        journal_angle=2.0,
        normal_force=big_force,
        slip=slip,
        coefficient=K_ARCHARD,
        effective_modulus=E_STAR,
        max_increment=limit,
    )
    assert not r.success and r.reduced == 2
    assert r.bearing_volume < r.requested_volume


def test_a_journal_is_never_worn_through_and_nothing_becomes_nan() -> None:
    hj = np.zeros(N)
    hj[10] = RJ * (1 - 1e-4)  # almost worn through already
    p = WornProfile(
        bearing_radius=RB, clearance=C0, length=L, bearing_depth=np.zeros(N), journal_depth=hj
    )
    r = archard_wear(
        p,
        bearing_angle=0.0,
        journal_angle=10.5 * STEP,
        normal_force=1e5,
        slip=1e3,
        coefficient=K_ARCHARD,
        effective_modulus=E_STAR,
        spread=False,
    )
    hj2 = r.profile.journal_depth  # WornProfile re-validated it: not worn through
    assert np.all(np.isfinite(hj2)) and hj2.max() < RJ
    assert r.reduced == 1
    clearance = r.profile.local_clearance(r.profile.angle, r.profile.angle)
    assert np.all(np.isfinite(clearance)) and np.all(clearance >= C0)
    K = r.profile.local_stiffness(r.profile.angle, r.profile.angle, effective_modulus=E_STAR)
    assert np.all(np.isfinite(K))


def test_non_finite_or_empty_input_changes_nothing() -> None:
    depth = np.zeros(N)
    for args in ((math.nan, 100.0, 1e-3), (1.0, math.inf, 1e-3), (1.0, 100.0, math.nan)):
        status, applied = wk.archard_increment(depth, *args, K_ARCHARD, RB, L, 1e-4, True, -1.0)
        assert (status, applied) == (wk.STATUS_REJECTED, 0.0)
    for args in ((1.0, 0.0, 1e-3), (1.0, -5.0, 1e-3), (1.0, 100.0, 0.0)):
        status, applied = wk.archard_increment(depth, *args, K_ARCHARD, RB, L, 1e-4, True, -1.0)
        assert (status, applied) == (wk.STATUS_OK, 0.0)
    assert not depth.any()
    with pytest.raises(ValueError, match="slip must be >= 0"):
        archard_wear(
            unworn(),
            bearing_angle=0.0,
            journal_angle=0.0,
            normal_force=1.0,
            slip=-1.0,
            coefficient=K_ARCHARD,
            effective_modulus=E_STAR,
        )
    with pytest.raises(ValueError, match="non-finite"):
        archard_wear(
            unworn(),
            bearing_angle=math.nan,
            journal_angle=0.0,
            normal_force=1.0,
            slip=1.0,
            coefficient=K_ARCHARD,
            effective_modulus=E_STAR,
        )
    with pytest.raises(ValueError, match="journal_angle is required"):
        archard_wear(
            unworn(),
            bearing_angle=0.0,
            normal_force=1.0,
            slip=1.0,
            coefficient=K_ARCHARD,
            effective_modulus=E_STAR,
        )


def test_bearing_only_wear_leaves_the_journal_alone() -> None:
    r = archard_wear(
        unworn(surfaces="bearing"),
        bearing_angle=[1.0, 2.0],
        normal_force=1000.0,
        slip=1e-2,
        coefficient=K_ARCHARD,
        effective_modulus=E_STAR,
    )
    assert r.journal_volume == 0.0 and not r.profile.journal_depth.any()
    assert_allclose(r.profile.bearing_volume, 2 * K_ARCHARD * 1000.0 * 1e-2, rtol=1e-10)


# --- Hertz line contact ----------------------------------------------------------------


def test_hertz_half_width_and_pressure_closed_form() -> None:
    r_star = effective_radius(RB, RJ, "sum-of-radii")
    force = 9182.0  # the paper's peak force before wear
    a = hertz_half_width(force, effective_radius=r_star, length=L, effective_modulus=E_STAR)
    assert_allclose(a, math.sqrt(4 * force * r_star / (math.pi * L * E_STAR)), rtol=1e-14)
    # paper-model A7: a ≈ 0.1–0.4 mm, p ≈ 0.7–2.5 GPa at the paper's loads and R*
    assert 1e-4 < a < 4e-4
    assert 0.7e9 < force / (2 * a * L) < 2.5e9
    assert hertz_half_width(0.0, effective_radius=r_star, length=L, effective_modulus=E_STAR) == 0.0


def test_archard_history_uses_the_local_hertz_width() -> None:
    # one sample with spread equals one kernel call with a from the unworn R*
    force, slip, angle = 4000.0, 1e-3, 2.0
    r = archard_wear(
        unworn(),
        bearing_angle=angle,
        journal_angle=0.5,
        normal_force=force,
        slip=slip,
        coefficient=K_ARCHARD,
        effective_modulus=E_STAR,
        form="conformal",
    )
    a = hertz_half_width(
        force,
        effective_radius=effective_radius(RB, RJ, "conformal"),
        length=L,
        effective_modulus=E_STAR,
    )
    depth = np.zeros(N)
    wk.archard_increment(depth, angle, force, slip, K_ARCHARD, RB, L, a, True, -1.0)
    assert_allclose(r.profile.bearing_depth, depth, rtol=1e-9, atol=1e-25)
    ds = r.to_dataset()
    assert ds.attrs["samples"] == 1 and ds.attrs["reduced_increments"] == 0
    assert_allclose(ds.attrs["requested_volume"], K_ARCHARD * force * slip)
