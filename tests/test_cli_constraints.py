"""The command on constrained polygon files: info lists segments, points, regions
and the smallest sensible n; mesh writes regions; every constraint error is one line."""

import json

import numpy as np
import pytest

from uniform2d import read_mesh, read_polygon, write_polygon
from uniform2d.cli.info import smallest_sensible_n
from uniform2d.mesh import Mesh

from support.conmesh import triangle_mesh
from test_cli import DATA, assert_one_error, run
from test_io_constraints import CROSSING, slab

FORMATS = (".json", ".geojson", ".wkt", ".poly", ".dxf")


@pytest.mark.parametrize("ext", FORMATS)
def test_info_on_every_format(capsys, tmp_path, ext):
    path = tmp_path / ("slab" + ext)
    labels = (3, 2.5) if ext == ".poly" else ("west", "zone")
    write_polygon(path, slab(labels))
    code, out, err = run(capsys, "info", path, "--json")
    assert code == 0, err
    d = json.loads(out)
    if ext != ".poly":  # .poly chains the pieces anew
        assert [s["length"] for s in d["segments"]] == pytest.approx(
            [10, 12, 2 * 2**0.5, 2 + 0.5 * 2**0.5], rel=1e-12)
    assert d["segment_length"] == pytest.approx(10 + 12 + 2 * 2**0.5 + 2 + 0.5 * 2**0.5)
    assert [r["area"] for r in d["regions"]] == [40, 47, 9]
    want = [None, None, None] if ext == ".wkt" else [labels[0], None, labels[1]]
    assert [r["label"] for r in d["regions"]] == want
    assert d["smallest_sensible_n"] == smallest_sensible_n(read_polygon(path))
    code, out, err = run(capsys, "info", path)
    assert "segments:        " in out and "region 2: area 9" in out and "smallest sensible n" in out


def test_smallest_sensible_n_bounds_tplus():
    """The cheap count is a lower bound on T+'s smallest feasible n (found by
    running INSERT), and equal to it on these polygons."""
    from uniform2d.tplus import smallest_feasible_n

    for name in ("benchmarks/heptagon_short.json", "benchmarks/square2holes.json", "truss_panel.json"):
        p = read_polygon(DATA / name)
        assert smallest_sensible_n(p) == smallest_feasible_n(p)


def test_smallest_sensible_n_counts_segments():
    from uniform2d import Polygon

    sq = [(0, 0), (12, 0), (12, 12), (0, 12)]
    bare = Polygon(sq, points=[(1, 1)])
    wall = Polygon(sq, segments=[[(6, 0), (6, 12)]], points=[(1, 1)])
    # l(V, V) = sqrt(2): 12 / (3 sqrt 2) -> 3 pieces, 2 points per side of 12
    assert smallest_sensible_n(bare) == 4 * 2
    # the wall splits the two sides it meets (6 -> 2 pieces each) and gets 2 points
    assert smallest_sensible_n(wall) == 2 * 2 + 4 * 1 + 2


@pytest.mark.parametrize("ext", [*CROSSING, ".dxf"])
def test_constraint_errors_are_one_line(capsys, tmp_path, ext):
    path = tmp_path / ("x" + ext)
    if ext == ".dxf":
        import ezdxf
        doc = ezdxf.new("R2010")
        msp = doc.modelspace()
        msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
        msp.add_line((1, 1), (5, 5))
        msp.add_line((1, 5), (5, 1))
        doc.saveas(path)
    else:
        path.write_text(CROSSING[ext])
    for argv in (("info", path), ("mesh", path, "-n", 50, "-o", tmp_path / "m.vtu")):
        code, out, err = run(capsys, *argv)
        assert_one_error(code, out, err)
        assert "segment 1 crosses segment 0 at (3, 3)" in err
    assert not (tmp_path / "m.vtu").exists()


def test_bad_region_seed_is_one_line(capsys, tmp_path):
    path = tmp_path / "r.json"
    path.write_text(json.dumps({"outer": [[0, 0], [4, 0], [4, 4], [0, 4]],
                                "segments": [[[2, 0], [2, 4]]], "regions": [[2, 1, "wall"]]}))
    code, out, err = run(capsys, "info", path)
    assert_one_error(code, out, err)
    assert "lies on a ring or segment" in err


@pytest.mark.parametrize("ext", [".vtu", ".msh", ".csv"])
def test_mesh_writes_regions(capsys, tmp_path, monkeypatch, ext):
    """The command's whole path -- read, mesh, write with regions, report -- with
    the mesher replaced by Triangle (any conforming mesh will do)."""
    import uniform2d.cli.mesh as cli_mesh

    def fake(polygon, args, progress=None):
        pts, tri = triangle_mesh(polygon, max_area=1.0)
        return Mesh(pts, tri, polygon, len(pts) - len(polygon.vertices), {"method": "triangle"})

    monkeypatch.setattr(cli_mesh, "_mesh_one", fake)
    src = tmp_path / "slab.geojson"
    write_polygon(src, slab())
    code, out, err = run(capsys, "mesh", src, "-n", 50, "-o", tmp_path / ("m" + ext), "--json")
    assert code == 0, err
    doc = json.loads(out)[0] if out.lstrip().startswith("[") else json.loads(out)
    assert [r["label"] for r in doc["regions"]] == ["west", None, "zone"]
    assert [r["area"] for r in doc["regions"]] == pytest.approx([40, 47, 9], rel=1e-12)
    pts, tri, reg = read_mesh(tmp_path / ("m" + ext), regions=True)
    assert np.bincount(reg).tolist() == [r["triangles"] for r in doc["regions"]]
    code, out, err = run(capsys, "mesh", src, "-n", 50, "-o", tmp_path / ("s" + ext), "--stats")
    assert code == 0 and "region 0 (west):" in out and "region 2 (zone):" in out
