"""Regions of a constrained polygon and of its meshes (uniform2d.regions)."""

import numpy as np
import pytest
import shapely

from uniform2d import InvalidArgumentError, InvalidConstraintError, Polygon
from uniform2d.mesh import Mesh
from uniform2d.mesh_regions import segment_chains, triangle_regions

from support.conmesh import triangle_mesh

SQ = [(0, 0), (10, 0), (10, 10), (0, 10)]


def slab():
    """A slab with a wall from edge to edge, a closed zone, a stiffener, a hole and columns."""
    return Polygon(SQ, [[(7, 7), (9, 7), (9, 9), (7, 9)]],
                   segments=[[(4, 0), (4, 10)], [(5, 2), (8, 2), (8, 5), (5, 5), (5, 2)],
                             [(1, 1), (3, 3)], [(6, 6), (6, 8)]],
                   points=[(2, 8), (6.5, 3.5), (4, 5)],
                   regions=[(2, 5, "west"), (6.5, 3, 2.5)])


def _square_split():
    """The unit square split by a vertical segment, meshed by hand: 4 triangles."""
    p = Polygon([(0, 0), (2, 0), (2, 1), (0, 1)], segments=[[(1, 0), (1, 1)]],
                regions=[(1.5, 0.5, "right")])
    # vertices: (0,0) (1,0) (2,0) (2,1) (1,1) (0,1)
    assert p.vertices.tolist() == [[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]]
    tri = np.array([[0, 1, 4], [0, 4, 5], [1, 2, 3], [1, 3, 4]])
    return p, p.vertices.copy(), tri


def test_hand_made_mesh_of_a_split_square():
    p, pts, tri = _square_split()
    assert len(p.regions) == 2 and p.regions.labels == (None, "right")
    assert triangle_regions(p, pts, tri).tolist() == [0, 0, 1, 1]
    edges, ids = segment_chains(p, pts, tri)
    assert edges.tolist() == [[1, 4]] and ids.tolist() == [0]
    m = Mesh(pts, tri, p, 0)
    assert m.regions.tolist() == [0, 0, 1, 1] and m.region_labels == (None, "right")


def test_regions_tile_the_polygon_and_follow_the_rule():
    p = slab()
    r = p.regions
    # west of the wall, east of it (less the closed zone and the hole), the zone
    assert len(r) == 3
    assert abs(r.areas.sum() - p.area) <= 1e-12 * p.area
    union = shapely.union_all(r.faces)
    assert abs(union.area - p.area) <= 1e-12 * p.area
    assert union.symmetric_difference(p.to_shapely()).area <= 1e-12 * p.area
    for i in range(len(r)):
        for j in range(i + 1, len(r)):
            assert r.faces[i].intersection(r.faces[j]).area == 0.0
    # numbered by their sorted vertex lists: (0,0) < (4,0) < (5,2)
    firsts = [min(map(tuple, np.asarray(f.exterior.coords))) for f in r.faces]
    assert firsts == sorted(firsts) == [(0.0, 0.0), (4.0, 0.0), (5.0, 2.0)]
    assert r.labels == ("west", None, 2.5)


def test_numbering_does_not_depend_on_how_the_input_is_given():
    p = slab()
    q = Polygon(SQ[::-1], [[(7, 9), (9, 9), (9, 7), (7, 7)]],
                segments=[[(3, 3), (1, 1)], [(6, 8), (6, 6)], [(4, 10), (4, 0)],
                          [(8, 5), (5, 5), (5, 2), (8, 2), (8, 5)]],
                points=[(4, 5), (6.5, 3.5), (2, 8)], regions=[(6.5, 3, 2.5), (2, 5, "west")])
    assert [f.area for f in p.regions.faces] == [f.area for f in q.regions.faces]
    assert p.regions.labels == q.regions.labels


@pytest.mark.parametrize("scale, offset", [(1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -1e6))])
def test_regions_scale_and_translate(scale, offset):
    p = slab()
    q = p.transformed(scale, offset)
    assert q.regions.labels == p.regions.labels
    np.testing.assert_allclose(q.regions.areas, p.regions.areas * scale**2, rtol=1e-9)


