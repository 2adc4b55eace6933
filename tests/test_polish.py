"""The polish of a uniform mesh (uniform2d.optimize.polish): it lowers the edge ratio,
longest edge and largest perimeter with exactly n points and a valid constrained Delaunay
mesh, never raises any of them or the edge CV nor lowers the worst angle, leaves its inputs
alone, is deterministic, gives the input back when it cannot gain, and is the optimiser's
last stage for small meshes."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import uniform2d
from support.jittered_mesh import jittered, measures
from uniform2d import Polygon
from uniform2d.errors import InvalidArgumentError
from uniform2d.optimize import pipeline
from uniform2d.optimize.polish import polish_extremes, polish_mesh
from uniform2d.sites import site_edges
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

LSHAPE = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


@pytest.fixture(scope="module")
def polished():
    pts, tri, edges = jittered(LSHAPE, 0.2)
    copies = (pts.copy(), tri.copy(), edges.copy())
    p2, t2, info = polish_extremes(LSHAPE, pts, tri, edges)
    return pts, tri, edges, copies, p2, t2, info


def test_lowers_the_longest_edge_and_the_largest_perimeter(polished):
    pts, tri, edges, _, p2, t2, info = polished
    k = len(pts) - len(LSHAPE.vertices)
    check_mesh(p2, t2, LSHAPE, n_steiner=k)
    assert len(p2) == len(pts)
    ratio0, long0, perim0, cv0, angle0 = measures(pts, tri)
    ratio1, long1, perim1, cv1, angle1 = measures(p2, t2)
    assert info["kept"]
    assert long1 < 0.99 * long0 and perim1 < 0.99 * perim0
    assert ratio1 <= ratio0 and cv1 <= cv0 and angle1 >= angle0
    assert info["after"] == pytest.approx((ratio1, long1, perim1, cv1, angle1), rel=1e-12)
    # the polygon's vertices stay, exactly; the boundary sites on their own edges
    assert np.array_equal(p2[: len(LSHAPE.vertices)], LSHAPE.vertices)
    assert np.array_equal(site_edges(LSHAPE, p2[len(LSHAPE.vertices):])[1], edges)


def test_inputs_are_not_modified(polished):
    pts, tri, edges, (p0, t0, e0), *_ = polished
    assert np.array_equal(pts, p0) and np.array_equal(tri, t0) and np.array_equal(edges, e0)


def test_deterministic_bytes(polished):
    pts, tri, edges, _, p2, t2, _ = polished
    p3, t3, _ = polish_extremes(LSHAPE, pts, tri, edges)
    digest = [hashlib.sha256(p.tobytes() + t.tobytes()).hexdigest() for p, t in ((p2, t2), (p3, t3))]
    assert digest[0] == digest[1]


def test_nothing_to_gain_gives_the_input_back():
    # one site at the centre of a square: the longest edges are the square's own
    # and the four perimeters equal, at their least where the site is
    pts, tri = triangulate(SQUARE, [(0.5, 0.5)], [-1])
    p2, t2, info = polish_extremes(SQUARE, pts, tri, [-1])
    assert not info["kept"] and info["after"] == info["before"]
    assert np.array_equal(p2, pts) and np.array_equal(t2, tri)


def test_uniform_mesh_polishes_small_meshes(monkeypatch):
    # the optimiser's last stage for meshes of up to POLISH_MAX points is polish_mesh's
    with monkeypatch.context() as mp:
        mp.setattr(pipeline, "POLISH_MAX", 0)
        raw = uniform2d.uniform_mesh(LSHAPE, 200)
    m = uniform2d.uniform_mesh(LSHAPE, 200)
    assert m.info["polished"] and not raw.info["polished"]
    check_mesh(m.points, m.triangles, LSHAPE, n_steiner=200)
    assert m.n_steiner == 200 and len(m.points) == len(LSHAPE.vertices) + 200
    before, after = measures(raw.points, raw.triangles), measures(m.points, m.triangles)
    assert all(a <= b for a, b in zip(after[:4], before[:4])) and after[4] >= before[4]
    assert after[2] < before[2]
    p = polish_mesh(raw)
    assert p.info["polish"]["kept"]
    assert np.array_equal(p.points, m.points) and np.array_equal(p.triangles, m.triangles)
    assert {k: v for k, v in p.info.items() if k != "polish"} == raw.info


def test_polish_mesh_refuses_a_graded_mesh():
    m = uniform2d.uniform_mesh(SQUARE, 80, size=lambda q: 0.05 + 0.2 * q[:, 0])
    with pytest.raises(InvalidArgumentError, match="size field"):
        polish_mesh(m)
