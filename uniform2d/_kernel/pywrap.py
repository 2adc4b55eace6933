"""Python-callable wrappers only for the kernels Python calls.

numba gives every compiled function a wrapper that Python can call (it unboxes
the arguments, calls the function, boxes the result).  Most kernels are only
ever called by other kernels, yet each one's wrapper was generated, optimised
and turned into machine code with it, and again in every caller its module is
linked into: a fifth of the IR the first run optimised.  So a kernel that no
Python code of uniform2d names (:func:`uniform2d.compile_cache.entry_kernels`,
asked once, at the first compile) is compiled without one, and its cache entry
has none.

Python may call such a kernel all the same (a test, a script): the call then
compiles the kernel once more with its wrapper, for the call's argument types
(not cached), and calls that.  numba must never reach a missing wrapper, so an
overload without one is kept for the kernels that call it and is never entered
in the dispatcher's table of what Python calls.  The machine code of the
kernel itself is the same either way.
"""

from __future__ import annotations

import threading

from numba.core import event, sigutils
from numba.core.compiler_lock import global_compiler_lock
from numba.core.registry import CPUDispatcher

__all__ = ["KernelDispatcher"]

_finder: list = []  # the function listing the kernels Python calls (callers_from)
_entries: dict = {}  # "ids": the ids of the kernels Python calls, once asked
_python = threading.local()  # .target: the kernel a call from Python is compiling


def callers_from(find) -> None:
    """Drop the wrappers of kernels no Python code calls, ``find()`` listing the
    ones it calls (:func:`uniform2d.compile_cache.python_called`: the command
    line and its warmer give it); asked at the first compile after this.
    Without it every kernel keeps its wrapper, as numba's do."""
    _finder[:] = [find]
    _entries.clear()


def _called_from_python(disp) -> bool:
    if not _finder:
        return True
    if "ids" not in _entries:
        try:
            _entries["ids"] = {id(d) for d in _finder[0]()}
        except Exception:  # cannot tell (numba's internals moved): wrappers everywhere
            _entries["ids"] = None
    ids = _entries["ids"]
    return ids is None or id(disp) in ids


def _has_wrapper(cres) -> bool:
    return bool(cres.library.get_pointer_to_function(cres.fndesc.llvm_cpython_wrapper_name))


class KernelDispatcher(CPUDispatcher):
    """numba's CPU dispatcher, compiling a kernel no Python code calls without
    its Python-callable wrapper (see the module doc)."""

    def _compile_for_args(self, *args, **kws):  # numba's path for a call from Python
        outer = getattr(_python, "target", None)
        _python.target = self
        try:
            return super()._compile_for_args(*args, **kws)
        finally:
            _python.target = outer

    def compile(self, sig):
        if getattr(_python, "target", None) is self:
            return self._for_python(sig)
        if _called_from_python(self):
            return super().compile(sig)
        options = self.targetoptions
        with global_compiler_lock:  # (the options are the dispatcher's, read by its compile)
            before = options.get("no_cpython_wrapper")
            options["no_cpython_wrapper"] = True
            try:
                return super().compile(sig)
            finally:
                if before is None:
                    del options["no_cpython_wrapper"]
                else:
                    options["no_cpython_wrapper"] = before

    def add_overload(self, cres):
        if _has_wrapper(cres):
            super().add_overload(cres)
        else:  # for the kernels that call it; never entered for Python
            self.overloads[tuple(cres.signature.args)] = cres

    def _for_python(self, sig):
        """The entry point, for a call from Python, of an overload for ``sig``
        with a wrapper: the kernel's own (loaded, or compiled with its wrapper)
        if it has one, else the kernel compiled once more, with it."""
        args, return_type = sigutils.normalize_signature(sig)
        key = tuple(args)
        with global_compiler_lock:
            if key not in self.overloads:
                entry = super().compile(sig)
                if key not in self.overloads:  # (types folded otherwise: as numba)
                    return entry
            cres = self.overloads[key]
            if _has_wrapper(cres):
                return cres.entry_point
            with event.trigger_event("numba:compile", data=dict(
                    dispatcher=self, args=args, return_type=return_type)):
                cres = self._compiler.compile(args, return_type)
            self._insert([a._code for a in args], cres.entry_point, cres.objectmode)
            return cres.entry_point
