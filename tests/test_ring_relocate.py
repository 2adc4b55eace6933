"""Relocation moves on a resampled mesh (uniform2d.ring_relocate): India at n = 2000,
whose longest edges are chords across a boundary vertex, gets a valid mesh with
the same points count, a lower edge ratio (at most 2) and a CV within the slack;
the rule keeps the input where the moved mesh is not better, and leaves meshes
with a ratio of 2 or less alone."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely

import uniform2d as u
import uniform2d.ring_relocate as ring_relocate
import uniform2d.ring_split as ring_split
from uniform2d.geometry import unique_edges
from uniform2d.optimize import optimize_mesh
from uniform2d.ring_relocate import CV_SLACK, relocated
from uniform2d.ring_split import ANGLE_SLACK
from uniform2d.testing import check_mesh
from uniform2d.uniform import NEAR_TIE, resampled_outline

OUTLINES = Path(__file__).resolve().parents[1] / "data" / "outlines"
N, TOL = 2000, 0.25


def _edges(m):
    E = unique_edges(m.triangles, len(m.points))
    return E, np.hypot(*(m.points[E[:, 1]] - m.points[E[:, 0]]).T)


def _first_mesh(name):
    """The mesh uniform_mesh makes before relocation (India's halving is not kept)."""
    p = u.read_polygon(OUTLINES / f"{name}.json")
    res, left = resampled_outline(p, N, resample=TOL)
    return p, res, optimize_mesh(res.polygon, left, near_tie=NEAR_TIE)


def test_india_chords_relocated_to_ratio_2():
    p, res, m = _first_mesh("india")
    q = m.quality()
    assert q.edge_ratio > 2
    # the case: the longest edge joins two polygon vertices, is no ring edge, and
    # one of its triangles has a polygon vertex as third corner (a corner with one triangle)
    E, L = _edges(m)
    a, b = E[np.argmax(L)]
    nV = len(res.polygon.vertices)
    ring = {tuple(sorted(e)) for e in res.polygon.edges.tolist()}
    assert a < nV and b < nV and (int(min(a, b)), int(max(a, b))) not in ring
    on = m.triangles[(m.triangles == a).any(axis=1) & (m.triangles == b).any(axis=1)]
    third = set(on.ravel().tolist()) - {int(a), int(b)}
    assert any(v < nV for v in third)

    m2, moves = relocated(m)
    assert moves > 0
    check_mesh(m2.points, m2.triangles, m2.polygon, n_steiner=m.n_steiner)
    assert len(m2.points) == len(m.points) and m2.polygon is m.polygon
    assert np.array_equal(m2.points[:nV], m.points[:nV])  # the rings untouched
    q2 = m2.quality()
    assert q2.edge_ratio < q.edge_ratio and q2.edge_ratio <= 2
    assert q2.cv_edge <= (1 + CV_SLACK) * q.cv_edge
    assert q2.min_angle >= (1 - ANGLE_SLACK) * q.min_angle
    E2, _ = _edges(m2)
    assert not ((E2[:, 0] == min(a, b)) & (E2[:, 1] == max(a, b))).any()  # the chord is gone

    # uniform_mesh makes that mesh: exact n, the tolerance held, the moves reported
    full = u.uniform_mesh(p, N, resample=TOL)
    r = full.info["resample"]
    assert r["relocated"] == moves and r["halved_edges"] == 0
    assert np.array_equal(full.points, m2.points) and np.array_equal(full.triangles, m2.triangles)
    assert len(full.points) == r["kept_vertices"] + N
    dev = max(shapely.hausdorff_distance(shapely.LinearRing(ra), shapely.LinearRing(rb),
                                         densify=0.1)
              for ra, rb in zip(p.rings, full.polygon.rings))
    assert dev <= TOL * r["spacing"] * (1 + 1e-9)


def test_kept_only_if_better(monkeypatch):
    _, _, m = _first_mesh("india")
    monkeypatch.setattr(ring_relocate, "CV_SLACK", -1.0)  # no CV can be that low
    m2, moves = relocated(m)
    assert moves == 0 and m2 is m


def test_ratio_of_2_or_less_left_alone():
    p = u.read_polygon(OUTLINES / "iceland.json")  # as given (no edge too short): 1.51
    m = u.uniform_mesh(p, 500, resample=TOL)
    assert m.quality().edge_ratio <= 2 and m.info["resample"]["relocated"] == 0
    m2, moves = relocated(m)
    assert moves == 0 and m2 is m


def test_a_flat_triangle_is_not_traded_for_a_lower_ratio(monkeypatch):
    # Australia, corners merged: six moves lower the ratio (2.253 -> 2.236) and
    # the CV, but leave a triangle of 18 degrees where the worst was 32
    p = u.read_polygon(OUTLINES / "australia.json")
    res, left = resampled_outline(p, N, resample=TOL, resample_corners="merge")
    m = optimize_mesh(res.polygon, left, near_tie=NEAR_TIE)
    q = m.quality()
    monkeypatch.setattr(ring_split, "ANGLE_SLACK", 1.0)  # any worst angle
    loose, moves = relocated(m)
    assert moves > 0 and loose.quality().edge_ratio < q.edge_ratio
    assert loose.quality().min_angle < (1 - ANGLE_SLACK) * q.min_angle  # the case
    monkeypatch.undo()
    m2, moves = relocated(m)
    assert moves == 0 and m2 is m
