"""Meshes of constrained polygons in files: regions and segment members round-trip."""

import csv
import json
import logging

import numpy as np
import pytest

from uniform2d import InvalidArgumentError, Polygon
from uniform2d.io import mesh_formats, read_mesh, write_mesh
from uniform2d.io.registry import MESH_FORMATS
from uniform2d.mesh import Mesh

from support.conmesh import triangle_mesh

REGION_EXTS = [e for e, f in MESH_FORMATS.items() if f.regions]
OTHER_EXTS = [e for e, f in MESH_FORMATS.items() if not f.regions]


@pytest.fixture(scope="module")
def mesh():
    p = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(7, 7), (9, 7), (9, 9), (7, 9)]],
                segments=[[(4, 0), (4, 10)], [(5, 2), (8, 2), (8, 5), (5, 5), (5, 2)],
                          [(1, 1), (3, 3)]],
                points=[(2, 8)], regions=[(2, 5, "west zone"), (6.5, 3, 7)])
    pts, tri = triangle_mesh(p, max_area=1.0)
    m = Mesh(pts, tri, p, len(pts) - len(p.vertices))
    assert sorted(set(m.regions.tolist())) == [0, 1, 2]
    return m


def _canon(tri, reg):
    """Triangles as sets, with their regions: a file may reorder and rotate them."""
    return sorted((tuple(sorted(t)), int(r)) for t, r in zip(tri.tolist(), reg.tolist()))


def test_every_format_is_listed_one_way_or_the_other():
    assert set(REGION_EXTS) >= {".vtu", ".vtk", ".msh", ".inp", ".mesh", ".csv", ".truss.json"}
    assert set(REGION_EXTS) | set(OTHER_EXTS) == set(mesh_formats())


@pytest.mark.parametrize("ext", REGION_EXTS)
def test_regions_round_trip(tmp_path, mesh, ext):
    path = tmp_path / ("m" + ext)
    mesh.write(path)
    pts, tri, reg = read_mesh(path, regions=True)
    np.testing.assert_array_equal(pts, mesh.points)
    assert reg is not None
    assert _canon(tri, reg) == _canon(mesh.triangles, mesh.regions)


@pytest.mark.parametrize("ext", OTHER_EXTS)
def test_formats_without_cell_data_drop_regions_with_a_warning(tmp_path, mesh, ext, caplog):
    path = tmp_path / ("m" + ext)
    with caplog.at_level(logging.WARNING, logger="uniform2d"):
        mesh.write(path)
    assert "does not store regions" in caplog.text
    assert read_mesh(path, regions=True)[2] is None


def test_plain_meshes_have_no_regions_in_files(tmp_path):
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    write_mesh(tmp_path / "a.vtu", pts, [[0, 1, 2], [0, 2, 3]])
    assert read_mesh(tmp_path / "a.vtu", regions=True)[2] is None
    write_mesh(tmp_path / "a.csv", pts, [[0, 1, 2], [0, 2, 3]])
    assert open(tmp_path / "a.csv").readline().strip() == "kind,id,x,y,i,j,k,length"


def test_gmsh_labels_are_physical_names(tmp_path, mesh):
    mesh.write(tmp_path / "m.msh")
    text = (tmp_path / "m.msh").read_text()
    assert '2 1 "west zone"' in text and '2 2 "region 1"' in text and '2 3 "7"' in text
    import meshio
    m = meshio.read(tmp_path / "m.msh")
    assert {k: v.tolist() for k, v in m.field_data.items()} == {
        "west zone": [1, 2], "region 1": [2, 2], "7": [3, 2], "outer": [4, 1], "hole 0": [5, 1],
        "segment 0": [6, 1], "segment 1": [7, 1], "segment 2": [8, 1], "point 0": [9, 0]}


def test_abaqus_element_sets_are_named_after_labels(tmp_path, mesh):
    mesh.write(tmp_path / "m.inp")
    text = (tmp_path / "m.inp").read_text()
    for name in ("REGION_0_WEST_ZONE", "REGION_1", "REGION_2_7"):
        assert f"ELSET={name}" in text.replace(" ", "").upper()


