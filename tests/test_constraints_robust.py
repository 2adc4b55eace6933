"""Near-degenerate constrained domains from the fuzz benchmark.

``data/constrained_near.json`` holds domains of ``uniform2d.testing.fuzz.constrained``,
each named ``<kind>_<seed>`` (``fuzz.constrained(seed)`` draws it again).
The first eight (seed 0, kinds ``c_near`` and ``c_tjunction``): two segments
leaving one vertex at an angle of ~1e-7, a fixed point a few units in the last
place off a segment, a segment ending a rounding off a ring edge, far from the
origin.  There the points of one segment piece lie within rounding tolerance
of another piece (or of a ring edge), so "which chain of edges is this piece"
is ambiguous by distance alone; and the closest vertices are so near that T+
would need millions of boundary points.

The others are every domain the benchmark (200 domains, half constrained,
seeds 0-3) failed on: a fixed point or segment end computed onto a rotated ring
edge or a segment (an ulp off it), which the polygon took for an interior
vertex beside a sliver no coordinate can hold a point in -- now a junction on
that edge or piece; region areas off by the rounding of boundary points far
from the origin; a region thinner than the probe that looked for its sides.

Every mesh is checked by ``uniform2d.testing.check_mesh`` (each piece a chain of mesh
edges, no point on two chains, the rest constrained Delaunay, exactly n) and
its triangles must tile the regions (``mesh_regions.triangle_regions``).
"""

from __future__ import annotations

import functools
import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from numba import njit

import uniform2d
from uniform2d.testing import check_mesh, edge_table, segment_chains
from uniform2d import Polygon
from uniform2d.errors import InsufficientPointsError, InvalidConstraintError
from uniform2d.optimize.shares import sides_of as _sides
from uniform2d.mesh_regions import triangle_regions
from uniform2d import constraints
from uniform2d._kernel.segment import eval_segment
from uniform2d.tplus import SEARCH_LIMIT, _phase1, least_k

DATA = Path(__file__).parent / "data" / "constrained_near.json"


@functools.cache
def domain(name: str) -> Polygon:
    d = json.loads(DATA.read_text())[name]
    return Polygon(d["outer"], d["holes"], segments=d["segments"], points=d["points"])


# (domain, n): INSERT's meshes whose pieces the old greedy chain walk could not
# follow (a crash in the library's own check, or a false "not Delaunay" from the
# test checker, which then left real piece edges in its Delaunay test)
INSERTS = [
    ("c_near_9", 2544), ("c_near_9", 2368), ("c_near_34", 3584), ("c_near_34", 1984),
    ("c_near_34", 355), ("c_tjunction_16", 463), ("c_near_21", 21),
    ("c_near_31", 1), ("c_near_35", 790), ("c_near_36", 80),
]  # fmt: skip


@pytest.mark.parametrize("name,n", INSERTS)
def test_insert_near_degenerate(name, n):
    P = domain(name)
    res = uniform2d.insert(P, n)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=n)


def test_chains_are_disjoint_where_pieces_nearly_overlap():
    """Pieces 9-12 and 9-13 of c_near_9 leave vertex 9 at an angle of ~2e-7: their
    chains are found separately, share no inner vertex, and both start at 9."""
    P = domain("c_near_9")
    res = uniform2d.insert(P, 2544)
    he, _, _ = edge_table(res.triangles)
    on = segment_chains(res.mesh_points, he, P)
    first = {v for u, v in on if u == 9}
    assert len(first) == 3  # 8-9 ends at 9 too: one edge on each of the three pieces


@pytest.mark.parametrize("name,n", [("c_near_9", 36), ("c_near_34", 30), ("c_near_21", 41)])
def test_uniform_mesh_near_degenerate(name, n):
    P = domain(name)
    mesh = uniform2d.uniform_mesh(P, n)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)


@pytest.mark.parametrize(
    "name,n", [("c_near_9", 158), ("c_near_21", 44), ("c_near_31", 53),
               ("c_near_35", 31), ("c_near_36", 859), ("c_near_34", 6)],
)  # fmt: skip
def test_tplus_refuses_at_once_when_vertices_nearly_coincide(name, n):
    """d_n <= l(V, V) for every n: where that is tiny, T+ needs more boundary
    points than any n it could be run for; the refusal names the distance."""
    P = domain(name)
    with pytest.raises(InsufficientPointsError, match="apart") as exc:
        uniform2d.tplus(P, n)
    least = int(str(exc.value).split("at least ")[1].split()[0])
    assert least == least_k(P) > n
    assert f"{P.min_vertex_distance():.6g}" in str(exc.value)


