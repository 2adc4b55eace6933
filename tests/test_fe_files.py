"""Meshes in finite-element files, read back with the real tools: Gmsh lists the
physical groups by name, meshio the Abaqus sets and element type and the VTU
cells and names, scikit-fem the named subdomains and boundaries (issue 33, items
2, 3 and 6)."""

import json

import meshio
import numpy as np
import pytest
from test_cli import DATA, assert_one_error, run

import uniform2d
from uniform2d import InvalidArgumentError, read_mesh, read_polygon
from uniform2d.io import write_mesh
from uniform2d.mesh_regions import ring_chains
from uniform2d.testing import check_mesh

CASES = {"roof": (DATA / "constrained" / "roof_panel.json", 120),
         "slab": (DATA / "constrained" / "slab_columns.json", 150),
         "plate": (DATA / "plate_bolts.json", 200)}


@pytest.fixture(scope="module", params=list(CASES))
def mesh(request):
    path, n = CASES[request.param]
    polygon = read_polygon(path)
    m = uniform2d.uniform_mesh(polygon, n=n)
    check_mesh(m.points, m.triangles, polygon, delaunay=False, n_steiner=n)
    return m


def _chain_nodes(edges):
    return {int(v) for v in np.asarray(edges).ravel()}


def _expected_groups(m):
    """name -> (dim, what the group holds): triangle indices, edge set or node."""
    labels = m.region_labels if m.polygon.region_seeds else (None,)
    regions = m.regions if m.polygon.region_seeds or m.polygon.has_constraints else np.zeros(
        len(m.triangles), np.int64)
    out = {}
    for r, lab in enumerate(labels):
        out[f"region {r}" if lab is None else str(lab)] = (2, np.flatnonzero(regions == r))
    edges, ids = m.ring_members
    for r in range(len(m.polygon.rings)):
        out["outer" if r == 0 else f"hole {r - 1}"] = (1, edges[ids == r])
    edges, ids = m.segment_members
    for s in range(len(m.polygon.segments)):
        out[f"segment {s}"] = (1, edges[ids == s])
    for k, v in enumerate(m.polygon.fixed.tolist()):
        out[f"point {k}"] = (0, np.array([v]))
    return out


def _edge_set(edges):
    return {tuple(sorted(e)) for e in np.asarray(edges).reshape(-1, 2).tolist()}


# -- the rings of a mesh -------------------------------------------------------------
def test_ring_members_walk_the_boundary(mesh):
    edges, ids = mesh.ring_members
    p = mesh.polygon
    assert sorted(set(ids.tolist())) == list(range(len(p.rings)))
    he = mesh.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    undirected = np.sort(he, axis=1)
    _, inv, count = np.unique(undirected, axis=0, return_inverse=True, return_counts=True)
    boundary = {tuple(e) for e in he[count[inv.ravel()] == 1].tolist()}
    assert {tuple(e) for e in edges.tolist()} == boundary  # directed as the triangles run
    for r in range(len(p.rings)):
        chain = edges[ids == r]
        assert chain[0, 0] == p.ring_offsets[r] == chain[-1, 1]  # from the ring's first vertex
        assert (chain[1:, 0] == chain[:-1, 1]).all()
        length = np.hypot(*(mesh.points[chain[:, 1]] - mesh.points[chain[:, 0]]).T).sum()
        ring = p.rings[r]
        assert length == pytest.approx(np.hypot(*(np.roll(ring, -1, 0) - ring).T).sum(), rel=1e-12)


def test_ring_members_refuse_a_mesh_missing_a_hole():
    p = read_polygon(DATA / "plate_bolts.json")
    m = uniform2d.uniform_mesh(read_polygon(DATA / "plate_bolts.json"), n=60)
    keep = m.triangles[~np.isin(m.triangles, np.arange(*p.ring_offsets[1:3])).any(axis=1)]
    with pytest.raises(InvalidArgumentError, match="does not conform to the polygon"):
        ring_chains(p, m.points, keep)