def test_truss_csv_marks_segment_members_and_triangle_regions(tmp_path, mesh):
    mesh.write(tmp_path / "m.csv")
    rows = list(csv.DictReader(open(tmp_path / "m.csv")))
    members = [r for r in rows if r["kind"] == "member"]
    edges, ids = mesh.segment_members
    # every number in the CSV counts from 1: ids, nodes, segments and regions
    marked = {(min(a, b) + 1, max(a, b) + 1): s + 1
              for (a, b), s in zip(edges.tolist(), ids.tolist())}
    for r in members:
        key = (int(r["i"]), int(r["j"]))
        assert r["segment"] == (str(marked[key]) if key in marked else "")
    assert sum(r["segment"] != "" for r in members) == len(edges)
    assert {r["segment"] for r in members} == {"", "1", "2", "3"}
    tris = [r for r in rows if r["kind"] == "triangle"]
    assert [int(r["region"]) - 1 for r in tris] == mesh.regions.tolist()
    labels = {int(r["region"]): r["label"] for r in tris}
    assert labels == {1: "west zone", 2: "", 3: "7"}


def test_truss_csv_written_before_counting_from_1_still_reads(tmp_path, mesh):
    """Files of earlier versions counted regions from 0 (they always hold a 0)."""
    mesh.write(tmp_path / "m.csv")
    with open(tmp_path / "m.csv") as f:
        rows = list(csv.reader(f))
    col = rows[0].index("region")
    for row in rows[1:]:
        if row[0] == "triangle":
            row[col] = str(int(row[col]) - 1)
    with open(tmp_path / "old.csv", "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    for name in ("m.csv", "old.csv"):
        assert read_mesh(tmp_path / name, regions=True)[2].tolist() == mesh.regions.tolist()


def test_truss_json_marks_segment_members(tmp_path, mesh):
    mesh.write(tmp_path / "m.truss.json")
    d = json.load(open(tmp_path / "m.truss.json"))
    seg = np.array(d["member_segments"])
    ij = np.array(d["members"])
    edges, ids = mesh.segment_members
    on = {tuple(sorted(e)): s for e, s in zip(edges.tolist(), ids.tolist())}
    assert [on.get(tuple(e), -1) for e in ij.tolist()] == seg.tolist()
    # each segment's members add up to its length
    L = np.array(d["lengths"])
    for s, line in enumerate(mesh.polygon.segments):
        assert L[seg == s].sum() == pytest.approx(np.hypot(*np.diff(line, axis=0).T).sum(), rel=1e-12)
    assert d["regions"] == mesh.regions.tolist() and d["region_labels"] == ["west zone", None, 7]


@pytest.mark.parametrize("kw, words", [
    (dict(regions=[0]), "one non-negative integer per triangle"),
    (dict(regions=[0.5, 1]), "one non-negative integer per triangle"),
    (dict(regions=[-1, 0]), "one non-negative integer per triangle"),
    (dict(region_labels=["a"]), "region_labels given without regions"),
    (dict(regions=[0, 1], region_labels=["a"]), "region_labels has 1 entries"),
    (dict(segment_members=([[0, 9]], [0])), "segment_members must be"),
])
def test_bad_region_arguments(tmp_path, kw, words):
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    with pytest.raises(InvalidArgumentError, match=words):
        write_mesh(tmp_path / "a.vtu", pts, [[0, 1, 2], [0, 2, 3]], **kw)
    assert not (tmp_path / "a.vtu").exists()


def test_bad_region_data_in_files(tmp_path):
    from uniform2d import FileFormatError
    p = tmp_path / "bad.truss.json"
    p.write_text(json.dumps({"nodes": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 2]], "regions": [-2]}))
    with pytest.raises(FileFormatError, match="one non-negative integer per triangle"):
        read_mesh(p, regions=True)
    import meshio
    meshio.write(tmp_path / "bad.vtu", meshio.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]]),
                 [("triangle", np.array([[0, 1, 2]]))], cell_data={"region": [np.array([0.5])]}))
    with pytest.raises(FileFormatError, match="not whole numbers"):
        read_mesh(tmp_path / "bad.vtu", regions=True)
