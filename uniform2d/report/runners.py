"""Running the cases: serially, in a local process pool, or on a Dask cluster.

All three return the results in case order, whatever order they finished in,
so the report never depends on where or when a case ran.
"""

from __future__ import annotations

import logging
import sys

from .._parallel import check_jobs, ordered_map
from .cases import run_case, warm_up

log = logging.getLogger(__name__)

__all__ = ["run_cases", "iter_cases"]


def _bar(total: int, progress: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc="cases", unit="case", file=sys.stderr, disable=not progress)


def run_cases(cases, *, jobs: int = 1, scheduler=None, progress: bool = False) -> list[dict]:
    """Every case's result, in the order of ``cases`` (see :func:`iter_cases`)."""
    return list(iter_cases(cases, jobs=jobs, scheduler=scheduler, progress=progress))


def iter_cases(cases, *, jobs: int = 1, scheduler=None, progress: bool = False):
    """Run every case (see :func:`uniform2d.report.cases.run_case`), yielding each
    result as soon as it and those before it are in.

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

    Yields
    ------
    dict
        Results, in the order of ``cases``.
    """
    check_jobs(jobs, scheduler)
    todo = [c for c in cases if c["status"] == "pending"]
    log.info("%d cases to run (%d not installed or not comparable)", len(todo), len(cases) - len(todo))
    with _bar(len(cases), progress) as bar:
        yield from ordered_map(run_case, cases, jobs=jobs, scheduler=scheduler,
                               initializer=warm_up, bar=bar)
