"""Seeds and meshes of polygons whose segments arrive split into pieces of about
the target size (as the surface layer's creases do).

The reference is the plain-polygon path: a strip between two segments, meshed
as a polygon of its own with the same boundary points, is what the region can
be at best, so the strip of several such regions may not be much worse.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

import uniform2d
from uniform2d.testing import check_mesh
from uniform2d import Polygon
from uniform2d.geometry import unique_edges
from uniform2d.optimize import improve, lattice_seed
from uniform2d.optimize.boundary import target_size
from uniform2d.optimize.rows import boundary_rows

H = 0.167
W = np.sqrt(1.25)  # strip width: no whole number of lattice rows fits it


def _ring(corners):
    """The closed polyline through ``corners`` sampled at about H (corners kept)."""
    pts = []
    for i in range(len(corners)):
        a, b = np.array(corners[i], float), np.array(corners[(i + 1) % len(corners)], float)
        k = int(round(np.linalg.norm(b - a) / H))
        pts += [a + (b - a) * j / k for j in range(k)]
    return np.array(pts)


def _strips(k=4):
    """k strips of width W and height 3, split by k - 1 pre-sampled segments."""
    m = int(round(3 / H))
    segs = [np.stack([np.full(m + 1, i * W), np.linspace(0, 3, m + 1)], 1) for i in range(1, k)]
    corners = [(i * W, 0) for i in range(k + 1)] + [(i * W, 3) for i in range(k, -1, -1)]
    return Polygon(_ring(corners), segments=segs)


def _ratio_cv(points, triangles):
    E = unique_edges(triangles)
    L = np.linalg.norm(points[E[:, 0]] - points[E[:, 1]], axis=1)
    return L.max() / L.min(), L.std() / L.mean()


def _alone():
    """One strip as a plain polygon, with the share of points of a strip of 600."""
    P = Polygon(_ring([(0, 0), (W, 0), (W, 3), (0, 3)]))
    n = 115
    pts, tri, _ = improve(P, lattice_seed(P, n))
    return _ratio_cv(pts, tri)


def test_equal_regions_get_equal_shares_of_the_seed():
    P = _strips()
    n = 600 - len(P.vertices)
    seed = lattice_seed(P, n)
    assert len(seed) == n
    counts = [np.count_nonzero(shapely.contains_xy(f, seed[:, 0], seed[:, 1]))
              for f in P.regions.faces]
    assert sum(counts) == n  # none on a segment
    assert max(counts) - min(counts) <= 1, counts


def test_segment_pieces_get_a_row_on_both_sides():
    P = Polygon([(0, 0), (8, 0), (8, 4), (0, 4)], segments=[[(3, 2), (4, 2), (5, 2)]])
    h = 1.0
    rows = boundary_rows(P, np.ones(len(P.constraint_edges), np.int64), h)
    near = rows[(np.abs(rows[:, 1] - 2) < 1.0) & (rows[:, 0] > 3) & (rows[:, 0] < 5)]
    # the apexes above and below the two pieces, at h * sqrt(3) / 2 from them
    for x in (3.5, 4.5):
        for y in (2 + np.sqrt(3) / 2, 2 - np.sqrt(3) / 2):
            assert np.hypot(near[:, 0] - x, near[:, 1] - y).min() < 1e-12
    # the free ends get a fan: a point straight beyond each end
    for x in (2.0, 6.0):
        assert np.hypot(rows[:, 0] - x, rows[:, 1] - 2).min() < 1e-12


def test_presampled_segments_mesh_as_well_as_a_region_alone():
    P = _strips()
    n = 600 - len(P.vertices)
    ratio0, cv0 = _alone()
    pts, tri, _ = improve(P, lattice_seed(P, n))
    check_mesh(pts, tri, P, n_steiner=n)
    ratio, cv = _ratio_cv(pts, tri)
    assert ratio <= 1.05 * ratio0 and cv <= 1.1 * cv0, (ratio, cv, ratio0, cv0)
    mesh = uniform2d.uniform_mesh(P, n)
    check_mesh(mesh.points, mesh.triangles, P, n_steiner=n)
    q = mesh.quality()
    assert q.edge_ratio <= 1.05 * ratio0 and q.cv_edge <= 1.1 * cv0, (q.edge_ratio, q.cv_edge)


@pytest.mark.parametrize("rows", [True, False])
def test_region_seed_is_inside_and_clear_of_fixed_points(rows):
    P = Polygon([(0, 0), (4, 0), (4, 3), (0, 3)],
                segments=[[(2, 0), (2, 3)]], points=[(1, 1.5), (3.2, 0.7)])
    n = 80
    seed = lattice_seed(P, n, rows=rows)
    assert len(seed) == n
    assert shapely.contains_xy(P.to_shapely(), seed[:, 0], seed[:, 1]).all()
    h = target_size(P, n)
    f = P.vertices[P.fixed]
    d = np.hypot(seed[:, None, 0] - f[None, :, 0], seed[:, None, 1] - f[None, :, 1])
    # half the lattice spacing, which is at least h / 2
    assert d.min() >= 0.25 * h
    assert np.abs(seed[:, 0] - 2.0).min() >= 0.25 * h
