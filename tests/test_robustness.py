"""Valid polygons that once gave a wrong mesh or a crash, and the invariants that fixed them.

``data/robustness_reproducers.json`` holds the cases fuzzers found (outer ring,
holes, the call, n, and what was seen then): rotated rectilinear outlines where
T+ returned triangles covering 1.01x the area, 'could not insert site',
INSERT kernel status -501/-3901, ZeroDivisionError in the relaxation, an
InvalidSitesError about sites the caller never passed, and T+'s piece count
flipping with scale and offset.  Each must now give a valid mesh with exactly n
Steiner points.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import uniform2d
from uniform2d.testing import check_mesh
from uniform2d import InternalError, Polygon
from uniform2d.insert import insert_on_edges
from uniform2d.validity import ensure_valid
from uniform2d.tplus import boundary_points, edge_of

CASES = json.loads((Path(__file__).parent / "data" / "robustness_reproducers.json").read_text())
BY_NAME = {c["name"]: c for c in CASES}
OCTAGON = Polygon(BY_NAME["rect8_tplus_wrong_and_crash"]["outer"])
INVARIANCE = Polygon(BY_NAME["tplus_piece_count_invariance"]["outer"])


def _area_rtol(poly):
    """1e-9, or what rounding boundary points onto rotated edges can change of the
    area where the coordinates are coarse for the polygon's size."""
    grain = 4 * np.spacing(float(np.abs(poly.vertices).max()))
    return max(1e-9, grain * poly.perimeter / poly.area)


def _check(poly, n, pts, tri):
    assert len(pts) == len(poly.vertices) + n
    check_mesh(pts, tri, poly, area_rtol=_area_rtol(poly))


@pytest.mark.parametrize("i", range(len(CASES)), ids=[f"{c['name']}-{c['n']}" for c in CASES])
def test_reproducer_meshes_correctly(i):
    c = CASES[i]
    poly = Polygon(c["outer"], c["holes"])
    mesh = getattr(uniform2d, c["call"])(poly, c["n"])
    pts = mesh.mesh_points if c["call"] == "insert" else mesh.points
    _check(poly, c["n"], pts, mesh.triangles)


def test_tplus_on_the_rotated_octagon_is_valid_for_every_n():
    """It was wrong for ~100 n in [1, 400] and raised for ~20 more."""
    for n in range(1, 401, 3):
        try:
            mesh = uniform2d.tplus(OCTAGON, n)
        except uniform2d.InsufficientPointsError:
            assert n < 40  # only where T+ needs more boundary points than n
            continue
        _check(OCTAGON, n, mesh.points, mesh.triangles)


def test_boundary_sites_on_rotated_edges_are_placed_exactly():
    """Sites rounded off rotated edges made GEOS cut flat or inverted ears; the
    exact check now rejects its triangulation and the sites split their edges by
    index -- through the public insert too."""
    pts, m = boundary_points(OCTAGON, 20.0)
    res = uniform2d.insert(OCTAGON, 50, sites=pts)
    _check(OCTAGON, len(pts) + 50, res.mesh_points, res.triangles)
    res2 = insert_on_edges(OCTAGON, 50, pts, edge_of(m))
    assert np.array_equal(res.mesh_points, res2.mesh_points)
    assert np.array_equal(res.triangles, res2.triangles)


TRANSFORMS = [(1e-6, 0.0), (1e6, 0.0), (1.0, 1e6), (1.0, -3e6), (1e-3, 1e4)]


@pytest.mark.parametrize("scale, offset", TRANSFORMS)
def test_tplus_piece_count_and_mesh_do_not_change_with_scale_and_offset(scale, offset):
    base = uniform2d.tplus(INVARIANCE, 18)
    moved = uniform2d.tplus(INVARIANCE.transformed(scale, (offset, offset)), 18)
    assert base.info["k"] == moved.info["k"] == 11
    grain = 8 * np.spacing(abs(offset) + 2 * scale)
    assert np.abs(moved.points - (base.points * scale + offset)).max() <= 1e-9 * scale + grain
    _check(moved.polygon, 18, moved.points, moved.triangles)


@pytest.mark.parametrize("scale, offset", TRANSFORMS)
def test_insert_does_not_change_with_scale_and_offset_on_a_rotated_outline(scale, offset):
    base = uniform2d.insert(OCTAGON, 150)
    P = OCTAGON.transformed(scale, (offset, offset))
    moved = uniform2d.insert(P, 150)
    size = 900.0 * scale
    grain = 8 * np.spacing(abs(offset) + size)
    assert np.abs(moved.points - (base.points * scale + offset)).max() <= 1e-9 * size + grain
    assert np.array_equal(moved.on_boundary, base.on_boundary)
    _check(P, 150, moved.mesh_points, moved.triangles)


