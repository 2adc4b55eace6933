"""numba's overloads compiled once for callers differing only in options they
do not inherit (uniform2d._kernel.overloads).

A kernel (uniform2d's njit: nogil, no C wrapper) and a plain numba function
(neither) both call ``np.empty(n, dtype)``: numba compiled the overload behind
it once for each; now once for both, giving the same arrays.  A dtype of its
own per case, so that no other test compiled that overload first.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest
from numba.core import event

from uniform2d._kernel import overloads
from uniform2d._kernel._jit import njit


class _Compiles(event.Listener):
    def __init__(self):
        self.names = []

    def on_start(self, e):
        pass

    def on_end(self, e):
        self.names.append(e.data["dispatcher"].py_func.__qualname__)


def _empty_compiles(dtype) -> int:
    """Compiles of numba's ``np.empty`` overload while a kernel and a plain numba
    function, each calling ``np.empty(n, dtype)``, compile."""

    def make(n):
        a = np.empty(n, dtype)
        a[:] = 3
        return a

    listener = _Compiles()
    event.register("numba:compile", listener)
    try:
        for jit in (njit, numba.njit):
            got = jit(make)(4)
            assert got.dtype == dtype and got.tolist() == [3, 3, 3, 3]
    finally:
        event.unregister("numba:compile", listener)
    return sum(name == "ol_np_empty.<locals>.impl" for name in listener.names)


def test_installed_by_the_kernels_njit():
    from numba.core.typing import templates

    assert getattr(templates._OverloadFunctionTemplate._get_impl, "_shared", False)


def test_numbas_empty_compiled_once_for_a_kernel_and_a_plain_function():
    assert _empty_compiles(np.uint16) == 1


def test_compiled_once_per_setting_without_it(monkeypatch):
    """The case above, the options left as they are: numba compiles it twice."""
    monkeypatch.setattr(overloads, "NOT_INHERITED", ())
    assert _empty_compiles(np.int16) == 2


@pytest.mark.parametrize("name", overloads.NOT_INHERITED)
def test_numba_does_not_pass_these_options_on(name):
    """What the lookup leaves out must be what numba's CPU target does not
    inherit (``CPUTargetOptions.finalize``): were numba to start inheriting
    one, the overload would compile differently per setting again."""
    from numba.core import cpu, targetconfig
    from numba.core.compiler import Flags

    top = Flags()
    setattr(top, name, not getattr(top, name))
    with targetconfig.ConfigStack().enter(top):
        flags = Flags()
        cpu.CPUTargetOptions().finalize(flags, {})
    assert getattr(flags, name) == getattr(Flags(), name)
