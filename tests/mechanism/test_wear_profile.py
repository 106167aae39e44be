"""Worn geometry of a clearance joint."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from mechanism.core.contact import effective_modulus, hertz_stiffness
from mechanism.core.scene import ClearanceRevolute, Material, WearSettings
from mechanism.core.wear import WornProfile
from mechanism.core.wear import _kernels as wk

pytestmark = pytest.mark.filterwarnings("error")

RB, C0, L = 0.015, 2e-4, 0.011
RJ = RB - C0
N = 360
STEEL = Material(youngs_modulus=207e9, poisson_ratio=0.3)
E_STAR = effective_modulus(STEEL, STEEL)


def profile(bearing=None, journal=None, **kw) -> WornProfile:
    return WornProfile(
        bearing_radius=RB,
        clearance=C0,
        length=L,
        bearing_depth=np.zeros(N) if bearing is None else bearing,
        journal_depth=np.zeros(N) if journal is None else journal,
        **kw,
    )


def joint_with(wear: WearSettings) -> ClearanceRevolute:
    return ClearanceRevolute(
        bearing=("ground", "C"),
        journal=("rod3", "C"),
        bearing_radius=RB,
        clearance=C0,
        length=L,
        bearing_material=STEEL,
        journal_material=STEEL,
        wear=wear,
    )


def arc_wear(depth: float, start_deg: float, stop_deg: float, n: int = N) -> np.ndarray:
    """A smooth bump of wear (cos²) over [start, stop] degrees, zero elsewhere."""
    centres = (np.arange(n) + 0.5) * 360.0 / n
    x = (centres - start_deg) / (stop_deg - start_deg)
    h = np.where((x > 0) & (x < 1), depth * np.sin(np.pi * x) ** 2, 0.0)
    return h


# --- regions ---------------------------------------------------------------------------


def test_region_index_boundaries_and_wrap_around() -> None:
    step = 2 * math.pi / N
    assert wk.region_index(0.0, N) == 0
    assert wk.region_index(0.5 * step, N) == 0
    assert wk.region_index(1.5 * step, N) == 1
    assert wk.region_index(2 * math.pi - 0.5 * step, N) == N - 1
    assert wk.region_index(2 * math.pi, N) == 0
    assert wk.region_index(-0.5 * step, N) == N - 1
    assert wk.region_index(-1e-300, N) in (0, N - 1)
    assert wk.region_index(4 * math.pi + 10.5 * step, N) == 10
    assert wk.region_index(-2 * math.pi + 10.5 * step, N) == 10
    assert wk.region_index(math.nan, N) == 0  # memory-safe in kernels
    p = profile()
    assert_allclose(p.angle[[0, -1]], [0.5 * step, 2 * math.pi - 0.5 * step])
    np.testing.assert_array_equal(p.region_index(p.angle), np.arange(N))
    with pytest.raises(ValueError, match="finite"):
        p.region_index(math.nan)


# --- local clearance -------------------------------------------------------------------


def _periodic_pchip(values: np.ndarray):
    """scipy's PCHIP through the region centres of three periods (independent reference)."""
    from scipy.interpolate import PchipInterpolator

    n = values.size
    centres = (np.arange(-n, 2 * n) + 0.5) * 2 * np.pi / n
    curve = PchipInterpolator(centres, np.tile(values, 3))
    return lambda angle, nu=0: curve(np.mod(angle, 2 * np.pi), nu)