def test_piece_count_rule_treats_a_ratio_within_rounding_of_an_integer_as_that_integer():
    sq = Polygon([(0, 0), (3, 0), (3, 3), (0, 3)])
    for gap in (1 - 1e-13, 1.0, 1 + 1e-13):
        assert boundary_points(sq, gap, 1e-9)[1].tolist() == [3, 3, 3, 3]
    assert boundary_points(sq, 1 - 1e-13)[1].tolist() == [4, 4, 4, 4]  # plain ceil
    assert boundary_points(sq, 3 / 3.01, 1e-9)[1].tolist() == [4, 4, 4, 4]


def test_a_star_at_the_limit_of_its_coordinates_precision_meshes():
    """A 1e-6 star with a 9-ulp edge at 1e6: the optimiser's sliding points came
    within the distance tolerance of a vertex and were refused as 'coinciding'
    although the caller passed no sites.  They are now placed by index."""
    c = BY_NAME["invalidsites_on_valid_input"]
    poly = Polygon(c["outer"])
    mesh = uniform2d.uniform_mesh(poly, c["n"])
    _check(poly, c["n"], mesh.points, mesh.triangles)


# -- the final check ---------------------------------------------------------------------
SQ = Polygon([(0, 0), (1, 0), (1, 1), (0, 1)])


def _good():
    res = uniform2d.insert(SQ, 6)
    return np.array(res.mesh_points), np.array(res.triangles)


def test_the_final_check_passes_a_valid_mesh():
    pts, tri = _good()
    ensure_valid(pts, tri, SQ, 6, "test")


@pytest.mark.parametrize(
    "corrupt, words",
    [
        (lambda p, t: (p, t[:, ::-1]), "counter-clockwise"),
        (lambda p, t: (p, t[1:]), "boundary"),
        (lambda p, t: (p, np.concatenate([t, t[:1]])), "twice"),
        (lambda p, t: (np.concatenate([p, [[0.5, 0.5]]]), t), "points"),
        (lambda p, t: (p * 1.0001, t), "polygon's vertices"),
    ],
    ids=["flipped", "hole", "overlap", "count", "moved"],
)
def test_the_final_check_raises_an_internal_error_on_a_wrong_mesh(corrupt, words):
    pts, tri = corrupt(*_good())
    with pytest.raises(InternalError, match="please report it") as exc:
        ensure_valid(pts, tri, SQ, 6, "test")
    assert words in str(exc.value)
    assert not isinstance(exc.value, uniform2d.Uniform2dError)


def test_the_final_check_sees_a_boundary_point_off_its_edge():
    pts, tri = _good()
    on = np.flatnonzero((pts[:, 1] == 0.0) & (pts[:, 0] > 0) & (pts[:, 0] < 1))
    assert len(on)
    pts[on[0], 1] = -1e-3
    with pytest.raises(InternalError, match="off its polygon edge"):
        ensure_valid(pts, tri, SQ, 6, "test")


# -- the exact fallback triangulation --------------------------------------------------
def _exact_triangles(poly):
    from uniform2d._kernel import polytri

    rings, k = [], 0
    for r in poly.rings:
        rings.append(list(range(k, k + len(r))))
        k += len(r)
    return polytri.triangulate(poly.vertices, rings)


@pytest.mark.parametrize("seed", range(8))
def test_exact_triangulation_of_polygons_with_holes_and_collinear_vertices(seed):
    """GEOS can cut flat ears on collinear vertices; polytri decides exactly."""
    from uniform2d.testing.polygons import with_holes

    p = with_holes(seed)
    # split every outer edge at 1/4 and 1/2: collinear within an ulp, and exactly
    # collinear where the edge is axis-parallel after rounding to a grid
    outer = []
    for a, b in zip(p.outer, np.roll(p.outer, -1, axis=0)):
        outer += [a, a + 0.25 * (b - a), a + 0.5 * (b - a)]
    q = Polygon(np.round(np.array(outer) * 64) / 64, p.holes)
    tri = _exact_triangles(q)
    nb = len(q.vertices)
    assert len(tri) == nb + 2 * q.n_holes - 2
    check_mesh(q.vertices, tri, q, delaunay=False)


