"""Bodies of a mechanism: rigid bodies (reference-point coordinates) and, with
flexible ANCF beams. Assembly uses their layouts; users describe bodies in scenes."""

from ._ancf_analysis import (
    BeamModes,
    BeamStaticSolution,
    beam_modes,
    euler_bernoulli_frequencies,
    solve_beam_static,
)

# compiled beam kernels and their table layouts, for assembly and the integrators
from ._ancf_kernels import (
    BEAM_F_COLUMNS,
    BEAM_F_DAMPING,
    BEAM_I_COLUMNS,
    beam_work,
    beams_force_add,
    beams_jacobian_add,
    beams_strain_energy,
)
from ._ancf_layout import AncfLayout
from ._ancf_mesh import AncfMesh
from ._rigid import RigidLayout, rigid_bar_from_beam

__all__ = [
    "AncfLayout",
    "AncfMesh",
    "BeamModes",
    "BeamStaticSolution",
    "RigidLayout",
    "beam_modes",
    "euler_bernoulli_frequencies",
    "rigid_bar_from_beam",
    "solve_beam_static",
]
