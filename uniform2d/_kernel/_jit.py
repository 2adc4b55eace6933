"""The kernel's ``njit``: numba's, without the C-callable (cfunc) wrapper.

numba gives every compiled function a wrapper callable from C (``.cfunc``,
``.ctypes``) besides the one Python calls.  The kernel never hands its
functions to C, but each wrapper would be compiled, optimised and linked into
every caller's machine code all the same, which lengthens the first run's
compile.  The Python-callable wrapper stays: any kernel function may be called
from Python.
"""

from __future__ import annotations

from numba import njit as _njit

__all__ = ["njit"]


def njit(*args, **options):
    """``numba.njit`` with ``no_cfunc_wrapper=True`` (as a bare decorator or with options)."""
    options.setdefault("no_cfunc_wrapper", True)
    return _njit(*args, **options)
