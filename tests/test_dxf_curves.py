"""DXF circles, arcs and bulges: a plate drawn as CAD draws it meshes with its holes."""

from __future__ import annotations

import math

import meshio
import numpy as np
import pytest

from uniform2d import uniform_mesh
from uniform2d.cli.main import main
from uniform2d.io import read_polygon
from uniform2d.io.dxf_curves import CHORD_TOL, chains, pieces_for
from uniform2d.testing import check_mesh

ezdxf = pytest.importorskip("ezdxf")

BOLTS = [((2.0, 2.0), 0.6), ((18.0, 2.0), 0.6), ((18.0, 8.0), 0.6), ((2.0, 8.0), 0.6)]
SLOT = ((8.0, 5.0), (12.0, 5.0), 0.8)  # centres of its two ends, radius


def _plate(path, *, outline="bulges"):
    """A 20 x 10 plate with rounded corners (radius 1), four bolt holes
    (CIRCLE), a slot (two LINEs, two ARCs) and a fillet-shaped open ARC segment."""
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    b = math.tan(math.radians(90) / 4)  # a quarter circle, counter-clockwise
    if outline == "bulges":
        msp.add_lwpolyline([(1, 0, 0), (19, 0, b), (20, 1, 0), (20, 9, b), (19, 10, 0),
                            (1, 10, b), (0, 9, 0), (0, 1, b)], format="xyb", close=True)
    else:  # LINEs and ARCs meeting end to end
        for a, c in (((1, 0), (19, 0)), ((20, 1), (20, 9)), ((19, 10), (1, 10)), ((0, 9), (0, 1))):
            msp.add_line(a, c)
        for centre, start in (((19, 1), 270), ((19, 9), 0), ((1, 9), 90), ((1, 1), 180)):
            msp.add_arc(centre, 1, start, start + 90)
    for c, r in BOLTS:
        msp.add_circle(c, r)
    (x0, y), (x1, _), r = SLOT
    msp.add_line((x0, y - r), (x1, y - r))
    msp.add_arc((x1, y), r, 270, 90)
    msp.add_line((x1, y + r), (x0, y + r))
    msp.add_arc((x0, y), r, 90, 270)
    msp.add_arc((10, 0), 3, 30, 150)  # open: a segment
    doc.saveas(path)


def _area(tri) -> float:
    """Total area of triangles (M, 3, 2)."""
    u, v = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    return float(0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum())


def _exact_area():
    (x0, _), (x1, _), r = SLOT
    corners = 4 * (1 - math.pi / 4)
    return 200 - corners - sum(math.pi * r * r for _, r in BOLTS) - (math.pi * r * r + (x1 - x0) * 2 * r)


def _curve_slack():
    """Sum over curves of their length x their sagitta bound: how far the
    polygon's area may be from the curved plate's."""
    arcs = [(1, math.pi / 2)] * 4 + [(r, 2 * math.pi) for _, r in BOLTS] + [(SLOT[2], 2 * math.pi)]
    return sum(r * t * CHORD_TOL * r for r, t in arcs)


