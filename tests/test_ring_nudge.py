"""Ring points moved off a resampled mesh's too-short edges (uniform2d.ring_nudge):
the tolerance held both ways (shapely's Hausdorff distance, independent of the
module's own bound), the kept corners where they were, n exact, a valid mesh
(check_mesh); Canada at n = 2000 gets a lower edge ratio in both corner modes,
and the keep rule leaves the mesh as it was where the moved one is not better."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

import uniform2d as u
import uniform2d.ring_nudge as ring_nudge
from uniform2d.outline import Resampled
from uniform2d.ring_nudge import band_bound, nudge_rings, relaxed
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate
from uniform2d.uniform import resampled_outline

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"
N, TOL = 2000, 0.25


def _hausdorff(a, b) -> float:
    return max(shapely.hausdorff_distance(shapely.LinearRing(ra), shapely.LinearRing(rb),
                                          densify=0.02)
               for ra, rb in zip(a.rings, b.rings))


@pytest.mark.parametrize("dy", [0.0, 0.05, 0.15, 0.3])
def test_band_bound_is_a_bound(dy):
    square = np.array([(0, 0), (4, 0), (4, 4), (0, 4)], float)
    ring = np.array([(0, 0), (1.7, dy), (4, 0), (4, 4), (0, 4)], float)
    b = band_bound(square, ring, 1, 4.0, 0.2)
    d = shapely.hausdorff_distance(shapely.LinearRing(square), shapely.LinearRing(ring),
                                   densify=0.001)
    longer = max(np.hypot(*(ring[1] - ring[0])), np.hypot(*(ring[2] - ring[1])))
    step = max(0.5 * longer / ring_nudge._SAMPLES, 0.5 * 0.2 / 16)
    assert d <= b <= d + step  # above the distance, by at most the sampling's half step


def _sample_step():
    """A 3 x 3 square resampled with two samples 0.45 apart on its bottom side."""
    sq = u.Polygon([(0, 0), (3, 0), (3, 3), (0, 3)])
    res = Resampled(u.Polygon([(0, 0), (1, 0), (1.45, 0), (3, 0), (3, 3), (0, 3)]),
                    np.array([1, 0, 0, 1, 1, 1], bool), 1.0, 0.25, 0.0, 4)
    return sq, res


def test_short_edge_lengthened_within_the_tolerance():
    sq, res = _sample_step()
    P, T = triangulate(res.polygon, [(1.5, 1.5)])
    rings, moved, dev, stuck = nudge_rings(sq, res, P, T, 0.25)
    assert {m[0] for m in moved} == {1, 2} and not stuck
    R = rings[0]
    assert np.hypot(*(R[2] - R[1])) > 0.45 + 0.3
    assert R[[0, 3, 4, 5]].tobytes() == res.polygon.vertices[[0, 3, 4, 5]].tobytes()  # kept
    d = shapely.hausdorff_distance(shapely.LinearRing(sq.outer), shapely.LinearRing(R),
                                   densify=0.001)
    assert d <= dev <= 0.25
    # skipped pairs are not moved; a kept end never moves
    rings2, moved2, _, _ = nudge_rings(sq, res, P, T, 0.25, skip={(1, 2), (2, 1)})
    assert not moved2 and rings2[0].tobytes() == res.polygon.outer.tobytes()


def test_kept_points_never_move():
    # vertex 1 kept (a corner, a fixed point or a segment end: res.kept says so): only
    # the other end of the short edge moves; both kept: nothing moves
    sq, res = _sample_step()
    P, T = triangulate(res.polygon, [(1.5, 1.5)])
    one = Resampled(res.polygon, np.array([1, 1, 0, 1, 1, 1], bool), 1.0, 0.25, 0.0, 4)
    rings, moved, dev, _ = nudge_rings(sq, one, P, T, 0.25)
    assert [m[0] for m in moved] == [2]
    assert rings[0][[0, 1, 3, 4, 5]].tobytes() == res.polygon.vertices[[0, 1, 3, 4, 5]].tobytes()
    assert np.hypot(*(rings[0][2] - rings[0][1])) > 0.45 and dev <= 0.25
    both = Resampled(res.polygon, np.ones(6, bool), 1.0, 0.25, 0.0, 4)
    rings, moved, _, _ = nudge_rings(sq, both, P, T, 0.25)
    assert not moved and rings[0].tobytes() == res.polygon.outer.tobytes()


def test_relaxed_carries_the_mesh_to_the_moved_polygon():
    old = u.Polygon([(0, 0), (1, 0), (2, 0), (2, 2), (0, 2)])
    m = u.uniform_mesh(old, 30)
    new = u.Polygon([(0, 0), (1.1, 0.05), (2, 0), (2, 2), (0, 2)])
    m2 = relaxed(old, new, m)
    check_mesh(m2.points, m2.triangles, new, n_steiner=m.n_steiner)
    assert len(m2.points) == len(m.points)
    # a move that would leave an interior point outside is refused
    sites = m.points[len(old.vertices):]
    sites = sites[sites[:, 1] > 0]  # interior points
    inner = sites[np.argmin(sites[:, 1])]
    bad = u.Polygon([(0, 0), (inner[0], inner[1] + 0.3), (2, 0), (2, 2), (0, 2)])
    assert relaxed(old, bad, m) is None


def _meshes(name, corners, monkeypatch):
    p = u.read_polygon(OUTLINES / f"{name}.json")
    with monkeypatch.context() as mp:
        mp.setattr(ring_nudge, "TRIES", 0)  # the mesh without the stage
        before = u.uniform_mesh(p, N, resample=TOL, resample_corners=corners)
    return p, before, u.uniform_mesh(p, N, resample=TOL, resample_corners=corners)


@pytest.mark.parametrize("corners", ["keep", "merge"])
def test_canada_ratio_lowered(corners, monkeypatch):
    p, before, m = _meshes("canada", corners, monkeypatch)
    r = m.info["resample"]
    q0, q = before.quality(), m.quality()
    assert before.info["resample"]["nudged"] == 0 and r["nudged"] > 0
    assert q.edge_ratio < q0.edge_ratio - 0.05
    assert q.cv_edge <= 1.01 * q0.cv_edge and q.min_angle >= 0.99 * q0.min_angle
    check_mesh(m.points, m.triangles, m.polygon, n_steiner=m.n_steiner)
    assert len(m.points) == r["kept_vertices"] + N  # n exact
    # the kept input vertices (corners) are vertices of the mesh, where they were
    res, _ = resampled_outline(p, N, resample=TOL, resample_corners=corners)
    kept = {tuple(v) for v in res.polygon.vertices[res.kept]}
    assert kept <= {tuple(v) for v in m.polygon.vertices}
    assert r["kept_vertices"] == before.info["resample"]["kept_vertices"]
    # the tolerance, measured both ways independently of the reported bound
    d = _hausdorff(p, m.polygon)
    assert d <= r["deviation"] * (1 + 1e-9) and d <= TOL * r["spacing"] * (1 + 1e-9)


def test_kept_only_if_better(monkeypatch):
    p = u.read_polygon(OUTLINES / "canada.json")
    with monkeypatch.context() as mp:
        mp.setattr(ring_nudge, "TRIES", 0)
        plain = u.uniform_mesh(p, N, resample=TOL)
    monkeypatch.setattr(ring_nudge, "CV_SLACK", -1.0)  # no CV can be that low
    m = u.uniform_mesh(p, N, resample=TOL)
    assert m.info["resample"]["nudged"] == 0
    assert m.points.tobytes() == plain.points.tobytes()
    assert m.triangles.tobytes() == plain.triangles.tobytes()


def _one_way(a, b, step: float) -> float:
    """max over a's ring points (sampled at ``step``) of the distance to b's
    samples: at most the Hausdorff distance from a to b plus half a step."""
    sa = shapely.get_coordinates(shapely.segmentize(shapely.LinearRing(a), step))
    sb = shapely.get_coordinates(shapely.segmentize(shapely.LinearRing(b), step))
    return float(cKDTree(sb).query(sa)[0].max())


def test_shoreline_with_short_ring_edges(monkeypatch):
    # the Bronx shoreline: ring edges of 0.1 h between its piers' points (the stage
    # used to be skipped where the shortest ring edge forces a ratio above 2)
    p, before, m = _meshes("nyc_bronx", "keep", monkeypatch)
    r = m.info["resample"]
    h = r["spacing"]
    res, _ = resampled_outline(p, N, resample=TOL)
    V = res.polygon.vertices

    def shortest(poly):
        return np.hypot(*(poly.vertices[poly.edges[:, 1]] - poly.vertices[poly.edges[:, 0]]).T).min()

    assert before.quality().mean_edge > 2 * shortest(res.polygon)  # the old rule's skip
    assert shortest(m.polygon) > shortest(res.polygon)
    q0, q = before.quality(), m.quality()
    assert before.info["resample"]["nudged"] == 0 and r["nudged"] > 0
    assert q.edge_ratio < 0.5 * q0.edge_ratio
    assert q.cv_edge <= 1.01 * q0.cv_edge and q.min_angle >= 0.99 * q0.min_angle
    check_mesh(m.points, m.triangles, m.polygon, n_steiner=m.n_steiner)
    assert len(m.points) == r["kept_vertices"] + N
    kept = {tuple(v) for v in V[res.kept]}
    assert kept <= {tuple(v) for v in m.polygon.vertices}
    assert r["deviation"] <= TOL * h * (1 + 1e-9)
    step = 0.002 * h
    for a, b in zip(p.rings, m.polygon.rings):  # both ways, independently of the module
        assert max(_one_way(a, b, step), _one_way(b, a, step)) <= r["deviation"] + 0.5 * step
