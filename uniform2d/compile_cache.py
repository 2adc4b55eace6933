"""Whether numba's compiled kernels are cached, so the command can say when it compiles.

The kernels are compiled on first use and cached (``cache=True``): next to
their source when that is writable, else in numba's user-wide cache directory
(``NUMBA_CACHE_DIR`` when set).  Each kernel's cache has an index file; numba
itself decides where it is and whether it is fresh (same source file stamp,
same numba version), so asking each kernel's own cache is the one test that
agrees with what numba will do: an index without an entry means a compile.

Only the kernels that Python code calls are asked (the *entry* kernels,
:func:`entry_kernels`): a kernel called only by other kernels is compiled
with its caller, never on its own, and numba loads a cached caller without
looking at its callees' caches.  So a callee's missing or stale entry (its
source edited since, in a development checkout) says nothing about what a run
compiles; counted, it made a cache whose every entry point was fresh look
cold.
"""

from __future__ import annotations

import importlib
import inspect
import logging
import os
import pkgutil
import sys
from pathlib import Path
from types import CodeType, FunctionType, ModuleType

__all__ = ["cold_kernels", "entry_kernels", "python_called", "drop_unused_wrappers",
           "kernels_cold", "cache_writable", "COMPILE_NOTICE"]

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


def _codes(module: ModuleType):
    """The code objects of the plain Python functions (not kernels) defined in
    ``module``, its classes' methods and properties included, nested ones too."""
    stack = []
    for obj in vars(module).values():
        if getattr(obj, "__module__", None) != module.__name__:
            continue
        members = vars(obj).values() if inspect.isclass(obj) else (obj,)
        for member in members:
            for f in (member, getattr(member, "__func__", None), getattr(member, "fget", None),
                      getattr(member, "fset", None)):
                if isinstance(f, FunctionType):
                    stack.append(f.__code__)
    while stack:
        code = stack.pop()
        yield code
        stack.extend(c for c in code.co_consts if isinstance(c, CodeType))


def entry_kernels(dispatchers) -> list:
    """The ``dispatchers`` that Python code of uniform2d calls, as far as the
    package's imported modules tell: a kernel a plain function (or method) names,
    directly or as an attribute of a kernel module it imported (``cdt.flip``).
    Kernels that kernels call by name (:func:`._kernel.external.called_by_name`)
    count too: their own entries are loaded, not copies in their callers.
    Every other kernel is a callee of kernels, compiled with its callers."""
    from . import _kernel
    from ._kernel.external import named_kernels

    kernel = _kernel.__name__ + "."
    wanted = {id(d): d for d in dispatchers}
    called = {}
    for name, module in list(sys.modules.items()):
        if not (name == "uniform2d" or name.startswith("uniform2d.")) or module is None:
            continue
        space = vars(module)
        for code in _codes(module):
            for word in code.co_names:
                obj = space.get(word)
                targets = [obj]
                if isinstance(obj, ModuleType) and obj.__name__.startswith(kernel):
                    targets = [getattr(obj, w, None) for w in code.co_names]  # kinsert.run
                for t in targets:
                    if id(t) in wanted:
                        called[id(t)] = t
    for d in named_kernels():
        if id(d) in wanted:
            called[id(d)] = d
    return list(called.values())


def python_called() -> list:
    """The kernels of ``uniform2d._kernel`` that the package's Python code calls
    (:func:`entry_kernels` of them all), every module of the package that
    names the kernel imported first (but the peers' adapters, which wrap other
    meshers), not only those ``import uniform2d`` imports."""
    import uniform2d

    root = Path(uniform2d.__file__).parent
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        if "_kernel" in parts or "peers" in parts or parts[-1] == "__main__":
            continue
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        if name not in sys.modules and "_kernel" in path.read_text(encoding="utf-8"):
            importlib.import_module(name)
    return entry_kernels(_kernel_dispatchers())


def drop_unused_wrappers() -> None:
    """Compile the kernels no Python code calls without numba's wrapper for
    Python (:mod:`uniform2d._kernel.pywrap`): less to compile on a cold cache.
    The command line calls it, and so does its warmer."""
    from ._kernel.pywrap import callers_from

    callers_from(python_called)


def cold_kernels() -> tuple[int, int]:
    """(entry kernels without a fresh cache entry, entry kernels with a disk
    cache): see :func:`entry_kernels` and the module doc."""
    import uniform2d  # noqa: F401  (the package's API modules, which call the kernels)

    dispatchers = entry_kernels(_kernel_dispatchers())
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
