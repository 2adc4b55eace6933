"""One way to run a function over many items: here, in local processes, or on a Dask cluster.

Used by the report (its cases) and the command line (its input files).  Results
come back in the order of the items, whatever order they finished in, so what a
caller writes never depends on where or when an item ran.
"""

from __future__ import annotations

import importlib.util
import multiprocessing
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Callable, Iterable, Iterator

from .errors import InvalidArgumentError

__all__ = ["Runner", "check_jobs", "ordered_map"]


def check_jobs(jobs: int, scheduler=None) -> None:
    """Refuse a ``jobs`` below 1, and a ``scheduler`` without the ``dask`` extra."""
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise InvalidArgumentError(f"jobs must be an integer of at least 1, got {jobs!r}")
    if scheduler is not None and importlib.util.find_spec("distributed") is None:
        raise ImportError("a Dask scheduler needs the 'dask' extra: pip install 'uniform2d[dask]'")


def _serial(fn, items, initializer):
    if initializer is not None:
        initializer()
    for i, item in enumerate(items):
        yield i, fn(item)


def _pool(fn, items, jobs, initializer):
    # spawn: no fork of a process that may hold gmsh/numba/thread state
    ctx = multiprocessing.get_context("spawn")
    ex = ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=initializer)
    try:
        yield from _submit(ex, fn, items)
    except BaseException:  # an interrupt or a failed worker: run nothing more
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    ex.shutdown()


def _dask(fn, items, scheduler, initializer):
    from distributed import Client
    from distributed import as_completed as dask_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    futures = []
    try:
        if initializer is not None:
            client.run(initializer)
        futures = client.map(fn, items, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        for fut in dask_completed(futures):
            yield index[fut.key], fut.result()
    except BaseException:  # an interrupt or a failed task: run nothing more
        if futures:
            client.cancel(futures)
        raise
    finally:
        if own:
            client.close()


def ordered_map(
    fn: Callable,
    items: Iterable,
    *,
    jobs: int = 1,
    scheduler=None,
    initializer: Callable | None = None,
    bar=None,
) -> Iterator:
    """``fn(item)`` for every item, yielded in the order of ``items``.

    Parameters
    ----------
    fn : callable
        A module-level function (local processes and Dask workers import it by
        name), taking one item; whatever it raises stops the map and is raised
        here, so a caller that wants to keep going catches inside ``fn``.
    jobs : int
        Local worker processes (1: run here, serially).
    scheduler : str or distributed.Client, optional
        Address of an existing Dask scheduler (``tcp://host:8786``) or a
        connected Client; overrides ``jobs``.  Needs the ``dask`` extra.
    initializer : callable, optional
        Run once in each process before its first item (e.g. loading the
        compiled kernels), so that no item's time includes it.
    bar : tqdm, optional
        Updated once per finished item, in the order they finish.
    """
    check_jobs(jobs, scheduler)
    items = list(items)
    if scheduler is not None:
        source = _dask(fn, items, scheduler, initializer)
    elif jobs > 1 and len(items) > 1:
        source = _pool(fn, items, min(jobs, len(items)), initializer)
    else:
        source = _serial(fn, items, initializer)
    yield from _in_order(source, bar)


def _in_order(source, bar) -> Iterator:
    """The values of ``source``'s ``(index, value)`` pairs, which come in the
    order they finish, yielded in index order."""
    done, following = {}, 0
    try:
        for i, value in source:
            if bar is not None:
                bar.update()
            done[i] = value
            while following in done:
                yield done.pop(following)
                following += 1
    finally:
        source.close()


class Runner:
    """Several :func:`ordered_map` calls on one set of workers: local processes
    started once (each loads the compiled kernels once), or one Dask client.

    Use as a context manager; :meth:`map` is :func:`ordered_map` on these
    workers.  A scheduler given as an address is connected on entry and
    closed on exit; a client is used as it is.

    Examples
    --------
    >>> with Runner() as run:
    ...     list(run.map(abs, [-1, 2])), list(run.map(str, [3]))
    ([1, 2], ['3'])
    """

    def __init__(self, jobs: int = 1, scheduler=None):
        check_jobs(jobs, scheduler)
        self.jobs, self.scheduler = jobs, scheduler
        self._pool = None
        self._client = None

    def __enter__(self):
        if self.scheduler is not None:
            from distributed import Client

            own = not isinstance(self.scheduler, Client)
            self._client = (Client(self.scheduler) if own else self.scheduler, own)
        return self

    def __exit__(self, kind, *rest) -> None:
        if self._pool is not None:
            # an interrupt or a failed item: run nothing more
            self._pool.shutdown(wait=kind is None, cancel_futures=kind is not None)
            self._pool = None
        if self._client is not None and self._client[1]:
            self._client[0].close()
        self._client = None

    def _source(self, fn, items):
        if self._client is not None:
            return _dask(fn, items, self._client[0], None)
        if self.jobs > 1 and len(items) > 1:
            if self._pool is None:
                ctx = multiprocessing.get_context("spawn")
                self._pool = ProcessPoolExecutor(max_workers=self.jobs, mp_context=ctx)
            return _submit(self._pool, fn, items)
        return _serial(fn, items, None)

    def map(self, fn: Callable, items: Iterable, bar=None) -> Iterator:
        """``fn(item)`` for every item, yielded in the order of ``items``
        (:func:`ordered_map`'s arguments)."""
        items = list(items)
        yield from _in_order(self._source(fn, items), bar)


def _submit(ex, fn, items):
    futures = {ex.submit(fn, item): i for i, item in enumerate(items)}
    try:
        for fut in as_completed(futures):
            yield futures[fut], fut.result()
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
