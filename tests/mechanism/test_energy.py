"""Energy conservation of the clearance slider-crank without dissipation, and the
constraint-drift bound documented in docs/simulator.md."""

from __future__ import annotations

import numpy as np
import pytest

from mechanism.core.integrate import Dopri5, GeneralizedAlpha, StepSettings
from mechanism.core.model import _kernels as k
from mechanism.core.model import assemble, initial_state
from tests.mechanism.scenes import s3

#: documented bound on max|Φ| (m) for rtol = atol = 1e-10 over 1 s (docs/simulator.md)
DRIFT_BOUND = 1e-10


def _coasting_mechanism():
    """S3 with restitution 1 (no L-N damping), no friction, no gravity and no driver,
    started with the ideal-mechanism velocities of 1000 rpm: it coasts, the journal
    rattles in the bearing and kinetic + contact energy is conserved."""
    driven = s3(**{"joints.B.restitution": 1.0, "effects.gravity": False, "drive.speed_rpm": 1000})
    q0, v0 = initial_state(assemble(driven))
    free = assemble(driven.replace({"drive": None}))
    assert free.drive_row is None and free.n_rows == 6
    return free, np.concatenate([q0, v0])


def _series(model, rec):
    energy = np.empty(rec.t.size)
    k.energy_series(model.kernel, model.workspace(), rec.q, rec.v, energy)
    drift = np.empty(rec.t.size)
    k.violation_series(model.kernel, model.workspace(), rec.t, rec.q, rec.v, drift)
    return energy, drift


def test_energy_is_conserved_to_1e6_over_one_second() -> None:
    model, y0 = _coasting_mechanism()
    t_out = np.linspace(0.0, 1.0, 2001)
    run = Dopri5().integrate(
        model, y0, t_out, steps=StepSettings(rtol=1e-10, atol=1e-10, max_step=np.inf)
    )
    assert run.stats.success
    rec = run.recording
    # the test is only meaningful with many impacts
    assert run.stats.contact_events > 100
    assert np.count_nonzero(rec.cj[:, 0, k.CJ_FN] > 0) > 20
    energy, drift = _series(model, rec)
    assert energy[0] > 1.0
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-6
    assert drift.max() < DRIFT_BOUND


def test_contact_potential_is_part_of_the_energy() -> None:
    """During an impact kinetic energy dips and K δ^(n+1)/(n+1) makes up for it."""
    model, y0 = _coasting_mechanism()
    t_out = np.linspace(0.0, 0.05, 50001)
    run = Dopri5().integrate(
        model, y0, t_out, steps=StepSettings(rtol=1e-10, atol=1e-10, max_step=np.inf)
    )
    rec = run.recording
    energy, _ = _series(model, rec)
    mass = model.kernel.mass
    kinetic = 0.5 * np.einsum("ti,ij,tj->t", rec.v, mass, rec.v)
    in_contact = rec.cj[:, 0, k.CJ_DELTA] > 0
    assert in_contact.any()
    dip = (energy - kinetic)[in_contact].max()
    assert dip > 1e-3 * energy[0]  # a visible share of the energy sits in the contact
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-6


def test_generalized_alpha_without_numerical_damping_keeps_energy_bounded() -> None:
    """ρ∞ = 1 (trapezoidal) neither dissipates nor gains more than its tolerance allows."""
    model, y0 = _coasting_mechanism()
    t_out = np.linspace(0.0, 0.1, 1001)
    run = GeneralizedAlpha(rho_inf=1.0).integrate(
        model, y0, t_out, steps=StepSettings(rtol=1e-8, atol=1e-8, max_step=np.inf)
    )
    assert run.stats.success
    energy, drift = _series(model, run.recording)
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-3
    assert drift.max() < 1e-8


@pytest.mark.slow
def test_energy_over_ten_seconds() -> None:
    model, y0 = _coasting_mechanism()
    t_out = np.linspace(0.0, 10.0, 2001)
    run = Dopri5().integrate(
        model, y0, t_out, steps=StepSettings(rtol=1e-11, atol=1e-11, max_step=np.inf)
    )
    energy, drift = _series(model, run.recording)
    assert np.abs(energy / energy[0] - 1.0).max() < 1e-6
    assert drift.max() < DRIFT_BOUND
