"""uniform2d.optimize: the optimised mesh with exactly n Steiner points."""

import numpy as np
import pytest

import uniform2d
from uniform2d.optimize import OBJECTIVES, optimize_mesh, target_size

from invariants import check_mesh
from polygen import benchmark_polygons, convex, star, with_holes

BENCH = benchmark_polygons()


def _crit(q):
    return q.edge_ratio, q.longest_edge, q.max_perimeter


@pytest.mark.parametrize("name", sorted(BENCH))
def test_benchmark_n200_beats_tplus_on_all_three(name):
    p = BENCH[name]
    tp = uniform2d.tplus(p, 200)
    m = optimize_mesh(p, 200, start=tp)
    assert m.n_steiner == 200 and len(m.points) == len(p.vertices) + 200
    check_mesh(m.points, m.triangles, p)
    qa, qb = m.quality(), tp.quality()
    for a, b in zip(_crit(qa), _crit(qb)):
        assert a < b
    assert m.info["method"] == "uniform" and m.info["objective"] == "balanced"
    assert m.info["fallback"] is None


@pytest.mark.parametrize("objective", OBJECTIVES)
@pytest.mark.parametrize("seed", range(3))
def test_random_polygons_valid_exact_and_never_worse(objective, seed):
    rng = np.random.default_rng(1000 + seed)
    for p in (convex(rng), star(rng), with_holes(rng)):
        n = 150
        try:
            tp = uniform2d.tplus(p, n)
        except uniform2d.InsufficientPointsError:
            continue
        m = optimize_mesh(p, n, objective=objective, start=tp)
        assert m.n_steiner == n and len(m.points) == len(p.vertices) + n
        check_mesh(m.points, m.triangles, p)
        h = target_size(p, n)
        from uniform2d.optimize import objective_value

        qa, qb = m.quality(d_n=False), tp.quality(d_n=False)
        va = objective_value(objective, qa.longest_edge, qa.shortest_edge, qa.max_perimeter, h)
        vb = objective_value(objective, qb.longest_edge, qb.shortest_edge, qb.max_perimeter, h)
        assert va <= vb


def test_deterministic():
    p = BENCH["star10"]
    a = optimize_mesh(p, 300)
    b = optimize_mesh(p, 300)
    assert np.array_equal(a.points, b.points)
    assert np.array_equal(a.triangles, b.triangles)


def test_info_and_certificates():
    p = BENCH["square"]
    m = optimize_mesh(p, 200, objective="ratio")
    i = m.info
    for key in ("method", "objective", "d_n", "start", "before", "after", "relax_iterations"):
        assert key in i
    q = m.quality()
    assert q.longest_edge_bound.factor >= 1 and q.max_perimeter_bound.factor >= 1
    assert i["after"]["edge_ratio"] == pytest.approx(q.edge_ratio)


def test_bad_objective():
    with pytest.raises(ValueError):
        optimize_mesh(BENCH["square"], 50, objective="nope")
