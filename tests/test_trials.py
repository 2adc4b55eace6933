"""The optimiser's trials (uniform2d.optimize.moves.improve_best): the first trial's
spring rounds split at schedule.PRUNE_ROUNDS, the starts ranked after the first part.

The split relies on a spring run going on where it stopped, bit for bit; the
reference is one run of all the rounds on a second copy of the same start.
"""

import hashlib
from pathlib import Path

import numpy as np
import pytest
from support.benchmarks import benchmark_polygons

import uniform2d
from uniform2d.optimize import schedule as S
from uniform2d.optimize.boundary import target_size
from uniform2d._kernel.descent import GAIN, PATIENCE
from uniform2d.optimize.moves import KernelMesh, Progress, _trial_plan, default_schedule
from uniform2d.optimize.objective import objective_code
from uniform2d.optimize.seed import start, variants
from uniform2d.testing import check_mesh

BENCH = benchmark_polygons()
BENCH_DIR = Path(__file__).resolve().parents[1] / "data" / "benchmarks"
OBJ = objective_code("balanced")


def _digest(m) -> str:
    return hashlib.sha256(m.points.tobytes() + m.triangles.tobytes()).hexdigest()


@pytest.mark.parametrize("name, n", [("star10", 200), ("square2holes", 3000)])
def test_spring_rounds_in_two_parts_are_the_rounds_in_one(name, n):
    # square2holes at 3000: deep lattice points frozen (the kernel's restricted passes)
    p = BENCH[name]
    h = target_size(p, n)
    sites, edges, frozen, _ = start(p, n, h, variants(p, n)[0])
    one = KernelMesh.built(p, sites, href=h, frozen=frozen, edges=edges)
    two = KernelMesh.built(p, sites, href=h, frozen=frozen, edges=edges)
    whole = S.TRIALS[0]
    run1 = one.advance(whole, OBJ)
    run2 = two.advance(whole._replace(spring_rounds=S.PRUNE_ROUNDS), OBJ)
    assert run2.spring_rounds == S.PRUNE_ROUNDS
    run2 = two.advance(whole._replace(spring_rounds=whole.spring_rounds - S.PRUNE_ROUNDS), OBJ,
                       run2)
    assert run1 == run2
    assert np.array_equal(one.xy, two.xy)
    assert one.rank(OBJ) == two.rank(OBJ)


def test_trial_plan_splits_the_first_trial_only_where_it_leaves_starts_out():
    plan = _trial_plan(12, S.KEEP_LARGE)
    assert [size for _, size, _ in plan] == [12, 5 + S.PRUNE_SPARE, 5, 3]
    large = _trial_plan(12, S.KEEP_LARGE, S.PRUNE_ROUNDS_LARGE)
    assert [(sched.spring_rounds, resumed) for sched, _, resumed in large[:2]] == [
        (S.PRUNE_ROUNDS_LARGE, 0), (S.TRIALS[0].spring_rounds - S.PRUNE_ROUNDS_LARGE,
                                    S.PRUNE_ROUNDS_LARGE)]
    assert [(sched, size) for sched, size, _ in _trial_plan(12, S.KEEP_LARGE, 0)] == list(
        zip(S.TRIALS, [12, 5, 3]))  # 0: no split
    # one fraction for every trial (meshes of up to KEEP_MAX points)
    assert [size for _, size, _ in _trial_plan(12, S.KEEP)] == [12, 8 + S.PRUNE_SPARE, 8, 6]
    assert plan[0][0].spring_rounds + plan[1][0].spring_rounds == S.TRIALS[0].spring_rounds
    assert plan[1][2] == S.PRUNE_ROUNDS and plan[0][2] == 0
    assert [sched for sched, _, _ in plan[2:]] == list(S.TRIALS[1:])
    # two starts, one goes on: nothing to leave out
    assert [(sched, size) for sched, size, _ in _trial_plan(2, S.KEEP_LARGE)] == list(
        zip(S.TRIALS, [2, 1, 1]))
    # no spare (large meshes): the split keeps what the next trial takes, and
    # never decides between two starts on the split's rounds alone
    spare = S.PRUNE_SPARE_LARGE
    assert [size for _, size, _ in _trial_plan(12, S.KEEP_LARGE, 5, spare)] == [12, 5 + spare, 5, 3]
    assert [size for _, size, _ in _trial_plan(2, S.KEEP_LARGE, 5, 0)] == [2, 1, 1]
    assert [size for _, size, _ in _trial_plan(3, S.KEEP_LARGE, 5, 0)] == [3, 2, 2, 2]


