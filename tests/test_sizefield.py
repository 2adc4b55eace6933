"""INSERT with a size field: a constant one is the paper's algorithm exactly; a graded
one ranks candidates by distance / h, stays a valid CDT and places points densely
where h is small."""

import numpy as np
import pytest

import uniform2d
from uniform2d.testing import check_mesh
from support.benchmarks import benchmark_polygons
from uniform2d.testing.polygons import with_holes
from uniform2d import Polygon, SizeField

SQUARE = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def test_sizefield_interpolates_and_validates():
    f = SizeField([0, 2], [0, 1], [[1.0, 3.0], [1.0, 3.0]])
    assert np.allclose(f([[1.0, 0.5], [0.0, 0.0], [5.0, 9.0]]), [2.0, 1.0, 3.0])
    with pytest.raises(ValueError, match="strictly increasing"):
        SizeField([0, 0], [0, 1], np.ones((2, 2)))
    with pytest.raises(ValueError, match="shape"):
        SizeField([0, 1], [0, 1], np.ones((3, 2)))
    with pytest.raises(ValueError, match="positive"):
        SizeField([0, 1], [0, 1], [[1.0, 0.0], [1.0, 1.0]])
    with pytest.raises(TypeError, match="SizeField"):
        uniform2d.insert(SQUARE, 5, size="small")
    with pytest.raises(ValueError, match="positive"):
        uniform2d.insert(SQUARE, 5, size=-1.0)


@pytest.mark.parametrize("name", ["hexagon", "lshape", "square2holes"])
def test_constant_size_is_the_paper_algorithm(name):
    P = benchmark_polygons()[name]
    a = uniform2d.insert(P, 150)
    b = uniform2d.insert(P, 150, size=0.37)
    c = uniform2d.insert(P, 150, size=SizeField.constant(P.bounds, 2.0))
    for r in (b, c):
        assert r.points.tobytes() == a.points.tobytes()
        assert r.weights.tobytes() == a.weights.tobytes()
        assert r.triangles.tobytes() == a.triangles.tobytes()


def _graded(P):
    x0, y0, x1, y1 = P.bounds
    w = max(x1 - x0, y1 - y0)
    return SizeField([x0, x1], [y0, y1], [[0.1 * w, 0.5 * w], [0.1 * w, 0.5 * w]])


@pytest.mark.parametrize("seed", range(4))
def test_graded_field_orders_by_distance_over_size(seed):
    P = with_holes(np.random.default_rng(seed)) if seed else SQUARE
    f = _graded(P)
    r = uniform2d.insert(P, 400, size=f)
    check_mesh(r.mesh_points, r.triangles, P)
    v = r.weights / f(r.points)
    assert np.all(np.diff(v) <= 1e-9 * v[:-1]), "distance / size must never increase"
    if seed:
        return
    # convex P: weights are plain nearest distances to the sites before each point
    sites = np.concatenate([P.vertices, r.points])
    nV = len(P.vertices)
    for j in range(0, len(r.points), 37):
        d = np.hypot(*(sites[: nV + j] - r.points[j]).T).min()
        assert abs(r.weights[j] - d) <= 1e-9 * d


def test_graded_field_makes_points_dense_where_size_is_small():
    r = uniform2d.insert(SQUARE, 2000, size=SizeField([0, 1], [0, 1], [[0.2, 1.0], [0.2, 1.0]]))
    left = (r.points[:, 0] < 0.25).sum()
    right = (r.points[:, 0] >= 0.75).sum()
    assert left > 5 * right  # density ~ 1 / h^2: h is 5 times smaller on the left
    # spacing follows h: mean nearest-neighbour distance ratio close to the size ratio
    from scipy.spatial import cKDTree

    d, _ = cKDTree(r.mesh_points).query(r.points, k=2)
    near_left = d[r.points[:, 0] < 0.1, 1].mean()
    near_right = d[r.points[:, 0] > 0.9, 1].mean()
    assert 2.5 < near_right / near_left < 6
