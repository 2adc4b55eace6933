"""Counts and names on the command line: --vertices, what -n counts, errors that
name their files, outputs checked before meshing, --stats' "wrote" line,
remesh --corner-angle."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import meshio
import numpy as np
import pytest

from uniform2d.cli.main import main
from uniform2d.io import read_polygon

ROOT = Path(__file__).resolve().parents[1]
ROOF = ROOT / "data/constrained/roof_panel.json"
SQUARE = ROOT / "data/benchmarks/square.json"
PLATE = ROOT / "data/patches/plate_hole.obj"


def _run(capsys, *argv):
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def _one_error(code, err, *words):
    assert code == 2 and err.count("\n") == 1 and err.startswith("uniform2d: error: "), err
    for w in words:
        assert w in err, err


def test_vertices_is_the_total_count(tmp_path, capsys):
    nv = len(read_polygon(ROOF).vertices)
    assert nv == 6  # 5 ring vertices and the ridge's end
    code, out, err = _run(capsys, "mesh", ROOF, "--vertices", 206, "-o", tmp_path / "v.vtu")
    assert code == 0, err
    assert len(meshio.read(tmp_path / "v.vtu").points) == 206
    assert "wrote" in out and "(206 points" in out and "n = 200)" in out
    # the same mesh as -n 200, byte for byte
    assert _run(capsys, "mesh", ROOF, "-n", 200, "-o", tmp_path / "n.vtu")[0] == 0
    assert (tmp_path / "v.vtu").read_bytes() == (tmp_path / "n.vtu").read_bytes()
    code, out, err = _run(capsys, "mesh", ROOF, "--vertices", 120, "--method", "paper",
                          "-o", tmp_path / "p.vtu")
    assert code == 0 and len(meshio.read(tmp_path / "p.vtu").points) == 120


@pytest.mark.parametrize("total", [6, 3])
def test_vertices_at_or_below_the_polygons_own_is_refused(tmp_path, capsys, total):
    code, _out, err = _run(capsys, "mesh", ROOF, "--vertices", total, "-o", tmp_path / "v.vtu")
    _one_error(code, err, f"--vertices {total} leaves no point to add",
               "the polygon has 6 vertices of its own", "give --vertices above 6")
    assert not (tmp_path / "v.vtu").exists()


def test_vertices_excludes_n_and_size(tmp_path, capsys):
    code, _out, err = _run(capsys, "mesh", ROOF, "--vertices", 100, "-n", 50)
    assert code == 2 and "not allowed with argument" in err


def test_help_says_what_n_counts(capsys):
    assert main(["mesh", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "points ADDED to the polygon's own vertices |V|" in text
    assert "the mesh has n + |V| vertices" in text and "--vertices N" in text
    assert main(["remesh", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "-n counts ALL the vertices of the output" in text
    assert "total number of vertices of the output mesh" in text and "--corner-angle" in text


def test_a_name_collision_names_both_inputs(tmp_path, capsys):
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        shutil.copy(SQUARE, tmp_path / d / "sq.json")
    a, b = tmp_path / "a/sq.json", tmp_path / "b/sq.json"
    code, _out, err = _run(capsys, "mesh", a, b, "-n", 10, "-o", tmp_path / "out/")
    _one_error(code, err, f"inputs '{a}' and '{b}' would both write '{tmp_path / 'out/sq.vtu'}'")
    assert not (tmp_path / "out").exists()


def test_an_unwritable_output_is_refused_before_meshing(tmp_path, capsys, monkeypatch):
    import uniform2d.uniform

    locked = tmp_path / "locked"
    locked.mkdir()
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: real(p, mode) and Path(p) != locked)

    def no_meshing(*a, **k):
        raise AssertionError("meshed before the output was checked")

    monkeypatch.setattr(uniform2d.uniform, "uniform_mesh", no_meshing)
    code, _out, err = _run(capsys, "mesh", SQUARE, "-n", 10, "-o", locked / "m.vtu")
    _one_error(code, err, f"cannot write '{locked / 'm.vtu'}'", "is not writable")
    code, _out, err = _run(capsys, "mesh", SQUARE, SQUARE, "-n", 10, "-o", locked / "sub/")
    _one_error(code, err, "is not writable")
    code, _out, err = _run(capsys, "mesh", SQUARE, "-n", 10, "-o", tmp_path / "missing/m.vtu")
    _one_error(code, err, "directory", "does not exist")
    src = locked / "sq.json"  # no -o: the mesh would go next to the input
    shutil.copy(SQUARE, src)
    code, _out, err = _run(capsys, "mesh", src, "-n", 10)
    _one_error(code, err, f"cannot write '{locked / 'sq.vtu'}'", "is not writable")


def test_stats_without_output_writes_next_to_the_input_and_says_so(tmp_path, capsys):
    src = tmp_path / "sq.json"
    shutil.copy(SQUARE, src)
    code, out, err = _run(capsys, "mesh", src, "-n", 30, "--stats")
    assert code == 0, err
    assert "Mesh quality" in out
    assert out.rstrip().splitlines()[-1].startswith(f"wrote {tmp_path / 'sq.vtu'} (34 points")
    assert (tmp_path / "sq.vtu").is_file()


# -- remesh (the surface layer) ----------------------------------------------------------
def test_remesh_single_input_errors_name_the_file(tmp_path, capsys):
    pytest.importorskip("surface")
    code, _out, err = _run(capsys, "remesh", PLATE, "-n", 2, "-o", tmp_path / "r.obj")
    _one_error(code, err, f"{PLATE}: ", "at least 3")
    assert not (tmp_path / "r.obj").exists()


def test_remesh_collision_and_unwritable_output(tmp_path, capsys, monkeypatch):
    pytest.importorskip("surface")
    for d in ("a", "b"):
        (tmp_path / d).mkdir()
        shutil.copy(PLATE, tmp_path / d / "p.obj")
    a, b = tmp_path / "a/p.obj", tmp_path / "b/p.obj"
    code, _out, err = _run(capsys, "remesh", a, b, "-n", 50, "-o", tmp_path / "out")
    _one_error(code, err, f"inputs '{a}' and '{b}' would both write")
    real = os.access
    monkeypatch.setattr(os, "access", lambda p, mode: real(p, mode) and Path(p) != tmp_path / "a")
    code, _out, err = _run(capsys, "remesh", a, "-n", 50, "-o", tmp_path / "a/r.obj")
    _one_error(code, err, "is not writable")


def test_remesh_corner_angle_reaches_the_layer(tmp_path, capsys):
    pytest.importorskip("surface")
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)

    def kept(*extra):
        out = tmp_path / f"r{len(extra)}.obj"
        code, text, err = _run(capsys, "remesh", PLATE, "-n", 200, "-o", out, "--stats", *extra)
        assert code == 0, err
        assert text.rstrip().splitlines()[-1].startswith(f"wrote {out} (200 vertices")
        V = np.array([[float(t) for t in line.split()[1:4]]
                      for line in out.read_text().splitlines() if line.startswith("v ")])
        return sum(bool(np.all(V == c, axis=1).any()) for c in corners)

    # the plate's corners turn by 90 degrees: kept under the default 30, not under 120
    assert kept() == 4
    assert kept("--corner-angle", "120") < 4
