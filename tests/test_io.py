"""uniform2d.io: every reader and writer round-trips, every bad file gets a clear error,
writes are atomic, and every polygon file in data/ loads."""

from __future__ import annotations

import json
import logging
import math
import os
from pathlib import Path

import ezdxf
import meshio
import numpy as np
import pytest
from scipy.spatial import Delaunay

import uniform2d
from uniform2d.io import common, geojson_file, json_file, poly_file, wkt_file
import uniform2d.io.truss as truss
from uniform2d import Polygon
from uniform2d.errors import FileFormatError, InvalidPolygonError, UnsupportedFormatError
from uniform2d.io import (
    mesh_formats,
    polygon_formats,
    read_mesh,
    read_polygon,
    write_mesh,
    write_polygon,
)
from uniform2d.io import registry

DATA = Path(__file__).resolve().parent.parent / "data"
POLYGON_EXTS = list(polygon_formats())
MESH_EXTS = list(mesh_formats())


def _circle(cx, cy, r, n):
    t = 2 * np.pi * np.arange(n) / n
    return np.c_[cx + r * np.cos(t), cy + r * np.sin(t)]


POLYGONS = {
    "square": Polygon([(0, 0), (1, 0), (1, 1), (0, 1)]),
    # clockwise input, collinear vertices, awkward floats, two holes
    "awkward": Polygon(
        [(0.1, 1 / 3), (0.1, 7.0000000000000009), (5.5, 7.0000000000000009),
         (11.0, 7.0000000000000009), (11.0, 1 / 3), (3e-7, -2.5)],
        [_circle(3, 4, 1 / 7, 13), [(7, 3), (9.25, 3), (8, 5.123456789012345)]],
    ),
    "l_bracket": read_polygon(DATA / "l_bracket.json"),
}


def _listing(directory):
    return sorted(p.name for p in Path(directory).iterdir())


# -- registry ----------------------------------------------------------------------------
def test_registry_lists_extensions_with_descriptions():
    assert POLYGON_EXTS == [".json", ".geojson", ".wkt", ".poly", ".dxf"]
    for ext in (".vtu", ".vtk", ".msh", ".obj", ".ply", ".off", ".inp", ".mesh", ".csv",
                ".truss.json"):
        assert ext in MESH_EXTS
    for table in (polygon_formats(), mesh_formats()):
        for ext, description in table.items():
            assert ext.startswith(".") and ext == ext.lower()
            assert isinstance(description, str) and len(description) > 5


@pytest.mark.parametrize(
    "name, ext",
    [("a.truss.json", ".truss.json"), ("A.TRUSS.JSON", ".truss.json"), ("m.vol.gz", ".vol.gz"),
     ("m.vol", ".vol"), ("x.csv", ".csv"), ("dir.v1/m.vtu", ".vtu")],
)
def test_registry_matches_longest_compound_extension(name, ext):
    assert registry.find_mesh_format(name).extension == ext


