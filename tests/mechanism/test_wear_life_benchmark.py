"""The wear-life benchmark's load sampler (``benchmarks/wear_life.py``) starts and stops.

The benchmark samples the load average in a thread while the paths run; stopping it used
to raise ``TypeError: 'Event' object is not callable`` after every path had finished (the
thread's stop event shadowed a method of ``threading.Thread``), so the run wrote no map,
table, figures or report.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "wear_life.py"
_spec = importlib.util.spec_from_file_location("wear_life_benchmark", SCRIPT)
benchmark = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(benchmark)


def test_the_load_sampler_stops_and_keeps_its_samples():
    sampler = benchmark.LoadSampler(every=0.01)
    sampler.start()
    sampler.stop()
    assert not sampler.is_alive()
    assert len(sampler.samples) >= 1
    assert all(load >= 0.0 for load in sampler.samples)
