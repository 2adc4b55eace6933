"""Ring points moved towards the far ends of a resampled mesh's too-long edges
(uniform2d.ring_shorten): the tolerance held both ways (shapely's Hausdorff
distance, independent of the module's own bound), kept points where they were,
n exact, a valid mesh (check_mesh); Antarctica at n = 2000 gets a lower edge
ratio, a mesh whose shortest edge is under FLOOR of the mean is left alone, and
the keep rule leaves the mesh as it was where the moved one is not better."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely

import uniform2d as u
import uniform2d.ring_nudge as ring_nudge
import uniform2d.ring_shorten as ring_shorten
from uniform2d.geometry import unique_edges
from uniform2d.outline import Resampled
from uniform2d.ring_shorten import shorten_rings
from uniform2d.testing import check_mesh
from uniform2d.triangulation import triangulate
from uniform2d.uniform import resampled_outline

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"
N, TOL = 2000, 0.25


def _hausdorff(a, b) -> float:
    return max(shapely.hausdorff_distance(shapely.LinearRing(ra), shapely.LinearRing(rb),
                                          densify=0.02)
               for ra, rb in zip(a.rings, b.rings))


def _long_side():
    """A 3 x 3 square resampled with one sample 0.8 from a corner: its ring edges
    0.8 and 2.2 are whole mesh edges around one interior point."""
    sq = u.Polygon([(0, 0), (3, 0), (3, 3), (0, 3)])
    res = Resampled(u.Polygon([(0, 0), (0.8, 0), (3, 0), (3, 3), (0, 3)]),
                    np.array([1, 0, 1, 1, 1], bool), 1.0, 0.25, 0.0, 4)
    P, T = triangulate(res.polygon, [(1.5, 1.5)])
    return sq, res, P, T


def test_long_edge_shortened_within_the_tolerance():
    sq, res, P, T = _long_side()
    rings, moved, dev, stuck = shorten_rings(sq, res, P, T, 0.25)
    assert moved == [(1, 2)] and not stuck
    R = rings[0]
    E = unique_edges(T, len(P))
    lo = np.hypot(*(P[E[:, 1]] - P[E[:, 0]]).T).min()
    # the long ring edge shorter, no ring edge shorter than the mesh's shortest edge
    assert np.hypot(*(R[2] - R[1])) < 2.2 - 0.2 and np.hypot(*(R[1] - R[0])) >= lo
    assert R[[0, 2, 3, 4]].tobytes() == res.polygon.vertices[[0, 2, 3, 4]].tobytes()  # kept
    d = shapely.hausdorff_distance(shapely.LinearRing(sq.outer), shapely.LinearRing(R),
                                   densify=0.001)
    assert d <= dev <= 0.25
    # skipped pairs are not moved; a kept end never moves
    rings2, moved2, _, _ = shorten_rings(sq, res, P, T, 0.25, skip={(1, 2)})
    assert (1, 2) not in moved2
    both = Resampled(res.polygon, np.ones(5, bool), 1.0, 0.25, 0.0, 4)
    rings3, moved3, _, _ = shorten_rings(sq, both, P, T, 0.25)
    assert not moved3 and rings3[0].tobytes() == res.polygon.outer.tobytes()


def test_no_move_the_band_check_cannot_vouch_for():
    # a tolerance of 1e-3: even the move straight along the outline is refused (the
    # band check samples the moved edges and adds half its step, more than that)
    sq, res, P, T = _long_side()
    rings, moved, dev, stuck = shorten_rings(sq, res, P, T, 1e-3)
    assert not moved and (1, 2) in stuck and dev == 0.0
    assert rings[0].tobytes() == res.polygon.outer.tobytes()


def _with_and_without(name, monkeypatch, corners="keep"):
    p = u.read_polygon(OUTLINES / f"{name}.json")
    with monkeypatch.context() as mp:
        mp.setattr(ring_shorten, "FLOOR", np.inf)  # the stage never runs
        before = u.uniform_mesh(p, N, resample=TOL, resample_corners=corners)
    return p, before, u.uniform_mesh(p, N, resample=TOL, resample_corners=corners)


def test_antarctica_ratio_lowered(monkeypatch):
    p, before, m = _with_and_without("antarctica", monkeypatch)
    r = m.info["resample"]
    q0, q = before.quality(), m.quality()
    assert before.info["resample"]["shortened"] == 0 and r["shortened"] > 0
    assert q.edge_ratio < q0.edge_ratio - 0.02
    assert q.cv_edge <= 1.01 * q0.cv_edge and q.min_angle >= 0.99 * q0.min_angle
    check_mesh(m.points, m.triangles, m.polygon, n_steiner=m.n_steiner)
    assert len(m.points) == r["kept_vertices"] + N  # n exact
    # the kept input vertices (corners) are vertices of the mesh, where they were
    res, _ = resampled_outline(p, N, resample=TOL)
    kept = {tuple(v) for v in res.polygon.vertices[res.kept]}
    assert kept <= {tuple(v) for v in m.polygon.vertices}
    assert r["kept_vertices"] == before.info["resample"]["kept_vertices"]
    # the tolerance, measured both ways independently of the reported bound
    d = _hausdorff(p, m.polygon)
    assert d <= r["deviation"] * (1 + 1e-9) and d <= TOL * r["spacing"] * (1 + 1e-9)


def test_short_side_floor_leaves_the_mesh(monkeypatch):
    # the USA's shortest edge (0.57 of the mean, a chord across a 29-degree tip) is
    # under FLOOR: the long side cannot bring the ratio to 2, the stage does not run
    p, before, m = _with_and_without("usa", monkeypatch)
    q = m.quality()
    assert q.shortest_edge < ring_shorten.FLOOR * q.mean_edge
    assert m.info["resample"]["shortened"] == 0
    assert m.points.tobytes() == before.points.tobytes()
    assert m.triangles.tobytes() == before.triangles.tobytes()


def test_kept_only_if_better(monkeypatch):
    p = u.read_polygon(OUTLINES / "antarctica.json")
    monkeypatch.setattr(ring_nudge, "CV_SLACK", -1.0)  # no CV can be that low
    with monkeypatch.context() as mp:
        mp.setattr(ring_shorten, "FLOOR", np.inf)
        plain = u.uniform_mesh(p, N, resample=TOL)
    m = u.uniform_mesh(p, N, resample=TOL)
    assert m.info["resample"]["shortened"] == 0
    assert m.points.tobytes() == plain.points.tobytes()
    assert m.triangles.tobytes() == plain.triangles.tobytes()