@pytest.mark.parametrize("n", [1, 10, 100, 1000])
def test_least_k_is_a_lower_bound(n):
    """least_k never exceeds the k phase 1 actually asks for (L-shaped room with
    a stiffener and a column, so l(V, V) is a real short distance)."""
    P = Polygon(
        [(0, 0), (6, 0), (6, 2), (3, 2), (3, 5), (0, 5)],
        segments=[[(1, 1), (1, 4.0)], [(1, 4.0), (2.5, 4.2)]],
        points=[(1.05, 2.0)],
    )
    d_n, pts, _, m = _phase1(P, n, 3.0)
    k = int(m.sum() - len(m)) if pts is None else len(pts)
    assert least_k(P) <= k
    assert d_n <= P.min_vertex_distance()


def test_tplus_feasible_polygon_unchanged():
    """Where l(V, V) is not tiny the old search still names the smallest n."""
    P = Polygon([(0, 0), (10, 0), (10, 1), (0, 1)], segments=[[(2, 0.5), (8, 0.5)]])
    with pytest.raises(InsufficientPointsError, match=r"smallest n that works for this polygon is (\d+)") as exc:
        uniform2d.tplus(P, 1)
    need = int(str(exc.value).rsplit(" ", 1)[1])
    mesh = uniform2d.tplus(P, need)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=need)
    assert np.isfinite(mesh.info["d_n"])


# -- the fuzz benchmark's failures (200 domains, --constrained 0.5, seeds 0-3) --------
def _mesh(P, call, n):
    if call == "insert":
        res = uniform2d.insert(P, n)
        return res.mesh_points, res.triangles
    m = getattr(uniform2d, call)(P, n)
    return m.points, m.triangles


def _area_rtol(P):
    """1e-9, or where the coordinates are coarse for P's size what rounding the
    boundary points onto rotated edges allows (4 ulps times the perimeter)."""
    return max(1e-9, 4 * np.spacing(np.abs(P.vertices).max()) * P.perimeter / P.area)


