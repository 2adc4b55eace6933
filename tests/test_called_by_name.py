"""Kernels called by name (``uniform2d/_kernel/external.py``, ``called_by_name``):
their callers hold a call, not a copy, compiled in one process and read back
from numba's cache in another."""

from __future__ import annotations

import json
import os
import subprocess
import sys

CODE = r"""
import hashlib, json
import numpy as np
import uniform2d
from uniform2d._kernel import cavity, insert, lawson
from uniform2d.testing import check_mesh

polygon = uniform2d.Polygon([(0, 0), (3, 0), (3, 1), (1, 2), (0, 1)])
mesh = uniform2d.uniform_mesh(polygon, n=80)
check_mesh(mesh.points, mesh.triangles, polygon)
digest = hashlib.sha256(np.asarray(mesh.points).tobytes()
                        + np.asarray(mesh.triangles).tobytes()).hexdigest()
hits = sum(d.stats.cache_hits.get(s, 0) for d in (lawson._lawson, insert.run)
           for s in d.signatures)
ir = "" if hits else "".join(lawson._lawson.inspect_llvm().values())
run_ir = "" if hits else "".join(insert.run.inspect_llvm().values())
print(json.dumps({"digest": digest, "points": len(mesh.points), "hits": hits,
                  "declares": "declare i32 @uniform2d_named_uniform2d_lawson_lawson_recorded_" in ir,
                  "copy": "define linkonce_odr i32 @_ZN9uniform2d7_kernel6lawson15lawson_recorded"
                          in ir,
                  "run_declares": [f"declare i32 @uniform2d_named_uniform2d_insert_{f}_" in run_ir
                                   for f in ("_gather", "_choose")]}))
"""


def _run(cache):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True,
                         env=env, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.splitlines()[-1])


def test_a_kernel_called_by_name_is_a_call_not_a_copy_and_loads_from_the_cache(tmp_path):
    cold = _run(tmp_path)  # an empty cache: every kernel compiled here
    assert cold["hits"] == 0 and cold["points"] == 5 + 80  # the corners and n
    assert cold["declares"] and not cold["copy"]
    assert cold["run_declares"] == [True, True]  # INSERT's steps call them by name
    warm = _run(tmp_path)  # the callers read back, calling the callee's cached code
    assert warm["hits"] > 0
    assert warm["digest"] == cold["digest"]
