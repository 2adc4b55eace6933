"""How many threads the library's independent work runs on, and running it there.

The optimiser tries several starts of a mesh (:func:`uniform2d.optimize.moves.improve_best`),
each in its own kernel state: independent work, which runs on a pool of
threads (the compiled kernels release the GIL: ``nogil``, see
:mod:`uniform2d._kernel._jit`).  Results come back in the order of the items
and every item's work is the same whatever thread runs it, so a mesh is the
same, bit for bit, on any number of threads.

The count is, in order: what :func:`set_threads` set; the environment variable
``UNIFORM2D_THREADS``; the cores this process may run on.

The threads are started once per process and kept (:func:`_pool`): a mesh maps
over its starts some seven times, and a thread started while other work keeps
the cores busy waits for a time slice (the scheduler lets new threads queue),
some milliseconds each on a loaded machine, where a kept thread woken for the
next map runs at once.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterable
from concurrent.futures import Future, ThreadPoolExecutor, wait

from .errors import InvalidArgumentError

__all__ = ["ENV", "get_threads", "in_background", "map_pool", "set_threads", "thread_map"]

#: The environment variable read when :func:`set_threads` was not called.
ENV = "UNIFORM2D_THREADS"
_chosen: list = [None]
#: Kept executors, by (process id, kind, size): a forked child starts its own.
_pools: dict = {}
_pools_lock = threading.Lock()
_worker = threading.local()  # ``inside`` on the threads of thread_map's executors
#: Threads in_background may run at once before a task waits for one.
BACKGROUND = 64


def _mark_worker() -> None:
    _worker.inside = True


def _forgotten_in_child() -> None:
    """A forked child has none of the parent's threads, and its lock may have
    been held by one of them at the fork: a new lock, and pools made anew."""
    global _pools_lock
    _pools_lock = threading.Lock()
    _pools.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forgotten_in_child)


def _pool(kind: str, size: int) -> ThreadPoolExecutor:
    """The kept executor of ``size`` threads for ``kind`` ("map": thread_map's,
    "background": in_background's), made on first use in this process."""
    key = (os.getpid(), kind, size)
    with _pools_lock:
        pool = _pools.get(key)
        if pool is None:
            pool = ThreadPoolExecutor(max_workers=size, thread_name_prefix=f"uniform2d-{kind}",
                                      initializer=_mark_worker if kind == "map" else None)
            _pools[key] = pool
        return pool


def _check(count, what: str) -> int:
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise InvalidArgumentError(f"{what} must be an integer of at least 1, got {count!r}")
    return count


def set_threads(count: int | None) -> None:
    """Run independent work on ``count`` threads (None: back to the default).

    Examples
    --------
    >>> from uniform2d.threads import set_threads, get_threads
    >>> set_threads(1); get_threads()
    1
    >>> set_threads(None)
    """
    _chosen[0] = None if count is None else _check(count, "the thread count")


def get_threads() -> int:
    """The thread count in force (see the module docstring)."""
    if _chosen[0] is not None:
        return _chosen[0]
    env = os.environ.get(ENV, "").strip()
    if env:
        try:
            value = int(env)
        except ValueError:
            value = None
        return _check(value if value is not None else env, ENV)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def thread_map(fn: Callable, items: Iterable) -> list:
    """``[fn(item) for item in items]``, the calls spread over :func:`get_threads`
    threads; the first exception raised is raised here.  Called from one of
    those threads (a map inside a map), it runs the calls there, in turn: the
    outer map's threads are busy, and waiting for them would never end.

    Examples
    --------
    >>> thread_map(lambda x: x * x, range(5))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    k = get_threads()
    if min(k, len(items)) <= 1 or getattr(_worker, "inside", False):
        return [fn(item) for item in items]
    pool = _pool("map", k)
    futures = [pool.submit(fn, item) for item in items]
    try:
        wait(futures)  # every call ended before any result or exception is given
    except BaseException:  # an interrupt: start no more of them
        for f in futures:
            f.cancel()
        raise
    return [f.result() for f in futures]


def map_pool() -> ThreadPoolExecutor | None:
    """The kept executor of :func:`thread_map`, for callers that submit work
    as earlier work ends (and must keep its results in a fixed order
    themselves); None where thread_map would run its calls in turn (one
    thread, or called from one of its threads).

    Examples
    --------
    >>> set_threads(1); map_pool() is None
    True
    >>> set_threads(None)
    """
    k = get_threads()
    if k <= 1 or getattr(_worker, "inside", False):
        return None
    return _pool("map", k)


def in_background(fn: Callable) -> Future:
    """``fn()`` started on a thread of its own, at once: its
    :class:`~concurrent.futures.Future` (``result()`` waits for it and gives
    its value, or raises what it raised).  For work that may be needed later
    while this thread does other work (a thread is used whatever
    :func:`get_threads` says: the caller decides whether to start it).

    Examples
    --------
    >>> in_background(lambda: sum(range(10))).result()
    45
    """
    # a kept thread that is idle, else a new one (up to BACKGROUND at once)
    return _pool("background", BACKGROUND).submit(fn)
