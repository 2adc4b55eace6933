"""Kernel helpers compiled without reference counting (``njit(borrowed=True)``,
numba's ``_nrt=False``): they allocate nothing, and the kernels they call keep
their own counting whatever is compiled first."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from numba.core.registry import CPUDispatcher

from uniform2d._kernel import cdt, descent, lawson, orient, star

ROOT = Path(__file__).resolve().parents[1]

#: Runs in a fresh process on an empty numba cache: compiles the borrowed
#: star.star_ok first (its callee orient2d, and the exact path's C function
#: behind it, are compiled under it), then asks orient2d to decide exactly
#: collinear points, nearly collinear ones and a plain turn, and prints the
#: signs and star_ok's answer.
FIRST = r"""
import json
import numpy as np
from uniform2d._kernel import orient, star

SP = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [-1.0, -1.0, 1.0]])
ok = bool(star.star_ok(0.1, 0.1, 0.0, 0.0, 3, 3, SP, 0.0))
e = 2.0 ** -52
signs = [orient.orient2d(0.0, 0.0, 1.0, 1.0, 3.0, 3.0),
         orient.orient2d(0.5, 0.5, 12.0, 12.0, 24.0, 24.0 + 24.0 * e),
         orient.orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0)]
print(json.dumps({"ok": ok, "signs": [float(np.sign(s)) for s in signs]}))
"""


def test_a_kernel_first_compiled_under_a_borrowed_helper_keeps_its_reference_counting(tmp_path):
    """numba compiles a callee with the options it was not given inherited
    from the kernel being compiled: were ``_nrt`` not explicit, orient2d's
    exact path (which allocates) would be compiled without reference counting
    and fail to compile."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", FIRST], env=env, capture_output=True, text=True,
                          timeout=600, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout)
    assert out == {"ok": True, "signs": [0.0, 1.0, 1.0]}


def test_borrowed_helpers_have_no_reference_counting_and_the_others_have_it():
    borrowed = [star.star_ok, star.search, star.gather, star.counted, descent._star_energy,
                descent._star_gradient, cdt.snap_to, cdt.snap_times, cdt.flip_on,
                lawson._not_delaunay, lawson._record]
    for kernel in borrowed:
        assert isinstance(kernel, CPUDispatcher)
        assert kernel.targetoptions["_nrt"] is False, kernel.py_func.__qualname__
    for kernel in (cdt.flip, cdt.snap, lawson.lawson_recorded, lawson._flips, orient.orient2d):
        assert kernel.targetoptions["_nrt"] is True, kernel.py_func.__qualname__

