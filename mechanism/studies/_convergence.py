"""Element-convergence study of flexible rods.

Jia et al. (Lubricants 2025, 13(3), 130) report the extreme axial strains of rods 3 and 4
for 4…24 ANCF elements per rod and settle on 16. :func:`element_convergence` repeats that
study for any scene with ANCF beams: the chosen rods are re-meshed, the scene is simulated
for each element count, and the signed extreme strain of every flexible rod (and the peak
contact force of each clearance joint) is tabulated against the element count.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from chaoskit.contract import check_int
from mechanism.core import Scene, simulate
from mechanism.core.integrate import Integrator
from mechanism.core.scene import AncfBeam

__all__ = ["ElementConvergence", "element_convergence"]


@dataclass(frozen=True, kw_only=True)
class ElementConvergence:
    """Extreme rod strains (and peak contact forces) against the number of elements.

    Attributes
    ----------
    scene_name : str
        Name of the scene studied.
    refined : tuple of str
        Rods whose element count was varied.
    elements : numpy.ndarray
        Element counts (int).
    rods : tuple of str
        Every flexible rod of the scene.
    strain : numpy.ndarray
        (elements, rods) signed extreme axial strain over the run, micro-strain.
    joints : tuple of str
        Clearance joints with contact forces.
    contact_force : numpy.ndarray
        (elements, joints) peak normal contact force, N.
    wall_time : numpy.ndarray
        Wall time of each simulation, s.
    revolutions, t_end : float
        Simulated duration (drive periods, s).
    method : str
        Integrator name.
    """

    scene_name: str
    refined: tuple[str, ...]
    elements: np.ndarray
    rods: tuple[str, ...]
    strain: np.ndarray
    joints: tuple[str, ...]
    contact_force: np.ndarray
    wall_time: np.ndarray
    t_end: float
    method: str

    def relative_change(self) -> np.ndarray:
        """(elements, rods) ``|ε(n_k) − ε(n_{k−1})| / |ε(n_k)|``; NaN in the first row."""
        out = np.full(self.strain.shape, np.nan)
        out[1:] = np.abs(np.diff(self.strain, axis=0)) / np.abs(self.strain[1:])
        return out

    def to_dataset(self) -> xr.Dataset:
        """The table as a Dataset (dims ``elements``, ``rod``, ``joint``)."""
        ds = xr.Dataset(
            {
                "strain": (
                    ("elements", "rod"),
                    self.strain,
                    {"units": "1e-6", "long_name": "signed extreme axial strain (micro-strain)"},
                ),
                "strain_relative_change": (
                    ("elements", "rod"),
                    self.relative_change(),
                    {"units": "1", "long_name": "relative change from the previous mesh"},
                ),
                "contact_force": (
                    ("elements", "joint"),
                    self.contact_force,
                    {"units": "N", "long_name": "peak normal contact force"},
                ),
                "wall_time": (
                    ("elements",),
                    self.wall_time,
                    {"units": "s", "long_name": "wall time of the simulation"},
                ),
            },
            coords={
                "elements": (
                    "elements",
                    self.elements,
                    {"units": "1", "long_name": "elements per refined rod"},
                ),
                "rod": ("rod", np.array(self.rods, dtype=object)),
                "joint": ("joint", np.array(self.joints, dtype=object)),
            },
        )
        ds.attrs.update(
            scene_name=self.scene_name,
            refined=",".join(self.refined),
            t_end=self.t_end,
            method=self.method,
        )
        return ds

    def to_markdown(self) -> str:
        """The table in the paper's layout: one row per element count."""
        head = ["elements", *(f"{r} (µε)" for r in self.rods)]
        head += [f"F_max {j} (N)" for j in self.joints] + ["wall (s)"]
        lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for i, n in enumerate(self.elements):
            cells = [str(int(n)), *(f"{x:.2f}" for x in self.strain[i])]
            cells += [f"{f:.1f}" for f in self.contact_force[i]] + [f"{self.wall_time[i]:.2f}"]
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)


def element_convergence(
    scene: Scene,
    *,
    rods: Sequence[str] | None = None,
    elements: Sequence[int] = (4, 8, 12, 16, 20, 24),
    revolutions: float | None = None,
    t_end: float | None = None,
    method: str | Integrator | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    output_step: float | None = None,
    progress: bool = False,
) -> ElementConvergence:
    """Simulate ``scene`` with each element count and tabulate the extreme rod strains.

    ε_ext = the value of largest ``|ε|`` over the run and over the nodes and element
    mid-points of the rod (× 1e6, positive = tension), as the paper's convergence table
    (Jia et al. 2025, §4.1).

    Parameters
    ----------
    scene : mechanism.core.scene.Scene
        A scene with ANCF beam bodies; ``effects.flexibility`` is switched on.
    rods : sequence of str, optional
        Beams whose ``elements`` are set to each count (default: every ANCF beam).
    elements : sequence of int
        Element counts, each 1…10000.
    revolutions, t_end, method, rtol, atol, output_step, progress
        As for :func:`mechanism.simulate`.

    Returns
    -------
    ElementConvergence

    Examples
    --------
    >>> import mechanism
    >>> sc = mechanism.load_scene("flexible-slider-crank")
    >>> table = element_convergence(sc, elements=(2, 4), t_end=0.002)
    >>> table.strain.shape
    (2, 1)
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a mechanism Scene; got {type(scene).__name__}.")
    beams = [name for name, body in scene.bodies.items() if isinstance(body, AncfBeam)]
    if not beams:
        raise ValueError(f"scene {scene.name!r} has no ANCF beam bodies to refine.")
    refined = tuple(beams if rods is None else rods)
    if not refined:
        raise ValueError("rods must name at least one ANCF beam.")
    for name in refined:
        if name not in beams:
            raise ValueError(
                f"rods: {name!r} is not an ANCF beam of scene {scene.name!r}; its beams are "
                f"{beams}."
            )
    counts = [check_int(n, name="elements", minimum=1, maximum=10000) for n in elements]
    if not counts:
        raise ValueError("elements must list at least one element count.")
    strain = np.empty((len(counts), len(beams)))
    forces: list[np.ndarray] = []
    joints: tuple[str, ...] = ()
    wall = np.empty(len(counts))
    duration = math.nan
    method_name = ""
    for i, n in enumerate(counts):
        changes: dict[str, Any] = {"effects.flexibility": True}
        changes.update({f"bodies.{name}.elements": n for name in refined})
        ds = None
        start = time.perf_counter()
        ds = simulate(
            scene.replace(changes),
            revolutions=revolutions,
            t_end=t_end,
            method=method,
            rtol=rtol,
            atol=atol,
            output_step=output_step,
            progress=progress,
        )
        wall[i] = time.perf_counter() - start
        strain[i] = [float(ds[f"strain_{name}"]) for name in beams]
        if "contact_force" in ds:
            joints = tuple(str(j) for j in ds["joint"].values)
            forces.append(ds["contact_force"].max("time").values.astype(np.float64))
        else:
            forces.append(np.zeros(0))
        duration = float(ds.attrs["t_end"])
        method_name = str(ds.attrs["solver_method"])
    return ElementConvergence(
        scene_name=scene.name,
        refined=refined,
        elements=np.array(counts, dtype=np.int64),
        rods=tuple(beams),
        strain=strain,
        joints=joints,
        contact_force=np.array(forces).reshape(len(counts), len(joints)),
        wall_time=wall,
        t_end=duration,
        method=method_name,
    )
