"""Work-precision of the flexible slider-crank (S6): ``mechanism`` against Exudyn 1.13.6.

Both codes integrate the *same* discretised model: the built-in scene
``flexible-slider-crank`` (16 ANCF elements, Biot strain, material curvature, 5/3 Gauss
points), which is Exudyn's ``ObjectANCFCable2D`` element, from the same initial state
(taken from ``mechanism``'s assembled model, node by node). The crank turns at a
prescribed 150 rad/s (Exudyn: a velocity-level coordinate constraint on its angle), the
slider is a point mass on the x axis pinned to the rod's end node.

The error of a run is measured against the converged solution of this model, not
against Simeon's modal reference (a different model, 1.4e-5 m away from the converged
ANCF solution at t = 0.1 s, docs/ancf.md §7): ``mechanism`` at h = ``--ref-step``
(2.5e-7 s, ρ∞ = 1). Reported per run: CPU time (``time.process_time`` around
``mechanism.simulate`` / ``exudyn.SolveDynamic``, best of ``--repeat`` interleaved
rounds, numba warmed up), the slider error at t = 0.1 s and the largest slider error on
the 1 ms output grid over [0, 0.1] s. Writes ``docs/benchmarks/flexible-vs-exudyn.csv``::

    NUMBA_NUM_THREADS=1 python benchmarks/flexible_vs_exudyn.py [--repeat 2] [--quick]
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    CoordinateConstraint,
    MarkerBodyPosition,
    MarkerNodeCoordinate,
    MarkerNodePosition,
    MassPoint2D,
    NodePoint2D,
    NodePoint2DSlope1,
    NodePointGround,
    NodeRigidBody2D,
    ObjectANCFCable2D,
    ObjectGround,
    ObjectRigidBody2D,
    RevoluteJoint2D,
    SensorNode,
)

import mechanism
from mechanism.core.model import assemble, initial_state

OUT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks" / "flexible-vs-exudyn.csv"
S6_X = 0.169737332842786  # Simeon's modal reference at t = 0.1 s
T_END = 0.1
GRID = 1e-3
STEPS = (2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6)
SCENE = "flexible-slider-crank"


def ours(h: float, rho_inf: float) -> tuple[np.ndarray, float, dict]:
    """Slider x on the output grid, CPU seconds and solver counts of ``mechanism``."""
    scene = mechanism.load_scene(SCENE).replace({"solver.max_step": h, "solver.rho_inf": rho_inf})
    start = time.process_time()
    ds = mechanism.simulate(scene, t_end=T_END, output_step=GRID)
    cpu = time.process_time() - start
    a = ds.attrs
    counts = dict(
        steps=a["solver_steps"],
        rhs=a["solver_function_evaluations"],
        jacobians=a["solver_jacobian_evaluations"],
        newton=a["solver_newton_iterations"],
    )
    return ds.slider_position.values, cpu, counts


def _exudyn_model(q0: np.ndarray, v0: np.ndarray):
    """Exudyn's S6 from ``mechanism``'s initial state (crank x, y, θ; 17 ANCF nodes of
    4 coordinates; slider x, y, θ)."""
    sc = mechanism.load_scene(SCENE)
    rod = sc.bodies["rod"]
    crank = sc.bodies["crank"]
    slider = sc.bodies["slider"]
    n_el = rod.elements
    area, inertia, young, rho = rod.area, rod.second_moment, rod.youngs_modulus, rod.density
    system = exu.SystemContainer()
    mbs = system.AddSystem()
    n_crank = mbs.AddNode(
        NodeRigidBody2D(referenceCoordinates=list(q0[0:3]), initialVelocities=list(v0[0:3]))
    )
    o_crank = mbs.AddObject(
        ObjectRigidBody2D(physicsMass=crank.mass, physicsInertia=crank.inertia, nodeNumber=n_crank)
    )
    ground = mbs.AddObject(ObjectGround())
    m_o = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0.0, 0.0, 0.0]))
    half = 0.5 * float(np.hypot(*np.subtract(crank.points["A"], crank.points["O"])))
    m_co = mbs.AddMarker(MarkerBodyPosition(bodyNumber=o_crank, localPosition=[-half, 0.0, 0.0]))
    m_ca = mbs.AddMarker(MarkerBodyPosition(bodyNumber=o_crank, localPosition=[half, 0.0, 0.0]))
    mbs.AddObject(RevoluteJoint2D(markerNumbers=[m_o, m_co]))
    m_fixed = mbs.AddMarker(
        MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()), coordinate=0)
    )
    m_angle = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n_crank, coordinate=2))
    mbs.AddObject(
        CoordinateConstraint(
            markerNumbers=[m_fixed, m_angle], offset=float(v0[2]), velocityLevel=True
        )
    )
    nodes = [
        mbs.AddNode(
            NodePoint2DSlope1(
                referenceCoordinates=list(q0[3 + 4 * j : 7 + 4 * j]),
                initialVelocities=list(v0[3 + 4 * j : 7 + 4 * j]),
            )
        )
        for j in range(n_el + 1)
    ]
    for e in range(n_el):
        mbs.AddObject(
            ObjectANCFCable2D(
                physicsLength=rod.length / n_el, physicsMassPerLength=rho * area,
                physicsBendingStiffness=young * inertia, physicsAxialStiffness=young * area,
                nodeNumbers=[nodes[e], nodes[e + 1]],
            )
        )  # fmt: skip
    mbs.AddObject(
        RevoluteJoint2D(
            markerNumbers=[m_ca, mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[0]))]
        )
    )
    n_slider = mbs.AddNode(
        NodePoint2D(referenceCoordinates=list(q0[-3:-1]), initialVelocities=list(v0[-3:-1]))
    )
    mbs.AddObject(MassPoint2D(physicsMass=slider.mass, nodeNumber=n_slider))
    m_end = mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1]))
    mbs.AddObject(
        RevoluteJoint2D(
            markerNumbers=[m_end, mbs.AddMarker(MarkerNodePosition(nodeNumber=n_slider))]
        )
    )
    m_sy = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=n_slider, coordinate=1))
    mbs.AddObject(CoordinateConstraint(markerNumbers=[m_fixed, m_sy]))
    sensor = mbs.AddSensor(
        SensorNode(
            nodeNumber=n_slider, storeInternal=True, writeToFile=False,
            outputVariableType=exu.OutputVariableType.Position,
        )
    )  # fmt: skip
    mbs.Assemble()
    return mbs, sensor


def theirs(h: float, rho_inf: float, index2: bool, q0, v0) -> tuple[np.ndarray, float, dict]:
    """Slider x on the output grid and CPU seconds of Exudyn's generalized-α (index 3, or
    its index-2 variant), default Newton settings (modified Newton, rtol 1e-8)."""
    mbs, sensor = _exudyn_model(q0, v0)
    settings = exu.SimulationSettings()
    ti = settings.timeIntegration
    ti.endTime = T_END
    ti.numberOfSteps = round(T_END / h)
    ti.generalizedAlpha.spectralRadius = rho_inf
    # Exudyn's index-2 variant exists only with its Newmark (trapezoidal) form
    ti.generalizedAlpha.useIndex2Constraints = index2
    ti.generalizedAlpha.useNewmark = index2
    ti.verboseMode = 0
    settings.solutionSettings.writeSolutionToFile = False
    settings.solutionSettings.sensorsWritePeriod = GRID
    settings.linearSolverSettings.ignoreSingularJacobian = False
    settings.linearSolverType = exu.LinearSolverType.EigenSparse
    start = time.process_time()
    try:
        exu.SolveDynamic(mbs, settings)
    except exu.ExudynValueError:
        return np.full(round(T_END / GRID) + 1, np.nan), np.nan, dict(steps=-1)
    cpu = time.process_time() - start
    data = mbs.GetSensorStoredData(sensor)
    grid = np.arange(0.0, T_END + 0.5 * GRID, GRID)
    x = np.interp(grid, data[:, 0], data[:, 1])
    return x, cpu, dict(steps=ti.numberOfSteps)


def main(repeat: int, quick: bool, ref_step: float) -> list[dict]:
    model = assemble(mechanism.load_scene(SCENE))
    q0, v0 = initial_state(model)
    ours(1e-4, 0.8)  # warm-up (JIT)
    ref, _, _ = ours(ref_step, 1.0)
    print(f"reference x(0.1 s) = {ref[-1]:.10f} m (Simeon {S6_X}: {S6_X - ref[-1]:+.3e})")
    steps = STEPS[:4] if quick else STEPS
    cases = [("mechanism", 0.8, False), ("mechanism", 1.0, False), ("exudyn", 0.9, False),
             ("exudyn", 1.0, True), ("exudyn", 1.0, False)]  # fmt: skip
    rows = []
    for h in steps:
        for code, rho, index2 in cases:
            cpu = np.inf
            for _ in range(repeat):
                if code == "mechanism":
                    x, c, counts = ours(h, rho)
                else:
                    x, c, counts = theirs(h, rho, index2, q0, v0)
                cpu = min(cpu, c)
            row = dict(
                code=code, variant="index 2" if index2 else "", rho_inf=rho, step=h,
                cpu_s=round(cpu, 4), x_end=f"{x[-1]:.10f}",
                error_end_m=f"{x[-1] - ref[-1]:.3e}",
                error_max_m=f"{np.max(np.abs(x - ref)):.3e}",
                error_vs_simeon_m=f"{x[-1] - S6_X:.3e}", **counts,
            )  # fmt: skip
            rows.append(row)
            print(row, flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    with OUT.open("w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--ref-step", type=float, default=2.5e-7)
    args = parser.parse_args()
    main(args.repeat, args.quick, args.ref_step)
