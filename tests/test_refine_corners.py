"""refine(polygon, "corners"): re-entrant corners are runs of reflex ring vertices (a sharp
corner is one vertex, a fillet an arc of several), a ring with no convex vertex (a
polygonised round hole) is none; meshes graded at them have exactly n points."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

import uniform2d
from uniform2d import Polygon, read_polygon
from uniform2d.errors import InvalidArgumentError
from uniform2d.refine import reentrant_corners, refine
from uniform2d.testing import check_mesh

DATA = Path(__file__).resolve().parents[1] / "data"
LSHAPE = Polygon([(0, 0), (1, 0), (1, 1), (-1, 1), (-1, -1), (0, -1)])
SQUARE = [(0, 0), (4, 0), (4, 4), (0, 4)]


def circle(cx, cy, r, k):
    """A clockwise k-gon (a hole ring: the domain on its left)."""
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    return np.column_stack([cx + r * np.cos(t), cy - r * np.sin(t)])


def filleted_l(k=6, r=0.2):
    """LSHAPE with its re-entrant corner (0, 0) replaced by a k-vertex arc of radius r
    (centre (r, -r), from (0, -r) to (r, 0)): every arc vertex turns by 90 / (k - 1) or
    half that, below the 20 degrees a single corner vertex needs."""
    t = np.radians(np.linspace(180, 90, k))
    arc = np.column_stack([r + r * np.cos(t), -r + r * np.sin(t)])
    outer = [(0, -1), *arc, (1, 0), (1, 1), (-1, 1), (-1, -1)]
    return Polygon(outer), arc


def test_round_hole_is_not_a_corner():
    P = Polygon(SQUARE, holes=[circle(2, 2, 1, 16)])
    # every vertex of the 16-gon has an interior angle of 202.5 degrees
    assert np.all(np.degrees(P.interior_angles()[4:]) > 200)
    assert reentrant_corners(P) == []
    with pytest.raises(InvalidArgumentError, match="no corners"):
        refine(P, "corners")


def test_command_refusing_corners_on_a_round_hole_says_use_holes(tmp_path, capsys):
    from uniform2d.cli.main import main
    from uniform2d.io import write_polygon

    src, out = tmp_path / "hole.json", tmp_path / "m.vtu"
    write_polygon(src, Polygon(SQUARE, holes=[circle(2, 2, 1, 16)]))
    assert main(["mesh", str(src), "-n", "300", "--refine", "corners:0.2", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("uniform2d: error: ") and '"holes"' in err
    assert not out.exists() and list(tmp_path.iterdir()) == [src]


def test_slot_hole_with_straight_vertices_is_not_a_corner():
    # two half circles joined by straight sides with a collinear vertex on each
    t = np.radians(np.linspace(90, -90, 7))
    right = np.column_stack([3 + 0.5 * np.cos(t), 2 + 0.5 * np.sin(t)])
    left = np.column_stack([1 - 0.5 * np.cos(t), 2 - 0.5 * np.sin(t)])
    hole = np.vstack([right, [(2, 1.5)], left, [(2, 2.5)]])
    P = Polygon([(-1, 0), (5, 0), (5, 4), (-1, 4)], holes=[hole])
    assert reentrant_corners(P) == []


def test_sharp_corners():
    assert [c.tolist() for c in reentrant_corners(LSHAPE)] == [[[0.0, 0.0]]]
    # a vertex turning by 10 degrees only is not a corner
    d = np.tan(np.radians(10.0))
    P = Polygon([(0, 0), (1, -d), (2, 0), (2, 1), (0, 1)])
    assert reentrant_corners(P) == []
    # an L-shaped hole: its three convex corners are the domain's re-entrant ones
    hole = [(1, 1), (1, 3), (2, 3), (2, 2), (3, 2), (3, 1)]
    P = Polygon(SQUARE, holes=[hole])
    got = sorted(map(tuple, np.vstack(reentrant_corners(P)).tolist()))
    assert got == [(1.0, 1.0), (1.0, 3.0), (2.0, 3.0), (3.0, 1.0), (3.0, 2.0)]


def test_filleted_corner_is_one_corner_near_its_arc():
    P, arc = filleted_l()
    corners = reentrant_corners(P)
    assert len(corners) == 1
    np.testing.assert_array_equal(corners[0], arc)
    f = refine(P, "corners", ratio=0.1, rate=0.5, size=1.0)
    # on the arc the size is the ratio's (up to the field grid's interpolation), also
    # mid-arc, 0.15 from the run's end points; it grows with the distance to the arc
    mid = (arc[2] + arc[3]) / 2
    far = np.array([(-0.8, 0.8)])
    line = shapely.LineString(arc)
    expect = min(1.0, 0.1 + 0.5 * shapely.distance(shapely.Point(far[0]), line))
    assert f(mid[None])[0] == pytest.approx(0.1, abs=0.01)
    assert f(far)[0] == pytest.approx(expect, rel=1e-2)


@pytest.mark.parametrize("make,n", [(lambda: filleted_l()[0], 300),
                                    (lambda: read_polygon(DATA / "l_bracket.json"), 400)])
def test_meshes_refined_at_corners(make, n):
    P = make()
    field = refine(P, "corners", ratio=0.15)
    m = uniform2d.uniform_mesh(P, n, size=field)
    check_mesh(m.points, m.triangles, P, n_steiner=n)
    assert m.n_steiner == n and len(m.points) == len(P.vertices) + n
    # denser near the corner than a uniform mesh of the same count
    u = uniform2d.uniform_mesh(P, n)
    line = shapely.LineString(reentrant_corners(P)[0])
    near = lambda pts: int((shapely.distance(shapely.points(pts), line)  # noqa: E731
                            < 2 * field(pts).min()).sum())
    assert near(m.points) > 2 * near(u.points)
