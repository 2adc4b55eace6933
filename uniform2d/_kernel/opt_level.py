"""The LLVM optimisation level the kernels compile at: 1, where numba's default is 3.

numba optimises every function it compiles with LLVM's ``-O3`` pipeline (its
``NUMBA_OPT``, read from ``numba.config.OPT`` at each optimisation).  The
kernels run as fast at ``-O1`` (``benchmarks/bench_compile.py`` and
``bench_speed.py`` give the figures): their time goes to memory traffic,
branches and the exact predicates' filters, which ``-O1`` already optimises
(inlining, promotion of memory to registers, simplification, loop-invariant
code motion); what ``-O3`` adds (loop unrolling, vectorisation, more inlining)
finds little there and costs compile time on every kernel of the first run.
The level changes no result: without fast-math flags, which the kernels never
use, LLVM may not reassociate, contract or otherwise change floating-point
arithmetic at any level, so the same bits come out (pinned by a test, and by
``benchmarks/hash_meshes.py``).  The machine-code generator keeps numba's level.

The level is set only while a kernel compiles.  ``numba.config.OPT`` is
process-wide, so a listener of numba's compile events sets it when a kernel
made by the kernel's ``njit`` (:func:`register`) starts compiling and puts back
what it was when that compile ends, however it ends; a function that is not a
kernel, compiled on the way (one of numba's own implementations, or user code),
compiles at the level the user's configuration gives, and so does user code
around a kernel.  numba compiles under its global compiler lock, so no other
thread compiles meanwhile.  A user's ``NUMBA_OPT`` below :data:`KERNEL_OPT`
lowers the kernels' level too (``NUMBA_OPT=0`` to debug them); above it, it
does not raise it.
"""

from __future__ import annotations

import weakref
from contextlib import contextmanager

from numba.core import config, event
from numba.core.registry import cpu_target

__all__ = ["KERNEL_OPT", "HOT_OPT", "register", "kernel_level"]

#: LLVM optimisation level of the kernels' compile (0-3).
KERNEL_OPT = 1

#: LLVM optimisation level of the kernels a mesh spends its time in (``njit(hot=True)``).
HOT_OPT = 3

_kernels: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # dispatcher -> hot
_saved: list = []  # config.OPT as it was when each compile under way started


def register(dispatcher, hot: bool = False) -> None:
    """Compile ``dispatcher`` (a kernel's numba dispatcher) at :data:`KERNEL_OPT`,
    or at :data:`HOT_OPT` if ``hot``."""
    _kernels[dispatcher] = hot


def _user_level():
    """The level the user's configuration gives (the one before any kernel's)."""
    return _saved[0] if _saved else config.OPT


def _kernel_level(hot: bool = False):
    user = _user_level()
    return type(user)(min(int(user), HOT_OPT if hot else KERNEL_OPT))


@contextmanager
def kernel_level():
    """Within: ``numba.config.OPT`` at the kernels' level (for a kernel that numba
    compiles without a dispatcher, as a ``cfunc``); restored on the way out."""
    _enter(True)
    try:
        yield
    finally:
        _leave()


def _enter(kernel: bool, hot: bool = False) -> None:
    if not _saved:
        config.reload_config()  # a changed NUMBA_ variable applies before it is saved
        # numba's code generator reads the level once, when it is made: made
        # here if not yet, it takes the user's
        cpu_target.target_context.codegen()
    level = _kernel_level(hot) if kernel else _user_level()
    _saved.append(config.OPT)
    config.OPT = level


def _leave() -> None:
    config.OPT = _saved.pop()


class _Scope(event.Listener):
    """Sets the level for each compile numba starts, puts it back at its end."""

    def on_start(self, ev):
        dispatcher = ev.data.get("dispatcher")
        hot = _kernels.get(dispatcher) if dispatcher is not None else None
        _enter(hot is not None, bool(hot))

    def on_end(self, ev):
        _leave()


event.register("numba:compile", _Scope())
