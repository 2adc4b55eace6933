"""The constraint model: Polygon(segments=, points=), junctions decided exactly."""

from fractions import Fraction

import numpy as np
import pytest

from uniform2d import InvalidConstraintError, InvalidPolygonError, Polygon

SQ = [(0, 0), (10, 0), (10, 10), (0, 10)]
HOLE = [(6, 6), (8, 6), (8, 8), (6, 8)]


def _on_piece(p, a, b) -> bool:
    """p on the closed segment a-b, in exact rationals."""
    p, a, b = ([Fraction(float(c)) for c in q] for q in (p, a, b))
    cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    return cross == 0 and min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def test_plain_polygon_unchanged():
    p = Polygon(SQ, [HOLE])
    assert not p.has_constraints
    assert p.n_ring_vertices == len(p.vertices) == 8
    assert p.segment_edges.shape == (0, 2) and p.fixed.shape == (0,)


def test_t_junction_joins_ring_and_points_split_segments():
    p = Polygon(SQ, [HOLE], segments=[[(1, 1), (5, 1), (5, 5), (1, 5), (1, 1)], [(3, 0), (3, 1)],
                                     [(5, 3), (9, 3)]], points=[(3, 3), (5, 2), (7, 3), (1, 1)])
    V = p.vertices
    assert [3.0, 0.0] in p.outer.tolist()
    # every vertex lies on no piece except as its end (pieces split at every junction)
    for a, b in p.segment_edges:
        for k in range(len(V)):
            if k not in (a, b):
                assert not (_on_piece(V[k], V[a], V[b])), (k, a, b)
    # fixed points are vertices, exactly where given
    assert np.array_equal(V[p.fixed], p.points)
    # the pieces of each segment chain end to end and cover the given polyline
    for s, line in enumerate(p.segments):
        e = p.segment_edges[p.segment_ids == s]
        assert np.array_equal(e[1:, 0], e[:-1, 1])
        assert np.array_equal(V[e[0, 0]], line[0]) and np.array_equal(V[e[-1, 1]], line[-1])
    assert p.area == 96.0 and p.perimeter == 48.0


@pytest.mark.parametrize("scale, offset", [(1e-6, (0, 0)), (1e6, (0, 0)), (1.0, (1e6, -1e6)), (3.7, (1e5, 2))])
def test_transformed_keeps_the_graph(scale, offset):
    p = Polygon(SQ, segments=[[(1, 1), (9, 1)], [(5, 1), (5, 9)]], points=[(3, 1), (5, 5)])
    q = p.transformed(scale, offset)
    assert np.array_equal(q.segment_edges, p.segment_edges)
    assert np.array_equal(q.fixed, p.fixed)
    assert len(q.vertices) == len(p.vertices)


@pytest.mark.parametrize("kw, words", [
    (dict(segments=[[(1, 1), (11, 1)]]), "crosses the outer ring at (10, 1)"),
    (dict(segments=[[(7, 7), (7.5, 7.5)]]), "inside hole 0"),
    (dict(segments=[[(1, 1), (5, 5)], [(1, 5), (5, 1)]]), "segment 1 crosses segment 0 at (3, 3)"),
    (dict(segments=[[(1, 1), (5, 1)], [(3, 1), (7, 1)]]), "overlap"),
    (dict(segments=[[(0, 0), (5, 0)]]), "runs along the outer ring"),
    (dict(points=[(11, 1)]), "outside the polygon"),
    (dict(points=[(7, 7)]), "inside hole 0"),
    (dict(points=[(1, 1), (1, 1)]), "points 0 and 1 are the same point"),
    (dict(segments=[[(1, 1), (3, 1), (2, 1)]]), "folds back"),
    (dict(segments=[[(1, 1), (1, 1)]]), "zero-length"),
    (dict(segments=[[(1, 1), (4, 1), (2, 3), (2, 0.5)]]), "crosses itself"),
    (dict(segments=[(1, 1), (2, 2)]), "wrap a single one"),
    (dict(segments=[[(1, 1), (np.nan, 2)]]), "non-finite"),
])
def test_bad_constraints_are_refused_with_the_place(kw, words):
    with pytest.raises(InvalidConstraintError, match=None) as exc:
        Polygon(SQ, [HOLE], **kw)
    assert words in str(exc.value)
    assert isinstance(exc.value, InvalidPolygonError) and isinstance(exc.value, ValueError)


def test_t_junction_on_hole():
    p = Polygon(SQ, [HOLE], segments=[[(0, 5), (6, 7)]])
    assert [6.0, 7.0] in p.holes[0].tolist()
    assert [0.0, 5.0] in p.outer.tolist() and p.n_ring_vertices == 10
