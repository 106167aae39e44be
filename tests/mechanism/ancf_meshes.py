"""Meshes, states and central differences shared by the ANCF element and energy tests."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from mechanism.core import AncfMesh

LAWS = [
    (axial, curvature)
    for axial in ("biot", "green")
    for curvature in ("material", "geometric", "linear")
]


def ancf_mesh(n_elements: int = 3, **kw: Any) -> AncfMesh:
    """A steel rod of the paper's section, 0.9 m long unless ``kw`` says otherwise."""
    base: dict[str, Any] = dict(
        length=0.9,
        n_elements=n_elements,
        area=1e-3,
        second_moment=3.33e-8,
        youngs_modulus=207e9,
        density=7800.0,
    )
    base.update(kw)
    return AncfMesh(**base)


def deformed(mesh: AncfMesh, seed: int = 0, amplitude: float = 0.03) -> np.ndarray:
    """The straight beam at 0.4 rad from (0.1, −0.2) plus Gaussian noise of ``amplitude``."""
    rng = np.random.default_rng(seed)
    noise = amplitude * rng.standard_normal(mesh.n_dofs)
    return mesh.straight_coordinates((0.1, -0.2), angle=0.4) + noise


def central_difference(func: Callable[[np.ndarray], Any], x: np.ndarray, h: float) -> np.ndarray:
    """(f(x + h eᵢ) − f(x − h eᵢ)) / 2h for every i, as the last axis (a gradient for a
    scalar f, a Jacobian for a vector f)."""
    columns = []
    for i in range(x.size):
        d = np.zeros(x.size)
        d[i] = h
        columns.append((np.asarray(func(x + d)) - np.asarray(func(x - d))) / (2.0 * h))
    return np.stack(columns, axis=-1)
