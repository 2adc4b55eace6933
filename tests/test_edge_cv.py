"""The edge CV lowered with the extremes held (uniform2d.optimize.edge_cv): a valid
constrained Delaunay mesh with exactly n points whose edge CV is lower and whose edge
ratio, longest edge, largest perimeter and worst angle are no worse; inputs left alone,
deterministic, the input back when nothing is gained, and the optimiser's last stage for
meshes of more than CV_STAGE_MIN points."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

import uniform2d
from support.jittered_mesh import jittered, measures
from uniform2d import Polygon
from uniform2d.io import read_polygon
from uniform2d.optimize import pipeline
from uniform2d.optimize.edge_cv import lower_edge_cv
from uniform2d.optimize.polish import polish_extremes
from uniform2d.sites import site_edges
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate

DATA = Path(__file__).resolve().parents[1] / "data" / "benchmarks"
LSHAPE = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def assert_better_cv(polygon, pts, tri, edges, p2, t2, info):
    """The stage's claim: a valid mesh of the same points, CV lower, nothing else worse."""
    nV = len(polygon.vertices)
    check_mesh(p2, t2, polygon, n_steiner=len(pts) - nV)
    assert len(p2) == len(pts)
    ratio0, long0, perim0, cv0, angle0 = measures(pts, tri)
    ratio1, long1, perim1, cv1, angle1 = measures(p2, t2)
    assert info["kept"]
    assert cv1 < cv0
    assert ratio1 <= ratio0 and long1 <= long0 and perim1 <= perim0 and angle1 >= angle0
    assert info["after"] == pytest.approx((ratio1, long1, perim1, cv1, angle1), rel=1e-12)
    # the polygon's vertices stay, exactly; the boundary sites on their own edges
    assert np.array_equal(p2[:nV], polygon.vertices)
    assert np.array_equal(site_edges(polygon, p2[nV:])[1], edges)


@pytest.fixture(scope="module")
def lowered():
    pts, tri, edges = jittered(LSHAPE, 0.1)
    copies = (pts.copy(), tri.copy(), edges.copy())
    p2, t2, info = lower_edge_cv(LSHAPE, pts, tri, edges)
    return pts, tri, edges, copies, p2, t2, info


def test_lowers_the_cv_of_a_jittered_mesh(lowered):
    pts, tri, edges, _, p2, t2, info = lowered
    assert_better_cv(LSHAPE, pts, tri, edges, p2, t2, info)
    # a jittered grid is far from even: the stage gains more than rounding
    assert info["after"][3] < 0.95 * info["before"][3]


@pytest.mark.parametrize("path, n", [("benchmarks/square2holes", 700), ("benchmarks/star10", 700),
                                     ("benchmarks/hexagon", 700), ("constrained/plate_zones", 700)])
def test_lowers_the_cv_of_optimised_meshes(path, n):
    # meshes of the optimiser below CV_STAGE_MIN (not lowered there): it still gains;
    # plate_zones has segments, whose sites slide along them
    polygon = read_polygon(DATA.parent / f"{path}.json")
    m = uniform2d.uniform_mesh(polygon, n)
    assert not m.info["cv_lowered"]
    _, edges = site_edges(polygon, m.points[len(polygon.vertices):])
    p2, t2, info = lower_edge_cv(polygon, m.points, m.triangles, edges)
    assert_better_cv(polygon, m.points, m.triangles, edges, p2, t2, info)


def test_inputs_are_not_modified(lowered):
    pts, tri, edges, (p0, t0, e0), *_ = lowered
    assert np.array_equal(pts, p0) and np.array_equal(tri, t0) and np.array_equal(edges, e0)


def test_deterministic_bytes(lowered):
    pts, tri, edges, _, p2, t2, _ = lowered
    p3, t3, _ = lower_edge_cv(LSHAPE, pts, tri, edges)
    digest = [hashlib.sha256(p.tobytes() + t.tobytes()).hexdigest() for p, t in ((p2, t2), (p3, t3))]
    assert digest[0] == digest[1]


def test_nothing_to_move_gives_the_input_back():
    # one site at the centre of a square: every edge of the mesh is an extreme (the
    # square's sides the longest, the spokes the shortest), so every point is held
    pts, tri = triangulate(SQUARE, [(0.5, 0.5)], [-1])
    p2, t2, info = lower_edge_cv(SQUARE, pts, tri, [-1])
    assert not info["kept"] and info["after"] == info["before"]
    assert np.array_equal(p2, pts) and np.array_equal(t2, tri)


@pytest.mark.parametrize("stage", [lower_edge_cv, polish_extremes])
def test_no_iterations_gives_the_input_back(stage):
    pts, tri, edges = jittered(SQUARE, 0.25, seed=1)
    p2, t2, info = stage(SQUARE, pts, tri, edges, iterations=0)
    assert not info["kept"]
    assert np.array_equal(p2, pts) and np.array_equal(t2, tri)


@pytest.fixture(scope="module")
def rect_raw():
    polygon = read_polygon(DATA / "rect4x1.json")
    return polygon, uniform2d.uniform_mesh(polygon, 300)


def test_uniform_mesh_lowers_the_cv_above_cv_stage_min(monkeypatch, rect_raw):
    # the optimiser's last stage for meshes of more than CV_STAGE_MIN points: lowered
    # here at 300 points by moving the threshold, against the same mesh without it
    polygon, raw = rect_raw
    with monkeypatch.context() as mp:
        mp.setattr(pipeline, "CV_STAGE_MIN", 0)
        m = uniform2d.uniform_mesh(polygon, 300)
    assert m.info["cv_lowered"] and not raw.info["cv_lowered"]
    check_mesh(m.points, m.triangles, polygon, n_steiner=300)
    assert m.n_steiner == 300 and len(m.points) == len(polygon.vertices) + 300
    before, after = measures(raw.points, raw.triangles), measures(m.points, m.triangles)
    assert after[3] < before[3]
    assert all(a <= b for a, b in zip(after[:3], before[:3])) and after[4] >= before[4]
    assert {k: v for k, v in m.info.items() if k not in ("cv_lowered", "after")} \
        == {k: v for k, v in raw.info.items() if k not in ("cv_lowered", "after")}


def test_uniform_mesh_leaves_meshes_above_cv_stage_max(monkeypatch, rect_raw):
    # beyond CV_STAGE_MAX points the mesh is the one made without the stage, bit for bit
    polygon, raw = rect_raw
    with monkeypatch.context() as mp:
        mp.setattr(pipeline, "CV_STAGE_MIN", 0)
        mp.setattr(pipeline, "CV_STAGE_MAX", len(raw.points) - 1)
        m = uniform2d.uniform_mesh(polygon, 300)
    assert not m.info["cv_lowered"]
    assert np.array_equal(m.points, raw.points) and np.array_equal(m.triangles, raw.triangles)