# (domain, call, n) that crashed or returned a mesh the checks refused: a fixed
# point or a segment end an ulp off a rotated ring edge or a segment ("could not
# insert vertex", "piece is not a chain of mesh edges", "not locally Delaunay");
# region areas off by the rounding of boundary points far from the origin; a
# region thinner than the 1e-6 probe of its sides (no side found: ValueError);
# (c_tjunction, the last rows but one) segments ending a rounding across an edge,
# refused as crossing it before they became T-junctions; and (seed 11) a fixed
# point 10 ulps off a piece, on its chain for the library's final check but
# beyond the region check's tolerance.
FUZZ = [
    ("c_free_1000000006", "uniform_mesh", 129), ("c_free_1000000016", "uniform_mesh", 25),
    ("c_points_1000000047", "tplus", 362), ("c_closed_1000000049", "tplus", 227),
    ("c_closed_1000000049", "uniform_mesh", 19), ("c_tjunction_1000000054", "uniform_mesh", 8),
    ("c_free_1000000063", "uniform_mesh", 110), ("c_free_1000000079", "uniform_mesh", 133),
    ("c_closed_1000000090", "tplus", 753), ("c_free_1000000094", "uniform_mesh", 1),
    ("c_free_1000000131", "uniform_mesh", 4), ("c_points_1000000175", "tplus", 43),
    ("c_points_1000000175", "uniform_mesh", 44), ("c_closed_1000000190", "uniform_mesh", 1),
    ("c_free_2000000014", "uniform_mesh", 1), ("c_free_2000000020", "tplus", 905),
    ("c_free_2000000020", "uniform_mesh", 6), ("c_points_2000000031", "tplus", 191),
    ("c_points_2000000031", "uniform_mesh", 12), ("c_tjunction_2000000075", "insert", 14),
    ("c_tjunction_2000000075", "uniform_mesh", 125), ("c_closed_2000000082", "tplus", 197),
    ("c_tjunction_2000000100", "insert", 205), ("c_tjunction_2000000100", "tplus", 24),
    ("c_tjunction_2000000100", "uniform_mesh", 104), ("c_free_2000000109", "insert", 848),
    ("c_free_2000000109", "uniform_mesh", 47), ("c_closed_2000000132", "insert", 700),
    ("c_free_2000000143", "uniform_mesh", 34), ("c_tjunction_2000000160", "tplus", 283),
    ("c_tjunction_2000000171", "insert", 40), ("c_tjunction_2000000171", "uniform_mesh", 4),
    ("c_free_2000000182", "uniform_mesh", 34), ("c_tjunction_3000000019", "insert", 27),
    ("c_tjunction_3000000019", "uniform_mesh", 11), ("c_tjunction_3000000046", "tplus", 15),
    ("c_tjunction_3000000046", "uniform_mesh", 2), ("c_tjunction_3000000087", "insert", 37),
    ("c_tjunction_3000000087", "uniform_mesh", 61), ("c_free_3000000123", "uniform_mesh", 101),
    ("c_tjunction_3000000132", "insert", 5), ("c_tjunction_3000000132", "uniform_mesh", 94),
    ("c_tjunction_60", "uniform_mesh", 100), ("c_free_69", "uniform_mesh", 281),
    ("c_points_101", "uniform_mesh", 12), ("c_free_142", "uniform_mesh", 267),
    ("c_tjunction_185", "insert", 20),
    ("c_tjunction_1000000035", "insert", 10), ("c_tjunction_1000000035", "tplus", 23),
    ("c_tjunction_1000000035", "uniform_mesh", 7), ("c_tjunction_1000000116", "insert", 13),
    ("c_tjunction_1000000116", "uniform_mesh", 2), ("c_tjunction_1000000124", "insert", 58),
    ("c_tjunction_1000000124", "uniform_mesh", 1), ("c_tjunction_2000000058", "insert", 613),
    ("c_tjunction_2000000058", "tplus", 5), ("c_tjunction_2000000058", "uniform_mesh", 8),
    ("c_tjunction_2000000081", "insert", 128), ("c_tjunction_3000000085", "insert", 12),
    ("c_tjunction_3000000085", "uniform_mesh", 134),
    ("c_near_11000000120", "insert", 181), ("c_near_11000000120", "uniform_mesh", 48),
]  # fmt: skip


@pytest.mark.parametrize("name,call,n", FUZZ)
def test_fuzz_failures_mesh_and_tile_the_regions(name, call, n):
    P = domain(name)
    pts, tri = _mesh(P, call, n)
    check_mesh(pts, tri, P, n_steiner=n, area_rtol=_area_rtol(P))
    reg = triangle_regions(P, pts, tri)
    assert set(reg.tolist()) == set(range(len(P.regions)))


def _q(p):
    return Fraction(float(p[0])), Fraction(float(p[1]))


def _within_ulps(p, a, b, k) -> bool:
    """Exactly: is p within k units in the last place (of the largest coordinate
    of p, a, b) of segment a-b, its foot strictly between a and b?"""
    (px, py), (ax, ay), (bx, by) = _q(p), _q(a), _q(b)
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    if not 0 < (px - ax) * dx + (py - ay) * dy < L2:
        return False
    cross = dx * (py - ay) - dy * (px - ax)
    ulp = Fraction(float(np.spacing(max(abs(float(c)) for q in (p, a, b) for c in q))))
    return cross * cross <= (k * ulp) ** 2 * L2


NAMES = sorted(json.loads(DATA.read_text()))
U = float(np.spacing(1.0))
SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


