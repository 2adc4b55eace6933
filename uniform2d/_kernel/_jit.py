"""The kernel's ``njit``: numba's, without the C-callable (cfunc) wrapper.

numba gives every compiled function a wrapper callable from C (``.cfunc``,
``.ctypes``) besides the one Python calls.  The kernel never hands its
functions to C, but each wrapper would be compiled, optimised and linked into
every caller's machine code all the same, which lengthens the first run's
compile.  The Python-callable wrapper stays: any kernel function may be called
from Python.

The same cost decides which functions are ``inline="always"``: numba turns
every compiled function into machine code together with a copy of all its
callees, so a function called from one place only, above a large call tree
(INSERT's steps, the cavity's split and flip, the relaxation sweeps), would
have that tree optimised and generated once more for itself.  Inlined into
its caller, its body is typed there instead and the copy is not made.  Small
functions with many callers, or whose callee trees would be copied into
several callers, stay separate.  So do the one-line helpers called from many
places (the half-edge steps, the tie threshold, a heap's order): numba
inlines a function by running its front end again at every call site, while
LLVM inlines a small separate function into its callers' machine code all
the same.

numba counts references to arrays (and structrefs): a function increfs
each array argument on entry and decrefs it on every way out, and an array
read from a structref, or an array variable reassigned in a loop, is counted
at every use.  These are atomic operations, and numba's pruning pass leaves
most of them in place where a function's exits branch: in the relaxation's
per-vertex loops they took a third of the time.  So the small helpers called
in the innermost loops, which allocate nothing and keep none of their
arguments, are compiled without counting (``borrowed=True``: numba's
``_nrt=False``; a function without it cannot read a structref's fields, so
the loops pass them the structref's arrays), and the loops hoist arrays out of
structrefs and keep array variables out of their reassignments.  ``_nrt`` is
given explicitly to every kernel: numba compiles a callee with the options it
was not given inherited from the kernel being compiled, and a kernel that
allocates must not inherit a borrowed helper's.

The disk cache is numba's, with one addition for the first run, where two
processes compile into it at once: a kernel one of them compiles is claimed
until it is cached, so the other waits for it rather than compiling it too
(:mod:`uniform2d.compile_claims`).

Every kernel releases the GIL (``nogil``): the kernel keeps no state between
calls but its arguments, so independent calls (the optimiser's starts, each
on its own arrays) run at once on a pool of threads (:mod:`uniform2d.threads`).
"""

from __future__ import annotations

from numba import njit as _njit

from ..compile_claims import enable_caching
from .inlining import install as _copy_inlined_whole
from .pywrap import KernelDispatcher

__all__ = ["njit"]

_copy_inlined_whole()  # numba's inlining, the callee's IR copied as a whole


def njit(*args, **options):
    """``numba.njit`` with ``no_cfunc_wrapper=True`` and ``nogil=True`` (as a bare
    decorator or with options); ``cache=True`` gives the kernel numba's disk
    cache through :func:`uniform2d.compile_claims.enable_caching` (the same
    cache, the kernel claimed while another process fills it too);
    ``borrowed=True`` compiles it without reference counting (see the module
    docstring: for helpers that allocate no array and keep none)."""
    options.setdefault("no_cfunc_wrapper", True)
    options.setdefault("nogil", True)
    # explicit either way: numba compiles a kernel's callees with the options
    # it was not given inherited from the kernel being compiled, and a callee
    # that allocates must not inherit a borrowed caller's
    options["_nrt"] = not options.pop("borrowed", False)
    cache = options.pop("cache", False)

    def cached(dispatcher):
        dispatcher.__class__ = KernelDispatcher  # a wrapper for Python only where it calls
        if cache:
            enable_caching(dispatcher)
        return dispatcher

    if args and callable(args[0]):  # a bare decorator
        return cached(_njit(*args, **options))
    decorate = _njit(*args, **options)
    return lambda func: cached(decorate(func))
