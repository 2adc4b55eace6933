"""The report keeps the whole problem: constraints reach our meshes and the peers'."""

from __future__ import annotations

import json
from itertools import pairwise
from pathlib import Path

import meshio
import numpy as np
import pytest

from uniform2d import peers
from uniform2d.io import read_polygon
from uniform2d.mesh_regions import polygon_vertices_first
from uniform2d.report import make_report
from uniform2d.testing import check_mesh

ROOT = Path(__file__).resolve().parents[1]
ROOF = ROOT / "data/constrained/roof_panel.json"


def _checked(path, polygon, method):
    """The mesh in ``path`` (read back with meshio), checked against ``polygon``."""
    m = meshio.read(path)
    pts, tri = polygon_vertices_first(polygon, m.points[:, :2], m.cells_dict["triangle"])
    check_mesh(pts, tri, polygon, delaunay=method in ("tplus", "uniform"))
    return pts, tri


def _on_segment_edges(points, triangles, a, b) -> list:
    """Independent check that segment a-b is a union of mesh edges: the mesh
    vertices within 1e-9 of its length from it, sorted along it, must start at a,
    end at b, and every consecutive two must be a mesh edge.  Returns what fails."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    L = float(np.hypot(*d))
    rel = points - a
    t = rel @ d / L**2
    dist = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0]) / L
    on = np.flatnonzero((dist <= 1e-9 * L) & (t >= -1e-12) & (t <= 1 + 1e-12))
    on = on[np.argsort(t[on])]
    edges = {tuple(sorted(e)) for t3 in triangles.tolist()
             for e in ((t3[0], t3[1]), (t3[1], t3[2]), (t3[2], t3[0]))}
    bad = []
    if len(on) < 2 or not np.allclose(points[on[0]], a) or not np.allclose(points[on[-1]], b):
        bad.append(f"ends of {a.tolist()}-{b.tolist()} are not mesh vertices")
    bad += [f"{points[u].tolist()}-{points[v].tolist()} on the segment is not an edge"
            for u, v in pairwise(on) if tuple(sorted((int(u), int(v)))) not in edges]
    return bad


@pytest.fixture(scope="module")
def roof_report(tmp_path_factory):
    pytest.importorskip("gmsh")
    out = tmp_path_factory.mktemp("roof")
    return out, make_report([str(ROOF)], out, ns=[300], peers=["gmsh"], figures=False)


def test_roof_report_has_the_segments_in_ours_and_gmsh(roof_report):
    out, res = roof_report
    spec = json.loads(ROOF.read_text())
    assert [c["status"] for c in res["cases"]] == ["ok", "ok", "ok"]
    assert [c["method"] for c in res["cases"]] == ["tplus", "uniform", "gmsh"]
    for c in res["cases"]:
        pts, tri = _checked(out / c["mesh"], read_polygon(ROOF), c["method"])
        for seg in spec["segments"]:
            for a, b in pairwise(seg):
                assert _on_segment_edges(pts, tri, a, b) == [], c["method"]
    # 300 Steiner points plus the 6 vertices (the ridge's end (6, 3) is one)
    assert res["cases"][0]["target_vertices"] == 306


def test_roof_report_describes_the_constraints(roof_report):
    out, res = roof_report
    inp = res["inputs"][0]
    assert (inp["n_vertices"], inp["n_holes"], inp["n_segments"], inp["n_points"]) == (6, 0, 3, 0)
    md = (out / "report.md").read_text()
    assert "polygon, 6 vertices, 0 holes, 3 segments, 3 labelled regions, area 60" in md


def test_fixed_points_reach_the_peers(tmp_path):
    """Triangle and the CVT baseline take segments and fixed points too."""
    spec = {"outer": [[0, 0], [4, 0], [4, 2], [0, 2]], "holes": [[[2.5, 0.5], [3.5, 0.5], [3.5, 1.5]]],
            "segments": [[[0.5, 0.3], [1.7, 1.6]]], "points": [[1.0, 1.5], [3.2, 1.8]]}
    src = tmp_path / "p.json"
    src.write_text(json.dumps(spec))
    names = [p for p in ("triangle", "cvt", "gmsh") if peers.available(p)]
    res = make_report([str(src)], tmp_path / "r", ns=[60], peers=names, figures=False)
    assert "polygon, 11 vertices, 1 hole, 1 segment, 2 fixed points" in (tmp_path / "r/report.md").read_text()
    for c in res["cases"]:
        assert c["status"] == "ok", c
        pts, tri = _checked(tmp_path / "r" / c["mesh"], read_polygon(src), c["method"])
        assert _on_segment_edges(pts, tri, *spec["segments"][0]) == [], c["method"]
        for q in spec["points"]:
            assert np.any(np.all(pts == q, axis=1)), (c["method"], q)
        assert c["measures"]["n_vertices"] - c["target_vertices"] == c["measures"]["vertex_error"]


def test_a_peer_without_constraints_is_not_comparable(tmp_path, monkeypatch):
    monkeypatch.setattr(peers, "takes_constraints", lambda name: name != "cvt")
    res = make_report([str(ROOF)], tmp_path, ns=[40], peers=["cvt"], figures=False)
    cvt = [c for c in res["cases"] if c["method"] == "cvt"]
    assert len(cvt) == 1 and cvt[0]["status"] == "not comparable" and cvt[0]["mesh"] is None
    assert "cannot take the segments" in cvt[0]["message"]
    md = (tmp_path / "report.md").read_text()
    assert "not comparable: cvt cannot take" in md and "| cvt | 0/1 (not comparable) |" in md
    # an unconstrained polygon is still compared
    res = make_report([str(ROOT / "data/benchmarks/square.json")], tmp_path / "sq", ns=[20],
                      peers=["cvt"], figures=False)
    assert [c["status"] for c in res["cases"]] == ["ok", "ok", "ok"]


def test_feature_angle_reaches_the_surface_remesh(tmp_path):
    pytest.importorskip("surface")
    src = str(ROOT / "data/patches/folded_plate.obj")
    flat = make_report([src], tmp_path / "a", ns=[300], peers=[], figures=False)
    kept = make_report([src], tmp_path / "b", ns=[300], peers=[], figures=False, feature_angle=30)
    dev = [r["cases"][0]["measures"]["hausdorff_max_rel"] for r in (flat, kept)]
    assert dev[0] > 1e-3 and dev[1] < 1e-12