# -- Gmsh ------------------------------------------------------------------------------
def test_gmsh_lists_the_physical_groups_by_name(tmp_path, mesh):
    gmsh = pytest.importorskip("gmsh")
    path = tmp_path / "m.msh"
    mesh.write(path)
    want = _expected_groups(mesh)
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.logger.start()
        gmsh.open(str(path))
        assert [w for w in gmsh.logger.get() if "rror" in w or "arning" in w] == []
        got = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
        assert set(got) == set(want)
        for name, (dim, items) in want.items():
            d, tag = got[name]
            assert d == dim
            nodes, coords = gmsh.model.mesh.getNodesForPhysicalGroup(d, tag)
            index = np.asarray(nodes, np.int64) - 1
            np.testing.assert_array_equal(coords.reshape(-1, 3)[:, :2], mesh.points[index])
            elements = [np.asarray(gmsh.model.mesh.getElements(d, e)[2][0]).reshape(-1, d + 1)
                        for e in gmsh.model.getEntitiesForPhysicalGroup(d, tag)]
            elements = np.concatenate(elements) - 1
            if dim == 2:
                assert len(elements) == len(items)
                assert _edge_set(elements[:, [0, 1, 1, 2, 2, 0]]) == _edge_set(
                    mesh.triangles[items][:, [0, 1, 1, 2, 2, 0]])
            elif dim == 1:
                assert _edge_set(elements) == _edge_set(items) and len(elements) == len(items)
            else:
                assert elements.ravel().tolist() == items.tolist()
    finally:
        gmsh.logger.stop()
        gmsh.finalize()


def test_scikit_fem_sees_named_subdomains_and_boundaries(tmp_path, mesh):
    skfem = pytest.importorskip("skfem")
    path = tmp_path / "m.msh"
    mesh.write(path)
    m = skfem.Mesh.load(str(path))
    np.testing.assert_array_equal(m.p.T, mesh.points)
    want = _expected_groups(mesh)
    subdomains = {k: v for k, v in want.items() if v[0] == 2}
    boundaries = {k: v for k, v in want.items() if v[0] == 1}
    assert set(m.subdomains) == set(subdomains)
    assert set(m.boundaries) == set(boundaries)
    for name, (_, items) in subdomains.items():
        assert {tuple(sorted(t)) for t in m.t.T[m.subdomains[name]].tolist()} == {
            tuple(sorted(t)) for t in mesh.triangles[items].tolist()}
    for name, (_, items) in boundaries.items():
        facets = m.facets.T[np.asarray(m.boundaries[name])]
        assert _edge_set(facets) == _edge_set(items) and len(facets) == len(items)
    rings = np.concatenate([m.boundaries[k] for k in boundaries if not k.startswith("segment")])
    assert sorted(rings.tolist()) == sorted(m.boundary_facets().tolist())


def test_gmsh_file_reads_back_with_regions(tmp_path, mesh):
    path = tmp_path / "m.msh"
    mesh.write(path)
    pts, tri, reg = read_mesh(path, regions=True)
    np.testing.assert_array_equal(pts, mesh.points)
    regions = mesh.regions if mesh.polygon.has_constraints else np.zeros(len(tri), int)
    assert sorted(zip(map(tuple, tri.tolist()), reg.tolist())) == sorted(
        zip(map(tuple, mesh.triangles.tolist()), regions.tolist()))


# -- Abaqus ----------------------------------------------------------------------------
def test_abaqus_sets_and_element_type_through_meshio(tmp_path, mesh):
    path = tmp_path / "m.inp"
    mesh.write(path)
    text = path.read_text()
    assert "*ELEMENT, TYPE=CPS3\n" in text and "R3D3" not in text
    m = meshio.read(path)
    assert [c.type for c in m.cells] == ["triangle"]
    np.testing.assert_array_equal(m.points, mesh.points)  # 2-D nodes, exact
    np.testing.assert_array_equal(m.cells[0].data, mesh.triangles)
    want = _expected_groups(mesh)
    abaqus = {name.upper().replace(" ", "_"): v for name, v in want.items() if v[0] < 2}
    assert set(m.point_sets) == set(abaqus)
    for name, (_, items) in abaqus.items():
        assert set(m.point_sets[name].tolist()) == _chain_nodes(items)
    regions = [v for v in want.values() if v[0] == 2]
    assert len(m.cell_sets) == len(regions)
    assert sorted(sorted(v[0].tolist()) for v in m.cell_sets.values()) == sorted(
        sorted(items.tolist()) for _, items in regions)


def test_abaqus_ring_surfaces_are_the_boundary_faces(tmp_path, mesh):
    path = tmp_path / "m.inp"
    mesh.write(path)
    text = path.read_text()
    edges, ids = mesh.ring_members
    for r in range(len(mesh.polygon.rings)):
        name = "OUTER" if r == 0 else f"HOLE_{r - 1}"
        block = text.split(f"*SURFACE, TYPE=ELEMENT, NAME={name}_EDGES\n")[1].split("*")[0]
        faces = [line.split(", ") for line in block.split("\n") if line]
        got = set()
        for e, f in faces:
            a, b, c = mesh.triangles[int(e) - 1]
            got.add({"S1": (a, b), "S2": (b, c), "S3": (c, a)}[f])
        assert got == {tuple(e) for e in edges[ids == r].tolist()}


