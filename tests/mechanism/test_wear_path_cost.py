"""The prior CPU time of the paper study's wear paths against measured paths.

The prior (``wear_path_cost``) sets the study's time-left estimate and the cost the report
states for rigid and flexible paths. It is checked against the wear-life benchmark's five
paths (``benchmarks/wear_life.py``, docs/wear.md §7: the rigid paper scene, default
``WearLifeSettings``, each ended early by the model's limit; CPU s of the path with its
analyses, of it in the simulations and averaging the wear / the exponent / the verdict,
two idle cores): 30 rpm after 35 000 cycles, 566.4 (430.3 / 107.9 / 27.4); 60 rpm after
20 000, 199.9 (133.9 / 49.3 / 16.2); 90 rpm after 25 000, 148.7 (84.4 / 30.4 / 33.4);
120 rpm after 20 000, 113.7 (76.6 / 20.5 / 16.3); 150 rpm after 15 000, 115.3 (74.3 /
23.8 / 17.0).
"""

from __future__ import annotations

import dataclasses

import pytest

import mechanism
from mechanism.studies.paper._published import WEAR_PATHS
from mechanism.studies.paper._schedule import wear_path_cost

#: the benchmark's measured paths as they ran: crank speed (rpm) -> (checkpoints reached,
#: CPU s of the path's task)
MEASURED = {
    30.0: (35000.0, 566.4),
    60.0: (20000.0, 199.9),
    90.0: (25000.0, 148.7),
    120.0: (20000.0, 113.7),
    150.0: (15000.0, 115.3),
}


@pytest.mark.parametrize("rpm", sorted(MEASURED))
def test_prior_of_a_benchmark_path_is_within_thirty_five_percent_of_its_measured_cpu(rpm):
    """0.91×, 0.98×, 1.24×, 1.12× and 0.76× the measured CPU of the 30 … 150 rpm paths
    (one fit to the five, by phase)."""
    reached, cpu = MEASURED[rpm]
    checkpoints = tuple(5000.0 * k for k in range(1, round(reached / 5000.0) + 1))
    settings = dataclasses.replace(
        mechanism.StudySettings.quick(),
        wear_path_cycles=reached,
        wear_path_checkpoints=checkpoints,
        wear_path_averaged_revolutions=8,
    )
    assert wear_path_cost(rpm, settings) / cpu == pytest.approx(1.0, abs=0.35)


def test_quick_rigid_paths_cost_about_four_and_a_half_cpu_minutes():
    """The five quick paths: 7.5 CPU min by the prior fitted to the benchmark's paths
    before the exponent's early end inside one run, the cheaper verdict and the approach
    bound on worn profiles; 4.5 after."""
    settings = mechanism.StudySettings.quick()
    minutes = sum(wear_path_cost(rpm, settings) for rpm, _ in WEAR_PATHS) / 60.0
    assert minutes == pytest.approx(4.5, abs=0.4)
