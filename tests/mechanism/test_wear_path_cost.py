"""The prior CPU time of the paper study's wear paths against measured paths.

The prior (``wear_path_cost``) sets the study's time-left estimate and the cost the report
states for rigid and flexible paths. It is checked against two rigid paths profiled stage
by stage (docs/wear.md §7: the paper scene at 150 and 30 rpm, unworn and 5 000 cycles,
8 averaged revolutions: 66.9 and 98.1 CPU s, one process, kernels compiled).
"""

from __future__ import annotations

import dataclasses

import pytest

import mechanism
from mechanism.studies.paper._published import WEAR_PATHS
from mechanism.studies.paper._schedule import wear_path_cost

#: measured CPU seconds of the profiled paths, by crank speed (rpm)
MEASURED = {150.0: 66.9, 30.0: 98.1}


@pytest.mark.parametrize("rpm", sorted(MEASURED))
def test_prior_of_a_profiled_path_is_within_fifteen_percent_of_its_measured_cpu(rpm):
    """Before the calibration on the profiled stages the prior gave 108.7 s (1.62×) at
    150 rpm and 180.0 s (1.83×) at 30 rpm; now 63.8 s and 93.8 s."""
    settings = dataclasses.replace(
        mechanism.StudySettings.quick(),
        wear_path_cycles=5000.0,
        wear_path_checkpoints=(5000.0,),
        wear_path_averaged_revolutions=8,
    )
    ratio = wear_path_cost(rpm, settings) / MEASURED[rpm]
    assert ratio == pytest.approx(1.0, abs=0.15)


def test_quick_rigid_paths_cost_about_six_cpu_minutes():
    """The five quick paths: 9.9 CPU min by the prior before its calibration, 5.5 after
    (the measured paths scaled by their measured/prior ratios give about 6)."""
    settings = mechanism.StudySettings.quick()
    minutes = sum(wear_path_cost(rpm, settings) for rpm, _ in WEAR_PATHS) / 60.0
    assert 5.0 <= minutes <= 7.0
