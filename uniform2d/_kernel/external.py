"""Kernels compiled once and called by name: the predicates' exact paths.

numba compiles a kernel together with a copy of every kernel it calls, callees
of callees included, and optimises and generates that copy again for each
caller.  The exact paths of the predicates (:mod:`.expansion`'s arithmetic
behind the filters of :func:`.orient.orient2d`, :func:`.dot.dot2d` and
:func:`.incircle.incircle`) are below almost every kernel, so a good part of
the first run's compile went into copies of code that runs only when a filter
cannot decide.  :func:`compiled_once` turns such a function (float64
arguments, a float64 result) into a C function, compiled once and cached on
disk like the kernels (numba's ``cfunc``), and returns a kernel-side stub that
calls it by a symbol name, as numba's compiled code calls numba's own C
helpers: the callers hold a call, not a copy.  The same code runs, so the
results are the same, bit for bit.

The C functions are compiled (or loaded from the cache) on first need, not at
import: :func:`ensure` runs when a kernel calling one is compiled (for that
one: on a cold cache the command and its warmer then compile different ones
at once) and before any kernel is loaded from numba's cache
(:func:`uniform2d.compile_claims.before_load`; all of them, since a cached
kernel may call any by name; not for the kernels the C functions are made of,
which call none).  Each is claimed like a kernel
while a second process fills the same cache (:mod:`uniform2d.compile_claims`).

:func:`called_by_name` does the same for larger kernels of any argument types
that several compiled kernels call (the Lawson flips behind every insertion,
the point insertion, INSERT's revalidation): the callee stays a numba kernel
with its own cache entry, and its callers call its machine code through a
symbol with numba's own calling convention (status, exceptions and references
as for a linked call).  The symbol is named from the callee and its argument
types, the same in every process, so a cached caller finds it once the callee
is loaded: before any kernel is read from the cache, every kernel called by
name is loaded (or compiled, if its entry is stale) for every signature it
was called by name with, listed in the cache beside it.
"""

from __future__ import annotations

import hashlib
import os
import pickle
from types import ModuleType

import llvmlite.binding as ll
from llvmlite import ir
from numba import types
from numba.core import cgutils, sigutils
from numba.core.ccallback import CFunc
from numba.core.compiler_lock import global_compiler_lock
from numba.core.dispatcher import Dispatcher
from numba.core.extending import intrinsic
from numba.core.registry import cpu_target

from ..compile_claims import ClaimedCache, before_load

__all__ = ["called_by_name", "compiled_once", "ensure", "named_kernels"]

_pending: dict = {}  # symbol -> (Python function, argument count): not compiled yet
_made: dict = {}  # symbol -> its CFunc (kept alive: the symbol points into its code)
_below: set = set()  # the Python functions of those C functions' kernels and their callees


def _symbol(func) -> str:
    return f"uniform2d_{func.__module__.rsplit('.', 1)[-1]}_{func.__name__}"


def ensure(name: str | None = None) -> None:
    """Compile (or load from the cache) the C function of symbol ``name``, or
    every one :func:`compiled_once` made (None), unless it is already, and
    register its symbol."""
    if not _pending or (name is not None and name not in _pending):
        return
    with global_compiler_lock:
        for symbol in [name] if name is not None else list(_pending):
            if symbol not in _pending:
                continue
            func, nargs = _pending.pop(symbol)  # before compiling: its cache calls ensure()
            sig = sigutils.normalize_signature(types.float64(*[types.float64] * nargs))
            c = CFunc(func, sig, locals={}, options={"nopython": True, "nogil": True, "_nrt": True})
            c._cache = ClaimedCache(func)
            try:
                c.compile()
            except BaseException:
                _pending[symbol] = (func, nargs)
                raise
            ll.add_symbol(symbol, c.address)
            _made[symbol] = c


def _before_load(func) -> None:
    if func not in _below:  # (a callee of a C function cannot call one: no recursion)
        ensure()  # any of them: which ones the cached code calls is not known


before_load(_before_load)


def _callees(func, seen: set) -> None:
    """Add ``func`` and the Python functions of every kernel it calls, callees of
    callees too, to ``seen``."""
    if func in seen:
        return
    seen.add(func)
    for word in func.__code__.co_names:
        kernel = func.__globals__.get(word)
        if isinstance(kernel, Dispatcher):
            _callees(kernel.py_func, seen)


def compiled_once(func, nargs: int):
    """The kernel stub calling ``func(x_1, ..., x_nargs) -> float`` (a kernel's
    Python function; 6 or 8 float64 arguments) compiled once as a C function."""
    name = _symbol(func)
    _pending[name] = (func, nargs)
    _callees(func, _below)
    floats = [types.float64] * nargs

    def codegen(context, builder, signature, args):
        ensure(name)
        fnty = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()] * nargs)
        fn = cgutils.get_or_insert_function(builder.module, fnty, name)
        return builder.call(fn, args)

    if nargs == 6:
        @intrinsic
        def call(typingctx, a, b, c, d, e, f):
            return types.float64(*floats), codegen
    elif nargs == 8:
        @intrinsic
        def call(typingctx, a, b, c, d, e, f, g, h):
            return types.float64(*floats), codegen
    else:
        raise ValueError(f"compiled_once takes 6 or 8 arguments, got {nargs}")
    return call


