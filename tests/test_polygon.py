"""The polygon model: normalisation, derived quantities, and one typed error with a
useful message for every kind of invalid input (and for bad arguments to insert)."""

import math

import numpy as np
import pytest

import uniform2d
from uniform2d import InsufficientPointsError, InvalidPolygonError, InvalidSitesError, Polygon

SQ = [(0, 0), (4, 0), (4, 4), (0, 4)]


def test_orientation_is_normalised_and_first_vertex_kept():
    cw_outer = SQ[::-1]
    ccw_hole = [(1, 1), (2, 1), (2, 2), (1, 2)]
    P = Polygon(cw_outer, [ccw_hole])
    x, y = P.outer.T
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0  # outer CCW
    hx, hy = P.holes[0].T
    assert 0.5 * np.sum(hx * np.roll(hy, -1) - np.roll(hx, -1) * hy) < 0  # hole CW
    assert tuple(P.outer[0]) == cw_outer[0] and tuple(P.holes[0][0]) == ccw_hole[0]
    assert P.area == 16 - 1 and P.perimeter == 16 + 4 and P.n_holes == 1
    assert P.vertices.shape == (8, 2) and len(P.rings) == 2
    assert np.array_equal(P.vertices[P.ring_offsets[1]:], P.holes[0])


def test_closing_vertex_dropped_and_collinear_vertices_kept():
    P = Polygon([(0, 0), (1, 0), (2, 0), (2, 1), (0, 1), (0, 0)])
    assert len(P.vertices) == 5  # (1, 0) is collinear but is a site
    assert P.area == 2.0
    angles = P.interior_angles()
    assert math.isclose(angles[1], math.pi)


def _exact_area(rings):
    """Shoelace of the float coordinates in rational arithmetic (signed by ring)."""
    from fractions import Fraction

    total = Fraction(0)
    for r in rings:
        q = [(Fraction(float(x)), Fraction(float(y))) for x, y in r]
        total += sum(q[i - 1][0] * q[i][1] - q[i][0] * q[i - 1][1] for i in range(len(q))) / 2
    return total


@pytest.mark.parametrize("scale", [1e-6, 1.0, 1e6])
@pytest.mark.parametrize("offset", [0.0, 1e3, 1e6])
def test_area_is_accurate_far_from_the_origin(scale, offset):
    # absolute-coordinate shoelace terms are offset**2 large and cancel: a unit
    # ring 1000 units away lost about 1e-9 of its area that way
    rng = np.random.default_rng(7)
    outer = np.array([(0.0, 0.0), (3.1, 0.2), (2.7, 2.9), (0.4, 2.2)]) + rng.uniform(0, 0.1, (4, 2))
    hole = np.array([(1.0, 1.0), (1.3, 1.9), (1.9, 1.1)])
    rings = [(r * scale + offset * scale) for r in (outer, hole)]
    P = Polygon(rings[0], [rings[1]])
    exact = _exact_area(P.rings)
    assert exact > 0
    assert abs(P.area - float(exact)) <= 1e-14 * float(exact)


def test_inputs_are_not_mutated_and_arrays_are_read_only():
    outer = np.array(SQ, dtype=float)[::-1].copy()
    before = outer.copy()
    P = Polygon(outer)
    assert np.array_equal(outer, before)
    with pytest.raises(ValueError):
        P.vertices[0, 0] = 7.0


def test_min_vertex_distance_and_edges():
    P = Polygon([(0, 0), (3, 0), (3, 1), (0, 1)])
    assert P.min_vertex_distance() == 1.0
    assert P.edges.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]


def test_edges_made_once_are_handed_out_as_fresh_arrays():
    # the edges are made once (the optimiser reads them a hundred times a
    # mesh); a caller that writes into what it got changes nothing of P's
    P = Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 2), (2, 2), (2, 1)]],
                segments=[[(3, 0.5), (3, 3.5)]])
    E, C = P.edges, P.constraint_edges
    assert E.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]
    assert C.tolist() == E.tolist() + P.segment_edges.tolist() and len(C) == len(E) + 1
    E[:] = -1
    C[:] = -1
    assert P.edges.min() == 0 and P.constraint_edges.min() == 0
    assert P.edges is not P.edges