def test_unknown_extension_lists_supported(tmp_path):
    with pytest.raises(UnsupportedFormatError) as e:
        read_polygon(tmp_path / "plate.step")
    msg = str(e.value)
    assert "'.step'" in msg and ", ".join(POLYGON_EXTS) in msg
    with pytest.raises(UnsupportedFormatError) as e:
        write_mesh(tmp_path / "mesh.xyz", [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    assert ", ".join(MESH_EXTS) in str(e.value)
    assert not (tmp_path / "mesh.xyz").exists()
    with pytest.raises(UnsupportedFormatError, match="no extension"):
        write_polygon(tmp_path / "plate", POLYGONS["square"])
    # a mesh extension given to the polygon reader says where to go
    with pytest.raises(UnsupportedFormatError, match="'.vtu' is a mesh format: use read_mesh"):
        read_polygon(tmp_path / "m.vtu")
    with pytest.raises(UnsupportedFormatError, match="polygon format: use write_polygon"):
        write_mesh(tmp_path / "m.wkt", [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])


# -- polygon round trips -------------------------------------------------------------------
@pytest.mark.parametrize("ext", POLYGON_EXTS)
@pytest.mark.parametrize("name", list(POLYGONS))
def test_polygon_round_trip(tmp_path, ext, name):
    polygon = POLYGONS[name]
    path = tmp_path / f"poly{ext}"
    write_polygon(path, polygon)
    back = read_polygon(path)
    assert back == polygon  # same rings, same first vertex, exact floats
    assert _listing(tmp_path) == [path.name]  # no temporary file left behind


@pytest.mark.parametrize("ext", [".meshb", ".vol.gz", ".dato.gz", ".truss.json", ".vtu"])
def test_mesh_round_trip_upper_case_extension(tmp_path, ext):
    points, triangles = _mesh()
    path = str(tmp_path / f"MESH{ext.upper()}")
    write_mesh(path, points, triangles)
    p, t = read_mesh(path)
    np.testing.assert_array_equal(p, points)
    np.testing.assert_array_equal(t, triangles)


@pytest.mark.parametrize("ext", POLYGON_EXTS)
def test_polygon_round_trip_with_str_path_and_upper_case(tmp_path, ext):
    path = str(tmp_path / f"PLATE{ext.upper()}")
    write_polygon(path, POLYGONS["square"])
    assert read_polygon(path) == POLYGONS["square"]


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_json_variants(tmp_path):
    ring = [[0, 0], [0, 2], [2, 2], [2, 0], [0, 0]]  # clockwise, closed, ints
    p = read_polygon(_write(tmp_path, "a.json", json.dumps({"outer": ring, "units": "mm"})))
    assert p == Polygon([(0, 0), (2, 0), (2, 2), (0, 2)])
    p = read_polygon(_write(tmp_path, "b.json", json.dumps({"outer": ring, "holes": None})))
    assert p.n_holes == 0
    # GeoJSON inside .json
    gj = {"type": "Polygon", "coordinates": [ring, [[0.5, 0.5], [1, 0.5], [1, 1], [0.5, 0.5]]]}
    p = read_polygon(_write(tmp_path, "c.json", json.dumps(gj)))
    assert p.n_holes == 1 and p.area == pytest.approx(4 - 0.125)


@pytest.mark.parametrize(
    "doc",
    [
        {"type": "Polygon", "coordinates": [[[0, 0], [3, 0], [0, 3], [0, 0]]]},
        {"type": "Feature", "properties": {"name": "t"},
         "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [3, 0], [0, 3], [0, 0]]]}},
        {"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {"note": "no geometry"}, "geometry": None},
            {"type": "Feature", "properties": {},
             "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [3, 0], [0, 3], [0, 0]]]}},
        ]},
        {"type": "MultiPolygon", "coordinates": [[[[0, 0], [3, 0], [0, 3], [0, 0]]]]},
        {"type": "Polygon", "coordinates": [[[0, 0, 5], [3, 0, 5], [0, 3, 5], [0, 0, 5]]]},
    ],
    ids=["geometry", "feature", "collection", "one-part-multipolygon", "with-z"],
)
def test_geojson_variants(tmp_path, doc):
    p = read_polygon(_write(tmp_path, "t.geojson", json.dumps(doc)))
    assert p == Polygon([(0, 0), (3, 0), (0, 3)])


def test_wkt_with_z_and_one_part_multipolygon(tmp_path):
    tri = Polygon([(0, 0), (3, 0), (0, 3)])
    wkt_z = "POLYGON Z ((0 0 1, 3 0 1, 0 3 1, 0 0 1))"
    assert read_polygon(_write(tmp_path, "a.wkt", wkt_z)) == tri
    assert read_polygon(_write(tmp_path, "b.wkt", "MULTIPOLYGON (((0 0, 3 0, 0 3, 0 0)))\n")) == tri


POLY_ZERO_BASED = """\
# a unit square with a square hole, 0-based, comments and blank lines
8 2 1 1   # vertices, dimension, attributes, markers

0 0 0 7 1
1 4 0 7 1
2 4 4 7 1
3 0 4 7 1
4 1 1 0 2
5 1 2 0 2
6 2 2 0 2
7 2 1 0 2
8 1
0 0 1 1
1 2 1 1
2 3 2 1
3 0 3 1
4 4 5 2
5 6 5 2
6 6 7 2
7 4 7 2
1
0 1.5 1.5
0  # no regional attributes
"""


def test_poly_zero_based_with_comments_and_attributes(tmp_path):
    p = read_polygon(_write(tmp_path, "sq.poly", POLY_ZERO_BASED))
    assert p == Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(1, 1), (1, 2), (2, 2), (2, 1)]])


def test_poly_vertices_in_node_file(tmp_path):
    _write(tmp_path, "t.node", "3 2 0 0\n1 0 0\n2 3 0\n3 0 3\n")
    p = read_polygon(_write(tmp_path, "t.poly", "0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n"))
    assert p == Polygon([(0, 0), (3, 0), (0, 3)])


def test_poly_outer_ring_need_not_come_first(tmp_path):
    text = ("7 2 0 0\n1 1 1\n2 2 1\n3 1.5 2\n4 0 0\n5 4 0\n6 4 4\n7 0 4\n"
            "7 0\n1 1 2\n2 2 3\n3 3 1\n4 4 5\n5 5 6\n6 6 7\n7 7 4\n1\n1 1.5 1.3\n")
    p = read_polygon(_write(tmp_path, "t.poly", text))
    assert p.n_holes == 1 and p.area == pytest.approx(16 - 0.5)


def _dxf(path, polylines, extra=None):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    handles = []
    for points, closed, kind in polylines:
        if kind == "lw":
            e = msp.add_lwpolyline(points, close=closed)
        else:
            e = msp.add_polyline2d(points, close=closed)
        handles.append(e.dxf.handle)
    if extra:
        extra(msp)
    doc.saveas(path)
    return handles


