"""Whether numba's compiled kernels are cached, so the command can say when it compiles.

The kernels are compiled on first use and cached (``cache=True``): next to
their source when that is writable, else in numba's user-wide cache directory
(``NUMBA_CACHE_DIR`` when set).  Each kernel's cache has an index file; numba
itself decides where it is and whether it is fresh (same source file stamp,
same numba version), so asking each kernel's own cache is the one test that
agrees with what numba will do: an index without an entry means a compile.
"""

from __future__ import annotations

import importlib
import logging
import os
import pkgutil

__all__ = ["cold_kernels", "kernels_cold", "cache_writable", "COMPILE_NOTICE"]

log = logging.getLogger(__name__)

#: What the command line prints, once, before a run that compiles the kernels.
COMPILE_NOTICE = (
    "compiling the numba kernels: the first run takes 25 to 50 s longer "
    "(they are cached for later runs)"
)


def _kernel_dispatchers():
    """Every numba dispatcher with a disk cache in ``uniform2d._kernel``."""
    from numba.core.caching import FunctionCache
    from numba.core.registry import CPUDispatcher

    from . import _kernel

    seen = {}
    for info in pkgutil.iter_modules(_kernel.__path__):
        module = importlib.import_module(f"{_kernel.__name__}.{info.name}")
        for obj in vars(module).values():
            if isinstance(obj, CPUDispatcher) and isinstance(obj._cache, FunctionCache):
                seen[id(obj)] = obj
    return list(seen.values())


def cold_kernels() -> tuple[int, int]:
    """(kernels without a fresh cache entry, kernels with a disk cache)."""
    dispatchers = _kernel_dispatchers()
    cold = sum(1 for d in dispatchers if not d._cache._cache_file._load_index())
    return cold, len(dispatchers)


def kernels_cold(fraction: float = 0.5) -> bool | None:
    """Whether a run will compile most kernels (more than ``fraction`` of them
    have no fresh cache entry); None if numba's cache cannot be inspected."""
    try:
        cold, total = cold_kernels()
    except Exception:  # numba's cache internals are not a public API: then say nothing
        log.debug("cannot inspect numba's cache", exc_info=True)
        return None
    log.debug("%d of %d kernels have no cache entry", cold, total)
    return total > 0 and cold > fraction * total


def cache_writable() -> bool:
    """Whether numba can write every kernel's cache directory (False if it cannot be told)."""
    try:
        paths = {d._cache._cache_path for d in _kernel_dispatchers()}
    except Exception:  # numba's cache internals are not a public API
        log.debug("cannot inspect numba's cache", exc_info=True)
        return False
    return bool(paths) and all(os.access(p, os.W_OK) for p in paths)
