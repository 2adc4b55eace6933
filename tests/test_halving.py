"""Successive halving's rounds without a wait between them
(uniform2d.optimize.halving.run_plan): on two threads, with trials
that end in another order than they started, the same survivors in the same
order, every start having run the same trials, and the same progress reports
as the rounds run in turn on one thread; a trial's exception is raised."""

from __future__ import annotations

import time

import numpy as np
import pytest

from uniform2d.optimize.halving import run_plan
from uniform2d.optimize.moves import _trial_plan
from uniform2d.optimize import schedule as S
from uniform2d.threads import set_threads


def _run(threads: int, seed: int, starts: int, keep):
    rng = np.random.default_rng(seed)
    ranks = rng.random((starts, 4)).round(1)  # ties: the index decides
    pause = rng.random((starts, 4)) * 2e-3

    def trial(entry, sched, resumed):
        i, state, progress = entry
        k = len(state)
        time.sleep(pause[i, k])
        state.append((sched, resumed))
        return float(ranks[i, k]), i, state, progress + 1

    plan = _trial_plan(starts, keep, S.PRUNE_ROUNDS_LARGE, S.PRUNE_SPARE_LARGE)
    reports = []
    set_threads(threads)
    try:
        out = run_plan(plan, [(i, [], 0) for i in range(starts)], trial,
                       lambda done, total: reports.append((done, total)))
    finally:
        set_threads(None)
    return out, reports


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("starts, keep", [(12, S.KEEP_LARGE), (12, S.KEEP), (7, S.KEEP), (2, S.KEEP)])
def test_same_survivors_as_in_turn(seed, starts, keep):
    one, rep1 = _run(1, seed, starts, keep)
    assert [i for i, _, _ in one] and rep1[-1][0] == rep1[-1][1]
    for threads in (2,):  # the kept pool of two (another size would start threads of its own)
        many, rep = _run(threads, seed, starts, keep)
        assert [(i, s, p) for i, s, p in many] == [(i, s, p) for i, s, p in one]
        assert rep == rep1


def test_a_trial_exception_is_raised():
    def trial(entry, sched, resumed):
        if entry[0] == 3:
            raise ValueError("trial 3")
        time.sleep(1e-3)
        return 0.0, entry[0], entry[1], entry[2]

    plan = _trial_plan(6, S.KEEP)
    set_threads(2)
    try:
        with pytest.raises(ValueError, match="trial 3"):
            run_plan(plan, [(i, None, 0) for i in range(6)], trial)
    finally:
        set_threads(None)