def test_dxf_lwpolyline_and_polyline_mixed(tmp_path, caplog):
    path = tmp_path / "m.dxf"
    _dxf(
        path,
        [([(1, 1), (2, 1), (2, 2)], True, "old"),
         ([(0, 0), (10, 0), (10, 10), (0, 10)], True, "lw")],
        extra=lambda msp: (msp.add_circle((5, 5), 1), msp.add_ellipse((5, 8), (1, 0), 0.5)),
    )
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        p = read_polygon(path)
    # the circle is a hole (a 23-gon: sagitta <= 0.01 of its radius), the ellipse ignored
    assert p.outer.tolist() == [[0, 0], [10, 0], [10, 10], [0, 10]]
    assert [len(h) for h in p.holes] == [3, 23]
    assert p.area == pytest.approx(100 - 0.5 - 23 / 2 * math.sin(2 * math.pi / 23), rel=1e-12)
    assert caplog.text.count("ignoring") == 1 and "ignoring 1 ELLIPSE: uniform2d reads" in caplog.text


def test_dxf_bulges_are_arcs(tmp_path, caplog):
    doc = ezdxf.new("R2010")
    doc.modelspace().add_lwpolyline(
        [(0, 0, 0), (10, 0, 0.5), (10, 10, 0), (0, 10, 0)], format="xyb", close=True
    )
    doc.saveas(tmp_path / "b.dxf")
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        p = read_polygon(tmp_path / "b.dxf")
    # bulge 0.5 from (10, 0) to (10, 10): counter-clockwise, 4 atan(0.5) = 106.3 degrees,
    # radius 6.25 about (6.25, 5); pieces with a sagitta <= 0.01 of the radius
    theta, r = 4 * math.atan(0.5), 6.25
    k = math.ceil(theta / (2 * math.acos(0.99)))
    arc = p.outer[p.outer[:, 0] > 10]
    assert len(p.outer) == 4 + k - 1 and len(arc) == k - 1
    assert np.hypot(arc[:, 0] - 6.25, arc[:, 1] - 5) == pytest.approx(np.full(k - 1, r), rel=1e-14)
    sag = r * (1 - math.cos(theta / k / 2))
    assert sag <= 0.01 * r
    assert p.area == pytest.approx(100 + r * r / 2 * (k * math.sin(theta / k) - math.sin(theta)),
                                   rel=1e-13)
    assert caplog.text == ""


def test_dxf_mirrored_ocs_uses_world_coordinates(tmp_path):
    doc = ezdxf.new("R2010")
    doc.modelspace().add_lwpolyline(
        [(0, 0), (2, 0), (2, 1)], close=True, dxfattribs={"extrusion": (0, 0, -1)}
    )
    doc.saveas(tmp_path / "m.dxf")
    p = read_polygon(tmp_path / "m.dxf")
    assert sorted(map(tuple, p.outer.tolist())) == [(-2.0, 0.0), (-2.0, 1.0), (0.0, 0.0)]


# -- polygon errors ------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name, text, fragment",
    [
        ("broken.json", '{"outer": [[0, 0], [1, 0], [0, 1]', "invalid JSON"),
        ("nouter.json", '{"holes": []}', 'missing the "outer" key'),
        ("list.json", "[[0, 0], [1, 0], [0, 1]]", "expected a JSON object"),
        ("deep.json", '{"outer": [[[0, 0], [1, 0], [0, 1]]]}', "one level of nesting too many"),
        ("three.json", '{"outer": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}', '"outer"[0] must be'),
        ("str.json", '{"outer": [[0, 0], ["1,5", 0], [0, 1]]}', "unreadable number"),
        ("bool.json", '{"outer": [[0, 0], [true, 0], [0, 1]]}', "unreadable number"),
        ("hole1.json", '{"outer": [[0, 0], [9, 0], [0, 9]], "holes": [[1, 1], [2, 1], [1, 2]]}',
         "looks like a single ring"),
        ("truss.json", '{"nodes": [[0, 0]], "members": [], "triangles": []}', "read_mesh"),
        ("multi.geojson",
         json.dumps({"type": "MultiPolygon", "coordinates": [
             [[[0, 0], [1, 0], [0, 1], [0, 0]]], [[[5, 5], [6, 5], [5, 6], [5, 5]]],
             [[[9, 9], [8, 9], [9, 8], [9, 9]]]]}),
         "contains a MultiPolygon with 3 parts; uniform2d meshes one polygon at a time: split it"),
        ("multi_in_feature.json",
         json.dumps({"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [
             [[[0, 0], [1, 0], [0, 1], [0, 0]]], [[[5, 5], [6, 5], [5, 6], [5, 5]]]]}}),
         "MultiPolygon with 2 parts"),
        ("two.geojson",
         json.dumps({"type": "FeatureCollection", "features": [
             {"type": "Feature", "geometry": {"type": "Polygon",
                                              "coordinates": [[[0, 0], [1, 0], [0, 1], [0, 0]]]}},
             {"type": "Feature", "geometry": {"type": "Polygon",
                                              "coordinates": [[[5, 5], [6, 5], [5, 6], [5, 5]]]}},
         ]}),
         "contains 2 polygons"),
        ("none.geojson", json.dumps({"type": "FeatureCollection", "features": []}),
         "contains no Polygon"),
        ("line.geojson", json.dumps({"type": "LineString", "coordinates": [[0, 0], [1, 1]]}),
         "contains a LineString"),
        ("flat.geojson", json.dumps({"type": "Polygon", "coordinates": [[0, 0], [1, 0], [0, 1]]}),
         "looks like a single ring"),
        ("multi.wkt",
         "MULTIPOLYGON (((0 0, 1 0, 0 1, 0 0)), ((5 5, 6 5, 5 6, 5 5)), ((9 9, 8 9, 9 8, 9 9)))",
         "contains a MultiPolygon with 3 parts; uniform2d meshes one polygon at a time: split it"),
        ("garbage.wkt", "POLYGON ((0 0, 1 0", "not valid WKT"),
        ("point.wkt", "POINT (1 2)", "contains a Point; expected a POLYGON"),
        ("empty.wkt", "  \n", "the file is empty"),
        ("latin1.wkt", None, "not a UTF-8 text file"),
        ("curve.wkt", "CURVEPOLYGON ((0 0, 1 0, 1 1, 0 0))", "unsupported WKT geometry"),
        ("deep.json", "[" * 100000 + "]" * 100000, "nested too deeply"),
        ("truncated.dxf", "0\nSECTION\n", "not a readable DXF file"),
    ],
)
def test_bad_polygon_file_format(tmp_path, name, text, fragment):
    path = tmp_path / name
    if text is None:
        path.write_bytes(b"POLYGON ((0 0, 1 0, 0 1, 0 0)) \xe9t\xe9")
    else:
        path.write_text(text, encoding="utf-8")
    with pytest.raises(FileFormatError) as e:
        read_polygon(path)
    assert fragment in str(e.value)
    assert str(e.value).startswith(str(path))


