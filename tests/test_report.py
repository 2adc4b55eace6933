"""The comparison report (issue 6): files, numbers, missing peers, runners, HTML, CLI."""

from __future__ import annotations

import base64
import html
import json
from html.parser import HTMLParser
from pathlib import Path

import pytest

import uniform2d
from uniform2d import peers
from uniform2d.io import read_mesh, read_polygon
from uniform2d.report import make_report, strip_timings

ROOT = Path(__file__).resolve().parents[1]
POLYGONS = [str(ROOT / "data/benchmarks/square.json"), str(ROOT / "data/benchmarks/lshape.json")]
PATCH = str(ROOT / "data/patches/cap60.obj")
NS = [40]

pytest.importorskip("surface")


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    return out, make_report(POLYGONS + [PATCH], out, ns=NS)


class _Tree(HTMLParser):
    """Collects what the report's structure promises."""

    def __init__(self):
        super().__init__()
        self.stack, self.cases, self.inputs, self.imgs, self.peers = [], {}, [], [], {}
        self.errors = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag not in ("img", "meta", "br"):
            self.stack.append(tag)
        if tag == "tr" and "data-case" in a:
            self.cases[a["data-case"]] = (a.get("data-status"), list(self.stack))
        if tag == "tr" and "data-peer" in a:
            self.peers[a["data-peer"]] = a["data-available"]
        if tag == "section" and "data-input" in a:
            self.inputs.append(a["data-input"])
        if tag == "img":
            self.imgs.append(a.get("src", ""))

    def handle_endtag(self, tag):
        if tag in ("img", "meta", "br"):
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"unbalanced </{tag}> with open {self.stack[-3:]}")
            return
        self.stack.pop()


def _parse(path) -> _Tree:
    t = _Tree()
    t.feed(Path(path).read_text(encoding="utf-8"))
    t.close()
    return t


def test_files_and_cases(serial):
    out, res = serial
    for name in ("index.html", "report.md", "results.json"):
        assert (out / name).is_file()
    assert json.loads((out / "results.json").read_text()) == res
    methods = {(c["input"], c["method"]) for c in res["cases"]}
    for stem in ("square", "lshape"):
        for m in ("tplus", "uniform", "gmsh", "triangle", "cvt"):
            assert (stem, m) in methods
    assert ("cap60", "remesh") in methods and ("cap60", "meshlab") in methods
    assert [p["name"] for p in res["peers"]] == list(peers.defaults())
    for c in res["cases"]:
        if c["family"] == "ours" or peers.available(c["method"]):
            assert c["status"] == "ok", c["message"]
            assert (out / c["mesh"]).is_file()
        else:
            assert c["status"] == "not installed"
        if c["status"] == "ok":
            if c["method"] in ("tplus", "uniform", "remesh", "cvt"):
                assert c["measures"]["vertex_error"] == 0
            assert c["measures"]["n_vertices"] - c["target_vertices"] == c["measures"]["vertex_error"]


def test_numbers_equal_quality_of_written_meshes(serial):
    out, res = serial
    polys = {Path(p).stem: read_polygon(p) for p in POLYGONS}
    checked = 0
    for c in res["cases"]:
        if c["status"] != "ok":
            continue
        if c["kind"] == "polygon":
            pts, tri = read_mesh(out / c["mesh"])
            q = uniform2d.quality(pts, tri, polys[c["input"]])
            assert json.loads(json.dumps(q.to_dict())) == c["quality"]
            m = c["measures"]
            assert m["edge_ratio"] == q.edge_ratio and m["longest_edge"] == q.longest_edge
            assert m["max_perimeter"] == q.max_perimeter and m["cv_edge"] == q.cv_edge
            assert m["min_angle"] == q.min_angle
            assert m["factor_longest_edge"] == q.longest_edge_bound.factor
            assert m["factor_perimeter"] == q.max_perimeter_bound.factor
            assert m["factor_edge_ratio"] == q.edge_ratio_bound.factor
        else:
            from surface import read_patch

            from surface.plugin import measures as surface_measures

            p = read_patch(out / c["mesh"])
            p0 = read_patch(PATCH)
            m = surface_measures(p.vertices, p.faces, p0.vertices, p0.faces)
            m["vertex_error"] = m["n_vertices"] - c["target_vertices"]
            m["vertex_error_rel"] = m["vertex_error"] / c["target_vertices"]
            assert json.loads(json.dumps(m)) == c["measures"]
        checked += 1
    assert checked >= 7


def test_html_structure(serial):
    out, res = serial
    t = _parse(out / "index.html")
    assert not t.errors and not t.stack
    assert set(t.cases) == {c["id"] for c in res["cases"]}
    for c in res["cases"]:
        status, ancestors = t.cases[c["id"]]
        assert status == c["status"]
        assert ancestors[:2] == ["html", "body"] and "section" in ancestors and "table" in ancestors
    assert t.inputs == [i["name"] for i in res["inputs"]] == ["square", "lshape", "cap60"]
    assert set(t.peers) == set(peers.defaults())
    assert len(t.imgs) == 3  # one figure per (input, n)
    for src in t.imgs:
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n"
    md = (out / "report.md").read_text()
    for c in res["cases"]:
        assert f"## {c['input']}, n = {c['n']}" in md