@pytest.mark.parametrize("outline", ["bulges", "lines and arcs"])
def test_plate_meshes_with_its_holes(tmp_path, outline):
    path = tmp_path / "plate.dxf"
    _plate(path, outline=outline)
    p = read_polygon(path)
    assert p.n_holes == 5 and len(p.segments) == 1
    assert abs(p.area - _exact_area()) <= _curve_slack()
    m = uniform_mesh(p, 400)
    check_mesh(m.points, m.triangles, p, n_steiner=400)
    tri = m.points[m.triangles]
    mesh_area = _area(tri)
    assert mesh_area == pytest.approx(p.area, rel=1e-12)
    assert abs(mesh_area - _exact_area()) <= _curve_slack()
    # no triangle inside a bolt hole or the slot: every mesh point is outside each
    # circle's inscribed polygon, so no closer to its centre than r cos(pi / k)
    k = pieces_for(2 * math.pi)
    cent = tri.mean(axis=1)
    (x0, y), (x1, _), rs = SLOT
    for c, r in [*BOLTS, ((x0, y), rs), ((x1, y), rs)]:
        d = np.hypot(*(m.points - c).T)
        assert d.min() >= r * math.cos(math.pi / k) * (1 - 1e-12)
        assert np.hypot(*(cent - c).T).min() > r * math.cos(math.pi / k)
    inside_slot = (cent[:, 0] > x0) & (cent[:, 0] < x1) & (np.abs(cent[:, 1] - y) < rs)
    assert not inside_slot.any()
    # the open arc is a chain of mesh edges on the circle of radius 3 about (10, 0)
    seg = p.segments[0]
    assert np.hypot(seg[:, 0] - 10, seg[:, 1]) == pytest.approx(np.full(len(seg), 3.0), rel=1e-14)


def test_cli_meshes_a_dxf_with_circles_without_warnings(tmp_path, capsys):
    path = tmp_path / "plate.dxf"
    _plate(path)
    out = tmp_path / "plate.vtu"
    assert main(["mesh", str(path), "-n", "300", "-o", str(out)]) == 0
    cap = capsys.readouterr()
    assert "ignoring" not in cap.err and "CIRCLE" not in cap.err and "bulge" not in cap.err
    m = meshio.read(out)
    tri = m.points[m.cells_dict["triangle"]][:, :, :2]
    area = _area(tri)
    assert abs(area - _exact_area()) <= _curve_slack()


def test_an_ignored_entity_is_named_once(tmp_path, capsys):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
    msp.add_ellipse((5, 5), (2, 0), 0.5)
    doc.saveas(tmp_path / "e.dxf")
    assert main(["mesh", str(tmp_path / "e.dxf"), "-n", "20", "-o", str(tmp_path / "e.msh")]) == 0
    err = capsys.readouterr().err
    assert err.count("ELLIPSE") == 1 and "ignoring 1 ELLIPSE" in err


def test_circle_on_a_zone_layer_is_a_closed_segment(tmp_path):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
    msp.add_circle((5, 5), 2, dxfattribs={"layer": "ZONE_PAD"})
    doc.saveas(tmp_path / "z.dxf")
    p = read_polygon(tmp_path / "z.dxf")
    assert p.n_holes == 0 and len(p.segments) == 1 and len(p.segments[0]) == 24
    assert p.regions.labels.count("ZONE_PAD") == 1


def test_chains_join_only_where_two_pieces_meet():
    a = np.array([[0.0, 0], [1, 0]])
    b = np.array([[1.0, 0], [1, 1]])
    c = np.array([[1.0, 1], [0, 1]])
    d = np.array([[0.0, 1], [0, 1e-17]])  # an ARC's computed end, off by a rounding
    rings, rest = chains([a, b, c, d], [True, True, True, False])
    assert len(rings) == 1 and rest == [] and rings[0][1].tolist() == [[0, 0], [1, 0], [1, 1], [0, 1]]
    # a third piece at a corner: nothing closes through it
    e = np.array([[1.0, 1], [2, 2]])
    rings, rest = chains([a, b, c, d, e], [True] * 5)
    assert rings == [] and len(rest) == 5
    rings, rest = chains([a, b], [True, True])  # an open chain stays pieces
    assert rings == [] and [i for i, _ in rest] == [0, 1]


def test_a_whole_circle_drawn_as_an_arc_is_a_hole(tmp_path):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
    msp.add_arc((5, 5), 2, 90, 90)
    doc.saveas(tmp_path / "a.dxf")
    p = read_polygon(tmp_path / "a.dxf")
    assert p.n_holes == 1 and len(p.holes[0]) == 23 and not p.segments
    k = 23
    assert p.area == pytest.approx(100 - k / 2 * 4 * math.sin(2 * math.pi / k), rel=1e-13)
