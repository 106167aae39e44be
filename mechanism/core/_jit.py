"""Decorators of the simulator's compiled kernels that allocate nothing.

``njit_noalloc()`` is ``numba.njit(cache=True)`` without numba's reference counting. With
it, every call of a kernel increments and decrements the count of each array in the model
and workspace tuples it receives (about 45 atomic operations per right-hand side of the
rigid paper scene), which took half the time of an evaluation (3.6 µs against 1.8 µs
without; ``docs/simulator.md``, *Cost*). Such a kernel cannot allocate (``np.empty``,
array expressions, slice assignment from an array), and the kernels it calls are compiled
the same way, so they must not allocate either; numba refuses to compile one that does.

``njit_inner()`` is ``njit_noalloc()`` for a kernel that the compiled loops call and a run
does not call from Python: it is compiled without the two wrappers numba builds for calls
from outside compiled code (the CPython wrapper that unboxes every argument, and the C
wrapper). For a kernel taking the model and workspace tuples those wrappers are a fifth to
a third of the code numba lowers and LLVM optimises (``docs/performance.md``,
*Compiling*). numba's own kernel without a CPython wrapper crashes the interpreter when
Python calls it; a kernel from ``njit_inner`` instead hands such a call to a twin compiled
with the wrappers (the same function under the name ``<name>_py``, compiled and cached on
its first call from Python), so tests and tools call it as before.
"""

from __future__ import annotations

import types
from collections.abc import Callable
from typing import Any, TypeVar

from numba import njit
from numba.core.registry import CPUDispatcher

__all__ = ["njit_inner", "njit_noalloc"]

F = TypeVar("F", bound=Callable[..., Any])


def njit_noalloc(**options: Any) -> Callable[[F], F]:
    """``numba.njit(cache=True, **options)`` compiled without reference counting."""
    # ``_nrt`` is numba's own option for this; its type stubs do not list it
    decorate: Callable[[F], F] = njit(  # type: ignore[call-overload]
        cache=True, _nrt=False, **options
    )
    return decorate


class InnerKernel(CPUDispatcher):  # type: ignore[misc]
    """A kernel compiled without wrappers for calls from Python (see :func:`njit_inner`);
    a call from Python runs its twin compiled with them."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        twin = self.__dict__.get("_python_twin")
        if twin is None:
            func = self.py_func
            copy = types.FunctionType(
                func.__code__, func.__globals__, func.__name__, func.__defaults__,
                func.__closure__,
            )  # fmt: skip
            # its own name, so its cache entries (which have the wrappers) are its own
            copy.__qualname__ = f"{func.__qualname__}_py"
            copy.__module__ = func.__module__
            copy.__doc__ = func.__doc__
            # (a kernel rebuilt by unpickling has no options of its own: the defaults)
            twin = njit_noalloc(**self.__dict__.get("_twin_options", {}))(copy)
            self.__dict__["_python_twin"] = twin
        return twin(*args, **kwargs)


def njit_inner(**options: Any) -> Callable[[F], F]:
    """:func:`njit_noalloc` without the wrappers for calls from Python (for a kernel the
    compiled loops call); a call from Python compiles and runs a twin that has them."""

    def decorate(func: F) -> F:
        kernel = njit_noalloc(no_cpython_wrapper=True, no_cfunc_wrapper=True, **options)(func)
        kernel.__class__ = InnerKernel
        kernel.__dict__["_twin_options"] = options
        return kernel

    return decorate
