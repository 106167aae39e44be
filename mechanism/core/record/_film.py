"""The oil-film force of the lubricated clearance joints, evaluated on a recorded state.

The right-hand side applies the film force without storing it, so the recorder evaluates
it again at every recorded (q, q̇) with the same compiled pieces the right-hand side calls
(the point cache, the clearance kinematics, the short-bearing force of
``mechanism.core.contact._lubrication`` and its breakdown fade): the recorded force is the
one the equations of motion used at that state.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from chaoskit.contract import variable
from mechanism.core._jit import njit_noalloc
from mechanism.core.contact import film_factor, positive_film_force, short_bearing_force
from mechanism.core.joints import PC_RATE, PC_VX, PC_VY, update_points
from mechanism.core.model import Model
from mechanism.core.model import kernels as model_kernels

__all__ = ["FILM_VARIABLES", "film_variables", "lubricated_rows"]

#: columns of the film table: F_r, F_t (N, along e/|e| and k × e/|e|), F_x, F_y (N, on the
#: journal), minimum film thickness h = c − |e| (m)
_FR, _FT, _FX, _FY, _H = range(5)
_FILM_COLUMNS = 5

#: The variables of a full record of a scene with a lubricated joint (dim
#: ``lubricated_joint``).
FILM_VARIABLES: tuple[str, ...] = (
    "film_force_radial",
    "film_force_tangential",
    "film_force_x",
    "film_force_y",
    "film_thickness",
)


def lubricated_rows(model: Model) -> np.ndarray:
    """Rows of the clearance table that carry an oil film (empty for a dry scene)."""
    km = model.kernel
    wet = (km.cj_f[:, model_kernels.CF_VISC] > 0.0) & (
        km.cj_i[:, model_kernels.CI_KIND] == model_kernels.CONTACT_JOURNAL
    )
    return np.flatnonzero(wet).astype(np.int64)


@njit_noalloc()
def _film_history(q, v, pt_i, pt_f, pci, pcf, cj_i, cj_f, rows, out):
    # the computation of the right-hand side's ``film_force_add``, keeping the force
    for i in range(q.shape[0]):
        update_points(q[i], v[i], pt_i, pt_f, pci, pcf)
        for r in range(rows.shape[0]):
            j = rows[r]
            b = cj_i[j, 0]
            jn = cj_i[j, 1]
            # journal rows only (``lubricated_rows``): no slider corner's kernels
            ex, ey, nx, ny, _, e_dot, _, _, _ = model_kernels.contact_kinematics(
                cj_i, cj_f, pcf, j, None
            )
            c = cj_f[j, model_kernels.CF_C]
            ne = math.sqrt(ex * ex + ey * ey)
            eps = ne / c
            row = out[i, r]
            row[_H] = c - ne
            w = film_factor(c, cj_f[j, model_kernels.CF_FILM], eps)
            row[_FR] = 0.0
            row[_FT] = 0.0
            row[_FX] = 0.0
            row[_FY] = 0.0
            if w != 0.0:
                eps_w = eps * (pcf[jn, PC_RATE] + pcf[b, PC_RATE])
                if ne > 0.0:
                    dvx = pcf[jn, PC_VX] - pcf[b, PC_VX]
                    dvy = pcf[jn, PC_VY] - pcf[b, PC_VY]
                    eps_w -= 2.0 * (ex * dvy - ey * dvx) / (c * ne)
                mu = cj_f[j, model_kernels.CF_VISC]
                rj = cj_f[j, model_kernels.CF_RJ]
                length = cj_f[j, model_kernels.CF_LUB_L]
                if cj_f[j, model_kernels.CF_CAV] > 0.0:
                    f_r, f_t = positive_film_force(mu, rj, length, c, eps, e_dot / c, eps_w)
                else:
                    f_r, f_t = short_bearing_force(mu, rj, length, c, eps, e_dot / c, eps_w)
                row[_FR] = w * f_r
                row[_FT] = w * f_t
                # as the right-hand side rounds it
                row[_FX] = w * (f_r * nx - f_t * ny)
                row[_FY] = w * (f_r * ny + f_t * nx)


def film_variables(
    model: Model, q: np.ndarray, v: np.ndarray
) -> tuple[dict[str, xr.Variable], dict[str, tuple]]:
    """The film force and thickness of every lubricated joint at the recorded states
    ``q``, ``v`` (N, n_dof), with their ``lubricated_joint`` coordinate; both empty for
    a scene without a lubricated joint."""
    rows = lubricated_rows(model)
    if rows.size == 0:
        return {}, {}
    km = model.kernel
    ws = model.workspace()
    q = np.ascontiguousarray(q, dtype=np.float64)
    v = np.ascontiguousarray(v, dtype=np.float64)
    out = np.zeros((q.shape[0], rows.size, _FILM_COLUMNS))
    _film_history(q, v, km.pt_i, km.pt_f, ws.pci, ws.pcf, km.cj_i, km.cj_f, rows, out)
    dims = ("time", "lubricated_joint")
    data = {
        "film_force_radial": variable(
            dims,
            out[:, :, _FR],
            "N",
            "oil-film force on the journal along the eccentricity e/|e| "
            "(negative: towards the bearing centre)",
        ),
        "film_force_tangential": variable(
            dims,
            out[:, :, _FT],
            "N",
            "oil-film force on the journal along k x e/|e|",
        ),
        "film_force_x": variable(dims, out[:, :, _FX], "N", "oil-film force on the journal, x"),
        "film_force_y": variable(dims, out[:, :, _FY], "N", "oil-film force on the journal, y"),
        "film_thickness": variable(
            dims,
            out[:, :, _H],
            "m",
            "minimum oil-film thickness c - |e| of the nominal geometry (negative: the "
            "surfaces overlap)",
        ),
    }
    names = np.array([model.clearance_joints[j] for j in rows], dtype=object)
    coords = {"lubricated_joint": ("lubricated_joint", names)}
    return data, coords
