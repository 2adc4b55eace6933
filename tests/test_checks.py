"""The independent mesh checker refuses each kind of broken mesh it names.

Every mesh test of the project leans on :func:`uniform2d.testing.check_mesh`;
a check that silently passed would let every one of them pass too.  Each test
here takes a valid mesh (the checker accepts it) and breaks one invariant.
"""

from fractions import Fraction

import numpy as np
import pytest

import uniform2d
from uniform2d.testing import check_mesh

SQUARE = uniform2d.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)])
SLAB = uniform2d.Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], segments=[[(1, 2), (3, 2)]],
                         points=[(2, 3)])


@pytest.fixture(scope="module")
def square_mesh():
    mesh = uniform2d.insert(SQUARE, 12)
    check_mesh(mesh.mesh_points, mesh.triangles, SQUARE, n_steiner=12)
    return mesh.mesh_points.copy(), mesh.triangles.copy()


@pytest.fixture(scope="module")
def slab_mesh():
    mesh = uniform2d.uniform_mesh(SLAB, 20)
    check_mesh(mesh.points, mesh.triangles, SLAB)
    return mesh.points.copy(), mesh.triangles.copy()


def _interior_edge_triangles(tri):
    """Two triangles sharing an interior edge: (i, j, the shared pair)."""
    for i in range(len(tri)):
        for j in range(i + 1, len(tri)):
            shared = set(tri[i].tolist()) & set(tri[j].tolist())
            if len(shared) == 2:
                return i, j, sorted(shared)
    raise AssertionError("no interior edge")


def test_shapes_and_indices_refused(square_mesh):
    pts, tri = square_mesh
    with pytest.raises(AssertionError, match=r"points must be \(N, 2\)"):
        check_mesh(pts[:, :1], tri, SQUARE)
    with pytest.raises(AssertionError, match=r"triangles must be \(M, 3\)"):
        check_mesh(pts, tri[:, :2], SQUARE)
    bad = tri.copy()
    bad[0, 0] = len(pts)
    with pytest.raises(AssertionError, match="outside"):
        check_mesh(pts, bad, SQUARE)
    nan = pts.copy()
    nan[-1, 0] = np.nan
    with pytest.raises(AssertionError, match="non-finite"):
        check_mesh(nan, tri, SQUARE)


def test_clockwise_triangle_refused(square_mesh):
    pts, tri = square_mesh
    bad = tri.copy()
    bad[3] = bad[3, ::-1]
    with pytest.raises(AssertionError, match="1 triangles are not strictly counter-clockwise"):
        check_mesh(pts, bad, SQUARE)


def test_triangle_twice_refused(square_mesh):
    pts, tri = square_mesh
    with pytest.raises(AssertionError, match="directed edge appears in two triangles"):
        check_mesh(pts, np.vstack([tri, tri[:1]]), SQUARE)


def test_missing_triangle_refused(square_mesh):
    """A hole in the mesh: its edges are boundary edges on no polygon edge."""
    pts, tri = square_mesh
    i, _, _ = _interior_edge_triangles(tri)
    with pytest.raises(AssertionError, match="boundary"):
        check_mesh(pts, np.delete(tri, i, axis=0), SQUARE)


def test_points_must_start_with_the_vertices(square_mesh):
    pts, tri = square_mesh
    moved = pts.copy()
    moved[0] += 1e-3
    with pytest.raises(AssertionError, match="must start with the polygon vertices"):
        check_mesh(moved, tri, SQUARE)


def test_boundary_point_off_its_edge_refused(square_mesh):
    pts, tri = square_mesh
    on_bottom = [k for k in range(4, len(pts)) if pts[k, 1] == 0.0 and 0 < pts[k, 0] < 4]
    assert on_bottom
    moved = pts.copy()
    moved[on_bottom[0], 1] = 1e-6  # still inside, its triangles still counter-clockwise
    with pytest.raises(AssertionError, match="is off polygon edge 0->1"):
        check_mesh(moved, tri, SQUARE)


def test_wrong_steiner_count_refused(square_mesh):
    pts, tri = square_mesh
    check_mesh(pts, tri, SQUARE, n_steiner=len(pts) - 4)
    with pytest.raises(AssertionError, match="Steiner points, not"):
        check_mesh(pts, tri, SQUARE, n_steiner=len(pts) - 3)


