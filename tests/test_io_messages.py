"""Files that are empty or broken in ways that once gave misleading messages:
each is a FileFormatError naming the file, what is wrong and how to fix it, and
on the command line one line and exit code 2, with no output file."""

from __future__ import annotations

import json

import pytest

from uniform2d import FileFormatError, Uniform2dError
from uniform2d.cli.main import main
from uniform2d.io import read_polygon

SQ = [[0, 0], [4, 0], [4, 4], [0, 4]]
POLY = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n"
EDGES = "4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n"

CASES = [
    ("e.wkt", "MULTIPOLYGON EMPTY",
     ["empty MULTIPOLYGON", "no polygon to mesh", "give one POLYGON ((x y, ...))"]),
    ("e.wkt", "POLYGON EMPTY", ["empty POLYGON", "give the outline's coordinates"]),
    ("e.wkt", "GEOMETRYCOLLECTION (MULTIPOLYGON EMPTY, LINESTRING (0 0, 1 1))",
     ["holds 0 non-empty POLYGONs", "needs exactly one"]),
    ("n.geojson", json.dumps({"type": "Polygon", "coordinates": [None]}),
     ["the outer ring must be a list of [x, y]", "got null"]),
    ("n.geojson", json.dumps({"type": "Polygon", "coordinates": [[None]]}),
     ["the outer ring[0] must be a position [x, y]", "got null"]),
    ("n.geojson", json.dumps({"type": "MultiPolygon", "coordinates": [None]}),
     ["the MultiPolygon's only polygon is null", "must be a non-empty list of rings"]),
    ("n.geojson", json.dumps({"type": "Feature", "properties": {},
                              "geometry": {"type": "Polygon", "coordinates": [None]}}),
     ["the outer ring must be a list of [x, y]", "got null"]),
    ("h.poly", POLY + EDGES + "-1\n",
     ["line 11: negative hole count -1", "give 0 or the number of hole points that follow"]),
    ("h.poly", POLY + "-4 0\n", ["line 6: negative segment count -4", "give 0 or the number"]),
    ("h.poly", "-4 2 0 0\n", ["line 1: negative vertex count -4", "give 0 or the number"]),
    ("h.poly", POLY + EDGES + "0\n-2\n", ["line 12: negative regional attribute count -2",
                                          "give 0 or the number"]),
]


@pytest.mark.parametrize("name, text, words", CASES)
def test_library_message(tmp_path, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(FileFormatError) as e:
        read_polygon(path)
    assert isinstance(e.value, Uniform2dError)
    msg = str(e.value)
    assert msg.startswith(f"{path}: ")
    for w in words:
        assert w in msg


@pytest.mark.parametrize("name, text, words", CASES)
def test_cli_one_line_exit_2(tmp_path, capsys, name, text, words):
    path = tmp_path / name
    path.write_text(text)
    out = tmp_path / "m.msh"
    assert main(["mesh", str(path), "-n", "10", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("uniform2d: error: ") and all(w in err for w in words)
    assert not out.exists()


def test_one_part_multipolygon_in_a_collection_is_read(tmp_path):
    path = tmp_path / "c.wkt"
    path.write_text("GEOMETRYCOLLECTION (MULTIPOLYGON (((0 0, 4 0, 4 4, 0 4, 0 0))), "
                    "LINESTRING (1 1, 3 3))")
    p = read_polygon(path)
    assert p.area == 16.0 and len(p.segments) == 1
    path.write_text("GEOMETRYCOLLECTION (MULTIPOLYGON (((0 0, 1 0, 1 1, 0 0)), "
                    "((5 5, 6 5, 6 6, 5 5))))")
    with pytest.raises(FileFormatError, match="MultiPolygon with 2 parts; uniform2d meshes one"):
        read_polygon(path)
