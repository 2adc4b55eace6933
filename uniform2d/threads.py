"""How many threads the library's independent work runs on, and running it there.

The optimiser tries several starts of a mesh (:func:`uniform2d.optimize.moves.improve_best`),
each in its own kernel state: independent work, which runs on a pool of
threads (the compiled kernels release the GIL: ``nogil``, see
:mod:`uniform2d._kernel._jit`).  Results come back in the order of the items
and every item's work is the same whatever thread runs it, so a mesh is the
same, bit for bit, on any number of threads.

The count is, in order: what :func:`set_threads` set; the environment variable
``UNIFORM2D_THREADS``; the cores this process may run on.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from concurrent.futures import Future, ThreadPoolExecutor

from .errors import InvalidArgumentError

__all__ = ["ENV", "get_threads", "in_background", "set_threads", "thread_map"]

#: The environment variable read when :func:`set_threads` was not called.
ENV = "UNIFORM2D_THREADS"
_chosen: list = [None]


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
    threads; the first exception raised is raised here.

    Examples
    --------
    >>> thread_map(lambda x: x * x, range(5))
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    k = min(get_threads(), len(items))
    if k <= 1:
        return [fn(item) for item in items]
    with ThreadPoolExecutor(max_workers=k) as pool:
        return list(pool.map(fn, items))


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
    pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="uniform2d-background")
    try:
        return pool.submit(fn)
    finally:
        pool.shutdown(wait=False)  # the task still runs; the thread ends with it
