"""Force elements against Exudyn 1.13.6: a pendulum with a spring–damper, a torsional
spring–damper and a periodic load, simulated by ``mechanism.simulate`` and by Exudyn.

The pendulum: a bar (0.8 kg, J = 0.012 kg m² about its centre of mass) pinned to the
ground 0.15 m from its centre of mass, under gravity, with

* a translational spring–damper (k = 300 N/m, c = 0.8 N s/m, L₀ = 0.2 m) from the ground
  point (0.25, 0.1) to the bar's tip (Exudyn ``ObjectConnectorSpringDamper``);
* a torsional spring–damper in the pin (k = 1.5 N m/rad, c = 0.01 N m s/rad,
  reference 0) — Exudyn's planar form, ``ObjectConnectorCoordinateSpringDamper`` on the
  bar's angle coordinate (its 3-D ``TorsionalSpringDamper`` needs 3-D rigid nodes);
* a horizontal load 4 sin(2πt/0.4) N at the tip (Exudyn ``LoadForceVector`` with a
  user function; in the scene a ``load`` with a Fourier ``time_profile``).

Exudyn integrates with its implicit trapezoidal rule (generalized-α, ρ∞ = 1) at a fixed
step; ``mechanism`` with Dormand–Prince at rtol 1e-10. The script prints the largest
difference of the bar angle and of the tip position over the run, and the wall time of
each code (median of ``--repeat`` runs, taken alternately, after one warm-up run each so
numba's compilation is not counted)::

    python benchmarks/force_elements_vs_exudyn.py [--t-end 2] [--step 1e-4] [--repeat 3]
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import exudyn as exu
import numpy as np
from exudyn.itemInterface import (
    LoadForceVector,
    MarkerBodyPosition,
    MarkerNodeCoordinate,
    NodePointGround,
    NodeRigidBody2D,
    ObjectConnectorCoordinateSpringDamper,
    ObjectConnectorSpringDamper,
    ObjectGround,
    ObjectJointRevolute2D,
    ObjectRigidBody2D,
    SensorBody,
    SensorNode,
)

import mechanism
from mechanism.core.scene import (
    FourierProfile,
    Load,
    Outputs,
    RevoluteJoint,
    RigidBody,
    RotationalSpringDamper,
    Scene,
    SolverSettings,
    SpringDamper,
    validate_scene,
)

MASS = 0.8  # kg
INERTIA = 0.012  # kg m², about the centre of mass
PIN = (-0.15, 0.0)  # pin point in the bar frame, m
TIP = (0.15, 0.0)  # tip point in the bar frame, m
ANCHOR = (0.25, 0.1)  # ground end of the spring, m
ANGLE0 = -1.2  # initial bar angle, rad (the pin at the origin)
SPRING = {"stiffness": 300.0, "damping": 0.8, "free_length": 0.2}
TORSION = {"stiffness": 1.5, "damping": 0.01}
LOAD_AMPLITUDE = 4.0  # N
LOAD_PERIOD = 0.4  # s
GRAVITY = 9.81


def _centre0() -> tuple[float, float]:
    """Initial centre of mass: the pin point at the origin."""
    c, s = math.cos(ANGLE0), math.sin(ANGLE0)
    return (-(c * PIN[0] - s * PIN[1]), -(s * PIN[0] + c * PIN[1]))


def pendulum_scene(output_step: float, rtol: float = 1e-10) -> Scene:
    """The pendulum with its three force elements as a ``mechanism`` scene."""
    return validate_scene(
        Scene(
            name="spring-pendulum",
            gravity=(0.0, -GRAVITY),
            ground_points={"O": (0.0, 0.0), "G": ANCHOR},
            bodies={
                "bar": RigidBody(
                    mass=MASS,
                    inertia=INERTIA,
                    position=_centre0(),
                    angle=ANGLE0,
                    points={"O": PIN, "E": TIP},
                )
            },
            joints={"O": RevoluteJoint(bodies=("ground", "bar"), points=("O", "O"))},
            forces={
                "spring": SpringDamper(bodies=("ground", "bar"), points=("G", "E"), **SPRING),
                "coil": RotationalSpringDamper(joint="O", **TORSION),
                "push": Load(
                    body="bar",
                    point="E",
                    force=(LOAD_AMPLITUDE, 0.0),
                    time_profile=FourierProfile(period=LOAD_PERIOD, sine=(1.0,)),
                ),
            },
            outputs=Outputs(crank_joint="O"),
            solver=SolverSettings(rtol=rtol, atol=rtol * 1e-2, output_step=output_step),
        )
    )


def run_mechanism(t_end: float, output_step: float) -> tuple[np.ndarray, np.ndarray]:
    """(time, [angle, tip x, tip y]) of ``mechanism.simulate``."""
    ds = mechanism.simulate(pendulum_scene(output_step), t_end=t_end, record="full")
    pose = ds.position.sel(body="bar").values
    c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    tip = np.stack([pose[:, 0] + c * TIP[0], pose[:, 1] + s * TIP[0]], axis=1)
    return ds.time.values, np.column_stack([pose[:, 2], tip])


def run_exudyn(t_end: float, step: float, output_step: float) -> tuple[np.ndarray, np.ndarray]:
    """(time, [angle, tip x, tip y]) of the same pendulum in Exudyn."""
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    x0, y0 = _centre0()
    node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[x0, y0, ANGLE0]))
    body = mbs.AddObject(ObjectRigidBody2D(mass=MASS, inertia=INERTIA, nodeNumber=node))
    m_pin_ground = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[0, 0, 0]))
    m_pin_bar = mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[*PIN, 0]))
    mbs.AddObject(ObjectJointRevolute2D(markerNumbers=[m_pin_ground, m_pin_bar]))
    m_anchor = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[*ANCHOR, 0]))
    m_tip = mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[*TIP, 0]))
    mbs.AddObject(
        ObjectConnectorSpringDamper(
            markerNumbers=[m_anchor, m_tip],
            referenceLength=SPRING["free_length"],
            stiffness=SPRING["stiffness"],
            damping=SPRING["damping"],
        )
    )
    ground_node = mbs.AddNode(NodePointGround(referenceCoordinates=[0, 0, 0]))
    m_ground_angle = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0))
    m_angle = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=node, coordinate=2))
    mbs.AddObject(
        ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[m_ground_angle, m_angle],
            stiffness=TORSION["stiffness"],
            damping=TORSION["damping"],
            # node coordinates are displacements from the reference pose: the spring's
            # reference angle 0 is the displacement −ANGLE0
            offset=-ANGLE0,
        )
    )
    m_centre = mbs.AddMarker(MarkerBodyPosition(bodyNumber=body, localPosition=[0, 0, 0]))
    mbs.AddLoad(LoadForceVector(markerNumber=m_centre, loadVector=[0, -MASS * GRAVITY, 0]))

    def push(mbs: object, t: float, load: object) -> list[float]:
        return [LOAD_AMPLITUDE * math.sin(2.0 * math.pi * t / LOAD_PERIOD), 0.0, 0.0]

    mbs.AddLoad(LoadForceVector(markerNumber=m_tip, loadVectorUserFunction=push))
    angle = mbs.AddSensor(
        SensorNode(
            nodeNumber=node,
            storeInternal=True,
            writeToFile=False,
            outputVariableType=exu.OutputVariableType.Coordinates,
        )
    )
    tip = mbs.AddSensor(
        SensorBody(
            bodyNumber=body,
            localPosition=[*TIP, 0],
            storeInternal=True,
            writeToFile=False,
            outputVariableType=exu.OutputVariableType.Position,
        )
    )
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.timeIntegration.endTime = t_end
    settings.timeIntegration.numberOfSteps = round(t_end / step)
    settings.timeIntegration.generalizedAlpha.spectralRadius = 1.0
    settings.timeIntegration.newton.relativeTolerance = 1e-12
    settings.timeIntegration.newton.absoluteTolerance = 1e-12
    settings.solution.sensors.writePeriod = output_step
    settings.solution.file.write = False
    settings.timeIntegration.verboseMode = 0
    mbs.SolveDynamic(settings)
    coords = mbs.GetSensorStoredData(angle)
    pos = mbs.GetSensorStoredData(tip)
    # the node's coordinates are displacements from its reference coordinates
    return coords[:, 0], np.column_stack([coords[:, 3] + ANGLE0, pos[:, 1], pos[:, 2]])


def compare(t_end: float, step: float, output_step: float) -> dict[str, float]:
    """Largest differences of angle (rad) and tip position (m) on the common samples."""
    t_m, y_m = run_mechanism(t_end, output_step)
    t_e, y_e = run_exudyn(t_end, step, output_step)
    y_e_on_m = np.column_stack([np.interp(t_m, t_e, y_e[:, i]) for i in range(3)])
    return {
        "angle": float(np.max(np.abs(y_m[:, 0] - y_e_on_m[:, 0]))),
        "tip": float(np.max(np.hypot(*(y_m[:, 1:] - y_e_on_m[:, 1:]).T))),
        "angle_range": float(np.ptp(y_m[:, 0])),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=2.0, help="simulated time, s")
    parser.add_argument("--step", type=float, default=1e-4, help="Exudyn's fixed step, s")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs of each code")
    args = parser.parse_args()
    output_step = 1e-3
    diff = compare(args.t_end, args.step, output_step)  # also the warm-up of both codes
    print(
        f"max |Δθ| = {diff['angle']:.3e} rad (θ swings over {diff['angle_range']:.3f} rad), "
        f"max |Δr_tip| = {diff['tip']:.3e} m"
    )
    times: dict[str, list[float]] = {"mechanism": [], "exudyn": []}
    for _ in range(args.repeat):
        start = time.perf_counter()
        run_mechanism(args.t_end, output_step)
        times["mechanism"].append(time.perf_counter() - start)
        start = time.perf_counter()
        run_exudyn(args.t_end, args.step, output_step)
        times["exudyn"].append(time.perf_counter() - start)
    for name, values in times.items():
        print(f"{name:>10}: median wall time {statistics.median(values):.3f} s of {values}")


if __name__ == "__main__":
    main()