@pytest.mark.parametrize(
    "outer, holes, fragments",
    [
        ([(0, 0), (1, 1)], [], ["at least 3 distinct"]),
        ([(0, 0), (1, 0), (1, 0), (0, 0)], [], ["at least 3 distinct"]),
        ([(0, 0), (1, 0), (float("nan"), 1)], [], ["vertex 2", "non-finite", "NaN"]),
        ([(0, 0), (1, 0), (1, float("inf"))], [], ["vertex 2", "non-finite"]),
        ([(0, 0), (1, 0), (1, 0), (1, 1)], [], ["vertices 1 and 2", "same point", "remove"]),
        ([(0, 0), (1, 0), (2, 0)], [], ["zero area"]),
        ([(0, 0), (2, 2), (2, 0), (0, 3)], [], ["intersects itself"]),
        ([(0, 0), (2, 0), (1, 1), (2, 2), (0, 2), (1, 1)], [], ["appears more than once"]),
        ([(0, 0), (1, 2)], [], ["at least 3 distinct"]),
        ([[0, 0, 0], [1, 0, 0], [1, 1, 0]], [], ["(k, 2)"]),
        ([("a", 0), (1, 0), (1, 1)], [], ["numbers"]),
        (SQ, [[(5, 5), (6, 5), (6, 6)]], ["hole 0", "outside"]),
        (SQ, [[(3, 1), (5, 1), (5, 2), (3, 2)]], ["hole 0", "crosses the outer ring"]),
        (SQ, [[(0, 1), (1, 1), (1, 2)]], ["hole 0", "touches the outer ring"]),
        (SQ, [[(1, 1), (2, 1), (2, 2)], [(1.5, 1.2), (3, 1.2), (3, 3)]], ["holes 0 and 1", "overlap"]),
        (SQ, [[(1, 1), (2, 1), (2, 2)], [(2, 1), (3, 1), (3, 2)]], ["holes 0 and 1", "touch"]),
        (SQ, [[(1, 1), (2, 1), (3, 1)]], ["hole 0", "zero area"]),
        (SQ, [[(1, 1), (3, 3), (3, 1), (1, 3)]], ["hole 0", "intersects itself"]),
        ([], [], ["outer ring", "no vertices", "at least 3"]),
        (SQ, [[]], ["hole 0", "no vertices"]),
        (np.empty((0, 2)), [], ["outer ring", "no vertices"]),
        ([(0, 0), (1e150, 0), (1e150, 1e150)], [], ["outer ring", "1e+150", "rescale"]),
        ([(0, 0), (1e-150, 0), (1e-150, 1e-150)], [], ["outer ring", "1e-150 across", "rescale"]),
        (SQ, [[(1e-110, 1e-110), (2e-110, 1e-110), (2e-110, 2e-110)]], ["hole 0", "across"]),
    ],
)
def test_invalid_polygons_raise_with_a_useful_message(outer, holes, fragments):
    with pytest.raises(InvalidPolygonError) as e:
        Polygon(outer, holes)
    assert isinstance(e.value, ValueError)
    msg = str(e.value)
    for f in fragments:
        assert f in msg, (f, msg)


@pytest.mark.parametrize("s", [1e-99, 1e99])
def test_coordinates_within_the_float64_range_are_accepted(s):
    P = Polygon(np.array(SQ) * s)
    assert P.area == 16 * s * s and P.perimeter == 16 * s


def test_single_hole_array_is_refused_with_a_hint():
    with pytest.raises(InvalidPolygonError, match=r"wrap a single hole as \[hole\]"):
        Polygon(SQ, np.array([(1, 1), (2, 1), (2, 2)], float))


@pytest.mark.parametrize(
    "sites, fragment",
    [
        ([(5, 5)], "outside the polygon"),
        ([(1, 1), (1, 1)], "more than once"),
        ([(0, 0)], "coincides with polygon vertex 0"),
        ([(1, float("nan"))], "non-finite"),
        ("abc", "(k, 2) array"),
    ],
)
def test_insert_rejects_bad_sites(sites, fragment):
    with pytest.raises(InvalidSitesError) as e:
        uniform2d.insert(Polygon(SQ), 3, sites=sites)
    assert fragment in str(e.value)


@pytest.mark.parametrize("n", [-1, 2.5, True, "3"])
def test_insert_rejects_bad_n(n):
    with pytest.raises(InsufficientPointsError, match="non-negative integer"):
        uniform2d.insert(Polygon(SQ), n)


def test_sites_on_the_boundary_and_inside_are_used():
    r = uniform2d.insert(Polygon(SQ), 5, sites=[(2, 0), (1, 1)])
    assert np.array_equal(r.mesh_points[4:6], [(2, 0), (1, 1)])
    assert len(r.mesh_points) == 4 + 2 + 5
