"""Successive halving's rounds of trials, on threads, without a wait between rounds.

:func:`uniform2d.optimize.moves.improve_best` runs its starts through a plan of
trials: every start the first, the best of them the next, and so on.  Run
round by round, each round waits for its slowest start while the other
threads idle (five starts on two threads: the third pair is one start), and
the serial schedule of the winner waits for the last round.  Here a start's
next trial is started as soon as the start is certain to be among those that
run it: when fewer than that many starts of its round are better or still
running.  The trials are the same, on the same states, ranked by the same
values: the same winner and the same mesh on any number of threads; only the
order in which the threads run them changes.
"""

from __future__ import annotations

from concurrent.futures import FIRST_COMPLETED, wait

from ..threads import map_pool

__all__ = ["run_plan"]


def run_plan(plan, alive: list, trial, report=None) -> list:
    """The starts of ``alive`` (``(index, state, progress)``) after the
    trials of ``plan`` (``(schedule, how many run it, resumed)``, as
    :func:`~uniform2d.optimize.moves._trial_plan` makes it), best first: those
    that ran the last trial.  ``trial(entry, sched, resumed)`` runs one trial,
    returning ``(rank, index, state, progress)`` (lower rank better, the index
    breaking ties).  ``report(done, total)``: after each round, as when the
    rounds run in turn.  On one thread, or from a thread of
    :func:`~uniform2d.threads.thread_map`'s, the rounds run in turn here."""
    sizes = []
    for _, size, _ in plan:
        sizes.append(min(size, sizes[-1] if sizes else len(alive)))
    total = sum(size for _, size, _ in plan)
    pool = map_pool()
    if pool is None or len(alive) <= 1:
        done = 0
        for (sched, _, resumed), size in zip(plan, sizes):
            scored = sorted((trial(a, sched, resumed) for a in alive[:size]), key=_key)
            done += size
            if report is not None:
                report(done, total)
            alive = [r[1:] for r in scored]
        return alive
    return _eager(plan, sizes, alive, trial, pool, report, total)


def _key(r):
    return r[:2]


def _eager(plan, sizes, alive, trial, pool, report, total):
    """:func:`run_plan` on ``pool``'s threads (see the module docstring)."""
    results = [{} for _ in plan]  # round -> {start index: trial result}
    started = [set() for _ in plan]
    running = {}

    def start(k, entry):
        sched, _, resumed = plan[k]
        running[pool.submit(trial, entry, sched, resumed)] = k
        started[k].add(entry[0])

    for entry in alive[:sizes[0]]:
        start(0, entry)
    rounds_reported, done = 0, 0
    try:
        while running:
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for f in finished:
                k = running.pop(f)
                r = f.result()
                results[k][r[1]] = r
            for k in range(rounds_reported, len(plan) - 1):
                ranked = sorted(results[k].values(), key=_key)
                pending = sizes[k] - len(ranked)
                for place, r in enumerate(ranked):
                    # fewer than sizes[k + 1] starts can end before it: it runs the next
                    if place + pending < sizes[k + 1] and r[1] not in started[k + 1]:
                        start(k + 1, r[1:])
            while rounds_reported < len(plan) and len(results[rounds_reported]) == \
                    sizes[rounds_reported]:
                done += sizes[rounds_reported]
                if rounds_reported < len(plan) - 1:
                    # its survivors run the next round already: the losers' states go
                    results[rounds_reported] = {}
                rounds_reported += 1
                if report is not None:
                    report(done, total)
    except BaseException:  # an interrupt or a trial's exception: start no more of them
        for f in running:
            f.cancel()
        wait(running)
        raise
    return [r[1:] for r in sorted(results[-1].values(), key=_key)]
