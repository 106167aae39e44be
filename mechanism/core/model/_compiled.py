"""The compiled model: the flat tables the kernels read (:class:`KernelModel`), their
scratch arrays (:class:`Workspace`) and the :class:`Model` that names what the tables hold
(bodies, coordinates, joint reactions, outputs)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from mechanism.core.bodies import AncfLayout, beam_work
from mechanism.core.forces import FO_COLUMNS, force_elements_add
from mechanism.core.joints import PCF_COLUMNS, PCI_COLUMNS, update_points
from mechanism.core.scene import ClearancePrismatic, ClearanceRevolute, Scene

from . import _kernels as model_kernels

__all__ = [
    "IdealJointRows",
    "KernelModel",
    "Model",
    "SliderMap",
    "Workspace",
    "with_effect_switches",
]


class KernelModel(NamedTuple):
    """The arrays the compiled kernels read (contiguous int64 / float64)."""

    n_dof: int
    n_rows: int
    mass: np.ndarray  # (n, n) constant mass matrix
    minv: np.ndarray  # (n, n) its inverse (block diagonal)
    blk_lo: np.ndarray  # (n,) first coordinate of the mass block of coordinate i
    blk_hi: np.ndarray  # (n,) one past its last coordinate
    # (n,) 2 where coordinate i's mass block couples only coordinates of the same parity
    # (an ANCF rod's x and y planes), else 1; minv_h[i] is then row i of M⁻¹ over them
    blk_st: np.ndarray
    minv_h: np.ndarray | None  # (n, largest such block / 2); None without such blocks
    gravity_force: np.ndarray  # (n,) constant generalised gravity
    pt_i: np.ndarray
    pt_f: np.ndarray
    con_i: np.ndarray
    con_f: np.ndarray
    drive_i: np.ndarray  # [kind, constraint index]
    drive_f: np.ndarray  # [θ₀, ω, period, ramp per period]
    spline_x: np.ndarray
    spline_c: np.ndarray
    # (n_cj, CI_COLUMNS) [bearing point, journal point, law code, friction code, kind]; a
    # slider corner (kind CONTACT_GUIDE) has the guide point and the corner point
    cj_i: np.ndarray
    cj_f: np.ndarray  # (n_cj, CF_COLUMNS)
    cw_i: np.ndarray  # (n_cj, CW_COLUMNS) worn-profile layout
    cw_f: np.ndarray  # (n_cj, 2) [E*, radius ratio limit]
    cw_h: np.ndarray  # flat wear depths (m) of all worn surfaces
    cw_k: np.ndarray  # flat tabulated curvatures (1/m) of the same regions
    out_i: np.ndarray  # [crank point a, crank point b, guide point, slider point] (−1: none)
    out_f: np.ndarray  # [ux, uy] slider guide axis in the guide body's frame
    jt_i: np.ndarray  # (n_ideal, 3) [JOINT_PIN | JOINT_PRISMATIC, first row, guide point]
    jt_f: np.ndarray  # (n_ideal, 2) prismatic guide normal in the guide body's frame
    alpha: float
    beta: float
    # flexible bodies : one row per ANCF beam, see ``beams_force_add``
    beam_i: np.ndarray  # (n_beams, BEAM_I_COLUMNS) int64
    beam_f: np.ndarray  # (n_beams, BEAM_F_COLUMNS) float64
    # force elements (springs, dampers, loads): see ``mechanism.core.forces._kernels``
    fe_i: np.ndarray  # (n_elements, FI_COLUMNS) int64
    fe_f: np.ndarray  # (n_elements, FF_COLUMNS) float64
    fe_t: np.ndarray  # flat tables and Fourier coefficients
    # Which effects the kernels are compiled for: None when the scene has none of an
    # effect, True when it may (the default: everything compiled). numba removes a branch
    # on an argument that is None before type inference, so the kernels behind a None
    # switch are not compiled at all; a dry rigid scene compiles no ANCF, force-element,
    # worn-contact or oil-film kernel (set by :func:`with_effect_switches`).
    beams_on: bool | None = True
    forces_on: bool | None = True
    worn_on: bool | None = True
    film_on: bool | None = True
    guide_on: bool | None = True  # slider corners of a translational clearance joint


def with_effect_switches(km: KernelModel, scene: Scene) -> KernelModel:
    """``km`` with each effect switch None where ``scene`` lacks the effect.

    Beams: no ANCF beam rows. Force elements: no element rows. Worn contact: no revolute
    clearance joint (the joints a wear profile applies to) or ``effects.clearance`` off.
    Oil film: no lubricated revolute clearance joint, or ``effects.clearance`` off. Slider
    corners: no translational clearance joint, or ``effects.clearance`` off. The
    switches follow the scene, not the tables, so every model assembled from one scene has
    the same switches and compiles the same kernels: the ideal companion of a run (its
    clearance joints made ideal) and the initial assembly compile nothing new. An unworn
    revolute clearance joint keeps the worn-contact kernels: the wear studies run one
    scene before and after wear, and a second specialisation would compile the whole run
    again. A switch is None only where the kernels would skip the effect at run time
    anyway, so the switches change what is compiled, never a result.
    """
    joints = [j for j in scene.joints.values() if isinstance(j, ClearanceRevolute)]
    guides = any(isinstance(j, ClearancePrismatic) for j in scene.joints.values())
    if not scene.effects.clearance:
        joints = []
        guides = False
    return km._replace(
        beams_on=True if km.beam_i.shape[0] > 0 else None,
        forces_on=True if km.fe_i.shape[0] > 0 else None,
        worn_on=True if joints else None,
        film_on=True if any(j.lubrication is not None for j in joints) else None,
        guide_on=True if guides else None,
    )


class Workspace(NamedTuple):
    """Scratch arrays of one right-hand-side evaluation (allocated once per run)."""

    phi: np.ndarray
    phiq: np.ndarray
    phit: np.ndarray
    gam: np.ndarray
    gen: np.ndarray
    a0: np.ndarray
    w: np.ndarray
    s: np.ndarray
    lam: np.ndarray
    cj: np.ndarray
    pci: np.ndarray
    pcf: np.ndarray
    nz_n: np.ndarray
    nz_j: np.ndarray
    fe: np.ndarray  # (n_elements, FO_COLUMNS) force, coordinate and rate of each element
    beam: np.ndarray  # scratch of the beams' elastic forces (``beam_work``)


@dataclass(frozen=True, kw_only=True)
class IdealJointRows:
    """Where an ideal joint's reaction lives in λ.

    ``kind``: ``"revolute"`` (rows r, r+1 = force on ``bodies[1]`` in x, y),
    ``"prismatic"`` (row r = relative angle → reaction moment, r+1 = normal force),
    ``"fixed"`` (r, r+1 force, r+2 moment). ``normal`` is the guide normal in the frame
    of ``bodies[0]`` for prismatic joints.
    """

    name: str
    kind: str
    row: int
    normal: tuple[float, float] = (0.0, 0.0)
    guide_point: int = -1


@dataclass(frozen=True, kw_only=True)
class SliderMap:
    """Slider output of a prismatic joint: s = u·(r_b − r_a), u = A(θ_a) ū."""

    joint: str
    guide_point: int
    slider_point: int
    axis: tuple[float, float]


@dataclass(frozen=True, kw_only=True)
class Model:
    """A scene compiled for the time loop (immutable; arrays are not to be modified).

    Attributes
    ----------
    scene : Scene
        The scene it was assembled from.
    kernel : KernelModel
        The compiled tables.
    body_names, body_offsets
        Bodies in coordinate order and the index of each body's first coordinate.
    rigid_bodies
        Names of the bodies with (x, y, θ) coordinates (outputs ``position``/``velocity``).
    beams
        Layout of every flexible ANCF beam by body name (empty when
        ``effects.flexibility`` is off); its coordinates start at its body offset.
    dof_names
        ``"body.coordinate"`` for every coordinate.
    ideal_joints
        Reaction layout of every ideal joint (including clearance joints made ideal).
    clearance_joints
        Names of the rows of the clearance table, which act through contact forces (empty
        when ``effects.clearance`` is off): a revolute clearance joint's name, and
        ``NAME.upper_front``, ``NAME.upper_rear``, ``NAME.lower_front``,
        ``NAME.lower_rear`` for the four slider corners of a translational one.
    force_elements
        Names of the scene's force elements in the row order of the kernel tables.
    drive_row
        Row of the driving constraint in λ (driving torque T = −λ), or None.
    crank_points
        (point a, point b) whose relative angle is the crank angle, or None.
    slider
        Slider output map, or None.
    q_guess
        Initial coordinates from the scene's pose guesses.
    """

    scene: Scene
    kernel: KernelModel
    body_names: tuple[str, ...]
    body_offsets: tuple[int, ...]
    rigid_bodies: tuple[str, ...]
    beams: dict[str, AncfLayout]
    dof_names: tuple[str, ...]
    point_index: dict[tuple[str, str], int]
    ideal_joints: tuple[IdealJointRows, ...]
    clearance_joints: tuple[str, ...]
    force_elements: tuple[str, ...]
    drive_row: int | None
    crank_points: tuple[int, int] | None
    slider: SliderMap | None
    q_guess: np.ndarray

    @property
    def n_dof(self) -> int:
        return self.kernel.n_dof

    @property
    def n_rows(self) -> int:
        return self.kernel.n_rows

    def force_element_values(self, t: np.ndarray, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Force, coordinate and rate of every force element at each sample, on request.

        Parameters
        ----------
        t : numpy.ndarray
            Times (N,), s.
        q, v : numpy.ndarray
            Coordinates and velocities (N, n_dof). For a model of rigid bodies only they
            are a run's ``position`` and ``velocity`` reshaped to (N, 3 × bodies).

        Returns
        -------
        numpy.ndarray
            (N, len(force_elements), 3): [..., 0] the spring tension (N), the torsional
            moment on the joint's second body (N m) or the load factor (1); [..., 1] the
            deflection L − L₀ (m), the angle φ − φ₀ (rad) or the profile's joint
            coordinate; [..., 2] its rate.
        """
        t = np.ascontiguousarray(t, dtype=np.float64)
        q = np.ascontiguousarray(q, dtype=np.float64).reshape(t.size, self.n_dof)
        v = np.ascontiguousarray(v, dtype=np.float64).reshape(t.size, self.n_dof)
        ws = self.workspace()
        out = np.zeros((t.size, len(self.force_elements), FO_COLUMNS))
        km = self.kernel
        for i in range(t.size):
            update_points(q[i], v[i], km.pt_i, km.pt_f, ws.pci, ws.pcf)
            force_elements_add(km.fe_i, km.fe_f, km.fe_t, t[i], ws.pci, ws.pcf, ws.gen, out[i])
        return out

    def workspace(self) -> Workspace:
        """Fresh scratch arrays for the kernels."""
        n = self.n_dof
        m = self.n_rows
        n_points = self.kernel.pt_i.shape[0]
        return Workspace(
            phi=np.zeros(m),
            phiq=np.zeros((m, n)),
            phit=np.zeros(m),
            gam=np.zeros(m),
            gen=np.zeros(n),
            a0=np.zeros(n),
            w=np.zeros((n, m)),
            s=np.zeros((m, m)),
            lam=np.zeros(m),
            cj=np.zeros((self.kernel.cj_i.shape[0], model_kernels.CJ_COLUMNS)),
            pci=np.zeros((n_points, PCI_COLUMNS), dtype=np.int64),
            pcf=np.zeros((n_points, PCF_COLUMNS)),
            nz_n=np.zeros(m, dtype=np.int64),
            nz_j=np.zeros((m, n), dtype=np.int64),
            fe=np.zeros((self.kernel.fe_i.shape[0], FO_COLUMNS)),
            beam=beam_work(self.kernel.beam_i),
        )
