"""Shift moves for the worst angle (:mod:`uniform2d.optimize.shift`).

The floor below is Gmsh's worst angle on ``heptagon_short`` at n = 300
(Frontal-Delaunay, size bisected to the count as in
``benchmarks/bench_uniform.py``, measured once: 43.18 deg), which the mesh
before the shift did not reach (42.86 deg).
"""

import numpy as np
import pytest
from support.benchmarks import benchmark_polygons
from support.boundary_edges import edges_of

import uniform2d
from uniform2d.optimize import anglefit, shift
from uniform2d.optimize.angles import MIN_GAIN
from uniform2d.optimize.boundary import target_size
from uniform2d.quality import quality
from uniform2d.testing import check_mesh
from uniform2d.threads import set_threads

POLYGONS = benchmark_polygons()


def test_heptagon_short_reaches_gmsh_angle():
    p = POLYGONS["heptagon_short"]
    m = uniform2d.uniform_mesh(p, 300)
    check_mesh(m.points, m.triangles, p)
    assert m.n_steiner == 300 and len(m.points) == 300 + len(p.vertices)
    assert m.quality().min_angle >= 43.18


@pytest.fixture
def unshifted(monkeypatch):
    """star10's mesh at n = 300 made without the shift."""
    p = POLYGONS["star10"]
    monkeypatch.setattr(shift, "SHIFT_BELOW", 0.0)
    monkeypatch.setattr(anglefit, "FIT_BELOW", 0.0)  # the fit after the shift: left out too
    m = uniform2d.uniform_mesh(p, 300)
    monkeypatch.undo()
    return p, m


def test_shift_raises_worst_angle_within_slack(unshifted):
    p, m = unshifted
    nV = len(p.vertices)
    edges = edges_of(p, m.points)
    pts0, tri0 = m.points.copy(), m.triangles.copy()
    q0 = quality(m.points, m.triangles)
    assert q0.min_angle < shift.SHIFT_BELOW
    h = target_size(p, 300)
    frozen = np.zeros(len(m.points) - nV, bool)
    pts, tri, kept, e2 = shift.shift_worst(p, m.points, m.triangles, frozen, "balanced", h, {},
                                           edges)
    assert np.array_equal(m.points, pts0) and np.array_equal(m.triangles, tri0)  # not mutated
    assert kept == 1
    check_mesh(pts, tri, p)
    assert len(pts) == len(pts0) and np.array_equal(pts[:nV], p.vertices)
    assert np.array_equal(edges_of(p, pts), e2)  # boundary sites stayed on their edges
    assert np.array_equal(np.sort(e2), np.sort(edges))  # and every edge kept its count
    q = quality(pts, tri)
    assert q.min_angle >= q0.min_angle + MIN_GAIN
    for k in ("edge_ratio", "longest_edge", "max_perimeter", "cv_edge"):
        assert getattr(q, k) <= getattr(q0, k) * (1 + shift.SLACK)


def test_fine_meshes_left_alone(unshifted, monkeypatch):
    """A mesh whose worst angle is SHIFT_BELOW or more comes back as it is."""
    p, m = unshifted
    nV = len(p.vertices)
    frozen = np.zeros(len(m.points) - nV, bool)
    monkeypatch.setattr(shift, "SHIFT_BELOW", quality(m.points, m.triangles).min_angle)
    out = shift.shift_worst(p, m.points, m.triangles, frozen, "balanced", target_size(p, 300),
                            {}, edges_of(p, m.points))
    assert out[0] is m.points and out[1] is m.triangles and out[2] == 0


def test_same_mesh_on_any_thread_count():
    p = POLYGONS["star10"]
    out = []
    try:
        for k in (1, 2):
            set_threads(k)
            m = uniform2d.uniform_mesh(p, 300)
            out.append(m.points.tobytes() + m.triangles.tobytes())
    finally:
        set_threads(None)
    assert out[0] == out[1]