def test_local_clearance_grows_by_exactly_the_local_depth() -> None:
    rng = np.random.default_rng(7)
    hb = rng.uniform(0, 3e-5, N)
    hj = rng.uniform(0, 1e-5, N)
    p = profile(hb, hj)
    # at the region centres the surface passes through the region depths (the centre
    # angles round to ~1e-16 of a region, the slopes reach ~3e-3 m/rad)
    rev = p.angle[::-1]
    assert_allclose(p.local_clearance(p.angle, rev) - C0, hb + hj[::-1], rtol=0, atol=1e-17)
    # between them it is the periodic monotone cubic (PCHIP) through the centres
    phi_b = rng.uniform(-10, 10, 2000)
    phi_j = rng.uniform(-10, 10, 2000)
    got = p.local_clearance(phi_b, phi_j)
    want = _periodic_pchip(hb)(phi_b) + _periodic_pchip(hj)(phi_j)
    # the wrapped angles round to ~1e-15 rad, the slopes reach ~3e-3 m/rad
    assert_allclose(got - C0, want, rtol=0, atol=1e-17)
    # the kernel the integrator calls gives the same numbers
    for x, y, c in zip(phi_b[:50], phi_j[:50], got[:50], strict=True):
        assert wk.local_clearance(C0, p.bearing_depth, p.journal_depth, x, y) == c
    # a bearing-only profile (empty journal array) in the kernel
    empty = np.zeros(0)
    assert wk.local_clearance(C0, p.bearing_depth, empty, phi_b[0], 0.3) == pytest.approx(
        C0 + _periodic_pchip(hb)(phi_b[0]), rel=0, abs=1e-18
    )


def test_worn_surface_is_continuous_and_smooth_across_region_boundaries() -> None:
    """The tabulation into regions must not make the clearance jump (the worn surface is
    smooth): at every region boundary the clearance and its angular slope are continuous,
    and the slope the penetration rate uses is the derivative of the clearance."""
    rng = np.random.default_rng(3)
    hb = arc_wear(4e-5, 60, 140) + rng.uniform(0, 5e-6, N) * (rng.uniform(size=N) > 0.5)
    p = profile(hb)
    boundary = np.arange(N) * 2 * np.pi / N
    eps = 1e-9  # rad; a region is 1.7e-2 rad
    below = p.local_clearance(boundary - eps)
    above = p.local_clearance(boundary + eps)
    largest_step = np.max(np.abs(np.diff(np.r_[hb, hb[0]])))
    assert largest_step > 1e-6  # region values differ by up to µm at the boundaries
    # C0: the jump is what the largest slope can do in 2 eps (piecewise constant: µm)
    slope_bound = 3 * largest_step * N / (2 * np.pi)
    assert np.max(np.abs(above - below)) <= slope_bound * 2 * eps
    # C1: the slope is continuous (a kink would leave a step of order largest_step / Δ)
    s_below = p.wear_depth_slope(boundary - eps)
    s_above = p.wear_depth_slope(boundary + eps)
    curvature_bound = 24 * largest_step * (N / (2 * np.pi)) ** 2
    assert np.max(np.abs(s_above - s_below)) <= curvature_bound * 2 * eps
    # the slope is the derivative of the clearance (central difference, O(h²), away from
    # the region centres where the cubic pieces meet)
    x = (rng.integers(0, N, 500) + 0.5 + rng.uniform(0.05, 0.95, 500)) * 2 * np.pi / N
    h = 1e-6
    numeric = (p.local_clearance(x + h) - p.local_clearance(x - h)) / (2 * h)
    assert_allclose(p.wear_depth_slope(x), numeric, rtol=0, atol=1e-7 * slope_bound)
    assert_allclose(p.wear_depth_slope(x), _periodic_pchip(hb)(x, 1), rtol=1e-9, atol=1e-15)


def test_worn_surface_never_overshoots_its_region_depths() -> None:
    # a groove with steep flanks and an isolated pit: an ordinary cubic spline would dip
    # below zero beside them (negative depth = a clearance below c₀)
    hb = np.zeros(N)
    hb[100:110] = 5e-5
    hb[200] = 2e-5
    p = profile(hb)
    fine = np.linspace(0, 2 * np.pi, 200_001)
    depth = p.wear_depth(fine)
    assert depth.min() >= 0.0
    ulp = 1e-15 * hb.max()  # the cubic's weights sum to 1 up to rounding
    assert depth.max() <= hb.max() + ulp
    assert np.all(p.local_clearance(fine) >= C0)
    # between two centres the depth stays between the two region values
    i = np.floor(np.mod(fine / (2 * np.pi / N) - 0.5, N)).astype(int)
    lo = np.minimum(hb[i], hb[(i + 1) % N])
    hi = np.maximum(hb[i], hb[(i + 1) % N])
    assert np.all(depth >= lo - ulp) and np.all(depth <= hi + ulp)
    # an extremum of the regions is an extremum of the surface, reached at the centre
    assert p.wear_depth(p.angle[200]) == pytest.approx(2e-5, rel=1e-12)
    assert p.wear_depth_slope(p.angle[200]) == pytest.approx(0.0, abs=1e-12)


