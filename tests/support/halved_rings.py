"""The rings a resampled mesh was made of: the resampled polygon, with the ring
edges uniform_mesh halved (uniform2d.ring_split) as midpoints inserted; and a
resampled mesh checked against its outline.  Both are about the mesh before
ring points are moved off its short edges (uniform2d.ring_nudge), which moves
ring points after halving."""

from __future__ import annotations

import numpy as np
import shapely

import uniform2d.ring_nudge as ring_nudge
from uniform2d import uniform_mesh
from uniform2d.outline import resample_polygon
from uniform2d.testing import check_mesh


def assert_halved_from(mesh, polygon) -> None:
    """Assert ``mesh.polygon``'s rings are ``polygon``'s with exactly
    ``mesh.info["resample"]["halved_edges"]`` ring edges halved: dropping the
    mesh polygon's ring vertices that are no vertex of ``polygon`` leaves
    ``polygon``'s ring vertices bit for bit, and each dropped one is the exact
    midpoint of its two neighbours."""
    assert mesh.info["resample"]["nudged"] == 0  # no ring point moved after halving
    halved = mesh.info["resample"]["halved_edges"]
    q = mesh.polygon
    assert len(q.rings) == len(polygon.rings)
    for ring, base in zip(q.rings, polygon.rings):
        key = ring[:, 0] + 1j * ring[:, 1]
        old = np.isin(key, base[:, 0] + 1j * base[:, 1])
        assert ring[old].tobytes() == base.tobytes()
        for i in np.flatnonzero(~old):
            a, b = ring[i - 1], ring[(i + 1) % len(ring)]
            assert old[i - 1] and old[(i + 1) % len(ring)]
            assert np.array_equal(ring[i], 0.5 * (a + b))
        halved -= int((~old).sum())
    assert halved == 0


def resampled_and_meshed(polygon, n: int, tol: float):
    """(resampled outline, mesh) of ``polygon`` at ``n`` points and tolerance
    ``tol``, checked: the mesh's rings are the resampled ones (whole edges
    halved aside), a valid mesh with exact n, and every ring within the
    resampling's deviation of the input by shapely's Hausdorff distance, which
    is within ``tol`` spacings.  The mesh is made with no ring point moved off
    its short edges (``ring_nudge.TRIES`` 0)."""
    r, left = resample_polygon(polygon, n, tolerance=tol)
    tries, ring_nudge.TRIES = ring_nudge.TRIES, 0
    try:
        m = uniform_mesh(polygon, n, resample=tol)
    finally:
        ring_nudge.TRIES = tries
    assert_halved_from(m, r.polygon)
    check_mesh(m.points, m.triangles, m.polygon, n_steiner=m.n_steiner)
    assert len(m.points) == m.info["resample"]["kept_vertices"] + n
    assert left + r.n_boundary == n
    d = max(shapely.hausdorff_distance(shapely.LinearRing(a), shapely.LinearRing(b), densify=0.1)
            for a, b in zip(polygon.rings, r.polygon.rings))
    assert d <= r.deviation * (1 + 1e-9) <= tol * r.spacing * (1 + 1e-9)
    return r, m


def plain_edges(polygon, P, T) -> tuple:
    """(edges, lengths, ring): a mesh's edges as a set of (smaller, larger)
    vertex pairs, their lengths by pair, and the polygon's ring edges as such
    pairs, by plain Python sets and loops (the tests' reference for
    uniform2d.ring_split's array code)."""
    edges = set()
    for a, b, c in T.tolist():
        for x, y in ((a, b), (b, c), (c, a)):
            edges.add((min(x, y), max(x, y)))
    length = {e: float(np.hypot(*(P[e[1]] - P[e[0]]))) for e in edges}
    ring = {(min(a, b), max(a, b)) for a, b in polygon.edges.tolist()}
    return edges, length, ring