_named: list = []  # the dispatchers called by name, in the order made (callees first)
_named_done: dict = {}  # symbol -> the compile result its address points into (kept alive)
_loading = [False]
_stub_of: dict = {}  # id of a called_by_name stub -> (the stub, the dispatcher it calls)
_reached: dict = {}  # dispatcher called by name -> the Python functions it may reach


def _named_symbol(disp, argtys) -> str:
    # stable across processes (a cached caller names it): not numba's mangled
    # name, whose version counter depends on the order of compilation
    digest = hashlib.sha1(str(argtys).encode()).hexdigest()[:16]
    return f"uniform2d_named_{_symbol(disp.py_func)}_{digest}"


def _register(disp, argtys):
    """Compile (or load) ``disp`` for ``argtys`` and register its symbol."""
    symbol = _named_symbol(disp, argtys)
    if symbol not in _named_done:
        disp.compile(argtys)
        cres = disp.overloads[argtys]
        address = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
        if not address:
            raise RuntimeError(f"{cres.fndesc.llvm_func_name} has no address")
        ll.add_symbol(symbol, address)
        _named_done[symbol] = cres
        _remember(disp, argtys)
    return symbol, _named_done[symbol]


def _signatures_file(disp):
    cache = getattr(disp, "_cache", None)
    path = getattr(cache, "_cache_path", None)
    return None if path is None else os.path.join(path, f"{_symbol(disp.py_func)}.named.pkl")


def _remembered(disp) -> list:
    """The signatures ``disp`` was called by name with, in this cache: kept
    apart from its own cache entries, which go stale when it is edited while its
    cached callers (numba does not look at their callees) still call it."""
    path = _signatures_file(disp)
    try:
        with open(path, "rb") as f:
            return list(pickle.load(f))
    except (OSError, TypeError, EOFError, pickle.UnpicklingError):
        return []


def _remember(disp, argtys) -> None:
    path = _signatures_file(disp)
    known = _remembered(disp)
    if path is None or argtys in known:
        return
    tmp = f"{path}.{os.getpid()}.tmp"
    try:
        with open(tmp, "wb") as f:
            pickle.dump(known + [argtys], f)
        os.replace(tmp, path)
    except OSError:  # an unwritable cache: numba caches nothing there either
        pass


def _reach(func, seen: set) -> None:
    """Add ``func`` and the Python functions of every kernel it may call
    (directly, as a module's attribute, or by name through a stub), callees of
    callees too, to ``seen``."""
    if func in seen:
        return
    seen.add(func)
    names = func.__code__.co_names
    for word in names:
        obj = func.__globals__.get(word)
        for target in [getattr(obj, n, None) for n in names] if isinstance(obj, ModuleType) \
                else [obj]:
            disp = _stub_of.get(id(target), (None, target))[1]
            if isinstance(disp, Dispatcher):
                _reach(disp.py_func, seen)


def _reaches(disp) -> set:
    if disp not in _reached:
        _reached[disp] = set()
        _reach(disp.py_func, _reached[disp])
    return _reached[disp]


def _load_named(func) -> None:
    """Before any kernel is read from the cache: every kernel called by name,
    for every signature in its cache, loaded and its symbol registered (which
    ones the cached code calls is not known).

    Not the ones that may call ``func`` or a function being typed now (this
    load may be a callee's, inside the compile of a kernel called by name, one
    whose entry in the cache is stale or was never written, while another
    process cached its callees): compiling one of those would type such a
    function again for the same argument types, which numba refuses as a
    re-entrant compile.  The cached code cannot call them by name: no kernel
    calls itself, directly or not."""
    if _loading[0] or func in _below:  # (the C functions' kernels call none by name)
        return
    _loading[0] = True
    try:
        ensure()  # the kernels called by name may call the C functions
        with global_compiler_lock:  # (typing runs under it: the call stack is this thread's)
            busy = {frame.func_id.func for frame in cpu_target.typing_context.callstack}
            busy.add(func)
            for disp in _named:
                if busy.isdisjoint(_reaches(disp)):
                    for argtys in _remembered(disp):
                        _register(disp, tuple(argtys))
    finally:
        _loading[0] = False


before_load(_load_named)


def named_kernels() -> list:
    """The kernels :func:`called_by_name` made stubs for (callees first)."""
    return list(_named)


def called_by_name(disp):
    """The kernel stub calling the kernel ``disp`` (its own compile, cached) by
    a symbol name with numba's calling convention, rather than linking a copy
    of it (and of its callees) into every caller."""
    _named.append(disp)
    nargs = disp.py_func.__code__.co_argcount

    def typer(typingctx, *args):
        argtys = tuple(types.unliteral(a) for a in args)
        symbol, cres = _register(disp, argtys)
        fndesc = cres.fndesc

        def codegen(context, builder, signature, llargs):
            fnty = context.call_conv.get_function_type(fndesc.restype, fndesc.argtypes)
            fn = cgutils.get_or_insert_function(builder.module, fnty, symbol)
            status, res = context.call_conv.call_function(
                builder, fn, fndesc.restype, fndesc.argtypes, llargs)
            with cgutils.if_unlikely(builder, status.is_error):
                context.call_conv.return_status_propagate(builder, status)
            return res

        return cres.signature.return_type(*argtys), codegen

    names = ", ".join(f"a{i}" for i in range(nargs))
    namespace = {"typer": typer}
    exec(f"def call(typingctx, {names}):\n    return typer(typingctx, {names})\n", namespace)
    stub = intrinsic(namespace["call"])
    _stub_of[id(stub)] = (stub, disp)
    return stub
