"""Validation targets S2 (rigid slider-crank) and S3 (slider-crank with a dry clearance
joint), docs/validation-targets.md."""

from __future__ import annotations

import numpy as np
import pytest

import mechanism
from tests.mechanism.scenes import s3

CRANK = 0.05
ROD = 0.12


@pytest.fixture(scope="module")
def s2():
    scene = mechanism.load_scene("slider-crank")
    period = scene.drive.period
    ds = mechanism.simulate(scene, t_end=1.0, output_step=period / 400, rtol=1e-10, atol=1e-10)
    return scene, ds


def test_s2_slider_follows_the_closed_form_position_over_one_second(s2) -> None:
    scene, ds = s2
    assert ds.attrs["solver_status"] == 0
    assert float(ds.time[-1]) == pytest.approx(1.0, abs=scene.drive.period / 400)
    theta = scene.drive.speed * ds.time.values
    np.testing.assert_allclose(ds.crank_angle.values, theta, rtol=0, atol=1e-9)
    exact = CRANK * np.cos(theta) + np.sqrt(ROD**2 - CRANK**2 * np.sin(theta) ** 2)
    assert np.abs(ds.slider_position.values - exact).max() < 1e-9


def test_s2_slider_acceleration_peaks_at_r_omega_squared_one_plus_r_over_l(s2) -> None:
    scene, ds = s2
    w = scene.drive.speed
    peak = CRANK * w**2 * (1 + CRANK / ROD)
    assert peak == pytest.approx(1.94e4, rel=1e-3)
    assert np.abs(ds.slider_acceleration.values).max() == pytest.approx(peak, rel=1e-7)


def test_s2_rod_slider_joint_force(s2) -> None:
    scene, ds = s2
    force = ds.joint_force.sel(ideal_joint="B").values
    per_rev = 400
    revs = force[: (force.size - 1) // per_rev * per_rev].reshape(-1, per_rev)
    # the reference simulation: peak 2720 N (±0.5 %) and minimum ≈ 433.7 N (±1 %) per revolution
    assert revs.max(axis=1) == pytest.approx(np.full(revs.shape[0], 2720.0), rel=5e-3)
    assert revs.min(axis=1) == pytest.approx(np.full(revs.shape[0], 433.7), rel=1e-2)
    # the pin force equals the force the rod exerts on the slider's guide and inertia
    fx = ds.joint_force_x.sel(ideal_joint="B").values
    m_slider = scene.bodies["slider"].mass
    guide = ds.joint_force_x.sel(ideal_joint="P").values
    np.testing.assert_allclose(fx + guide, m_slider * ds.slider_acceleration.values, atol=1e-6)


def _first_impact(ds):
    force = ds.contact_force.isel(joint=0).values
    depth = ds.penetration.isel(joint=0).values
    start = int(np.argmax(force > 0))
    end = start + int(np.argmax(force[start:] == 0))
    assert end > start + 10, "the first impact must be resolved by the output grid"
    return force[start:end].max(), depth[start:end].max()


@pytest.mark.parametrize(
    ("method", "tol"), [("dopri5", 1e-6), ("generalized-alpha", 1e-5), ("DOP853", 1e-6)]
)
def test_s3_first_impact_frictionless(method, tol) -> None:
    ds = mechanism.simulate(s3(), t_end=6e-4, output_step=2.5e-7, method=method, rtol=tol, atol=tol)
    peak, depth = _first_impact(ds)
    assert peak == pytest.approx(45.8e3, rel=0.03)
    assert depth == pytest.approx(77.9e-6, rel=0.03)


def test_s3_first_impact_at_the_benchmark_settings() -> None:
    """The settings of benchmarks/test_bench_simulate.py keep the first impact within 3 %."""
    scene = s3(**{"solver.max_step": 1e-4})
    ds = mechanism.simulate(scene, t_end=6e-4, output_step=1e-6, rtol=1e-5, atol=1e-5)
    peak, depth = _first_impact(ds)
    assert peak == pytest.approx(45.8e3, rel=0.03)
    assert depth == pytest.approx(77.9e-6, rel=0.03)


def _stroboscopic(ds, per_rev, skip_revs):
    ex = ds.eccentricity_x.isel(joint=0).values
    ey = ds.eccentricity_y.isel(joint=0).values
    idx = np.arange(skip_revs * per_rev, ex.size, per_rev)
    return ex[idx], ey[idx]


@pytest.fixture(scope="module")
def s3_runs():
    runs = {}
    for mu in (0.0, 0.1):
        scene = s3(friction=mu, **{"solver.max_step": 1e-4})
        per_rev = 100
        ds = mechanism.simulate(
            scene, t_end=1.0, output_step=scene.drive.period / per_rev, rtol=1e-5, atol=1e-5
        )
        runs[mu] = (ds, per_rev)
    return runs


def test_s3_frictionless_free_flight_and_scattered_map(s3_runs) -> None:
    ds, per_rev = s3_runs[0.0]
    c = 5e-4
    late = ds.in_contact.isel(joint=0).values[20 * per_rev :]
    # free flight alternates with contact: many separations and impacts
    assert 0.05 < 1.0 - late.mean() < 0.95
    separations = np.count_nonzero(np.diff(late.astype(int)) == -1)
    assert separations > 100
    ex, ey = _stroboscopic(ds, per_rev, 20)
    spread = np.hypot(ex - ex.mean(), ey - ey.mean())
    assert spread.max() > 0.3 * c  # a cloud, not a point


def test_s3_with_friction_permanent_contact_and_period_one_map(s3_runs) -> None:
    ds, per_rev = s3_runs[0.1]
    c = 5e-4
    late = ds.in_contact.isel(joint=0).values[20 * per_rev :]
    assert late.all()  # permanent contact after the start-up impacts
    ex, ey = _stroboscopic(ds, per_rev, 20)
    spread = np.hypot(ex - ex.mean(), ey - ey.mean())
    assert spread.max() < 0.05 * c  # one point: period 1
    assert np.hypot(ex, ey).min() > c  # on the bearing wall


@pytest.mark.parametrize("mu", [0.0, 0.1])
def test_s3_implicit_and_explicit_integrators_agree(mu) -> None:
    """Through the first impacts the implicit generalized-α run follows a tight dopri5
    run; over 20 ms (tens of impacts, rattling then sliding) it stays bounded."""
    # both step limits at the output step, the setting this comparison was calibrated with
    scene = s3(friction=mu).replace({"solver.max_step": 1e-5})
    kw = {"t_end": 0.02, "output_step": 1e-5}
    ref = mechanism.simulate(scene, rtol=1e-8, atol=1e-8, **kw)
    imp = mechanism.simulate(scene, method="generalized-alpha", rtol=1e-6, atol=1e-6, **kw)
    early = slice(0, 300)  # 3 ms
    for name in ("eccentricity_x", "eccentricity_y"):
        diff = np.abs(ref[name].values[early] - imp[name].values[early]).max()
        assert diff < 5e-6
    c = 5e-4
    assert imp.penetration.values.max() < 0.2 * c
    assert imp.attrs["solver_contact_events"] > 10
    assert imp.attrs["solver_jacobian_evaluations"] > 0
    assert imp.contact_force.values.max() == pytest.approx(ref.contact_force.values.max(), rel=0.01)
