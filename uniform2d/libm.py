"""exp, log, arctan2, arcsin, arccos with the same bits on every CPU.

numpy dispatches these float64 ufuncs to SIMD code chosen for the CPU it runs
on (on AVX-512 CPUs its own or SVML-derived approximations), and their last
bits differ from the C library's, which it uses elsewhere: the same polygon
then gave a different mesh on an AVX-512 machine than on an AVX2 one.  These
drop-in replacements go through the C library on every CPU (a numba loop,
:mod:`uniform2d._kernel.libm`), so they return exactly what numpy's baseline
path returns, at about its speed.  sin, cos, hypot and sqrt are not here:
numpy 2.4 computes them the same way on every CPU (docs/architecture.md,
"Same bytes on every CPU").

Each takes array-likes (broadcast like the ufunc) and returns a float64 array of
the broadcast shape, a 0-d input giving a numpy float64.
"""

from __future__ import annotations

import numpy as np

from ._kernel.libm import acos_into, asin_into, atan2_into, exp_into, log_into

__all__ = ["arctan2", "exp", "log", "arcsin", "arccos"]


def _flat(*args):
    """The arguments broadcast to one shape, each as a contiguous 1-D float64
    array, and an output array of that shape (arrays of one shape are not
    broadcast: the optimiser calls these thousands of times a mesh)."""
    arrays = [np.asarray(a, dtype=np.float64) for a in args]
    if any(a.shape != arrays[0].shape for a in arrays):
        arrays = np.broadcast_arrays(*arrays)
    out = np.empty(arrays[0].shape)
    # contiguous and writable: numba compiles a kernel again for a read-only array
    return [np.require(a, np.float64, ("C", "W")).reshape(-1) for a in arrays], out


def _unary(kernel, x):
    (flat,), out = _flat(x)
    kernel(flat, out.reshape(-1))
    return out[()] if out.ndim == 0 else out


def arctan2(y, x):
    """``np.arctan2(y, x)`` by the C library's atan2."""
    (fy, fx), out = _flat(y, x)
    atan2_into(fy, fx, out.reshape(-1))
    return out[()] if out.ndim == 0 else out


def exp(x):
    """``np.exp(x)`` by the C library's exp."""
    return _unary(exp_into, x)


def log(x):
    """``np.log(x)`` by the C library's log."""
    return _unary(log_into, x)


def arcsin(x):
    """``np.arcsin(x)`` by the C library's asin."""
    return _unary(asin_into, x)


def arccos(x):
    """``np.arccos(x)`` by the C library's acos."""
    return _unary(acos_into, x)