@pytest.mark.parametrize("max_area", [None, 0.5, 0.05])
def test_mesh_regions_match_triangles_own_attributes(max_area):
    """Triangle's regional attributes (an independent flood fill) give the same
    region per triangle; each triangle lies in its region; areas add up."""
    p = slab()
    pts, tri, want = triangle_mesh(p, max_area=max_area, attributes=True)
    got = triangle_regions(p, pts, tri)
    assert np.array_equal(got, want)
    t = pts[tri]
    area = 0.5 * np.abs((t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1])
                        - (t[:, 1, 1] - t[:, 0, 1]) * (t[:, 2, 0] - t[:, 0, 0]))
    sums = np.bincount(got, weights=area, minlength=len(p.regions))
    np.testing.assert_allclose(sums, p.regions.areas, rtol=1e-12)
    for k in range(0, len(tri), max(1, len(tri) // 50)):
        assert p.regions.faces[got[k]].buffer(1e-9).contains(shapely.Polygon(t[k]))


def test_segment_chains_follow_steiner_points_on_segments():
    p = slab()
    pts, tri = triangle_mesh(p, max_area=0.05)
    edges, ids = segment_chains(p, pts, tri)
    for s, line in enumerate(p.segments):
        e = edges[ids == s]
        assert np.array_equal(e[1:, 0], e[:-1, 1])        # one chain
        assert np.array_equal(pts[e[0, 0]], line[0]) and np.array_equal(pts[e[-1, 1]], line[-1])
        length = np.hypot(*(pts[e[:, 1]] - pts[e[:, 0]]).T).sum()
        assert length == pytest.approx(np.hypot(*np.diff(line, axis=0).T).sum(), rel=1e-12)
        assert len(e) > len(line) - 1                     # Triangle split the long ones


def test_a_mesh_missing_a_segment_is_refused():
    p, pts, _ = _square_split()
    crossing = np.array([[0, 1, 5], [1, 2, 3], [1, 3, 5], [5, 3, 4]])   # edge 1-4 missing
    with pytest.raises(InvalidArgumentError, match="segment piece from vertex 1"):
        triangle_regions(p, pts, crossing)
    with pytest.raises(InvalidArgumentError, match="start with the polygon's vertices"):
        triangle_regions(p, pts[::-1], crossing)


def test_unconstrained_polygon_is_one_region():
    p = Polygon(SQ, [[(7, 7), (9, 7), (9, 9), (7, 9)]])
    assert len(p.regions) == 1 and p.regions.areas.tolist() == [96.0]
    pts, tri = triangle_mesh(p)
    assert triangle_regions(p, pts, tri).tolist() == [0] * len(tri)


@pytest.mark.parametrize("seeds, words", [
    ([(4, 5, "a")], "lies on a ring or segment"),
    ([(8, 8, "a")], "outside the polygon or in a hole"),
    ([(20, 5, "a")], "outside the polygon or in a hole"),
    ([(1, 5, "a"), (2, 5, "b")], "regions 0 and 1 both lie in region 0"),
    ([(1, 5)], "expected a seed (x, y, label)"),
    ([(1, 5, None)], "is not a string or a finite number"),
    ([(1, 5, float("nan"))], "is not a string or a finite number"),
    ([(1, 5, True)], "is not a string or a finite number"),
    ([("x", 5, "a")], "are not numbers"),
    ([(float("inf"), 5, "a")], "is not finite"),
    ("abc", "sequence of (x, y, label) seeds"),
])
def test_bad_region_seeds(seeds, words):
    with pytest.raises(InvalidConstraintError) as e:
        Polygon(SQ, segments=[[(4, 0), (4, 10)]], points=[(2, 2)], regions=seeds,
                holes=[[(7, 7), (9, 7), (9, 9), (7, 9)]])
    assert words in str(e.value)


def test_seed_equality_and_repr():
    a = Polygon(SQ, regions=[(1, 1, "x")])
    assert a == Polygon(SQ, regions=[(1, 1, "x")]) and a != Polygon(SQ, regions=[(1, 1, "y")])
    assert "1 region labels" in repr(a)
    assert a.region_seeds == ((1.0, 1.0, "x"),)
