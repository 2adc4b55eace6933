"""GEOS's triangulation of a polygon's rings is kept for the next start with the
same rings (uniform2d.triangulation._ring_triangles): the same triangles as
made afresh, and a caller's copy cannot change what is kept."""

from __future__ import annotations

import numpy as np
import shapely
from support.benchmarks import benchmark_polygons

from uniform2d.testing import check_mesh
from uniform2d.triangulation import _initial_triangles, _ring_triangles, _stages, triangulate


def _rings(p):
    return [list(range(p.ring_offsets[r], p.ring_offsets[r + 1])) for r in range(len(p.rings))]


def test_kept_triangles_are_those_made_afresh_and_stay_unchanged():
    p = benchmark_polygons()["square2holes"]
    rings = _rings(p)
    first = _initial_triangles(p.vertices, rings)
    idx = np.concatenate([np.asarray(r, dtype=np.int64) for r in rings])
    key = (np.ascontiguousarray(p.vertices[idx]).tobytes(), idx.tobytes(),
           tuple(len(r) for r in rings))
    fresh = _ring_triangles.__wrapped__(key)
    assert np.array_equal(first, fresh)
    first[:] = 0  # the caller's copy
    again = _initial_triangles(p.vertices, rings)
    assert np.array_equal(again, fresh) and again is not first
    # moved coordinates are other rings: not the kept triangles
    moved = p.vertices * 2.0
    other = _initial_triangles(moved, rings)
    assert np.array_equal(other, _ring_triangles.__wrapped__(
        (np.ascontiguousarray(moved[idx]).tobytes(), key[1], key[2])))


def test_a_mesh_from_kept_triangles_is_the_mesh_made_afresh():
    p = benchmark_polygons()["star10"]
    rng = np.random.default_rng(3)
    lo, hi = p.vertices.min(0), p.vertices.max(0)
    sites = lo + (hi - lo) * rng.random((400, 2))
    sites = sites[shapely.contains_xy(p.to_shapely(), sites[:, 0], sites[:, 1])]
    _ring_triangles.cache_clear()
    fresh = triangulate(p, sites)
    assert _ring_triangles.cache_info().misses == 1
    _stages.clear()  # (else the rings' whole triangulation is kept: test_stages.py)
    kept = triangulate(p, sites)
    assert _ring_triangles.cache_info().hits == 1
    check_mesh(*kept, p)
    assert fresh[0].tobytes() == kept[0].tobytes() and fresh[1].tobytes() == kept[1].tobytes()