def test_exact_triangulation_of_a_ring_geos_gets_wrong():
    """A fuzzer's rotated rectilinear ring with vertices on its edges: GEOS's
    triangulation fails the exact check, so insert falls back to polytri."""
    c = BY_NAME["fuzz_collinear_exact_fallback"]
    poly = Polygon(c["outer"], c["holes"])
    tri = _exact_triangles(poly)
    check_mesh(poly.vertices, tri, poly, delaunay=False)
    res = uniform2d.insert(poly, c["n"])
    _check(poly, c["n"], res.mesh_points, res.triangles)


def test_too_coarse_coordinates_are_refused_with_advice():
    """A square 6 units in the last place wide at 1e7 has no room for a few points
    (a point rounded past the end of its boundary subsegment would fold the
    boundary): that is the input's limit, said as such -- not a wrong mesh."""
    q = np.spacing(1e7)
    sq = Polygon(np.array([[0, 0], [6, 0], [6, 6], [0, 6]]) * q + 1e7)
    with pytest.raises(uniform2d.CoordinatePrecisionError, match="nearer the origin"):
        uniform2d.insert(sq, 20)
    assert issubclass(uniform2d.CoordinatePrecisionError, uniform2d.InvalidPolygonError)
    res = uniform2d.insert(sq.transformed(1.0, (-1e7, -1e7)), 20)
    _check(sq.transformed(1.0, (-1e7, -1e7)), 20, res.mesh_points, res.triangles)


# -- the final check's compiled parts against plain references -------------------------
def _meshes():
    """Triangle lists of a few meshes (square, a polygon with a hole), with holes
    punched in them and triangles dropped at random: boundaries of every shape."""
    rng = np.random.default_rng(5)
    ring = Polygon([(0, 0), (3, 0), (3, 2), (0, 2)], holes=[[(1, 0.5), (1, 1.5), (2, 1.5), (2, 0.5)]])
    out = []
    for poly, n in ((SQ, 40), (ring, 120)):
        res = uniform2d.insert(poly, n)
        pts, tri = np.array(res.mesh_points), np.array(res.triangles)
        out.append((pts, tri))
        keep = rng.random(len(tri)) > 0.3
        out.append((pts, tri[keep]))
    return out


@pytest.mark.parametrize("case", range(4))
def test_unmatched_edges_are_the_edges_without_a_reverse(case):
    from uniform2d._kernel.validity import _unmatched

    pts, tri = _meshes()[case]
    tri = np.ascontiguousarray(tri, dtype=np.int64)
    count, bu, bv = _unmatched(tri, np.int64(len(pts)))
    directed = {(int(a), int(b)) for t in tri for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    expect = sorted((a, b) for a, b in directed if (b, a) not in directed)
    assert count == len(expect) == len(bu) == len(bv)
    assert sorted(zip(bu.tolist(), bv.tolist())) == expect
    # a triangle given twice repeats its three directed edges
    count, bu, bv = _unmatched(np.concatenate([tri, tri[-1:]]), np.int64(len(pts)))
    assert count == -1 and len(bu) == len(bv) == 0


@pytest.mark.parametrize("case", range(4))
def test_area2_is_twice_the_exact_signed_area(case):
    from fractions import Fraction

    from uniform2d._kernel.validity import _area2

    pts, tri = _meshes()[case]
    tri = np.ascontiguousarray(tri, dtype=np.int64)
    P = [(Fraction(x), Fraction(y)) for x, y in pts.tolist()]
    exact = sum(
        (P[b][0] - P[a][0]) * (P[c][1] - P[a][1]) - (P[b][1] - P[a][1]) * (P[c][0] - P[a][0])
        for a, b, c in tri.tolist()
    )
    got = _area2(pts, tri)
    assert abs(Fraction(got) - exact) <= 8 * np.finfo(float).eps * float(exact)


def test_hilbert_order_walks_a_full_grid_cell_by_cell():
    """On every cell of a 2**b x 2**b grid the Hilbert order visits each cell once,
    each step to an edge-neighbour, from one corner cell to an adjacent corner."""
    from uniform2d._kernel.hilbert import hilbert_order

    side = 8
    g = np.array([(i, j) for j in range(side) for i in range(side)], dtype=np.float64)
    rng = np.random.default_rng(2)
    g = g[rng.permutation(len(g))]
    order = hilbert_order(g, bits=3)
    assert sorted(order.tolist()) == list(range(side * side))
    walk = g[order]
    assert (np.abs(np.diff(walk, axis=0)).sum(axis=1) == 1).all()
    assert walk[0].tolist() == [0, 0] and walk[-1].tolist() in ([side - 1, 0], [0, side - 1])
