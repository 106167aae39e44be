"""Force elements against Exudyn 1.13.6 (skipped when it is not installed): a pendulum
with a translational spring–damper, a torsional spring–damper and a periodic load
(``benchmarks/force_elements_vs_exudyn.py`` builds both models)."""

from __future__ import annotations

import pytest

pytest.importorskip("exudyn")

from benchmarks.force_elements_vs_exudyn import compare


def test_spring_pendulum_trajectory_agrees_with_exudyn() -> None:
    """1 s of the damped, forced pendulum: angle within 2e-5 rad and tip within 1e-5 m of
    Exudyn's trapezoidal rule at a 1e-4 s step (measured 4e-6 rad and 1.3e-6 m over 2 s;
    the difference shrinks with Exudyn's step as h², so it is Exudyn's discretisation
    error). The motion is damped and driven, not chaotic."""
    diff = compare(1.0, 1e-4, 1e-3)
    assert diff["angle_range"] > 1.0  # the elements move the pendulum over a wide swing
    assert diff["angle"] < 2e-5
    assert diff["tip"] < 1e-5
