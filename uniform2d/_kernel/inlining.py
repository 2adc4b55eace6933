"""numba's inlining (``inline="always"``), copying a callee's IR as a whole.

numba inlines a function by running its front end at the call site and copying
the IR it gets twice (one copy to splice into the caller, one kept as it was),
block by block, each block with a deepcopy memo of its own.  Every variable of
a block refers to the function's scope, and the scope holds every variable of
the function: so each block's copy copied the whole scope again, blocks times
variables, most of the inlining's time (INSERT's compile inlines 37 calls).

While one of uniform2d's functions is inlined, the blocks of one IR share one
memo (as a deepcopy of all the blocks at once would): the statements are copied
as before, the scope once.  The spliced IR is the same, the scope aside, which
inlining replaces with the caller's (every callee variable is renamed into it);
``tests/test_inlining.py`` compiles a caller both ways and compares the LLVM IR.
"""

from __future__ import annotations

import copy
import threading

from numba.core import inline_closurecall, ir

__all__ = ["PACKAGES", "install", "sharing"]

#: The packages whose ``inline="always"`` functions are copied this way
#: (numba's own inlining of every other function is left as it is).
PACKAGES = ("uniform2d",)

_state = threading.local()  # .memos: {id(scope): memo} during one inlining, else None


class _Copier:
    """Stands for the ``copy`` module in numba's inliner: a block's deepcopy
    shares the memo of the blocks of the same scope during one inlining."""

    def __getattr__(self, name):
        return getattr(copy, name)

    @staticmethod
    def deepcopy(x, memo=None):
        memos = getattr(_state, "memos", None)
        if memo is None and memos is not None and isinstance(x, ir.Block):
            memo = memos.setdefault(id(x.scope), {})  # (the memo keeps the scope alive)
        return copy.deepcopy(x, memo)


def _ours(callee_ir) -> bool:
    module = getattr(callee_ir.func_id, "modname", None) or ""
    return module.split(".")[0] in PACKAGES


def install() -> None:
    """Copy the IR of uniform2d's inlined functions as a whole (see the module
    doc); once per process, the kernel's ``njit`` calls it.  Where numba's
    inliner is not as this module expects, nothing is changed."""
    worker = getattr(inline_closurecall, "InlineWorker", None)
    original = getattr(worker, "inline_ir", None)
    if original is None or getattr(original, "_whole_copy", False) \
            or getattr(inline_closurecall, "copy", None) is not copy:
        return

    def inline_ir(self, caller_ir, block, i, callee_ir, *args, **kwargs):
        outer = getattr(_state, "memos", None)
        _state.memos = {} if getattr(_state, "on", True) and _ours(callee_ir) else None
        try:
            return original(self, caller_ir, block, i, callee_ir, *args, **kwargs)
        finally:
            _state.memos = outer

    inline_ir._whole_copy = True
    inline_closurecall.copy = _Copier()
    worker.inline_ir = inline_ir


class sharing:  # noqa: N801  (used as a context manager, like numba's own switches)
    """``with sharing(False):`` compiles in this thread with numba's block by
    block copies (for comparisons); ``sharing(True)`` is the default."""

    def __init__(self, on: bool):
        self.on = on

    def __enter__(self):
        self.outer = getattr(_state, "on", True)
        _state.on = self.on
        return self

    def __exit__(self, *exc):
        _state.on = self.outer
        return False