def test_a_profile_deeper_than_the_clearance_stays_valid() -> None:
    # wear only opens the joint: depth 3 c₀ means local clearance 4 c₀, stiffness finite
    hb = arc_wear(3 * C0, 75, 132)
    p = profile(hb)
    deepest = p.angle[np.argmax(hb)]
    assert_allclose(p.local_clearance(deepest), C0 + hb.max(), rtol=1e-14)
    K = p.local_stiffness(p.angle, effective_modulus=E_STAR)
    assert np.all(np.isfinite(K)) and np.all(K > 0)
    assert np.all(p.local_clearance(p.angle) >= C0)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(bearing=-1e-9 * np.ones(N)), "bearing_depth must be >= 0"),
        (dict(journal=np.r_[np.zeros(N - 1), RJ]), "worn through"),
        (dict(bearing=np.r_[np.zeros(N - 1), np.nan]), "non-finite"),
        (dict(journal=np.zeros(N - 1)), "same number of regions"),
        (dict(bearing=np.zeros(2), journal=np.zeros(2)), "at least 3"),
        (dict(smoothing_regions=0), "smoothing_regions"),
        (dict(surfaces="shaft"), "surfaces"),
    ],
)
def test_invalid_profiles_are_rejected_with_a_clear_error(kw, match) -> None:
    with pytest.raises(ValueError, match=match):
        profile(**kw)


def test_profile_arrays_are_frozen_copies() -> None:
    hb = np.zeros(N)
    p = profile(hb)
    hb[3] = 1.0
    assert p.bearing_depth[3] == 0.0
    with pytest.raises(ValueError):
        p.bearing_depth[3] = 1.0


# --- curvature -------------------------------------------------------------------------


def test_unworn_surfaces_have_their_nominal_radius() -> None:
    p = profile()
    assert_allclose(p.curvature_radius(surface="bearing"), RB, rtol=1e-11)
    assert_allclose(p.curvature_radius(surface="journal"), RJ, rtol=1e-11)


def test_untouched_arcs_keep_their_radius() -> None:
    hb = arc_wear(5e-5, 75, 132) + arc_wear(5e-5, 252, 310)
    hj = arc_wear(2e-5, 10, 40)
    p = profile(hb, hj, smoothing_regions=5)
    # a region is untouched when no region within the smoothing window ± 1 is worn
    reach = 5 // 2 + 1
    for depth, surface, radius in ((hb, "bearing", RB), (hj, "journal", RJ)):
        worn = depth > 0
        near = np.zeros(N, dtype=bool)
        for shift in range(-reach, reach + 1):
            near |= np.roll(worn, shift)
        rho = p.curvature_radius(surface=surface)
        assert (~near).sum() > 200
        assert_allclose(rho[~near], radius, rtol=1e-10)
        assert np.max(np.abs(rho[near] / radius - 1)) > 1e-3  # the worn arcs did change
    K0 = hertz_stiffness(RB, RJ, STEEL, STEEL, "sum-of-radii")
    far = p.angle[200]  # bearing and journal both untouched at 200°
    assert_allclose(p.local_stiffness(far, far, effective_modulus=E_STAR), K0, rtol=1e-9)
    K0c = hertz_stiffness(RB, RJ, STEEL, STEEL, "conformal")
    assert_allclose(
        p.local_stiffness(far, far, effective_modulus=E_STAR, form="conformal"), K0c, rtol=1e-8
    )