@pytest.mark.parametrize("etype", ["CPE3", "CAX3", "cps3"])
def test_abaqus_element_types_on_request(tmp_path, etype):
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    tri = np.array([[0, 1, 2], [0, 2, 3]])
    path = tmp_path / "m.inp"
    write_mesh(path, pts, tri, element_type=etype)
    assert f"*ELEMENT, TYPE={etype.upper()}\n" in path.read_text()
    p, t = read_mesh(path)  # meshio alone does not know CPE3 and CAX3
    np.testing.assert_array_equal(p, pts)
    np.testing.assert_array_equal(t, tri)


@pytest.mark.parametrize("name, kw, words", [
    ("m.inp", {"element_type": "S3"}, "'S3' not available; use one of CPS3, CPE3, CAX3"),
    ("m.inp", {"element_type": "C3D4"}, "use one of CPS3, CPE3, CAX3"),
    ("m.vtu", {"element_type": "CPS3"}, "declares no element type"),
])
def test_element_type_refusals(tmp_path, name, kw, words):
    pts, tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [[0, 1, 2]]
    with pytest.raises(InvalidArgumentError, match=words):
        write_mesh(tmp_path / name, pts, tri, **kw)
    assert list(tmp_path.iterdir()) == []


def test_axisymmetric_needs_non_negative_radius(tmp_path):
    with pytest.raises(InvalidArgumentError, match="x is the radius"):
        write_mesh(tmp_path / "m.inp", [[-1.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [[0, 1, 2]],
                   element_type="CAX3")
    assert list(tmp_path.iterdir()) == []


def test_surface_remesh_is_written_with_shell_elements(tmp_path):
    pytest.importorskip("trimesh")
    from surface import write_patch

    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    F = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    write_patch(tmp_path / "t.inp", V, F)
    assert "*ELEMENT, TYPE=S3\n" in (tmp_path / "t.inp").read_text()
    m = meshio.read(tmp_path / "t.inp")
    np.testing.assert_array_equal(m.points, V)
    np.testing.assert_array_equal(m.cells_dict["triangle"], F)
    write_patch(tmp_path / "r.inp", V, F, element_type="S3R")
    assert "TYPE=S3R\n" in (tmp_path / "r.inp").read_text()
    with pytest.raises(InvalidArgumentError, match="does not fit a surface"):
        write_patch(tmp_path / "x.inp", V, F, element_type="CPS3")


# -- VTU / VTK -------------------------------------------------------------------------
@pytest.mark.parametrize("ext", [".vtu", ".vtk"])
def test_vtk_files_carry_the_sets_as_cells(tmp_path, mesh, ext):
    path = tmp_path / ("m" + ext)
    mesh.write(path)
    m = meshio.read(path)
    want = _expected_groups(mesh)
    tags = {name: k for k, name in enumerate(want, start=1)}
    if ext == ".vtu":  # the names, as meshio gives Gmsh's physical names
        assert {k: v.tolist() for k, v in m.field_data.items()} == {
            name: [tags[name], dim] for name, (dim, _) in want.items()}
    kinds = {c.type: k for k, c in enumerate(m.cells)}
    np.testing.assert_array_equal(m.cells[kinds["triangle"]].data, mesh.triangles)
    tri_set = m.cell_data["set"][kinds["triangle"]]
    line_set = m.cell_data["set"][kinds["line"]]
    lines = m.cells[kinds["line"]].data
    for name, (dim, items) in want.items():
        if dim == 2:
            assert sorted(np.flatnonzero(tri_set == tags[name]).tolist()) == sorted(items.tolist())
        elif dim == 1:
            assert _edge_set(lines[line_set == tags[name]]) == _edge_set(items)
        else:
            vert = m.cells[kinds["vertex"]].data[m.cell_data["set"][kinds["vertex"]] == tags[name]]
            assert vert.ravel().tolist() == items.tolist()
    assert (m.cell_data["region"][kinds["line"]] == -1).all()
    assert read_mesh(path, regions=True)[2].tolist() == np.asarray(
        m.cell_data["region"][kinds["triangle"]]).tolist()


# -- several outputs from one run ------------------------------------------------------
def test_one_run_writes_several_formats(capsys, tmp_path):
    src = DATA / "constrained" / "roof_panel.json"
    outs = [tmp_path / n for n in ("a.msh", "a.inp", "a.vtu")]
    argv = ["mesh", src, "-n", 60, "--element-type", "cpe3", "--json"]
    code, out, err = run(capsys, *argv, *[x for o in outs for x in ("-o", o)])
    assert code == 0, err
    doc = json.loads(out)
    assert doc["outputs"] == [str(o) for o in outs] and doc["output"] == str(outs[0])
    assert "*ELEMENT, TYPE=CPE3\n" in outs[1].read_text()
    # the same bytes as one run per format
    for o in outs:
        single = tmp_path / ("single" + o.suffix)
        code, _, err = run(capsys, "mesh", src, "-n", 60, "-o", single,
                           *(["--element-type", "CPE3"] if o.suffix == ".inp" else []))
        assert code == 0, err
        assert single.read_bytes() == o.read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["a.msh", "a.inp", "a.vtu", "single.msh", "single.inp", "single.vtu"])


@pytest.mark.parametrize("outputs, extra, words", [
    (["a.msh", "a.xyz"], [], "unknown extension '.xyz'"),
    (["a.msh", "missing/a.inp"], [], "directory 'missing' does not exist"),
    (["a.msh", "./a.msh"], [], "name one file twice"),
    (["a.msh", "a.vtu"], ["--element-type", "CAX3"], "applies to Abaqus .inp outputs"),
])
def test_every_output_is_checked_before_meshing(capsys, tmp_path, monkeypatch, outputs, extra,
                                                words):
    import uniform2d.cli.mesh as cli_mesh

    def never(*args, **kwargs):
        raise AssertionError("meshed before the outputs were checked")

    monkeypatch.setattr(cli_mesh, "_mesh_one", never)
    monkeypatch.chdir(tmp_path)
    argv = ["mesh", DATA / "constrained" / "roof_panel.json", "-n", 60, *extra]
    code, out, err = run(capsys, *argv, *[x for o in outputs for x in ("-o", o)])
    assert_one_error(code, out, err)
    assert words in err
    assert list(tmp_path.iterdir()) == []


def test_several_inputs_take_one_output_directory(capsys, tmp_path):
    src = [DATA / "constrained" / "roof_panel.json", DATA / "plate_bolts.json"]
    code, out, err = run(capsys, "mesh", *src, "-n", 60, "-o", tmp_path / "a/", "-o",
                         tmp_path / "b/")
    assert_one_error(code, out, err)
    assert "give one -o directory" in err


def test_remesh_writes_several_formats(capsys, tmp_path):
    pytest.importorskip("igl")
    pytest.importorskip("pymeshlab")
    outs = [tmp_path / "s.obj", tmp_path / "s.inp"]
    code, out, err = run(capsys, "remesh", DATA / "patches" / "cap60.obj", "-n", 60,
                         *[x for o in outs for x in ("-o", o)])
    assert code == 0, err
    assert out.startswith(f"wrote {outs[0]}, {outs[1]} (60 vertices")
    m = meshio.read(outs[1])
    assert m.points.shape == (60, 3) and "*ELEMENT, TYPE=S3\n" in outs[1].read_text()
    import surface
    obj = surface.read_model(outs[0])
    np.testing.assert_allclose(m.points, obj.vertices, rtol=0, atol=1e-15)
    code, out, err = run(capsys, "remesh", DATA / "patches" / "cap60.obj", "-n", 60,
                         "-o", tmp_path / "t.obj", "--element-type", "S3R")
    assert_one_error(code, out, err)
    assert "applies to Abaqus .inp outputs" in err


def test_set_names_stay_unique(tmp_path):
    """Two regions with one label, a region labelled like a ring: every Gmsh name and
    every Abaqus set name is still one set's."""
    from uniform2d.io.mesh_sets import mesh_sets

    ring = (np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), np.zeros(4, int))
    sets = mesh_sets(3, regions=np.array([0, 1, 2]), labels=("slab", "slab", "outer"),
                     ring_members=ring, segment_members=(np.array([[0, 2]]), np.array([0])))
    assert [(s.name, s.abaqus, s.tag) for s in sets] == [
        ("slab", "REGION_0_SLAB", 1), ("slab (tag 2)", "REGION_1_SLAB", 2),
        ("outer", "REGION_2_OUTER", 3), ("outer (tag 4)", "OUTER", 4),
        ("segment 0", "SEGMENT_0", 5)]
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    tri = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    write_mesh(tmp_path / "m.msh", pts, tri, regions=[0, 1, 2, 2],
               region_labels=("slab", "slab", "outer"), ring_members=ring)
    m = meshio.read(tmp_path / "m.msh")
    assert {k: v.tolist() for k, v in m.field_data.items()} == {
        "slab": [1, 2], "slab (tag 2)": [2, 2], "outer": [3, 2], "outer (tag 4)": [4, 1]}
    assert read_mesh(tmp_path / "m.msh", regions=True)[2].tolist() == [0, 1, 2, 2]
