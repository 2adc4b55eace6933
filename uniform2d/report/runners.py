"""Running the cases: serially, in a local process pool, or on a Dask cluster.

All three return the results in case order, whatever order they finished in,
so the report never depends on where or when a case ran.
"""

from __future__ import annotations

import importlib.util
import logging
import multiprocessing
import sys
from concurrent.futures import ProcessPoolExecutor, as_completed

from ..errors import InvalidArgumentError
from .cases import run_case, warm_up

log = logging.getLogger(__name__)

__all__ = ["run_cases"]


def _bar(total: int, progress: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc="cases", unit="case", file=sys.stderr, disable=not progress)


def _serial(cases, bar):
    warm_up()
    out = []
    for case in cases:
        bar.set_postfix_str(case["id"], refresh=False)
        out.append(run_case(case))
        bar.update()
    return out


def _pool(cases, jobs, bar):
    out = [None] * len(cases)
    # spawn: no fork of a process that may hold gmsh/numba/thread state
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=ctx, initializer=warm_up) as ex:
        futures = {ex.submit(run_case, c): i for i, c in enumerate(cases)}
        for fut in as_completed(futures):
            out[futures[fut]] = fut.result()
            bar.update()
    return out


def _dask(cases, scheduler, bar):
    from distributed import Client
    from distributed import as_completed as dask_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        client.run(warm_up)
        futures = client.map(run_case, cases, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        out = [None] * len(cases)
        for fut in dask_completed(futures):
            out[index[fut.key]] = fut.result()
            bar.update()
        return out
    finally:
        if own:
            client.close()


def run_cases(cases, *, jobs: int = 1, scheduler=None, progress: bool = False) -> list[dict]:
    """Run every case (see :func:`uniform2d.report.cases.run_case`).

    Parameters
    ----------
    cases : list of dict
        From :func:`uniform2d.report.cases.plan`.
    jobs : int
        Local worker processes (1: run here, serially).
    scheduler : str or distributed.Client, optional
        Address of an existing Dask scheduler (``tcp://host:8786``) or a
        connected Client; overrides ``jobs``.  Needs the ``dask`` extra.
    progress : bool
        Show a tqdm bar over cases on stderr.

    Returns
    -------
    list of dict
        Results, in the order of ``cases``.
    """
    if jobs < 1:
        raise InvalidArgumentError(f"jobs must be at least 1, got {jobs}")
    todo = [c for c in cases if c["status"] != "not installed"]
    log.info("%d cases to run (%d not installed)", len(todo), len(cases) - len(todo))
    with _bar(len(cases), progress) as bar:
        if scheduler is not None:
            if importlib.util.find_spec("distributed") is None:
                raise ImportError(
                    "--scheduler needs the 'dask' extra: pip install 'uniform2d[dask]'"
                )
            results = _dask(cases, scheduler, bar)
        elif jobs > 1 and len(cases) > 1:
            results = _pool(cases, min(jobs, len(cases)), bar)
        else:
            results = _serial(cases, bar)
    return results