@pytest.mark.parametrize("name", NAMES)
def test_no_vertex_left_beside_a_piece_and_junctions_within_rounding(name):
    """No vertex of P lies within 2 ulps of a piece it does not end (a ring edge
    or a segment piece): such a vertex is a junction splitting it.  And every
    vertex spliced into a given ring edge or segment piece lies on it or within
    2 ulps: nothing farther is moved onto a piece."""
    d = json.loads(DATA.read_text())[name]
    try:
        P = domain(name)
    except InvalidConstraintError as exc:
        assert name == "c_near_26", exc
        return
    V = P.vertices
    for u, v in P.constraint_edges:
        for w in range(len(V)):
            if w not in (u, v):
                assert not _within_ulps(V[w], V[u], V[v], 2), (int(w), int(u), int(v))
    given = [(np.asarray(d["outer"]), True)] + [(np.asarray(s), False) for s in d["segments"]]
    now = [P.outer] + P.split_segments()
    for (line, ring), got in zip(given, now):
        ends = np.roll(line, -1, axis=0) if ring else line[1:]
        pieces = list(zip(line, ends))
        have = set(map(tuple, line.tolist()))
        for q in got:
            if tuple(q) not in have:
                assert any(_within_ulps(q, a, b, 2) for a, b in pieces), q


@pytest.mark.parametrize(
    "name,what",
    [("c_points_1000000047", "ring"), ("c_points_2000000031", "ring"),
     ("c_free_1000000006", "segment"), ("c_free_2000000020", "segment")],
)  # fmt: skip
def test_a_fixed_point_an_ulp_off_a_piece_is_a_junction_on_it(name, what):
    """The fixed point computed onto a rotated ring edge (c_points) or a segment
    (c_free) is off it by rounding, not on it: it joins the ring, or splits the
    segment, instead of standing an ulp beside it."""
    P = domain(name)
    d = json.loads(DATA.read_text())[name]
    given = [np.asarray(d["outer"])] + [np.asarray(s) for s in d["segments"]]
    off = []
    for i, k in enumerate(P.fixed):
        line = given[0] if what == "ring" else np.concatenate(given[1:])
        pieces = zip(line, np.roll(line, -1, axis=0))
        if any(_within_ulps(P.points[i], a, b, 2) and not _within_ulps(P.points[i], a, b, 0)
               for a, b in pieces):
            off.append(int(k))
    assert off
    for k in off:
        if what == "ring":
            assert k < P.n_ring_vertices
        else:
            assert k in P.segment_edges[:, 0] and k in P.segment_edges[:, 1]


def _cross(a, b) -> Fraction:
    (ax, ay), (bx, by) = _q(a), _q(b)
    return ax * by - ay * bx


def _area2(ring) -> Fraction:
    return sum(_cross(a, b) for a, b in zip(ring, [*ring[1:], ring[0]]))


@pytest.mark.parametrize("name", [x for x in NAMES if x != "c_near_26"])
def test_region_sides_trace_each_region_counter_clockwise(name):
    """The edges with region r on their left, traversed forward, and those with
    r on their right, backward, bound r counter-clockwise: their exact shoelace
    sum is twice its exact area (a free piece, r on both sides, cancels)."""
    P = domain(name)
    faces = P.regions.faces
    sides = _sides(P, faces)
    V = P.vertices
    E = P.constraint_edges
    for r, f in enumerate(faces):
        want = abs(_area2(f.exterior.coords[:-1]))
        want -= sum(abs(_area2(h.coords[:-1])) for h in f.interiors)
        got = Fraction(0)
        for (u, v), (left, right) in zip(E, sides):
            got += (int(left == r) - int(right == r)) * _cross(V[u], V[v])
        assert got == want, (r, float(got), float(want))