@pytest.mark.parametrize("name, n", [("star10", 200), ("rect4x1", 1000)])
def test_split_first_trial_finishes_the_same_mesh(name, n, monkeypatch):
    # star10 at 200: its winner ranks seventh of 12 after 10 spring rounds;
    # rect4x1 at 1000: fifth (the most of the benchmark polygons at that size)
    p = BENCH[name]
    pruned = uniform2d.uniform_mesh(p, n)
    check_mesh(pruned.points, pruned.triangles, p)
    monkeypatch.setattr(S, "PRUNE_ROUNDS", 0)
    monkeypatch.setattr(S, "PRUNE_ROUNDS_LARGE", 0)
    whole = uniform2d.uniform_mesh(p, n)
    assert _digest(pruned) == _digest(whole)


@pytest.mark.parametrize("name, n", [("rect4x1", 1000), ("star10", 1000)])
def test_narrower_trials_of_large_meshes_keep_the_winner(name, n, monkeypatch):
    # rect4x1 at 1000: its winner ranks fifth of 12 after 10 spring rounds and
    # fourth after the spring trial; star10 at 1000: third after the p = 8 one
    # (the most of the benchmark polygons): KEEP_LARGE's 6, 5 and 3 starts keep
    # it, the same mesh as with half of the starts going on after each trial
    from fractions import Fraction

    p = BENCH[name]
    narrow = uniform2d.uniform_mesh(p, n)
    check_mesh(narrow.points, narrow.triangles, p)
    assert len(narrow.points) == len(p.vertices) + n
    monkeypatch.setattr(S, "KEEP_LARGE", Fraction(1, 2))
    half = uniform2d.uniform_mesh(p, n)
    assert _digest(narrow) == _digest(half)


def test_a_start_whose_spring_stopped_runs_no_more_rounds():
    p = BENCH["square"]
    n = 100
    h = target_size(p, n)
    sites, edges, frozen, _ = start(p, n, h, variants(p, n)[0])
    st = KernelMesh.built(p, sites, href=h, frozen=frozen, edges=edges)
    from uniform2d.optimize.moves import _trial

    stopped = Progress(3, 0, None)  # its spring stopped after 3 of the rounds asked
    before = st.xy.copy()
    _, _, _, run = _trial((0, st, stopped), S.TRIALS[0], OBJ, resumed=S.PRUNE_ROUNDS)
    assert run == stopped
    assert np.array_equal(st.xy, before)


def test_starts_sharing_their_rows_leave_them_as_they_were():
    # the two lattice edges' starts of one spacing share start_parts (made once,
    # read by both, on threads): each start is the one made alone, the parts unchanged
    from uniform2d.io import read_polygon
    from uniform2d.optimize.seed import start_parts

    plate = read_polygon(str(BENCH_DIR.parent / "plate_bolts.json"))
    n = 500 - len(plate.vertices)
    h = target_size(plate, n)
    tried = variants(plate, n)
    assert len({v[1] for v in tried}) == 2
    for spacing, edge, layered in tried[-2:]:
        parts = start_parts(plate, n, h, spacing, layered, True)
        before = [None if a is None else a.copy() for a in parts]
        alone = start(plate, n, h, (spacing, edge, layered), True)
        shared = start(plate, n, h, (spacing, edge, layered), True, shared=parts)
        for x, y in zip(alone, shared):
            assert np.array_equal(x, y)
        for x, y in zip(parts, before):
            assert (x is None and y is None) or np.array_equal(x, y)


