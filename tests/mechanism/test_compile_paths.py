"""A scene compiles only the kernels of the effects it has.

The compiled model carries one switch per optional effect (ANCF beams, force elements,
worn contact, oil film, the slider corners of a translational clearance joint), None when
the scene lacks the effect; numba removes a branch on a None argument before type
inference, so the kernels of that effect are never compiled.
What a run compiles is seen in a child process with an empty numba cache
(``NUMBA_CACHE_DIR`` a new folder): with a cache, a kernel loaded from it does not compile
the kernels it calls, and the check would pass whatever they are.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import mechanism
from mechanism.core.model import assemble
from tests.mechanism.scenes import rigid_paper

#: the kernels of the optional effects, by the module that defines them
EFFECT_KERNELS = {
    "beams": ("mechanism.core.bodies", ("beams_force_add", "beams_strain_energy")),
    "forces": ("mechanism.core.forces", ("force_elements_add", "force_elements_potential")),
    "worn": ("mechanism.core.model._kernels", ("worn_contact", "worn_clearance_rate")),
    "film": ("mechanism.core.model._kernels", ("film_force_add",)),
    "guide": (
        "mechanism.core.joints",
        ("guide_kinematics", "guide_force_add", "guide_acceleration"),
    ),
}

#: child process, with the JSON of ``EFFECT_KERNELS`` and a mode: ``light`` compiles the
#: clearance forces and the mechanical energy (a few kernels that reach every effect's
#: kernels) of the translational-clearance slider-crank, then of the rigid paper scene;
#: ``simulate`` runs the rigid paper scene, then evaluates the
#: right-hand side of a press scene with force elements and a lubricated joint; it prints
#: the signature count of each effect's kernels after each
CHILD = textwrap.dedent(
    """
    import importlib, json, sys
    import numpy as np
    import mechanism
    from mechanism.core.model import assemble, kernels
    from tests.mechanism.scenes import rigid_paper

    effect_kernels, mode = json.loads(sys.argv[1]), sys.argv[2]

    def counts():
        out = {}
        for effect, (module, names) in effect_kernels.items():
            mod = importlib.import_module(module)
            out[effect] = sum(len(getattr(mod, n).signatures) for n in names)
        return out

    def evaluate(scene, light):
        model = assemble(scene)
        km, ws = model.kernel, model.workspace()
        n = model.n_dof
        y = np.concatenate([model.q_guess, np.zeros(n)])
        vimp = np.zeros(km.cj_i.shape[0])
        counters = np.zeros(kernels.CNT_COLUMNS, dtype=np.int64)
        if light:
            kernels.clearance_forces(km, ws.pci, ws.pcf, vimp, ws.gen, ws.cj, counters)
        else:
            kernels.rhs(km, ws, 0.0, y, vimp, np.zeros(2 * n), counters)
        kernels.mechanical_energy(km, ws, y)

    if mode == "light":
        evaluate(mechanism.load_scene("slider-crank-translational-clearance"), light=True)
        corners = counts()
        evaluate(rigid_paper(), light=True)
        print(json.dumps({"corners": corners, "dry": counts()}))
        sys.exit()
    mechanism.simulate(rigid_paper(), revolutions=0.2, record="sections")
    dry = counts()
    # the run and its ideal companion share one specialisation
    dry["rhs"] = len(kernels.rhs.signatures)
    wet = mechanism.load_scene("slider-crank-spring-load").replace(
        {"joints.B.lubrication": {"viscosity": 0.04}}
    )
    evaluate(wet, light=False)
    print(json.dumps({"dry": dry, "wet": counts()}))
    """
)


def _compiled_in_child(tmp_path: Path, mode: str) -> dict[str, dict[str, int]]:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "NUMBA_NUM_THREADS": "1"}
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(EFFECT_KERNELS), mode],
        env=env, cwd=root, capture_output=True, text=True, timeout=1800, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def _worn(scene: mechanism.Scene) -> mechanism.Scene:
    joint = scene.joints["C"]
    depth = np.zeros(360)
    depth[100:140] = 5e-5
    worn = dataclasses.replace(
        joint, wear=dataclasses.replace(joint.wear, bearing_profile=tuple(depth))
    )
    return dataclasses.replace(scene, joints={**scene.joints, "C": worn})


def _switched_on(scene: mechanism.Scene) -> set[str]:
    km = assemble(scene).kernel
    switches = {
        "beams": km.beams_on,
        "forces": km.forces_on,
        "worn": km.worn_on,
        "film": km.film_on,
        "guide": km.guide_on,
    }
    return {name for name, on in switches.items() if on is not None}


@pytest.mark.parametrize(
    ("make", "expected"),
    [
        (rigid_paper, {"worn"}),
        (lambda: mechanism.load_scene("paper"), {"beams", "worn"}),
        (lambda: mechanism.load_scene("slider-crank-spring-load"), {"forces", "worn"}),
        (lambda: rigid_paper({"joints.C.lubrication": {"viscosity": 0.04}}), {"film", "worn"}),
        (lambda: _worn(rigid_paper()), {"worn"}),
        # no revolute clearance joint: nothing can be worn
        (lambda: mechanism.load_scene("slider-crank-translational-clearance"), {"guide"}),
        (lambda: mechanism.load_scene("slider-crank"), set()),
        (lambda: rigid_paper({"effects.clearance": False}), set()),
        (
            lambda: mechanism.load_scene("slider-crank-translational-clearance").replace(
                {"effects.clearance": False}
            ),
            set(),
        ),
    ],
    ids=[
        "rigid-paper", "flexible-paper", "force-elements", "lubricated", "worn",
        "translational-clearance", "ideal-joints", "clearance-off", "corners-off",
    ],
)  # fmt: skip
def test_each_effect_switch_is_on_exactly_when_the_scene_has_the_effect(make, expected) -> None:
    assert _switched_on(make()) == expected


@pytest.mark.parametrize(
    "make",
    [
        lambda: mechanism.load_scene("paper"),
        lambda: mechanism.load_scene("slider-crank-spring-load").replace(
            {"joints.B.lubrication": {"viscosity": 0.04}}
        ),
    ],
    ids=["flexible-paper", "lubricated-press"],
)
def test_the_ideal_companion_of_a_run_has_the_runs_switches(make) -> None:
    """The switches follow the scene, not the tables: the ideal companion of a run (its
    clearance joints made ideal, no clearance rows) compiles the run's specialisation."""
    scene = make()
    main = assemble(scene).kernel
    ideal = assemble(scene, ideal=True).kernel
    assert main.cj_i.shape[0] > 0
    assert ideal.cj_i.shape[0] == 0
    switches = ("beams_on", "forces_on", "worn_on", "film_on", "guide_on")
    assert [getattr(main, s) for s in switches] == [getattr(ideal, s) for s in switches]