def test_region_areas_allow_rounding_far_from_the_origin_only():
    """A zone 1e-4 across 1e7 from the origin: its mesh's area is off by the
    rounding of its boundary points (more than 1e-9 of P, less than the slack);
    the slack is still far below one triangle, so a missing one is caught."""
    P = domain("c_closed_1000000049")
    pts, tri = _mesh(P, "tplus", 227)
    reg = triangle_regions(P, pts, tri)
    p = pts[tri]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))  # fmt: skip
    off = np.abs(np.bincount(reg, weights=area) - P.regions.areas)
    assert off.max() > 1e-9 * P.area
    r = int(np.argmax(off))
    drop = np.flatnonzero(reg == r)[np.argmin(area[reg == r])]
    with pytest.raises(uniform2d.InvalidArgumentError, match=f"in region {r} cover"):
        triangle_regions(P, pts, np.delete(tri, drop, axis=0))
    near = Polygon(SQUARE, segments=[[(0.2, 0.2), (0.4, 0.2), (0.3, 0.4), (0.2, 0.2)]])
    pts, tri = _mesh(near, "insert", 30)
    d1, d2 = pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]]
    smallest = np.argmin(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    with pytest.raises(uniform2d.InvalidArgumentError, match="cover"):
        triangle_regions(near, pts, np.delete(tri, smallest, axis=0))


def test_a_segment_along_a_ring_edge_within_rounding_is_refused():
    """c_near_26's second segment runs 1 ulp beside a ring edge: at these
    coordinates it overlaps the edge (no point fits between them)."""
    with pytest.raises(InvalidConstraintError,
                       match=r"segment 1 runs along the outer ring \(they overlap near \("):
        domain("c_near_26")


@pytest.mark.parametrize("k", [1, 2, 3])
def test_fixed_point_near_an_edge_joins_it_up_to_two_ulps(k):
    """(0.5, k ulp) beside edge (0, 0)-(1, 0): on it for k <= 2 (decided exactly),
    inside for k = 3; INSERT meshes both."""
    P = Polygon(SQUARE, points=[(0.5, k * U)])
    assert (P.fixed[0] == 1) if k <= 2 else (P.fixed[0] == 4 and P.n_ring_vertices == 4)
    if k <= 2:
        assert P.outer.tolist() == [[0, 0], [0.5, k * U], [1, 0], [1, 1], [0, 1]]
    res = uniform2d.insert(P, 40)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=40)


def test_segment_ending_a_rounding_across_an_edge_is_a_t_junction():
    """A segment ending 1 ulp beyond edge (0, 0)-(1, 0) ends on it (a
    T-junction); 3 ulps beyond, it crosses the edge and is refused."""
    P = Polygon(SQUARE, segments=[[(0.5, 0.5), (0.5, -U)]])
    assert P.outer.tolist() == [[0, 0], [0.5, -U], [1, 0], [1, 1], [0, 1]]
    assert P.segment_edges.tolist() == [[5, 1]]
    res = uniform2d.insert(P, 40)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=40)
    assert len(P.regions) == 1
    with pytest.raises(InvalidConstraintError, match="segment 0 crosses the outer ring"):
        Polygon(SQUARE, segments=[[(0.5, 0.5), (0.5, -3 * U)]])


def test_segment_nearly_along_another_is_refused_and_one_ending_beside_it_splits_it():
    """Segment 1 within an ulp of segment 0 over (0.2..0.4, 0.5) runs along it
    (refused, both named and where); a segment ending an ulp beside segment 0
    splits it there."""
    h = float(np.spacing(0.5))
    seg0 = [(0.1, 0.5), (0.9, 0.5)]
    with pytest.raises(InvalidConstraintError,
                       match=r"segment 1 runs along segment 0 \(they overlap near \(0\.2"):
        Polygon(SQUARE, segments=[seg0, [(0.2, 0.5 + h), (0.4, 0.5 + h)]])
    P = Polygon(SQUARE, segments=[seg0, [(0.3, 0.5 + h), (0.3, 0.9)]])
    assert P.split_segments()[0].tolist() == [[0.1, 0.5], [0.3, 0.5 + h], [0.9, 0.5]]
    res = uniform2d.insert(P, 40)
    check_mesh(res.mesh_points, res.triangles, P, n_steiner=40)
    triangle_regions(P, res.mesh_points, res.triangles)


def test_a_point_within_rounding_of_two_ring_edges_is_refused():
    """(1 - ulp, ulp) is within 2 ulps of both edges at the corner (1, 0): it
    cannot join the ring twice, and is refused naming both edges."""
    with pytest.raises(InvalidConstraintError,
                       match=r"lies on both the outer ring edge 0 and the outer ring edge 1"):
        Polygon(SQUARE, points=[(1 - U, U)])
    P = Polygon(SQUARE, points=[(1 - 8 * U, 8 * U)])  # clear of both: inside
    assert P.n_ring_vertices == 4 and P.fixed.tolist() == [4]