POLY_SQUARE = "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n"


@pytest.mark.parametrize(
    "text, fragment",
    [
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n", None),  # the valid baseline
        (POLY_SQUARE + "3 0\n1 1 2\n2 2 3\n3 3 4\n0\n", "the segments enclose no area"),
        (POLY_SQUARE + "6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 1 3\n0\n", "remove the duplicate"),
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 9\n0\n", "refers to vertex 9"),
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 3\n4 4 1\n0\n", "to itself"),
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 9 9\n", "not inside any hole ring"),
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 2 2\n", "not inside any hole ring"),
        ("8 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 10 10\n6 12 10\n7 10 12\n8 1 1\n"
         "7 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 5\n0\n", "2 separate areas"),
        (POLY_SQUARE + "4 0\n1 1 2\n2 2 3\n3 3 4\n", "the file ends before segment 4 of 4"),
        ("4 2 0 0\n1 0 0\n2 4 0\n3 4 x\n4 0 4\n", "unreadable y coordinate 'x'"),
        ("4 2 0 0\n1 0 0\n3 4 0\n3 4 4\n4 0 4\n", "numbered consecutively"),
        ("4 3 0 0\n", "must be 2-D"),
        ("", "the file ends before the vertex count"),
        (POLY_SQUARE + "0 0\n0\n", "has no segments"),
        ("1e15 2 0 0\n0 0 0\n", "counts 1000000000000000 vertices, but only 1 lines follow"),
    ],
)
def test_bad_poly(tmp_path, text, fragment):
    path = _write(tmp_path, "bad.poly", text)
    if fragment is None:
        assert read_polygon(path).area == 16.0
        return
    with pytest.raises(FileFormatError) as e:
        read_polygon(path)
    assert fragment in str(e.value)
    assert str(e.value).startswith(str(path))


def test_open_dxf_polyline_is_a_segment(tmp_path):
    path = tmp_path / "open.dxf"
    _dxf(
        path,
        [([(0, 0), (10, 0), (10, 10), (0, 10)], True, "lw"),
         ([(1, 1), (2, 1), (2, 2)], True, "lw"),
         ([(5, 5), (6, 5), (6, 6)], False, "lw")],
    )
    p = read_polygon(path)
    assert p.n_holes == 1 and [s.tolist() for s in p.segments] == [[[5, 5], [6, 5], [6, 6]]]


def test_dxf_without_polylines(tmp_path):
    path = tmp_path / "none.dxf"

    def stuff(msp):
        msp.add_line((0, 0), (1, 0))
        msp.add_ellipse((0, 0), (1, 0), 0.5)

    _dxf(path, [], extra=stuff)
    with pytest.raises(FileFormatError, match="no closed curve in modelspace") as e:
        read_polygon(path)
    assert "(found 1 ELLIPSE, 1 LINE)" in str(e.value)


def test_dxf_not_a_dxf(tmp_path):
    with pytest.raises(FileFormatError, match="not a readable DXF"):
        read_polygon(_write(tmp_path, "x.dxf", "hello\n"))


def test_dxf_ring_outside_outer(tmp_path):
    path = tmp_path / "two.dxf"
    handles = _dxf(path, [([(0, 0), (10, 0), (10, 10), (0, 10)], True, "lw"),
                          ([(20, 20), (21, 20), (21, 21)], True, "lw")])
    with pytest.raises(InvalidPolygonError, match=f"handle {handles[1]}.*lies outside the outer"):
        read_polygon(path)


BOWTIE = [[0, 0], [4, 4], [4, 0], [0, 2]]  # unequal lobes: non-zero area


