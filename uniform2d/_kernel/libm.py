"""The C library's transcendental functions over arrays, one element at a time.

numpy computes float64 ``exp``, ``log``, ``arctan2``, ``arcsin`` ... with SIMD
code it picks for the CPU at run time (AVX-512 here, its own or SVML-derived
approximations), whose last bits differ from the C library's, which numpy
calls on CPUs without those instructions.  A mesh built from them then differs
from one CPU to another.  These loops call the C library (numba lowers
``math.*`` to libm calls, which LLVM does not vectorise without a vector math
library), so every CPU gets the bits numpy's baseline path gives.
"""

from __future__ import annotations

import math

from ._jit import njit

__all__ = ["atan2_into", "exp_into", "log_into", "asin_into", "acos_into"]


@njit(cache=True)
def atan2_into(y, x, out):
    """out[i] = atan2(y[i], x[i]) (1-D float64 arrays of one length)."""
    for i in range(out.shape[0]):
        out[i] = math.atan2(y[i], x[i])


@njit(cache=True)
def exp_into(x, out):
    """out[i] = exp(x[i])."""
    for i in range(out.shape[0]):
        out[i] = math.exp(x[i])


@njit(cache=True)
def log_into(x, out):
    """out[i] = log(x[i]) (-inf at 0 and nan below, as numpy's; numba's math.log
    raises nothing in a kernel)."""
    for i in range(out.shape[0]):
        out[i] = math.log(x[i])


@njit(cache=True)
def asin_into(x, out):
    """out[i] = asin(x[i])."""
    for i in range(out.shape[0]):
        out[i] = math.asin(x[i])


@njit(cache=True)
def acos_into(x, out):
    """out[i] = acos(x[i])."""
    for i in range(out.shape[0]):
        out[i] = math.acos(x[i])