def test_the_winner_of_a_medium_mesh_goes_on_with_the_medium_schedule(monkeypatch):
    # above MEDIUM points the winner of the trials goes on with SCHEDULE_MEDIUM
    # (a shorter second spring run); improve() and smaller meshes keep SCHEDULE
    assert S.schedule_for(S.MEDIUM + 1, False, winner=True) == S.SCHEDULE_MEDIUM
    assert S.schedule_for(S.MEDIUM, False, winner=True) == S.SCHEDULE
    assert S.schedule_for(S.SMALL, False, winner=True) == S.SCHEDULE_MEDIUM
    # above SMALL, SCHEDULE's stages with a shorter spread stage
    assert S.schedule_for(S.SMALL + 1, False, winner=True) == S.SCHEDULE_BIG
    assert S.schedule_for(S.LARGE, False, winner=True) == S.SCHEDULE_BIG
    assert S.SCHEDULE_BIG._replace(stages=()) == S.SCHEDULE._replace(
        spread_sweeps=S.SCHEDULE_BIG.spread_sweeps)
    assert S.SCHEDULE_BIG.spread_sweeps < S.SCHEDULE.spread_sweeps
    # ... whose stages run as many sweeps at most, but stop sooner on a slow creep
    for k in S.SCHEDULE_BIG.exponents:
        stage = S.SCHEDULE_BIG.stage(k)
        assert stage.sweeps == S.SCHEDULE.sweeps and stage.patience < PATIENCE
        assert stage.gain is None or stage.gain > GAIN
    assert S.schedule_for(S.SMALL + 1, False) == S.SCHEDULE
    assert S.schedule_for(S.MEDIUM + 1, False) == S.SCHEDULE
    assert S.schedule_for(S.MEDIUM + 1, True, winner=True) == S.SCHEDULE_GRADED
    assert S.schedule_for(S.LARGE + 1, False, winner=True) == S.SCHEDULE_LARGE
    assert S.SCHEDULE_MEDIUM.spring_rounds < S.SCHEDULE.spring_rounds
    p = BENCH["lshape"]
    n = S.MEDIUM + 100
    medium = uniform2d.uniform_mesh(p, n)
    check_mesh(medium.points, medium.triangles, p)
    assert len(medium.points) == len(p.vertices) + n
    trials = S.TRIALS[0].spring_rounds
    assert medium.info["relax_iterations"] <= trials + S.SCHEDULE_MEDIUM.spring_rounds
    monkeypatch.setattr(S, "MEDIUM", 10**9)  # the full schedule after all
    full = uniform2d.uniform_mesh(p, n)
    check_mesh(full.points, full.triangles, p)
    assert medium.info["relax_iterations"] < full.info["relax_iterations"]
    assert _digest(medium) != _digest(full)


def test_a_stage_keeps_its_own_limits():
    # Stage(sweeps, patience, gain): at most ``sweeps``; with gain 1 no sweep can
    # lower the objective by the whole of it, so the stage ends after exactly
    # ``patience`` sweeps (each lowering the objective or not: square2holes at
    # 3000 still moves after the spring rounds)
    p = BENCH["square2holes"]
    n = 3000
    h = target_size(p, n)
    sites, edges, frozen, _ = start(p, n, h, variants(p, n)[0])
    made = {}
    for stage in (S.Stage(3), S.Stage(25, 2, 1.0), S.Stage(25, 4, 1.0)):
        st = KernelMesh.built(p, sites, href=h, frozen=frozen, edges=edges)
        st.advance(S.Schedule(20, 0, (), 0), OBJ)
        sched = S.Schedule(0, 25, (5,), 0, stages=((5, stage),))
        made[stage] = st.advance(sched, OBJ).sweeps
    assert made == {S.Stage(3): 3, S.Stage(25, 2, 1.0): 2, S.Stage(25, 4, 1.0): 4}
    # a stage the schedule does not name: its sweeps and the kernel's rule
    assert S.Schedule(0, 25, (5, 6), 0, stages=((5, S.Stage(3)),)).stage(6) == S.Stage(25)
    # a caller's sweeps hold for every stage
    big = default_schedule(S.SMALL + 1, False, True, sweeps=10)
    assert big.stages == () and big.stage(5) == S.Stage(10)
