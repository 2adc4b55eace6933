"""The outline stages' compiled point-to-segment distances: the same bits as the
numpy function they stand for, and the right geometry."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from uniform2d import segment_distance as sd
from uniform2d.geometry import point_segment_distance as numpy_distance


def cases(seed, k, scale, shift):
    """Points and segments at one scale, a few of them zero-length, some points
    on the segments' ends and lines."""
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(k, 2)) * scale + shift
    A = P + rng.normal(size=(k, 2)) * scale
    B = A + rng.normal(size=(k, 2)) * scale
    B[::11] = A[::11]
    P[1::13] = A[1::13]
    P[2::13] = 0.5 * (A[2::13] + B[2::13])
    return P, A, B


@pytest.mark.parametrize("scale,shift", [(1.0, 0.0), (1e-6, 0.0), (1e6, 0.0), (1.0, 1e6), (1e-3, -3e5)])
def test_rowwise_is_the_numpy_function_bit_for_bit(scale, shift):
    P, A, B = cases(1, 20000, scale, shift)
    np.testing.assert_array_equal(sd.point_segment_distance(P, A, B), numpy_distance(P, A, B))


@pytest.mark.parametrize("scale,shift", [(1.0, 0.0), (1e-6, 0.0), (1e6, 0.0), (1.0, 1e6)])
def test_from_a_point_and_nearest_are_the_broadcast_numpy_bits(scale, shift):
    P, A, B = cases(2, 400, scale, shift)
    for X in P[:25]:
        want = numpy_distance(np.broadcast_to(X, A.shape), A, B)
        np.testing.assert_array_equal(sd.from_point(X, A, B), want)
    Z = P[:300]
    want = np.array([numpy_distance(np.broadcast_to(z, A.shape), A, B).min() for z in Z])
    np.testing.assert_array_equal(sd.nearest(Z, A, B), want)


def test_the_geometry_against_geos_and_the_empty_cases():
    P, A, B = cases(3, 300, 1.0, 0.0)
    parts = [shapely.Point(a) if np.array_equal(a, b) else shapely.LineString([a, b])
             for a, b in zip(A, B)]
    want = shapely.distance(shapely.GeometryCollection(parts), shapely.points(P))
    np.testing.assert_allclose(sd.nearest(P, A, B), want, rtol=1e-12, atol=1e-14)
    assert np.isinf(sd.nearest(P[:3], A[:0], B[:0])).all()
    assert sd.from_point(P[0], A[:0], B[:0]).shape == (0,)


def test_inputs_are_read_not_modified_and_may_be_views():
    P, A, B = cases(4, 50, 1.0, 0.0)
    keep = [P.copy(), A.copy(), B.copy()]
    got = sd.point_segment_distance(P[::2], A[::2], B[::2].tolist())
    np.testing.assert_array_equal(got, numpy_distance(P[::2], A[::2], B[::2]))
    for a, b in zip((P, A, B), keep):
        np.testing.assert_array_equal(a, b)


def test_other_dimensions_go_to_numpy():
    rng = np.random.default_rng(5)
    P, A, B = (rng.normal(size=(200, 3)) for _ in range(3))
    np.testing.assert_array_equal(sd.point_segment_distance(P, A, B), numpy_distance(P, A, B))
    # a 3-D distance differs from the distance of the first two coordinates
    assert not np.array_equal(sd.point_segment_distance(P, A, B),
                              sd.point_segment_distance(P[:, :2], A[:, :2], B[:, :2]))
