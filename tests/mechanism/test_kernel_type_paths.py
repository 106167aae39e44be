"""numba's on-disk cache index pickles the types of compiled arguments by the module that
defined them, and is unpickled whole before numba checks whether it is fresh. The tables
the compiled loops take moved to modules of their own; an index written by an older source
(a process still running it) names them at their former place, which must still resolve to
the same classes, or every kernel call that reads such an index fails."""

from __future__ import annotations

import pickle

import pytest

from mechanism.core.integrate import Recording
from mechanism.core.model import KernelModel, Workspace


@pytest.mark.parametrize(
    ("module", "name", "cls"),
    [
        ("mechanism.core.model._assemble", "KernelModel", KernelModel),
        ("mechanism.core.model._assemble", "Workspace", Workspace),
        ("mechanism.core.integrate._methods", "Recording", Recording),
    ],
)
def test_a_cache_index_of_an_older_source_finds_the_kernel_types(module, name, cls) -> None:
    # protocol 0 global reference, as a pickle written while the class lived in ``module``
    reference = f"c{module}\n{name}\n.".encode()
    assert pickle.loads(reference) is cls