def test_region_chains_take_a_vertex_the_library_puts_on_the_piece():
    """Fixed point 16 of c_near_11000000120 lies 10 ulps off piece 10-11 (not a
    junction), within the boundary tolerance: the mesh's chain of the piece runs
    through it, and the region check follows that chain."""
    from uniform2d.mesh_regions import segment_chains as region_chains

    P = domain("c_near_11000000120")
    assert P.segment_edges[0].tolist() == [10, 11] and P.fixed.tolist() == [16]
    res = uniform2d.insert(P, 181)
    edges, ids = region_chains(P, res.mesh_points, res.triangles)
    assert edges[ids == 0].tolist() == [[10, 16], [16, 11]]


# -- fuzz seeds 9 and 10: segments leaving one vertex at a tiny angle ----------------
BOX = [(-1, -1), (2, -1), (2, 2), (-1, 2)]


def _fan(offset):
    return Polygon(BOX, segments=[[(0, 0), (1, 0.3)], [(0, 0), (1, 0.3 + offset)]])


def test_segments_closer_than_insert_can_keep_apart_are_refused():
    """Far ends 1e-10 apart in a polygon 3 across: INSERT's tie tolerance is
    3e-9 there, the mesh lost one of the two pieces; now the polygon is refused,
    naming both segments, the place and the distance to keep."""
    tol = constraints.apart_tol([np.array(BOX)], [np.array([(0.0, 0.0), (1.0, 0.3)])])
    assert tol == pytest.approx(3e-9, rel=1e-5)
    with pytest.raises(InvalidConstraintError,
                       match=r"segment 1 \(piece 0\) runs along segment 0") as exc:
        _fan(1e-10)
    assert "(0, 0)" in str(exc.value) and "(1, 0.2999" in str(exc.value)
    assert f"more than {tol:.3g} apart" in str(exc.value)


@pytest.mark.parametrize("factor", [1.5, 3.0, 100.0])
def test_segments_just_farther_apart_mesh(factor):
    """Just beyond that distance the fan is accepted and every mesh keeps both
    pieces as chains of edges (check_mesh)."""
    tol = constraints.apart_tol([np.array(BOX)], [np.array([(0.0, 0.0), (1.0, 0.3)])])
    P = _fan(factor * tol)
    for n in (200, 2000):
        res = uniform2d.insert(P, n)
        check_mesh(res.mesh_points, res.triangles, P, n_steiner=n)


def test_apart_rule_is_exact_at_its_tolerance():
    """The rule compares exact distances with the tolerance: an end at exactly
    the tolerance from the other piece is near, one a rational hair beyond is not."""
    a, b = (Fraction(0), Fraction(0)), (Fraction(1), Fraction(0))
    tol = Fraction(1, 10**9)
    assert constraints._dist2_to_piece((Fraction(1, 2), tol), a, b) == tol * tol
    assert constraints._dist2_to_piece((Fraction(2), tol), a, b) == 1 + tol * tol


NEAR_161 = {
    "outer": [
        [5165346.947666551, 141.480883381982],
        [5165346.921437861, 141.53879698756748],
        [5165346.782908432, 141.53067051981435],
        [5165346.790254716, 141.46505506009586],
    ],
    "segments": [
        [[5165346.852173149, 141.53473372470168], [5165346.853291465, 141.51567013244622]],
        [[5165346.893731981, 141.53717160704917], [5165346.866026099, 141.5355462555201]],
        [[5165346.853291465, 141.51567013244622], [5165346.854409784, 141.49660651132092]],
        [[5165346.853291465, 141.51567013244622], [5165346.854409782, 141.4966065112015]],
    ],
    "points": [
        [5165346.852732277, 141.52520194136798],
    ],
}  # fmt: skip


def test_fuzz_crash_two_pieces_two_ulps_apart_refused():
    """Seed 9 c_near 9000000161 (insert n = 388 lost a piece): the two segments
    leave vertex (5165346.853..., 141.515...) at ~1e-7, far ends 2 ulps apart."""
    with pytest.raises(InvalidConstraintError, match=r"segment 3 \(piece 0\) runs along segment 2"):
        Polygon(NEAR_161["outer"], segments=NEAR_161["segments"], points=NEAR_161["points"])