def _offset_circle_depth(radius: float, offset: float, nominal: float, outward: bool):
    """Depth that turns a ring of radius ``nominal`` into a circle of ``radius`` whose
    centre is shifted by ``offset`` along x: r(φ) = d cos φ + √(ρ² − d² sin² φ)."""
    phi = (np.arange(N) + 0.5) * 2 * np.pi / N
    r = offset * np.cos(phi) + np.sqrt(radius**2 - (offset * np.sin(phi)) ** 2)
    return r - nominal if outward else nominal - r


def test_curvature_of_an_exactly_circular_worn_surface() -> None:
    # three points of a circle determine that circle: the unsmoothed curvature radius is
    # exact for an eccentric circular "worn" bearing and journal
    hb = _offset_circle_depth(RB + 3e-4, 1e-4, RB, outward=True)
    hj = _offset_circle_depth(RJ - 2e-4, 0.5e-4, RJ, outward=False)
    assert hb.min() >= 0 and hj.min() >= 0
    p = profile(hb, hj, smoothing_regions=1)
    assert_allclose(p.curvature_radius(surface="bearing"), RB + 3e-4, rtol=1e-10)
    assert_allclose(p.curvature_radius(surface="journal"), RJ - 2e-4, rtol=1e-10)
    r_star = 1 / (1 / (RJ - 2e-4) + 1 / (RB + 3e-4))
    assert_allclose(p.local_effective_radius(p.angle, p.angle), r_star, rtol=1e-10)
    # the conformal difference of curvatures amplifies round-off by R/c ≈ 30
    r_conf = 1 / (1 / (RJ - 2e-4) - 1 / (RB + 3e-4))
    assert_allclose(
        p.local_effective_radius(p.angle, p.angle[::-1], form="conformal"), r_conf, rtol=1e-9
    )


def test_moving_average_smoothing() -> None:
    hb = np.zeros(N)
    hb[100] = 5e-6
    for width, weights in ((1, [1]), (3, [1, 1, 1]), (5, [1] * 5), (4, [0.5, 1, 1, 1, 0.5])):
        p = profile(hb, smoothing_regions=width)
        s = p.smoothed_depth()
        half = len(weights) // 2
        assert_allclose(
            s[100 - half : 100 + half + 1], 5e-6 * np.array(weights) / width, rtol=1e-13
        )
        assert_allclose(s.sum(), hb.sum(), rtol=1e-13)  # the average conserves volume
        assert np.count_nonzero(s) == len(weights)


def test_symmetric_profile_gives_symmetric_curvature() -> None:
    hb = arc_wear(4e-5, 20, 70)
    hb = hb + hb[::-1]  # mirror about 0/180° in region space
    p = profile(hb)
    rho = p.curvature_radius()
    assert_allclose(rho, rho[::-1], rtol=1e-9)


def test_local_stiffness_is_bounded_for_any_worn_shape() -> None:
    # a single deep pit is the worst case for the three-point curvature
    hb = np.zeros(N)
    hb[50] = 1e-4
    for smoothing in (1, 3, 5):
        p = profile(hb, smoothing_regions=smoothing)
        for form in ("sum-of-radii", "conformal"):
            K0 = hertz_stiffness(RB, RJ, STEEL, STEEL, form)
            K = p.local_stiffness(
                p.angle, effective_modulus=E_STAR, form=form, radius_ratio_limit=10.0
            )
            assert np.all(np.isfinite(K))
            assert np.all(K >= K0 / math.sqrt(10) * (1 - 1e-12))
            assert np.all(K <= K0 * math.sqrt(10) * (1 + 1e-12))
    with pytest.raises(ValueError, match="radius_ratio_limit"):
        p.local_stiffness(0.0, effective_modulus=E_STAR, radius_ratio_limit=0.5)


def test_kernel_local_stiffness_matches_the_profile_method() -> None:
    hb = arc_wear(3e-5, 75, 132)
    hj = arc_wear(1e-5, 200, 260)
    p = profile(hb, hj)
    for phi_b, phi_j in ((1.7, 3.9), (0.2, 5.0), (2.1, 4.2)):
        K = wk.local_stiffness(
            E_STAR, 1, RB, RJ, p.bearing_depth, p.journal_depth, phi_b, phi_j, 5, 10.0
        )
        assert_allclose(K, p.local_stiffness(phi_b, phi_j, effective_modulus=E_STAR), rtol=1e-14)


