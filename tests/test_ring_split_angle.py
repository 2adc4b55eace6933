"""Whole ring edges halved for the worst angle (uniform2d.ring_split.edges_for_angle):
the edges named against a brute-force reference, and Triangle's square with a
circular hole (meshed as given: its own edges of 1.3 to 1.9 spacings) gaining on
its worst angle over the mesh without resample, with the rings the same point
set, exact n and an edge ratio still at most 2."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from support.halved_rings import plain_edges

import uniform2d as u
from uniform2d.optimize import optimize_mesh
from uniform2d.ring_split import (
    ANGLE_BELOW, HALF_REACH, SPLIT_LONG, SPLIT_RATIO, better_angle, edges_for_angle,
)
from uniform2d.testing import check_mesh

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"
N = 2000


def _angles(P, T):
    """The smallest angle of each triangle by the law of cosines, one by one."""
    out = []
    for tri in T.tolist():
        q = P[tri]
        s = [float(np.hypot(*(q[(i + 1) % 3] - q[(i + 2) % 3]))) for i in range(3)]
        out.append(min(np.degrees(np.arccos((s[(i + 1) % 3] ** 2 + s[(i + 2) % 3] ** 2 - s[i] ** 2)
                                            / (2 * s[(i + 1) % 3] * s[(i + 2) % 3])))
                       for i in range(3)))
    return out


def _reference(polygon, P, T):
    """edges_for_angle by plain Python sets and loops."""
    edges, length, ring = plain_edges(polygon, P, T)
    mean = sum(length.values()) / len(length)
    long = {e for e in edges & ring if length[e] >= SPLIT_LONG * mean}
    angles = _angles(P, T)
    worst = min(range(len(T)), key=angles.__getitem__)
    a, b, c = T[worst].tolist()
    sides = {(min(x, y), max(x, y)) for x, y in ((a, b), (b, c), (c, a))}
    if angles[worst] >= ANGLE_BELOW or not sides & long:
        return []
    if len(sides & ring) >= 2:                        # a corner's one triangle
        return []
    ratio = max(max(length.values()) / min(length.values()), SPLIT_RATIO)
    if min(length[e] for e in long) / 2 * ratio < HALF_REACH * max(length[e] for e in edges - long):
        return []
    return sorted(long)


@pytest.fixture(scope="module")
def square_hole():
    p = u.read_polygon(OUTLINES / "triangle_square_circle_hole.json")
    return p, u.uniform_mesh(p, N), u.uniform_mesh(p, N, resample=0.25)


def test_edges_named_as_the_reference_names_them(square_hole):
    p, first, _ = square_hole
    pairs = edges_for_angle(p, first.points, first.triangles)
    assert len(pairs) > 0
    assert pairs.tolist() == [list(e) for e in _reference(p, first.points, first.triangles)]
    circle = u.Polygon([(np.cos(t), np.sin(t)) for t in np.linspace(0, 2 * np.pi, 40,
                                                                     endpoint=False)])
    m = optimize_mesh(circle, 300)   # edges of 0.16, the mesh's about 0.11: none that long
    assert edges_for_angle(circle, m.points, m.triangles).tolist() \
        == [list(e) for e in _reference(circle, m.points, m.triangles)]


def test_a_corners_one_triangle_is_not_halved_for():
    """A spike of 19 degrees between ring edges of 3.04 (mean edge about 1.2): its
    tip's triangle is the worst, its two long sides whole ring edges, but the angle
    is the outline's own; the same polygon with the tip's triangle split is halved."""
    from uniform2d.triangulation import triangulate
    ring = ([(x, 0) for x in range(6)] + [(6, y) for y in range(5)]
            + [(5, 4), (4, 4), (3.5, 4), (3, 7), (2.5, 4), (2, 4), (1, 4)]
            + [(0, y) for y in range(4, 0, -1)])
    spike = u.Polygon(ring)
    inside = [(x, y) for x in range(1, 6) for y in range(1, 4)]
    P, T = triangulate(spike, inside)
    assert min(_angles(P, T)) < 20
    assert edges_for_angle(spike, P, T).tolist() == _reference(spike, P, T) == []
    P, T = triangulate(spike, [*inside, (3, 4.6)])      # a point inside the spike
    named = edges_for_angle(spike, P, T).tolist()
    assert named == [list(e) for e in _reference(spike, P, T)] and len(named) > 0


def test_square_with_a_hole_gains_its_worst_angle(square_hole):
    p, first, m = square_hole
    q0, q = first.quality(), m.quality()
    k = m.info["resample"]["halved_for_angle"]
    assert k > 0 and not m.info["resample"]["resampled"]
    assert len(m.points) == len(p.vertices) + N            # n exact, the midpoints in it
    assert len(m.polygon.vertices) == len(p.vertices) + k
    assert min(_angles(m.points, m.triangles)) > max(35.0, q0.min_angle + 5)   # 28.2 as given
    assert q.edge_ratio <= 2 and better_angle(q, q0)
    # the same rings as point sets: every input vertex stays, every new one on an input edge
    kept = {tuple(v) for v in m.polygon.vertices.tolist()}
    assert all(tuple(v) in kept for v in p.vertices.tolist())
    lines = shapely.MultiLineString([np.vstack([r, r[:1]]) for r in p.rings])
    new = [v for v in m.polygon.vertices.tolist() if v not in p.vertices.tolist()]
    assert len(new) == k and max(lines.distance(shapely.Point(v)) for v in new) < 1e-12
    check_mesh(m.points, m.triangles, m.polygon)


def test_worst_angle_against_gmsh_on_the_same_polygon(square_hole):
    """Gmsh on the same polygon at the same vertex count: the halving closes most
    of the gap (28.2 against Gmsh's 37.6 degrees before; 35.5 now)."""
    pytest.importorskip("gmsh")
    from uniform2d.peers import gmsh_peer
    p, first, m = square_hole
    g = gmsh_peer.mesh(p, len(m.points))
    ours, peer = min(_angles(m.points, m.triangles)), min(_angles(g.points, g.triangles))
    before = first.quality().min_angle
    assert peer - ours < 0.3 * (peer - before)
