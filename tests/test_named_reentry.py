"""A kernel called by name compiled while another process has cached its callees
(``uniform2d/_kernel/external.py``): loading such a callee from the cache
registers the kernels called by name first, and must not compile the one being
compiled there, a second time, inside itself (numba refuses it: "compiler
re-entrant to the same function signature").

The cache state is the one a first run meets when the command and its warmer,
or two runs, fill one cache: the signatures the kernel was called by name with
are in the cache (``*.named.pkl``), its own entry is not, a callee's is."""

from __future__ import annotations

import json
import os
import subprocess
import sys

CODE = r"""
import json, sys
import numpy as np
from numba import typeof, types
from uniform2d._kernel import cdt, lawson

if sys.argv[1] == "callee":
    grown = lawson.grown(np.arange(3, dtype=np.int32), 5)
    print(json.dumps({"grown": grown[:3].tolist(), "size": int(grown.shape[0])}))
else:
    m, _ = cdt.allocate(8, 16)
    # what legalize_stack calls: _lawson, which calls lawson_recorded by name
    sig = (typeof(m), types.int32[::1], types.int64, types.int32, types.int64)
    lawson._lawson.compile(sig)
    print(json.dumps({"compiled": sig in lawson._lawson.overloads,
                      "grown_hits": sum(lawson.grown.stats.cache_hits.values())}))
"""


def _run(cache, step):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run([sys.executable, "-c", CODE, step], capture_output=True, text=True,
                         env=env, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.splitlines()[-1])


def test_a_kernel_called_by_name_compiles_while_its_callee_loads_from_the_cache(tmp_path):
    first = _run(tmp_path, "caller")  # cold: lawson_recorded called by name, signature kept
    assert first == {"compiled": True, "grown_hits": 0}
    kept = list(tmp_path.rglob("uniform2d_lawson_lawson_recorded.named.pkl"))
    assert len(kept) == 1
    removed = list(tmp_path.rglob("*.nb[ic]"))
    assert removed
    for p in removed:  # the kernels' entries gone, the kept signatures left
        p.unlink()
    # another process caches a callee of lawson_recorded (grown) only
    callee = _run(tmp_path, "callee")
    assert callee["grown"] == [0, 1, 2] and callee["size"] >= 5
    assert list(tmp_path.rglob("*.nbi"))
    # lawson_recorded compiled (no entry) for its stub in _lawson, grown loaded
    # from the cache meanwhile: that load must not compile lawson_recorded again
    second = _run(tmp_path, "caller")
    assert second["compiled"] and second["grown_hits"] > 0
