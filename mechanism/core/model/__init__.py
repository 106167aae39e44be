"""The compiled model: a scene assembled once into flat tables the time loop evaluates."""

# the compiled right-hand side, constraints, contact state and their table layouts, for the
# integrators and the recorder; not public API
from . import _kernels as kernels
from ._assemble import assemble, initial_state
from ._compiled import KernelModel, Model, Workspace

# the names the compiled integrator loops call (numba resolves them as globals of the
# importing module, so they are bound by name rather than reached through ``kernels``)
from ._kernels import (
    CF_FILM,
    CF_FLOOR,
    CF_V0,
    CF_V1,
    CF_VISC,
    CJ_DELTA,
    CJ_DELTA_DOT,
    CJ_FN,
    CJ_PHI_B,
    CJ_VT,
    CNT_COLUMNS,
    CNT_CONTACT_EVENTS,
    CNT_FEV,
    CNT_JAC,
    CNT_NEWTON,
    CNT_REJECTED,
    CNT_STEPS,
    CW_WORN,
    accelerations,
    approach_step,
    beams_energy_if,
    beams_force_if,
    cholesky_solve,
    clearance_forces,
    clearance_state,
    crank_angle,
    derived_outputs,
    entry_depth_ratio,
    evaluate_constraints,
    forces_add_if,
    forces_energy_if,
    journal_travel_ratio,
    light_outputs,
    project,
    rhs,
    schur,
    solve,
    update_latch,
)

__all__ = ["KernelModel", "Model", "Workspace", "assemble", "initial_state"]
