"""Polygon files with segments, fixed points and region labels: round trips,
hand-written files of each format, and a typed error naming the file for bad ones."""

import json
import logging

import ezdxf
import numpy as np
import pytest

from uniform2d import FileFormatError, InvalidConstraintError, Polygon
from uniform2d.io import read_polygon, write_polygon

SQ = [(0, 0), (10, 0), (10, 10), (0, 10)]
HOLE = [(7, 7), (9, 7), (9, 9), (7, 9)]


def slab(labels=("west", "zone")):
    return Polygon(SQ, [HOLE],
                   segments=[[(4, 0), (4, 10)], [(5, 2), (8, 2), (8, 5), (5, 5), (5, 2)],
                             [(1, 1), (3, 3)], [(6, 6), (6, 8), (6.5, 8.5)]],
                   points=[(2, 8), (6.5, 3.5), (4, 5)],
                   regions=[(2, 5, labels[0]), (6.5, 3, labels[1])])


def _graph(p):
    """What a file must keep: the rings, the constraint edges and fixed points as
    coordinates, and the label of every region."""
    V = p.vertices
    edges = {frozenset(map(tuple, V[e].tolist())) for e in p.segment_edges}
    return ([r.tolist() for r in p.rings], edges, sorted(map(tuple, p.points.tolist())),
            [f.area for f in p.regions.faces], p.regions.labels)


@pytest.mark.parametrize("ext, labels", [(".json", ("west", 2.5)), (".geojson", ("west", 7)),
                                         (".dxf", ("west", "zone")), (".poly", (3, 2.5))])
def test_round_trip_with_constraints_and_labels(tmp_path, ext, labels):
    p = slab(labels)
    write_polygon(tmp_path / ("s" + ext), p)
    q = read_polygon(tmp_path / ("s" + ext))
    if ext == ".poly":
        # a fixed point on a segment comes back as a vertex of it: still a mesh vertex
        assert [4.0, 5.0] in q.split_segments()[0].tolist() and [4.0, 5.0] not in q.points.tolist()
        q = Polygon(q.outer, q.holes, segments=q.segments, points=[*q.points, (4, 5)],
                    regions=q.region_seeds)
    assert _graph(q) == _graph(p)
    if ext in (".json", ".geojson"):
        assert q == p          # the segments exactly as given, too
        assert [s.tolist() for s in q.segments] == [s.tolist() for s in p.segments]
    # writing again gives the same bytes
    write_polygon(tmp_path / ("t" + ext), q)
    if ext != ".poly":
        assert (tmp_path / ("t" + ext)).read_bytes() == (tmp_path / ("s" + ext)).read_bytes()


def test_wkt_round_trip_drops_labels_with_a_warning(tmp_path, caplog):
    p = slab()
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        write_polygon(tmp_path / "s.wkt", p)
    assert "dropping the 2 region labels" in caplog.text
    q = read_polygon(tmp_path / "s.wkt")
    assert _graph(q)[:4] == _graph(p)[:4] and q.regions.labels == (None,) * 3
    assert q == Polygon(p.outer, p.holes, segments=p.segments, points=p.points)