@pytest.mark.parametrize("ext", POLYGON_EXTS)
def test_self_intersecting_ring_is_invalid_polygon(tmp_path, ext):
    path = tmp_path / f"bowtie{ext}"
    if ext in (".json", ".geojson"):
        doc = ({"outer": BOWTIE} if ext == ".json"
               else {"type": "Polygon", "coordinates": [BOWTIE + [BOWTIE[0]]]})
        path.write_text(json.dumps(doc))
    elif ext == ".wkt":
        path.write_text("POLYGON ((0 0, 4 4, 4 0, 0 2, 0 0))")
    elif ext == ".poly":
        path.write_text("4 2 0 0\n1 0 0\n2 4 4\n3 4 0\n4 0 2\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
    else:
        _dxf(path, [(BOWTIE, True, "lw")])
    with pytest.raises(InvalidPolygonError) as e:
        read_polygon(path)
    assert str(e.value).startswith(f"{path}: outer ring")
    assert "intersects itself" in str(e.value)


def test_invalid_hole_names_the_polyline(tmp_path):
    path = tmp_path / "cross.dxf"
    handles = _dxf(path, [([(0, 0), (10, 0), (10, 10), (0, 10)], True, "lw"),
                          ([(8, 8), (12, 8), (12, 9), (8, 9)], True, "lw")])
    with pytest.raises(InvalidPolygonError, match=f"hole 0 = polyline #2 .handle {handles[1]}"):
        read_polygon(path)


def test_missing_polygon_file_message(tmp_path):
    path = tmp_path / "nothere.json"
    with pytest.raises(FileNotFoundError) as e:
        read_polygon(path)
    assert "polygon file not found" in str(e.value) and str(path) in str(e.value)
    with pytest.raises(FileNotFoundError, match="mesh file not found"):
        read_mesh(tmp_path / "nothere.vtu")


def test_write_polygon_wants_a_polygon(tmp_path):
    with pytest.raises(TypeError, match="uniform2d.Polygon"):
        write_polygon(tmp_path / "x.json", [(0, 0), (1, 0), (0, 1)])


# -- mesh round trips ----------------------------------------------------------------------
def _mesh():
    rng = np.random.default_rng(7)
    pts = rng.random((60, 2)) * np.array([12000.0, 3e-3]) - np.array([7.3, 1 / 3])
    pts[0] = (0.1, 1 / 3)
    tri = Delaunay(pts).simplices.astype(np.int64)
    return pts, tri


@pytest.mark.parametrize("ext", MESH_EXTS)
def test_mesh_round_trip_exact(tmp_path, ext, capfd):
    points, triangles = _mesh()
    p0, t0 = points.copy(), triangles.copy()
    points.setflags(write=False)
    path = tmp_path / f"mesh{ext}"
    write_mesh(path, points, triangles)
    p, t = read_mesh(path)
    assert p.dtype == np.float64 and p.shape == points.shape
    assert np.issubdtype(t.dtype, np.integer) and t.shape == triangles.shape
    np.testing.assert_array_equal(p, points)  # bit for bit
    np.testing.assert_array_equal(t, triangles)
    np.testing.assert_array_equal(points, p0)  # inputs untouched
    np.testing.assert_array_equal(triangles, t0)
    assert _listing(tmp_path) == [path.name]
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # library code (and meshio under it) prints nothing


@pytest.mark.parametrize("ext", [e for e, f in registry.MESH_FORMATS.items() if f.point_data])
def test_point_data_is_stored(tmp_path, ext):
    points, triangles = _mesh()
    w = np.linspace(0.0, 1.0, len(points)) ** 2
    path = tmp_path / f"mesh{ext}"
    write_mesh(path, points, triangles, point_data={"weight": w})
    if ext == ".csv":
        rows = [r.split(",") for r in path.read_text().splitlines()]
        assert rows[0][-1] == "weight"
        got = [float(r[-1]) for r in rows[1:] if r[0] == "node"]
    elif ext == ".truss.json":
        got = json.loads(path.read_text())["point_data"]["weight"]
    else:
        got = meshio.read(path).point_data["weight"]
    np.testing.assert_array_equal(np.ravel(got), w)


def test_point_data_dropped_with_warning(tmp_path, caplog):
    points, triangles = _mesh()
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        write_mesh(tmp_path / "m.msh", points, triangles, point_data={"w": points[:, 0]})
    assert "does not store point data" in caplog.text


@pytest.mark.parametrize(
    "points, triangles, fragment",
    [
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], "shape (N, 2)"),
        ([[0, 0], [1, 0], [0, np.nan]], [[0, 1, 2]], "non-finite"),
        ([[0, 0], [1, 0], [0, 1]], [[0, 1, 3]], "there are 3 points"),
        ([[0, 0], [1, 0], [0, 1]], [[0.0, 1.0, 2.0]], "integer"),
        ([[0, 0], [1, 0], [0, 1]], np.zeros((0, 3), int), "M >= 1"),
    ],
)
def test_write_mesh_rejects_bad_arrays(tmp_path, points, triangles, fragment):
    with pytest.raises(ValueError) as e:
        write_mesh(tmp_path / "m.vtu", points, triangles)
    assert fragment in str(e.value)
    assert _listing(tmp_path) == []