def test_tabulated_local_stiffness_equals_the_on_the_fly_one() -> None:
    hb = arc_wear(3e-5, 75, 132) + arc_wear(2e-5, 250, 300)
    hj = arc_wear(1e-5, 200, 260)
    p = profile(hb, hj)
    kb, kj = p.curvature(surface="bearing"), p.curvature(surface="journal")
    rng = np.random.default_rng(2)
    for phi_b, phi_j in rng.uniform(-7, 7, (200, 2)):
        for form in (0, 1):
            direct = wk.local_stiffness(
                E_STAR, form, RB, RJ, p.bearing_depth, p.journal_depth, phi_b, phi_j, 5, 10.0
            )
            table = wk.local_stiffness_tabulated(E_STAR, form, RB, RJ, kb, kj, phi_b, phi_j, 10.0)
            assert_allclose(table, direct, rtol=1e-14)
    empty = np.zeros(0)
    K0 = hertz_stiffness(RB, RJ, STEEL, STEEL, "sum-of-radii")
    assert_allclose(
        wk.local_stiffness_tabulated(E_STAR, 1, RB, RJ, empty, empty, 1.0, 2.0, 10.0),
        K0,
        rtol=1e-12,
    )


# --- volume, datasets, scene round trip ------------------------------------------------


def test_volume_is_the_annular_sector_between_nominal_and_worn_radius() -> None:
    hb = arc_wear(5e-5, 75, 132)
    hj = arc_wear(5e-5, 10, 80)
    p = profile(hb, hj)
    step = 2 * np.pi / N
    assert_allclose(p.bearing_volume, np.sum(L * step / 2 * ((RB + hb) ** 2 - RB**2)), rtol=1e-12)
    assert_allclose(p.journal_volume, np.sum(L * step / 2 * (RJ**2 - (RJ - hj) ** 2)), rtol=1e-12)
    assert profile().volume == 0.0


def test_to_dataset_is_labelled_and_round_trips(tmp_path) -> None:
    p = profile(arc_wear(5e-5, 75, 132), arc_wear(1e-5, 0, 30), smoothing_regions=3)
    ds = p.to_dataset()
    assert ds["wear_depth"].dims == ("angle",) and ds.sizes["angle"] == N
    for name in [*ds.data_vars, "angle"]:
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]
    assert_allclose(ds.attrs["bearing_volume"], p.bearing_volume)
    path = tmp_path / "profile.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    back = WornProfile.from_dataset(xr.load_dataset(path, engine="h5netcdf"))
    np.testing.assert_array_equal(back.bearing_depth, p.bearing_depth)
    np.testing.assert_array_equal(back.journal_depth, p.journal_depth)
    assert (back.smoothing_regions, back.surfaces, back.clearance) == (3, "both", C0)


def test_scene_joint_round_trip() -> None:
    joint = joint_with(WearSettings(regions=180, surfaces="bearing", smoothing_regions=3))
    p = WornProfile.from_joint(joint)
    assert (p.regions, p.surfaces, p.smoothing_regions, p.volume) == (180, "bearing", 3, 0.0)
    worn = p.with_depth(bearing_depth=arc_wear(4e-5, 75, 132, n=180))
    joint2 = worn.apply_to(joint)
    assert len(joint2.wear.bearing_profile) == 180 and joint2.wear.journal_profile == ()
    assert joint2.wear.coefficient == joint.wear.coefficient
    again = WornProfile.from_joint(joint2)
    np.testing.assert_array_equal(again.bearing_depth, worn.bearing_depth)
    bad = joint_with(WearSettings(regions=360, bearing_profile=(0.0,) * 100))
    with pytest.raises(ValueError, match="bearing_profile must hold"):
        WornProfile.from_joint(bad)
    with pytest.raises(ValueError, match="clearance"):
        WornProfile.unworn(bearing_radius=RB, clearance=3e-4, length=L).apply_to(joint)
