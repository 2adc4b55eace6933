"""numba's own overloads (``np.empty``, ``min``, ...) compiled once per caller's options they use.

numba compiles an overload (the implementation behind ``np.empty``, ``min``,
``max`` in a kernel) as a function of its own, once per argument types and per
*options of the calling function*: every option, while the overload inherits
only four of them (``nrt``, ``fastmath``, ``error_model``, ``forceinline``:
``numba.core.cpu.CPUTargetOptions.finalize``).  The kernels differ from each
other, and from numba's own functions, in options none of them inherits:
whether numba generates a wrapper for Python (:mod:`.pywrap`) or for C, and
whether the GIL is released.  So ``np.empty(n, np.int64)`` was compiled again
for each of those settings, the same code every time.

While numba looks an overload up, the caller's options it does not inherit are
given their defaults: the lookup finds the one compiled already.  What the
overload is compiled with, and so its code, is unchanged (the inherited options
are the caller's, as before); ``tests/test_overloads.py`` checks it.
"""

from __future__ import annotations

from numba.core import targetconfig
from numba.core.typing import templates

__all__ = ["NOT_INHERITED", "install"]

#: Options of a calling function that numba's overloads do not inherit, and
#: that the kernels or numba's own functions set differently.
NOT_INHERITED = ("no_cpython_wrapper", "no_cfunc_wrapper", "release_gil")


def _lookup_flags(flags):
    """``flags`` with the options of :data:`NOT_INHERITED` at their defaults
    (``flags`` itself when none is set)."""
    if flags is None or not any(flags.is_set(name) for name in NOT_INHERITED):
        return flags
    same = flags.copy()
    for name in NOT_INHERITED:
        same.discard(name)
    return same


def install() -> None:
    """Look numba's overloads up without the caller's options they do not
    inherit (see the module doc); once per process, the kernel's ``njit`` calls
    it.  Where numba is not as this module expects, nothing is changed."""
    template = getattr(templates, "_OverloadFunctionTemplate", None)
    original = getattr(template, "_get_impl", None)
    stack = getattr(targetconfig, "ConfigStack", None)
    if original is None or stack is None or getattr(original, "_shared", False):
        return

    def _get_impl(self, args, kws):
        flags = stack.top_or_none()
        same = _lookup_flags(flags)
        if same is flags:
            return original(self, args, kws)
        with stack().enter(same):
            return original(self, args, kws)

    _get_impl._shared = True
    template._get_impl = _get_impl