def test_poly_drops_text_labels_with_a_warning(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        write_polygon(tmp_path / "s.poly", slab(("west", 2)))
    assert "dropping 1 text labels" in caplog.text
    assert read_polygon(tmp_path / "s.poly").regions.labels == (None, None, 2)


def test_plain_polygons_write_as_before(tmp_path):
    p = Polygon(SQ, [HOLE])
    for ext in (".json", ".geojson", ".wkt", ".poly", ".dxf"):
        write_polygon(tmp_path / ("a" + ext), p)
        assert read_polygon(tmp_path / ("a" + ext)) == p
    assert (tmp_path / "a.wkt").read_text().startswith("POLYGON ((")
    assert "segments" not in (tmp_path / "a.json").read_text()


POLY = """# a slab: outline, a hole, a wall from edge to edge, a closed zone, a stiffener
# and two free vertices (one outside: dropped, as Triangle drops it)
14 2 0 0
1 0 0
2 10 0
3 10 10
4 0 10
5 7 7
6 9 7
7 9 9
8 7 9
9 4 0
10 4 10
11 5 2
12 8 2
13 8 5
14 5 5
"""


def test_poly_with_interior_segments_holes_and_attributes(tmp_path, caplog):
    text = POLY.replace("14 2 0 0", "17 2 0 0") + "15 1 1\n16 2 2\n17 20 20\n" + (
        "15 0\n1 1 9\n2 9 2\n3 2 3\n4 3 10\n5 10 4\n6 4 1\n7 5 6\n8 6 7\n9 7 8\n10 8 5\n"
        "11 9 10\n12 11 12\n13 12 13\n14 13 14\n15 14 11\n"
        "1\n1 8 8\n2\n1 2 5 1 0\n2 6 3 -2 0.5\n")
    path = tmp_path / "slab.poly"
    path.write_text(text)
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        p = read_polygon(path)
    assert "dropping 0 segments and 1 vertices" in caplog.text
    assert p.n_holes == 1 and p.outer.tolist() == [[0, 0], [4, 0], [10, 0], [10, 10], [4, 10], [0, 10]]
    assert sorted(s.tolist() for s in p.segments) == [
        [[4.0, 0.0], [4.0, 10.0]], [[5.0, 2.0], [8.0, 2.0], [8.0, 5.0], [5.0, 5.0], [5.0, 2.0]]]
    assert p.points.tolist() == [[1, 1], [2, 2]]
    assert p.regions.labels == (1, None, -2)
    assert p.regions.areas.tolist() == [40.0, 60.0 - 4 - 9, 9.0]


def test_poly_labels_agree_with_triangle(tmp_path):
    """Triangle, given the polygon and seeds read from the file, spreads the same
    attributes: every triangle's attribute is the label uniform2d gives its region."""
    triangle = pytest.importorskip("triangle")
    p = slab((1, 5))
    write_polygon(tmp_path / "s.poly", p)
    q = read_polygon(tmp_path / "s.poly")
    data = {"vertices": np.array(q.vertices), "segments": np.array(q.constraint_edges), "holes": [[8.0, 8.0]],
            "regions": [[x, y, lab, 0] for x, y, lab in q.region_seeds]}
    out = triangle.triangulate(data, "pAQ")
    want = out["triangle_attributes"][:, 0]
    pts = out["vertices"][out["triangles"]].mean(axis=1)
    got = [q.regions.labels[q.regions.locate(x, y)] or 0 for x, y in pts]
    assert np.array_equal(np.array(got, float), want)


def _dxf(path, build):
    doc = ezdxf.new("R2010")
    build(doc.modelspace())
    doc.saveas(path)


def test_dxf_lines_points_texts_and_zone_layers(tmp_path):
    def build(msp):
        msp.add_lwpolyline(SQ, close=True)
        msp.add_lwpolyline(HOLE, close=True, dxfattribs={"layer": "HOLES"})
        msp.add_line((4, 0), (4, 10))
        msp.add_lwpolyline([(1, 1), (3, 3)])
        msp.add_point((2, 8))
        msp.add_lwpolyline([(5, 2), (8, 2), (8, 5), (5, 5)], close=True, dxfattribs={"layer": "ZONE_STEEL"})
        msp.add_text("timber", dxfattribs={"insert": (2, 5)})
    _dxf(tmp_path / "z.dxf", build)
    p = read_polygon(tmp_path / "z.dxf")
    assert p.n_holes == 1 and len(p.segments) == 3 and p.points.tolist() == [[2, 8]]
    assert p.regions.labels == ("timber", None, "ZONE_STEEL")


def test_geojson_zones_points_and_labels(tmp_path):
    def feat(geom, **props):
        return {"type": "Feature", "properties": props, "geometry": geom}
    doc = {"type": "FeatureCollection", "features": [
        feat({"type": "Polygon", "coordinates": [SQ + [SQ[0]], HOLE + [HOLE[0]]]}),
        feat({"type": "Polygon", "coordinates": [[[5, 2], [8, 2], [8, 5], [5, 5], [5, 2]]]}, label="steel"),
        feat({"type": "MultiLineString", "coordinates": [[[4, 0], [4, 10]], [[1, 1], [3, 3]]]}),
        feat({"type": "MultiPoint", "coordinates": [[2, 8], [6, 8]]}),
        feat({"type": "Point", "coordinates": [1, 5]}, label="concrete"),
    ]}
    (tmp_path / "z.geojson").write_text(json.dumps(doc))
    p = read_polygon(tmp_path / "z.geojson")
    assert len(p.segments) == 3 and p.points.tolist() == [[2, 8], [6, 8]]
    assert p.regions.labels == ("concrete", None, "steel")


def test_wkt_geometry_collection(tmp_path):
    (tmp_path / "c.wkt").write_text(
        "GEOMETRYCOLLECTION (POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0)), "
        "MULTILINESTRING ((4 0, 4 10), (1 1, 3 3)), POINT (2 8), MULTIPOINT ((6 8), (6 2)))")
    p = read_polygon(tmp_path / "c.wkt")
    assert len(p.segments) == 2 and p.points.tolist() == [[2, 8], [6, 8], [6, 2]]
    assert len(p.regions) == 2


def test_json_keys(tmp_path):
    doc = {"outer": SQ, "segments": [[[4, 0], [4, 10]]], "points": [[2, 2]],
           "regions": [[1, 1, "a"], [6, 1, 3]]}
    (tmp_path / "k.json").write_text(json.dumps(doc))
    p = read_polygon(tmp_path / "k.json")
    assert p.regions.labels == ("a", 3) and p.points.tolist() == [[2, 2]]


BAD_FILES = [
    ("s.json", json.dumps({"outer": SQ, "segments": {"a": 1}}), '"segments" must be a list'),
    ("s.json", json.dumps({"outer": SQ, "segments": [[4, 0], [4, 10]]}), "looks like a single one"),
    ("s.json", json.dumps({"outer": SQ, "segments": [[[4, 0], [4, "x"]]]}), '"segments"[0][1] has an unreadable number'),
    ("s.json", json.dumps({"outer": SQ, "points": [[1]]}), '"points"[0] must be a position'),
    ("s.json", json.dumps({"outer": SQ, "regions": [[1, 1]]}), '"regions"[0] must be [x, y, label]'),
    ("s.json", json.dumps({"outer": SQ, "regions": [[1, 1, [2]]]}), '"regions"[0] must be [x, y, label]'),
    ("s.geojson", json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [SQ]}},
        {"type": "Feature", "properties": {"label": [1]}, "geometry": {"type": "Point", "coordinates": [1, 1]}}]}),
     'the "label" property [1] is not a string or number'),
    ("s.geojson", json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [SQ]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": []}}]}),
     'needs non-empty "coordinates"'),
    ("s.geojson", json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [SQ]}}, None]}),
     "features[1] is null, not a GeoJSON Feature object"),
    ("s.wkt", "GEOMETRYCOLLECTION (LINESTRING (0 0, 1 1))", "holds 0 non-empty POLYGONs"),
    ("s.wkt", "GEOMETRYCOLLECTION (POLYGON ((0 0, 1 0, 0 1, 0 0)), POLYGON ((5 5, 6 5, 5 6, 5 5)))",
     "holds 2 non-empty POLYGONs"),
    ("s.wkt", "GEOMETRYCOLLECTION (POLYGON ((0 0, 1 0, 0 1, 0 0)), LINEARRING (0 0, 1 0, 0 1, 0 0))",
     "member 1 of the GEOMETRYCOLLECTION is a LinearRing"),
    ("s.wkt", "GEOMETRYCOLLECTION (POLYGON ((0 0, 1 0, 0 1, 0 0)), ", "not valid WKT"),
    ("s.wkt", "MULTIPOLYGON EMPTY", "contains an empty MULTIPOLYGON"),
    ("s.poly", POLY + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n-1\n", "negative hole count -1"),
    ("s.poly", POLY + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n-2\n", "negative regional attribute count"),
    ("s.poly", POLY + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n1\n1 2 x 1\n", "unreadable region y 'x'"),
    ("s.poly", POLY + "5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 9 10\n1\n1 20 20\n",
     "hole point 1 (20, 20) is not inside any area"),
    ("s.poly", POLY + "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n1\n1 1 1\n",
     "every area the segments enclose holds a hole point"),
]


@pytest.mark.parametrize("name, text, words", BAD_FILES)
def test_bad_constraint_files(tmp_path, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(FileFormatError) as e:
        read_polygon(path)
    assert str(e.value).startswith(f"{path}: ") and words in str(e.value)


CROSSING = {
    ".json": json.dumps({"outer": SQ, "segments": [[[1, 1], [5, 5]], [[1, 5], [5, 1]]]}),
    ".geojson": json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [SQ + [SQ[0]]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[1, 1], [5, 5]]}},
        {"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": [[1, 5], [5, 1]]}}]}),
    ".wkt": "GEOMETRYCOLLECTION (POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0)), LINESTRING (1 1, 5 5), LINESTRING (1 5, 5 1))",
    ".poly": POLY.replace("14 2 0 0", "18 2 0 0") + "15 1 1\n16 5 5\n17 1 5\n18 5 1\n"
             "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 15 16\n6 17 18\n0\n",
}