def test_missing_peer_is_listed(tmp_path, monkeypatch):
    from uniform2d.peers import gmsh_peer

    monkeypatch.setattr(gmsh_peer, "available", lambda: False)
    assert not peers.available("gmsh")
    res = make_report(POLYGONS[:1], tmp_path, ns=[20], peers=["gmsh", "cvt"], figures=False)
    info = {p["name"]: p for p in res["peers"]}
    assert info["gmsh"]["available"] is False and info["cvt"]["available"] is True
    gm = [c for c in res["cases"] if c["method"] == "gmsh"]
    assert len(gm) == 1 and gm[0]["status"] == "not installed" and gm[0]["mesh"] is None
    t = _parse(tmp_path / "index.html")
    assert t.cases[gm[0]["id"]][0] == "not installed"
    assert t.peers["gmsh"] == "false"
    assert "not installed" in (tmp_path / "report.md").read_text()


def test_jobs_2_same_results(serial, tmp_path):
    _, res = serial
    res2 = make_report(POLYGONS + [PATCH], tmp_path, ns=NS, jobs=2)
    assert strip_timings(res2) == strip_timings(res)


def test_dask_local_cluster_same_results(serial, tmp_path):
    distributed = pytest.importorskip("distributed")
    _, res = serial
    with distributed.LocalCluster(processes=False, n_workers=1, threads_per_worker=2,
                                  dashboard_address=None) as cluster:
        res2 = make_report(POLYGONS + [PATCH], tmp_path, ns=NS, scheduler=cluster.scheduler_address)
    assert strip_timings(res2) == strip_timings(res)


def test_cli_report_and_compare(tmp_path, capsys):
    from uniform2d.cli.main import main

    out = tmp_path / "rep"
    assert main(["report", POLYGONS[1], "-n", "20", "-n", "30", "--peers", "cvt",
                 "-o", str(out), "--no-figures"]) == 0
    res = json.loads((out / "results.json").read_text())
    assert res["ns"] == [20, 30] and len(res["cases"]) == 6
    a = out / res["cases"][0]["mesh"]
    b = out / res["cases"][2]["mesh"]
    capsys.readouterr()
    assert main(["compare", str(a), str(b), "--polygon", POLYGONS[1], "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["meshes"][0]["quality"] == res["cases"][0]["quality"]
    assert main(["report", POLYGONS[1], "--peers", "nope", "-o", str(out)]) == 2
    assert "unknown peer" in capsys.readouterr().err
    assert main(["compare", str(a), str(tmp_path / "missing.msh")]) == 2


def test_tune_and_switches():
    from uniform2d.peers import triangle_peer
    from uniform2d.peers.base import tune

    t = tune(lambda h: int(round(1000 / h)), lambda c: c, 333, 1.0)
    assert t.count == 333 and t.evaluations == len(t.history)
    assert "e" not in triangle_peer.switches(1e-4)


def test_scheduler_without_dask_says_which_extra_to_install(monkeypatch):
    import importlib.util

    from uniform2d.report.runners import run_cases

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "distributed" else real(name, *a)
    )
    case = {"status": "ok"}
    with pytest.raises(ImportError, match=r"pip install 'uniform2d\[dask\]'"):
        run_cases([case], scheduler="tcp://127.0.0.1:1")


def test_certificates_lead_each_polygon_section(serial):
    """Every polygon section states, for our meshes, how far from optimal they provably
    are and which bound is active, before the table; the factors lead the columns."""
    from uniform2d.report.render import _columns, certificate

    out, res = serial
    html_text = (out / "index.html").read_text(encoding="utf-8")
    md = (out / "report.md").read_text()
    ours = [c for c in res["cases"] if c["kind"] == "polygon" and c["family"] == "ours"]
    assert ours
    for c in ours:
        q = c["quality"]
        text = certificate(c)
        b = q["edge_ratio_bound"]
        assert f"edge ratio within {(b['factor'] - 1) * 100:.3g} %" in text
        assert f"bound: {b['term']}" in text and b["detail"] in text
        assert html.escape(text) in html_text and f"- {text}" in md
        section = md.index(f"## {c['input']}, n = {c['n']}")
        assert section < md.index(text) < md.index("| method |", section)
    square = [c for c in ours if c["input"] == "square"]
    assert all("corner (90 deg at (" in certificate(c) for c in square)
    assert [k for k, _, _ in _columns("polygon")][2:5] == [
        "factor_longest_edge", "factor_perimeter", "factor_edge_ratio"]
    assert not certificate({"method": "x", "quality": None})
