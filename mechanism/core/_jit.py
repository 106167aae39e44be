"""Decorator of the simulator's compiled kernels that allocate nothing.

``njit_noalloc()`` is ``numba.njit(cache=True)`` without numba's reference counting. With
it, every call of a kernel increments and decrements the count of each array in the model
and workspace tuples it receives (about 45 atomic operations per right-hand side of the
rigid paper scene), which took half the time of an evaluation (3.6 µs against 1.8 µs
without; ``docs/simulator.md``, *Cost*). Such a kernel cannot allocate (``np.empty``,
array expressions, slice assignment from an array), and the kernels it calls are compiled
the same way, so they must not allocate either; numba refuses to compile one that does.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

from numba import njit

__all__ = ["njit_noalloc"]

F = TypeVar("F", bound=Callable[..., Any])


def njit_noalloc(**options: Any) -> Callable[[F], F]:
    """``numba.njit(cache=True, **options)`` compiled without reference counting."""
    # ``_nrt`` is numba's own option for this; its type stubs do not list it
    decorate: Callable[[F], F] = njit(  # type: ignore[call-overload]
        cache=True, _nrt=False, **options
    )
    return decorate
