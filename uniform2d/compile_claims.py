"""Two processes filling one numba cache, each kernel compiled by one of them only.

On a cold cache the command compiles its kernels while a second process (the
warmer, :mod:`uniform2d.cli._warmer`) compiles, into the same cache, those the
run needs later.  numba looks in its cache before it compiles a kernel, but a
kernel the other process is compiling at that moment is not there yet: both
would compile it, the work of one of them lost.  So, while the two share a
cache, a process *claims* a kernel it is about to compile for some argument
types (an exclusive lock on a file named after the kernel's cache index and
those types, in a directory the two share) and holds the claim until the
compiled kernel is in the cache.  A process finding a kernel claimed waits for
the claim to end, then loads the kernel from the cache instead of compiling it.

The lock is ``flock``'s: the system drops it when its process ends, however it
ends.  Two processes cannot wait on each other for ever, since a kernel is
claimed only by the process compiling it, the kernels a compile waits for are
its callees, and no kernel calls itself, directly or not; a wait is bounded all
the same (:data:`PATIENCE`), after which the process compiles the kernel
itself.  Without :func:`share` (the default, and where ``fcntl`` is missing),
a cache behaves exactly as numba's own.

A claim is per argument types, but numba keeps one index per kernel, for all
of them: to save an overload it reads the index, picks a data file's name
not in it, writes the index, then the data.  Two processes saving overloads
of one kernel for different types at once (``heap.grown`` for two dtypes,
one in each) could both read the index before either wrote it, pick the same
name, and leave an index that gives one's types the other's code (or loses
an entry).  While shared, each kernel's index is locked for its read-modify-
write (and its reads, shared), so the two see each other's saves whole.
"""

from __future__ import annotations

import hashlib
import logging
import os
import time
from contextlib import contextmanager

from numba.core import event
from numba.core.caching import FunctionCache, IndexDataCacheFile

try:
    import fcntl
except ImportError:  # no flock (Windows): kernels are never claimed
    fcntl = None

__all__ = ["ENV", "PATIENCE", "ClaimedCache", "before_load", "share", "shared", "enable_caching"]

log = logging.getLogger(__name__)

#: The environment variable naming the shared directory in the second process.
ENV = "UNIFORM2D_COMPILE_CLAIMS"

#: Seconds a process waits for a kernel the other one compiles, before it
#: compiles the kernel itself.
PATIENCE = 120.0

_state = {"dir": None}
_held: dict[str, int] = {}  # claimed kernel (its cache's file name) -> the lock file's descriptor
_before_load: list = []  # called before numba reads a kernel from its cache


def share(directory: str | None) -> None:
    """Claim the kernels this process compiles in ``directory`` (shared with the
    other process filling the same cache), or, with None, stop claiming them."""
    _state["dir"] = directory if fcntl is not None else None


def before_load(callback) -> None:
    """Call ``callback(func)`` each time, before the kernel of Python function
    ``func`` is loaded from its cache (what cached code needs loaded first:
    :mod:`uniform2d._kernel.external`)."""
    _before_load.append(callback)


def shared() -> str | None:
    """The directory where this process claims kernels, or None."""
    return _state["dir"]


def _claim(key: str) -> bool:
    """Hold the claim on ``key``, waiting while the other process holds it (at
    most :data:`PATIENCE` s); False if it could not be had."""
    if key in _held:
        return True
    try:
        fd = os.open(os.path.join(_state["dir"], key + ".lock"), os.O_RDWR | os.O_CREAT, 0o600)
    except OSError:
        log.debug("cannot claim %s", key, exc_info=True)
        return False
    deadline = time.monotonic() + PATIENCE
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            break
        except BlockingIOError:
            if time.monotonic() > deadline:
                os.close(fd)
                log.debug("%s stayed claimed: compiling it here too", key)
                return False
            time.sleep(0.005)
        except OSError:
            os.close(fd)
            log.debug("cannot claim %s", key, exc_info=True)
            return False
    _held[key] = fd
    return True


def _release(key: str) -> None:
    fd = _held.pop(key, None)
    if fd is not None:
        os.close(fd)  # closing the only descriptor of the lock drops the lock


@contextmanager
def _index_locked(name: str, how: int):
    """Hold ``flock``'s lock ``how`` on the index ``name`` in the shared
    directory (nothing while none is shared, or if its file cannot be opened)."""
    fd = None
    if _state["dir"] is not None:
        try:
            fd = os.open(os.path.join(_state["dir"], name + ".index-lock"),
                         os.O_RDWR | os.O_CREAT, 0o600)
            fcntl.flock(fd, how)  # held for a file's read or write: not for long
        except OSError:
            log.debug("cannot lock the index %s", name, exc_info=True)
    try:
        yield
    finally:
        if fd is not None:
            os.close(fd)


class _LockedIndex(IndexDataCacheFile):
    """numba's index and data files of one kernel, read and written under the
    index's lock while a directory is shared (see the module doc)."""

    def save(self, key, data):
        with _index_locked(self._index_name, fcntl.LOCK_EX if fcntl else 0):
            super().save(key, data)

    def load(self, key):
        with _index_locked(self._index_name, fcntl.LOCK_SH if fcntl else 0):
            return super().load(key)


class ClaimedCache(FunctionCache):
    """numba's per-function disk cache, claiming (see the module doc) the kernel
    from a miss in the cache until its compiled code is saved there, its index
    locked while it is read or written."""

    def __init__(self, py_func):
        super().__init__(py_func)
        self._cache_file.__class__ = _LockedIndex  # (numba's, made by Cache.__init__)

    def _key(self, sig=None) -> str:
        """The kernel's claim for the argument types ``sig``: its index file's
        name (see numba's cache) and a digest of the types; the index file's
        name alone (the prefix of all its claims) without ``sig``."""
        name = self._cache_file._index_name
        if sig is None:
            return name
        return f"{name}.{hashlib.sha1(str(sig).encode()).hexdigest()[:16]}"

    def load_overload(self, sig, target_context):
        if _before_load and self._index_key(sig, target_context.codegen()) in \
                self._cache_file._load_index():
            for callback in _before_load:
                callback(self._py_func)
        data = super().load_overload(sig, target_context)
        if data is not None or _state["dir"] is None or not self._enabled:
            return data
        key = self._key(sig)
        if _claim(key):
            data = super().load_overload(sig, target_context)  # compiled meanwhile?
            if data is not None:
                _release(key)
        return data

    def save_overload(self, sig, data):
        try:
            super().save_overload(sig, data)
        finally:
            _release(self._key(sig))


class _Unclaim(event.Listener):
    """Drops the claim of a kernel whose compile failed (nothing will be saved):
    one whose compile ended without adding its overload (numba adds it before
    the end; ``Event.is_failed`` cannot tell, it is True after a success)."""

    def on_start(self, ev):
        pass

    def on_end(self, ev):
        if not _held:
            return
        dispatcher = ev.data.get("dispatcher")
        cache = getattr(dispatcher, "_cache", None)
        if isinstance(cache, ClaimedCache) and tuple(ev.data["args"]) not in dispatcher.overloads:
            prefix = cache._key() + "."
            for key in [k for k in _held if k.startswith(prefix)]:
                _release(key)


event.register("numba:compile", _Unclaim())


def enable_caching(dispatcher) -> None:
    """Give a numba dispatcher its disk cache, as ``cache=True`` does, one that
    claims what it compiles while :func:`share` is on."""
    dispatcher._cache = ClaimedCache(dispatcher.py_func)
