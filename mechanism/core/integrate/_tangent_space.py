"""The constraint manifold around a state of a rigid model: its tangent space, the
projection onto it, the latch a run continues with, and the kinematics and derivative of a
state — what callers of :func:`integrate_tangent` (periodic orbits, sections) read.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from mechanism.core.model import kernels as model_kernels

from . import _tangent_kernels as tangent_kernels
from ._methods import initial_latch

if TYPE_CHECKING:
    from mechanism.core.model import Model

__all__ = [
    "clearance_kinematics",
    "project_state",
    "section_latch",
    "state_derivative",
    "tangent_basis",
]


def section_latch(
    model: Model, y: np.ndarray, held: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The latch a run from state ``y`` continues with: (impact velocities (m/s), contact
    flags) of the clearance joints.

    A separated joint tracks its approach speed (floored, as the integrators do); a joint
    in contact keeps its value from ``held`` (the impact velocity latched when the contact
    began), or the floor without it, as :func:`mechanism.simulate` starts.
    """
    vimp, contact = initial_latch(model, np.ascontiguousarray(y, dtype=np.float64))
    if held is not None:
        inside = contact != 0
        vimp[inside] = np.asarray(held, dtype=np.float64)[inside]
    return vimp, contact


def tangent_basis(model: Model, y: np.ndarray, *, t: float, time_scale: float) -> np.ndarray:
    """Orthonormal basis of the tangent space of the constraint manifold at ``y``.

    Returns
    -------
    numpy.ndarray
        (2n, 2f) columns, f = n − m the scene's degrees of freedom, orthonormal in the
        scaled norm ``|δq|² + τ²|δq̇|²`` (τ = ``time_scale``): the directions a state of the
        scene can move in (:func:`initial_deviation` projects a random one onto it).

    Raises
    ------
    ValueError
        Without a degree of freedom, or with a singular constraint Jacobian at ``y``.
    """
    n = model.n_dof
    free = n - model.n_rows
    if free <= 0:
        raise ValueError(
            f"the scene has no degree of freedom ({n} coordinates, {model.n_rows} "
            "constraint equations): its motion is prescribed by the drive."
        )
    y = np.ascontiguousarray(y, dtype=np.float64)
    ws, ws2 = model.workspace(), model.workspace()
    scale = np.concatenate([np.ones(n), np.full(n, float(time_scale))])
    columns = np.empty((2 * n, 2 * n))
    for i in range(2 * n):
        e = np.zeros(2 * n)
        e[i] = 1.0 / scale[i]
        if not tangent_kernels.project_tangent(
            model.kernel, ws, ws2, float(t), y, e, np.empty(2 * n)
        ):
            raise ValueError("the constraint Jacobian is singular at the state.")
        columns[:, i] = e * scale
    u, _, _ = np.linalg.svd(columns)
    return u[:, : 2 * free] / scale[:, None]


def project_state(model: Model, y: np.ndarray, *, t: float, tol: float = 1e-14) -> np.ndarray:
    """``y`` moved onto the constraint manifold Φ(q, t) = 0, Φq q̇ + Φt = 0 at time ``t``
    (minimum-mass-norm corrections, as the simulator's projection).

    Raises
    ------
    ValueError
        On a singular constraint Jacobian.
    """
    out = np.ascontiguousarray(y, dtype=np.float64).copy()
    if not model_kernels.project(model.kernel, model.workspace(), float(t), out, float(tol), 20):
        raise ValueError("the constraint Jacobian is singular at the state.")
    return out


def clearance_kinematics(
    model: Model, states: np.ndarray, *, t: np.ndarray, latch: np.ndarray
) -> np.ndarray:
    """Relative journal position and penetration of every clearance joint at states.

    Parameters
    ----------
    states : numpy.ndarray
        (samples, 2n) states [q; q̇].
    t : numpy.ndarray
        (samples,) times (s).
    latch : numpy.ndarray
        (samples, joints) latched impact velocities (m/s).

    Returns
    -------
    numpy.ndarray
        (samples, joints, 4): eccentricity x and y (m, journal centre relative to the
        bearing centre, as ``simulate`` records them), penetration δ (m, > 0 in contact)
        and its rate δ̇ (m/s).
    """
    km = model.kernel
    ws = model.workspace()
    states = np.ascontiguousarray(np.atleast_2d(states), dtype=np.float64)
    latch = np.ascontiguousarray(np.atleast_2d(latch), dtype=np.float64)
    times = np.broadcast_to(np.asarray(t, dtype=np.float64), (states.shape[0],))
    columns = np.array(
        [model_kernels.CJ_EX, model_kernels.CJ_EY, model_kernels.CJ_DELTA,
         model_kernels.CJ_DELTA_DOT], dtype=np.int64,
    )  # fmt: skip
    out = np.empty((states.shape[0], km.cj_i.shape[0], 4))
    tangent_kernels.clearance_rows(km, ws, np.ascontiguousarray(times), states, latch, columns, out)
    return out


def state_derivative(model: Model, y: np.ndarray, *, t: float, latch: np.ndarray) -> np.ndarray:
    """The right-hand side f(t, y) = [q̇; q̈] of the rigid equations of motion, with the
    clearance joints' latched impact velocities ``latch`` (m/s).

    Raises
    ------
    ValueError
        When the constraint matrix is singular at ``y``.
    """
    y = np.ascontiguousarray(y, dtype=np.float64)
    out = np.zeros_like(y)
    counters = np.zeros(model_kernels.CNT_COLUMNS, dtype=np.int64)
    vimp = np.ascontiguousarray(latch, dtype=np.float64)
    if (
        model_kernels.rhs(model.kernel, model.workspace(), float(t), y, vimp, out, counters)
        != model_kernels.STATUS_OK
    ):
        raise ValueError("the constraint matrix is singular at the state.")
    return out
