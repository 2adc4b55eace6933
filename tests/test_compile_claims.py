"""Two processes filling one numba cache: a kernel one of them has claimed, the
other waits for and loads, never compiles; a failed compile leaves no claim;
without a shared directory nothing is claimed."""

from __future__ import annotations

import fcntl
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from numba import types

from uniform2d import compile_claims
from uniform2d._kernel import expansion

ROOT = Path(__file__).resolve().parents[1]
SIG = (types.float64, types.float64)

#: Runs in a fresh process on the cache in $NUMBA_CACHE_DIR, claiming in argv[1]
#: (none if empty): says "calling", calls two_sum, prints whether it loaded it
#: from the cache and which kernels it compiled.
CALL = r"""
import json, sys
from numba.core import event
from uniform2d import compile_claims
from uniform2d._kernel import expansion

compiled = []

class Compiled(event.Listener):
    def on_start(self, e):
        pass

    def on_end(self, e):
        compiled.append(e.data["dispatcher"].py_func.__name__)

event.register("numba:compile", Compiled())
compile_claims.share(sys.argv[1] or None)
print("calling", flush=True)
expansion.two_sum(1.0, 2.0 ** -60)
stats = expansion.two_sum.stats
print(json.dumps({"hits": len(stats.cache_hits), "compiled": compiled}), flush=True)
"""


def _start(cache: Path, claims: str) -> subprocess.Popen:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": str(ROOT)}
    return subprocess.Popen([sys.executable, "-c", CALL, claims], env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _claim_file(claims: Path) -> Path:
    return claims / (expansion.two_sum._cache._key(SIG) + ".lock")


@pytest.mark.skipif(compile_claims.fcntl is None, reason="claims need flock")
def test_a_claimed_kernel_is_waited_for_and_loaded_not_compiled(tmp_path):
    cache, claims = tmp_path / "cache", tmp_path / "claims"
    claims.mkdir()
    with open(_claim_file(claims), "w") as held:  # the other process compiles it now ...
        fcntl.flock(held, fcntl.LOCK_EX)
        waiting = _start(cache, str(claims))
        assert waiting.stdout.readline() == "calling\n"
        filler = _start(cache, "")  # ... and puts it in the cache (it claims nothing)
        out, err = filler.communicate(timeout=300)
        assert filler.returncode == 0, err
        assert json.loads(out.splitlines()[-1])["compiled"] == ["two_sum"]
        assert waiting.poll() is None  # it cannot go on while the claim holds
    out, err = waiting.communicate(timeout=300)  # the claim ends with its file's closing
    assert waiting.returncode == 0, err
    assert json.loads(out.splitlines()[-1]) == {"hits": 1, "compiled": []}


@pytest.mark.skipif(compile_claims.fcntl is None, reason="claims need flock")
def test_a_compile_claims_its_kernel_until_cached_and_a_failed_one_leaves_no_claim(tmp_path):
    code = r"""
import fcntl, os, sys
from numba import types
from uniform2d import compile_claims
from uniform2d._kernel import expansion

claims = sys.argv[1]
compile_claims.share(claims)
key = expansion.two_sum._cache._key((types.float64, types.float64))
seen = []
load = compile_claims.ClaimedCache.load_overload
def spy(self, sig, ctx):  # the claim is held from the miss to the save
    data = load(self, sig, ctx)
    if data is None and self._key(sig) == key:
        with open(os.path.join(claims, key + ".lock")) as f:
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
                seen.append("free")
            except BlockingIOError:
                seen.append("held")
    return data
compile_claims.ClaimedCache.load_overload = spy
expansion.two_sum(1.0, 2.0)
try:
    expansion.two_sum("a", 2.0)
except Exception:
    pass
for name in os.listdir(claims):  # every claim has ended
    with open(os.path.join(claims, name)) as f:
        fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
print(seen, sum(name.endswith(".lock") for name in os.listdir(claims)))  # (not .index-lock)
"""
    claims = tmp_path / "claims"
    claims.mkdir()
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", code, str(claims)], env=env, text=True,
                          capture_output=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["['held']", "2"]  # two_sum's two argument types


def test_nothing_is_claimed_unless_shared(tmp_path):
    assert compile_claims.shared() is None
    waiting = _start(tmp_path / "cache", "")
    out, err = waiting.communicate(timeout=300)
    assert waiting.returncode == 0, err
    assert json.loads(out.splitlines()[-1]) == {"hits": 0, "compiled": ["two_sum"]}


#: A kernel with a claimed cache (as uniform2d's), in a module of its own.
KERNEL = """
from numba import njit
from uniform2d.compile_claims import enable_caching

@njit
def grown(a):
    return a[0] + 1

enable_caching(grown)
"""

#: Runs in a fresh process (the module above on sys.path, the cache in
#: $NUMBA_CACHE_DIR): claiming in argv[1], calls grown on an array of dtype
#: argv[2]; numba's save, once it has read the index, waits (5 s at most) for
#: the other process's save to have read it too, as a loaded machine may leave
#: a process between the read and the write.
SLOW_SAVE = r"""
import os, sys, time
import numpy as np
from numba.core import caching
from uniform2d import compile_claims

read, save, saving = caching.IndexDataCacheFile._load_index, caching.IndexDataCacheFile.save, []

def read_then_wait(self):
    index = read(self)
    if saving:
        open(sys.argv[2] + ".read", "w").close()
        other = ("float64" if sys.argv[2] == "int64" else "int64") + ".read"
        deadline = time.monotonic() + 5.0
        while not os.path.exists(other) and time.monotonic() < deadline:
            time.sleep(0.01)
    return index

def save_saying(self, key, data):
    saving.append(key)
    try:
        save(self, key, data)
    finally:
        saving.pop()

caching.IndexDataCacheFile._load_index = read_then_wait
caching.IndexDataCacheFile.save = save_saying
compile_claims.share(sys.argv[1])
import kernel
kernel.grown(np.zeros(1, sys.argv[2]))
"""


@pytest.mark.skipif(compile_claims.fcntl is None, reason="claims need flock")
def test_two_processes_saving_one_kernel_for_two_types_at_once_keep_both(tmp_path):
    """numba reads a kernel's index, then writes it and the data; two
    processes doing so at once for two dtypes wrote the same data file's name,
    and an index giving one's types the other's code.  Each type, loaded after
    them, must be found in the cache with its own code."""
    (tmp_path / "kernel.py").write_text(KERNEL)
    claims = tmp_path / "claims"
    claims.mkdir()
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])}
    procs = [subprocess.Popen([sys.executable, "-c", SLOW_SAVE, str(claims), dtype], env=env,
                              stderr=subprocess.PIPE, text=True, cwd=tmp_path)
             for dtype in ("int64", "float64")]
    for p in procs:
        assert p.wait(timeout=300) == 0, p.stderr.read()
        p.stderr.close()
    check = ("import numpy as np, kernel\n"
             "print(repr(kernel.grown(np.zeros(1, 'int64'))), repr(kernel.grown(np.zeros(1))),"
             " len(kernel.grown.stats.cache_hits), len(kernel.grown.stats.cache_misses))")
    done = subprocess.run([sys.executable, "-c", check], env=env, capture_output=True, text=True,
                          timeout=300, check=True)
    assert done.stdout.split() == ["1", "1.0", "2", "0"]