def test_write_mesh_rejects_bad_point_data(tmp_path):
    with pytest.raises(ValueError, match="one entry per point"):
        write_mesh(tmp_path / "m.vtu", [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]],
                   point_data={"w": [1.0, 2.0]})
    with pytest.raises(ValueError, match="one value per node"):
        write_mesh(tmp_path / "m.csv", [[0, 0], [1, 0], [0, 1]], [[0, 1, 2]],
                   point_data={"v": np.zeros((3, 2))})


# -- truss formats --------------------------------------------------------------------------
SQUARE_PTS = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
SQUARE_TRI = np.array([[0, 1, 2], [0, 2, 3]])


def test_truss_csv_layout(tmp_path):
    path = tmp_path / "t.csv"
    write_mesh(path, SQUARE_PTS, SQUARE_TRI)
    lines = path.read_text().splitlines()
    assert lines[0] == "kind,id,x,y,i,j,k,length"
    assert lines[1:5] == ["node,1,0.0,0.0,,,,", "node,2,4.0,0.0,,,,", "node,3,4.0,3.0,,,,",
                          "node,4,0.0,3.0,,,,"]
    assert lines[5:10] == ["member,1,,,1,2,,4.0", "member,2,,,1,3,,5.0", "member,3,,,1,4,,3.0",
                           "member,4,,,2,3,,3.0", "member,5,,,3,4,,4.0"]
    assert lines[10:] == ["triangle,1,,,1,2,3,", "triangle,2,,,1,3,4,"]