@pytest.mark.slow
def test_the_contact_forces_and_energy_of_a_dry_rigid_scene_compile_no_absent_effect(
    tmp_path: Path,
) -> None:
    """The clearance forces and mechanical energy (which call the worn-contact, oil-film,
    ANCF, force-element and slider-corner kernels of the scenes that have them) of a dry
    rigid scene without a revolute clearance joint compile none of them but its corners';
    the rigid paper scene's revolute clearance joint (which a wear study wears) adds the
    worn-contact ones only (the counts add up over the two scenes)."""
    got = _compiled_in_child(tmp_path, "light")
    assert got["corners"] == {"beams": 0, "forces": 0, "worn": 0, "film": 0, "guide": 2}
    assert got["dry"] == {"beams": 0, "forces": 0, "worn": 2, "film": 0, "guide": 2}


@pytest.mark.slow
def test_a_fresh_rigid_simulate_compiles_no_kernel_of_an_absent_effect(tmp_path: Path) -> None:
    """A fresh ``simulate`` of the rigid paper scene compiles none of the ANCF,
    force-element, oil-film and slider-corner kernels; the press scene with a lubricated
    joint then compiles its force-element and film kernels, and still no ANCF one. Over
    20 s: it compiles a whole run from an empty cache."""
    got = _compiled_in_child(tmp_path, "simulate")
    assert got["dry"] == {"beams": 0, "forces": 0, "worn": 2, "film": 0, "guide": 0, "rhs": 1}
    assert got["wet"]["beams"] == 0
    assert got["wet"]["guide"] == 0
    assert got["wet"]["forces"] == 2  # one signature each of the force and the potential
    assert got["wet"]["film"] == 1
