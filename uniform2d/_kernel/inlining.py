"""numba's inlining (``inline="always"``): a callee's IR copied as a whole, its front end run once.

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

numba also runs the callee's whole front end (bytecode to IR, its own inlining
of its callees, rewrites) again at every call site, for an IR that is copied
before it is changed: the same IR each time but for the numbers numba draws
from process-wide counters (block labels, the function's unique name, which
prefixes its variables once inlined).  So the IR of one of uniform2d's
functions is kept, per function and compile options, from its first front end,
and every later call site gets it under a unique name of its own
(``FunctionIdentity.derive``, as a new front end would give): the variables
spliced into the caller are as before, but for those numbers.  The front end
reads the globals a function names (and its inlined callees theirs): the IR is
kept only while each is still bound to the object it read.
"""

from __future__ import annotations

import copy
import threading
from types import ModuleType

from numba.core import inline_closurecall, ir

__all__ = ["PACKAGES", "install", "sharing", "front_ends"]

#: The packages whose ``inline="always"`` functions are copied this way
#: (numba's own inlining of every other function is left as it is).
PACKAGES = ("uniform2d",)

_state = threading.local()  # .memos: {id(scope): memo} during one inlining, else None
_front_ends: dict = {}  # (function, options) -> the IR of its first front end (under numba's lock)


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


def _front_end_key(worker, func, enable_ssa):
    """What a front end's IR depends on besides ``func``: the compile options the
    worker passes it (its flags, locals, contexts), or None where they cannot
    be hashed (then the front end runs).  numba makes a target context per
    compile from the flags (``_make_subtarget``): its class and the flags
    stand for it."""
    if (getattr(func, "__module__", None) or "").split(".")[0] not in PACKAGES \
            or not getattr(_state, "on", True) or worker.flags is None:
        return None
    flags = worker.flags.copy()
    flags.enable_ssa = enable_ssa
    try:
        key = (func, flags, tuple(sorted((worker.locals or {}).items())),
               id(worker.typingctx), type(worker.targetctx), type(worker.pipeline))
        hash(key)
    except TypeError:
        return None
    return key


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
    _install_front_ends(worker)


def _bound(func) -> tuple:
    """What ``func``'s front end read of the world: the values of the globals its
    code names (and, of a module among them, its attributes of those names:
    ``cdt.flip``), and of its closure's cells."""
    names, space = func.__code__.co_names, func.__globals__
    values = []
    for name in names:
        value = space.get(name, _bound)
        values.append(value)
        if isinstance(value, ModuleType):
            values.extend(getattr(value, n, _bound) for n in names)
    for cell in func.__closure__ or ():
        try:
            values.append(cell.cell_contents)
        except ValueError:  # (an empty cell)
            values.append(_bound)
    return tuple(values)


def _still(reads) -> bool:
    return all(all(a is b for a, b in zip(_bound(f), seen)) for f, seen in reads)


def _install_front_ends(worker) -> None:
    """The callee's front end once per function and options (see the module doc),
    kept while the globals it read (its own, its inlined callees') are bound to
    the same objects: numba's front end reads them again at every call site."""
    original = getattr(worker, "run_untyped_passes", None)
    if original is None:
        return

    def run_untyped_passes(self, func, enable_ssa=False):
        key = _front_end_key(self, func, enable_ssa)
        kept = _front_ends.get(key) if key is not None else None
        outer = getattr(_state, "reads", None)
        if kept is not None and _still(kept[1]):
            self.flags.enable_ssa = enable_ssa  # (as numba's front end leaves them)
            func_ir = kept[0].copy()  # new blocks (sharing the statements inline_ir copies)
            func_ir.func_id = kept[0].func_id.derive()
            reads = kept[1]
        elif key is None and outer is None:
            return original(self, func, enable_ssa)
        else:
            _state.reads = reads = [(func, _bound(func))]
            try:
                func_ir = original(self, func, enable_ssa)
            finally:
                _state.reads = outer
            reads = tuple(reads)
            if key is not None:  # (numba copies it before changing it: inline_ir)
                _front_ends[key] = (func_ir, reads)
        if outer is not None:  # (a callee's front end: what it read, its caller read)
            outer.extend(reads)
        return func_ir

    worker.run_untyped_passes = run_untyped_passes


def front_ends() -> int:
    """How many functions' front ends are kept (for tests)."""
    return len(_front_ends)


class sharing:  # noqa: N801  (used as a context manager, like numba's own switches)
    """``with sharing(False):`` compiles in this thread with numba's block by
    block copies and a front end at every call site (for comparisons);
    ``sharing(True)`` is the default."""

    def __init__(self, on: bool):
        self.on = on

    def __enter__(self):
        self.outer = getattr(_state, "on", True)
        _state.on = self.on
        return self

    def __exit__(self, *exc):
        _state.on = self.outer
        return False