def test_tplus_refusal_states_a_true_lower_bound():
    """Where d_n keeps falling (a thin wedge between two segments), the search
    for the smallest n stops as soon as the d_n it found bounds k above the
    search limit for every larger n; the bound is recomputed here from INSERT
    (seed 9 c_near 9000000102, where T+ searched for minutes)."""
    P = domain("c_near_9000000102")
    with pytest.raises(InsufficientPointsError, match="in vain") as exc:
        uniform2d.tplus(P, 66)
    msg = str(exc.value)
    at = int(msg.split("every n from ")[1].split()[0])
    least = int(msg.split("needs at least ")[1].split()[0])
    d_at = uniform2d.insert(P, at).min_distance()
    assert least == least_k(P, 3.0, d_at) > SEARCH_LIMIT
    # d_n never grows with n: INSERT's first points are the same for a larger n
    assert uniform2d.insert(P, at + 500).min_distance() <= d_at
    _, pts, _, m = _phase1(P, at, 3.0)
    assert (int(m.sum() - len(m)) if pts is None else len(pts)) >= least > at


def test_tplus_refuses_soon_on_a_thin_wedge_domain():
    """Seed 10 c_near 10000000151 (T+ n = 5 searched for minutes: a long ring
    edge shadowed by a segment 0.002 from it made INSERT slow near n = 40000,
    and d_n falls there): one run past the lower bound, then a refusal saying
    why."""
    P = domain("c_near_10000000151")
    with pytest.raises(InsufficientPointsError, match="in vain"):
        uniform2d.tplus(P, 5)


# -- INSERT's subsegment evaluation gathers only the sites within its bound ----------
@njit
def _all_evaluations(m, tight):
    """(value, x, y) of every constrained half-edge's evaluation: with no bound,
    or (tight) with its own exact value as the bound."""
    out = np.full((3 * m.nt, 3), np.nan)
    for h in range(3 * m.nt):
        if m.tw[h] < 0 or m.tc[h] != 0:
            w, x, y = eval_segment(m, h, 1e-9, np.inf)
            if tight:
                w, x, y = eval_segment(m, h, 1e-9, w)
            out[h, 0], out[h, 1], out[h, 2] = w, x, y
    return out


@pytest.mark.parametrize("seed,n", [(5000000098, 3000), (10000000151, 2000)])
def test_subsegment_bound_changes_no_evaluation(seed, n):
    """A bound as tight as the value itself gathers fewer sites and gives the
    same (value, point), bit for bit, on every constrained subsegment of
    domains where a segment runs close beside a ring edge."""
    from uniform2d.testing.fuzz import constrained

    from uniform2d._kernel import heap
    from uniform2d._kernel import insert as kinsert
    from uniform2d.sites import site_edges
    from uniform2d.triangulation import load

    _, o, h, s, p = constrained(seed)
    P = Polygon(o, h, segments=s, points=p)
    sites, edges = site_edges(P, None)
    loaded = load(P, sites, size=None, room=n, edges=edges)
    m, tmax = loaded.m, loaded.max_triangles
    M = heap.new_heap(tmax + tmax // 2 + 64)
    kinsert.push_initial(m, M)
    xy, w, b = np.empty((n, 2)), np.empty(n), np.zeros(n, np.bool_)
    assert kinsert.run(m, M, kinsert.new_pool(64), n, xy, w, b, 1e-9, 1e-12) == n
    loose, tight = _all_evaluations(m, False), _all_evaluations(m, True)
    done = ~np.isnan(loose[:, 0])
    assert done.sum() > 100
    assert np.array_equal(loose[done], tight[done])


def test_tplus_names_the_smallest_n_on_a_shadowed_ring_edge():
    """Seed 5 c_near 5000000098 (T+ n = 216 searched for over 5 minutes, INSERT
    slowing near n = 35000): the search jumps to the k a failed n needed and
    names an n that works while the one below does not."""
    from uniform2d.testing.fuzz import constrained

    from uniform2d.tplus import _k

    _, o, h, s, p = constrained(5000000098)
    P = Polygon(o, h, segments=s, points=p)
    with pytest.raises(InsufficientPointsError,
                       match=r"smallest n that works for this polygon is (\d+)") as exc:
        uniform2d.tplus(P, 216)
    need = int(str(exc.value).rsplit(" ", 1)[1])
    assert _k(P, need, 3.0)[0] <= need < _k(P, need - 1, 3.0)[0] + 1