def test_truss_json_layout(tmp_path):
    path = tmp_path / "t.truss.json"
    write_mesh(path, SQUARE_PTS, SQUARE_TRI)
    doc = json.loads(path.read_text())
    assert doc["format"] == "uniform2d-truss" and doc["version"] == 1
    assert doc["nodes"] == SQUARE_PTS.tolist()
    assert doc["members"] == [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    assert doc["lengths"] == [4.0, 5.0, 3.0, 3.0, 4.0]
    assert doc["triangles"] == SQUARE_TRI.tolist()
    assert "point_data" not in doc


def test_truss_csv_hand_made_ids_and_comments(tmp_path):
    text = ("\ufeff# exported by hand\nkind,id,x,y,i,j,k,length,note\n"
            "node,10,0,0,,,,,a\nnode,20,4,0,,,,,b\nnode,30,4,3,,,,,c\n"
            "member,1,,,10,20,,4\n\ntriangle,7,,,10,20,30,\n")
    p, t = read_mesh(_write(tmp_path, "h.csv", text))
    assert p.tolist() == [[0, 0], [4, 0], [4, 3]] and t.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize(
    "name, text, fragment",
    [
        ("a.csv", "kind;id;x;y;i;j;k;length\n", "separator must be a comma"),
        ("b.csv", "kind,id,x,y,i,j,k,length\nnode,1,0,0\n", "has no triangle rows"),
        ("c.csv", "kind,id,x,y,i,j,k,length\nnode,1,0,0\nnode,2,1,0\nnode,3,0,1\n"
                  "triangle,1,,,1,2,4,\n", "refers to node 4"),
        ("d.csv", "kind,id,x,y,i,j,k,length\nnode,1,0,abc\n", "unreadable y 'abc'"),
        ("e.csv", "kind,id,x,y,i,j,k,length\nnode,1,0,0\nnode,1,1,0\n", "node id 1 appears twice"),
        ("f.csv", "kind,id,x,y,i,j,k,length\nbeam,1,,,1,2,,\n", "unknown kind 'beam'"),
        ("g.truss.json", '{"nodes": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 3]]}',
         "refers to node 3"),
        ("h.truss.json", '{"nodes": [[0, 0], [1, 0], [0, 1]]}', 'missing the "triangles" key'),
        ("i.truss.json", '{"outer": [[0, 0], [1, 0], [0, 1]]}', "read_polygon"),
        ("j.truss.json", '{"nodes": [[0, 0], [1, 0], [0, "1"]], "triangles": [[0, 1, 2]]}',
         '"nodes" must be'),
        ("k.truss.json", '{"nodes": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 2.5]]}',
         "integer node indices"),
        ("l.truss.json", "[" * 100000 + "]" * 100000, "nested too deeply"),
    ],
)
def test_bad_truss_files(tmp_path, name, text, fragment):
    path = _write(tmp_path, name, text)
    with pytest.raises(FileFormatError) as e:
        read_mesh(path)
    assert fragment in str(e.value) and str(e.value).startswith(str(path))


# -- other mesh reading ---------------------------------------------------------------------
def test_read_mesh_keeps_only_triangles(tmp_path, caplog):
    pts = np.c_[SQUARE_PTS, np.zeros(4)]
    cells = [("vertex", np.array([[0]])), ("line", np.array([[0, 1], [1, 2]])),
             ("quad", np.array([[0, 1, 2, 3]])), ("triangle", SQUARE_TRI)]
    meshio.write_points_cells(tmp_path / "g.vtu", pts, cells)
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        p, t = read_mesh(tmp_path / "g.vtu")
    assert p.tolist() == SQUARE_PTS.tolist() and t.tolist() == SQUARE_TRI.tolist()
    assert "ignoring non-triangle cells (1 blocks of quad)" in caplog.text
    assert "line" not in caplog.text


def test_meshio_messages_become_log_records(tmp_path, caplog, capfd):
    path = _write(tmp_path, "bad.su2", "NDIME= 2\nthis is not a mesh\n")
    with caplog.at_level(logging.WARNING, logger="uniform2d"), pytest.raises(FileFormatError):
        read_mesh(path)
    assert "meshio says" in caplog.text
    assert capfd.readouterr() == ("", "")


def test_read_mesh_rejects_non_planar_and_triangle_free(tmp_path):
    pts = np.c_[SQUARE_PTS, [0, 0, 1, 0]]
    meshio.write_points_cells(tmp_path / "bent.obj", pts, [("triangle", SQUARE_TRI)])
    with pytest.raises(FileFormatError, match="not planar"):
        read_mesh(tmp_path / "bent.obj")
    meshio.write_points_cells(tmp_path / "quad.vtu", np.c_[SQUARE_PTS, np.zeros(4)],
                              [("quad", np.array([[0, 1, 2, 3]]))])
    with pytest.raises(FileFormatError, match="contains no triangles"):
        read_mesh(tmp_path / "quad.vtu")


@pytest.mark.parametrize("ext", [e for e in MESH_EXTS if not e.endswith(".gz")])
def test_read_mesh_garbage(tmp_path, ext, capfd):
    path = _write(tmp_path, f"junk{ext}", "this is not a mesh\n1 2 3\n")
    with pytest.raises(FileFormatError) as e:
        read_mesh(path)
    assert str(e.value).startswith(str(path))
    out, err = capfd.readouterr()
    assert out == "" and err == ""  # meshio.read would print and sys.exit(1); we must not


# -- atomic writes --------------------------------------------------------------------------
def _fail_midway(real, calls=5):
    state = {"n": 0}

    def wrapper(*args, **kwargs):
        state["n"] += 1
        if state["n"] > calls:
            raise RuntimeError("serialiser crashed midway")
        return real(*args, **kwargs)

    return wrapper


@pytest.mark.parametrize("ext", [".csv", ".truss.json"])
def test_truss_write_failing_midway_leaves_nothing(tmp_path, monkeypatch, ext):
    monkeypatch.setattr(truss, "_num", _fail_midway(truss._num))
    path = tmp_path / f"t{ext}"
    with pytest.raises(RuntimeError, match="midway"):
        write_mesh(path, *_mesh())
    assert _listing(tmp_path) == []


def test_meshio_write_failing_midway_keeps_old_file(tmp_path, monkeypatch):
    path = tmp_path / "m.vtu"
    path.write_text("old content")

    def bad_write(filename, *args, **kwargs):
        Path(filename).write_text("<VTKFile half")
        raise RuntimeError("serialiser crashed midway")

    monkeypatch.setattr(meshio, "write", bad_write)
    with pytest.raises(RuntimeError, match="midway"):
        write_mesh(path, *_mesh())
    assert path.read_text() == "old content"
    assert _listing(tmp_path) == ["m.vtu"]


@pytest.mark.parametrize("ext", [".json", ".geojson", ".wkt", ".poly"])
def test_polygon_write_failing_midway_keeps_old_file(tmp_path, monkeypatch, ext):
    path = tmp_path / f"p{ext}"
    path.write_text("old content")
    failing = _fail_midway(common.num)
    for module in (common, json_file, geojson_file, wkt_file, poly_file):  # each writes numbers
        monkeypatch.setattr(module, "num", failing)
    with pytest.raises(RuntimeError, match="midway"):
        write_polygon(path, POLYGONS["l_bracket"])
    assert path.read_text() == "old content"
    assert _listing(tmp_path) == [path.name]


def test_dxf_without_ezdxf_names_the_extra(tmp_path, monkeypatch):
    """ezdxf is the ``dxf`` extra: without it a .dxf file is a typed error saying
    what to install, and nothing is left behind."""
    import sys

    written = tmp_path / "written.dxf"
    write_polygon(written, POLYGONS["square"])
    monkeypatch.setitem(sys.modules, "ezdxf", None)  # import ezdxf now fails
    with pytest.raises(UnsupportedFormatError, match=r"uniform2d\[dxf\]"):
        read_polygon(written)
    with pytest.raises(UnsupportedFormatError, match=r"uniform2d\[dxf\]"):
        write_polygon(tmp_path / "p.dxf", POLYGONS["square"])
    assert _listing(tmp_path) == ["written.dxf"]


def test_registry_writer_failing_leaves_nothing(tmp_path, monkeypatch):
    from dataclasses import replace

    def half(path, polygon):
        Path(path).write_text("POLYGON ((0 0,")
        raise OSError("disk full")

    spec = registry.POLYGON_FORMATS[".wkt"]
    monkeypatch.setitem(registry.POLYGON_FORMATS, ".wkt", replace(spec, writer=half))
    with pytest.raises(OSError, match="disk full"):
        write_polygon(tmp_path / "p.wkt", POLYGONS["square"])
    assert _listing(tmp_path) == []


def test_write_into_missing_directory(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        write_polygon(tmp_path / "no" / "p.json", POLYGONS["square"])


def test_written_files_have_normal_permissions(tmp_path):
    if os.name != "posix":
        pytest.skip("POSIX permissions")
    umask = os.umask(0o022)
    try:
        write_polygon(tmp_path / "p.json", POLYGONS["square"])
    finally:
        os.umask(umask)
    assert (tmp_path / "p.json").stat().st_mode & 0o777 == 0o644


# -- the data directory ---------------------------------------------------------------------
DATA_POLYGONS = sorted(
    p for p in DATA.rglob("*")
    if p.is_file() and "patches" not in p.parts and registry.match_format(p, registry.POLYGON_FORMATS)
)


def test_data_directory_has_the_expected_files():
    names = {p.relative_to(DATA).as_posix() for p in DATA_POLYGONS}
    assert {"plate_bolts.json", "truss_panel.json", "l_bracket.json",
            "examples/l_bracket.geojson", "examples/l_bracket.wkt", "examples/l_bracket.poly",
            "examples/l_bracket.dxf", "benchmarks/square.json",
            "benchmarks/square2holes.json"} <= names


@pytest.mark.parametrize("path", DATA_POLYGONS, ids=lambda p: p.relative_to(DATA).as_posix())
def test_every_data_polygon_loads(path):
    p = read_polygon(path)
    assert p.area > 0


@pytest.mark.parametrize("ext", [".geojson", ".wkt", ".poly", ".dxf"])
def test_examples_equal_the_json_bracket(ext):
    assert read_polygon(DATA / "examples" / f"l_bracket{ext}") == POLYGONS["l_bracket"]


def test_engineering_examples_are_what_the_readme_says():
    plate = read_polygon(DATA / "plate_bolts.json")
    assert plate.bounds == (0.0, 0.0, 400.0, 250.0) and plate.n_holes == 5
    assert len(plate.vertices) == 148
    panel = read_polygon(DATA / "truss_panel.json")
    assert panel.bounds == (0.0, 0.0, 12.0, 3.0) and panel.n_holes == 1
    bracket = POLYGONS["l_bracket"]
    assert bracket.bounds == (0.0, 0.0, 120.0, 80.0) and bracket.n_holes == 2


def test_atomic_write_errors_name_the_users_file_not_the_temporary_one(tmp_path):
    from uniform2d.io.atomic import atomic_write

    target = tmp_path / "mesh.vtu"
    target.mkdir()  # replacing a directory fails
    with pytest.raises(IsADirectoryError) as e:
        atomic_write(target, lambda tmp: tmp.write_text("x"), extension=".vtu")
    assert e.value.filename == str(target) and ".tmp-" not in str(e.value)
    assert [p.name for p in tmp_path.iterdir()] == ["mesh.vtu"]


def test_every_mesh_format_writes_the_same_bytes_every_time(tmp_path):
    # meshio stamps OBJ and PLY headers with the time, and gzip stores a time and
    # a file name: none of that may reach the output
    import time

    from uniform2d.io.registry import MESH_FORMATS

    for run_ in ("a", "b"):
        for ext in MESH_FORMATS:
            write_mesh(tmp_path / f"{run_}{ext}", SQUARE_PTS, SQUARE_TRI)
        if run_ == "a":
            time.sleep(1.1)
    for ext in MESH_FORMATS:
        a = (tmp_path / f"a{ext}").read_bytes()
        assert a == (tmp_path / f"b{ext}").read_bytes(), ext
        if ext.endswith(".gz"):
            assert a[:2] == b"\x1f\x8b", f"{ext} is not gzip-compressed"
        points, triangles = read_mesh(tmp_path / f"a{ext}")
        assert np.array_equal(points, SQUARE_PTS) and np.array_equal(triangles, SQUARE_TRI)


def test_every_polygon_format_writes_the_same_bytes_every_time(tmp_path):
    import time

    from uniform2d.io import write_polygon
    from uniform2d.io.registry import POLYGON_FORMATS

    P = Polygon([(0, 0), (4, 0), (4, 3), (0, 3)], [[(1, 1), (2, 1), (2, 2)]])
    exts = [e for e, f in POLYGON_FORMATS.items() if f.writer is not None]
    for run_ in ("a", "b"):
        for ext in exts:
            write_polygon(tmp_path / f"{run_}{ext}", P)
        if run_ == "a":
            time.sleep(1.1)
    for ext in exts:
        assert (tmp_path / f"a{ext}").read_bytes() == (tmp_path / f"b{ext}").read_bytes(), ext
        assert np.array_equal(read_polygon(tmp_path / f"a{ext}").vertices, P.vertices), ext


@pytest.mark.parametrize(
    "name, text",
    [("nan.wkt", "POLYGON ((0 0, nan 0, 1 1, 0 0))"),
     ("nan.poly", "3 2 0 0\n1 0 0\n2 nan 0\n3 1 1\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n")],
)
def test_non_finite_coordinates_give_one_error_and_no_warnings(tmp_path, name, text):
    # numpy and shapely warn about NaN on the way; the CLI must print one line only
    import warnings

    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(uniform2d.InvalidPolygonError, match="non-finite coordinate"):
            read_polygon(path)
