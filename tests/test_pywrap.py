"""Kernels no Python code calls are compiled without numba's wrapper for Python,
yet Python may still call them: the same bits, no crash, in the process that
compiled them and in a later one loading them from the cache."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

#: Runs in a fresh process on the cache NUMBA_CACHE_DIR names.  argv[1] == "drop":
#: the command line's setting (drop_unused_wrappers) first.  Prints whether the
#: overloads of distance.to_segments (called from Python by uniform2d) and of
#: its callee _brute (called by kernels only) have a wrapper, and whether
#: Python calls of both give the bits of the plain Python function.
CODE = r"""
import json, sys
import numpy as np
from uniform2d.compile_cache import drop_unused_wrappers
from uniform2d._kernel import distance as D

if sys.argv[1] == "drop":
    drop_unused_wrappers()
rng = np.random.default_rng(3)
pts, a, b = rng.random((7, 2)), rng.random((4, 2)), rng.random((4, 2))
ref = D._brute.py_func(pts, a, b, np.inf)
first = sys.argv[2]
out = {}
for name in ([first] + [n for n in ("to_segments", "_brute") if n != first]):
    got = getattr(D, name)(pts, a, b, np.inf)
    out[name + " same"] = got.tobytes() == ref.tobytes()

def wrapped(disp):
    return [bool(c.library.get_pointer_to_function(c.fndesc.llvm_cpython_wrapper_name))
            for c in disp.overloads.values()]

out["to_segments wrapped"] = wrapped(D.to_segments)
out["_brute wrapped"] = wrapped(D._brute)
json.dump(out, sys.stdout)
"""


def _run(cache, *argv) -> dict:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    done = subprocess.run([sys.executable, "-c", CODE, *argv], env=env, capture_output=True,
                          text=True, timeout=600, check=True)
    return json.loads(done.stdout)


@pytest.mark.compile_cache
def test_a_kernel_only_kernels_call_has_no_wrapper_yet_python_can_call_it(tmp_path):
    first = _run(tmp_path, "drop", "to_segments")
    assert first["to_segments same"] and first["_brute same"]
    assert first["to_segments wrapped"] == [True]
    # the callee's overload has none; the Python call compiled it once more, with one,
    # outside the overloads the kernels link
    assert first["_brute wrapped"] == [False]

    # a later process, on the same cache, calling the callee from Python first: its
    # cached entry has no wrapper either
    later = _run(tmp_path, "keep", "_brute")
    assert later["to_segments same"] and later["_brute same"]
    assert later["_brute wrapped"] == [False]


@pytest.mark.compile_cache
def test_without_the_setting_every_kernel_keeps_its_wrapper(tmp_path):
    res = _run(tmp_path, "keep", "to_segments")
    assert res["to_segments same"] and res["_brute same"]
    assert res["to_segments wrapped"] == [True] and res["_brute wrapped"] == [True]