def test_area_short_of_the_polygon_refused(square_mesh):
    """The areas are summed and compared: a correct mesh's sum is within
    rounding of the polygon's (1e-12 relative), and no sum meets a negative
    tolerance.  (A mesh that passes the boundary and edge checks covers the
    polygon once, so the area check is the backstop that catches a fold the
    others miss; no such mesh is built here.)"""
    pts, tri = square_mesh
    check_mesh(pts, tri, SQUARE, area_rtol=1e-12)
    with pytest.raises(AssertionError, match="the triangles cover"):
        check_mesh(pts, tri, SQUARE, area_rtol=-1.0)


def _cocircular(a, b, c, d) -> bool:
    """The four points on one circle, decided in exact rationals."""
    rows = []
    for p in (a, b, c):
        x, y = Fraction(float(p[0])) - Fraction(float(d[0])), Fraction(float(p[1])) - Fraction(float(d[1]))
        rows.append((x, y, x * x + y * y))
    (a1, a2, a3), (b1, b2, b3), (c1, c2, c3) = rows
    return a1 * (b2 * c3 - b3 * c2) - a2 * (b1 * c3 - b3 * c1) + a3 * (b1 * c2 - b2 * c1) == 0


def _ccw(pts, t) -> bool:
    p = pts[list(t)]
    return (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0]) > 0


def test_flipped_edge_not_delaunay(square_mesh):
    """Flipping an interior edge of a Delaunay mesh (its quadrilateral convex)
    gives a non-Delaunay edge unless the four points are cocircular; with
    ``delaunay=False`` every such flip is accepted."""
    pts, tri = square_mesh
    refused = 0
    for i in range(len(tri)):
        for j in range(i + 1, len(tri)):
            shared = set(tri[i].tolist()) & set(tri[j].tolist())
            if len(shared) != 2:
                continue
            k = next(m for m in range(3) if tri[i][m] not in shared)
            a, p, q = tri[i][k], tri[i][(k + 1) % 3], tri[i][(k + 2) % 3]
            b = next(v for v in tri[j].tolist() if v not in shared)
            bad = tri.copy()
            bad[i], bad[j] = (a, p, b), (a, b, q)  # tri[i] = (a, p, q) counter-clockwise
            if not (_ccw(pts, bad[i]) and _ccw(pts, bad[j])):
                continue  # not a convex quadrilateral: no flip
            check_mesh(pts, bad, SQUARE, delaunay=False)
            if _cocircular(pts[a], pts[p], pts[q], pts[b]):
                check_mesh(pts, bad, SQUARE)
                continue
            with pytest.raises(AssertionError, match="1 interior edges are not locally Delaunay"):
                check_mesh(pts, bad, SQUARE)
            refused += 1
    assert refused > 0


def test_unused_fixed_point_refused(slab_mesh):
    """The fixed point's triangles replaced by a fan from one of its neighbours:
    a valid triangulation of the rest, the fixed point in none of its triangles."""
    pts, tri = slab_mesh
    k = int(SLAB.fixed[0])
    star = tri[(tri == k).any(axis=1)]
    link = {}  # around k: each triangle (k, u, v) counter-clockwise gives u -> v
    for t in star.tolist():
        m = t.index(k)
        link[t[(m + 1) % 3]] = t[(m + 2) % 3]
    ring = [next(iter(link))]
    while len(ring) < len(link):
        ring.append(link[ring[-1]])
    for s in range(len(ring)):
        r = ring[s:] + ring[:s]
        fan = [(r[0], r[m], r[m + 1]) for m in range(1, len(r) - 1)]
        if all(_ccw(pts, t) for t in fan):
            break
    else:
        pytest.skip("no fan of the fixed point's link is valid")
    bad = np.vstack([tri[~(tri == k).any(axis=1)], fan])
    with pytest.raises(AssertionError, match="fixed point 0 is not a mesh vertex"):
        check_mesh(pts, bad, SLAB, delaunay=False)


def test_segment_point_off_its_segment_refused(slab_mesh):
    pts, tri = slab_mesh
    a, b = (int(v) for v in SLAB.segment_edges[0])
    on = [i for i in range(len(pts)) if i not in (a, b) and pts[i, 1] == 2.0
          and 1.0 < pts[i, 0] < 3.0]
    assert on, "the segment carries Steiner points"
    moved = pts.copy()
    moved[on[0], 1] += 1e-3
    with pytest.raises(AssertionError, match="segment piece"):
        check_mesh(moved, tri, SLAB, delaunay=False)
