"""The graded path's last stage (uniform2d.optimize.variance.lower_variance): it lowers the
CV of q = length / h(midpoint) with exactly n points and a valid constrained Delaunay mesh,
max q / min q not grown, the input kept when it cannot do better, and the uniform path
never runs it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import uniform2d
from uniform2d import Polygon, SizeField, read_polygon
from uniform2d import graded
from uniform2d.geometry import polygon_edges
from uniform2d.optimize import variance
from uniform2d.optimize.variance import lbfgs, lower_variance
from uniform2d.refine import refine
from uniform2d.relative import relative_measures
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

DATA = Path(__file__).resolve().parents[1] / "data"
SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
LSHAPE = Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])


def corner(p):
    return 0.02 + 0.6 * np.hypot(p[:, 0], p[:, 1])


def without_stage(monkeypatch, polygon, n, size):
    with monkeypatch.context() as mp:
        mp.setattr(graded, "VARIANCE_ITERATIONS", 0)
        return uniform2d.uniform_mesh(polygon, n, size=size)


@pytest.mark.parametrize("case", ["lshape", "plate"])
def test_stage_lowers_cv_of_q(monkeypatch, case):
    if case == "lshape":
        P, n, h = LSHAPE, 300, corner
    else:
        P = read_polygon(DATA / "plate_bolts.json")
        n, h = 400, refine(P, "holes", ratio=0.25)
    before = without_stage(monkeypatch, P, n, h)
    after = uniform2d.uniform_mesh(P, n, size=h)
    for m in (before, after):
        check_mesh(m.points, m.triangles, P, n_steiner=n)
        assert len(m.points) == len(P.vertices) + n
    assert after.info["variance_stage"] and not before.info["variance_stage"]
    rb = relative_measures(before.points, before.triangles, before.size)
    ra = relative_measures(after.points, after.triangles, after.size)
    assert ra.q_cv < 0.99 * rb.q_cv
    assert ra.q_ratio <= rb.q_ratio * (1 + variance.RATIO_SLACK)
    # the polygon's vertices stay, exactly
    assert np.array_equal(after.points[: len(P.vertices)], P.vertices)


def test_direct_call_keeps_boundary_sites_on_their_edges():
    f = SizeField([0, 1], [0, 1], [[0.1, 0.15], [0.1, 0.15]])
    # a jittered triangular lattice of spacing 0.125 and points on the four sides
    rng = np.random.default_rng(5)
    gy, gx = np.mgrid[1:8, 1:8] * 0.125
    inner = np.c_[(gx + 0.0625 * (np.arange(7)[:, None] % 2)).ravel(), gy.ravel()]
    inner = inner[inner[:, 0] < 0.95] + rng.uniform(-0.02, 0.02, (len(inner[inner[:, 0] < 0.95]), 2))
    t = np.arange(1, 8) * 0.125
    z, o = np.zeros(7), np.ones(7)
    on = np.concatenate([np.c_[t, z], np.c_[o, t], np.c_[1 - t, o], np.c_[z, 1 - t]])
    sites = np.concatenate([inner, on])
    k = len(inner)
    edges = np.r_[np.full(k, -1), np.repeat([0, 1, 2, 3], 7)]
    pts, tri = triangulate(SQUARE, sites, edges)
    pts0, tri0 = pts.copy(), tri.copy()
    p2, t2, info = lower_variance(SQUARE, pts, tri, edges, f)
    assert np.array_equal(pts, pts0) and np.array_equal(tri, tri0)  # inputs not mutated
    assert info["kept"] and info["cv"][1] < 0.9 * info["cv"][0]
    check_mesh(p2, t2, SQUARE, n_steiner=len(sites))
    r0, r2 = relative_measures(pts, tri, f), relative_measures(p2, t2, f)
    assert r2.q_cv == pytest.approx(info["cv"][1]) and r2.q_cv < r0.q_cv
    assert r2.q_ratio <= r0.q_ratio * (1 + variance.RATIO_SLACK)
    a, d, _ = polygon_edges(SQUARE, constraints=True)
    for j, e in enumerate(edges[k:]):
        p = p2[len(SQUARE.vertices) + k + j]
        cross = (p[0] - a[e][0]) * d[e][1] - (p[1] - a[e][1]) * d[e][0]
        assert abs(cross) < 1e-12 and 0 < np.dot(p - a[e], d[e]) < np.dot(d[e], d[e])


def test_nothing_gained_returns_the_input():
    f = SizeField([0, 1], [0, 1], [[0.1, 0.3], [0.1, 0.3]])
    pts, tri = triangulate(SQUARE, [(0.3, 0.3), (0.4, 0.7), (0.7, 0.5)])
    p2, t2, info = lower_variance(SQUARE, pts, tri, [-1, -1, -1], f, iterations=0)
    assert not info["kept"] and p2 is not pts and np.array_equal(p2, pts)
    assert np.array_equal(t2, tri) and info["cv"][0] == info["cv"][1]


def test_lbfgs_minimises_a_quadratic():
    A = np.diag([1.0, 10.0, 100.0])
    x, made = lbfgs(lambda x: (0.5 * x @ A @ x - x.sum(), A @ x - 1.0), np.zeros(3), 200)
    assert np.allclose(x, 1.0 / np.diag(A), rtol=1e-6) and made <= 200


def test_lbfgs_stops_where_the_curvature_underflows():
    """At this scale the gradient change's square underflows (y . y = 0 with
    s . y > 0): the next direction's scaling is undefined, and the run stops at
    the point reached instead of dividing by zero (a 6-point mesh of the
    constrained fuzz corpus met it in the polish)."""
    x0 = np.array([1.0, -2.0, 0.5])
    x, made = lbfgs(lambda x: (1e-200 * (x @ x), 2e-200 * x), x0, 50)
    assert np.all(np.isfinite(x)) and 1 <= made <= 50
    assert x @ x < x0 @ x0


def test_uniform_path_never_runs_the_stage(monkeypatch):
    def boom(*a, **k):
        raise AssertionError("the uniform path ran the variance stage")

    monkeypatch.setattr(graded, "lower_variance", boom)
    m = uniform2d.uniform_mesh(SQUARE, 60)
    assert m.info["method"] != "graded" and "variance_stage" not in m.info
    with pytest.raises(AssertionError, match="variance stage"):
        uniform2d.uniform_mesh(SQUARE, 60, size=corner)