@pytest.mark.parametrize("ext", [*CROSSING, ".dxf"])
def test_crossing_segments_in_any_format(tmp_path, ext):
    path = tmp_path / ("x" + ext)
    if ext == ".dxf":
        _dxf(path, lambda msp: (msp.add_lwpolyline(SQ, close=True), msp.add_line((1, 1), (5, 5)),
                                msp.add_line((1, 5), (5, 1))))
    else:
        path.write_text(CROSSING[ext])
    with pytest.raises(InvalidConstraintError) as e:
        read_polygon(path)
    assert str(e.value).startswith(f"{path}: segment 1 crosses segment 0 at (3, 3)")


def test_bad_dxf_label_seed_is_named(tmp_path):
    _dxf(tmp_path / "l.dxf", lambda msp: (msp.add_lwpolyline(SQ, close=True),
                                          msp.add_text("a", dxfattribs={"insert": (20, 20)})))
    with pytest.raises(InvalidConstraintError, match="outside the polygon or in a hole"):
        read_polygon(tmp_path / "l.dxf")
    _dxf(tmp_path / "n.dxf", lambda msp: (msp.add_line((0, 0), (1, 0)), msp.add_arc((0, 0), 1, 0, 90)))
    with pytest.raises(FileFormatError, match=r"no closed curve in modelspace \(found 1 ARC, 1 LINE"):
        read_polygon(tmp_path / "n.dxf")
